r"""The residual map: every joint drawn where it is, coloured by its residual over its threshold.

With tens of joints a bar per joint and step is unreadable (ten colours repeat, 180 bars a
step); the map puts the joints on the structure's own layout instead: the plates in place (in
their plane, or in 3D when they have frames), each joint a line coloured by
:math:`\log_{10}(E_{\Gamma}^2/t)` on a diverging scale centred on the threshold :math:`t` (above
it: it stands out), the corrected joints drawn thick with their new :math:`\log_{10}k`, the
joint that stands out most named. A junction's members are drawn on their own plates, just off
the line, so that the weak weld of a stiffener is told from the others on the same line.

As in :mod:`updating.figures.residuals`, :func:`residual_map_data` computes (numpy only, tested
on its own) and :func:`draw_residual_map` draws (matplotlib, imported inside).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from updating.inverse.strategy import Step, excess_ratios

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from assembly import Case
    from assembly.models import Joint

__all__ = ["ResidualMapData", "residual_map_data", "draw_residual_map", "MAP_JOINTS",
           "MEMBER_OFFSET"]

MAP_JOINTS = 12
"""Joints above which ``vtcr update --plot`` draws the map instead of the bars."""

MEMBER_OFFSET = 0.06
"""A junction member's line is drawn this fraction of its plate's size inside the plate."""

RATIO_DECADES = 2.0
"""The colour scale spans this many decades of residual over threshold on each side of 1."""


@dataclass(frozen=True)
class ResidualMapData:
    """What :func:`draw_residual_map` draws.

    Attributes
    ----------
    outlines : dict of str to ndarray, shape (5, d)
        Closed plate outlines, d = 2 (the assembly plane) or 3 (plates with frames).
    segments : dict of str to ndarray, shape (2, d)
        Per updatable joint, the end points of its line (a junction member's, off the line on
        its own plate).
    ratios : dict of str to float
        Residual over threshold (above 1: the joint stands out).
    corrected : dict of str to float
        The corrected joints and their log10 k in the step.
    most : str or None
        The joint that stands out most, if any does.
    """

    outlines: dict
    segments: dict
    ratios: dict
    corrected: dict
    most: str | None

    @property
    def dimension(self) -> int:
        return next(iter(self.outlines.values())).shape[1]


def _place(case: Case, plate_id: str, x: Sequence[float] | np.ndarray,
           y: Sequence[float] | np.ndarray) -> np.ndarray:
    """Plate-local points in the assembly plane, or in space when every plate has a frame."""
    plate = case.plates[plate_id]
    if all(p.frame is not None for p in case.plates.values()):
        return plate.frame.to_space(x, y)
    return np.column_stack(plate.to_global(x, y))


def _segment(case: Case, joint: Joint, member: str | None) -> np.ndarray:
    """End points of a joint's line; a junction member's moved into its own plate."""
    side = next((s for s in joint.sides if s.plate == member), joint.sides[0])
    plate = case.plates[side.plate]
    start, tangent, normal, length = plate.edge_frame(side.edge)
    inside = 0.0 if member is None else MEMBER_OFFSET * min(plate.size)
    local = np.array([start, start + length * tangent]) - inside * np.asarray(normal)
    return _place(case, side.plate, local[:, 0], local[:, 1])


def residual_map_data(case: Case, step: Step, stop_ratio: float,
                      corrected: Iterable[str] = ()) -> ResidualMapData:
    """The map of ``step`` (an :class:`updating.inverse.strategy.Step`) of ``case``; ``corrected``
    names the joints to mark as corrected (default: those corrected in the step)."""
    outlines = {}
    for pid, plate in case.plates.items():
        lx, ly = plate.size
        outlines[pid] = _place(case, pid, [0.0, lx, lx, 0.0, 0.0], [0.0, 0.0, ly, ly, 0.0])
    segments = {name: _segment(case, case.joints[jid], member)
                for name, (jid, member) in case.updatable_joints().items()}
    ratios = excess_ratios(step, stop_ratio)
    marked = set(corrected) or set(step.corrected)
    standing = [j for j in ratios if ratios[j] > 1.0]
    return ResidualMapData(outlines, segments, ratios,
                           {j: step.parameters[j]["log10_stiffness"] for j in sorted(marked)},
                           max(standing, key=ratios.get) if standing else None)


def draw_residual_map(data: ResidualMapData, figure: Figure, title: str = "") -> Figure:
    r"""Draw the map on an empty matplotlib ``figure``: plates grey, joints coloured by
    :math:`\log_{10}` of their residual over threshold (red above 0), corrected joints thick and
    labelled with their log10 k. Returns the figure."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    space = data.dimension == 3
    ax = figure.add_subplot(projection="3d" if space else None)
    for outline in data.outlines.values():
        ax.plot(*outline.T, color="0.75", linewidth=0.8)
    norm = Normalize(-RATIO_DECADES, RATIO_DECADES)
    cmap = colormaps["coolwarm"]
    for joint, segment in data.segments.items():
        level = float(np.log10(max(data.ratios[joint], 1e-300)))
        thick = joint in data.corrected
        ax.plot(*segment.T, color=cmap(norm(level)), linewidth=5.0 if thick else 2.5,
                solid_capstyle="butt", zorder=3)
        if thick or joint == data.most:
            middle = segment.mean(axis=0)
            text = (f"{joint} → {data.corrected[joint]:.2f}" if thick
                    else f"{joint} ({data.ratios[joint]:.1f}×)")
            ax.text(*middle, text, fontsize="small", ha="center", va="bottom", zorder=4)
    bar = figure.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.8,
                          extend="both")
    bar.set_label(r"$\log_{10}(E_\Gamma^2$ / threshold): above 0 the joint stands out")
    if space:
        extent = np.concatenate(list(data.outlines.values()))
        ax.set_box_aspect(np.ptp(extent, axis=0) + 1e-9)
    else:
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    standing = sum(r > 1.0 for r in data.ratios.values())
    summary = (f"{standing} of {len(data.ratios)} joints stand out"
               + (f", most {data.most}" if data.most else "")
               + (f"; thick: corrected ({len(data.corrected)})" if data.corrected else ""))
    figure.suptitle(f"{title}\n{summary}" if title else summary, fontsize="medium")
    return figure
