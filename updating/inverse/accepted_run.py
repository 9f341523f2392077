"""The accepted run of a test inversion (:mod:`updating.inverse.confidence`): from the
acceptance margin of the test at any candidate value, a value the test accepts near the
estimate (:func:`accepted_start`) and the ends of the run of accepted values around it
(:func:`run_end`), walked to in strides and located by regula falsi.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["STRIDES", "Margin", "accepted_start", "run_end"]

Margin = Callable[[float], tuple[float, int, float]]
"""The acceptance margin of a test at a candidate value: ``(margin, side, centre)``, the
margin >= 0 where the value is accepted (how far inside the redraws' central range the
observed statistic lies, in units of that range), ``side`` -1 or +1 where it is rejected below
or above that range (0 accepted), ``centre`` the statistic's signed distance to the redraws'
median in the same units."""

STRIDES = 4  # longest stride of a walk, in walk steps


def _clamp(v: float, bounds: tuple[float, float]) -> float:
    return min(max(v, bounds[0]), bounds[1])


def accepted_start(start: float, margin: Margin, bounds: tuple[float, float], walk: float,
                   resolution: float) -> float | None:
    """An accepted value near ``start``: ``start`` itself, else the value where the observed
    statistic crosses the redraws' median (inside the accepted run by construction): walked to
    in steps of ``walk`` in the direction that brings them together (from the slope
    at ``start``), then found by regula falsi. None if there is no crossing within the bounds.
    """
    if margin(start)[1] == 0:
        return start
    centre = margin(start)[2]
    probe = _clamp(start + resolution, bounds)
    if probe == start:
        probe = _clamp(start - resolution, bounds)
    slope = (margin(probe)[2] - centre) / (probe - start)
    direction = -np.sign(centre) * np.sign(slope) or 1.0
    a = start
    while True:
        b = _clamp(a + direction * walk, bounds)
        if margin(b)[1] == 0:
            return b
        if np.sign(margin(b)[2]) != np.sign(centre):
            break
        if b == a:
            return None
        a = b
    for _ in range(40):
        m = _between(a, b, margin(a)[2], margin(b)[2])
        if margin(m)[1] == 0:
            return m
        if np.sign(margin(m)[2]) == np.sign(centre):
            a = m
        else:
            b = m
        if abs(b - a) < 1e-6:
            break
    return None


def _between(a: float, b: float, fa: float, fb: float) -> float:
    """The zero of the line through ``(a, fa)`` and ``(b, fb)`` (values of opposite signs),
    kept a tenth of the bracket away from its ends so that every step shrinks it."""
    t = fa / (fa - fb) if fa != fb else 0.5
    return a + min(max(t, 0.1), 0.9) * (b - a)


def _stride(a: float, previous: float | None, margin: Margin, walk: float) -> float:
    """The next step of a walk through accepted values: ``walk``, or up to :data:`STRIDES`
    times it while the margin, extrapolated along its last slope, stays above zero for twice
    the stride (a longer stride could land past a rejected gap; the margin is smooth)."""
    if previous is None:
        return walk
    slope = (margin(a)[0] - margin(previous)[0]) / abs(a - previous)
    if slope >= 0.0:
        return STRIDES * walk
    room = margin(a)[0] / -slope  # distance to the extrapolated zero
    return float(np.clip(0.5 * room, walk, STRIDES * walk))


def run_end(inside: float, direction: int, margin: Margin, bounds: tuple[float, float],
            indistinguishable: Callable[[float, float], bool], walk: float,
            resolution: float) -> tuple[float, int]:
    """The end of the accepted run walking from ``inside`` in ``direction``, and the side of
    the rejection beyond it (0 when the bound was reached). The end is the zero of the
    acceptance margin, bracketed to ``resolution`` by regula falsi and then interpolated
    (the margin is smooth in the value: rounding the end outwards to the bracket would widen a
    0.05-decade interval by a fifth, and its coverage with it). Once the model's predictions
    at the last accepted value and at the bound are ``indistinguishable`` (less than one noise
    deviation apart, all values together: a near-rigid or near-hinge joint), the run reaches
    the bound."""
    a, previous = inside, None
    bound = bounds[1] if direction > 0 else bounds[0]
    while True:
        if indistinguishable(a, bound):
            return bound, 0
        b = _clamp(a + direction * _stride(a, previous, margin, walk), bounds)
        if margin(b)[1] != 0:
            break
        if b == bound:
            return b, 0
        a, previous = b, a
    while abs(b - a) > resolution:
        m = _between(a, b, margin(a)[0], margin(b)[0])
        if margin(m)[1] == 0:
            a = m
        else:
            b = m
    end = a + (b - a) * margin(a)[0] / (margin(a)[0] - margin(b)[0])  # the margin's zero
    return end, margin(b)[1]
