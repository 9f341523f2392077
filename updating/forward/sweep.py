"""Frequency sweeps of the model: the response at probe points and where the power goes.

Each frequency is an independent task (:func:`sweep_point`: one solve of the description and
its :class:`solver.power.PowerFlow`), run on an :class:`updating.executor.Executor`; the
frequencies come from :func:`solver.sweep.refine_frequencies`, which refines the requested
grid until the resonances are resolved.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from solver import solve_case
from solver.guards import check_description
from solver.plate import evaluate_field
from solver.power import PowerFlow, power_flow
from solver.substructure import AssemblySystem, build_assembly_system
from solver.sweep import initial_frequencies, refine_frequencies
from solver.tolerance import solve_to_tolerance
from updating.data.measurements import Measurements
from updating.inverse.cost import direct_amplitudes

if TYPE_CHECKING:
    from assembly import Case
    from updating.executor import Executor

_R = TypeVar("_R")

__all__ = ["Sweep", "sweep_point", "frequency_sweep", "band_resolutions", "BandResolutions",
           "strongest_peaks",
           "smallest_loss_factor", "round_evaluator", "BALANCE_TOLERANCE", "FrequencyResponseData",
           "frequency_response_data", "frequency_band", "spatial_rms", "plate_deflection"]

BALANCE_TOLERANCE = 1e-2
"""Relative power imbalance above which a frequency is flagged. At the default resolution the
imbalance follows the field error: 5e-4 on the Levy chain of the tests (field error 3e-4), 5e-10
at resolution 1.5; a per cent means the discretisation misses a condition somewhere."""


def smallest_loss_factor(case: Case) -> float:
    """The smallest loss factor of the plates' materials: the narrowest half-power bandwidth
    of a resonance is this times its frequency (joint damping only widens it)."""
    return min(case.materials[plate.material].loss_factor for plate in case.plates.values())


def round_evaluator(task: Callable[[float], _R], executor: Executor | None = None,
                    on_round: Callable[[int], object] | None = None
                    ) -> Callable[[Sequence[float]], list[_R]]:
    """``evaluate(frequencies) -> [task(f) for f in frequencies]`` for
    :func:`solver.sweep.refine_frequencies`: each round of frequencies on ``executor`` (default
    in this process), then ``on_round(number of frequencies solved so far)`` (progress)."""
    solved = 0

    def evaluate(frequencies: Sequence[float]) -> list[_R]:
        nonlocal solved
        results = executor.map(task, frequencies) if executor else [task(f) for f in frequencies]
        solved += len(results)
        if on_round:
            on_round(solved)
        return results

    return evaluate


TOLERANCE_BANDS = 4
"""Sub-bands of a sweep that meets a tolerance, each solved at the resolution its top frequency
needs (the ray counts the rule gives grow with the frequency)."""


@dataclass(frozen=True)
class BandResolutions:
    """Per sub-band of a sweep, the resolution of every plate that meets a tolerance at its top
    (:func:`band_resolutions`)."""

    low: float  # the band's lower frequency (Hz)
    tops: tuple  # the sub-bands' upper frequencies (Hz), increasing
    resolutions: tuple  # per sub-band, {plate: resolution}

    def at(self, frequency: float) -> dict[str, float]:
        """``{plate: resolution}`` of the sub-band that holds ``frequency``."""
        index = int(np.searchsorted(self.tops, frequency * (1.0 - 1e-12)))
        return self.resolutions[min(index, len(self.tops) - 1)]

    def describe(self) -> str:
        """One line: each sub-band's largest resolution."""
        low = self.low
        parts = []
        for top, resolution in zip(self.tops, self.resolutions):
            parts.append(f"{low:g}-{top:g} Hz: {max(resolution.values()):.3g}")
            low = top
        return "resolution per sub-band (largest over the plates): " + ", ".join(parts)


