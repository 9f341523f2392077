"""What the commands share: the console, the description and the measurements they load, the
modified problem they build, the error-estimate lines, provenance and the executor."""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import hashlib
import math
import os
import sys
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.console import Console
from rich.markup import escape

from assembly import Case, load_case
from solver.errors import NumericalError
from solver.estimate import ErrorEstimate, unseen_texts
from solver.sizing import available_memory, estimate_size
from solver.tolerance import solve_to_tolerance
from updating.cli.parser import version_text
from updating.data.measurements import (
    Measurements,
    check_joints_seen,
    read_measurements,
    simulate_measurements,
)
from updating.data.runfile import (
    description_digest,
    measurement_digest,
)
from updating.data.uff import UFF_SUFFIXES, is_uff, read_uff
from updating.errors import InputError
from updating.executor import Executor, frequency_threads
from updating.inverse.cost import ModifiedProblem

if TYPE_CHECKING:
    from solver import CaseSolution

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


OUTPUT_OPTIONS = (("out", "--out"), ("json", "--json"), ("csv", "--csv"), ("report", "--report"),
                   ("uff", "--uff"))
"""The options that name output files (``-``: standard output)."""


def map_large_arrays() -> None:
    """Fix glibc's mmap threshold at :data:`MMAP_THRESHOLD` (nothing on other C libraries)."""
    if "MALLOC_MMAP_THRESHOLD_" in os.environ or "mmap_threshold" in os.environ.get(
            "GLIBC_TUNABLES", ""):
        return

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.mallopt(-3, MMAP_THRESHOLD)  # M_MMAP_THRESHOLD of <malloc.h>
    except (OSError, AttributeError):  # not glibc: its own policy stays
        pass


def console_for(args: argparse.Namespace) -> Console:
    # with an output on standard output (``--json -``) the tables go to standard error, so
    # that the output can be piped; a file or a pipe has no width: 120 columns keeps wide
    # tables (Table 4) on one line
    to_stderr = any(str(getattr(args, name, None)) == "-" for name, _ in OUTPUT_OPTIONS)
    stream = sys.stderr if to_stderr else sys.stdout
    width = None if stream.isatty() else 120
    return Console(quiet=getattr(args, "quiet", False), highlight=False, width=width,
                   stderr=to_stderr)


def load_description(args: argparse.Namespace) -> Case:
    """The description of ``args.case``, loaded and validated once per command."""
    if getattr(args, "case_model", None) is None:
        args.case_model = load_case(args.case)
    return args.case_model


def frequencies_of(case: Case, args: argparse.Namespace) -> tuple[float, ...]:
    if getattr(args, "frequency", None) is None:
        return case.frequencies
    return tuple(args.frequency)


def print_solution_warnings(console: Console, solution: CaseSolution) -> None:
    for warning in solution.warnings:
        warn(console, warning)


def warn(console: Console, line: str) -> None:
    console.print(f"[yellow]warning:[/] {escape(line)}", soft_wrap=True)


def checked_measurements(case: Case, args: argparse.Namespace) -> Measurements:
    """:func:`load_measurements`, after checking that they can see the joints to update."""
    if not case.joints:
        raise InputError(f"{args.case}: joints: the description has no joint to update; add a "
                         "[joints.ID] table (vtcr solve works without joints)")
    joints = ([args.joint] if getattr(args, "joint", None) in case.updatable_joints()
              else None)
    if not getattr(args, "measurements", None):  # simulated: check the layout first
        warnings = check_joints_seen(case, None, joints, f"{args.case}: measurement")
        measurements = load_measurements(case, args)
    else:
        measurements = load_measurements(case, args)
        warnings = check_joints_seen(case, measurements, joints, args.measurements)
    for line in warnings:
        warn(console_for(args), line)
    return measurements


def print_problem_warnings(args: argparse.Namespace, problem: ModifiedProblem) -> None:
    """Print the condition warnings of a ModifiedProblem; stop on a non-finite set-up."""
    for line in getattr(problem, "warnings", ()):
        warn(console_for(args), line)
    for frequency, energy in problem.reference_energies.items():
        if not (math.isfinite(energy) and energy > 0):
            raise NumericalError(f"the reference energy at {frequency:g} Hz is {energy}: the "
                                 "model's response is zero or not finite; check the loads and "
                                 "the plates' materials")


# Problems of one input printed at most (a generated file can hold a million bad keys).
MAX_PROBLEM_LINES = 50


# Estimated errors above this are flagged (the accuracy the tests hold the rule to).
ESTIMATE_WARNING = 1e-2


def resolution_text(resolution: float | dict[str, float]) -> str:
    """A resolution factor, or the range of per-plate factors."""
    if isinstance(resolution, dict):
        values = resolution.values()
        return f"{min(values):.3g}-{max(values):.3g} (per plate)"
    return f"{resolution:.3g}"


