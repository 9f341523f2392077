"""What every figure of vtcr needs: matplotlib on demand, a new figure, field colours and atomic
PNG writing, log-axis values and the truth of a simulated experiment (a leaf of the figure
modules, so that none of them imports another's private helpers).

matplotlib is imported inside the functions only: the core runs without the ``plot`` extra.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from assembly import Case
from updating.data.files import atomic_output
from updating.errors import InputError

if TYPE_CHECKING:
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure

__all__ = ["MISSING_MATPLOTLIB", "require_matplotlib", "new_figure", "field_colours",
           "powers_of_ten_bar", "save_figure_atomic", "positive", "true_parameters",
           "true_log_k", "LOG_K_LABEL"]

MISSING_MATPLOTLIB = ("--plot needs matplotlib: pip install 'matplotlib>=3.7' (the extra plot "
                      "of vtcr)")

LOG_K_LABEL = r"$\log_{10} k$  ($k$ in N·m/m per rad)"
"""The axis label of a joint's log10 stiffness."""


def require_matplotlib() -> ModuleType:
    """Import matplotlib or raise :class:`InputError` with the install hint (exit 2)."""
    try:
        import matplotlib
    except ImportError:
        raise InputError(MISSING_MATPLOTLIB) from None
    return matplotlib


def new_figure(**kwargs: Any) -> Figure:
    """An empty matplotlib figure (constrained layout) on the Agg canvas, or
    :class:`~updating.errors.InputError` without matplotlib."""
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(layout="constrained", **kwargs)
    FigureCanvasAgg(figure)
    return figure


def field_colours(quantity: str) -> tuple[str, str]:
    """``(colour map, colour-bar label)`` of a field map of ``|w|`` or ``Re w``."""
    return ("viridis", "|w| [m]") if quantity == "abs" else ("RdBu_r", "Re w [m]")


def powers_of_ten_bar(bar: Colorbar) -> None:
    """A colour bar's ticks with a ``1e-5``-style multiplier, not 0.00001 ticks."""
    bar.formatter.set_powerlimits((-2, 3))
    bar.update_ticks()


def save_figure_atomic(figure: Figure, path: str | Path, dpi: float = 120) -> Path:
    """Write ``figure`` as PNG through a temporary file in the same directory and a rename."""
    path = Path(path)
    with atomic_output(path, binary=True) as handle:
        figure.savefig(handle, format="png", dpi=dpi)
    return path


def true_parameters(case: Case) -> dict[str, dict[str, float]] | None:
    """Joint parameters of ``[truth.joints]`` (None when the description has none)."""
    if not case.truth.joints:
        return None
    return case.true_case().updatable_parameters()


def true_log_k(case: Case, joint: str) -> float | None:
    """The true log10 k of an updatable joint (``[truth.joints]``), or None."""
    return case.true_log10_stiffness().get(joint)


def positive(values: ArrayLike) -> np.ndarray:
    """Values for a log axis: non-positive entries become NaN (gaps, not warnings)."""
    values = np.asarray(values, dtype=float).copy()
    values[~(values > 0)] = np.nan
    return values
