"""Reports of an updating run: a rich table like the paper's Table 4, JSON, Markdown.

Formatting only: everything shown comes from :class:`updating.inverse.strategy.UpdateResult`.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from rich import box
from rich.table import Table

from updating.inverse.strategy import Step, UpdateResult, thresholds

if TYPE_CHECKING:
    from updating.inverse.confidence import ConfidenceInterval

__all__ = ["steps_table", "identified_lines", "result_json", "result_markdown", "notable_joints"]


def _label(step: Step) -> str:
    return f"step {step.step}" + ("*" if step.recorrection else "")


OUTSIDE = ("; the estimate lies outside it: the noise biases the estimate, while the interval "
           "is calibrated at each candidate value")
"""Said of an identified value outside its own interval when the data carry noise: the score
test's interval holds the truth at its level whatever the estimator's bias
(:mod:`updating.inverse.confidence`), and with noise the estimate is biased by about its own
spread (the four plates' G2: 4.20 with ``>= 4.29``, true 4.5)."""

OUTSIDE_NOISE_FREE = ("; the estimate lies outside it: without noise, what the data hold "
                      "beyond the model (its discretisation error, or a joint it does not "
                      "correct) biases the estimate, while the interval is calibrated at each "
                      "candidate value")
"""Said of an identified value outside its own interval when no noise is stated: the bias
cannot be the noise's."""


def identified_lines(result: UpdateResult, truth: Mapping[str, Mapping[str, float]] | None = None,
                     noise: float | None = None) -> list[str]:
    """One line per corrected joint and identified parameter: its value and its confidence
    interval (or bound), its true value where ``truth`` (``{joint: {parameter: value}}``,
    :meth:`assembly.Case.true_parameters`) has it, and why the value lies outside its interval
    when it does (:data:`OUTSIDE` with the stated ``noise``, :data:`OUTSIDE_NOISE_FREE`
    without: ``noise = 0``)."""
    outside = OUTSIDE_NOISE_FREE if noise == 0.0 else OUTSIDE
    truth = truth or {}
    lines = []

    def line(joint: str, name: str, interval: ConfidenceInterval, label: str,
             digits: str) -> str:
        value = result.parameters[joint][name]
        text = f"{joint}: {label} = {value:{digits}}; {interval.text}"
        if name in truth.get(joint, {}):
            text += f" (true {truth[joint][name]:{digits}})"
        # within the printed digits, a value on an end is in the interval
        tolerance = 0.005 if name == "log10_stiffness" else 0.005 * abs(value)
        return text + ("" if interval.holds(value, tolerance) else outside)

    for joint, interval in sorted(result.intervals.items()):
        lines.append(line(joint, "log10_stiffness", interval, "log10 k", ".2f"))
        for (other, name), more in sorted(result.parameter_intervals.items()):
            if other == joint:
                lines.append(line(joint, name, more, name.replace("_", " "), ".3g"))
    if result.intervals:
        method = next(iter(result.intervals.values())).method
        lines.append(f"intervals: {method}")
    return lines


def steps_table(result: UpdateResult, title: str,
                joints: Collection[str] | None = None) -> Table:
    """Rows: joints, then E_mod^2 and its noise floor; per step log10 k and E_Gamma^2 (%).

    The joint corrected in a step is shown in bold (the paper's Table 4) and marked ``>``, which
    a log without styles keeps; a step marked ``*`` re-corrects a joint selected before (see
    :mod:`updating.inverse.strategy`). ``joints`` restricts the rows (a large structure's summary,
    :func:`notable_joints`); the caption counts the others.
    """
    # left padding only: five steps of four joints fit in 80 columns
    table = Table(title=title, box=box.SIMPLE_HEAD, pad_edge=False, padding=(0, 0, 0, 1))
    table.add_column("joint", no_wrap=True)
    for step in result.steps:
        table.add_column(f"{_label(step)}\nlog k", justify="right", no_wrap=True)
        table.add_column("\nE_Γ² %", justify="right", no_wrap=True)
    every = list(result.steps[0].parameters)
    rows = every if joints is None else [j for j in every if j in set(joints)]
    for joint in rows:
        cells = []
        for step in result.steps:
            value = f"{step.parameters[joint]['log10_stiffness']:.2f}"
            residual = f"{100 * step.residuals[joint]:.2f}"
            if joint in step.corrected:  # bold on a terminal, the ">" survives in a log
                value, residual = f"[bold]>{value}[/]", f"[bold]{residual}[/]"
            cells += [value, residual]
        table.add_row(joint, *cells)
    table.add_row("E_mod² %", *[c for s in result.steps for c in ("", f"{100 * s.e_mod:.2f}")])
    table.add_row("floor %", *[c for s in result.steps
                               for c in ("", f"{100 * s.e_mod_floor:.2f}")])
    hidden = len(every) - len(rows)
    table.caption = (">, bold: corrected joint(s); *: re-correction. "
                     + (f"{hidden} joints neither corrected nor standing out in any step are "
                        "not shown (every joint: --all, or the JSON). " if hidden else "")
                     + f"Stopped: {result.message}")
    return table


def notable_joints(result: UpdateResult, stop_ratio: float) -> set[str]:
    """The joints corrected or standing out of their thresholds in some step of ``result``:
    the rows of a large structure's summary table."""
    notable = set()
    for step in result.steps:
        limits = thresholds(step, stop_ratio)
        notable |= set(step.corrected) | {j for j, v in step.residuals.items() if v > limits[j]}
    return notable


def result_json(result: UpdateResult, extra: Mapping[str, Any] | None = None,
                bounds: tuple[float, float] | None = None) -> dict[str, Any]:
    """The contract's JSON: ``{"steps": [...], ...}``, the status and the identified values."""
    out = {"steps": [step.to_json() for step in result.steps], "status": result.status,
           "message": result.message}
    if bounds is not None:
        out["identified"] = {
            joint: {"log10_stiffness": result.parameters[joint]["log10_stiffness"],
                    **interval.to_json(), **_more_parameters(result, joint)}
            for joint, interval in sorted(result.intervals.items())}
    out.update(extra or {})
    return out


def _more_parameters(result: UpdateResult, joint: str) -> dict[str, Any]:
    """``{"parameters": {name: {value, interval, ...}}}`` of the joint's other identified
    parameters that have an interval (loss factor, line mass), or nothing."""
    more = {name: {"value": result.parameters[joint][name], **interval.to_json()}
            for (other, name), interval in sorted(result.parameter_intervals.items())
            if other == joint}
    return {"parameters": more} if more else {}


def result_markdown(result: UpdateResult, title: str,
                    truth: Mapping[str, Mapping[str, float]] | None = None,
                    noise: float | None = None, warnings: Sequence[str] = ()) -> str:
    """A Markdown report of the run (same content as :func:`steps_table`), for a lab notebook,
    with the description's ``warnings`` that the run printed."""
    joints = list(result.steps[0].parameters)
    head = ["joint"] + [f"{_label(s)} log k / E_Γ² %" for s in result.steps]
    lines = [f"# {title}", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for joint in joints:
        cells = []
        for step in result.steps:
            text = (f"{step.parameters[joint]['log10_stiffness']:.2f} / "
                    f"{100 * step.residuals[joint]:.2f}")
            cells.append(f"**{text}**" if joint in step.corrected else text)
        lines.append(f"| {joint} | " + " | ".join(cells) + " |")
    lines.append("| E_mod² % | " + " | ".join(f"{100 * s.e_mod:.2f}" for s in result.steps)
                 + " |")
    lines.append("| noise floor % | " + " | ".join(f"{100 * s.e_mod_floor:.2f}"
                                                 for s in result.steps) + " |")
    lines += ["", "Bold: the joint(s) corrected in that step; *: a re-correction. "
              "The floor is E_mod² of a correct model under the stated measurement noise.", ""]
    lines += [f"- {line}" for line in identified_lines(result, truth, noise)]
    lines += ["", f"Stopped: {result.message}.", ""]
    if warnings:
        lines += ["Warnings of the description's checks:", ""]
        lines += [f"- {line}" for line in warnings] + [""]
    return "\n".join(lines)
