r"""Joint lines: their Gauss rules, the Legendre functions that carry their loads, and the
channel parameters of the joint laws (``docs/method.md`` sections 6.2 and 7.3).

A leaf of the assembly solve: :mod:`solver.substructure` builds its channels on these rules,
and :mod:`solver.power` integrates the power through the joints on the same ones.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from assembly.case import Case
from assembly.joints import JunctionJoint
from solver.line_ends import held_end_exponents, held_free_ends
from solver.plate_corners import clamped_free_exponents
from solver.rays import end_graded_rule, gauss_legendre

__all__ = ["LOAD_WAVENUMBER_COUNT", "LoadEnds", "NO_SINGULAR_ENDS", "interface_function_count",
           "end_layer_count",
           "END_LAYER_FROM", "PINNED_LINE_FACTOR", "HANGING_LINE_FACTOR",
           "pinned_line_count",
           "load_function_projection", "singular_load_ends", "held_free_end_exponents",
           "extra_load_functions", "legendre_count_floor", "mixed_end_legendre_count",
           "load_function_values", "joint_gauss", "channel_parameters",
           "joint_parameters", "translational_stiffness"]


LOAD_WAVENUMBER_COUNT = 0.75
r"""The count of a joint's wavenumbers, :math:`0.75\,s\,\kappa_0L` Legendre functions at
resolution :math:`s` (:func:`interface_function_count`): its loads carry wavenumbers up to
about :math:`1.5\kappa_0`, and a Legendre series resolves :math:`e^{j\beta\sigma}` on
:math:`[0, L]` from :math:`\beta L/2` functions."""


def interface_function_count(kappa0: float, length: float, resolution: float = 1.0,
                             tau: float = 2.5, kappa_answered: float | None = None) -> int:
    r"""Legendre functions per interface unknown:
    :math:`M = \lceil\min(0.75\,s\,\kappa_0,\ \tfrac{\tau}{2}\kappa_a)\,L\rceil + 2`, with
    :math:`\kappa_a = \kappa_0` (``kappa_answered``) unless given.

    A Legendre series resolves :math:`e^{j\beta\sigma}` on :math:`[0, L]` once
    :math:`M > \beta L/2`; the joint loads carry wavenumbers up to about :math:`1.5\kappa_0`
    (propagating waves plus the slower part of the edge boundary layers). More functions than
    the plates' rays can answer make the loads' system ill-posed: against the Levy series of a
    three-plate chain from 60 to 600 Hz and log10 k = 2 to 8, ``+ 2`` was near the best count
    everywhere, and ``+ 8`` up to ten times less accurate at stiff joints and low
    :math:`\kappa_0L` (``bench/README.md``). For the same reason the count stops growing with
    the resolution :math:`s` where the functions pass the rays' largest edge wavenumber
    :math:`\tau\kappa_a` (``tau``, the ``edge_wavenumber_ratio``), at :math:`s = 2\tau/3`:
    on a stiffened panel at 2500 Hz (rays at resolution 2.25) 59, 65 and 87 functions gave
    7e-9, 7e-9 and 2e-8, the 129 of resolution 3.375 6e-3.

    A moving line (``docs/method.md`` section 10.4) takes for :math:`\kappa_a` the smallest
    :math:`\kappa_0` of its members, the largest edge wavenumber *every* member's rays answer.
    A member's :math:`K_n`, :math:`N_{nn}`, :math:`N_{nt}` enter only the line's force
    balance and translation continuity; on a function its bending rays cannot answer, its
    :math:`K_n` is balanced by the other members' in-plane tractions, whose response, of
    compliance about :math:`1/(A^*\beta)`, is 1e3 to 1e4 times smaller than a bending one:
    a near-null direction of the interface problem per such function. On a three-bay panel
    at 2500 Hz (1 mm skin, 2 mm stiffeners, :math:`\kappa_0` 100 and 71 /m) the 53 functions
    of :math:`\kappa_0 = 100` left 72 singular values below 1e-8 of the largest, interface
    loads of 1e5 to 1e7 N/m for a 1 N force and, through the grouped factorisation of the
    interface problem, fields wrong by order 1; the 38 of :math:`\kappa_a = 71` converge
    (2e-5 to 2e-4 between resolutions 1.5 and 2.25). Where the members reach further (a line
    that meets others or ends on a free edge), :math:`\kappa_a` counts their reach
    (:func:`solver.layout.answered_wavenumber`).
    """
    answered = kappa0 if kappa_answered is None else kappa_answered
    return math.ceil(min(LOAD_WAVENUMBER_COUNT * resolution * kappa0, 0.5 * tau * answered)
                     * length) + 2


END_LAYER_FROM = 1.5
"""The resolution from which a moving line with an end that translates along it has at least
:func:`end_layer_count` functions (below it the count of :func:`interface_function_count`
stands: at resolution 1 the floor made the sliding L fold at 1 kHz twenty times worse)."""


def end_layer_count(kappa_answered: float, length: float, resolution: float,
                    tau: float = 2.5) -> int:
    r"""The fewest Legendre functions of a moving line with an end that translates along it,
    from resolution :data:`END_LAYER_FROM` (:func:`solver.line_ends.end_layer_lines`): an end
    free to slide (a free edge, or a supported one free in plane) or a junction point where
    moving lines meet:

    .. math:: M_e = \min\left(\lceil 4\sqrt{\kappa_a L}\,\rceil,\
              \lceil\tfrac{\tau}{2}\kappa_a L\rceil + 2\right),

    :math:`\kappa_a` the wavenumber the members' reach answers
    (:func:`solver.layout.answered_wavenumber`), the second term the cap of
    :func:`interface_function_count`. At such an end the loads form a layer that the Legendre
    functions resolve on a scale of about :math:`L/M^2` and the members' edge waves on one of
    :math:`1/\kappa_a`; where the two meet the error is least, and past it the loads ask what
    the rays do not answer and the error rises again. The wavenumbers' count
    (:math:`0.75\,s\,\kappa_0L`) falls short of it at low frequency and resolution. Against
    independent finite elements, worst plate's ``w`` at resolutions 1.5, 2.25 and 3.375
    (``bench/bench_free_ends.py --finite-elements``, ``--sliding-ends``,
    ``bench/bench_corner.py --floating``): the free-ended bracket at 300 Hz 2.5e-4, 1.0e-4,
    2.1e-5 against 2.4e-3, 5.3e-4, 4.4e-5 with the wavenumbers' count, at 1 kHz 2.4e-4, 3.7e-5,
    7.1e-6 against 5.9e-4, 3.8e-5, 7.1e-6; the fold with sliding ends at 300 Hz 8.2e-5, 1.3e-5,
    6.8e-6 against 1.2e-4, 4.9e-5, 8.4e-6; the floating corner 2.4e-2, 4.4e-3, 1.8e-3 against
    2.3, 7.9e-2, 1.0e-2; at the same cost, the estimates 0.49 to 1.23 times the errors. Where
    lines meet (``bench/bench_corner.py``): the trihedral corner at 300 Hz 8.9e-6, 1.0e-6,
    3.0e-7 against 4.7e-5, 8.2e-6, 1.6e-6. On a U channel of two free-ended lines, a check
    after the rule was set (``bench/bench_free_ends.py --channel``): 5.6e-4, 2.7e-4, 5.0e-5
    against 6.2e-3, 1.0e-3, 1.3e-4. The best count of each fold, scanned at resolution 1.5,
    lies within a few functions of :math:`4.6\sqrt{\kappa_aL}` (free ends; 4.6 to 5.2 on the
    channel) and :math:`3.9\sqrt{\kappa_aL}` (sliding); past it the error rises fast, so the
    floor keeps below the free ends' best. Returns 0 below :data:`END_LAYER_FROM`."""
    if resolution < END_LAYER_FROM - 1e-9:
        return 0
    reach = kappa_answered * length
    return min(math.ceil(4.0 * math.sqrt(reach)), math.ceil(0.5 * tau * reach) + 2)


