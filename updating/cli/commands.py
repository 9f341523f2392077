"""The commands of ``vtcr``: one function per command, each taking the parsed arguments and
returning the exit status (:data:`COMMANDS`), and :func:`execute`, which checks the options and
the description, runs a command and turns every expected failure into one line and a status.

Bad input exits with status 2 and one line per problem naming the file, the field and the fix;
no traceback. The commands only format what the library returns.
"""

from __future__ import annotations

import contextlib
import csv
import ctypes
import ctypes.util
import errno
import hashlib
import io
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from assembly import DescriptionError, load_case, summarise
from assembly.schema import case_json_schema
from solver import field_grid, solve_case
from solver.errors import NumericalError
from solver.estimate import (
    ToleranceError,
    enriched_plates,
    enriched_size,
    estimate_error,
    solve_to_tolerance,
)
from solver.guards import check_description
from solver.sizing import available_memory, estimate_size
from updating.cli.parser import SUMMARY_JOINTS, version_text
from updating.inverse.cost import ModifiedProblem, cost_curve, log_grid
from updating.executor import Executor, frequency_threads
from updating.figures.figure_tools import require_matplotlib
from updating.data.files import (
    InputError,
    output_collisions,
    output_path_problem,
    plot_directory_problem,
    read_probes,
    write_json_atomic,
    write_text_atomic,
)
from updating.data.measurements import (
    Measurements,
    check_joints_seen,
    measurement_layout,
    read_measurements,
    simulate_measurements,
    write_measurements,
)
from updating.inverse.plan import identifiability_plan
from updating.figures.plots import (
    write_curve_figure,
    write_plan_figure,
    write_sweep_figures,
    write_update_figures,
)
from updating.cli.progress import progress_bar
from updating.cli.report import (
    identified_lines,
    notable_joints,
    result_json,
    result_markdown,
    steps_table,
)
from updating.data.runfile import (
    RunFile,
    RunLock,
    description_digest,
    fingerprint,
    load_run,
    measurement_digest,
    read_run,
    refuse_other_measurements,
    refuse_replacing,
)
from updating.inverse.strategy import (
    excess_ratios,
    finished_result,
    localise,
    standing_summary,
    thresholds,
    update_joints,
)
from updating.forward.sweep import BALANCE_TOLERANCE, frequency_sweep
from updating.data.uff import UFF_SUFFIXES, is_uff, read_uff
from updating.data.uff_export import write_uff

__all__ = ["execute", "COMMANDS", "NOT_CONVERGED"]

NOT_CONVERGED = 3
"""Exit status of ``vtcr update`` when the loop stops without converging (status 1: joints
still stand out but no correction helps; status 2: ``max_steps`` reached); its outputs are
written all the same."""

# Arrays above this are mapped from the system and returned to it when freed, for problems
# factorised by groups (solver.multifrontal). glibc's default raises the threshold to the
# largest array freed so far (up to 32 MB), after which a large factorisation's fronts and
# contributions come from the heap and fragment it. On the 10 x 10 grid, vtcr solve (with its
# estimate) peaked at 0.49-0.53 GB against 0.45-0.46 GB with this threshold, and vtcr localise
# at 0.56-0.58 GB against 0.51-0.52 GB, in the same time (numpy advises huge pages from 4 MB,
# so mapping costs few page faults). Small problems keep the default: the main job took 0.1 s
# more in page faults with it, for 16 MB less. A user's setting wins.
MMAP_THRESHOLD = 4 << 20


def _map_large_arrays():
    """Fix glibc's mmap threshold at :data:`MMAP_THRESHOLD` (nothing on other C libraries)."""
    if "MALLOC_MMAP_THRESHOLD_" in os.environ or "mmap_threshold" in os.environ.get(
            "GLIBC_TUNABLES", ""):
        return

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.mallopt(-3, MMAP_THRESHOLD)  # M_MMAP_THRESHOLD of <malloc.h>
    except (OSError, AttributeError):  # not glibc: its own policy stays
        pass


def _console(args):
    # with an output on standard output (``--json -``) the tables go to standard error, so
    # that the output can be piped; a file or a pipe has no width: 120 columns keeps wide
    # tables (Table 4) on one line
    to_stderr = any(str(getattr(args, name, None)) == "-" for name, _ in _OUTPUT_OPTIONS)
    stream = sys.stderr if to_stderr else sys.stdout
    width = None if stream.isatty() else 120
    return Console(quiet=getattr(args, "quiet", False), highlight=False, width=width,
                   stderr=to_stderr)


def _load(args):
    """The description of ``args.case``, loaded and validated once per command."""
    if getattr(args, "case_model", None) is None:
        args.case_model = load_case(args.case)
    return args.case_model


def _frequencies(case, args):
    if getattr(args, "frequency", None) is None:
        return case.frequencies
    return tuple(args.frequency)


def cmd_check(args):
    case = _load(args)
    console = _console(args)
    console.print(summarise(case))
    if case.joints:
        for line in estimate_size(case).lines(enriched_size(case)):
            console.print(line)
    return 0


def _solution_warnings(console, solution):
    for warning in solution.warnings:
        _warn(console, warning)


def _warn(console, line):
    console.print(f"[yellow]warning:[/] {escape(line)}", soft_wrap=True)


