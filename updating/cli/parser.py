"""The ``vtcr`` argument parser: every command, option and default (``docs/cli.md``).

Only argparse: building the parser, and ``vtcr --help``, load neither numpy nor the solver.
Each command's ``run`` default names its function in :data:`updating.cli.commands.COMMANDS`.
"""

from __future__ import annotations

import argparse
from importlib.metadata import PackageNotFoundError, version
from typing import Any, NoReturn

__all__ = ["build_parser", "version_text", "SUMMARY_JOINTS"]


class _DefaultsFormatter(argparse.HelpFormatter):
    """Help that states each option's default, unless its text already does."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if ("default" not in text and action.default not in (None, False, argparse.SUPPRESS)
                and action.option_strings):
            text += f" (default {action.default})"
        return text


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors are one line ``vtcr: ...`` (exit status 2), and
    whose help states every default."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _DefaultsFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"vtcr: {message}; see `{self.prog} --help`\n")


def _estimate_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--no-estimate", action="store_true",
                        help="skip the a-posteriori estimate of the discretisation error (an "
                             "enriched solve per frequency, 1.5 to 3 times a solve)")


def _measurement_options(parser: argparse.ArgumentParser, what: str = "measured field",
                         default: str = "simulated") -> None:
    parser.add_argument("--measurements", metavar="FILE",
                        help=f"{what}: CSV plate,x,y,re,im[,frequency], or a UFF file "
                             f"(.uff, .unv, .58: datasets 58/58b, needs pyuff) with "
                             f"--uff-map (default: {default})")
    parser.add_argument("--uff-map", metavar="MAP.csv",
                        help="CSV node,plate,x,y placing the UFF response nodes on the plates "
                             "(plate-local metres)")


def _confidence_option(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument("--confidence", type=float, metavar="LEVEL",
                        help=f"level of {what} (default [updating] confidence, 0.9)")


SUMMARY_JOINTS = 30
"""Joints above which vtcr localise prints only those that stand out and the next five."""


def _renamed(parser: argparse.ArgumentParser, old: str, new: str,
             why: str = "renamed to") -> None:
    """``old``, kept for one release to be refused with a line naming ``new`` (the value is
    read but not used: ``updating.cli.commands`` refuses it)."""
    parser.add_argument(old, dest=f"renamed_{old.lstrip('-').replace('-', '_')}",
                        metavar="VALUE", help=f"refused: {why} {new}")


def version_text() -> str:
    try:
        return version("vtcr")
    except PackageNotFoundError:  # run from a checkout that was not installed
        return "unknown"


def _compute_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--workers", type=int, metavar="N",
                        help="local worker processes for independent tasks (default [compute] "
                             "workers, else 1: this process)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="a running Dask scheduler, e.g. tcp://host:8786 (default [compute] "
                             "scheduler; needs distributed)")


def _add_check(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr check`` to ``sub``; return its parser (without ``--quiet``)."""
    check = sub.add_parser("check", help="validate and summarise an assembly description")
    check.add_argument("case", help="assembly description (TOML)")
    check.set_defaults(run="check")
    return check