PINNED_LINE_FACTOR = 7.0
r"""The factor :math:`c` of :func:`pinned_line_count` on a line with a pinned end on which no
member hangs alone (the fold with sliding ends, the channel whose web hangs on both its
lines), :math:`c\sqrt{\kappa_aL}`."""

HANGING_LINE_FACTOR = 8.5
r"""The factor :math:`c` of :func:`pinned_line_count` on a line with a pinned end on which a
member hangs alone (a stiffener free at its ends and top on a supported skin)."""


def pinned_line_count(kappa_answered: float, length: float, resolution: float,
                      hanging: bool) -> int:
    r"""The Legendre functions of a moving line with a pinned end
    (:func:`solver.line_ends.pinned_lines`), from resolution :data:`END_LAYER_FROM` on, in
    place of the usual count and its floors:

    .. math:: M_p = \lceil c\,\sqrt{\kappa_aL}\,\rceil,\qquad c =
              \text{:data:`HANGING_LINE_FACTOR` (8.5) if a member hangs on the line alone
              (``hanging``), else :data:`PINNED_LINE_FACTOR` (7)},

    :math:`\kappa_a` as for :func:`end_layer_count`. The line's loads are concentrated at the
    pins, layers about 0.2 mm wide. Against independent finite elements the error falls
    steeply with the count to a best count and rises fast past it (the members' reach no
    longer answers the functions), so the count is fixed, neither a floor nor the usual count,
    which is too small at low frequency and resolution and too large at 3 kHz from resolution
    3.375 on.

    * *A member hangs on the line alone* (``hanging``): its rigid motion in its plane, most of
      its error, is held only through this line's functions. The T junction whose stiffener is
      free at its ends and top (``bench/bench_free_ends.py --pinned-counts``): best counts 6.3
      to 8.6 :math:`\sqrt{\kappa_aL}`; worst plate's ``w`` at resolutions 1.5 and 2.25, 300 Hz
      1.5e-2 and 4.1e-3 with the usual count (25, 32 functions), 1.0e-4 and 1.2e-5 with this
      one (52, 64); 1 kHz 6.1e-2 and 4.8e-3 (38, 56), 3.8e-4 and 2.2e-4 (70, 86); at 3 kHz (no
      reference) the changes between resolutions 1.5, 2.25 and 3.375 fall, 1.0e-3 then 5.3e-4,
      where with the usual count they do not (9.4e-3, 1.0e-2). Of 7.5, 8 and 8.5 times, 8.5
      left the estimates closest to the errors.
    * *No member hangs alone*: the L fold with sliding ends (``--sliding-ends``), whose usual
      count with the free end's floor was best before its members had their logarithmic
      families (3.9 :math:`\sqrt{\kappa_aL}` at resolution 1.5) and fell short after. Worst
      plate's ``w``, then ``(u, v)``, at resolutions 1.5, 2.25, 3.375: 300 Hz 7.0e-7, 7.5e-7,
      3.4e-7 and 4.6e-4, 2.9e-4, 1.4e-4 (with the usual count 4.1e-5, 2.2e-5, 9.8e-6 and
      2.7e-2, 1.3e-2, 4.9e-3); 1 kHz 2.4e-6, 5.2e-7, 6.7e-7 and 1.6e-4, 3.8e-5, 4.4e-5
      (7.7e-5, 2.2e-5, 3.6e-6 and 1.2e-2, 2.9e-3, 3.2e-4); at 3 kHz the changes 1.4e-6, 5.4e-7
      (1.3e-4, 1.5e-5). Factors 6.5 and 7.5 did about as well, 5.5 and 8.5 worse (5.5: 1.1e-5
      at 1 kHz and 1.5, its ``(u, v)`` estimate 0.12 to 0.17 of the error at 3.375; 8.5:
      1.6e-5 at 1 kHz and 2.25). A U channel whose ends slide (``--sliding-channel``, no
      reference), whose web hangs on both lines: changes of ``w`` between resolutions 1.5,
      2.25 and 3.375 of 1.6e-5, 2.9e-6 at 300 Hz and 7.3e-5, 1.6e-5 at 1 kHz, against 4.8e-5,
      1.1e-5 and 1.2e-4, 3.8e-5 with 8.5 and 9.2e-4, 5.1e-4 and 7.3e-3, 2.1e-3 with the usual
      count.

    ``docs/method.md`` section 10.4, *Pinned ends*. Below :data:`END_LAYER_FROM` the usual
    count stands: there the enriched solve of the error estimate has this count, and the
    estimate sees what the usual count leaves. Returns 0 below it."""
    if resolution < END_LAYER_FROM - 1e-9:
        return 0
    factor = HANGING_LINE_FACTOR if hanging else PINNED_LINE_FACTOR
    return math.ceil(factor * math.sqrt(kappa_answered * length))