def _check_description(args):
    """Physical and numerical sanity of the description, before any work; prints warnings."""
    if not getattr(args, "case", None):
        return
    frequency = getattr(args, "frequency", None)
    frequencies = None if frequency is None else tuple(frequency)
    if args.command == "frf":  # the band's ends bound every frequency of the sweep
        frequencies = tuple(args.band)
    case = _load(args)
    for line in check_description(case, args.case, frequencies,
                                  need_loads=args.command != "check"):
        _warn(_console(args), line)
    if case.joints:
        if estimate_size(case, max(frequencies) if frequencies else None).grouped:
            _map_large_arrays()


def _checked_measurements(case, args):
    """:func:`_measurements`, after checking that they can see the joints to update."""
    if not case.joints:
        raise InputError(f"{args.case}: joints: the description has no joint to update; add a "
                         "[joints.ID] table (vtcr solve works without joints)")
    joints = ([args.joint] if getattr(args, "joint", None) in case.updatable_joints()
              else None)
    if not getattr(args, "measurements", None):  # simulated: check the layout first
        warnings = check_joints_seen(case, None, joints, f"{args.case}: measurement")
        measurements = _measurements(case, args)
    else:
        measurements = _measurements(case, args)
        warnings = check_joints_seen(case, measurements, joints, args.measurements)
    for line in warnings:
        _warn(_console(args), line)
    return measurements


def _problem_warnings(args, problem):
    """Print the condition warnings of a ModifiedProblem; stop on a non-finite set-up."""
    for line in getattr(problem, "warnings", ()):
        _warn(_console(args), line)
    for frequency, energy in problem.reference_energies.items():
        if not (math.isfinite(energy) and energy > 0):
            raise NumericalError(f"the reference energy at {frequency:g} Hz is {energy}: the "
                                 "model's response is zero or not finite; check the loads and "
                                 "the plates' materials")


def cmd_solve(args):
    case = _load(args)
    probes = read_probes(args.probes, case) if args.probes else None
    tolerance = args.tolerance if args.tolerance is not None else case.discretisation.tolerance
    # one frequency at a time: each solution (and the system it keeps) is freed before the
    # next frequency's solves
    results = [_solve_frequency(args, case, frequency, probes, tolerance)
               for frequency in _frequencies(case, args)]
    if args.json:  # one shape: the contract's first-frequency keys, then every frequency
        write_json_atomic(args.json, {**_provenance(args, case), **results[0],
                                      "frequencies": results})
    return 0


def _solve_frequency(args, case, frequency, probes, tolerance):
    """``vtcr solve`` at one frequency: prints its table, returns its JSON entry."""
    console = _console(args)
    solution, estimate = _solve_with_estimate(case, frequency, tolerance, not args.no_estimate)
    _solution_warnings(console, solution)
    _estimate_lines(console, {frequency: estimate} if estimate is not None else {})
    if probes is None:  # the measurement layout: [measurement] plates, grid and points
        points = measurement_layout(case) or {
            pid: field_grid(case, pid, case.measurement.spacing) for pid in case.plates}
        order = [(pid, i) for pid in points for i in range(len(points[pid]))]
    else:
        points, order = probes.by_plate, probes.order
    values = {pid: solution.w(pid, pts) for pid, pts in points.items()}
    rows = [
        {"plate": pid, "x": float(points[pid][i, 0]), "y": float(points[pid][i, 1]),
         "w": [float(values[pid][i].real), float(values[pid][i].imag)]}
        for pid, i in order
    ]
    residuals = getattr(solution, "residuals", {})
    system = getattr(solution, "system", None)
    if residuals:
        console.print("joint residuals E_Gamma^2 (discretisation floor at the model's own "
                      "parameters): " + ", ".join(f"{j} {v:.1e}" for j, v in residuals.items()))
    table = Table(title=f"{case.name}: w at {frequency:g} Hz "
                        f"({solution.n_unknowns} ray unknowns, "
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
        "interface_unknowns": system.n_s if system is not None else 0,
        "timings": dict({phase: float(t) for phase, t in solution.timings.items()},
                        **({"estimate": estimate.seconds} if estimate is not None else {})),
        "condition_estimate": solution.condition_estimate,
        "error_estimate": estimate.to_json() if estimate is not None else None,
        "warnings": list(solution.warnings),
        "joint_residuals": residuals,
        "probes": rows,
    }


# Problems of one input printed at most (a generated file can hold a million bad keys).
MAX_PROBLEM_LINES = 50

# Estimated errors above this are flagged (the accuracy the tests hold the rule to).
ESTIMATE_WARNING = 1e-2


def _solve_with_estimate(case, frequency, tolerance, estimate):
    """A solve and its error estimate: to ``tolerance`` if given, else at the description's
    resolution (estimate None when not wanted)."""
    if tolerance is not None:
        return solve_to_tolerance(case, frequency, tolerance)
    if not estimate:
        return solve_case(case, frequency, check=False), None
    # the enriched solve first: the solution keeps its system (36 MB on the 10 x 10 grid),
    # which would otherwise stay in memory through the enriched solve's peak
    enriched = enriched_plates(case, frequency)
    solution = solve_case(case, frequency, check=False)
    return solution, estimate_error(case, solution, enriched=enriched)


def _resolution_text(resolution):
    """A resolution factor, or the range of per-plate factors."""
    if isinstance(resolution, dict):
        values = resolution.values()
        return f"{min(values):.3g}-{max(values):.3g} (per plate)"
    return f"{resolution:.3g}"