def band_resolutions(case: Case, band: tuple[float, float], tolerance: float,
                     peaks: Sequence[float] = (), bands: int = TOLERANCE_BANDS) -> BandResolutions:
    """The resolutions at which a sweep over ``band`` meets ``tolerance`` (relative L2 of w):
    per each of ``bands`` equal sub-bands, the finest that
    :func:`solver.tolerance.solve_to_tolerance` needs at its top (the ray counts grow with the
    frequency) and at the resonance ``peaks`` it holds (where the relative error is largest),
    starting from the sub-band below (never coarser). Raises
    :class:`solver.errors.ToleranceError` where the tolerance cannot be reached."""
    low, high = band
    tops = tuple(low + (high - low) * (k + 1) / bands for k in range(bands))
    resolutions, start, bottom = [], None, low
    for top in tops:
        inside = [f for f in peaks if bottom <= f < top] + [top]
        for frequency in inside:
            estimate = solve_to_tolerance(case, frequency, tolerance, resolution=start)[1]
            start = {pid: estimate.resolution_of(pid) for pid in case.plates}
        resolutions.append(start)
        bottom = top
    return BandResolutions(low, tops, tuple(resolutions))


def strongest_peaks(sweep: Sweep, count: int) -> list[float]:
    """The frequencies of the ``count`` largest local maxima of the sweep's spatial RMS."""
    rms = sweep.spatial_rms()
    peaks = [i for i in range(len(rms)) if (i == 0 or rms[i] >= rms[i - 1])
             and (i == len(rms) - 1 or rms[i] >= rms[i + 1])]
    return sorted(float(sweep.frequencies[i]) for i in sorted(peaks, key=lambda i: -rms[i])[:count])


def sweep_point(case: Case, points: Mapping[str, np.ndarray], frequency: float,
                resolutions: BandResolutions | None = None
                ) -> tuple[np.ndarray, dict[str, np.ndarray], PowerFlow]:
    """One frequency: ``(response vector, {plate: w at points}, PowerFlow)``.

    ``points`` is ``{plate: (n, 2) plate-local points}``; the response vector concatenates the
    plates' values in that order (what :func:`solver.sweep.refine_frequencies` compares).
    ``resolutions`` (:class:`BandResolutions`) gives the resolution at the frequency (default
    the description's).
    """
    resolution = resolutions.at(frequency) if resolutions is not None else None
    solution = solve_case(case, frequency, resolution=resolution, residuals=False, check=False)
    values = {pid: solution.w(pid, pts) for pid, pts in points.items()}
    vector = np.concatenate([values[pid] for pid in points]) if points else np.zeros(0)
    return vector, values, power_flow(case, solution)


@dataclass(frozen=True)
class Sweep:
    """A sweep's frequencies, responses at the points, power flows and how it was sampled."""

    frequencies: np.ndarray
    points: dict  # plate -> (n, 2)
    values: list  # per frequency: {plate: w (n,)}
    powers: list  # per frequency: PowerFlow
    sampling: dict  # solver.sweep.refine_frequencies's report, plus the requested grid

    @property
    def imbalances(self) -> np.ndarray:
        return np.array([p.imbalance for p in self.powers])

    def spatial_rms(self) -> np.ndarray:
        """Per frequency, the RMS of |w| over the points (m)."""
        return np.array([spatial_rms(v.values()) for v in self.values])

    def measurements(self) -> Measurements:
        """The sweep as :class:`updating.data.measurements.Measurements` (one set per frequency)."""
        return Measurements({float(f): {pid: (self.points[pid], values[pid])
                                        for pid in self.points}
                             for f, values in zip(self.frequencies, self.values)})

    def to_json(self, order: Sequence[tuple[str, int]],
                nodes: Iterable[int] | None = None) -> dict[str, Any]:
        """JSON: sampling report, probe points in ``order`` ((plate, index) pairs) with their
        UFF node numbers (``nodes``, default 1, 2, ...), and per frequency ``w`` at the probes
        ([re, im]) and the power flow."""
        nodes = range(1, len(order) + 1) if nodes is None else nodes
        return {
            "band": [float(self.frequencies[0]), float(self.frequencies[-1])],
            "sampling": self.sampling,
            "balance_tolerance": BALANCE_TOLERANCE,
            "probes": [{"plate": pid, "x": float(self.points[pid][i, 0]),
                        "y": float(self.points[pid][i, 1]), "node": int(node)}
                       for (pid, i), node in zip(order, nodes)],
            "frequencies": [
                {"frequency": float(f),
                 "w": [[float(values[pid][i].real), float(values[pid][i].imag)]
                       for pid, i in order],
                 "power": power.to_json()}
                for f, values, power in zip(self.frequencies, self.values, self.powers)],
        }


