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
        results.append({
            "frequency": frequency,
            "unknowns": solution.n_unknowns,
            "condition_estimate": solution.condition_estimate,
            "warnings": list(solution.warnings),
            "probes": rows,
        })
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

    for p in (check, solve):
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