def _measurements(case, args):
    path, uff_map = getattr(args, "measurements", None), getattr(args, "uff_map", None)
    if path and is_uff(path):  # dispatch on the suffix: UFF 58 (needs pyuff) or CSV
        return read_uff(path, case, uff_map)
    if uff_map:
        raise InputError(f"--uff-map {uff_map}: only used with a UFF measurement file "
                         f"({', '.join(UFF_SUFFIXES)}); got --measurements {path or '(none)'}")
    if path:
        return read_measurements(path, case)
    _warn_untrue_simulation(args, case)
    return simulate_measurements(case, executor=_executor(args, case))


def _warn_untrue_simulation(args, case):
    """A simulated experiment of a description without [truth] measures the model itself."""
    if case.joints and not case.truth.joints:
        _warn(_console(args), f"{args.case} has no [truth.joints] table: the simulated "
                              "experiment is the model itself (its joints as described), so "
                              "only noise and discretisation are left to find; add "
                              "[truth.joints.ID] tables, or give measured data")


def cmd_simulate(args):
    case = _load(args)
    _warn_untrue_simulation(args, case)
    measurements = simulate_measurements(case, noise=args.noise, seed=args.seed,
                                         executor=_executor(args, case))
    write_measurements(args.out, measurements)
    _console(args).print(f"{measurements.count()} simulated values at "
                         f"{', '.join(f'{f:g}' for f in measurements.frequencies)} Hz "
                         f"written to {args.out}")
    return 0


def _modified_problem(case, args, measurements=None, discretisation=True):
    """The updating problem on ``measurements`` (default: read or simulated per ``args``);
    ``discretisation``: see :class:`updating.inverse.cost.ModifiedProblem`."""
    if measurements is None:
        measurements = _checked_measurements(case, args)
    resolution = _resolution_for_tolerance(case, _console(args))
    executor = _executor(args, case)
    problem = ModifiedProblem(case, measurements, resolution=resolution, executor=executor,
                              estimate=not getattr(args, "no_estimate", True),
                              threads=executor.threads, discretisation=discretisation,
                              check=False)  # checked before the command ran
    _problem_warnings(args, problem)
    _estimate_lines(_console(args), problem.error_estimates,
                    " of the model at its initial parameters")
    return problem


def _resolution_for_tolerance(case, console):
    """With ``[discretisation] tolerance``: the resolution at which the model's response meets
    it at every frequency (the highest any frequency needs); else None (the description's)."""
    tolerance = case.discretisation.tolerance
    if tolerance is None:
        return None
    resolution = dict.fromkeys(case.plates, 0.0)
    for frequency in case.frequencies:
        estimate = solve_to_tolerance(case, frequency, tolerance)[1]
        resolution = {pid: max(r, estimate.resolution_of(pid)) for pid, r in resolution.items()}
    console.print(f"resolution {_resolution_text(resolution)} meets the tolerance "
                  f"{tolerance:g} at every frequency (\\[discretisation] tolerance)")
    return resolution


def _estimate_lines(console, estimates, what=""):
    """One line: the estimated error of w at each frequency of ``estimates`` (``{frequency:
    ErrorEstimate}``), its resolution and the worst plate; a warning above
    :data:`ESTIMATE_WARNING` or when the estimate was skipped."""
    if not estimates:
        return
    skipped = [e for e in estimates.values() if e.total is None]
    if skipped:
        _warn(console, f"the discretisation error is not estimated: {skipped[0].reason}; give "
                       "--no-estimate to skip it knowingly")
        return
    worst = max(estimates.values(), key=lambda e: e.total)
    plate = worst.worst_plate()
    console.print(f"estimated error of w{what} (relative L2, against an enriched solve): "
                  + ", ".join(f"{e.total:.1e} at {f:g} Hz" for f, e in estimates.items())
                  + f" (resolution {_resolution_text(worst.resolution)})"
                  + (f"; largest on plate {plate} ({worst.plates[plate]:.1e})"
                     if len(worst.plates) > 1 else ""))
    if worst.total > ESTIMATE_WARNING:
        _warn(console, f"the estimated error {worst.total:.1e} exceeds {ESTIMATE_WARNING:g}: "
                       "raise [discretisation] resolution or give a tolerance")
    # a small plate can be wrong while the total, weighted by the energy, is not
    above = {}
    for f, e in estimates.items():
        for pid, value in e.plates.items():
            if value > ESTIMATE_WARNING and value > above.get(pid, (0.0, 0.0))[0]:
                above[pid] = (value, f)
    if above:
        _warn(console, f"the estimated error exceeds {ESTIMATE_WARNING:g} on plate"
                       f"{'s' if len(above) > 1 else ''} "
                       + ", ".join(f"{pid} ({v:.1e} at {f:g} Hz)" for pid, (v, f) in above.items())
                       + ": raise [discretisation] resolution (of those plates) or give a "
                         "tolerance")


def _estimates_json(estimates):
    """``error_estimate`` of a multi-frequency JSON: the worst total and plate values over the
    frequencies, and every frequency's estimate."""
    if not estimates:
        return None
    values = list(estimates.values())
    known = all(e.total is not None for e in values)
    plates = {}
    for e in values:
        for pid, v in e.plates.items():
            plates[pid] = max(plates.get(pid, 0.0), v)
    return {"total": max(e.total for e in values) if known else None, "plates": plates,
            "frequencies": {f"{f:g}": e.to_json() for f, e in estimates.items()}}


