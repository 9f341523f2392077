"""Progress display for long work (correction steps, cost curves, frequency sweeps).

On an interactive terminal, a transient bar (it disappears when the work ends) on the same
console as the results. Elsewhere — a pipe, a log file, a CI job — each labelled stage (a
correction step, a figure, a refinement round) is one line on standard error with the time
elapsed, so that a long run is never silent and the results on standard output stay clean.
Nothing under ``--quiet``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

if TYPE_CHECKING:
    from rich.console import Console

__all__ = ["progress_bar"]


@contextmanager
def progress_bar(console: Console, description: str,
                 total: float | None) -> Iterator[Callable[..., None]]:
    """Yield ``advance(description=None)``: one unit of work done, optionally relabelled."""
    shown = console.is_terminal and not console.quiet
    logged = not console.is_terminal and not console.quiet
    start = time.perf_counter()
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), console=console, transient=True,
                  disable=not shown) as progress:
        task = progress.add_task(description, total=total)

        def advance(label: str | None = None, amount: float = 1) -> None:
            progress.update(task, advance=amount,
                            **({"description": label} if label is not None else {}))
            if logged and label is not None:
                print(f"vtcr: {label} ({time.perf_counter() - start:.1f} s)", file=sys.stderr,
                      flush=True)

        yield advance
