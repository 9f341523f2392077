"""Command-line interface: ``vtcr check | solve | ...`` (also ``python -m updating``).

Bad input exits with status 2 and one line per problem naming the file, the field and the fix;
no traceback. The commands only format what the library returns.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
from rich.console import Console
from rich.table import Table

__all__ = ["main"]


def _console(args):
    return Console(quiet=getattr(args, "quiet", False), highlight=False)


def _load(path):
    from assembly import load_case

    return load_case(path)


def _frequencies(case, args):
    if getattr(args, "frequency", None) is None:
        return case.frequencies
    return (args.frequency,)


def cmd_check(args):
    from assembly import summarise

    case = _load(args.case)
    _console(args).print(summarise(case))
    return 0


def _solution_warnings(console, solution):
    for warning in solution.warnings:
        console.print(f"[yellow]warning:[/] {warning}")


def cmd_solve(args):
    from solver import field_grid, solve_case
    from updating.files import read_probes, write_json_atomic

    case = _load(args.case)
    probes = read_probes(args.probes, case) if args.probes else None
    console = _console(args)
    results = []
    for frequency in _frequencies(case, args):
        solution = solve_case(case, frequency)
        _solution_warnings(console, solution)
        if probes is None:
            spacing = case.measurement.spacing
            points = {pid: field_grid(case, pid, spacing) for pid in case.plates}
            order = [(pid, i) for pid in case.plates for i in range(len(points[pid]))]
        else:
            points, order = probes.by_plate, probes.order
        values = {pid: solution.w(pid, pts) for pid, pts in points.items()}
        rows = [
            {"plate": pid, "x": float(points[pid][i, 0]), "y": float(points[pid][i, 1]),
             "w": [float(values[pid][i].real), float(values[pid][i].imag)]}
            for pid, i in order
        ]
        residuals = getattr(solution, "residuals", {})
        results.append({
            "frequency": frequency,
            "unknowns": solution.n_unknowns,
            "condition_estimate": solution.condition_estimate,
            "warnings": list(solution.warnings),
            "joint_residuals": residuals,
            "probes": rows,
        })
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
    if args.json:
        write_json_atomic(args.json, results[0] if len(results) == 1 else {"frequencies": results})
    return 0


def _measurements(case, args):
    from updating.measurements import read_measurements, simulate_measurements

    if getattr(args, "measurements", None):
        return read_measurements(args.measurements, case)
    return simulate_measurements(case)


def cmd_simulate(args):
    from updating.measurements import simulate_measurements, write_measurements

    case = _load(args.case)
    measurements = simulate_measurements(case, noise=args.noise, seed=args.seed)
    write_measurements(args.out, measurements)
    _console(args).print(f"{measurements.count()} simulated values at "
                         f"{', '.join(f'{f:g}' for f in measurements.frequencies)} Hz "
                         f"written to {args.out}")
    return 0


def _modified_problem(case, args):
    from updating.cost import ModifiedProblem

    return ModifiedProblem(case, _measurements(case, args))


def cmd_localise(args):
    from updating.files import write_json_atomic
    from updating.strategy import localise

    case = _load(args.case)
    problem = _modified_problem(case, args)
    step = localise(problem, problem.initial_parameters(), noise=case.measurement.noise)
    table = Table(title=f"{case.name}: joint residuals (E_mod^2 = {100 * step.e_mod:.3f} %)")
    for column in ("joint", "log10 k", "E_Gamma^2 %", "floor %"):
        table.add_column(column, justify="right")
    for joint in sorted(step.residuals, key=step.residuals.get, reverse=True):
        table.add_row(joint, f"{step.parameters[joint]['log10_stiffness']:.2f}",
                      f"{100 * step.residuals[joint]:.3f}", f"{100 * step.floors[joint]:.3f}")
    _console(args).print(table)
    if args.json:
        write_json_atomic(args.json, step.to_json())
    return 0


def cmd_update(args):
    import time

    from updating.files import write_json_atomic, write_text_atomic
    from updating.report import result_json, result_markdown, steps_table
    from updating.strategy import update_joints

    case = _load(args.case)
    console = _console(args)
    t0 = time.perf_counter()
    problem = _modified_problem(case, args)
    t1 = time.perf_counter()
    result = update_joints(problem, case.updating, noise=case.measurement.noise)
    t2 = time.perf_counter()
    bounds = case.updating.bounds
    console.print(steps_table(result, f"{case.name}: localisation and correction", bounds))
    n_rays, n_s, n_g = problem.size
    console.print(f"{n_rays} ray unknowns, {n_s} interface unknowns, {n_g} constraints; "
                  f"set-up {t1 - t0:.2f} s, updating {t2 - t1:.2f} s")
    if args.json:
        write_json_atomic(args.json, result_json(result, {"case": case.name}))
    if args.report:
        write_text_atomic(args.report, result_markdown(result, case.name, bounds))
    return 0


def cmd_curve(args):
    import csv
    import io

    import numpy as np

    from updating.cost import cost_curve
    from updating.files import InputError, write_text_atomic

    case = _load(args.case)
    if args.joint not in case.joints:
        raise InputError(f"--joint {args.joint}: not a joint of {args.case} "
                         f"(joints: {', '.join(case.joints)})")
    problem = _modified_problem(case, args)
    lo, hi = case.updating.bounds
    rows = cost_curve(problem, problem.initial_parameters(), args.joint,
                      np.linspace(lo, hi, args.points))
    table = Table(title=f"{case.name}: cost against log10 k of {args.joint}")
    header = ("log10_stiffness", "e_mod", "e_int", "e_mes", "e_joint")
    for column in header:
        table.add_column(column, justify="right")
    best = min(rows, key=lambda row: row[1])
    for row in rows:
        style = "bold" if row is best else None
        table.add_row(*(f"{v:.4g}" for v in row), style=style)
    _console(args).print(table)
    if args.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)
        write_text_atomic(args.csv, buffer.getvalue())
    return 0


def build_parser():
    parser = argparse.ArgumentParser(
        prog="vtcr",
        description="Localise and correct badly modelled joints of plate assemblies (VTCR).")
    sub = parser.add_subparsers(dest="command", required=True)

    check = sub.add_parser("check", help="validate and summarise an assembly description")
    check.add_argument("case", help="assembly description (TOML)")
    check.set_defaults(run=cmd_check)

    solve = sub.add_parser("solve", help="forced response at the description's frequencies")
    solve.add_argument("case", help="assembly description (TOML)")
    solve.add_argument("--probes", help="CSV with header plate,x,y (plate-local metres)")
    solve.add_argument("--json", help="write the results to this JSON file")
    solve.add_argument("--frequency", type=float, help="solve at this frequency (Hz) only")
    solve.add_argument("--max-rows", type=int, default=20, help="rows shown in the terminal")
    solve.set_defaults(run=cmd_solve)

    simulate = sub.add_parser("simulate", help="simulated experiment from the true joints")
    simulate.add_argument("case")
    simulate.add_argument("--out", required=True, help="measurement CSV to write")
    simulate.add_argument("--noise", type=float, help="uniform noise fraction (default [measurement] noise)")
    simulate.add_argument("--seed", type=int, help="noise seed (default [measurement] seed)")
    simulate.set_defaults(run=cmd_simulate)

    localise = sub.add_parser("localise", help="per-joint residuals at the model's parameters")
    localise.add_argument("case")
    localise.add_argument("--measurements", help="measurement CSV (default: simulated)")
    localise.add_argument("--json")
    localise.set_defaults(run=cmd_localise)

    update = sub.add_parser("update", help="localisation-correction loop")
    update.add_argument("case")
    update.add_argument("--measurements", help="measurement CSV (default: simulated)")
    update.add_argument("--json")
    update.add_argument("--report", help="Markdown report to write")
    update.set_defaults(run=cmd_update)

    curve = sub.add_parser("curve", help="E_mod^2, E_int^2, E_mes^2 against one joint's log10 k")
    curve.add_argument("case")
    curve.add_argument("--joint", required=True)
    curve.add_argument("--measurements", help="measurement CSV (default: simulated)")
    curve.add_argument("--csv")
    curve.add_argument("--points", type=int, default=41)
    curve.set_defaults(run=cmd_curve)

    for p in (check, solve, simulate, localise, update, curve):
        p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return parser


def main(argv=None):
    """Entry point of the ``vtcr`` console script; returns the exit status."""
    from assembly import DescriptionError
    from updating.files import InputError

    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "frequency", None) is not None and not args.frequency > 0:
        parser.error(f"--frequency must be > 0 Hz, got {args.frequency}")
    if getattr(args, "noise", None) is not None and not 0 <= args.noise < 1:
        parser.error(f"--noise must be a fraction in [0, 1), got {args.noise}")
    if getattr(args, "points", 2) < 2:
        parser.error(f"--points must be at least 2, got {args.points}")
    try:
        return args.run(args)
    except (DescriptionError, InputError) as err:
        for line in str(err).splitlines():
            print(f"vtcr: {line}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("vtcr: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