def frequency_sweep(case: Case, band: tuple[float, float], points: dict[str, np.ndarray],
                    step: float | None = None, count: int | None = None, tolerance: float = 0.1,
                    fraction: float = 0.25, max_points: int = 2000,
                    executor: Executor | None = None,
                    on_round: Callable[[int], object] | None = None, check: bool = True,
                    resolutions: BandResolutions | None = None) -> Sweep:
    """Sweep ``band = (F1, F2)`` Hz, refining until the resonances are resolved.

    Parameters
    ----------
    case : assembly.Case
    points : dict of str to ndarray
        Plate-local points per plate where the response is recorded.
    step, count : float / int
        The requested grid: ``step`` Hz apart, or ``count`` frequencies.
    tolerance, fraction, max_points :
        Refinement rule (:func:`solver.sweep.refine_frequencies`).
    executor : updating.executor.Executor, optional
        Runs the frequencies of each round (default: in this process).
    on_round : callable, optional
        Called with the number of frequencies solved so far after each round (progress).
    check : bool, optional
        Run the description's guard rails at both ends of the band first (the magnitudes they
        check grow or fall with the frequency): errors raise
        :class:`assembly.DescriptionError`, warnings go into the sampling report (default
        True; False where they ran already).
    resolutions : BandResolutions, optional
        The resolution per sub-band (:func:`band_resolutions`: a sweep that meets
        ``[discretisation] tolerance``); default the description's everywhere.
    """
    warnings = check_description(case, case.name, list(band), need_loads=True) if check else []
    grid = initial_frequencies(band[0], band[1], step=step, points=count)
    evaluate = round_evaluator(functools.partial(sweep_point, case, points,
                                                 resolutions=resolutions), executor, on_round)
    frequencies, results, report = refine_frequencies(
        evaluate, grid, smallest_loss_factor(case), tolerance, fraction, max_points)
    report = dict(report, requested={"band": [float(band[0]), float(band[1])],
                                     "step": step, "points": count},
                  **({"warnings": warnings} if warnings else {}))
    return Sweep(frequencies, points, [values for _, values, _ in results],
                 [power for _, _, power in results], report)


def plate_deflection(system: AssemblySystem, amplitudes: Mapping[str, np.ndarray], plate_id: str,
                     points: np.ndarray) -> np.ndarray:
    """``w`` of plate ``plate_id`` at its plate-local ``points`` (n, 2), from the plates'
    ray ``amplitudes`` on ``system``."""
    return evaluate_field(system.problems[plate_id], system.bases[plate_id],
                          amplitudes[plate_id], points)["w"]


@dataclass(frozen=True)
class FrequencyResponseData:
    """Spatial RMS of ``|w|`` (m) over the measurement points against frequency.

    Attributes
    ----------
    frequencies : ndarray, shape (n,)
        Hz.
    curves : dict of str to ndarray, shape (n,)
        ``"initial"``, ``"updated"`` and, with ``[truth.joints]``, ``"true"``.
    analysed : tuple of float
        The measured frequencies (Hz).
    measured : ndarray, shape (len(analysed),)
        RMS of the measured ``|w|`` at the analysed frequencies.
    """

    frequencies: np.ndarray
    curves: dict
    analysed: tuple
    measured: np.ndarray


def frequency_band(frequencies: Sequence[float], width: float = 0.2,
                   points: int = 60) -> np.ndarray:
    """``points`` frequencies over ``[(1 - width) f_min, (1 + width) f_max]`` plus ``frequencies``.

    The analysed frequencies are inserted so that the curves pass through them.
    """
    if points < 2:
        raise ValueError(f"points must be at least 2, got {points}")
    if not 0.0 < width < 1.0:
        raise ValueError(f"width must be in (0, 1), got {width}")
    lo, hi = (1.0 - width) * min(frequencies), (1.0 + width) * max(frequencies)
    return np.union1d(np.linspace(lo, hi, points), np.asarray(frequencies, dtype=float))


