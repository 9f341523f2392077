"""Field maps of assemblies placed in 3D (plates with frames: stiffened panels, boxes).

The same three panels as :func:`updating.figures.fields.draw_field_maps` (measured, initial
model, updated model, one colour scale), each a 3D view of the plates: the model panels colour
every plate's surface by the field, the measured panel colours the measurement points. Colours
are mapped by hand (``facecolors``) because matplotlib's 3D surfaces take no shared norm.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from updating.figures.field_data import FieldMapData, SpaceLayout, costs_text
from updating.figures.figure_tools import (
    field_colours,
    new_figure,
    powers_of_ten_bar,
    require_matplotlib,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D

__all__ = ["draw_field_maps_in_space"]

VIEW = {"elev": 28.0, "azim": -58.0}
"""Viewing angles (degrees): from above the first octant's diagonal, so that a skin in the
x-y plane and stiffeners standing on it are both seen."""


def _frame_lines(ax: Axes3D, space: SpaceLayout, labels: bool) -> None:
    """Plate outlines (black), joint lines (dashed) and point forces (orange stars)."""
    for pid, outline in space.outlines.items():
        ax.plot(outline[:, 0], outline[:, 1], outline[:, 2], color="black", lw=0.6)
        if labels:
            ax.text(*outline[:4].mean(axis=0), pid, fontsize="x-small", ha="center")
    for line in space.joints.values():
        ax.plot(line[:, 0], line[:, 1], line[:, 2], color="dimgrey", lw=1.0, ls="--")
    if len(space.forces):
        f = space.forces
        ax.scatter(f[:, 0], f[:, 1], f[:, 2], marker="*", s=120, color="tab:orange",
                   edgecolors="black", depthshade=False)


def _equal_box(ax: Axes3D, space: SpaceLayout) -> None:
    """Axes limits and box aspect so that one metre is as long along x, y and z; fewer ticks
    along the short sides."""
    from matplotlib.ticker import MaxNLocator

    every = np.vstack(list(space.outlines.values()))
    low, high = every.min(axis=0), every.max(axis=0)
    span = np.maximum(high - low, 0.02 * np.max(high - low))
    centre = 0.5 * (low + high)
    for setter, c, s in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, span):
        setter(c - 0.5 * s, c + 0.5 * s)
    ax.set_box_aspect(span)
    ax.set_xlabel("x [m]", fontsize="small")
    ax.set_ylabel("y [m]", fontsize="small")
    ax.set_zlabel("z [m]", fontsize="small")
    ax.tick_params(labelsize="x-small")
    for axis, s in zip((ax.xaxis, ax.yaxis, ax.zaxis), span):
        axis.set_major_locator(MaxNLocator(max(2, int(6 * s / span.max()))))
    ax.view_init(**VIEW)


def draw_field_maps_in_space(data: FieldMapData, title: str = "") -> Figure:
    """Three 3D panels (measured, initial, updated) of a
    :class:`updating.figures.fields.FieldMapData` whose
    :attr:`~updating.figures.fields.FieldMapData.space` is set."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    require_matplotlib()
    space = data.space
    figure = new_figure(figsize=(15.0, 5.6))
    axes = [figure.add_subplot(1, 3, i + 1, projection="3d") for i in range(3)]
    cmap_name, label = field_colours(data.quantity)
    cmap = colormaps[cmap_name]
    norm = Normalize(*data.limits)
    ax = axes[0]
    for pid, (_, values) in data.measured.items():
        xyz = space.measured[pid]
        ax.scatter(xyz[:, 0], xyz[:, 1], xyz[:, 2], c=cmap(norm(values)), s=18, marker="s",
                   depthshade=False)
    ax.set_title(f"measured\n{sum(len(v) for _, v in data.measured.values())} points",
                 fontsize="medium")
    for ax, name in ((axes[1], "initial"), (axes[2], "updated")):
        for pid, (x, y, z) in space.surfaces.items():
            ax.plot_surface(x, y, z, facecolors=cmap(norm(getattr(data, name)[pid])),
                            rstride=1, cstride=1, linewidth=0, antialiased=False, shade=False)
        i = 0 if name == "initial" else 1
        ax.set_title(f"{name} model\nmisfit {100 * data.misfit[i]:.1f} %", fontsize="medium")
    for i, ax in enumerate(axes):
        _frame_lines(ax, space, labels=(i == 0))
        _equal_box(ax, space)
    powers_of_ten_bar(figure.colorbar(ScalarMappable(norm, cmap), ax=axes, label=label,
                                      fraction=0.02, shrink=0.7, pad=0.02))
    figure.suptitle(f"{title or 'field'} at {data.frequency:g} Hz; {costs_text(data)}\nplates "
                    "placed in space by their frames; dots: measurement points; star: point "
                    "force", fontsize="medium")
    return figure