def cmd_localise(args):
    case = _load(args)
    measurements = _checked_measurements(case, args)
    problem = _modified_problem(case, args, measurements)
    step = localise(problem, problem.initial_parameters(), noise=case.measurement.noise)
    limits = thresholds(step, case.updating.stop_ratio)
    excess = excess_ratios(step, case.updating.stop_ratio)
    order = sorted(step.residuals, key=excess.get, reverse=True)
    standing = [j for j in order if excess[j] > 1.0]
    # a large structure's table shows the joints that stand out and the next few; the JSON
    # has every joint
    shown = order if args.all or len(order) <= SUMMARY_JOINTS else order[:len(standing) + 5]
    table = Table(title=f"{case.name}: joint residuals (E_mod^2 = {100 * step.e_mod:.3f} %)")
    for column in ("joint", "log10 k", "E_Gamma^2 %", "floor %", "threshold %",
                   "x threshold", "stands out"):
        table.add_column(column, justify="right")
    for joint in shown:
        table.add_row(joint, f"{step.parameters[joint]['log10_stiffness']:.2f}",
                      f"{100 * step.residuals[joint]:.3f}", f"{100 * step.floors[joint]:.3f}",
                      f"{100 * limits[joint]:.3f}", f"{excess[joint]:.2f}",
                      "yes" if excess[joint] > 1.0 else "")
    console = _console(args)
    console.print(table)
    if len(shown) < len(order):
        console.print(f"{len(order) - len(shown)} more joints below their thresholds (every "
                      "joint: --all, or the JSON)")
    summary = standing_summary(step, lambda j: problem.neighbourhood(j)[0],
                               case.updating.stop_ratio)
    console.print(summary or "no joint stands out of its threshold")
    if problem.weights is not None:
        console.print(problem.weights.describe())
    if args.json:
        write_json_atomic(args.json, {**_provenance(args, case, measurements),
                                      **step.to_json(), "weights": _weights_json(problem),
                                      "error_estimate": _estimates_json(problem.error_estimates)})
    return 0


def _planned_points(case, args):
    """The points of the planned measurement: a measurement file's (values unused), else the
    description's grid and point measurements, at every frequency of the description."""
    if getattr(args, "measurements", None):
        return _measurements(case, args)
    layout = measurement_layout(case)
    if not layout:
        raise InputError(f"{args.case}: measurement: no planned point; add a [measurement] "
                         "spacing (a grid on every plate) or points, or give --measurements")
    return Measurements({f: {pid: (points, np.ones(len(points), dtype=complex))
                             for pid, points in layout.items()} for f in case.frequencies})


def _updatable_joint_names(case, args, option, names):
    """``names`` checked against the case's updatable joints (one line and exit 2 naming the
    first that is not one)."""
    for name in names:
        if name not in case.updatable_joints():
            raise InputError(f"{option} {name}: not an updatable joint of {args.case} "
                             f"(joints: {', '.join(case.updatable_joints())}; a junction's "
                             "finite member as JOINT.PLATE); give one of them")
    return names


def cmd_plan(args):
    case = _load(args)
    if not case.joints:
        raise InputError(f"{args.case}: joints: the description has no joint to plan for; add "
                         "a [joints.ID] table")
    joints = (_updatable_joint_names(case, args, "--joints", args.joints) if args.joints
              else None)
    console = _console(args)
    if args.plot:
        require_matplotlib()  # fail before the work, not after it
    points = _planned_points(case, args)
    if case.measurement.noise <= 0.0:
        _warn(console, f"{args.case}: [measurement] noise is 0: the plan assumes ±1 % uniform "
                       "noise; state the planned test's, e.g. noise = 0.05")
    level = case.updating.confidence if args.confidence is None else args.confidence
    count = len(joints or case.updatable_joints())
    seconds = estimate_size(case).plan_seconds(count)
    if seconds > LONG_PLAN_SECONDS:
        joints_text = f"{count} joint" + ("s" if count != 1 else "")
        _warn(console, f"{args.case}: planning {joints_text} takes about {seconds / 60:.0f} min "
                       "on this kind of machine (vtcr check); --joints J1 J2 ... plans some")
    with progress_bar(console, "planning", count) as advance:
        plans, noise, estimates = identifiability_plan(
            case, points, level=level, resolution=_resolution_for_tolerance(case, console),
            threads=_threads(args, case), estimate=not args.no_estimate, joints=joints,
            on_joint=lambda joint: advance(f"planned {joint}"))
    _estimate_lines(console, estimates, " of the model")
    frequencies = points.frequencies
    table = Table(title=f"{case.name}: what {points.count(frequencies[0])} planned values per "
                        f"frequency can tell ({noise.description})")
    table.add_column("joint")
    table.add_column("log10 k", justify="right")
    for f in frequencies:
        table.add_column(f"%/0.1 dec\n{f:g} Hz", justify="right")
    table.add_column(f"expected {100 * level:g} %", justify="right")
    table.add_column("verdict")
    table.add_column("damping: share, %/0.1 eta", justify="right")
    for joint, plan in plans.items():
        damping = (f"{100 * max(plan.damping_share.values()):.2g} %, "
                   f"{100 * max(plan.damping_sensitivity.values()):.2g}"
                   + ("" if plan.damping_identifiable else " (below the noise)"))
        table.add_row(joint, f"{plan.value:.2f}",
                      *[f"{100 * plan.stiffness_sensitivity[f]:.2f}" for f in frequencies],
                      plan.interval.brief, plan.verdict, damping)
    console.print(table)
    for joint, plan in plans.items():
        if plan.verdict != "identifiable" and plan.best_source:
            frequency, plate = plan.best_source
            console.print(f"{joint}: {plan.verdict}; most of what the data say about it comes "
                          f"from plate {plate} at {frequency:g} Hz "
                          f"({100 * plan.information[plan.best_source]:.0f} % of its "
                          "information): measure there more densely, or add a frequency where "
                          "its sensitivity is higher")
    if args.json:
        write_json_atomic(args.json, {
            **_provenance(args, case, None), "case": case.name, "noise": noise.description,
            "confidence": level, "frequencies": list(frequencies),
            "error_estimate": _estimates_json(estimates),
            "joints": {joint: plan.to_json() for joint, plan in plans.items()}})
    if args.plot:
        path = write_plan_figure(plans, frequencies, args.plot, case.name)
        console.print(f"figure written to {path}")
    return 0


