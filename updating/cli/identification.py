"""The commands of the identification: ``localise``, ``plan``, ``update`` and ``curve``."""

from __future__ import annotations

import argparse
import csv
import io
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from rich.table import Table

from solver.estimate import enriched_size
from solver.sizing import estimate_size
from updating.cli.common import (
    NOT_CONVERGED,
    checked_measurements,
    console_for,
    estimates_json,
    executor_for,
    load_description,
    load_measurements,
    modified_problem,
    print_estimates,
    provenance,
    resolution_for_tolerance,
    run_path_for,
    threads_for,
    warn,
)
from updating.cli.parser import SUMMARY_JOINTS
from updating.cli.progress import progress_bar
from updating.cli.report import (
    identified_lines,
    notable_joints,
    result_json,
    result_markdown,
    steps_table,
)
from updating.data.files import write_json_atomic, write_text_atomic
from updating.data.measurements import (
    Measurements,
    measurement_layout,
)
from updating.data.runfile import (
    RunFile,
    RunLock,
    description_digest,
    fingerprint,
    load_run,
    read_run,
    refuse_other_measurements,
    refuse_replacing,
)
from updating.errors import InputError
from updating.figures.curves import write_curve_figure
from updating.figures.figure_tools import require_matplotlib
from updating.figures.plots import write_update_figures
from updating.figures.responses import write_plan_figure
from updating.inverse.cost import ModifiedProblem, cost_curve, log_grid
from updating.inverse.plan import identifiability_plan
from updating.inverse.strategy import (
    Step,
    UpdateResult,
    excess_ratios,
    finished_result,
    localise,
    standing_summary,
    thresholds,
    update_joints,
)

if TYPE_CHECKING:
    from rich.console import Console

    from assembly import Case
    from assembly.settings import Updating


def cmd_localise(args: argparse.Namespace) -> int:
    case = load_description(args)
    measurements = checked_measurements(case, args)
    problem = modified_problem(case, args, measurements)
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
    console = console_for(args)
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
        write_json_atomic(args.json, {**provenance(args, case, measurements),
                                      **step.to_json(), "weights": _weights_json(problem),
                                      "error_estimate": estimates_json(problem.error_estimates)})
    return 0


def _planned_points(case: Case, args: argparse.Namespace) -> Measurements:
    """The points of the planned measurement: a measurement file's (values unused), else the
    description's grid and point measurements, at every frequency of the description."""
    if getattr(args, "measurements", None):
        return load_measurements(case, args)
    layout = measurement_layout(case)
    if not layout:
        raise InputError(f"{args.case}: measurement: no planned point; add a [measurement] "
                         "spacing (a grid on every plate) or points, or give --measurements")
    return Measurements({f: {pid: (points, np.ones(len(points), dtype=complex))
                             for pid, points in layout.items()} for f in case.frequencies})


def _updatable_joint_names(case: Case, args: argparse.Namespace, option: str,
                           names: list[str]) -> list[str]:
    """``names`` checked against the case's updatable joints (one line and exit 2 naming the
    first that is not one)."""
    for name in names:
        if name not in case.updatable_joints():
            raise InputError(f"{option} {name}: not an updatable joint of {args.case} "
                             f"(joints: {', '.join(case.updatable_joints())}; a junction's "
                             "finite member as JOINT.PLATE); give one of them")
    return names


def cmd_plan(args: argparse.Namespace) -> int:
    case = load_description(args)
    if not case.joints:
        raise InputError(f"{args.case}: joints: the description has no joint to plan for; add "
                         "a [joints.ID] table")
    joints = (_updatable_joint_names(case, args, "--joints", args.joints) if args.joints
              else None)
    console = console_for(args)
    if args.plot:
        require_matplotlib()  # fail before the work, not after it
    points = _planned_points(case, args)
    if case.measurement.noise <= 0.0:
        warn(console, f"{args.case}: [measurement] noise is 0: the plan assumes ±1 % uniform "
                       "noise; state the planned test's, e.g. noise = 0.05")
    level = case.updating.confidence if args.confidence is None else args.confidence
    count = len(joints or case.updatable_joints())
    seconds = estimate_size(case).plan_seconds(
        count, None if args.no_estimate else enriched_size(case))
    if seconds > LONG_PLAN_SECONDS:
        joints_text = f"{count} joint" + ("s" if count != 1 else "")
        warn(console, f"{args.case}: planning {joints_text} takes about {seconds / 60:.0f} min "
                       "on this kind of machine (vtcr check); --joints J1 J2 ... plans some")
    with progress_bar(console, "planning", count) as advance:
        plans, noise, estimates = identifiability_plan(
            case, points, level=level, resolution=resolution_for_tolerance(case, console),
            threads=threads_for(args, case), estimate=not args.no_estimate, joints=joints,
            on_joint=lambda joint: advance(f"planned {joint}"), executor=executor_for(args, case))
    print_estimates(console, estimates, " of the model")
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
            **provenance(args, case, None), "case": case.name, "noise": noise.description,
            "confidence": level, "frequencies": list(frequencies),
            "error_estimate": estimates_json(estimates),
            "joints": {joint: plan.to_json() for joint, plan in plans.items()}})
    if args.plot:
        path = write_plan_figure(plans, frequencies, args.plot, case.name)
        console.print(f"figure written to {path}")
    return 0


