r"""The cost curve of one joint: :math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and the
joint's :math:`E_\Gamma^2` against its :math:`\log_{10}k`, the other joints fixed (the paper's
Figs. 6-9 and 14): ``cost_<joint>.png`` of ``vtcr update --plot`` and ``vtcr curve --plot``.

:func:`cost_curve_data` computes what is drawn (numpy only), :func:`draw_cost_curve` draws it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from updating.figures.figure_tools import (
    LOG_K_LABEL,
    new_figure,
    positive,
    require_matplotlib,
    save_figure_atomic,
    true_log_k,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from assembly import Case

__all__ = ["CostCurveData", "cost_curve_data", "draw_cost_curve", "write_curve_figure"]


@dataclass(frozen=True)
class CostCurveData:
    """One joint's cost curve; costs dimensionless (fractions, drawn in %).

    Attributes
    ----------
    joint : str
    log10_k, e_mod, e_int, e_mes, e_joint : ndarray of float, shape (n,)
    identified, true, initial : float or None
        log10 k marked on the curve (identified value, ``[truth]`` value, model start).
    interval : tuple of float or None
        log10 k range to shade (the confidence interval), labelled ``interval_label``.
    note : str
        What the other joints are held at (subtitle).
    identified_label : str
        Legend of the ``identified`` mark.
    """

    joint: str
    log10_k: np.ndarray
    e_mod: np.ndarray
    e_int: np.ndarray
    e_mes: np.ndarray
    e_joint: np.ndarray
    identified: float | None = None
    true: float | None = None
    initial: float | None = None
    interval: tuple[float, float] | None = None
    note: str = ""
    identified_label: str = "identified"
    interval_label: str = "interval"


def cost_curve_data(rows: Sequence[Sequence[float]], joint: str, identified: float | None = None,
                    true: float | None = None, initial: float | None = None,
                    interval: tuple[float, float] | None = None, note: str = "",
                    interval_label: str = "interval") -> CostCurveData:
    """Arrays of a cost curve from :func:`updating.inverse.cost.cost_curve` rows.

    Parameters
    ----------
    rows : sequence of (log10_k, e_mod, e_int, e_mes, e_joint)
    joint : str
    identified : float, optional
        Marked value; default the curve's minimum of :math:`E_{mod}^2`.

    Returns
    -------
    CostCurveData
    """
    table = np.asarray(rows, dtype=float).reshape(-1, 5)
    order = np.argsort(table[:, 0])
    table = table[order]
    label = "identified"
    if identified is None and len(table):
        identified = float(table[np.argmin(table[:, 1]), 0])
        label = "minimum"
    return CostCurveData(joint, *(table[:, i].copy() for i in range(5)), identified=identified,
                         true=true, initial=initial, interval=interval, note=note,
                         identified_label=label, interval_label=interval_label)


def draw_cost_curve(data: CostCurveData, title: str = "") -> Figure:
    """Figure of a :class:`CostCurveData` (log y axis, costs in %)."""
    figure = new_figure(figsize=(7.5, 5.0))
    ax = figure.add_subplot()
    styles = [
        (data.e_mod, r"$E_{mod}^2$ (cost)", {"color": "black", "lw": 2.2}),
        (data.e_int, r"$E_{int}^2$ (interface error)", {"color": "tab:blue", "lw": 1.5}),
        (data.e_mes, r"$E_{mes}^2$ (measurement term)", {"color": "tab:orange", "lw": 1.5}),
        (data.e_joint, rf"$E_\Gamma^2$ of {data.joint}",
         {"color": "tab:green", "lw": 1.5, "ls": "--"}),
    ]
    for values, label, style in styles:
        ax.plot(data.log10_k, positive(100.0 * values), label=label, **style)
    ax.set_yscale("log")
    if data.interval is not None and data.interval[1] > data.interval[0]:
        ax.axvspan(*data.interval, color="tab:red", alpha=0.08, label=data.interval_label)
    if data.initial is not None:
        ax.axvline(data.initial, color="grey", ls=":", lw=1.3,
                   label=f"model start {data.initial:.2f}")
    if data.identified is not None:
        ax.axvline(data.identified, color="tab:red", lw=1.5,
                   label=f"{data.identified_label} {data.identified:.2f}")
    if data.true is not None:
        ax.axvline(data.true, color="tab:purple", ls="--", lw=1.5, label=f"true {data.true:.2f}")
    ax.set_xlabel(LOG_K_LABEL)
    ax.set_ylabel("error [%] (log scale)")
    ax.set_xlim(data.log10_k.min(), data.log10_k.max())
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    title = title or f"cost against $\\log_{{10}} k$ of joint {data.joint}"
    ax.set_title(f"{title}\n{data.note}" if data.note else title, fontsize="medium")
    ax.legend(fontsize="small", loc="best", framealpha=0.9)
    return figure


def write_curve_figure(case: Case, rows: Sequence[Sequence[float]], joint: str,
                       directory: str | Path,
                       parameters_note: str = "other joints at their initial values") -> Path:
    """Write ``cost_<joint>.png`` for :func:`updating.inverse.cost.cost_curve` rows
    (``vtcr curve``)."""
    require_matplotlib()
    frequencies = ", ".join(f"{f:g}" for f in case.frequencies)
    data = cost_curve_data(rows, joint, true=true_log_k(case, joint),
                           initial=case.updatable_parameters()[joint]["log10_stiffness"],
                           note=f"{parameters_note}; {frequencies} Hz")
    return save_figure_atomic(draw_cost_curve(data, f"{case.name}: cost against "
                                                    f"$\\log_{{10}} k$ of {joint}"),
                              Path(directory) / f"cost_{joint}.png")
