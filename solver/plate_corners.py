r"""Corner functions of the bending field where a clamped edge meets a free one
(``docs/method.md`` section 5.5), and the same functions at orders near 2, 3 and 4 for the
logarithmic family of a moving line's mixed ends (:func:`logarithmic_wedges`, section 10.4).

Near such a right-angle corner the static plate's local solutions are :math:`r^\mu F(\theta)`
with the exponents of the clamped-free wedge (Williams, 1952): :math:`\mu = 2.069 \pm 0.439j`,
then 3.464, for :math:`\nu = 0.3` (:func:`clamped_free_exponents`). Their moments go like
:math:`r^{\mu - 2}` and their Kirchhoff shear like :math:`r^{\mu - 3}`, nearly :math:`1/r`; the
rays are entire functions and follow them only slowly (about 1e-3 at 200 rays a plate).

The functions added are exact solutions of :math:`\Delta^2w - \kappa^4w = 0`. With
:math:`z = \kappa r` and :math:`(r, \theta)` polar about the corner, the wedge in
:math:`0\le\theta\le\pi/2`, a plate solution is the sum of a Helmholtz solution,
:math:`(\Delta + \kappa^2)w = 0`, and a modified one, :math:`(\Delta - \kappa^2)w = 0`:

* :math:`J_\nu(z)e^{j\nu\theta}`, bounded;
* :math:`I_\nu(z)e^{j\nu\theta}` grows like :math:`e^{\kappa r}` across the plate (about
  :math:`e^{26}` at 1 kHz across a 0.1 x 0.5 m, 2 mm stiffener), which no combination with the
  rays can cancel in double precision. Its growth is the part
  :math:`F_\nu = \frac1{2\pi}\int_{-\pi}^{\pi}e^{z\cos(\theta - \alpha)}e^{j\nu\alpha}d\alpha`,
  a superposition of evanescent plane waves and so an entire function that carries none of
  the corner's singularity. What is left,

  .. math:: R_\nu(z, \theta) = I_\nu(z)e^{j\nu\theta} - F_\nu
     = \frac{\sin\nu\pi}{\pi}e^{j\nu\theta}\Big[j\int_0^\theta e^{-z\cos s - j\nu s}ds
       - \int_0^\infty e^{-z\cosh t - \nu t}dt\Big],

  (from :math:`I_\nu(z) = \frac1\pi\int_0^\pi e^{z\cos t}\cos\nu t\,dt - \frac{\sin\nu\pi}\pi
  \int_0^\infty e^{-z\cosh t - \nu t}dt`, :math:`\mathrm{Re}\,z > 0`), is bounded for
  :math:`|\theta|\le\pi/2` (:math:`\cos s\ge 0` there), decays like :math:`e^{-z\cos\theta}`,
  solves :math:`(\Delta - \kappa^2)R_\nu = 0` and has the same non-integer powers of
  :math:`r` as :math:`I_\nu e^{j\nu\theta}`; it vanishes for integer :math:`\nu`, and not at
  the corner: :math:`R_\nu(0) = -F_\nu(0) = -\mathrm{sinc}\,\nu`.

Per exponent :math:`\mu` and per orientation (:math:`\theta` and :math:`-\theta`: the
functions of :math:`e^{-j\nu\theta}`), three functions: :math:`J_\mu e^{j\mu\theta}`,
:math:`R_\mu`, whose leading terms are :math:`r^\mu e^{j\mu\theta}`, and
:math:`J_{\mu-2}e^{j(\mu-2)\theta} - R_{\mu-2}`, whose :math:`r^{\mu-2}` terms cancel (those of
:math:`J_\nu` and :math:`I_\nu` are equal) and whose leading term is
:math:`r^\mu e^{j(\mu-2)\theta}`. Together they span the static wedge solutions of degree
:math:`\mu` (:math:`r^\mu e^{\pm j\mu\theta}`, :math:`r^\mu e^{\pm j(\mu-2)\theta}`), each with
a dynamic completion; the variational form picks the combination.

Derivatives follow from the ladders of the Wirtinger operators :math:`\partial = \partial_x +
j\partial_y`, :math:`\bar\partial = \partial_x - j\partial_y`:
:math:`\partial(J_\nu e^{j\nu\theta}) = -\kappa J_{\nu+1}e^{j(\nu+1)\theta}`,
:math:`\bar\partial(J_\nu e^{j\nu\theta}) = \kappa J_{\nu-1}e^{j(\nu-1)\theta}`,
:math:`\partial R_\nu = \kappa R_{\nu+1}`, :math:`\bar\partial R_\nu = \kappa R_{\nu-1}` (as
:math:`I_\nu e^{j\nu\theta}` and every evanescent wave in :math:`F_\nu`); a derivative along a
unit direction :math:`d` (a complex number) is :math:`(\bar d\partial + d\bar\partial)/2`.

Evaluation: for :math:`|z| <` :data:`SERIES_BELOW` by the power series
:math:`J_\nu, I_\nu = \sum_k(\mp1)^k(z/2)^{2k+\nu}/(k!\,\Gamma(k+\nu+1))` (a combination of the
two summed term by term, so that cancelling leading terms cancel exactly) and
:math:`F_\nu = \sum_m\mathrm{sinc}(\nu - m)I_m(z)e^{jm\theta}`; beyond it by Gauss-Legendre
quadrature of the integrals above and of Schläfli's
:math:`J_\nu(z) = \frac1\pi\int_0^\pi\cos(\nu t - z\sin t)dt
- \frac{\sin\nu\pi}\pi\int_0^\infty e^{-z\sinh t - \nu t}dt`, every integrand bounded.
The in-plane corner functions use the same Bessel functions beyond the reach of their own
series (:func:`wedge_field` of :math:`J_\nu` alone, :mod:`solver.membrane_corners`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.special
from numpy.typing import ArrayLike

from assembly.geometry import plate_edges

__all__ = ["CLAMPED_FREE_EXPONENT_LIMIT", "SERIES_BELOW", "clamped_free_exponents",
           "WedgeFamily", "clamped_free_wedges", "ORDER_STEP", "LOGARITHMIC_ORDERS",
           "logarithmic_wedges", "wedge_derivatives", "wedge_field",
           "wedge_edge_traces", "newton_roots"]

CLAMPED_FREE_EXPONENT_LIMIT = 4.0
r"""Exponents :math:`\mu` (:math:`w\sim r^\mu`) with :math:`1 < \mathrm{Re}\,\mu <` this get
functions: :math:`2.069\pm0.439j` and 3.464 for :math:`\nu = 0.3`, 18 functions a corner. On a
0.3 x 0.4 m, 2 mm plate clamped on one edge at 1 kHz the change of ``w`` between resolutions
1 and 2.25 is 3.1e-5 with the first pair, 1.6e-5 with three exponents and 9.6e-6 with five,
and between 2.25 and 3.4 7.8e-7, 1.8e-6 and 1.4e-6 (the rays alone: 5.3e-4 and 3.8e-4)."""

SERIES_BELOW = 4.0
"""Below this :math:`|\\kappa r|` the functions are summed as power series (their largest terms
about :math:`I_0(4) = 11`), above it integrated."""

_SERIES_TERMS = 40
_SUM_ORDERS = 40  # |m| <= this in F_nu's sum: I_m(4) / I_0(4) < 1e-40 beyond
_TAIL = 40.0  # the infinite integrals stop where their exponent has fallen by this


@functools.lru_cache(maxsize=32)
def clamped_free_exponents(poisson_ratio: float) -> tuple[complex, ...]:
    r"""The exponents :math:`\mu` of the right-angle Kirchhoff wedge clamped on one edge and
    free on the other, :math:`1 < \mathrm{Re}\,\mu <` :data:`CLAMPED_FREE_EXPONENT_LIMIT`,
    non-integer, sorted by real part: the roots of :math:`\det A(\mu) = 0` for
    :math:`w = r^\mu F(\theta)`, :math:`F = (\cos\mu\theta, \sin\mu\theta, \cos(\mu-2)\theta,
    \sin(\mu-2)\theta)\cdot c`, with :math:`F(0) = F'(0) = 0` (clamped at :math:`\theta = 0`)
    and, at :math:`\theta = \pi/2`,

    .. math:: F'' + \mu F + \nu\mu(\mu-1)F = 0\ (M_{\theta\theta} = 0),\qquad
        F''' + \mu^2F' + (1-\nu)(\mu-1)(\mu-2)F' = 0\ (V_\theta = 0),

    by Newton's method from a grid of starts (:func:`newton_roots`). At :math:`\mu = 1` and 2 the four functions are
    not independent and the determinant vanishes for every wedge: those roots are dropped with
    the other integers (polynomial fields, which the rays carry)."""
    def det(mu: complex) -> complex:
        return complex(np.linalg.det(_wedge_conditions(mu, poisson_ratio)))

    def slope(mu: complex, h: float = 1e-6) -> complex:
        return (det(mu + h) - det(mu - h)) / (2 * h)

    starts = (complex(x, y) for x in np.arange(1.1, CLAMPED_FREE_EXPONENT_LIMIT + 1.0, 0.2)
              for y in (-1.0, -0.4, 0.0, 0.4, 1.0))
    return newton_roots(det, slope, starts, 1.0, CLAMPED_FREE_EXPONENT_LIMIT, 1e-14)


def newton_roots(f: Callable[[complex], complex], derivative: Callable[[complex], complex],
                 starts: Iterable[complex], lower: float, upper: float,
                 tolerance: float) -> tuple[complex, ...]:
    """The distinct roots of the analytic ``f`` with ``lower < Re < upper``, not integers (the
    wedge exponents whose fields are polynomials, which the rays carry), by Newton's method
    from each of ``starts`` until a step falls below ``tolerance`` times the root (a start whose
    step grows past 10 is given up); sorted by real part, then imaginary, a negligible
    imaginary part dropped."""
    roots: list[complex] = []
    for start in starts:
        x = start
        for _ in range(100):
            step = f(x) / derivative(x)
            x -= step
            if not abs(step) < 10.0 or abs(step) < tolerance * max(1.0, abs(x)):
                break
        if (abs(step) < 1e-10 and lower < x.real < upper and abs(x - round(x.real)) > 1e-6
                and all(abs(x - r) > 1e-7 for r in roots)):
            roots.append(complex(x.real, 0.0 if abs(x.imag) < 1e-10 else x.imag))
    return tuple(sorted(roots, key=lambda r: (round(r.real, 8), r.imag)))


def _wedge_conditions(mu: complex, poisson_ratio: float) -> np.ndarray:
    """The 4 x 4 matrix of :func:`clamped_free_exponents`: rows clamped (two) and free (two),
    columns the four angular functions."""
    nu, edge = poisson_ratio, math.pi / 2
    rows = np.zeros((4, 4), complex)
    for column, (order, sine) in enumerate(((mu, False), (mu, True), (mu - 2, False),
                                            (mu - 2, True))):
        def derivative(n: int, theta: float) -> complex:
            # n-th derivative of cos(order t) or sin(order t)
            phase = order * theta + (n * math.pi / 2) - (math.pi / 2 if sine else 0.0)
            return order**n * np.cos(phase)
        f0, f1, f2, f3 = (derivative(n, edge) for n in range(4))
        rows[:, column] = (derivative(0, 0.0), derivative(1, 0.0),
                           f2 + mu * f0 + nu * mu * (mu - 1) * f0,
                           f3 + mu**2 * f1 + (1 - nu) * (mu - 1) * (mu - 2) * f1)
    return rows


@dataclass(frozen=True)
class WedgeFamily:
    r"""The corner functions of one corner (clamped-free, or a logarithmic family): the corner
    ``point`` and the angle
    ``angle`` of the edge from which :math:`\theta` is measured (the plate lies in
    :math:`0\le\theta\le\pi/2` of it), and per function ``(mu, reflected, kind)``: kind 0
    :math:`J_\mu e^{j\mu\theta}`, 1 :math:`R_\mu`, 2 :math:`J_{\mu-2}e^{j(\mu-2)\theta} -
    R_{\mu-2}`, of :math:`-\theta` when ``reflected``."""

    point: tuple[float, float]
    angle: float
    functions: tuple[tuple[complex, bool, int], ...]

    def __len__(self) -> int:
        return len(self.functions)


def clamped_free_wedges(size: Sequence[float], kinds: Sequence[str],
                        poisson_ratio: float) -> tuple[WedgeFamily, ...]:
    """The wedge families of a plate's corners where a ``clamped`` edge meets a ``free`` one,
    ``kinds`` the four edges' bending conditions in the order of
    :data:`assembly.geometry.EDGE_NAMES` (corner ``c`` joins edges ``c - 1`` and ``c``)."""
    edges = plate_edges(size)
    exponents = clamped_free_exponents(poisson_ratio)
    functions = tuple((mu, reflected, kind) for mu in exponents
                      for reflected in (False, True) for kind in range(3))
    families = []
    for c in range(4):
        if {kinds[c - 1], kinds[c]} == {"clamped", "free"}:
            outgoing = edges[c].tangent  # the plate lies to its left, over a right angle
            families.append(WedgeFamily(tuple(map(float, edges[c].start)),
                                        math.atan2(outgoing[1], outgoing[0]), functions))
    return tuple(families)


ORDER_STEP = 1e-3
r"""Half the distance :math:`h` between the two orders :math:`\mu\pm h` that stand for the
derivative in the order, :math:`\partial_\mu f = (f(\mu + h) - f(\mu - h))/2h + O(h^2)`, of
a logarithmic family (:func:`logarithmic_wedges`, and the in-plane one of
:func:`solver.membrane_corners.logarithmic_family`); the difference loses three of sixteen
digits."""

LOGARITHMIC_ORDERS = (2.0, 3.0, 4.0)
r"""The integer orders :math:`\mu` of the bending logarithmic family (``docs/method.md``
section 10.4): a log-singular edge load on a plate carries :math:`r^\mu\ln r` terms from
:math:`\mu = 2` on (shear :math:`\sim\ln r` gives :math:`r^3\ln r`, moment :math:`r^2\ln
r`). Adding :math:`\mu = 1` spoils the solve (changes of order 1 on the L fold)."""


def logarithmic_wedges(point: Sequence[float], direction: Sequence[float]) -> WedgeFamily:
    r"""The bending logarithmic family of a right-angle corner at ``point``, the plate to the
    left of ``direction`` (the edge leaving the corner): the functions of
    :class:`WedgeFamily` of every kind and orientation at the orders :math:`\mu\pm h`,
    :math:`\mu` in :data:`LOGARITHMIC_ORDERS`, :math:`h` = :data:`ORDER_STEP`. Both orders
    are kept, so their span holds :math:`f(\mu)` and :math:`\partial_\mu f`, whose static
    limits carry :math:`r^\mu\ln r`: exact, bounded plate solutions for a corner where a
    moving line's log-singular loads meet a supported end (``docs/method.md`` section 10.4)."""
    functions = tuple((mu + step, reflected, kind) for mu in LOGARITHMIC_ORDERS
                      for step in (-ORDER_STEP, ORDER_STEP)
                      for reflected in (False, True) for kind in range(3))
    return WedgeFamily(tuple(map(float, point)), math.atan2(direction[1], direction[0]),
                       functions)


def _gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w  # on [0, 1]


Request = tuple[float, float, complex, int]
r"""A value wanted of :func:`_values`: :math:`\alpha J_\nu e^{j\nu\theta} + \beta R_\nu` at
the angles ``sign * theta``, as ``(alpha, beta, nu, sign)``."""

_CHUNK = 2000  # points at a time: the series terms are (points, terms, orders) arrays


def _series_values(z: np.ndarray, theta: np.ndarray, requests: Sequence[Request]) -> np.ndarray:
    r"""The ``requests`` by power series, (len(z), len(requests)); each combination is summed
    term by term, so that leading terms that cancel cancel exactly."""
    orders = np.array(sorted({request[2] for request in requests}, key=lambda o: (o.real, o.imag)))
    index = {order: i for i, order in enumerate(orders)}
    k = np.arange(_SERIES_TERMS)
    m = np.arange(-_SUM_ORDERS, _SUM_ORDERS + 1)
    # terms[p, k, o] = (z/2)^(2k + nu) / (k! Gamma(k + nu + 1))
    log_half = np.log(0.5 * z)
    terms = (np.exp(np.outer(log_half, orders))[:, None, :]
             * np.exp(np.outer(2 * log_half, k))[:, :, None]) * (
        scipy.special.rgamma(k + 1.0)[None, :, None]
        * scipy.special.rgamma(k[:, None] + orders[None, :] + 1.0)[None])
    bessel_i = scipy.special.iv(m[None, :], z[:, None])
    weights = np.sinc(orders[None, :] - m[:, None]) + 0j
    sums = {sign: (bessel_i * np.exp(1j * sign * m * theta[:, None])) @ weights
            for sign in (1, -1)}  # F_nu = sum_m sinc(nu - m) I_m(z) e^{j m theta}
    out = np.empty((len(z), len(requests)), complex)
    groups: dict[tuple[float, float, int], list[int]] = {}
    for column, (alpha, beta, _, sign) in enumerate(requests):
        groups.setdefault((alpha, beta, sign), []).append(column)
    for (alpha, beta, sign), members in groups.items():
        o = [index[requests[column][2]] for column in members]
        powers = np.einsum("pko,k->po", terms[:, :, o], alpha * (-1.0) ** k + beta + 0j)
        out[:, members] = np.exp(1j * sign * np.outer(theta, orders[o])) * powers \
            - beta * sums[sign][:, o]
    return out


def _integral_values(z: np.ndarray, theta: np.ndarray,
                     requests: Sequence[Request]) -> np.ndarray:
    r"""The ``requests`` by Gauss-Legendre quadrature of the integral forms of :math:`J_\nu` and
    :math:`R_\nu` (module docstring), (len(z), len(requests)); every integrand is bounded. The
    infinite integrals stop where their exponent has fallen by :data:`_TAIL`."""
    bessel_orders = sorted({r[2] for r in requests if r[0]}, key=lambda o: (o.real, o.imag))
    remainders = sorted({(r[2], r[3]) for r in requests if r[1]},
                        key=lambda k: (k[0].real, k[0].imag, k[1]))
    n = max(32, math.ceil(float(np.abs(z).max(initial=0.0))) + 24)
    x, weights = _gauss(n)
    weights = weights + 0j  # a complex array times a real one would not go to BLAS
    bessel = {}
    if bessel_orders:
        orders = np.array(bessel_orders)
        angles = math.pi * x
        sine = np.sin(angles)
        # (1/pi) int_0^pi cos(nu t - z sin t) dt, both exponentials of the cosine at once
        first = 0.5 * (np.exp(-1j * z[:, None] * sine) @ (
            weights[:, None] * np.exp(1j * np.outer(angles, orders)))
            + np.exp(1j * z[:, None] * sine) @ (
                weights[:, None] * np.exp(-1j * np.outer(angles, orders))))
        end = np.arcsinh(_TAIL / z.real + 1.0)
        t = end[:, None] * x
        tail = _shifted_sums(-z[:, None] * np.sinh(t), t, orders, weights) * end[:, None]
        values = first - np.sin(np.pi * orders) / np.pi * tail
        bessel = {order: values[:, i] for i, order in enumerate(bessel_orders)}
    remainder = {}
    if remainders:
        end = np.arccosh(_TAIL / z.real + 1.0)
        t = end[:, None] * x
        cosh_exponent = -z[:, None] * np.cosh(t)
        for sign in (1, -1):
            keys = [key for key in remainders if key[1] == sign]
            if not keys:
                continue
            orders = np.array([key[0] for key in keys])
            angle = sign * theta
            s = angle[:, None] * x
            arc = _shifted_sums(-z[:, None] * np.cos(s), 1j * s, orders, weights)
            tail = _shifted_sums(cosh_exponent, t, orders, weights) * end[:, None]
            values = (np.sin(np.pi * orders) / np.pi * np.exp(1j * np.outer(angle, orders))
                      * (1j * arc * angle[:, None] - tail))
            remainder |= {key: values[:, i] for i, key in enumerate(keys)}
    out = np.empty((len(z), len(requests)), complex)
    for column, (alpha, beta, order, sign) in enumerate(requests):
        value = 0.0
        if alpha:
            value = alpha * bessel[order] * np.exp(1j * order * sign * theta)
        if beta:
            value = value + beta * remainder[order, sign]
        out[:, column] = value
    return out


def _shifted_sums(exponent: np.ndarray, rate: np.ndarray, orders: np.ndarray,
                  weights: np.ndarray) -> np.ndarray:
    r""":math:`\sum_n w_n\exp(e_{pn} - \nu_o c_{pn})` for every point ``p`` and order ``o``,
    (points, orders), with ``exponent`` :math:`e` and ``rate`` :math:`c` (points, nodes). The
    orders of one exponent differ by integers, :math:`\nu = \nu_0 + d`: one exponential per
    :math:`\nu_0`, times integer powers of :math:`e^{-c}`."""
    shifts = np.floor(orders.real).astype(int)
    bases = np.round(orders - shifts, 12)
    step = np.exp(-rate)
    out = np.empty((len(exponent), len(orders)), complex)
    for base in np.unique(bases):
        members = np.flatnonzero(bases == base)
        anchor = int(shifts[members].min())
        current = _exp(exponent - (base + anchor) * rate)
        power = anchor
        for i in members[np.argsort(shifts[members])]:
            while power < shifts[i]:
                current = current * step
                power += 1
            out[:, i] = current @ weights
    return out


def _exp(exponent: np.ndarray) -> np.ndarray:
    """``exp``, its argument's real part held above -600: what falls below is negligible, and
    subnormal results would slow every later operation on them manyfold."""
    return np.exp(np.maximum(exponent.real, -600.0) + 1j * exponent.imag)


def _values(z: np.ndarray, theta: np.ndarray, r: np.ndarray,
            requests: Sequence[Request]) -> np.ndarray:
    r"""The ``requests`` at every point, (len(z), len(requests)): by series below
    :data:`SERIES_BELOW`, by quadrature above, and their limits at the corner itself, where
    the powers of r vanish and :math:`F_\nu` is :math:`\mathrm{sinc}\,\nu` (:math:`I_m(0) = 0`
    for :math:`m \ne 0`)."""
    out = np.empty((len(z), len(requests)), complex)
    corner = r == 0
    if corner.any():
        betas, orders = np.array([(r[1], r[2]) for r in requests]).T
        out[corner] = -betas * np.sinc(orders)
    small = ~corner & (np.abs(z) < SERIES_BELOW)
    for start in range(0, len(z), _CHUNK):
        chunk = np.zeros(len(z), bool)
        chunk[start:start + _CHUNK] = True
        for part, values in ((chunk & small, _series_values),
                             (chunk & ~corner & ~small, _integral_values)):
            if part.any():
                out[part] = values(z[part], theta[part], requests)
    return out


def wedge_derivatives(family: WedgeFamily, kappa: complex, points: np.ndarray,
                      max_order: int = 3) -> dict[tuple[int, int], np.ndarray]:
    r""":math:`\partial^a\bar\partial^b` of every function of ``family`` at ``points``
    (plate frame, (n, 2)) for :math:`a + b\le` ``max_order``, in the wedge's frame (rotated by
    ``family.angle``): ``{(a, b): (n, len(family))}``.

    Of :math:`\Phi = \alpha J_\nu e^{j\nu\theta} + \beta R_\nu`,
    :math:`\partial^a\bar\partial^b\Phi = \kappa^{a+b}[(-1)^a\alpha J_{\nu'}e^{j\nu'\theta} +
    \beta R_{\nu'}]`, :math:`\nu' = \nu + a - b`; a reflected function
    :math:`\Phi(r, -\theta)` swaps :math:`a` and :math:`b`. At the corner itself
    (:math:`r = 0`) the values are the limits of ``w``, its slopes and its moments (the only
    quantities used there): the powers of :math:`r` vanish (:math:`\mathrm{Re}\,\mu > 2`;
    the logarithmic family's order :math:`2 - 10^{-3}` gives moments like
    :math:`r^{-10^{-3}}`, 1.03 at :math:`r = 10^{-12}`, whose power is dropped there too), and
    :math:`F_\nu` leaves :math:`\beta\,\mathrm{sinc}\,\nu'` (``R`` does not vanish at
    the corner: its entire part :math:`-F_\nu` does not)."""
    local = (np.asarray(points, float) - family.point) @ np.array(
        [[math.cos(family.angle), -math.sin(family.angle)],
         [math.sin(family.angle), math.cos(family.angle)]])
    r = np.hypot(local[:, 0], local[:, 1])
    theta = np.arctan2(local[:, 1], local[:, 0])
    coefficients = {0: (1.0, 0.0, 0), 1: (0.0, 1.0, 0), 2: (1.0, -1.0, -2)}
    requests: dict[Request, int] = {}
    columns = {}
    for n in range(max_order + 1):
        for a in range(n + 1):
            b = n - a
            wanted = []
            for mu, reflected, kind in family.functions:
                alpha, beta, shift = coefficients[kind]
                first, second = (b, a) if reflected else (a, b)
                request = ((-1.0) ** first * alpha, beta, mu + shift + first - second,
                           -1 if reflected else 1)
                wanted.append(requests.setdefault(request, len(requests)))
            columns[a, b] = wanted
    values = _values(kappa * r, theta, r, list(requests))
    return {(a, b): kappa ** (a + b) * values[:, wanted] for (a, b), wanted in columns.items()}


def _directional(direction: complex) -> dict[tuple[int, int], complex]:
    r"""The derivative along a unit ``direction`` (complex), :math:`(\bar d\partial +
    d\bar\partial)/2`, as ``{(a, b): coefficient}``."""
    return {(1, 0): 0.5 * np.conj(direction), (0, 1): 0.5 * direction}


def _product(*operators: dict) -> dict[tuple[int, int], complex]:
    out = {(0, 0): 1.0 + 0j}
    for operator in operators:
        step: dict[tuple[int, int], complex] = {}
        for (a, b), c in out.items():
            for (e, f), g in operator.items():
                step[a + e, b + f] = step.get((a + e, b + f), 0.0) + c * g
        out = step
    return out


def _apply(operator: dict, derivatives: dict) -> np.ndarray:
    """``operator`` applied: its coefficients are numbers, or one per point (n,)."""
    return sum(np.reshape(c, (-1, 1)) * derivatives[key] for key, c in operator.items())


def _local_direction(family: WedgeFamily, vector: np.ndarray) -> np.ndarray:
    """Unit vectors (n, 2) of the plate's frame as complex numbers in the wedge's frame."""
    return (vector[:, 0] + 1j * vector[:, 1]) * complex(math.cos(family.angle),
                                                        -math.sin(family.angle))


def wedge_edge_traces(families: Sequence[WedgeFamily], kappa: complex,
                      bending_stiffness: complex, poisson_ratio: float, points: np.ndarray,
                      normal: ArrayLike, tangent: ArrayLike,
                      keys: Sequence[str]) -> dict[str, np.ndarray]:
    r"""Edge quantities of the corner functions at ``points`` on edges (``normal``,
    ``tangent``: one unit vector (2,), or one per point (n, 2)), any of ``w``, ``slope`` (:math:`\partial_nw`), ``tangential``
    (:math:`\partial_sw`), ``moment`` (:math:`M_n = -D^*(w_{nn} + \nu w_{tt})`), ``twist``
    (:math:`M_{nt} = -D^*(1-\nu)w_{nt}`), ``shear`` (:math:`K_n = -D^*(w_{nnn} +
    (2-\nu)w_{ntt})`), ``shear_q`` (:math:`Q_n = -D^*(w_{nnn} + w_{ntt})`): each
    (len(points), total functions), families side by side."""
    d, nu = bending_stiffness, poisson_ratio
    points = np.asarray(points, float)
    normal = np.broadcast_to(np.asarray(normal, float), points.shape)
    tangent = np.broadcast_to(np.asarray(tangent, float), points.shape)
    columns: dict[str, list[np.ndarray]] = {key: [] for key in keys}
    order = 3 if {"shear", "shear_q"} & set(keys) else 2
    for family in families:
        n = _directional(_local_direction(family, normal))
        t = _directional(_local_direction(family, tangent))
        derivatives = wedge_derivatives(family, kappa, points, order)
        operators = {"w": {(0, 0): 1.0}, "slope": n, "tangential": t}

        def value(key: str) -> np.ndarray:
            if key in operators:
                return _apply(operators[key], derivatives)
            if key == "moment":
                return -d * (_apply(_product(n, n), derivatives)
                             + nu * _apply(_product(t, t), derivatives))
            if key == "twist":
                return -d * (1 - nu) * _apply(_product(n, t), derivatives)
            across = _apply(_product(n, n, n), derivatives)
            along = _apply(_product(n, t, t), derivatives)
            return -d * (across + ((2 - nu) if key == "shear" else 1.0) * along)

        for key in keys:
            columns[key].append(value(key))
    return {key: np.hstack(value) for key, value in columns.items()}


def wedge_field(families: Sequence[WedgeFamily], kappa: complex, points: np.ndarray,
                quantities: Sequence[str] = ("w",)) -> dict[str, np.ndarray]:
    """``w`` and its derivatives in the plate's frame (``w_x, w_y, w_xx, w_xy, w_yy``) of the
    corner functions at ``points``: each (len(points), total functions)."""
    columns: dict[str, list[np.ndarray]] = {q: [] for q in quantities}
    order = max(len(q) - 2 if q != "w" else 0 for q in quantities)
    for family in families:
        derivatives = wedge_derivatives(family, kappa, points, order)
        rotation = complex(math.cos(family.angle), -math.sin(family.angle))
        for q in quantities:
            # the plate's x and y directions in the wedge's frame
            operator = {(0, 0): 1.0} if q == "w" else _product(*(
                _directional(rotation * (1.0 if axis == "x" else 1j)) for axis in q[2:]))
            columns[q].append(_apply(operator, derivatives))
    return {q: np.hstack(v) for q, v in columns.items()}