def load_function_projection(root_w: np.ndarray, psi: np.ndarray) -> np.ndarray:
    r""":math:`Q^HW^{1/2}`, shape (n_f, Gauss points): the coordinates, on an orthonormal basis
    :math:`Q` of the joint's weighted load functions :math:`W^{1/2}\psi`, of a quantity sampled
    at the joint's Gauss points. A channel's load and kinematic samples are taken through it.

    The residual :math:`r = (LS + l) - c(RS + \rho)` then counts through its :math:`L^2`
    projection on the functions that carry the loads, :math:`\|Q^HW^{1/2}r\|^2`: the joint law
    is imposed as far as the loads can carry it. The part of the plates' traces outside those
    functions, which no load of the discretisation can balance, is not counted; measuring it
    made each channel's rows as many as its Gauss points (instead of its functions) and, with
    the functions a plate's rays can answer, left a floor of that part in every residual
    (``bench/README.md``)."""
    return scipy.linalg.orth(root_w[:, None] * psi).conj().T * root_w


LoadEnds = tuple[bool | tuple[complex, ...], ...]
"""Per end of a joint line (start, end), how its loads are singular there
(:func:`singular_load_ends`)."""

NO_SINGULAR_ENDS: LoadEnds = (False, False)

SINGULAR_END_FUNCTIONS = 2
"""Load functions added per singular end of a moving line (:func:`load_function_values`)."""