def _add_solve(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr solve`` to ``sub``; return its parser (without ``--quiet``)."""
    solve = sub.add_parser("solve", help="forced response at the description's frequencies")
    solve.add_argument("case", help="assembly description (TOML)")
    solve.add_argument("--probes", help="CSV with header plate,x,y (plate-local metres)")
    solve.add_argument("--json", help="write the results to this JSON file")
    solve.add_argument("--frequency", type=float, action="append",
                       help="solve at this frequency in Hz instead of the description's; "
                            "repeat for several (default: the description's frequencies)")
    solve.add_argument("--max-rows", type=int, default=20,
                       help="rows shown in the terminal (all of them in the JSON)")
    solve.add_argument("--tolerance", type=float, metavar="TOL",
                       help="raise the resolution until the estimated relative L2 error of w "
                            "(or of (u, v, w)) is below TOL on every plate, or exit 2 naming "
                            "the plate that cannot reach it (default [discretisation] "
                            "tolerance; none: solve at the description's resolution)")
    _estimate_option(solve)
    solve.set_defaults(run="solve")
    return solve


def _add_simulate(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr simulate`` to ``sub``; return its parser (without ``--quiet``)."""
    simulate = sub.add_parser("simulate", help="simulated experiment from the true joints")
    simulate.add_argument("case", help="assembly description (TOML)")
    simulate.add_argument("--out", required=True, help="measurement CSV to write")
    simulate.add_argument("--noise", type=float,
                          help="uniform noise fraction (default [measurement] noise)")
    simulate.add_argument("--seed", type=int, help="noise seed (default [measurement] seed)")
    _compute_options(simulate)
    simulate.set_defaults(run="simulate")
    return simulate


def _add_localise(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr localise`` to ``sub``; return its parser (without ``--quiet``)."""
    localise = sub.add_parser("localise", help="per-joint residuals at the model's parameters")
    localise.add_argument("case", help="assembly description (TOML)")
    _measurement_options(localise)
    _estimate_option(localise)
    localise.add_argument("--json", help="write the residuals, their floors and the error "
                                         "estimate to this JSON file")
    localise.add_argument("--all", action="store_true",
                          help=f"print every joint (above {SUMMARY_JOINTS} joints, only those "
                               "that stand out and the next five are printed)")
    _compute_options(localise)
    localise.set_defaults(run="localise")
    return localise


def _add_plan(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr plan`` to ``sub``; return its parser (without ``--quiet``)."""
    plan = sub.add_parser("plan", help="before the test: which joints the planned "
                                       "measurement can identify")
    plan.add_argument("case", help="assembly description (TOML)")
    _measurement_options(plan, "the planned points (their values are not used)",
                         "the description's [measurement] grid and points")
    _confidence_option(plan, "the expected intervals")
    plan.add_argument("--joints", nargs="+", metavar="JOINT",
                      help="plan only these joints (default: every updatable one); each costs "
                           "about 40 %% of a factorisation of the interface problem (vtcr "
                           "check prints the estimate), so plan a large structure region by "
                           "region")
    _estimate_option(plan)
    plan.add_argument("--json", help="write the sensitivities, expected intervals and "
                                     "verdicts to this JSON file")
    plan.add_argument("--plot", metavar="DIR",
                      help="write the sensitivity figure into DIR (needs matplotlib)")
    _compute_options(plan)
    plan.set_defaults(run="plan")
    return plan


def _add_update(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr update`` to ``sub``; return its parser (without ``--quiet``)."""
    update = sub.add_parser("update", help="localisation-correction loop")
    update.add_argument("case", help="assembly description (TOML)")
    _measurement_options(update)
    _estimate_option(update)
    update.add_argument("--json", help="write the steps, the identified values and the "
                                       "timings to this JSON file")
    update.add_argument("--report", help="Markdown report to write")
    update.add_argument("--all", action="store_true",
                        help=f"a row for every joint (above {SUMMARY_JOINTS} joints, only those "
                             "corrected or standing out in some step)")
    update.add_argument("--plot", metavar="DIR",
                        help="write PNG figures into DIR (needs matplotlib)")
    update.add_argument("--run", dest="run_file", metavar="RUN",
                        help="run file saving every finished step (default: beside --report or "
                             "--json, else CASE.run.json in the current directory)")
    update.add_argument("--resume", metavar="RUN",
                        help="continue the run saved in RUN from its last finished step (a "
                             "finished run is reported without running the loop again)")
    update.add_argument("--force", action="store_true",
                        help="replace an existing run file (default: refuse, so that no run "
                             "is lost)")
    _confidence_option(update, "the confidence interval of every corrected joint")
    _compute_options(update)
    update.set_defaults(run="update")
    return update


def _add_curve(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr curve`` to ``sub``; return its parser (without ``--quiet``)."""
    curve = sub.add_parser("curve", help="E_mod^2, E_int^2, E_mes^2 against one joint's log10 k")
    curve.add_argument("case", help="assembly description (TOML)")
    curve.add_argument("--joint", required=True, help="the joint whose log10 k is varied")
    _measurement_options(curve)
    curve.add_argument("--csv", help="write the curve as CSV to this file")
    curve.add_argument("--samples", type=int, default=41,
                       help="samples of log10 k over [updating] bounds (default 41)")
    _renamed(curve, "--points", "--samples")
    _estimate_option(curve)
    curve.add_argument("--plot", metavar="DIR",
                       help="write the curve as DIR/cost_JOINT.png (needs matplotlib)")
    _compute_options(curve)
    curve.set_defaults(run="curve")
    return curve


def _add_frf(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr frf`` to ``sub``; return its parser (without ``--quiet``)."""
    frf = sub.add_parser("frf", help="frequency response and power flow over a band")
    frf.add_argument("case", help="assembly description (TOML)")
    _estimate_option(frf)
    frf.add_argument("--band", nargs=2, type=float, required=True, metavar=("F1", "F2"),
                     help="frequency band (Hz)")
    grid = frf.add_mutually_exclusive_group()
    grid.add_argument("--step", type=float, help="initial frequency step (Hz)")
    grid.add_argument("--start-frequencies", type=int, default=41, metavar="N",
                      help="initial number of frequencies (default 41)")
    frf.add_argument("--sampling-tolerance", type=float, default=0.1,
                     help="refine where neighbouring responses differ by more than this "
                          "fraction (default 0.1)")
    _renamed(frf, "--points", "--start-frequencies")
    frf.add_argument("--tolerance", type=float, metavar="TOL",
                     help="the estimated relative L2 error of w (or of (u, v, w)) to meet at "
                          "every frequency of the band: each sub-band swept at the resolution "
                          "that meets it at its top and its resonances (default "
                          "[discretisation] tolerance; none: the description's resolution)")
    frf.add_argument("--max-points", type=int, default=2000,
                     help="most frequencies of the refined sweep (default 2000)")
    frf.add_argument("--probes", help="CSV with header plate,x,y (default: the measurement grid)")
    frf.add_argument("--csv", help="write the response as plate,x,y,frequency,re,im")
    frf.add_argument("--json", help="write the sweep, the power flows and the sampling")
    frf.add_argument("--uff", metavar="OUT.uff",
                     help="write the response at the probes as UFF datasets 58 (FRFs per newton "
                          "under a single point force), with units (164) and nodes (15); needs "
                          "pyuff")
    frf.add_argument("--plot", metavar="DIR",
                     help="write frf.png and power.png into DIR (needs matplotlib)")
    _compute_options(frf)
    frf.set_defaults(run="frf")
    return frf


def _add_schema(sub: argparse._SubParsersAction[_Parser]) -> _Parser:
    """Add ``vtcr schema`` to ``sub``; return its parser (without ``--quiet``)."""
    schema = sub.add_parser("schema", help="JSON Schema of the description (editor completion)")
    schema.add_argument("--out", help="write it to this file (default: standard output)")
    schema.set_defaults(run="schema")
    return schema


def build_parser() -> _Parser:
    parser = _Parser(
        prog="vtcr",
        description="Localise and correct badly modelled joints of plate assemblies (VTCR).")
    parser.add_argument("--version", action="version", version=f"vtcr {version_text()}")
    sub = parser.add_subparsers(dest="command", required=True)
    commands = [add(sub) for add in (_add_check, _add_solve, _add_simulate, _add_localise,
                                     _add_plan, _add_update, _add_curve, _add_frf, _add_schema)]
    for p in commands:
        p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    return parser
