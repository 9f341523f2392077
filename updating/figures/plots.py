r"""Figures of an updating run (optional extra ``vtcr[plot]``: matplotlib, Agg backend).

``vtcr update CASE.toml --plot DIR`` writes, into ``DIR``:

* ``cost_<joint>.png`` — :math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and the
  joint's :math:`E_\Gamma^2` against its :math:`\log_{10}k`, the other joints at their final
  values (the paper's Figs. 6–9 and 14), for every joint corrected in the run;
* ``field_<f>Hz.png`` — :math:`|w|` of the measurements, of the initial and of the updated
  model, plates laid out in the assembly plane, one colour scale (Figs. 12–13);
* ``residuals.png`` — :math:`E_{\Gamma_i}^2` per joint and :math:`E_{mod}^2` per step
  (Table 4); above :data:`~updating.figures.residual_map.MAP_JOINTS` joints, the residual map
  of the last step (:mod:`updating.figures.residual_map`: the joints on the structure's layout,
  coloured by residual over threshold, the corrected ones marked), and
  ``residuals_initial.png`` that of the first;
* ``frf.png`` — spatial RMS of :math:`|w|` over the measurement points against frequency, for
  the initial, updated (and true) joints, around the analysed frequencies (Fig. 11 right),
  sampled as ``vtcr frf`` samples (refined until the resonance peaks are resolved).

``vtcr frf CASE.toml --band F1 F2 --plot DIR`` writes ``frf.png`` (the sweep's spatial RMS, each
solved frequency marked) and ``power.png`` (injected power, power dissipated in the plates and
in the joints, and the power transmitted by the joints that carry the most).

This module writes the figures of a run (:func:`write_update_figures`); each kind lives in its
own module: :mod:`~updating.figures.curves`, :mod:`~updating.figures.fields` (and
:mod:`~updating.figures.fields_space`), :mod:`~updating.figures.residuals` (and
:mod:`~updating.figures.residual_map`), :mod:`~updating.figures.responses`. Each is split in
two layers: ``*_data`` functions compute what is drawn (numpy arrays, no matplotlib; tested on
their own), ``draw_*`` functions turn those into a :class:`matplotlib.figure.Figure`.
matplotlib is imported only inside the drawing layer, so ``import updating.figures.plots``
works without it; :func:`require_matplotlib` turns its absence into a
one-line :class:`~updating.errors.InputError`. Figures are written atomically (a temporary file
in the same directory, then :func:`os.replace`): an interrupted run never leaves a half-written
PNG.

Model fields. The "initial model" and "updated model" panels of the field maps show the
model's own response (the direct problem, r = 0) with the initial and with the identified joint
parameters: the paper's Fig. 13 shows "the response of the updated structure", and only the
model's own response shows how wrong the initial model was. ``field_source="modified"`` draws
instead the field of the modified problem, the minimiser of :math:`E_{mod}^2` at those
parameters (a compromise between the joint laws and the measurements, r = ``[updating] r``):
at the optimum it is close to the updated response, but at the initial parameters the
measurement term pulls it towards the measurements and hides most of the model error. The
frequency response also uses the model's own response (no measurement exists off the analysed
frequencies).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from assembly.types import JointParameters
from updating.figures.curves import cost_curve_data, draw_cost_curve
from updating.figures.field_data import field_map_data
from updating.figures.fields import draw_field_maps
from updating.figures.figure_tools import (
    new_figure,
    require_matplotlib,
    save_figure_atomic,
    true_log_k,
    true_parameters,
)
from updating.figures.residual_map import MAP_JOINTS, draw_residual_map, residual_map_data
from updating.figures.residuals import draw_residual_bars, residual_bars_data
from updating.figures.responses import draw_frequency_response
from updating.forward.sweep import frequency_band, frequency_response_data, spatial_rms
from updating.inverse.cost import ModifiedProblem, cost_curve, log_grid
from updating.inverse.strategy import UpdateResult

if TYPE_CHECKING:
    from assembly import Case
    from updating.data.measurements import Measurements
    from updating.executor import Executor

__all__ = ["write_update_figures"]


def _frequency_name(frequency: float) -> str:
    return f"field_{frequency:g}Hz.png"


def _corrected_joints(result: UpdateResult) -> list[str]:
    joints = []
    for step in result.steps:
        joints += [joint for joint in step.corrected if joint not in joints]
    return joints


def write_update_figures(case: Case, problem: ModifiedProblem, measurements: Measurements,
                         result: UpdateResult, directory: str | Path, curve_points: int = 41,
                         frf_points: int = 40, frf_width: float = 0.1, quantity: str = "abs",
                         field_source: str = "direct",
                         on_work: Callable[[str], object] | None = None,
                         executor: Executor | None = None) -> list[Path]:
    """Write the figures of an updating run into ``directory`` (created if needed).

    Parameters
    ----------
    case : assembly.Case
    problem : updating.inverse.cost.ModifiedProblem
    measurements : updating.data.measurements.Measurements
    result : updating.inverse.strategy.UpdateResult
    directory : str or Path
    curve_points : int
        Points of each cost curve over ``[updating] bounds``.
    frf_points : int
        Initial frequencies of the response curve over ``(1 -/+ frf_width)`` times the
        analysed band, refined until the resonances are resolved (at most 400 frequencies).
    quantity : {"abs", "real"}
        Field maps of ``|w|`` or ``Re w``.
    field_source : {"direct", "modified"}
        See :func:`updating.figures.field_data.field_map_data`.
    on_work : callable, optional
        Called with a label before each cost curve and after each round of response-curve
        frequencies (progress display).
    executor : updating.executor.Executor, optional
        Solves the response curve's frequencies in parallel.

    Returns
    -------
    list of Path
        ``residuals.png`` (and ``residuals_initial.png`` above ``MAP_JOINTS`` joints),
        ``cost_<joint>.png`` per corrected joint, ``field_<f>Hz.png`` per
        measured frequency, ``frf.png``.

    Raises
    ------
    InputError
        When matplotlib is not installed.
    """
    require_matplotlib()
    directory = Path(directory)
    written = _residual_figures(case, result, directory)
    final = JointParameters.of(result.parameters)
    initial = problem.initial_parameters()
    written += _cost_curve_figures(case, problem, result, initial, final, directory,
                                   curve_points, on_work)
    written += _field_figures(case, problem, measurements, initial, final, directory, quantity,
                              field_source)
    written.append(_frequency_response_figure(case, measurements, initial, final, directory,
                                              frf_points, frf_width, on_work, executor))
    return written


def _residual_figures(case: Case, result: UpdateResult, directory: Path) -> list[Path]:
    """``residuals.png``: the residual bars of every step, or above :data:`MAP_JOINTS` joints
    the residual map at the end of the run, and ``residuals_initial.png`` that of the first
    localisation."""
    name = case.name
    stopped = f"stopped: {result.message}"
    if len(result.parameters) <= MAP_JOINTS:
        bars = residual_bars_data(result, case.updating.stop_ratio)
        return [save_figure_atomic(
            draw_residual_bars(bars, f"{name}: joint residuals per step\n{stopped}"),
            directory / "residuals.png")]
    # bars of tens of joints are unreadable: maps
    corrected = _corrected_joints(result)
    written = []
    for label, step, path in (("first localisation", result.steps[0], "residuals_initial"),
                              ("end of the run", result.steps[-1], "residuals")):
        data = residual_map_data(case, step, case.updating.stop_ratio,
                                 corrected if step is result.steps[-1] else ())
        written.append(save_figure_atomic(
            draw_residual_map(data, new_figure(figsize=(9.0, 7.0)),
                              f"{name}: joint residuals, {label}\n{stopped}"),
            directory / f"{path}.png"))
    return written


def _cost_curve_figures(case: Case, problem: ModifiedProblem, result: UpdateResult,
                        initial: Mapping[str, Mapping[str, float]],
                        final: Mapping[str, Mapping[str, float]], directory: Path,
                        curve_points: int, on_work: Callable[[str], object] | None
                        ) -> list[Path]:
    """``cost_<joint>.png`` of every joint corrected in the run, the other joints at their
    ``final`` values; ``on_work`` is called before each curve."""
    base_grid = log_grid(case.updating.bounds, curve_points)
    frequencies = ", ".join(f"{f:g}" for f in problem.frequencies)
    written = []
    for joint in _corrected_joints(result):
        marks = [final[joint]["log10_stiffness"], true_log_k(case, joint)]
        lo, hi = case.updating.bounds
        grid = np.union1d(base_grid, [v for v in marks if v is not None and lo <= v <= hi])
        if on_work:
            on_work(f"cost curve of {joint}")
        rows = cost_curve(problem, final, joint, grid)
        data = cost_curve_data(rows, joint, identified=final[joint]["log10_stiffness"],
                               true=true_log_k(case, joint),
                               initial=initial[joint]["log10_stiffness"],
                               interval=result.intervals[joint].span(case.updating.bounds),
                               interval_label=result.intervals[joint].text,
                               note=f"other joints at their final values; {frequencies} Hz")
        written.append(save_figure_atomic(
            draw_cost_curve(data, f"{case.name}: cost against $\\log_{{10}} k$ of {joint}"),
            directory / f"cost_{joint}.png"))
    return written


def _field_figures(case: Case, problem: ModifiedProblem, measurements: Measurements,
                   initial: Mapping[str, Mapping[str, float]],
                   final: Mapping[str, Mapping[str, float]], directory: Path, quantity: str,
                   field_source: str) -> list[Path]:
    """``field_<f>Hz.png`` of every measured frequency: the measured, initial and updated
    fields."""
    shown = "|w|" if quantity == "abs" else "Re w"
    written = []
    for frequency in measurements.frequencies:
        data = field_map_data(case, problem, measurements, frequency, initial, final,
                              quantity=quantity, source=field_source)
        written.append(save_figure_atomic(draw_field_maps(data, f"{case.name}: {shown}"),
                                          directory / _frequency_name(frequency)))
    return written


def _frequency_response_figure(case: Case, measurements: Measurements,
                               initial: Mapping[str, Mapping[str, float]],
                               final: Mapping[str, Mapping[str, float]], directory: Path,
                               frf_points: int, frf_width: float,
                               on_work: Callable[[str], object] | None,
                               executor: Executor | None) -> Path:
    """``frf.png``: the spatial RMS of the initial, updated (and true) models over the
    measurement points around the analysed band, the measured RMS marked; ``on_work`` is
    called after each round of frequencies."""
    analysed = measurements.frequencies
    points = {pid: np.asarray(p, dtype=float)
              for pid, (p, _) in measurements.data[analysed[0]].items()}
    sets = {"initial": initial, "updated": final}
    truth = true_parameters(case)
    if truth is not None:
        sets["true"] = truth
    measured_rms = [spatial_rms(v for _, v in measurements.data[f].values()) for f in analysed]
    frf = frequency_response_data(
        case, sets, frequency_band(analysed, frf_width, frf_points), points, measured_rms,
        analysed, executor=executor,
        on_round=lambda n: on_work(f"response curve: {n} frequencies") if on_work else None)
    return save_figure_atomic(
        draw_frequency_response(frf, f"{case.name}: spatial RMS of |w| over the measurement "
                                     "points"),
        directory / "frf.png")
