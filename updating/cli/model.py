"""The commands on the model alone: ``check``, ``solve``, ``simulate``, ``frf`` and ``schema``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from rich.table import Table

from assembly import Case, summarise
from assembly.schema import case_json_schema
from solver import CaseSolution, field_grid, solve_case
from solver.estimate import ErrorEstimate, enriched_size, enriched_solve, estimate_error
from solver.sizing import estimate_size
from solver.tolerance import solve_to_tolerance
from updating.cli.common import (
    console_for,
    estimates_json,
    executor_for,
    frequencies_of,
    load_description,
    print_estimates,
    print_solution_warnings,
    provenance,
    warn,
    warn_untrue_simulation,
)
from updating.cli.progress import progress_bar
from updating.data.files import (
    Probes,
    read_probes,
    write_json_atomic,
    write_text_atomic,
)
from updating.data.measurements import (
    measurement_layout,
    simulate_measurements,
    write_measurements,
)
from updating.data.uff_export import write_uff
from updating.figures.figure_tools import require_matplotlib
from updating.figures.responses import write_sweep_figures
from updating.forward.sweep import (
    BALANCE_TOLERANCE,
    BandResolutions,
    Sweep,
    band_resolutions,
    frequency_sweep,
    strongest_peaks,
)

if TYPE_CHECKING:
    from rich.console import Console


def cmd_check(args: argparse.Namespace) -> int:
    case = load_description(args)
    console = console_for(args)
    console.print(summarise(case))
    if case.joints:
        for line in estimate_size(case).lines(enriched_size(case)):
            console.print(line)
    return 0


def cmd_solve(args: argparse.Namespace) -> int:
    case = load_description(args)
    probes = read_probes(args.probes, case) if args.probes else None
    tolerance = args.tolerance if args.tolerance is not None else case.discretisation.tolerance
    # one frequency at a time: each solution (and the system it keeps) is freed before the
    # next frequency's solves
    results = [_solve_frequency(args, case, frequency, probes, tolerance)
               for frequency in frequencies_of(case, args)]
    if args.json:  # one shape: the contract's first-frequency keys, then every frequency
        write_json_atomic(args.json, {**provenance(args, case), **results[0],
                                      "frequencies": results})
    return 0


def _solve_frequency(args: argparse.Namespace, case: Case, frequency: float, probes: Probes | None,
                     tolerance: float | None) -> dict[str, Any]:
    """``vtcr solve`` at one frequency: prints its table, returns its JSON entry."""
    console = console_for(args)
    solution, estimate = _solve_with_estimate(case, frequency, tolerance, not args.no_estimate)
    print_solution_warnings(console, solution)
    print_estimates(console, {frequency: estimate} if estimate is not None else {})
    if probes is None:  # the measurement layout: [measurement] plates, grid and points
        points = measurement_layout(case) or {
            pid: field_grid(case, pid, case.measurement.spacing) for pid in case.plates}
        order = [(pid, i) for pid in points for i in range(len(points[pid]))]
    else:
        points, order = probes.by_plate, probes.order
    values = {pid: solution.w(pid, pts) for pid, pts in points.items()}
    in_plane = {pid: solution.in_plane(pid, pts) for pid, pts in points.items()}

    def pair(value: complex) -> list[float]:
        return [float(value.real), float(value.imag)]

    rows = [
        {"plate": pid, "x": float(points[pid][i, 0]), "y": float(points[pid][i, 1]),
         "w": pair(values[pid][i]), "u": pair(in_plane[pid][i, 0]),
         "v": pair(in_plane[pid][i, 1])}
        for pid, i in order
    ]
    residuals = getattr(solution, "residuals", {})
    system = getattr(solution, "system", None)
    if residuals:
        console.print("joint residuals E_Gamma^2 (discretisation floor at the model's own "
                      "parameters): " + ", ".join(f"{j} {v:.1e}" for j, v in residuals.items()))
    n_s = system.n_s if system is not None else 0
    table = Table(title=f"{case.name}: w at {frequency:g} Hz "
                        f"({solution.n_unknowns - n_s} ray unknowns, {n_s} interface unknowns, "
                        f"condition estimate {solution.condition_estimate:.1e})")
    for column in ("plate", "x [m]", "y [m]", "|w| [m]", "phase [deg]"):
        table.add_column(column, justify="right")
    for row in rows[: args.max_rows]:
        w = complex(*row["w"])
        table.add_row(row["plate"], f"{row['x']:.4f}", f"{row['y']:.4f}", f"{abs(w):.4e}",
                      f"{np.degrees(np.angle(w)):.1f}")
    if len(rows) > args.max_rows:
        table.caption = f"{len(rows) - args.max_rows} more rows in the JSON output"
    console.print(table)
    return {
        "frequency": frequency,
        "unknowns": solution.n_unknowns,
        "interface_unknowns": n_s,
        "timings": dict({phase: float(t) for phase, t in solution.timings.items()},
                        **({"estimate": estimate.seconds} if estimate is not None else {})),
        "condition_estimate": solution.condition_estimate,
        "error_estimate": estimate.to_json() if estimate is not None else None,
        "warnings": list(solution.warnings),
        "joint_residuals": residuals,
        "probes": rows,
    }


def _solve_with_estimate(case: Case, frequency: float, tolerance: float | None,
                         estimate: bool) -> tuple[CaseSolution, ErrorEstimate | None]:
    """A solve and its error estimate: to ``tolerance`` if given, else at the description's
    resolution (estimate None when not wanted)."""
    if tolerance is not None:
        return solve_to_tolerance(case, frequency, tolerance)
    if not estimate:
        return solve_case(case, frequency, check=False), None
    # the enriched solve first: the solution keeps its system (36 MB on the 10 x 10 grid),
    # which would otherwise stay in memory through the enriched solve's peak
    enriched = enriched_solve(case, frequency)
    solution = solve_case(case, frequency, check=False)
    return solution, estimate_error(case, solution, enriched=enriched)


def cmd_simulate(args: argparse.Namespace) -> int:
    case = load_description(args)
    warn_untrue_simulation(args, case)
    measurements = simulate_measurements(case, noise=args.noise, seed=args.seed,
                                         executor=executor_for(args, case))
    write_measurements(args.out, measurements)
    console_for(args).print(f"{measurements.count()} simulated values at "
                         f"{', '.join(f'{f:g}' for f in measurements.frequencies)} Hz "
                         f"written to {args.out}")
    return 0


def cmd_frf(args: argparse.Namespace) -> int:
    case = load_description(args)
    console = console_for(args)
    if args.plot:
        require_matplotlib()  # fail before the sweep, not after it
    probes = read_probes(args.probes, case) if args.probes else None
    if probes is None:
        points = {pid: field_grid(case, pid, case.measurement.spacing) for pid in case.plates}
        order, nodes = [(pid, i) for pid in case.plates for i in range(len(points[pid]))], None
    else:
        points, order, nodes = probes.by_plate, list(probes.order), probes.nodes
    count = None if args.step is not None else args.start_frequencies
    executor = executor_for(args, case)
    resolutions = None
    tolerance = args.tolerance if args.tolerance is not None else case.discretisation.tolerance
    if tolerance is not None:  # a first sweep finds the resonances the resolution must meet
        with progress_bar(console, "resolution per sub-band", None):
            first = frequency_sweep(case, tuple(args.band), points, step=args.step, count=count,
                                    tolerance=args.sampling_tolerance,
                                    max_points=args.max_points, executor=executor, check=False)
            resolutions = band_resolutions(case, tuple(args.band), tolerance,
                                           strongest_peaks(first, SWEEP_ESTIMATE_PEAKS))
        console.print(f"{resolutions.describe()}: meets the tolerance {tolerance:g} at each "
                      "sub-band's top and at the strongest resonances")
    with progress_bar(console, f"sweep on {executor.description}", None) as advance:
        sweep = frequency_sweep(case, tuple(args.band), points, step=args.step, count=count,
                                tolerance=args.sampling_tolerance, max_points=args.max_points,
                                executor=executor, check=False, resolutions=resolutions,
                                on_round=lambda n: advance(f"{n} frequencies solved", 0))
    _print_sweep(console, case, sweep, len(order))
    estimates = {} if args.no_estimate else _sweep_estimates(case, sweep, resolutions)
    print_estimates(console, estimates, f" of the sweep at its {SWEEP_ESTIMATE_PEAKS} strongest "
                                        "peaks and its top")
    missed = {f: e.total for f, e in estimates.items()
              if tolerance is not None and e.total is not None and e.total > tolerance}
    if missed:
        warn(console, f"the tolerance {tolerance:g} is not met at "
                      + ", ".join(f"{f:g} Hz ({v:.1e})" for f, v in missed.items())
                      + " (a resonance of the final sweep away from the first one's): "
                        "lower the tolerance (--tolerance, [discretisation] tolerance) or "
                        "raise resolution")
    if args.csv:
        write_measurements(args.csv, sweep.measurements(), sweep=True)
    if args.json:
        write_json_atomic(args.json, {**provenance(args, case), **sweep.to_json(order, nodes),
                                      "error_estimate": estimates_json(estimates)})
    if args.uff:
        write_uff(args.uff, case, sweep, order, nodes)
    if args.plot:
        paths = write_sweep_figures(case, sweep, args.plot)
        console.print(f"{len(paths)} figures written to {args.plot}: "
                      f"{', '.join(p.name for p in paths)}")
    flagged = int(np.sum(sweep.imbalances > BALANCE_TOLERANCE))
    if flagged:
        warn(console, f"the power balance misses by more than {BALANCE_TOLERANCE:.0%} at "
                       f"{flagged} frequencies: raise [discretisation] resolution")
    return 0


SWEEP_ESTIMATE_PEAKS = 5
"""Response peaks of a sweep at which its discretisation error is estimated, with the top of
the band: the relative error is largest at the resonances (where the field is most sensitive to
the boundary conditions) and at the highest frequency (where the ray counts are tightest)."""


def _sweep_estimates(case: Case, sweep: Sweep, resolutions: BandResolutions | None = None
                     ) -> dict[float, ErrorEstimate]:
    """Error estimates at the sweep's :data:`SWEEP_ESTIMATE_PEAKS` strongest response peaks
    and at its highest frequency, the largest of which stands for the band (one solve and one
    enriched solve each, not one per frequency of the sweep), each at the resolution the sweep
    used there (``resolutions``, :class:`updating.forward.sweep.BandResolutions`)."""
    chosen = sorted(set(strongest_peaks(sweep, SWEEP_ESTIMATE_PEAKS))
                    | {float(sweep.frequencies[-1])})
    def at(f: float) -> dict[str, float] | None:
        return None if resolutions is None else resolutions.at(f)

    return {f: estimate_error(case, solve_case(case, f, resolution=at(f), residuals=False,
                                               check=False), at(f))
            for f in chosen}


def _print_sweep(console: Console, case: Case, sweep: Sweep, n_points: int) -> None:
    """Sampling, resonance peaks and the power flow at the strongest one."""
    s = sweep.sampling
    requested = (f"step {s['requested']['step']:g} Hz" if s["requested"]["step"] is not None
                 else f"{s['requested']['points']} points")
    console.print(
        f"{case.name}: {s['final']} frequencies over {sweep.frequencies[0]:g}-"
        f"{sweep.frequencies[-1]:g} Hz at {n_points} points: {s['initial']} requested "
        f"({requested}), refined in {s['rounds']} rounds until neighbouring responses differ by "
        f"less than {100 * s['tolerance']:.3g} % or the step is below {s['fraction']:g} eta f "
        f"(eta = {s['loss_factor']:g}, the half-power bandwidth of the lightest-damped plate)"
        + ("" if s["resolved"] else f"; stopped at --max-points {s['final']}, some peaks may "
                                    "be under-sampled"))
    rms = sweep.spatial_rms()
    peaks = [i for i in range(len(rms)) if (i == 0 or rms[i] >= rms[i - 1])
             and (i == len(rms) - 1 or rms[i] >= rms[i + 1])]
    peaks = sorted(sorted(peaks, key=lambda i: -rms[i])[:10])
    table = Table(title="response peaks (largest 10)")
    for column in ("f [Hz]", "RMS |w| [m]", "injected [W]", "plates [W]", "joints [W]",
                   "imbalance"):
        table.add_column(column, justify="right")
    for i in peaks:
        p = sweep.powers[i]
        table.add_row(f"{sweep.frequencies[i]:.3f}", f"{rms[i]:.3e}", f"{p.total_injected:.3e}",
                      f"{sum(p.dissipated.values()):.3e}",
                      f"{sum(p.joint_dissipated.values()):.3e}", f"{p.imbalance:.1e}")
    console.print(table)
    top = max(peaks, key=lambda i: rms[i])
    power = sweep.powers[top]
    table = Table(title=f"power flow at {sweep.frequencies[top]:.3f} Hz (time-averaged)")
    for column in ("plate", "injected [W]", "dissipated [W]", "kinetic energy [J]"):
        table.add_column(column, justify="right")
    for pid in power.injected:
        table.add_row(pid, f"{power.injected[pid]:.3e}", f"{power.dissipated[pid]:.3e}",
                      f"{power.kinetic[pid]:.3e}")
    console.print(table)
    if power.transmitted:
        table = Table(title="joints: transmitted from the first plate of `between` to the "
                            "second, and dissipated")
        for column in ("joint", "transmitted [W]", "dissipated [W]"):
            table.add_column(column, justify="right")
        for jid in power.transmitted:
            table.add_row(jid, f"{power.transmitted[jid]:.3e}",
                          f"{power.joint_dissipated[jid]:.3e}")
        console.print(table)
    worst = int(np.argmax(sweep.imbalances))
    console.print(f"power balance (injected against dissipated in plates and joints): largest "
                  f"imbalance {sweep.imbalances[worst]:.1e} at {sweep.frequencies[worst]:g} Hz")


def cmd_schema(args: argparse.Namespace) -> int:
    # strict JSON (no Infinity): editors read the schema with a strict parser
    text = json.dumps(case_json_schema(), indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    if not args.out:
        sys.stdout.write(text)
        return 0

    write_text_atomic(args.out, text)
    console_for(args).print(f"JSON Schema of the description written to {args.out}; for editor "
                         f"completion, start a description beside it with "
                         f"`#:schema ./{Path(args.out).name}`", markup=False)
    return 0