def singular_load_ends(case: Case, joint_id: str,
                       resolution: float | Mapping[str, float] | None = None) -> LoadEnds:
    r"""How a joint's loads are singular at its start and its end (along the line), per end:
    the exponents :math:`\lambda` of :func:`held_free_end_exponents` at the end of a held
    line on a free edge (:func:`solver.line_ends.held_free_ends`); ``True`` where they are
    log-singular, at the mixed ends of a moving line
    (:meth:`assembly.Case.singular_line_ends`, ``docs/method.md`` section 10.4; a held line's
    loads are not: without the in-plane field no member's deflection is tied to another's
    translation, and a line with a mixed end moves only with ``held = false``,
    :func:`assembly.lines.moving_lines`); the exponents :math:`\lambda` of
    :func:`solver.line_ends.held_end_exponents` where they go like :math:`t^{\lambda - 1}`, at
    an end fixed in its plane (``resolution`` as there); ``False`` elsewhere."""
    joint = case.joints[joint_id]
    if joint.kind == "coplanar":
        return NO_SINGULAR_ENDS
    free = held_free_ends(case, joint_id)
    if any(free):
        exponents = held_free_end_exponents(
            tuple(sorted({case.material_of(plate).poisson_ratio for plate in joint.plates})))
        return tuple(exponents if end else False for end in free)
    logarithmic = case.singular_line_ends(joint_id) if joint.held is False else NO_SINGULAR_ENDS
    powers = held_end_exponents(case, joint_id, resolution)
    return tuple(True if log else (power or False) for log, power in zip(logarithmic, powers))


@functools.cache
def held_free_end_exponents(poisson_ratios: tuple[float, ...]) -> tuple[complex, ...]:
    r"""The exponents :math:`\lambda` of the moment along a held line at an end on a free edge
    (:func:`solver.line_ends.held_free_ends`), :math:`M \sim t^{\lambda - 1}`: those of its
    members' clamped-free corners, :math:`\lambda = \mu - 1` for each exponent :math:`\mu` of
    :func:`solver.plate_corners.clamped_free_exponents` (the moment of :math:`r^\mu F(\theta)`
    goes like :math:`r^{\mu - 2}`), one of each conjugate pair (its load functions are the real
    and imaginary parts): :math:`1.069 + 0.439j` and :math:`2.464` for :math:`\nu = 0.3`
    (``docs/method.md`` section 5.5, *A held line's end on a free edge*)."""
    exponents = {complex(mu) - 1.0 for nu in poisson_ratios
                 for mu in clamped_free_exponents(nu) if complex(mu).imag >= 0.0}
    return tuple(lam if lam.imag > 0.0 else lam.real
                 for lam in sorted(exponents, key=lambda lam: (lam.real, lam.imag)))