def load_measurements(case: Case, args: argparse.Namespace) -> Measurements:
    path, uff_map = getattr(args, "measurements", None), getattr(args, "uff_map", None)
    if path and is_uff(path):  # dispatch on the suffix: UFF 58 (needs pyuff) or CSV
        return read_uff(path, case, uff_map)
    if uff_map:
        raise InputError(f"--uff-map {uff_map}: only used with a UFF measurement file "
                         f"({', '.join(UFF_SUFFIXES)}); got --measurements {path or '(none)'}")
    if path:
        return read_measurements(path, case)
    warn_untrue_simulation(args, case)
    return simulate_measurements(case, executor=executor_for(args, case))


def warn_untrue_simulation(args: argparse.Namespace, case: Case) -> None:
    """A simulated experiment of a description without [truth] measures the model itself."""
    if case.joints and not case.truth.joints:
        warn(console_for(args), f"{args.case} has no [truth.joints] table: the simulated "
                              "experiment is the model itself (its joints as described), so "
                              "only noise and discretisation are left to find; add "
                              "[truth.joints.ID] tables, or give measured data")


def modified_problem(case: Case, args: argparse.Namespace,
                     measurements: Measurements | None = None,
                     discretisation: bool = True) -> ModifiedProblem:
    """The updating problem on ``measurements`` (default: read or simulated per ``args``);
    ``discretisation``: see :class:`updating.inverse.cost.ModifiedProblem`."""
    if measurements is None:
        measurements = checked_measurements(case, args)
    resolution = resolution_for_tolerance(case, console_for(args))
    executor = executor_for(args, case)
    problem = ModifiedProblem(case, measurements, resolution=resolution, executor=executor,
                              estimate=not getattr(args, "no_estimate", True),
                              threads=executor.threads, discretisation=discretisation,
                              check=False)  # checked before the command ran
    print_problem_warnings(args, problem)
    print_estimates(console_for(args), problem.error_estimates,
                    " of the model at its initial parameters")
    return problem


def resolution_for_tolerance(case: Case, console: Console) -> dict[str, float] | None:
    """With ``[discretisation] tolerance``: the resolution at which the model's response meets
    it at every frequency (the highest any frequency needs); else None (the description's)."""
    tolerance = case.discretisation.tolerance
    if tolerance is None:
        return None
    resolution = dict.fromkeys(case.plates, 0.0)
    for frequency in case.frequencies:
        estimate = solve_to_tolerance(case, frequency, tolerance)[1]
        resolution = {pid: max(r, estimate.resolution_of(pid)) for pid, r in resolution.items()}
    console.print(f"resolution {resolution_text(resolution)} meets the tolerance "
                  f"{tolerance:g} at every frequency (\\[discretisation] tolerance)")
    return resolution


def print_estimates(console: Console, estimates: Mapping[float, ErrorEstimate],
                    what: str = "") -> None:
    """One line: the estimated error of w at each frequency of ``estimates`` (``{frequency:
    ErrorEstimate}``), its resolution and the worst plate (and one for the in-plane field
    where there is one); a warning above :data:`ESTIMATE_WARNING` or when the estimate was
    skipped."""
    if not estimates:
        return
    skipped = [e for e in estimates.values() if e.total is None]
    if skipped:
        warn(console, f"the discretisation error is not estimated: {skipped[0].reason}; give "
                       "--no-estimate to skip it knowingly")
        return
    worst = max(estimates.values(), key=lambda e: e.total)
    plate = max(worst.plates, key=worst.plates.get)  # of w
    console.print(f"estimated error of w{what} (relative L2, against an enriched solve): "
                  + ", ".join(f"{e.total:.1e} at {f:g} Hz" for f, e in estimates.items())
                  + f" (resolution {resolution_text(worst.resolution)})"
                  + (f"; largest on plate {plate} ({worst.plates[plate]:.1e})"
                     if len(worst.plates) > 1 else ""))
    in_plane = {f: e for f, e in estimates.items() if e.in_plane}
    if in_plane:  # the members of moving lines: their (u, v), relative to its own norm
        worst_in_plane = max(in_plane.values(), key=lambda e: e.in_plane_total)
        plate = max(worst_in_plane.in_plane, key=worst_in_plane.in_plane.get)
        console.print("estimated error of the in-plane displacement (u, v)"
                      f"{what}: " + ", ".join(f"{e.in_plane_total:.1e} at {f:g} Hz"
                                               for f, e in in_plane.items())
                      + f"; largest on plate {plate} ({worst_in_plane.in_plane[plate]:.1e})")
    unseen = {f: unseen_texts(e, e.total) for f, e in estimates.items()}
    for kind in ("lines", "near forces"):  # one warning per kind, at the first frequency
        blind = [(f, texts[kind]) for f, texts in unseen.items() if kind in texts]
        if blind:
            frequency, text = blind[0]
            warn(console, f"{frequency:g} Hz"
                 + (f" (and {len(blind) - 1} more frequencies)" if len(blind) > 1 else "")
                 + f": {text}")
    if worst.total > ESTIMATE_WARNING:
        warn(console, f"the estimated error {worst.total:.1e} exceeds {ESTIMATE_WARNING:g}: "
                       "raise [discretisation] resolution or give a tolerance")
    # a small plate can be wrong while the total, weighted by the energy, is not
    above = {}
    for f, e in estimates.items():
        for pid, value in e.plates.items():
            if value > ESTIMATE_WARNING and value > above.get(pid, (0.0, 0.0))[0]:
                above[pid] = (value, f)
    if above:
        warn(console, f"the estimated error exceeds {ESTIMATE_WARNING:g} on plate"
                       f"{'s' if len(above) > 1 else ''} "
                       + ", ".join(f"{pid} ({v:.1e} at {f:g} Hz)" for pid, (v, f) in above.items())
                       + ": raise [discretisation] resolution (of those plates) or give a "
                         "tolerance")