def _weights_json(problem: ModifiedProblem) -> dict[str, Any]:
    """The weights of the modified error a run used: ``r`` and, for the scale-free ones, the
    balance and the noise the data were weighed by (``docs/updating.md``, section 2)."""
    if problem.weights is None:
        return {"rule": "given", "r": problem.r}
    w = problem.weights
    return {"rule": "scale-free", "r": w.r, "balance": w.balance, "noise": w.noise}


def _truth(case: Case, args: argparse.Namespace) -> dict[str, dict[str, float]]:
    """``{joint: {parameter: true value}}`` of a simulated experiment (none with measured
    data); a junction's every finite member when its truth gives a value."""
    if getattr(args, "measurements", None):
        return {}
    return case.true_parameters()


def _finished_steps(count: int) -> str:
    return f"{count} finished step{'' if count == 1 else 's'} {'is' if count == 1 else 'are'}"


def _resume_command(args: argparse.Namespace, run_path: str | Path) -> str:
    """The command that continues an interrupted ``vtcr update``, with the outputs it asked for
    (the same JSON, report, figures and measurements)."""
    kept = [f"{option} {value}" for option, value in (
        ("--measurements", getattr(args, "measurements", None)), ("--json", args.json),
        ("--report", args.report), ("--plot", args.plot),
        ("--confidence", args.confidence)) if value is not None]
    return " ".join([f"vtcr update {args.case}", *kept, f"--resume {run_path}"])


def cmd_update(args: argparse.Namespace) -> int:
    case = load_description(args)
    console = console_for(args)
    if args.plot:
        require_matplotlib()  # fail before the run, not after it
    t0 = time.perf_counter()
    measurements, run = _open_run(case, args, console)
    problem = modified_problem(case, args, measurements)
    t1 = time.perf_counter()
    settings = case.updating
    if args.confidence is not None:
        settings = settings.model_copy(update={"confidence": args.confidence})
    result = _run_loop(case, args, console, problem, run, settings)
    if result is None:  # interrupted: the run file holds the finished steps
        return 130
    if not run.finished:  # a finished run read back is reported as its file holds it
        run.finish(result)
    t2 = time.perf_counter()
    _print_result(case, args, console, problem, result, settings)
    timings = _print_sizes_and_timings(console, problem, result, run, t1 - t0, t2 - t1)
    _write_outputs(case, args, console, problem, measurements, result, timings, settings.bounds)
    if not result.status == 0:  # the outputs hold what was found; a script must see the rest
        print(f"vtcr: the loop stopped without converging (status {result.status}): "
              f"{result.message}; exit status {NOT_CONVERGED}", file=sys.stderr)
        return NOT_CONVERGED
    return 0


def _open_run(case: Case, args: argparse.Namespace,
              console: Console) -> tuple[Measurements, RunFile]:
    """The measurements and the run file of ``vtcr update``: the run to resume (``--resume``:
    read, then checked against the description and the measurements) or a new one, which does
    not replace an existing run file without ``--force`` (a finished run of the same
    description and measurements excepted); the file is locked for the command's life."""
    run_path = args.resume or run_path_for(args)
    replaceable = None
    if args.resume:
        read_run(args.resume)  # a missing or foreign file is refused before any work
    elif not args.force:
        replaceable = refuse_replacing(run_path, description_digest(case))
    args.resources.enter_context(RunLock(run_path))
    measurements = checked_measurements(case, args)
    digests = fingerprint(case, measurements)
    refuse_other_measurements(run_path, replaceable, digests[1])
    if args.resume:
        run = load_run(args.resume, case, digests)
        state = ("finished: its result is reported without running the loop again"
                 if run.finished else f"resuming after step {run.steps[-1].step}")
        console.print(f"run file {run.path}: {len(run.steps)} finished steps; {state}")
    else:
        run = RunFile(run_path, case.name, digests)
    return measurements, run