def _weights_json(problem):
    """The weights of the modified error a run used: ``r`` and, for the scale-free ones, the
    balance and the noise the data were weighed by (``docs/updating.md``, section 2)."""
    if problem.weights is None:
        return {"rule": "given", "r": problem.r}
    w = problem.weights
    return {"rule": "scale-free", "r": w.r, "balance": w.balance, "noise": w.noise}


def _truth(case, args):
    """``{joint: {parameter: true value}}`` of a simulated experiment (none with measured
    data); a junction's every finite member when its truth gives a value."""
    if getattr(args, "measurements", None):
        return {}
    return case.true_parameters()


def _finished_steps(count):
    return f"{count} finished step{'' if count == 1 else 's'} {'is' if count == 1 else 'are'}"


def _resume_command(args, run_path):
    """The command that continues an interrupted ``vtcr update``, with the outputs it asked for
    (the same JSON, report, figures and measurements)."""
    kept = [f"{option} {value}" for option, value in (
        ("--measurements", getattr(args, "measurements", None)), ("--json", args.json),
        ("--report", args.report), ("--plot", args.plot),
        ("--confidence", args.confidence)) if value is not None]
    return " ".join([f"vtcr update {args.case}", *kept, f"--resume {run_path}"])


def _run_path(args):
    """The run file: ``--run``, else beside the report or the JSON, else ``CASE.run.json``."""
    if args.run_file:
        return Path(args.run_file)
    for output in (args.report, args.json):
        if output and output != "-":
            return Path(output).with_suffix(".run.json")
    return Path(Path(args.case).stem + ".run.json")


def cmd_update(args):
    case = _load(args)
    console = _console(args)
    if args.plot:
        require_matplotlib()  # fail before the run, not after it
    t0 = time.perf_counter()
    run_path = args.resume or _run_path(args)
    replaceable = None
    if args.resume:
        read_run(args.resume)  # a missing or foreign file is refused before any work
    elif not args.force:
        replaceable = refuse_replacing(run_path, description_digest(case))
    args.resources.enter_context(RunLock(run_path))
    measurements = _checked_measurements(case, args)
    digests = fingerprint(case, measurements)
    refuse_other_measurements(run_path, replaceable, digests[1])
    if args.resume:
        run = load_run(args.resume, case, digests)
        state = ("finished: its result is reported without running the loop again"
                 if run.finished else f"resuming after step {run.steps[-1].step}")
        console.print(f"run file {run.path}: {len(run.steps)} finished steps; {state}")
    else:
        run = RunFile(run_path, case.name, digests)
    problem = _modified_problem(case, args, measurements)
    t1 = time.perf_counter()
    settings = case.updating
    if args.confidence is not None:
        settings = settings.model_copy(update={"confidence": args.confidence})
    with progress_bar(console, "localising", settings.max_steps + 1) as advance:
        def corrected(number, joint, again):
            advance(f"step {number}: {'re-' if again else ''}correcting {joint}", amount=0)

        def finished(step):
            run.save_step(step)
            advance(f"step {step.step} finished (E_mod^2 {100 * step.e_mod:.2f} %)")

        try:
            if run.finished:
                result = finished_result(problem, run.steps, run.finished[0], settings,
                                         case.measurement.noise)
            else:
                result = update_joints(problem, settings, noise=case.measurement.noise,
                                       start=run.steps, on_step=finished, on_correct=corrected)
        except KeyboardInterrupt:
            print(f"vtcr: interrupted; {_finished_steps(len(run.steps))} saved in {run.path}; "
                  f"continue with: {_resume_command(args, run.path)}", file=sys.stderr)
            return 130
    if not run.finished:  # a finished run read back is reported as its file holds it
        run.finish(result)
    t2 = time.perf_counter()
    bounds = settings.bounds
    rows = (None if args.all or len(result.parameters) <= SUMMARY_JOINTS
            else notable_joints(result, settings.stop_ratio))
    console.print(steps_table(result, f"{case.name}: localisation and correction", rows))
    summary = standing_summary(result.steps[0], lambda j: problem.neighbourhood(j)[0],
                               settings.stop_ratio)
    if summary:
        console.print(f"first localisation: {summary}")
    if problem.weights is not None:
        console.print(problem.weights.describe())
    for line in identified_lines(result, _truth(case, args), case.measurement.noise):
        console.print(line)
    n_rays, n_s, n_g = problem.size
    console.print(f"{n_rays} ray unknowns, {n_s} interface unknowns, {n_g} constraints; "
                  f"set-up {t1 - t0:.2f} s, updating {t2 - t1:.2f} s; run file {run.path}")
    n_f = len(problem.frequencies)
    joint = next((s.selected for s in reversed(result.steps) if s.selected),
                 next(iter(problem.joints), None))
    timings = {"setup": t1 - t0, "updating": t2 - t1,
               # the fastest of the run's own evaluations, if it made any (not a resumed
               # finished run): timing it again would cost the run one more
               "global_solve": min(problem.evaluation_times, default=None)
               or problem.evaluation_seconds(result.parameters, repeats=1),
               "correction_evaluation": problem.evaluation_seconds(result.parameters, joint),
               "plates_per_frequency": sum(problem.factorisation_seconds.values()) / n_f}
    console.print(f"one E_mod^2(p) solve ({n_f} frequenc{'ies' if n_f > 1 else 'y'}): "
                  f"{1e3 * timings['global_solve']:.1f} ms, during a correction of {joint}: "
                  f"{1e3 * timings['correction_evaluation']:.2f} ms; plate blocks and transfer "
                  f"operators: {1e3 * timings['plates_per_frequency']:.1f} ms per frequency")
    if args.json:
        sizes = dict(zip(("ray_unknowns", "interface_unknowns", "constraints"), problem.size))
        write_json_atomic(args.json, result_json(
            result, {"case": case.name, "sizes": sizes, "timings_s": timings,
                     "error_estimate": _estimates_json(problem.error_estimates),
                     "weights": _weights_json(problem),
                     **_provenance(args, case, measurements)}, bounds))
    if args.report:
        write_text_atomic(args.report, result_markdown(result, case.name, _truth(case, args),
                                                          case.measurement.noise))
    if args.plot:
        t3 = time.perf_counter()
        with progress_bar(console, "figures", None) as advance:
            paths = write_update_figures(case, problem, measurements, result, args.plot,
                                         on_work=lambda label: advance(label),
                                         executor=_executor(args, case))
        console.print(f"{len(paths)} figures written to {args.plot} "
                      f"({time.perf_counter() - t3:.1f} s): {', '.join(p.name for p in paths)}")
    if not result.status == 0:  # the outputs hold what was found; a script must see the rest
        print(f"vtcr: the loop stopped without converging (status {result.status}): "
              f"{result.message}; exit status {NOT_CONVERGED}", file=sys.stderr)
        return NOT_CONVERGED
    return 0


