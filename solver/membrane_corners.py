r"""Corner functions of the in-plane field where a ``fixed`` edge meets a ``free`` or loaded one
(``docs/method.md`` section 10.5).

Near such a right-angle corner the plane-stress field is not smooth: the static problem's
local solutions are :math:`r^\lambda\mathbf F(\theta)` with the exponents :math:`\lambda` of the
clamped-free wedge (Williams, 1952), the roots of

.. math:: 1 + \kappa^2 + 2\kappa\cos(\pi\lambda) = 4\lambda^2,\qquad
    \kappa = \frac{3 - \nu}{1 + \nu}\ \text{(plane stress)},

0.758 and then complex pairs (:math:`1.719 \pm 0.448j`, :math:`3.812 \pm 1.060j` for
:math:`\nu = 0.3`). The rays are entire functions and carry :math:`r^{0.758}` only through slow
convergence; a plate loaded on a line edge that meets a fixed end (a skin bay beside a moving
line, a stiffener) carries these fields in its response to every load function, even where the
assembled structure has no corner.

The functions added here are exact solutions of the time-harmonic membrane equation (the
Trefftz property is kept) whose static limits span the four static solutions of each degree
:math:`\lambda`. In Wirtinger form, :math:`\partial = (\partial_x - j\partial_y)/2`,
:math:`\bar\partial = (\partial_x + j\partial_y)/2`, :math:`z = x + jy` in the corner's frame,
with :math:`\mathbf u = \nabla\Phi` (longitudinal, :math:`(\Delta + k_L^2)\Phi = 0`) or
:math:`\mathbf u = \nabla\times(\Psi\mathbf e_z)` (shear, :math:`(\Delta + k_S^2)\Psi = 0`) and
the Helmholtz solutions

.. math:: \Gamma(\mu + 1)\Big(\frac2k\Big)^\mu J_\mu(kr)e^{\pm j\mu\theta}
    = \sum_{m\ge0}c_m(k^2)\,z^{\mu_\pm + m}\bar z^{\mu_\mp + m},\qquad
    c_m(k^2) = \frac{(-k^2/4)^m}{m!\,(\mu + 1)_m}

(:math:`\mu_+ = \mu`, :math:`\mu_- = 0`), the four functions of degree :math:`\lambda` are

* :math:`F_1^\pm = \nabla\Phi` with :math:`\mu = \lambda + 1`: static limit
  :math:`\nabla z^{\lambda+1}`, :math:`\nabla\bar z^{\lambda+1}`;
* :math:`F_2^\pm = (\nabla\Phi_L \pm j\,\nabla\times\Psi_S)/(k_S^2 - k_L^2)` with
  :math:`\mu = \lambda - 1` and the same normalisation: for an analytic :math:`h`,
  :math:`\nabla\times h = j\nabla h` (and :math:`-j` for an anti-analytic one), so the
  :math:`m = 0` terms cancel exactly and are left out, and the :math:`m = 1` terms give the
  static solutions of the form :math:`z^\lambda\bar z`, :math:`z\bar z^\lambda`; the longitudinal
  and shear waves enter only through :math:`k_L^{2m}, k_S^{2m}` over
  :math:`k_S^2 - k_L^2 = k_L^2(1 + \nu)/(1 - \nu)`, without cancellation.

Per exponent one function is kept: the combination of the four whose static limit is the
wedge's eigenfunction (fixed on one edge, traction-free on the other; the null vector of the
static 4 x 4 system, which vanishes exactly at the roots above). Every monomial and its
derivatives are :math:`z^p\bar z^q = r^{p+q}e^{j(p-q)\theta}` with :math:`\partial(z^p\bar
z^q) = p\,z^{p-1}\bar z^q`, :math:`\bar\partial(z^p\bar z^q) = q\,z^p\bar z^{q-1}`, and along a
series :math:`p - q` is fixed, so each sum is a polynomial in :math:`r^2` times one power of
:math:`r` and one exponential of :math:`\theta` (the branch cut on the bisector's far side,
outside the plate).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.special

from assembly.geometry import plate_edges
from solver.plate_corners import ORDER_STEP, WedgeFamily, newton_roots, wedge_field

__all__ = ["CORNER_EXPONENT_LIMIT", "CLOSED_FORMS_BEYOND", "fixed_free_exponents",
           "CornerFamily",
           "corner_family", "fixed_free_layout", "fixed_free_corners", "LOGARITHMIC_DEGREES",
           "logarithmic_family", "logarithmic_corners", "loaded_corner_family",
           "loaded_corners", "corner_fields",
           "corner_displacements", "plane_stress_resultants"]

CORNER_EXPONENT_LIMIT = 4.0
r"""Exponents :math:`\lambda` with :math:`0 < \mathrm{Re}\,\lambda <` this get a corner function
(five for :math:`\nu = 0.3`). Measured on ``cases/stiffened_panel.toml`` at 184.8 Hz, the
in-plane change between resolutions 1.25 and 1.875 on the worst plate: 1.8e-1 without corner
functions, 1.1e-1 with the first exponent, 1.2e-2 with three, 7.9e-4 with five
(``docs/method.md`` section 10.5)."""

CLOSED_FORMS_BEYOND = 4.0
r"""Beyond :math:`|k_S|r =` this the corner functions are evaluated in closed form, from
Bessel functions (:func:`solver.plate_corners.wedge_field`), and below it by their series,
whose largest terms are then about :math:`I_0(4) = 11`."""

SERIES_TOLERANCE = 1e-17
"""The series are summed until a term of the largest radius falls below this fraction."""


@functools.lru_cache(maxsize=32)
def fixed_free_exponents(poisson_ratio: float) -> tuple[complex, ...]:
    r"""The roots :math:`\lambda` of :math:`f(\lambda) = 1 + \kappa^2 + 2\kappa\cos(\pi\lambda)
    - 4\lambda^2` with :math:`0 < \mathrm{Re}\,\lambda <` :data:`CORNER_EXPONENT_LIMIT`,
    :math:`\kappa = (3 - \nu)/(1 + \nu)`, by Newton's method from a grid of starts
    (:func:`solver.plate_corners.newton_roots`), sorted by real part (conjugate pairs, negative
    imaginary part first); integer roots (1 and 2 at :math:`\nu = 0`) are left out, their
    fields being polynomials."""
    kappa = (3.0 - poisson_ratio) / (1.0 + poisson_ratio)

    def f(lam: complex) -> complex:
        return 1.0 + kappa**2 + 2.0 * kappa * np.cos(np.pi * lam) - 4.0 * lam**2

    def slope(lam: complex) -> complex:
        return -2.0 * np.pi * kappa * np.sin(np.pi * lam) - 8.0 * lam

    starts = (complex(x, y) for x in np.arange(0.1, CORNER_EXPONENT_LIMIT + 1.0, 0.25)
              for y in (-1.5, -0.5, 0.0, 0.5, 1.5))
    return newton_roots(f, slope, starts, 0.0, CORNER_EXPONENT_LIMIT, 1e-15)


@dataclass(frozen=True)
class _Series:
    r"""Functions :math:`\sum_{m\ge0}(a_m\nabla + b_m\nabla\times)(z^{\alpha+m}\bar
    z^{\beta+m})`, one per row: ``alpha``, ``beta`` (n_functions,), ``gradient``
    (:math:`a_m`), ``curl`` (:math:`b_m`) (n_functions, n_terms)."""

    alpha: np.ndarray
    beta: np.ndarray
    gradient: np.ndarray
    curl: np.ndarray

    @staticmethod
    def stack(series: Sequence[_Series]) -> _Series:
        return _Series(*(np.concatenate([getattr(one, name) for one in series])
                         for name in ("alpha", "beta", "gradient", "curl")))


def _pochhammer(x: complex, n: int) -> complex:
    return math.prod((x + j for j in range(n)), start=1.0 + 0j)


def _wedge_functions(lam: complex, k_long2: complex, k_shear2: complex,
                     n_terms: int) -> _Series:
    r"""The four functions :math:`F_1^+, F_1^-, F_2^+, F_2^-` of degree ``lam`` (module
    notes), their series cut at ``n_terms`` terms."""
    m0 = np.arange(n_terms)
    first = np.array([(-k_long2 / 4.0) ** m / (math.factorial(m) * _pochhammer(lam + 2.0, m))
                      for m in m0])
    m1 = np.arange(1, n_terms + 1)
    common = np.array([(-0.25) ** m / (math.factorial(m) * _pochhammer(lam, m)
                                       * (k_shear2 - k_long2)) for m in m1])
    longitudinal = common * k_long2 ** m1
    shear = 1j * common * k_shear2 ** m1
    none = np.zeros(n_terms, complex)
    # F_2's series start at m = 1: written from m = 0 on z^lam zbar (z zbar^lam), so that every
    # function is r^(lam + 1) times a polynomial in r^2 and no power of r is negative
    return _Series(np.array([lam + 1.0, 0.0, lam, 1.0], complex),
                   np.array([0.0, lam + 1.0, 1.0, lam], complex),
                   np.stack([first, first, longitudinal, longitudinal]),
                   np.stack([none, none, shear, -shear]))


def _local_fields(series: _Series, local: np.ndarray, gradient: bool = True,
                  combinations: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray | None]:
    r"""``u`` (points, 2, n) and, if ``gradient``, :math:`\partial_ju_i` (points, 2, 2, n) of
    the functions of ``series`` (or of their ``combinations``, (functions, n)) at ``local``
    (points, 2), the points in their corner's frame (the plate in the quadrant x, y >= 0).

    Each function is :math:`\nabla f + \nabla\times(g\mathbf e_z)` with
    :math:`f = \sum_m a_m z^{p_m}\bar z^{q_m}`, :math:`g = \sum_m b_m z^{p_m}\bar z^{q_m}`,
    :math:`p_m = \alpha + m`, :math:`q_m = \beta + m`. With
    :math:`\partial_x = \partial + \bar\partial`, :math:`\partial_y = j(\partial -
    \bar\partial)` and :math:`c_\pm = a \pm jb`,

    .. math::
        u_x = X + Y,\quad u_y = j(X - Y),\qquad
        X = \sum_m c_{+,m}\,\partial(z^{p_m}\bar z^{q_m}),\quad
        Y = \sum_m c_{-,m}\,\bar\partial(z^{p_m}\bar z^{q_m}),

    and with :math:`Z = \sum c_+\partial^2`, :math:`\bar Z = \sum c_-\bar\partial^2`,
    :math:`Z_a = 2\sum a\,\partial\bar\partial`, :math:`Z_b = 2\sum b\,\partial\bar\partial`
    of the same monomials,

    .. math::
        \partial_xu_x = Z + \bar Z + Z_a,\quad \partial_yu_y = Z_a - Z - \bar Z,\quad
        \partial_yu_x = j(Z - \bar Z) + Z_b,\quad \partial_xu_y = j(Z - \bar Z) - Z_b.

    Along a series :math:`p - q = \alpha - \beta = d` and :math:`p + q = s + 2m`
    (:math:`s = \alpha + \beta`), so :math:`\partial(z^p\bar z^q) =
    p\,r^{s+2m-1}e^{j(d-1)\theta}`, :math:`\bar\partial(z^p\bar z^q) =
    q\,r^{s+2m-1}e^{j(d+1)\theta}`, and :math:`\partial^2`, :math:`\partial\bar\partial`,
    :math:`\bar\partial^2` give :math:`p(p-1)`, :math:`pq`, :math:`q(q-1)` times
    :math:`r^{s+2m-2}e^{j(d-2)\theta}`, :math:`r^{s+2m-2}e^{jd\theta}`,
    :math:`r^{s+2m-2}e^{j(d+2)\theta}`: each of the six sums is a polynomial in :math:`r^2`
    (one product of the points' powers of :math:`r^2` with every function's coefficients) times
    one power of :math:`r` and one exponential of :math:`\theta`. The combinations, linear,
    are applied to the six sums."""
    radius = np.maximum(np.hypot(local[:, 0], local[:, 1]), np.finfo(float).tiny)
    # the branch cut on the far side of the bisector theta = pi/4, outside the quadrant
    theta = np.angle((local[:, 0] + 1j * local[:, 1]) * np.exp(-0.25j * np.pi)) + 0.25 * np.pi
    a, b = series.gradient, series.curl  # (functions, terms)
    m = np.arange(a.shape[1])
    p, q = series.alpha[:, None] + m, series.beta[:, None] + m
    coefficients = [p * (a + 1j * b), q * (a - 1j * b)]
    if gradient:
        coefficients += [p * (p - 1) * (a + 1j * b), q * (q - 1) * (a - 1j * b),
                         2 * p * q * a, 2 * p * q * b]
    coefficients = np.stack(coefficients).transpose(2, 0, 1)  # (terms, sums, functions)
    n_points, (n_terms, n_sums, n_functions) = len(radius), coefficients.shape
    sums = (((radius**2)[:, None] ** m) @ coefficients.reshape(n_terms, -1)).reshape(
        n_points, n_sums, n_functions)
    # r^(s-1) e^{j(d-1)theta}, r^(s-1) e^{j(d+1)theta}, then r^(s-2) e^{j(d-2)theta},
    # r^(s-2) e^{j(d+2)theta}, r^(s-2) e^{jd theta} (twice); each power of r formed once, as
    # an exponential (at the corner itself r^(s-2) is large but finite, and r^(s-1) vanishes)
    log_r, turn = np.log(radius)[:, None], np.exp(1j * theta)[:, None]
    angle = 1j * theta[:, None] * (series.alpha - series.beta)
    first = np.exp(log_r * (series.alpha + series.beta - 1.0) + angle)
    prefactors = [first / turn, first * turn]
    if gradient:
        second = np.exp(log_r * (series.alpha + series.beta - 2.0) + angle)
        prefactors += [second / turn**2, second * turn**2, second, second]
    sums *= np.stack(prefactors, axis=1)
    if combinations is not None:
        sums = sums @ combinations
    x, y = sums[:, 0], sums[:, 1]
    u = np.stack([x + y, 1j * (x - y)], axis=1)
    if not gradient:
        return u, None
    z, z_bar, z_a, z_b = sums[:, 2], sums[:, 3], sums[:, 4], sums[:, 5]
    pure, mixed = z + z_bar, 1j * (z - z_bar)
    return u, np.stack([np.stack([pure + z_a, mixed + z_b], axis=1),
                        np.stack([mixed - z_b, z_a - pure], axis=1)], axis=1)


def plane_stress_resultants(gradient: np.ndarray, stiffness: complex,
                            poisson_ratio: float) -> np.ndarray:
    r""":math:`\mathbf N = A^*[\nu\,\mathrm{tr}\,\boldsymbol\varepsilon\,\mathbf I
    + (1 - \nu)\boldsymbol\varepsilon]`, :math:`\boldsymbol\varepsilon` the symmetric part of
    ``gradient`` (points, 2, 2, ...)."""
    strain = 0.5 * (gradient + np.swapaxes(gradient, 1, 2))
    trace = strain[:, 0, 0] + strain[:, 1, 1]
    resultants = (1.0 - poisson_ratio) * strain
    resultants[:, 0, 0] += poisson_ratio * trace
    resultants[:, 1, 1] += poisson_ratio * trace
    return stiffness * resultants


def _static_on_edges(lam: complex, fixed_first: bool, poisson_ratio: float
                     ) -> tuple[_Series, np.ndarray, np.ndarray, np.ndarray]:
    r"""The four static functions of degree ``lam`` (the leading terms of
    :func:`_wedge_functions`, whose coefficients do not depend on the wavenumbers:
    :math:`k_S^2/k_L^2 = 2/(1 - \nu)`), a point of the fixed edge and one of the other edge at
    unit distance (the x axis of the corner's frame is the fixed edge if ``fixed_first``), the
    other edge's outward normal, and the functions' displacement at the fixed edge's point
    (2, 4)."""
    leading = _wedge_functions(lam, 1.0, 2.0 / (1.0 - poisson_ratio), 1)
    on_fixed, on_other = np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]])
    normal = np.array([-1.0, 0.0])  # outward on the y axis
    if not fixed_first:
        on_fixed, on_other, normal = on_other, on_fixed, np.array([0.0, -1.0])
    u, _ = _local_fields(leading, on_fixed, gradient=False)
    return leading, on_other, normal, u[0]


@functools.lru_cache(maxsize=256)
def _static_null_vector(lam: complex, fixed_first: bool, poisson_ratio: float) -> np.ndarray:
    r"""The combination of the four static functions of degree ``lam`` that is the wedge's
    eigenfunction: :math:`\mathbf u = 0` on the fixed edge, :math:`\mathbf N\mathbf n = 0` on
    the free one (the x axis of the corner's frame is the fixed edge if ``fixed_first``, else
    the free one), of their static limits (:func:`_static_on_edges`)."""
    leading, on_free, normal, u_fixed = _static_on_edges(lam, fixed_first, poisson_ratio)
    _, gradient = _local_fields(leading, on_free)
    traction = np.einsum("ijn,j->in", plane_stress_resultants(gradient, 1.0, poisson_ratio)[0],
                         normal)
    system = np.vstack([u_fixed, traction])
    _, singular, vh = np.linalg.svd(system)
    if singular[-1] > 1e-9 * singular[0]:
        raise ArithmeticError(f"the static wedge system of exponent {lam} is not singular "
                              f"(singular values {singular}): not a root of the wedge equation")
    null = vh[-1].conj()
    null.flags.writeable = False
    return null


@dataclass(frozen=True)
class CornerFamily:
    r"""The corner functions of one fixed-free corner of a plate.

    Attributes
    ----------
    point : ndarray of float, shape (2,)
        The corner, in the plate's axes.
    frame : ndarray of float, shape (2, 2)
        Columns :math:`\mathbf x', \mathbf y'`: the directions of the corner's two edges away
        from it, right-handed, so that the plate is the quadrant :math:`x', y' \ge 0`.
    functions : _Series
        The four series of each exponent (:func:`_wedge_functions`), exponent after exponent.
    combinations : ndarray of complex, shape (4 n_exponents, n_exponents)
        Column :math:`e`: the static eigenfunction of exponent :math:`e` on its four series.
    exponents, wavenumbers : the exponents :math:`\lambda` and :math:`(k_L, k_S)`
    series_radius : float
        Beyond this distance from the corner the four functions are evaluated in closed form
        (:func:`_closed_fields`), where their series would lose digits to cancellation.
    """

    point: np.ndarray
    frame: np.ndarray
    functions: _Series
    combinations: np.ndarray
    exponents: tuple[complex, ...] = ()
    wavenumbers: tuple[complex, complex] = (0j, 0j)
    series_radius: float = math.inf

    @property
    def n_functions(self) -> int:
        return self.combinations.shape[1]


def _series_length(k_shear: complex, radius: float) -> int:
    r"""Terms for :math:`|c_m|\rho^m \le` :data:`SERIES_TOLERANCE` at :math:`r =` ``radius``
    (a bound of the terms: :math:`(|k_S|r/2)^{2m}/(m!)^2`), at least five."""
    x, term, m = (abs(k_shear) * radius / 2.0) ** 2, 1.0, 0
    while term > SERIES_TOLERANCE or m < 4:
        m += 1
        term *= x / m**2
    return m + 1


def corner_family(point: np.ndarray, fixed_direction: np.ndarray, free_direction: np.ndarray,
                  poisson_ratio: float, k_long: complex, k_shear: complex,
                  radius: float) -> CornerFamily:
    r"""The :class:`CornerFamily` of a right-angle corner at ``point`` whose fixed and free edges
    leave it along ``fixed_direction`` and ``free_direction``, for the exponents of
    :func:`fixed_free_exponents`; ``radius`` bounds the distance from the corner to any point of
    the plate (the series' length)."""
    fixed_first, first, second = _corner_frame(fixed_direction, free_direction)
    exponents = fixed_free_exponents(float(poisson_ratio))
    combinations = np.zeros((4 * len(exponents), len(exponents)), complex)
    for e, lam in enumerate(exponents):
        combinations[4 * e:4 * e + 4, e] = _static_null_vector(lam, fixed_first, poisson_ratio)
    return _family(point, first, second, exponents, combinations, k_long, k_shear, radius)


def _corner_frame(fixed_direction: np.ndarray, other_direction: np.ndarray
                  ) -> tuple[bool, np.ndarray, np.ndarray]:
    """``(fixed_first, first, second)``: whether the fixed edge is the x axis of the corner's
    right-handed frame, and the frame's axes (the plate the quadrant x, y >= 0)."""
    fixed_direction, other_direction = np.asarray(fixed_direction), np.asarray(other_direction)
    turned = np.array([-fixed_direction[1], fixed_direction[0]])
    fixed_first = bool(np.allclose(turned, other_direction))
    return (fixed_first, *((fixed_direction, other_direction) if fixed_first
                           else (other_direction, fixed_direction)))


def _family(point: np.ndarray, first: np.ndarray, second: np.ndarray,
            exponents: Sequence[complex], combinations: np.ndarray, k_long: complex,
            k_shear: complex, radius: float) -> CornerFamily:
    """The :class:`CornerFamily` at ``point``, its frame's columns ``first`` and ``second``,
    of the four series of each of ``exponents`` cut at the distance where their closed forms
    take over (or ``radius``, the farthest point of the plate), combined by
    ``combinations``."""
    series_radius = CLOSED_FORMS_BEYOND / abs(k_shear)
    n_terms = _series_length(k_shear, min(radius, series_radius))
    functions = [_wedge_functions(lam, k_long**2, k_shear**2, n_terms) for lam in exponents]
    return CornerFamily(np.asarray(point, float), np.column_stack([first, second]),
                        _Series.stack(functions), combinations, tuple(exponents),
                        (complex(k_long), complex(k_shear)), series_radius)


LOGARITHMIC_DEGREES = (1.0, 2.0)
r"""The degrees :math:`\lambda` of the in-plane logarithmic family (:func:`logarithmic_family`):
a displacement datum with a kink at a corner gives the membrane :math:`r\ln r` terms, and
their followers :math:`r^2\ln r`; adding degree 3 changed nothing on the L fold
(``docs/method.md`` section 10.4)."""


def logarithmic_family(point: np.ndarray, first: np.ndarray, second: np.ndarray,
                       k_long: complex, k_shear: complex, radius: float) -> CornerFamily:
    r"""The in-plane logarithmic family of a right-angle corner at ``point`` whose edges leave
    it along ``first`` and ``second`` (right-handed): per degree :math:`\lambda` of
    :data:`LOGARITHMIC_DEGREES`, the four functions of :func:`_wedge_functions` differenced in
    the degree, :math:`(F(\lambda + h) - F(\lambda - h))/2h`,
    :math:`h` = :data:`solver.plate_corners.ORDER_STEP`: exact solutions whose static limits
    carry :math:`r^\lambda\ln r` (their values at :math:`\lambda` are polynomials, in the
    rays' span). ``radius`` as for :func:`corner_family`."""
    exponents = [complex(degree + step) for degree in LOGARITHMIC_DEGREES
                 for step in (ORDER_STEP, -ORDER_STEP)]
    combinations = np.zeros((4 * len(exponents), 4 * len(LOGARITHMIC_DEGREES)), complex)
    for d in range(len(LOGARITHMIC_DEGREES)):
        for j in range(4):
            combinations[8 * d + j, 4 * d + j] = 0.5 / ORDER_STEP
            combinations[8 * d + 4 + j, 4 * d + j] = -0.5 / ORDER_STEP
    return _family(point, first, second, exponents, combinations, k_long, k_shear, radius)


def logarithmic_corners(size: tuple[float, float], corners: Sequence[int], k_long: complex,
                        k_shear: complex) -> tuple[CornerFamily, ...]:
    """The :func:`logarithmic_family` of each of a plate's ``corners`` (corner ``c`` joins
    edges ``c - 1`` and ``c``)."""
    edges = plate_edges(size)
    return tuple(logarithmic_family(edges[c].start, edges[c].tangent, -edges[c - 1].tangent,
                                    k_long, k_shear, math.hypot(*size)) for c in corners)


def fixed_free_layout(conditions: Sequence[str]) -> tuple[tuple[int, bool], ...]:
    """The fixed-free corners of a plate whose edges' in-plane conditions are ``conditions``
    (in the order of :data:`assembly.geometry.EDGE_NAMES`): ``(i, incoming_fixed)`` for each
    corner ``i`` (the end of edge ``i - 1``, the start of edge ``i``) where a ``fixed`` edge meets
    a ``free`` one (a free edge, or a line's member edge loaded by the line). Plates of one
    size whose layouts are equal have the same corner functions."""
    return tuple((i, conditions[i - 1] == "fixed") for i in range(4)
                 if {conditions[i - 1], conditions[i]} == {"fixed", "free"})


def fixed_free_corners(size: tuple[float, float], conditions: Sequence[str],
                       poisson_ratio: float, k_long: complex, k_shear: complex
                       ) -> tuple[CornerFamily, ...]:
    """The :class:`CornerFamily` of every corner of :func:`fixed_free_layout`."""
    diagonal = math.hypot(*size)
    edges = plate_edges(size)
    families = []
    for i, incoming_fixed in fixed_free_layout(conditions):
        fixed, free = _corner_edges(edges, i, incoming_fixed)
        families.append(corner_family(edges[i].start, fixed, free, poisson_ratio, k_long,
                                      k_shear, diagonal))
    return tuple(families)


def _corner_edges(edges: Sequence, corner: int, incoming_fixed: bool
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The directions away from ``corner`` (joining edges ``corner - 1`` and ``corner``) of its
    fixed edge and of its other edge; ``incoming_fixed``: edge ``corner - 1`` is the fixed one."""
    along_outgoing, along_incoming = edges[corner].tangent, -edges[corner - 1].tangent
    return ((along_incoming, along_outgoing) if incoming_fixed
            else (along_outgoing, along_incoming))


@functools.lru_cache(maxsize=256)
def _fixed_edge_space(lam: complex, fixed_first: bool, poisson_ratio: float) -> np.ndarray:
    r"""The combinations (4, 2) of the four static functions of degree ``lam`` that vanish on
    the fixed edge (the x axis of the corner's frame if ``fixed_first``, else the y axis),
    their tractions on the other edge left unconstrained: the fields a load
    :math:`r^{\lambda - 1}` on that edge drives (an orthonormal basis of the null space of the
    displacements on the fixed edge, :func:`_static_on_edges`)."""
    *_, u_fixed = _static_on_edges(lam, fixed_first, poisson_ratio)
    _, _, vh = np.linalg.svd(u_fixed)
    space = vh[2:].conj().T
    space.flags.writeable = False
    return space


def loaded_corner_family(point: np.ndarray, fixed_direction: np.ndarray,
                         loaded_direction: np.ndarray, poisson_ratio: float, k_long: complex,
                         k_shear: complex, radius: float,
                         exponents: Sequence[float]) -> CornerFamily:
    r"""The corner functions of degree :math:`\lambda` (each of ``exponents``) of a right-angle
    corner whose fixed edge leaves ``point`` along ``fixed_direction`` and whose other edge,
    along ``loaded_direction``, carries a load :math:`r^{\lambda - 1}` (a moving line's member
    at an end fixed in its plane, :func:`solver.line_ends.held_end_exponents`): two per
    exponent (:func:`_fixed_edge_space`). ``radius`` as for :func:`corner_family`."""
    fixed_first, first, second = _corner_frame(fixed_direction, loaded_direction)
    combinations = np.zeros((4 * len(exponents), 2 * len(exponents)), complex)
    for e, lam in enumerate(exponents):
        combinations[4 * e:4 * e + 4, 2 * e:2 * e + 2] = _fixed_edge_space(
            complex(lam), fixed_first, poisson_ratio)
    return _family(point, first, second, [complex(lam) for lam in exponents], combinations,
                   k_long, k_shear, radius)


def loaded_corners(size: tuple[float, float],
                   corners: Sequence[tuple[int, bool, tuple[float, ...]]], poisson_ratio: float,
                   k_long: complex, k_shear: complex) -> tuple[CornerFamily, ...]:
    """The :func:`loaded_corner_family` of each ``(corner, incoming_fixed, exponents)``
    (corner ``c`` joins edges ``c - 1`` and ``c``; ``incoming_fixed``: edge ``c - 1`` is the
    fixed one)."""
    edges = plate_edges(size)
    return tuple(loaded_corner_family(edges[c].start, *_corner_edges(edges, c, incoming_fixed),
                                      poisson_ratio, k_long, k_shear, math.hypot(*size),
                                      exponents)
                 for c, incoming_fixed, exponents in corners)


def _closed_fields(family: CornerFamily, local: np.ndarray, gradient: bool
                   ) -> tuple[np.ndarray, np.ndarray | None]:
    r"""The four functions of each exponent of ``family`` (those of :func:`_wedge_functions`,
    in its order) in closed form at ``local`` (points, 2), the corner's frame: ``u`` (points,
    2, 4 n) and, if ``gradient``, :math:`\partial_ju_i` (points, 2, 2, 4 n). With
    :math:`P_\pm(\mu, k) = \Gamma(\mu+1)(2/k)^\mu J_\mu(kr)e^{\pm j\mu\theta}`, whose series
    is :math:`\sum_m c_m(k^2)z^{\mu+m}\bar z^m` (or its mirror), and its derivatives from
    :func:`solver.plate_corners.wedge_field`: :math:`F_1^\pm = \nabla P_\pm(\lambda+1, k_L)`
    and :math:`F_2^\pm = (\nabla P_\pm(\lambda-1, k_L) \pm j\nabla\times P_\pm(\lambda-1, k_S))
    / (k_S^2 - k_L^2)`, exactly the sums of their series (the cancelling :math:`m = 0` terms
    included: :math:`\nabla h \pm j\nabla\times h = 0` for those static terms)."""
    k_long, k_shear = family.wavenumbers
    names = ("w_x", "w_y") + (("w_xx", "w_xy", "w_yy") if gradient else ())

    def potentials(orders: list[complex], k: complex) -> dict[str, np.ndarray]:
        """The derivatives ``names`` of :math:`P_+` and :math:`P_-` of each order, side by
        side (points, 2 orders)."""
        functions = tuple((order, reflected, 0) for order in orders for reflected in (False, True))
        values = wedge_field((WedgeFamily((0.0, 0.0), 0.0, functions),), k, local, names)
        scale = np.repeat([np.exp(scipy.special.loggamma(order + 1.0) + order * np.log(2.0 / k))
                           for order in orders], 2)
        return {name.removeprefix("w_"): value * scale for name, value in values.items()}

    def gradient_of(f):  # u = grad f
        u = np.stack([f["x"], f["y"]], axis=1)
        return u, (np.stack([np.stack([f["xx"], f["xy"]], axis=1),
                             np.stack([f["xy"], f["yy"]], axis=1)], axis=1) if gradient else None)

    def curl_of(g):  # u = curl (g e_z)
        u = np.stack([g["y"], -g["x"]], axis=1)
        return u, (np.stack([np.stack([g["xy"], g["yy"]], axis=1),
                             np.stack([-g["xx"], -g["xy"]], axis=1)], axis=1)
                   if gradient else None)

    lams = list(family.exponents)
    u_first, g_first = gradient_of(potentials([lam + 1.0 for lam in lams], k_long))
    u_long, g_long = gradient_of(potentials([lam - 1.0 for lam in lams], k_long))
    u_shear, g_shear = curl_of(potentials([lam - 1.0 for lam in lams], k_shear))
    signs = np.tile([1.0, -1.0], len(lams))  # F_2^+ and F_2^- of each exponent
    u_second = (u_long + 1j * signs * u_shear) / (k_shear**2 - k_long**2)
    # per exponent F_1^+, F_1^-, F_2^+, F_2^-, as the series are stacked
    order = np.concatenate([[2 * e, 2 * e + 1, 2 * len(lams) + 2 * e, 2 * len(lams) + 2 * e + 1]
                            for e in range(len(lams))])
    u = np.concatenate([u_first, u_second], axis=-1)[..., order]
    if not gradient:
        return u, None
    g_second = (g_long + 1j * signs * g_shear) / (k_shear**2 - k_long**2)
    return u, np.concatenate([g_first, g_second], axis=-1)[..., order]


def _frame_fields(family: CornerFamily, local: np.ndarray, gradient: bool
                  ) -> tuple[np.ndarray, np.ndarray | None]:
    """The corner functions of ``family`` at ``local`` (points, 2), in its frame, as
    :func:`_local_fields` gives them: from their series within ``family.series_radius`` of the
    corner, in closed form beyond (:func:`_closed_fields`)."""
    far = np.hypot(local[:, 0], local[:, 1]) > family.series_radius
    if not far.any():
        return _local_fields(family.functions, local, gradient, family.combinations)
    shape = (len(local), 2, family.n_functions)
    u = np.empty(shape, complex)
    derivatives = np.empty(shape[:2] + (2,) + shape[2:], complex) if gradient else None
    near = ~far
    if near.any():
        u[near], near_derivatives = _local_fields(family.functions, local[near], gradient,
                                                  family.combinations)
        if gradient:
            derivatives[near] = near_derivatives
    far_u, far_derivatives = _closed_fields(family, local[far], gradient)
    u[far] = far_u @ family.combinations
    if gradient:
        derivatives[far] = far_derivatives @ family.combinations
    return u, derivatives


def _plate_axes(families: tuple[CornerFamily, ...], points: np.ndarray, gradient: bool
                ) -> tuple[np.ndarray, np.ndarray | None]:
    r"""Displacement (points, 2, n) and, if ``gradient``, :math:`\partial_ju_i`
    (points, 2, 2, n) of the corner functions of ``families`` in the plate's axes, corner by
    corner (:func:`_frame_fields`): for a frame :math:`Q = [\mathbf x'\ \mathbf y']`,
    :math:`\mathbf u = Q\mathbf u'` and :math:`\nabla\mathbf u = Q\nabla'\mathbf u'Q^T`,
    the latter as :math:`(Q\otimes Q)` on the four components."""
    n_functions = [family.n_functions for family in families]
    u = np.empty((len(points), 2, sum(n_functions)), complex)
    derivatives = np.empty((len(points), 4, sum(n_functions)), complex) if gradient else None
    for family, end in zip(families, np.cumsum(n_functions)):
        columns = slice(end - family.n_functions, end)
        frame_u, frame_derivatives = _frame_fields(
            family, (points - family.point) @ family.frame, gradient)
        u[..., columns] = family.frame @ frame_u
        if gradient:
            derivatives[..., columns] = np.kron(family.frame, family.frame) @ (
                frame_derivatives.reshape(len(points), 4, -1))
    return u, None if derivatives is None else derivatives.reshape(len(points), 2, 2, -1)


def corner_fields(families: tuple[CornerFamily, ...], points: np.ndarray, stiffness: complex,
                  poisson_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    r"""Displacement (points, 2, n) and resultants :math:`\mathbf N` (points, 2, 2, n) of the
    corner functions of ``families``, in the plate's axes, at ``points`` (n, 2)."""
    points = np.atleast_2d(np.asarray(points, float))
    if not families:
        return np.zeros((len(points), 2, 0), complex), np.zeros((len(points), 2, 2, 0), complex)
    u, gradient = _plate_axes(families, points, True)
    return u, plane_stress_resultants(gradient, stiffness, poisson_ratio)


def corner_displacements(families: tuple[CornerFamily, ...], points: np.ndarray) -> np.ndarray:
    """The displacements of :func:`corner_fields` alone, (points, 2, n), without the second
    derivatives."""
    points = np.atleast_2d(np.asarray(points, float))
    if not families:
        return np.zeros((len(points), 2, 0), complex)
    return _plate_axes(families, points, False)[0]
