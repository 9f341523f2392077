"""The commands of ``vtcr``: one function per command, each taking the parsed arguments and
returning the exit status (:data:`COMMANDS`), and :func:`execute`, which checks the options and
the description, runs a command and turns every expected failure into one line and a status.

Bad input exits with status 2 and one line per problem naming the file, the field and the fix;
no traceback. The commands only format what the library returns.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import math
import sys

from assembly import DescriptionError
from solver.errors import NumericalError, ToleranceError
from solver.guards import check_description
from solver.sizing import estimate_size
from updating.cli.common import (
    MAX_PROBLEM_LINES,
    OUTPUT_OPTIONS,
    console_for,
    load_description,
    map_large_arrays,
    run_path_for,
    warn,
)
from updating.cli.identification import cmd_curve, cmd_localise, cmd_plan, cmd_update
from updating.cli.model import cmd_check, cmd_frf, cmd_schema, cmd_simulate, cmd_solve
from updating.data.files import output_collisions, output_path_problem, plot_directory_problem
from updating.errors import InputError

__all__ = ["execute", "COMMANDS"]


def _check_description(args: argparse.Namespace) -> None:
    """Physical and numerical sanity of the description, before any work; prints warnings and
    keeps them in ``args.description_warnings``, for the JSON outputs (:func:`provenance`)."""
    if not getattr(args, "case", None):
        return
    frequency = getattr(args, "frequency", None)
    frequencies = None if frequency is None else tuple(frequency)
    if args.command == "frf":  # the band's ends bound every frequency of the sweep
        frequencies = tuple(args.band)
    case = load_description(args)
    args.description_warnings = check_description(case, args.case, frequencies,
                                                  need_loads=args.command != "check")
    for line in args.description_warnings:
        warn(console_for(args), line)
    if case.joints:
        if estimate_size(case, max(frequencies) if frequencies else None).grouped:
            map_large_arrays()


def _option_problems(args: argparse.Namespace) -> list[str]:
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
    for name, flag in OUTPUT_OPTIONS + (("run_file", "--run"),):
        if getattr(args, name, None) is not None:
            problem = output_path_problem(getattr(args, name), flag, inputs)
            problems += [problem] if problem else []
    outputs = [(flag, getattr(args, name, None)) for name, flag in OUTPUT_OPTIONS]
    if args.command == "update":  # the run file is written after every step
        outputs.append(("--resume", args.resume) if args.resume else
                       ("--run" if args.run_file else "the run file", run_path_for(args)))
    problems += output_collisions(outputs)
    if getattr(args, "plot", None) is not None:
        problem = plot_directory_problem(args.plot)
        problems += [problem] if problem else []
    return problems


def _sweep_option_problems(args: argparse.Namespace) -> list[str]:
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
}
"""The options renamed for one meaning per name, refused for one release with the new name."""


COMMANDS = {"check": cmd_check, "solve": cmd_solve, "simulate": cmd_simulate,
            "localise": cmd_localise, "plan": cmd_plan, "update": cmd_update, "curve": cmd_curve,
            "frf": cmd_frf, "schema": cmd_schema}
"""The function of each command (the parser's ``run`` default)."""


def execute(args: argparse.Namespace) -> int:
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