def cmd_curve(args):
    case = _load(args)
    _updatable_joint_names(case, args, "--joint", [args.joint])
    if args.plot:
        require_matplotlib()
    problem = _modified_problem(case, args, discretisation=False)  # no floor, no interval
    with progress_bar(_console(args), f"cost curve of {args.joint}", args.samples) as advance:
        rows = cost_curve(problem, problem.initial_parameters(), args.joint,
                          log_grid(case.updating.bounds, args.samples), on_point=advance)
    table = Table(title=f"{case.name}: cost against log10 k of {args.joint} (in %; the CSV "
                        "holds fractions)")
    header = ("log10_stiffness", "e_mod", "e_int", "e_mes", "e_joint")
    for column in ("log10 k", "E_mod² %", "E_int² %", "E_mes² %", f"E_Γ² % of {args.joint}"):
        table.add_column(column, justify="right")
    best = min(rows, key=lambda row: row[1])
    for row in rows:
        marker = " <" if row is best else ""  # the minimum, also visible in a log
        table.add_row(f"{row[0]:.4g}", *(f"{100 * v:.4g}" for v in row[1:-1]),
                      f"{100 * row[-1]:.4g}{marker}", style="bold" if row is best else None)
    _console(args).print(table)
    if args.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)
        write_text_atomic(args.csv, buffer.getvalue())
    if args.plot:
        path = write_curve_figure(case, rows, args.joint, args.plot)
        _console(args).print(f"figure written to {path}")
    return 0


def cmd_frf(args):
    case = _load(args)
    console = _console(args)
    if args.plot:
        require_matplotlib()  # fail before the sweep, not after it
    probes = read_probes(args.probes, case) if args.probes else None
    if probes is None:
        points = {pid: field_grid(case, pid, case.measurement.spacing) for pid in case.plates}
        order, nodes = [(pid, i) for pid in case.plates for i in range(len(points[pid]))], None
    else:
        points, order, nodes = probes.by_plate, list(probes.order), probes.nodes
    count = None if args.step is not None else args.start_frequencies
    executor = _executor(args, case)
    with progress_bar(console, f"sweep on {executor.description}", None) as advance:
        sweep = frequency_sweep(case, tuple(args.band), points, step=args.step, count=count,
                                tolerance=args.sampling_tolerance, max_points=args.max_points,
                                executor=executor, check=False,
                                on_round=lambda n: advance(f"{n} frequencies solved", 0))
    _print_sweep(console, case, sweep, len(order))
    estimates = {} if args.no_estimate else _sweep_estimates(case, sweep)
    _estimate_lines(console, estimates, f" of the sweep at its {SWEEP_ESTIMATE_PEAKS} strongest "
                                        "peaks and its top")
    if args.csv:
        write_measurements(args.csv, sweep.measurements(), sweep=True)
    if args.json:
        write_json_atomic(args.json, {**_provenance(args, case), **sweep.to_json(order, nodes),
                                      "error_estimate": _estimates_json(estimates)})
    if args.uff:
        write_uff(args.uff, case, sweep, order, nodes)
    if args.plot:
        paths = write_sweep_figures(case, sweep, args.plot)
        console.print(f"{len(paths)} figures written to {args.plot}: "
                      f"{', '.join(p.name for p in paths)}")
    flagged = int(np.sum(sweep.imbalances > BALANCE_TOLERANCE))
    if flagged:
        _warn(console, f"the power balance misses by more than {BALANCE_TOLERANCE:.0%} at "
                       f"{flagged} frequencies: raise [discretisation] resolution")
    return 0


