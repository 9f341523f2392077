"""Frequency sweeps of the model: the response at probe points and where the power goes.

Each frequency is an independent task (:func:`sweep_point`: one solve of the description and
its :class:`solver.power.PowerFlow`), run on an :class:`updating.executor.Executor`; the
frequencies come from :func:`solver.sweep.refine_frequencies`, which refines the requested
grid until the resonances are resolved.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from solver import solve_case
from solver.power import power_flow
from solver.sweep import initial_frequencies, refine_frequencies

__all__ = ["Sweep", "sweep_point", "frequency_sweep", "smallest_loss_factor",
           "round_evaluator", "BALANCE_TOLERANCE"]

BALANCE_TOLERANCE = 1e-2
"""Relative power imbalance above which a frequency is flagged. At the default resolution the
imbalance follows the field error: 5e-4 on the Levy chain of the tests (field error 3e-4), 5e-10
at resolution 1.5; a per cent means the discretisation misses a condition somewhere."""


def smallest_loss_factor(case):
    """The smallest loss factor of the plates' materials: the narrowest half-power bandwidth
    of a resonance is this times its frequency (joint damping only widens it)."""
    return min(case.materials[plate.material].loss_factor for plate in case.plates.values())


def round_evaluator(task, executor=None, on_round=None):
    """``evaluate(frequencies) -> [task(f) for f in frequencies]`` for
    :func:`solver.sweep.refine_frequencies`: each round of frequencies on ``executor`` (default
    in this process), then ``on_round(number of frequencies solved so far)`` (progress)."""
    solved = 0

    def evaluate(frequencies):
        nonlocal solved
        results = executor.map(task, frequencies) if executor else [task(f) for f in frequencies]
        solved += len(results)
        if on_round:
            on_round(solved)
        return results

    return evaluate


def sweep_point(case, points, frequency):
    """One frequency: ``(response vector, {plate: w at points}, PowerFlow)``.

    ``points`` is ``{plate: (n, 2) plate-local points}``; the response vector concatenates the
    plates' values in that order (what :func:`solver.sweep.refine_frequencies` compares).
    """
    solution = solve_case(case, frequency, residuals=False)
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
    def imbalances(self):
        return np.array([p.imbalance for p in self.powers])

    def spatial_rms(self):
        """Per frequency, the RMS of |w| over the points (m)."""
        from updating.plots import spatial_rms

        return np.array([spatial_rms(v.values()) for v in self.values])

    def measurements(self):
        """The sweep as :class:`updating.measurements.Measurements` (one set per frequency)."""
        from updating.measurements import Measurements

        return Measurements({float(f): {pid: (self.points[pid], values[pid])
                                        for pid in self.points}
                             for f, values in zip(self.frequencies, self.values)})

    def to_json(self, order, nodes=None):
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


def frequency_sweep(case, band, points, step=None, count=None, tolerance=0.1, fraction=0.25,
                    max_points=2000, executor=None, on_round=None) -> Sweep:
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
    """
    grid = initial_frequencies(band[0], band[1], step=step, points=count)
    evaluate = round_evaluator(functools.partial(sweep_point, case, points), executor, on_round)
    frequencies, results, report = refine_frequencies(
        evaluate, grid, smallest_loss_factor(case), tolerance, fraction, max_points)
    report = dict(report, requested={"band": [float(band[0]), float(band[1])],
                                     "step": step, "points": count})
    return Sweep(frequencies, points, [values for _, values, _ in results],
                 [power for _, _, power in results], report)
