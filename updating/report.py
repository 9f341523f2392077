"""Reports of an updating run: a rich table like the paper's Table 4, JSON, Markdown.

Formatting only: everything shown comes from :class:`updating.strategy.UpdateResult`.
"""

from __future__ import annotations

from rich.table import Table

__all__ = ["steps_table", "result_json", "result_markdown"]


def _bound_note(step, joint, bounds):
    """``(>= a)`` or ``(<= b)`` when the selected joint's cost is flat up to a bound."""
    if step.selected != joint or not step.interval:
        return ""
    low, high = step.interval
    if high >= bounds[1] - 1e-9 and low > bounds[0] + 1e-9:
        return f" (>= {low:.2f})"
    if low <= bounds[0] + 1e-9 and high < bounds[1] - 1e-9:
        return f" (<= {high:.2f})"
    return ""


def steps_table(result, title, bounds):
    """Rows: joints, then E_mod^2; per step the log10 k and E_Gamma^2 (%) of every joint.

    The joint corrected in a step is shown in bold; a joint whose cost stays within 1 % of its
    minimum up to a bound is marked ``>= a`` (stiff: only a lower bound is identifiable) or
    ``<= b`` (near-hinge: only an upper bound).
    """
    table = Table(title=title)
    table.add_column("joint")
    for step in result.steps:
        label = "initial" if step.step == 0 else f"step {step.step}"
        table.add_column(f"{label}\nlog10 k", justify="right")
        table.add_column("E_G^2 %", justify="right")
    for joint in result.steps[0].parameters:
        cells = []
        for step in result.steps:
            style = "bold" if step.selected == joint else ""
            value = step.parameters[joint]["log10_stiffness"]
            note = _bound_note(step, joint, bounds)
            cells += [f"[{style}]{value:.2f}{note}[/]" if style else f"{value:.2f}",
                      f"{100 * step.residuals[joint]:.2f}"]
        table.add_row(joint, *cells)
    cells = []
    for step in result.steps:
        cells += ["", f"{100 * step.e_mod:.2f}"]
    table.add_row("E_mod^2 %", *cells, end_section=True)
    table.caption = result.message
    return table


def result_json(result, extra=None):
    """The contract's JSON: ``{"steps": [...], ...}`` plus the status."""
    out = {"steps": [step.to_json() for step in result.steps], "status": result.status,
           "message": result.message}
    out.update(extra or {})
    return out


def result_markdown(result, title, bounds):
    """A Markdown report of the run (same content as :func:`steps_table`)."""
    joints = list(result.steps[0].parameters)
    head = ["joint"] + [f"{'initial' if s.step == 0 else f'step {s.step}'} log k / E_G^2 %"
                        for s in result.steps]
    lines = [f"# {title}", "", "| " + " | ".join(head) + " |",
             "|" + "---|" * len(head)]
    for joint in joints:
        cells = []
        for step in result.steps:
            text = (f"{step.parameters[joint]['log10_stiffness']:.2f}"
                    f"{_bound_note(step, joint, bounds)} / {100 * step.residuals[joint]:.2f}")
            cells.append(f"**{text}**" if step.selected == joint else text)
        lines.append(f"| {joint} | " + " | ".join(cells) + " |")
    lines.append("| E_mod^2 % | " + " | ".join(f"{100 * s.e_mod:.2f}" for s in result.steps)
                 + " |")
    lines += ["", f"Stopped: {result.message}.", ""]
    return "\n".join(lines)