SWEEP_ESTIMATE_PEAKS = 5
"""Response peaks of a sweep at which its discretisation error is estimated, with the top of
the band: the relative error is largest at the resonances (where the field is most sensitive to
the boundary conditions) and at the highest frequency (where the ray counts are tightest)."""


def _sweep_estimates(case, sweep):
    """Error estimates at the sweep's :data:`SWEEP_ESTIMATE_PEAKS` strongest response peaks
    and at its highest frequency, the largest of which stands for the band (one solve and one
    enriched solve each, not one per frequency of the sweep)."""
    rms = sweep.spatial_rms()
    peaks = [i for i in range(len(rms)) if (i == 0 or rms[i] >= rms[i - 1])
             and (i == len(rms) - 1 or rms[i] >= rms[i + 1])]
    strongest = sorted(peaks, key=lambda i: -rms[i])[:SWEEP_ESTIMATE_PEAKS]
    chosen = sorted({float(sweep.frequencies[i]) for i in strongest}
                    | {float(sweep.frequencies[-1])})
    return {f: estimate_error(case, solve_case(case, f, residuals=False, check=False))
            for f in chosen}


def _print_sweep(console, case, sweep, n_points):
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


def cmd_schema(args):
    text = json.dumps(case_json_schema(), indent=2, ensure_ascii=False) + "\n"
    if not args.out:
        sys.stdout.write(text)
        return 0

    write_text_atomic(args.out, text)
    _console(args).print(f"JSON Schema of the description written to {args.out}; for editor "
                         f"completion, start a description beside it with "
                         f"`#:schema ./{Path(args.out).name}`", markup=False)
    return 0


# What the numbers of every JSON output are in (SI labels; a description in another consistent
# unit system reads them in its own units, see the README).
UNITS = {"length": "m", "w": "m", "frequency": "Hz", "power": "W", "energy": "J",
         "log10_stiffness": "log10 of the rotational stiffness in N (N m/m per rad)",
         "loss_factor": "1", "mass": "kg/m",
         "costs and residuals": "fractions, or % in fields named *_percent"}


def _provenance(args, case, measurements=None):
    """The tool, the units and fingerprints of the inputs, for every JSON output."""
    inputs = {"description": {"path": str(args.case), "sha256": description_digest(case)}}
    probes = getattr(args, "probes", None)
    if probes:
        with open(probes, "rb") as handle:
            inputs["probes"] = {"path": str(probes),
                                "sha256": hashlib.sha256(handle.read()).hexdigest()}
    if measurements is not None:
        inputs["measurements"] = {"path": getattr(args, "measurements", None) or "simulated",
                                  "sha256": measurement_digest(measurements)}
    return {"vtcr": {"version": version_text(), "command": args.command}, "units": UNITS,
            "inputs": inputs}


def _executor(args, case):
    """The command's executor, started once and closed when the command ends (``main``).

    Command-line options win over the description's ``[compute]`` table; ``--workers`` alone
    means local processes even when the description names a scheduler.
    """
    if getattr(args, "executor", None) is None:
        workers, scheduler = getattr(args, "workers", None), getattr(args, "scheduler", None)
        if workers is None and scheduler is None:
            workers, scheduler = case.compute.workers, case.compute.scheduler
        threads = _threads(args, case) if (workers or 1) == 1 and scheduler is None else 1
        args.executor = args.resources.enter_context(Executor(workers or 1, scheduler, threads))
    return args.executor


def _threads(args, case):
    """Threads for the per-frequency solves of this process: one per usable core, as many as
    the estimated peak memory of one solve (``solver.sizing``) lets fit in half the memory."""
    if getattr(args, "threads", None) is None:
        args.threads = frequency_threads(len(case.frequencies) or 1,
                                         estimate_size(case).solve_bytes, available_memory())
    return args.threads


_OUTPUT_OPTIONS = (("out", "--out"), ("json", "--json"), ("csv", "--csv"), ("report", "--report"),
                   ("uff", "--uff"))


def _option_problems(args):
    """One line per bad option value, naming the option and the fix (before any work)."""
    problems = []
    frequencies, noise = getattr(args, "frequency", None) or (), getattr(args, "noise", None)
    seed, samples = getattr(args, "seed", None), getattr(args, "samples", None)
    max_rows = getattr(args, "max_rows", None)
    problems += [f"--frequency {frequency}: must be a finite frequency > 0 in Hz; give "
                 "e.g. --frequency 155" for frequency in frequencies
                 if not (math.isfinite(frequency) and frequency > 0)]
    if noise is not None and not 0 <= noise < 1:
        problems.append(f"--noise {noise}: must be a fraction in [0, 1); give e.g. --noise 0.1 "
                        "for +-10 %")
    if seed is not None and seed < 0:
        problems.append(f"--seed {seed}: must be a whole number >= 0; give e.g. --seed 1")
    if samples is not None and samples < 2:
        problems.append(f"--samples {samples}: must be at least 2 (samples of log10 k over "
                        "[updating] bounds); give e.g. --samples 41")
    problems += [f"--{old.removeprefix('renamed_').replace('_', '-')}: {RENAMED[args.command, old]}"
                 for old, value in vars(args).items()
                 if old.startswith("renamed_") and value is not None]
    if max_rows is not None and max_rows < 0:
        problems.append(f"--max-rows {max_rows}: must be >= 0 (0 shows no rows); give e.g. "
                        "--max-rows 20")
    tolerance = getattr(args, "tolerance", None)
    if tolerance is not None and not 0 < tolerance < 1:
        problems.append(f"--tolerance {tolerance}: must be a relative error in (0, 1); give "
                        "e.g. --tolerance 1e-3")
    confidence = getattr(args, "confidence", None)
    if confidence is not None and not 0 < confidence < 1:
        problems.append(f"--confidence {confidence}: must be a level in (0, 1); give e.g. "
                        "--confidence 0.9")
    workers = getattr(args, "workers", None)
    if workers is not None and workers < 1:
        problems.append(f"--workers {workers}: must be at least 1; give e.g. --workers 2")
    if args.command == "frf":
        problems += _sweep_option_problems(args)
    inputs = [getattr(args, n, None) for n in ("case", "probes", "measurements", "uff_map")]
    for name, flag in (("run_file", "--run"), ("resume", "--resume")):
        if getattr(args, name, None) == "-":
            problems.append(f"{flag} -: a run file is read back to resume a run; give a file "
                            f"name, e.g. {flag} four_plates.run.json")
    for name, flag in _OUTPUT_OPTIONS + (("run_file", "--run"),):
        if getattr(args, name, None) is not None:
            problem = output_path_problem(getattr(args, name), flag, inputs)
            problems += [problem] if problem else []
    outputs = [(flag, getattr(args, name, None)) for name, flag in _OUTPUT_OPTIONS]
    if args.command == "update":  # the run file is written after every step
        outputs.append(("--resume", args.resume) if args.resume else
                       ("--run" if args.run_file else "the run file", _run_path(args)))
    problems += output_collisions(outputs)
    if getattr(args, "plot", None) is not None:
        problem = plot_directory_problem(args.plot)
        problems += [problem] if problem else []
    return problems


