"""What every figure of vtcr needs: matplotlib on demand, a new figure, field colours and atomic
PNG writing (a leaf of the figure modules :mod:`updating.figures.plots`, :mod:`updating.figures.plots_space` and
:mod:`updating.figures.plots_map`, so that none of them imports another's private helpers).

matplotlib is imported inside the functions only: the core runs without the ``plot`` extra.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any, Protocol

from updating.data.files import InputError, atomic_output

if TYPE_CHECKING:
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure

__all__ = ["MISSING_MATPLOTLIB", "require_matplotlib", "new_figure", "field_colours",
           "costs_text", "powers_of_ten_bar", "save_figure_atomic"]

MISSING_MATPLOTLIB = ("--plot needs matplotlib: pip install 'matplotlib>=3.7' (the extra plot "
                      "of vtcr)")


class MapCosts(Protocol):
    """What :func:`costs_text` reads of a :class:`updating.figures.plots.FieldMapData` (named
    by its attributes: this leaf cannot import :mod:`updating.figures.plots`, which imports it)."""

    @property
    def e_mod(self) -> tuple[float, float]: ...

    @property
    def n_frequencies(self) -> int: ...


def require_matplotlib() -> ModuleType:
    """Import matplotlib or raise :class:`InputError` with the install hint (exit 2)."""
    try:
        import matplotlib
    except ImportError:
        raise InputError(MISSING_MATPLOTLIB) from None
    return matplotlib


def new_figure(**kwargs: Any) -> Figure:
    """An empty matplotlib figure (constrained layout) on the Agg canvas, or
    :class:`~updating.data.files.InputError` without matplotlib."""
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(layout="constrained", **kwargs)
    FigureCanvasAgg(figure)
    return figure


def field_colours(quantity: str) -> tuple[str, str]:
    """``(colour map, colour-bar label)`` of a field map of ``|w|`` or ``Re w``."""
    return ("viridis", "|w| [m]") if quantity == "abs" else ("RdBu_r", "Re w [m]")


def costs_text(data: MapCosts) -> str:
    """:math:`E_{mod}^2` at the initial and updated parameters of a :class:`FieldMapData`."""
    summed = f" (sum over {data.n_frequencies} frequencies)" if data.n_frequencies > 1 else ""
    return (f"$E_{{mod}}^2$ {100 * data.e_mod[0]:.2f} % initial, "
            f"{100 * data.e_mod[1]:.2f} % updated{summed}")


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
