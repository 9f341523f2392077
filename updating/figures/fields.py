r"""Field maps: :math:`|w|` (or Re w) of the measurements, of the initial and of the updated
model, plates laid out in the assembly plane on one colour scale (the paper's Figs. 12-13):
``field_<f>Hz.png`` of ``vtcr update --plot``. Plates placed in 3D are drawn in space
(:mod:`updating.figures.fields_space`).

:func:`updating.figures.field_data.field_map_data` computes what is drawn (numpy only),
:func:`draw_field_maps` draws it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from updating.figures.field_data import FieldMapData, costs_text
from updating.figures.fields_space import draw_field_maps_in_space
from updating.figures.figure_tools import field_colours, new_figure, powers_of_ten_bar

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["draw_field_maps"]


def _draw_plate_frame(ax: Axes, data: FieldMapData, labels: bool = False) -> None:
    """Plate outlines, joint lines (dashed white) and measurement points (black dots)."""
    for pid, outline in data.outlines.items():
        ax.plot(outline[:, 0], outline[:, 1], color="black", lw=0.8)
        if labels:
            corner = outline[0] + 0.04 * (outline[2] - outline[0])
            ax.text(*corner, pid, fontsize="small", ha="left", va="bottom", color="white",
                    fontweight="bold",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "black", "alpha": 0.45, "lw": 0})
    for jid, line in data.joints.items():
        ax.plot(line[:, 0], line[:, 1], color="white", lw=1.2, ls="--")
        if labels:
            ax.text(*line.mean(axis=0), jid, fontsize="small", ha="center", va="center",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.8, "lw": 0})
    n_points = sum(len(xy) for xy in data.measured_global.values())
    for xy in data.measured_global.values():
        ax.plot(xy[:, 0], xy[:, 1], ".", color="black", ms=3 if n_points < 200 else 1.5)
    forces, edges = data.loads
    for line in edges:
        ax.plot(line[:, 0], line[:, 1], color="tab:orange", lw=3.0, solid_capstyle="butt",
                label="edge load" if labels else None)
    if len(forces):
        ax.plot(forces[:, 0], forces[:, 1], "*", color="tab:orange", ms=13, mec="black",
                mew=0.8, label="point force" if labels else None)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (assembly plane)")
    ax.set_ylabel("y [m]")


def draw_field_maps(data: FieldMapData, title: str = "") -> Figure:
    """Three panels (measured, initial, updated) of a :class:`FieldMapData`, one colour scale;
    in 3D when its plates are placed in space."""
    if data.space is not None:
        return draw_field_maps_in_space(data, title)
    every = np.vstack(list(data.outlines.values()))
    span = every.max(axis=0) - every.min(axis=0)
    stacked = span[0] > 2.2 * span[1]
    ratio = span[1] / span[0]
    if stacked:  # long assemblies: panels one above the other
        width = 8.0
        figsize = (width + 1.6, 3 * (width * ratio + 0.75) + 0.9)
        bar_height = 0.6
        axes = new_figure(figsize=figsize).subplots(3, 1, sharex=True, sharey=True)
    else:
        panel = 4.4
        figsize = (3 * panel + 1.0, panel * ratio + 2.0)
        bar_height = float(np.clip(panel * ratio / (panel * ratio + 1.0), 0.5, 0.9))
        axes = new_figure(figsize=figsize).subplots(1, 3, sharex=True, sharey=True)
    figure = axes[0].figure
    cmap, label = field_colours(data.quantity)
    norm = {"vmin": data.limits[0], "vmax": data.limits[1], "cmap": cmap}
    mappable = None
    ax = axes[0]
    for pid, (points, values) in data.measured.items():
        cells = data.cells.get(pid)
        plate_outline = data.outlines[pid]
        if cells is not None:
            xe, ye = np.meshgrid(*cells)
            origin = plate_outline[0]
            # plate-local cell corners -> assembly plane (same affine map as the outline)
            ex = (plate_outline[1] - origin) / cells[0][-1]
            ey = (plate_outline[3] - origin) / cells[1][-1]
            gx = origin[0] + ex[0] * xe + ey[0] * ye
            gy = origin[1] + ex[1] * xe + ey[1] * ye
            nx, ny = len(cells[0]) - 1, len(cells[1]) - 1
            grid = np.full((ny, nx), np.nan)
            ix = np.searchsorted(cells[0], points[:, 0]) - 1
            iy = np.searchsorted(cells[1], points[:, 1]) - 1
            grid[iy, ix] = values
            mappable = ax.pcolormesh(gx, gy, grid, shading="flat", **norm)
        else:
            xy = data.measured_global[pid]
            mappable = ax.scatter(xy[:, 0], xy[:, 1], c=values, s=40, marker="s",
                                  edgecolors="none", **norm)
    for pid, outline in data.outlines.items():
        if pid not in data.measured:
            ax.text(*outline[:4].mean(axis=0), "not measured", ha="center", va="center",
                    color="grey", fontsize="small")
    ax.set_title(f"measured\n{sum(len(v) for _, v in data.measured.values())} points")
    for ax, name in ((axes[1], "initial"), (axes[2], "updated")):
        fields = getattr(data, name)
        for pid, (gx, gy) in data.grids.items():
            mappable = ax.pcolormesh(gx, gy, fields[pid], shading="gouraud", **norm)
        i = 0 if name == "initial" else 1
        ax.set_title(f"{name} model\nmisfit {100 * data.misfit[i]:.1f} %")
    for i, ax in enumerate(axes):
        _draw_plate_frame(ax, data, labels=(i == 0))
        ax.set_facecolor("whitesmoke")
        if stacked and i < 2:
            ax.set_xlabel("")
        if not stacked and i > 0:
            ax.set_ylabel("")
    if len(data.loads[0]) or data.loads[1]:
        axes[0].legend(fontsize="small", loc="lower right", framealpha=0.8)
    # pad and fraction are relative to all three panels: keep the bar close to them
    low = min(float(np.min(f[pid])) for f in (data.initial, data.updated) for pid in f)
    high = max(float(np.max(f[pid])) for f in (data.initial, data.updated) for pid in f)
    extend = {(False, False): "neither", (False, True): "max", (True, False): "min",
              (True, True): "both"}[low < data.limits[0], high > data.limits[1]]
    bar = figure.colorbar(mappable, ax=list(axes), label=label, pad=0.015, fraction=0.03,
                          shrink=bar_height, extend=extend)
    powers_of_ten_bar(bar)
    source = ("model panels: minimisers of $E_{mod}^2$ at the initial and updated joints"
              if data.source == "modified" else
              "model panels: response of the model with the initial and updated joints")
    costs = costs_text(data)
    misfit = r"misfit = $\|w - \tilde w\| / \|\tilde w\|$ there"
    figure.suptitle(f"{title or 'field'} at {data.frequency:g} Hz; {costs}\n{source}; dots: "
                    f"measurement points; {misfit}", fontsize="medium")
    return figure
