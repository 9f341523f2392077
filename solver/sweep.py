r"""Frequencies of a sweep that resolve its resonances.

A lightly damped structure's response changes by orders of magnitude within a half-power
bandwidth :math:`\Delta f = \eta f` of each resonance (2-3 Hz at 250 Hz for :math:`\eta` = 0.01),
so a uniform grid either misses peaks or wastes solves between them. Starting from the
requested grid, :func:`refine_frequencies` bisects every interval whose two ends differ by more
than ``tolerance``,

.. math:: \frac{\|w(f_{k+1}) - w(f_k)\|}{\max(\|w(f_k)\|, \|w(f_{k+1})\|)} > \text{tolerance},

(the response vector: probe displacements), until every interval passes or is narrower than
``fraction`` of the smallest half-power bandwidth :math:`\eta_{min}f` (so that each resonance
peak gets about ``1 / fraction`` points across its half-power band), or ``max_points`` are
spent. Each round's new frequencies are evaluated together, so a parallel executor serves a
whole round at once.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np

__all__ = ["initial_frequencies", "refine_frequencies", "relative_change"]


def initial_frequencies(low: float, high: float, step: float | None = None,
                        points: int | None = None) -> np.ndarray:
    """The requested grid over ``[low, high]`` (Hz): ``step`` apart, or ``points`` values.

    With ``step`` the last interval may be shorter (``high`` is always included).
    """
    if not (math.isfinite(low) and math.isfinite(high) and 0.0 < low < high):
        raise ValueError(f"the band must satisfy 0 < F1 < F2, got {low} {high}")
    if step is not None:
        if not (math.isfinite(step) and step > 0.0):
            raise ValueError(f"the step must be > 0 Hz, got {step}")
        count = math.floor((high - low) / step * (1.0 + 1e-12))
        return np.unique(np.append(low + step * np.arange(count + 1), high))
    if points is None or points < 2:
        raise ValueError(f"a sweep needs at least 2 points, got {points}")
    return np.linspace(low, high, points)


def relative_change(a: np.ndarray, b: np.ndarray) -> float:
    """:math:`\\|b - a\\| / \\max(\\|a\\|, \\|b\\|)` of two response vectors (0 if both vanish)."""
    scale = max(float(np.linalg.norm(a)), float(np.linalg.norm(b)))
    return float(np.linalg.norm(b - a)) / scale if scale > 0.0 else 0.0


def refine_frequencies(
    evaluate: Callable[[list[float]], Iterable[tuple[Any, ...]]],
    frequencies: Sequence[float] | np.ndarray, loss_factor: float, tolerance: float = 0.1,
    fraction: float = 0.25, max_points: int = 2000,
) -> tuple[np.ndarray, list[tuple[Any, ...]], dict[str, Any]]:
    """Sample a response adaptively; returns ``(frequencies, responses, report)``.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(list of Hz) -> list of results``, one per frequency, each a tuple whose
        first item is the response vector compared between neighbours (the rest is kept as
        returned).
    frequencies : array_like of float
        The initial grid (increasing).
    loss_factor : float
        The smallest loss factor of the structure: resonances are at least ``loss_factor * f``
        wide at half power.
    tolerance, fraction, max_points :
        See the module docstring.

    Returns
    -------
    frequencies : ndarray of float
    results : list
        ``evaluate``'s results, one per frequency.
    report : dict
        ``initial``, ``final`` (counts), ``rounds``, ``tolerance``, ``fraction``,
        ``resolved`` (False when ``max_points`` stopped the refinement) and ``largest_change``
        (the largest relative change left between neighbours wider than the minimum step).
    """
    freqs = [float(f) for f in frequencies]
    results = list(evaluate(freqs))
    rounds = 0
    resolved = True
    while True:
        wanted = [0.5 * (freqs[i] + freqs[i + 1]) for i in range(len(freqs) - 1)
                  if _needs_point(freqs[i], freqs[i + 1], results[i][0], results[i + 1][0],
                                  loss_factor, tolerance, fraction)]
        if not wanted:
            break
        room = max_points - len(freqs)
        if room <= 0:
            resolved = False
            break
        if len(wanted) > room:
            resolved = False
            wanted = wanted[:room]
        rounds += 1
        merged = sorted(zip(freqs + wanted, results + list(evaluate(wanted))),
                        key=lambda pair: pair[0])
        freqs, results = [f for f, _ in merged], [r for _, r in merged]
    changes = [relative_change(results[i][0], results[i + 1][0]) for i in range(len(freqs) - 1)
               if freqs[i + 1] - freqs[i] > fraction * loss_factor * freqs[i]]
    report = {"initial": len(frequencies), "final": len(freqs), "rounds": rounds,
              "tolerance": tolerance, "fraction": fraction, "loss_factor": loss_factor,
              "resolved": resolved, "largest_change": max(changes, default=0.0)}
    return np.array(freqs), results, report


def _needs_point(f1: float, f2: float, w1: np.ndarray, w2: np.ndarray, loss_factor: float,
                 tolerance: float, fraction: float) -> bool:
    return (f2 - f1 > fraction * loss_factor * f1
            and relative_change(w1, w2) > tolerance)