def _function_count(exponent: complex) -> int:
    r"""Load functions of one exponent of a singular end: the real and imaginary parts of
    :math:`t^{\lambda - 1}` where :math:`\lambda` is complex."""
    return 2 if isinstance(exponent, complex) else 1


def extra_load_functions(ends: LoadEnds) -> int:
    """The load functions :func:`load_function_values` adds to the Legendre ones at the
    singular ``ends``: :data:`SINGULAR_END_FUNCTIONS` at a log-singular end, one per real
    exponent and two per complex one at an end fixed in its plane or a held line's end on a
    free edge."""
    return sum(SINGULAR_END_FUNCTIONS if end is True
               else sum(map(_function_count, end)) if end else 0 for end in ends)


def _singular_functions(t: np.ndarray, s: np.ndarray, ends: LoadEnds) -> list[np.ndarray]:
    r""":math:`\ln t`, :math:`t\ln t` if the start is log-singular, :math:`t^{\lambda - 1}` for
    each of its exponents (its real and imaginary parts for a complex one) if it has exponents;
    likewise of :math:`s` at the end; at
    ``t`` in (0, 1) with ``s`` = 1 - ``t`` (given apart: near the end ``t`` rounds to 1 before
    ``s`` to 0)."""
    functions = []
    for end, x in zip(ends, (t, s)):
        if end is True:
            functions += [np.log(x), x * np.log(x)]
        elif end:
            for lam in end:
                power = x ** (lam - 1.0)
                functions += [power.real, power.imag] if isinstance(lam, complex) else [power]
    return functions


SINGULAR_RULE = (24, 0.15, 20)
"""The rule of the inner products in :func:`_orthonormal_singular_parts` and
:func:`mixed_end_legendre_count`: on each half of the
line, panels in geometric progression of ratio 0.15 towards its end (24 of them, the last
2e-20 wide), with 20 Gauss points more than the Legendre functions each: the products of
the Legendre and logarithmic functions to round-off."""


