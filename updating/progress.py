"""Progress display for long work (correction steps, cost curves, frequency sweeps).

Shown only on an interactive terminal and never under ``--quiet``: a pipe, a log file or a CI
job gets the results and nothing else. The display is transient (it disappears when the work
ends) and goes to the same console as the results.
"""

from __future__ import annotations

from contextlib import contextmanager

from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

__all__ = ["progress_bar"]


@contextmanager
def progress_bar(console, description, total):
    """Yield ``advance(description=None)``: one unit of work done, optionally relabelled."""
    shown = console.is_terminal and not console.quiet
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), console=console, transient=True,
                  disable=not shown) as progress:
        task = progress.add_task(description, total=total)

        def advance(label=None, amount=1):
            progress.update(task, advance=amount,
                            **({"description": label} if label is not None else {}))

        yield advance
