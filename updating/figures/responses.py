r"""Figures over frequency: the spatial RMS of :math:`|w|` (``frf.png``), the power flow of a
sweep (``power.png``: injected power, power dissipated in the plates and in the joints, and the
power transmitted by the joints that carry the most) and the measurement plan's
identifiability per joint (``plan.png``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from updating.figures.figure_tools import (
    new_figure,
    positive,
    require_matplotlib,
    save_figure_atomic,
)
from updating.forward.sweep import FrequencyResponseData

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from assembly import Case
    from updating.forward.sweep import Sweep
    from updating.inverse.plan import JointPlan

__all__ = ["draw_frequency_response", "draw_power_flow", "write_sweep_figures", "draw_plan",
           "write_plan_figure"]


def draw_frequency_response(data: FrequencyResponseData, title: str = "") -> Figure:
    """RMS ``|w|`` against frequency; analysed frequencies and measured RMS marked."""
    figure = new_figure(figsize=(8.0, 5.0))
    ax = figure.add_subplot()
    styles = {"initial": {"color": "tab:blue", "lw": 1.4, "ls": "--", "label": "initial model"},
              "updated": {"color": "tab:red", "lw": 1.8, "label": "updated model"},
              "true": {"color": "black", "lw": 1.0, "ls": ":", "label": "true structure ([truth])"},
              "sweep": {"color": "tab:blue", "lw": 1.2, "marker": ".", "ms": 3,
                        "label": "model (dots: solved frequencies)"}}
    for label, values in data.curves.items():
        style = styles.get(label, {"label": label})
        ax.plot(data.frequencies, positive(values), **style)
    for i, frequency in enumerate(data.analysed):
        ax.axvline(frequency, color="grey", lw=1.0, alpha=0.7,
                   label="analysed frequency" if i == 0 else None)
    if len(data.measured):
        ax.plot(data.analysed[:len(data.measured)], data.measured, "o", color="tab:green",
                mfc="none", ms=8, mew=1.5, label="measurements")
    ax.set_yscale("log")
    ax.set_xlim(data.frequencies.min(), data.frequencies.max())
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("spatial RMS of |w| [m]")
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    ax.set_title(title or "frequency response")
    ax.legend(fontsize="small", loc="best", framealpha=0.9)
    return figure


def draw_power_flow(sweep: Sweep, title: str = "", joints_shown: int = 8) -> Figure:
    """Power against frequency of an :class:`updating.forward.sweep.Sweep`: injected, dissipated in
    the plates and in the joints (top), transmitted by the ``joints_shown`` joints that carry
    the most (bottom, absolute values)."""
    figure = new_figure(figsize=(8.0, 7.0))
    top, bottom = figure.subplots(2, 1, sharex=True)
    f = sweep.frequencies
    injected = [p.total_injected for p in sweep.powers]
    plates = [sum(p.dissipated.values()) for p in sweep.powers]
    joints = [sum(p.joint_dissipated.values()) for p in sweep.powers]
    top.plot(f, positive(injected), color="black", lw=1.6, label="injected")
    top.plot(f, positive(plates), color="tab:blue", lw=1.2, ls="--",
             label="dissipated in the plates")
    if sweep.powers and sweep.powers[0].joint_dissipated:
        top.plot(f, positive(joints), color="tab:red", lw=1.2, ls=":",
                 label="dissipated in the joints")
    top.set_yscale("log")
    top.set_ylabel("time-averaged power [W]")
    top.set_title(title or "power flow")
    top.legend(fontsize="small", loc="best", framealpha=0.9)
    names = list(sweep.powers[0].transmitted) if sweep.powers else []
    carried = {j: np.abs([p.transmitted[j] for p in sweep.powers]) for j in names}
    shown = sorted(names, key=lambda j: -carried[j].max())[:joints_shown]
    for joint in shown:
        bottom.plot(f, positive(carried[joint]), lw=1.0, label=joint)
    if shown:
        bottom.set_yscale("log")
        bottom.legend(fontsize="small", loc="best", framealpha=0.9,
                      ncol=2 if len(shown) > 4 else 1)
    bottom.set_ylabel("|power transmitted| [W]")
    bottom.set_xlabel("frequency [Hz]")
    for ax in (top, bottom):
        ax.grid(True, which="major", alpha=0.4)
        ax.set_xlim(f.min(), f.max())
    return figure


def write_sweep_figures(case: Case, sweep: Sweep, directory: str | Path) -> list[Path]:
    """Write ``frf.png`` and ``power.png`` of a ``vtcr frf`` sweep into ``directory``."""
    require_matplotlib()
    directory = Path(directory)
    data = FrequencyResponseData(sweep.frequencies, {"sweep": sweep.spatial_rms()}, (),
                                 np.zeros(0))
    response = draw_frequency_response(
        data, f"{case.name}: spatial RMS of |w| over the probes, "
              f"{len(sweep.frequencies)} frequencies")
    return [save_figure_atomic(response, directory / "frf.png"),
            save_figure_atomic(draw_power_flow(sweep, f"{case.name}: power flow"),
                               directory / "power.png")]


def draw_plan(plans: Mapping[str, JointPlan], frequencies: Sequence[float],
              title: str = "") -> Figure:
    """Grouped bars of each joint's field sensitivity (% per 0.1 decade of log10 k) per
    frequency, the joints labelled with their verdict (:mod:`updating.inverse.plan`)."""
    joints = list(plans)
    figure = new_figure(figsize=(float(np.clip(0.6 * len(joints) * len(frequencies) + 3.0, 7.0,
                                            14.0)), 4.8))
    ax = figure.subplots()
    width = 0.8 / max(len(frequencies), 1)
    x = np.arange(len(joints))
    for i, frequency in enumerate(frequencies):
        values = [100 * plans[j].stiffness_sensitivity[frequency] for j in joints]
        ax.bar(x - 0.4 + (i + 0.5) * width, positive(np.array(values)), width,
               label=f"{frequency:g} Hz")
    ax.set_xticks(x, [f"{j}\n{plans[j].verdict}" for j in joints])
    ax.set_yscale("log")
    ax.set_ylabel("field change [%] per +0.1 decade of log10 k")
    ax.grid(True, axis="y", alpha=0.4)
    ax.legend(fontsize="small")
    ax.set_title(title or "sensitivity of the planned measurement", fontsize="medium")
    return figure


def write_plan_figure(plans: Mapping[str, JointPlan], frequencies: Sequence[float],
                      directory: str | Path, name: str) -> Path:
    """``DIR/plan.png`` (:func:`draw_plan`); the directory is created if needed."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return save_figure_atomic(draw_plan(plans, frequencies,
                                        f"{name}: what the planned measurement can tell"),
                              directory / "plan.png")