def spatial_rms(values: Iterable[np.ndarray]) -> float:
    r"""Return :math:`\sqrt{\mathrm{mean}|w|^2}` of a sequence of complex arrays."""
    flat = np.concatenate([np.ravel(v) for v in values])
    return float(np.sqrt(np.mean(np.abs(flat) ** 2)))


def _set_responses(case: Case, parameter_sets: Mapping[str, Mapping[str, Mapping[str, float]]],
                   points: Mapping[str, np.ndarray], resolution: float | None,
                   frequency: float) -> tuple[np.ndarray, list[float]]:
    """The response vector of every parameter set at ``points`` and their spatial RMS at one
    frequency, from one shared system (a task of :func:`frequency_response_data`)."""
    system = build_assembly_system(case, float(frequency), resolution)
    alpha = case.updatable_alpha()
    values = []
    for parameters in parameter_sets.values():
        amplitudes = direct_amplitudes(system, parameters, alpha)
        values.append(np.concatenate([plate_deflection(system, amplitudes, pid, pts)
                                      for pid, pts in points.items()]))
    return np.concatenate(values), [spatial_rms([v]) for v in values]


def frequency_response_data(case: Case,
                            parameter_sets: Mapping[str, Mapping[str, Mapping[str, float]]],
                            frequencies: Sequence[float] | np.ndarray,
                            points: Mapping[str, np.ndarray],
                            measured: Sequence[float] | np.ndarray | None = None,
                            analysed: Iterable[float] = (), resolution: float | None = None,
                            on_round: Callable[[int], object] | None = None,
                            tolerance: float = 0.1, max_points: int = 400,
                            executor: Executor | None = None) -> FrequencyResponseData:
    """Spatial RMS of the model response at ``points`` for several joint parameter sets.

    One parameter-independent system per frequency
    (:func:`solver.substructure.build_assembly_system`) is shared by the parameter sets: the
    direct problem at each set is a small reduced solve. The result equals
    ``solver.solve_case(case.with_joint_parameters(p), f)`` sampled at ``points``. The
    frequencies are refined as ``vtcr frf`` refines them
    (:func:`solver.sweep.refine_frequencies`: bisection where a curve changes by more than
    ``tolerance`` between neighbours, down to a quarter of the half-power bandwidth), so that
    every resonance peak of every curve is drawn at its height.

    Parameters
    ----------
    case : assembly.Case
        An assembly with joints.
    parameter_sets : dict of str to dict
        ``{label: {joint: {log10_stiffness, loss_factor, mass}}}``.
    frequencies : array_like of float, shape (n,)
        The initial grid (Hz), increasing.
    points : dict of str to ndarray, shape (m, 2)
        Plate-local points per plate.
    measured : array_like of float, optional
        RMS of the measurements at ``analysed``.
    analysed : sequence of float
        The measured frequencies (Hz), marked on the figure.
    resolution : float, optional
        Discretisation resolution (default the description's).
    on_round : callable, optional
        Called with the number of frequencies solved so far after each round (progress).
    tolerance, max_points :
        Refinement rule (:func:`solver.sweep.refine_frequencies`).
    executor : updating.executor.Executor, optional
        Solves each round's frequencies in parallel.

    Returns
    -------
    FrequencyResponseData

    Notes
    -----
    Cost: one system build per frequency (about 0.1 s for ``cases/four_plates.toml``; the
    response curve of its update takes about 300 frequencies).
    """
    evaluate = round_evaluator(
        functools.partial(_set_responses, case, parameter_sets, points, resolution), executor,
        on_round)
    frequencies, results, _ = refine_frequencies(
        evaluate, np.asarray(frequencies, dtype=float), smallest_loss_factor(case), tolerance,
        max_points=max_points)
    curves = {label: np.array([rms[k] for _, rms in results])
              for k, label in enumerate(parameter_sets)}
    measured = np.asarray([] if measured is None else measured, dtype=float)
    return FrequencyResponseData(frequencies, curves, tuple(analysed), measured)