def _run_loop(case: Case, args: argparse.Namespace, console: Console, problem: ModifiedProblem,
              run: RunFile, settings: Updating) -> UpdateResult | None:
    """The localisation–correction loop from the run file's steps, each finished step saved
    in it, with a progress bar (a finished run's result, without running the loop again).
    None when interrupted (Ctrl-C), after saying how to continue."""
    with progress_bar(console, "localising", settings.max_steps + 1) as advance:
        def corrected(number: int, joint: str, again: bool) -> None:
            advance(f"step {number}: {'re-' if again else ''}correcting {joint}", amount=0)

        def finished(step: Step) -> None:
            run.save_step(step)
            advance(f"step {step.step} finished (E_mod^2 {100 * step.e_mod:.2f} %)")

        try:
            if run.finished:
                return finished_result(problem, run.steps, run.finished[0], settings,
                                       case.measurement.noise)
            return update_joints(problem, settings, noise=case.measurement.noise,
                                 start=run.steps, on_step=finished, on_correct=corrected)
        except KeyboardInterrupt:
            print(f"vtcr: interrupted; {_finished_steps(len(run.steps))} saved in {run.path}; "
                  f"continue with: {_resume_command(args, run.path)}", file=sys.stderr)
            return None


def _print_result(case: Case, args: argparse.Namespace, console: Console,
                  problem: ModifiedProblem, result: UpdateResult, settings: Updating) -> None:
    """The steps' table (a large structure's notable joints only, unless ``--all``), the first
    localisation's standing joints, the weights and the identified values."""
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


def _print_sizes_and_timings(console: Console, problem: ModifiedProblem, result: UpdateResult,
                             run: RunFile, setup: float, updating: float) -> dict[str, float]:
    """Print the problem's size and the run's timings (``setup`` and ``updating`` in s), and
    what one evaluation costs; return the timings for the JSON."""
    n_rays, n_s, n_g = problem.size
    console.print(f"{n_rays} ray unknowns, {n_s} interface unknowns, {n_g} constraints; "
                  f"set-up {setup:.2f} s, updating {updating:.2f} s; run file {run.path}")
    n_f = len(problem.frequencies)
    joint = next((s.selected for s in reversed(result.steps) if s.selected),
                 next(iter(problem.joints), None))
    timings = {"setup": setup, "updating": updating,
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
    return timings


def _write_outputs(case: Case, args: argparse.Namespace, console: Console,
                   problem: ModifiedProblem, measurements: Measurements, result: UpdateResult,
                   timings: Mapping[str, float], bounds: tuple[float, float]) -> None:
    """The outputs ``vtcr update`` was asked for: ``--json``, ``--report`` and ``--plot``."""
    if args.json:
        sizes = dict(zip(("ray_unknowns", "interface_unknowns", "constraints"), problem.size))
        write_json_atomic(args.json, result_json(
            result, {"case": case.name, "sizes": sizes, "timings_s": timings,
                     "error_estimate": estimates_json(problem.error_estimates),
                     "weights": _weights_json(problem),
                     **provenance(args, case, measurements)}, bounds))
    if args.report:
        write_text_atomic(args.report, result_markdown(
            result, case.name, _truth(case, args), case.measurement.noise,
            getattr(args, "description_warnings", ())))
    if args.plot:
        t3 = time.perf_counter()
        with progress_bar(console, "figures", None) as advance:
            paths = write_update_figures(case, problem, measurements, result, args.plot,
                                         on_work=lambda label: advance(label),
                                         executor=executor_for(args, case))
        console.print(f"{len(paths)} figures written to {args.plot} "
                      f"({time.perf_counter() - t3:.1f} s): {', '.join(p.name for p in paths)}")


def cmd_curve(args: argparse.Namespace) -> int:
    case = load_description(args)
    _updatable_joint_names(case, args, "--joint", [args.joint])
    if args.plot:
        require_matplotlib()
    problem = modified_problem(case, args, discretisation=False)  # no floor, no interval
    with progress_bar(console_for(args), f"cost curve of {args.joint}", args.samples) as advance:
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
    console_for(args).print(table)
    if args.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(rows)
        write_text_atomic(args.csv, buffer.getvalue())
    if args.plot:
        path = write_curve_figure(case, rows, args.joint, args.plot)
        console_for(args).print(f"figure written to {path}")
    return 0


LONG_PLAN_SECONDS = 600.0  # a plan estimated longer than this says so before it starts