def _sweep_option_problems(args):
    """Bad values of ``vtcr frf``'s sweep options, one line each."""
    problems = []
    low, high = args.band
    if not (math.isfinite(low) and math.isfinite(high) and 0 < low < high):
        problems.append(f"--band {low:g} {high:g}: must be two finite frequencies "
                        "0 < F1 < F2 in Hz; give e.g. --band 200 260")
    if args.step is not None and not (math.isfinite(args.step) and args.step > 0):
        problems.append(f"--step {args.step}: must be a finite step > 0 in Hz; give e.g. "
                        "--step 1")
    if args.start_frequencies < 2:
        problems.append(f"--start-frequencies {args.start_frequencies}: a sweep needs at least "
                        "2 frequencies; give e.g. --start-frequencies 41")
    if not 0 < args.sampling_tolerance <= 1:
        problems.append(f"--sampling-tolerance {args.sampling_tolerance}: must be a fraction in "
                        "(0, 1]; give e.g. --sampling-tolerance 0.1")
    if args.max_points < 2:
        problems.append(f"--max-points {args.max_points}: must be at least 2; give e.g. "
                        "--max-points 2000")
    if args.uff is not None:
        try:
            import pyuff  # noqa: F401
        except ImportError:
            problems.append(f"--uff {args.uff}: writing UFF needs pyuff; install it with "
                            "pip install 'pyuff>=2.4' (the extra uff of vtcr)")
    return problems


RENAMED = {
    ("curve", "renamed_points"): "renamed to --samples (log10 k samples); give e.g. "
                                  "--samples 41",
    ("frf", "renamed_points"): "renamed to --start-frequencies (the sweep's initial "
                                "frequencies); give e.g. --start-frequencies 41",
    ("frf", "renamed_tolerance"): "the sweep's refinement criterion is --sampling-tolerance "
                                   "(--tolerance is the discretisation error in every "
                                   "command); give e.g. --sampling-tolerance 0.1",
}
"""The options renamed for one meaning per name, refused for one release with the new name."""

LONG_PLAN_SECONDS = 600.0  # a plan estimated longer than this says so before it starts


COMMANDS = {"check": cmd_check, "solve": cmd_solve, "simulate": cmd_simulate,
            "localise": cmd_localise, "plan": cmd_plan, "update": cmd_update, "curve": cmd_curve,
            "frf": cmd_frf, "schema": cmd_schema}
"""The function of each command (the parser's ``run`` default)."""


def execute(args):
    """Check the options and the description of the parsed ``args``, run their command and
    return its exit status: every expected failure is one line on standard error and a status
    (2 bad input, 1 numerical failure, 130 interrupted; ``docs/cli.md``)."""
    problems = _option_problems(args)
    for line in problems:
        print(f"vtcr: {line}", file=sys.stderr)
    if problems:
        return 2
    try:
        with contextlib.ExitStack() as args.resources:  # the executor's processes, if any
            _check_description(args)
            return COMMANDS[args.run](args)
    except (DescriptionError, InputError) as err:
        lines = str(err).splitlines()
        for line in lines[:MAX_PROBLEM_LINES]:
            print(f"vtcr: {line}", file=sys.stderr)
        if len(lines) > MAX_PROBLEM_LINES:
            print(f"vtcr: ... and {len(lines) - MAX_PROBLEM_LINES} more problems not shown; "
                  "fix these first", file=sys.stderr)
        return 2
    except ToleranceError as err:
        print(f"vtcr: {args.case}: {err}", file=sys.stderr)
        return 2
    except NumericalError as err:
        print(f"vtcr: numerical failure: {err}", file=sys.stderr)
        return 1
    except OSError as err:  # an output that cannot be written after all (atomic_output)
        fix = "free space or give another path" if err.errno == errno.ENOSPC else \
            "give another path"
        print(f"vtcr: {err.filename}: {err.strerror or err}; {fix}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("vtcr: interrupted", file=sys.stderr)
        return 130