def estimates_json(estimates: Mapping[float, ErrorEstimate]) -> dict[str, Any] | None:
    """``error_estimate`` of a multi-frequency JSON: the worst total and plate values over the
    frequencies, and every frequency's estimate."""
    if not estimates:
        return None
    values = list(estimates.values())
    known = all(e.total is not None for e in values)
    out = {"total": max(e.total for e in values) if known else None,
           "plates": _worst_by_plate(e.plates for e in values),
           "frequencies": {f"{f:g}": e.to_json() for f, e in estimates.items()}}
    in_plane = [e for e in values if e.in_plane]
    if in_plane:  # only where some plate carries an in-plane field: flat JSON as before
        out["in_plane"] = {"total": max(e.in_plane_total for e in in_plane),
                           "plates": _worst_by_plate(e.in_plane for e in in_plane)}
    return out


def _worst_by_plate(per_frequency: Iterable[Mapping[str, float]]) -> dict[str, float]:
    """Per plate, the largest of its values over the frequencies."""
    worst: dict[str, float] = {}
    for values in per_frequency:
        for pid, value in values.items():
            worst[pid] = max(worst.get(pid, 0.0), value)
    return worst


def run_path_for(args: argparse.Namespace) -> Path:
    """The run file: ``--run``, else beside the report or the JSON, else ``CASE.run.json``."""
    if args.run_file:
        return Path(args.run_file)
    for output in (args.report, args.json):
        if output and output != "-":
            return Path(output).with_suffix(".run.json")
    return Path(Path(args.case).stem + ".run.json")


# What the numbers of every JSON output are in (SI labels; a description in another consistent
# unit system reads them in its own units, see the README).
UNITS = {"length": "m", "w": "m", "frequency": "Hz", "power": "W", "energy": "J",
         "log10_stiffness": "log10 of the rotational stiffness in N (N m/m per rad)",
         "loss_factor": "1", "mass": "kg/m",
         "costs and residuals": "fractions, or % in fields named *_percent"}


def provenance(args: argparse.Namespace, case: Case,
               measurements: Measurements | None = None) -> dict[str, Any]:
    """The tool, the units and fingerprints of the inputs, for every JSON output, with the
    warnings the description's checks gave (a number they qualify, such as an error estimate
    that leaves out what a warning names, keeps its caveat in the file)."""
    inputs = {"description": {"path": str(args.case), "sha256": description_digest(case),
                              "warnings": list(getattr(args, "description_warnings", ()))}}
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


def executor_for(args: argparse.Namespace, case: Case) -> Executor:
    """The command's executor, started once and closed when the command ends (``main``).

    Command-line options win over the description's ``[compute]`` table; ``--workers`` alone
    means local processes even when the description names a scheduler.
    """
    if getattr(args, "executor", None) is None:
        workers, scheduler = getattr(args, "workers", None), getattr(args, "scheduler", None)
        if workers is None and scheduler is None:
            workers, scheduler = case.compute.workers, case.compute.scheduler
        threads = threads_for(args, case) if (workers or 1) == 1 and scheduler is None else 1
        args.executor = args.resources.enter_context(Executor(workers or 1, scheduler, threads))
    return args.executor


def threads_for(args: argparse.Namespace, case: Case) -> int:
    """Threads for the per-frequency solves of this process: one per usable core, as many as
    the estimated peak memory of one solve (``solver.sizing``) lets fit in half the memory."""
    if getattr(args, "threads", None) is None:
        args.threads = frequency_threads(len(case.frequencies) or 1,
                                         estimate_size(case).solve_bytes, available_memory())
    return args.threads