def _graded_unit_rule(n_legendre: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(t, 1 - t, weights)`` of :data:`SINGULAR_RULE` on (0, 1), graded towards both ends
    (``1 - t`` given apart, for the same reason as in :func:`_singular_functions`)."""
    panels, ratio, points = SINGULAR_RULE
    cuts = np.concatenate([[0.0], 0.5 * ratio ** np.arange(panels)[::-1]])
    x, w = gauss_legendre(n_legendre + points)
    half = 0.5 * np.diff(cuts)
    near = ((cuts[:-1] + half)[:, None] + half[:, None] * x).ravel()  # in (0, 1/2)
    t, s = np.concatenate([near, 1.0 - near]), np.concatenate([1.0 - near, near])
    return t, s, np.tile((half[:, None] * w).ravel(), 2)


SINGULAR_REMAINDER = 1e-6
r"""What the Legendre functions of a line with a mixed end may leave of the next term of its
loads' expansion, :math:`t^2\ln t` (relative :math:`L^2(0, 1)`): :func:`mixed_end_legendre_count`."""


@functools.cache
def mixed_end_legendre_count(remainder: float = SINGULAR_REMAINDER, most: int = 60) -> int:
    r"""The fewest Legendre functions a line with a mixed end carries its loads on:

    .. math:: M_s = \min\{M : \|f - \Pi_Mf\| \le \epsilon\,\|f\|\},
              \qquad f = t^2\ln t,

    :math:`\Pi_M` the :math:`L^2(0, 1)` projection on :math:`P_0(2t - 1), \dots,
    P_{M-1}(2t - 1)` and :math:`\epsilon` ``remainder`` (:data:`SINGULAR_REMAINDER`): 27
    (``docs/method.md`` section 10.4). Near a mixed end the loads go like :math:`a\ln t + b +
    c\,t\ln t + O(t^2\ln t)`; the two singular terms are load functions of their own
    (:func:`load_function_values`), and the Legendre functions carry the rest, whose slowest
    part is :math:`t^2\ln t`: its remainder falls like :math:`M^{-5}` (1e-5 at 17, 1e-6 at 27,
    6e-7 at 30). The count of the wavenumbers (:func:`interface_function_count`) does not see
    it: on the L fold of the tests with roller ends it gives 7 to 22 functions from 60 to
    500 Hz, and from resolution 2.25 on ``w`` stopped 5.7e-6 to 1.4e-5 off an independent
    finite-element solution at 60 to 300 Hz, where the error estimate, whose enriched solve
    keeps the count, said 0.01 to 0.28 of it. With at least 27 ``w`` is within 1.9e-7 to
    2.3e-6 of the finite elements at resolution 2.25 (6.6e-7 to 7.2e-6 at 1.5), and the
    estimate 0.86 to 1.14 times the error where that is above 1e-5 (0.23 to 5.2 times
    below: where the floor decides the count the enriched solve carries the same 27, and
    does not see what they leave). At most ``most`` functions are tried."""
    t, _, weights = _graded_unit_rule(most)
    f = t**2 * np.log(t)
    legendre = np.polynomial.legendre.legvander(2.0 * t - 1.0, most - 1)
    coefficients = (2.0 * np.arange(most) + 1.0) * (legendre.T @ (weights * f))
    partial_sums = np.cumsum(legendre * coefficients, axis=1)  # column M - 1: Pi_M f
    left = np.sqrt(weights @ (f[:, None] - partial_sums) ** 2 / (weights @ f**2))
    if not np.any(left <= remainder):
        raise ValueError(f"{most} Legendre functions leave {left[-1]:.1e} of t^2 ln t, "
                         f"above {remainder:.1e}")
    return int(np.argmax(left <= remainder)) + 1


def legendre_count_floor(ends: LoadEnds) -> int:
    """The fewest Legendre functions of a joint whose loads are log-singular at ``ends``
    (:func:`singular_load_ends`): :func:`mixed_end_legendre_count` at a mixed end, else 0."""
    return mixed_end_legendre_count() if any(end is True for end in ends) else 0


@functools.cache
def _orthonormal_singular_parts(n_legendre: int, ends: LoadEnds) -> np.ndarray:
    r"""The coefficients :math:`A`, shape ``(n_legendre + k, k)``, of the parts of the ``k``
    functions of :func:`_singular_functions` orthogonal to the ``n_legendre`` Legendre
    functions and to each other, of unit :math:`L^2(0, 1)` norm: ``[P, S] @ A`` (modified
    Gram-Schmidt, twice, on the inner products of a graded rule, :data:`SINGULAR_RULE`)."""
    t, s, weights = _graded_unit_rule(n_legendre)
    legendre = np.polynomial.legendre.legvander(2.0 * t - 1.0, n_legendre - 1)
    values = np.column_stack([legendre, *_singular_functions(t, s, ends)])
    coefficients = np.eye(values.shape[1])[:, n_legendre:]
    inverse_norms = 2.0 * np.arange(n_legendre) + 1.0  # the Legendre functions': 1/(2i + 1)
    for _ in range(2):  # a second pass restores the orthogonality the first loses in rounding
        for j in range(coefficients.shape[1]):
            column = values @ coefficients[:, j]
            coefficients[:n_legendre, j] -= inverse_norms * (legendre.T @ (weights * column))
            for i in range(j):
                other = values @ coefficients[:, i]
                coefficients[:, j] -= np.sum(weights * other * column) * coefficients[:, i]
            column = values @ coefficients[:, j]
            coefficients[:, j] /= math.sqrt(np.sum(weights * column**2))
    return coefficients


def load_function_values(sigma: ArrayLike, length: float, n: int,
                         ends: LoadEnds = NO_SINGULAR_ENDS) -> np.ndarray:
    r"""The joint's ``n`` load functions at arc lengths ``sigma``, shape ``(len(sigma), n)``:
    the Legendre functions :math:`P_m(2t - 1)`, :math:`t = \sigma/L`, then at each singular
    end (``ends``: start, end, :func:`singular_load_ends`) the singular terms of the loads
    there: at an end fixed in its plane :math:`t^{\lambda - 1}` for each of its exponents
    (``docs/method.md`` section 10.4, *The loads' singular terms*); at a log-singular end the
    two leading ones,
    :math:`\ln t` and :math:`t\ln t` at the start, :math:`\ln(1 - t)` and
    :math:`(1 - t)\ln(1 - t)` at the end, each by its part orthogonal to the functions before
    it, of unit norm (:func:`_orthonormal_singular_parts`).

    At a mixed end of a moving line the loads go like :math:`a\ln t + b + c\,t\ln t +
    O(t^2\ln t)` (``docs/method.md`` section 10.4). A Legendre series of that converges only
    algebraically (the coefficients of :math:`\ln t` fall like :math:`1/m`), and more
    Legendre functions than the rays answer spoil the solve; hence the two singular terms
    as functions of their own: on the L fold of the tests with roller ends the field then
    meets an independent finite-element solution to 2e-6 to 1e-5 in ``w`` and 1e-4 to 4e-4
    in ``(u, v)``, where the Legendre functions alone left 1e-4 and 1e-2 to 1e-1. By their
    orthogonal parts, because :math:`t\ln t` is close
    to the span of the Legendre functions (2e-5 of its norm outside 50 of them): taken as
    is, the loads' coefficients cancel, 1e5 for loads of 1e2 N/m on the T junction of the
    tests at 3 kHz, and that solve changed by 4e-4 between resolutions 2.25 and 3.4 where
    the orthogonal parts leave 2e-5."""
    t = np.asarray(sigma, dtype=float) / length
    singular = _singular_functions(t, (length - np.asarray(sigma, dtype=float)) / length, ends)
    legendre = np.polynomial.legendre.legvander(2.0 * t - 1.0, n - len(singular) - 1)
    if not singular:
        return legendre
    values = np.column_stack([legendre, *singular])
    return np.column_stack([legendre, values @ _orthonormal_singular_parts(legendre.shape[1],
                                                                           tuple(ends))])


def joint_gauss(length: float, k_max: float, ends: LoadEnds = NO_SINGULAR_ENDS
                ) -> tuple[np.ndarray, np.ndarray]:
    r"""Gauss points and weights on a joint line of ``length`` (m):
    :math:`\lceil k_{max}L\rceil + 16` points, where :math:`k_{max}` is the largest ray
    wavenumber of the joint's plates; graded towards both ends
    (:func:`solver.rays.end_graded_rule`) where one is singular (``ends``,
    :func:`singular_load_ends`), for the logarithmic load functions and the plates' corner
    functions there."""
    n = math.ceil(k_max * length) + 16
    if any(ends):
        return end_graded_rule(length, n)
    x, w = gauss_legendre(n)
    return 0.5 * length * (x + 1.0), 0.5 * length * w


def channel_parameters(parameters: Mapping[str, Mapping[str, float]],
                       omega: float) -> dict[tuple[str, str], complex]:
    r"""``{(channel name, kind): c}`` from ``{name: {log10_stiffness, loss_factor, mass}}``
    (:meth:`assembly.Case.updatable_parameters`): the rotation channel's
    :math:`k(1 + j\zeta)` and the mass channel's :math:`\omega^2\mu`."""
    out = {}
    for name, p in parameters.items():
        out[name, "rotation"] = 10.0 ** p["log10_stiffness"] * (1.0 + 1j * p["loss_factor"])
        out[name, "mass"] = omega**2 * p["mass"] + 0j
    return out


def joint_parameters(case: Case, omega: float) -> dict[tuple[str, str], complex]:
    """Channel parameters ``{(channel name, kind): c}`` of the description's joints."""
    return channel_parameters(case.updatable_parameters(), omega)


def translational_stiffness(joint: JunctionJoint, plate: str) -> complex:
    r""":math:`k_{t,i}^* = 10^{\log_{10}k_{t,i}}(1 + j\zeta_{t,i})` (N/m²) of a junction
    member's translational spring."""
    return (10.0 ** joint.member_log10_translational_stiffness(plate)
            * (1.0 + 1j * joint.member_translational_loss_factor(plate)))
