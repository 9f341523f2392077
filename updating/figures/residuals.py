r"""Residual bars: :math:`E_{\Gamma_i}^2` per joint against its threshold, and
:math:`E_{mod}^2`, per step of an updating run (the paper's Table 4): ``residuals.png`` of
``vtcr update --plot`` up to :data:`updating.figures.residual_map.MAP_JOINTS` joints (above,
the residual map).

:func:`residual_bars_data` computes what is drawn (numpy only), :func:`draw_residual_bars`
draws it.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from updating.figures.figure_tools import new_figure, positive
from updating.inverse.strategy import UpdateResult, thresholds

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["ResidualBarsData", "residual_bars_data", "draw_residual_bars"]


@dataclass(frozen=True)
class ResidualBarsData:
    r"""Per-step joint residuals (Table 4), in %.

    Attributes
    ----------
    labels : tuple of str
        One per step (``"initial"``, ``"step 1"``, ...).
    joints : tuple of str
    residuals : ndarray, shape (n_steps, n_joints)
        :math:`E_{\Gamma_i}^2` in %.
    thresholds : ndarray, shape (n_steps, n_joints)
        Each joint's threshold in % (a joint above it stands out:
        :func:`updating.inverse.strategy.thresholds`).
    selected : tuple of (int or None)
        Column of the joint corrected in each step.
    e_mod : ndarray, shape (n_steps,)
        :math:`E_{mod}^2` in %.
    log10_k : ndarray, shape (n_steps, n_joints)
    """

    labels: tuple[str, ...]
    joints: tuple[str, ...]
    residuals: np.ndarray
    thresholds: np.ndarray
    selected: tuple[int | None, ...]
    e_mod: np.ndarray
    log10_k: np.ndarray


def residual_bars_data(result: UpdateResult, stop_ratio: float = 1.0) -> ResidualBarsData:
    """Arrays of :func:`draw_residual_bars` from an
    :class:`~updating.inverse.strategy.UpdateResult`."""
    joints = tuple(result.steps[0].parameters)
    labels = tuple("initial" if s.step == 0 else f"step {s.step}" for s in result.steps)
    residuals = np.array([[100.0 * s.residuals[j] for j in joints] for s in result.steps])
    limits = [thresholds(s, stop_ratio) for s in result.steps]
    levels = np.array([[100.0 * at_step[j] for j in joints] for at_step in limits])
    selected = tuple(joints.index(s.selected) if s.selected in joints else None
                     for s in result.steps)
    e_mod = np.array([100.0 * s.e_mod for s in result.steps])
    log10_k = np.array([[s.parameters[j]["log10_stiffness"] for j in joints]
                        for s in result.steps])
    return ResidualBarsData(labels, joints, residuals, levels, selected, e_mod, log10_k)


def draw_residual_bars(data: ResidualBarsData, title: str = "") -> Figure:
    r"""Draw grouped bars of :math:`E_{\Gamma_i}^2` per step and :math:`E_{mod}^2` (Table 4)."""
    from matplotlib.patches import Patch

    n_bars = len(data.labels) * max(1, len(data.joints))
    figure = new_figure(figsize=(float(np.clip(0.45 * n_bars + 3.0, 7.0, 14.0)), 6.5))
    top, bottom = figure.subplots(2, 1, sharex=True, height_ratios=(2.2, 1.0))
    n_steps, n_joints = data.residuals.shape
    width = 0.8 / max(n_joints, 1)
    colours = [f"C{i % 10}" for i in range(n_joints)]
    x = np.arange(n_steps)
    for j, joint in enumerate(data.joints):
        offsets = x - 0.4 + (j + 0.5) * width
        chosen = np.array([s == j for s in data.selected])
        top.bar(offsets, positive(data.residuals[:, j]), width, color=colours[j],
                edgecolor=np.where(chosen, "black", colours[j]).tolist(),
                linewidth=np.where(chosen, 2.0, 0.5).tolist(),
                hatch=None, label=joint)
        top.plot(offsets, positive(data.thresholds[:, j]), "_", color="black", ms=10, mew=1.5)
    top.set_yscale("log")
    top.set_ylabel(r"$E_{\Gamma_i}^2$ [%] (log scale)")
    handles = [Patch(color=c, label=j) for c, j in zip(colours, data.joints)]
    handles.append(Patch(facecolor="white", edgecolor="black", linewidth=2.0,
                         label="joint corrected in the step"))
    from matplotlib.lines import Line2D

    handles.append(Line2D([], [], marker="_", ls="none", color="black", ms=10, mew=1.5,
                          label="threshold (stands out above)"))
    top.legend(handles=handles, fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    top.grid(True, axis="y", which="major", alpha=0.4)
    width = int(figure.get_figwidth() * 11)  # characters per title line
    title = "\n".join(textwrap.fill(line, width) for line in
                      (title or "joint residuals per step").splitlines())
    figure.suptitle(title, fontsize="medium")
    bottom.plot(x, data.e_mod, "o-", color="black")
    for i, value in enumerate(data.e_mod):
        bottom.annotate(f"{value:.2f} %", (x[i], value), xytext=(0, 6),
                        textcoords="offset points", ha="center", fontsize="small")
    bottom.set_ylabel(r"$E_{mod}^2$ [%]")
    bottom.set_ylim(0.0, 1.3 * max(float(np.max(data.e_mod)), 1e-12))
    bottom.grid(True, axis="y", alpha=0.4)
    ticks = []
    for i, label in enumerate(data.labels):
        s = data.selected[i]
        ticks.append(label if s is None else f"{label}\n{data.joints[s]} → "
                     f"{data.log10_k[i, s]:.2f}")
    bottom.set_xticks(x, ticks)
    bottom.set_xlabel(r"step (corrected joint → its new $\log_{10} k$)")
    return figure
