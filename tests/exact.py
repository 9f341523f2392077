"""Exact series reference solutions for vibrating Kirchhoff plates and Levy plate chains.

This module is deliberately independent of the ``solver``, ``assembly`` and ``updating``
packages: it only uses numpy and re-derives everything from the public conventions.

Conventions
-----------
Time dependence ``exp(+j omega t)``.  A plate has the complex hysteretic rigidity
``D* = E h^3 (1 + j eta) / (12 (1 - nu^2))`` and the mass per area ``rho_h``; the transverse
deflection ``w`` obeys, for a load ``f`` per area along ``+w``,

    D* (w_xxxx + 2 w_xxyy + w_yyyy) - rho_h omega^2 w = f.

Each plate occupies its local rectangle ``[0, Lx] x [0, Ly]``.  On an edge with outward
normal ``n`` and tangent ``t``

    theta = dw/dn,   M_n = -D* (w_nn + nu w_tt),   K_n = -D* (w_nnn + (2 - nu) w_ntt),

so on the right edge (``n = +x``) ``M_n = -D*(w_xx + nu w_yy)``,
``K_n = -D*(w_xxx + (2 - nu) w_xyy)`` and on the left edge (``n = -x``)
``M_n = -D*(w_xx + nu w_yy)``, ``K_n = +D*(w_xxx + (2 - nu) w_xyy)``, ``theta = -w_x``.
An ``edge_shear`` load of amplitude ``p`` prescribes ``K_n = p`` and an ``edge_moment``
load prescribes ``M_n = m``; the virtual work of the edge loads is
``int (K_n v - M_n dv/dn) ds``.

Boundary conditions: clamped (``w = 0``, ``theta = 0``), simply supported (``w = 0``,
``M_n = m``), free (``M_n = m``, ``K_n = p``), with ``m``, ``p`` the prescribed edge loads
(zero when absent).

A joint links the ``right`` edge of plate A to the ``left`` edge of plate B, with
``k* = k (1 + j zeta)`` and ``Theta = theta_A + theta_B``:

* coplanar: ``w_A = w_B``, ``M_n^A = M_n^B = k* Theta``, ``K_n^A + K_n^B = omega^2 mu w``;
* hinge: ``w_A = w_B = 0``, ``M_n^A = M_n^B = k* Theta``.

Methods
-------
``navier_point_force`` is the double sine series of a plate simply supported on its four
edges.  ``levy_plate`` and ``levy_chain`` expand the response of plates simply supported
on ``y = 0`` and ``y = Ly`` in ``sin(alpha_m y)``, ``alpha_m = m pi / Ly``, and solve the
ordinary differential equation of each harmonic exactly (see ``levy_chain``).

Public API
----------
complex_rigidity, navier_point_force, default_n_terms,
Section, Joint, coplanar, hinge, EdgeLoad, levy_plate, levy_chain,
LevySolution, LevyPlateField.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "complex_rigidity",
    "navier_point_force",
    "default_n_terms",
    "Section",
    "Joint",
    "coplanar",
    "hinge",
    "EdgeLoad",
    "levy_plate",
    "levy_chain",
    "LevySolution",
    "LevyPlateField",
]

BOUNDARY_CONDITIONS = ("clamped", "simply_supported", "free")
EDGES = ("left", "right")
LOAD_KINDS = ("edge_shear", "edge_moment")
DISTRIBUTIONS = ("uniform", "half_sine")

# Number of points evaluated at once (points x harmonics complex arrays stay ~ 30 MB).
_CHUNK_ENTRIES = 2_000_000
# Gauss-Legendre nodes per panel of the energy quadrature.
_GAUSS_NODES = 16


def complex_rigidity(E, h, nu, eta):
    """Complex hysteretic bending rigidity.

    Parameters
    ----------
    E, h, nu, eta : float
        Young's modulus (Pa), thickness (m), Poisson ratio, loss factor.

    Returns
    -------
    complex
        ``D* = E h^3 (1 + j eta) / (12 (1 - nu^2))``.
    """
    return E * h**3 * (1.0 + 1j * eta) / (12.0 * (1.0 - nu**2))


# --------------------------------------------------------------------------------------
# Navier series
# --------------------------------------------------------------------------------------


def navier_point_force(Lx, Ly, D, rho_h, omega, x0, y0, F, x, y, n_terms=1000):
    """Deflection of a plate simply supported on its four edges under a point force.

    With ``alpha_m = m pi / Lx`` and ``beta_n = n pi / Ly``,

        w(x, y) = 4 F / (Lx Ly) sum_{m,n=1}^{n_terms}
                  sin(alpha_m x0) sin(beta_n y0) sin(alpha_m x) sin(beta_n y)
                  / (D* (alpha_m^2 + beta_n^2)^2 - rho_h omega^2).

    The terms decay like ``(m^2 + n^2)^-2``; away from the force the oscillating sines
    make the truncated sum converge much faster than at the drive point.  With the
    default ``n_terms = 1000`` the relative error at points a few millimetres away from
    the force on a decimetre plate is below ``1e-8``.

    Parameters
    ----------
    Lx, Ly : float
        Plate dimensions (m).
    D : complex
        Complex rigidity ``D*``.
    rho_h : float
        Mass per area (kg/m^2).
    omega : float
        Angular frequency (rad/s).
    x0, y0, F : float
        Force position (m) and amplitude (N, along ``+w``).
    x, y : array_like
        Evaluation points (broadcast together).
    n_terms : int
        Number of terms in each direction.

    Returns
    -------
    numpy.ndarray
        Complex deflection, shape of ``broadcast(x, y)``.
    """
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    idx = np.arange(1, n_terms + 1)
    alpha = idx * np.pi / Lx
    beta = idx * np.pi / Ly
    denom = D * (alpha[:, None] ** 2 + beta[None, :] ** 2) ** 2 - rho_h * omega**2
    coef = (4.0 * F / (Lx * Ly)) * np.outer(np.sin(alpha * x0), np.sin(beta * y0)) / denom
    xf, yf = x.ravel(), y.ravel()
    out = np.empty(xf.size, complex)
    step = max(1, _CHUNK_ENTRIES // n_terms)
    for start in range(0, xf.size, step):
        sl = slice(start, start + step)
        sx = np.sin(np.outer(xf[sl], alpha))
        sy = np.sin(np.outer(yf[sl], beta))
        out[sl] = np.sum((sx @ coef) * sy, axis=1)
    return out.reshape(x.shape)


# --------------------------------------------------------------------------------------
# Levy problem description
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Section:
    """One plate of a Levy chain.

    Attributes
    ----------
    Lx : float
        Length along ``x`` (m); the plate occupies local ``[0, Lx] x [0, Ly]``.
    D : complex
        Complex rigidity ``D*`` (see ``complex_rigidity``).
    nu : float
        Poisson ratio.
    rho_h : float
        Mass per area (kg/m^2).
    """

    Lx: float
    D: complex
    nu: float
    rho_h: float


@dataclass(frozen=True)
class Joint:
    """Joint between the right edge of plate ``i`` and the left edge of plate ``i + 1``.

    Attributes
    ----------
    kind : {'coplanar', 'hinge'}
        Joint law (see the module docstring).
    k : float
        Rotational stiffness (N m / rad / m).
    zeta : float
        Loss factor of the stiffness, ``k* = k (1 + j zeta)``.
    mu : float
        Line mass (kg/m) of a coplanar joint; must be 0 for a hinge.
    """

    kind: str
    k: float
    zeta: float = 0.0
    mu: float = 0.0

    def __post_init__(self):
        if self.kind not in ("coplanar", "hinge"):
            raise ValueError(f"unknown joint kind {self.kind!r}")
        if self.kind == "hinge" and self.mu != 0.0:
            raise ValueError("a hinge joint has a fixed line: its line mass must be 0")

    @property
    def k_star(self):
        """Complex stiffness ``k (1 + j zeta)``."""
        return self.k * (1.0 + 1j * self.zeta)


def coplanar(k, zeta=0.0, mu=0.0):
    """Coplanar joint: ``w_A = w_B``, ``M_A = M_B = k* Theta``, ``K_A + K_B = omega^2 mu w``."""
    return Joint("coplanar", k, zeta, mu)


def hinge(k, zeta=0.0):
    """Hinge joint (fold line fixed): ``w_A = w_B = 0``, ``M_A = M_B = k* Theta``."""
    return Joint("hinge", k, zeta)


@dataclass(frozen=True)
class EdgeLoad:
    """Line load on an outer ``left`` or ``right`` edge.

    Attributes
    ----------
    edge : {'left', 'right'}
        Outer left edge of the first plate or outer right edge of the last plate.
    kind : {'edge_shear', 'edge_moment'}
        Prescribes ``K_n`` (free edges only) or ``M_n`` (free or simply supported edges).
    amplitude : complex
        ``p`` (N/m) or ``m`` (N m/m).
    distribution : {'uniform', 'half_sine'}
        ``amplitude`` or ``amplitude * sin(pi y / Ly)`` along the edge.
    """

    edge: str
    kind: str
    amplitude: complex
    distribution: str = "uniform"

    def __post_init__(self):
        if self.edge not in EDGES:
            raise ValueError(f"edge loads are on 'left' or 'right', not {self.edge!r}")
        if self.kind not in LOAD_KINDS:
            raise ValueError(f"unknown edge load kind {self.kind!r}")
        if self.distribution not in DISTRIBUTIONS:
            raise ValueError(f"unknown distribution {self.distribution!r}")

    def harmonics(self, m):
        """Sine coefficients ``c_m`` with ``load(y) = sum_m c_m sin(m pi y / Ly)``.

        ``uniform``: ``c_m = 2 a (1 - (-1)^m) / (m pi)``; ``half_sine``: ``c_m = a [m == 1]``.
        """
        m = np.asarray(m)
        if self.distribution == "half_sine":
            return np.where(m == 1, self.amplitude, 0.0) + 0j
        return self.amplitude * 2.0 * (1.0 - (-1.0) ** m) / (m * np.pi) + 0j


def default_n_terms(Ly, kappa, needs_many):
    """Number of Levy harmonics used when ``n_terms`` is not given.

    Rule: if every load is a ``half_sine`` edge load only harmonic 1 is loaded and the
    single harmonic is exact, so 1 is returned.  Otherwise ``max(1000, 20 |kappa| Ly / pi)``
    harmonics, i.e. at least up to ``alpha_m = 20 |kappa|``.  Beyond ``alpha ~ kappa`` the
    harmonic responses decay algebraically: ``alpha^-3`` for a point force (truncation
    error of ``w`` below ``~1e-6`` relative even on the force line), ``alpha^-4`` for a
    uniform edge shear and ``alpha^-3`` for a uniform edge moment.

    Parameters
    ----------
    Ly : float
        Width of the chain (m).
    kappa : float
        Largest ``|kappa|`` of the plates, ``kappa^4 = rho_h omega^2 / D*``.
    needs_many : bool
        Whether a point force or a uniform edge load is present.
    """
    if not needs_many:
        return 1
    return int(max(1000, np.ceil(20.0 * kappa * Ly / np.pi)))


# --------------------------------------------------------------------------------------
# One-dimensional building blocks of a harmonic
# --------------------------------------------------------------------------------------


def _basis(s1, s2, xi, k):
    """k-th xi-derivative of the decaying basis pair of one harmonic.

    The pair is ``phi_1 = exp(-s2 xi)`` and ``phi_2 = (exp(-s1 xi) - exp(-s2 xi)) / (s1 - s2)``
    (a divided difference: it stays well conditioned when ``s1 -> s2`` at high harmonics).
    With ``g_k = ((-s1)^k - (-s2)^k) / (s1 - s2)``,

        phi_1^(k) = (-s2)^k exp(-s2 xi),   phi_2^(k) = (-s1)^k phi_2 + g_k exp(-s2 xi).

    Parameters
    ----------
    s1, s2 : numpy.ndarray
        Roots (broadcastable with ``xi``), ``Re s >= 0``.
    xi : numpy.ndarray
        Distance from the reference edge (>= 0).
    k : int
        Derivative order, 0..3.

    Returns
    -------
    tuple of numpy.ndarray
        ``(phi_1^(k), phi_2^(k))``.
    """
    d = s1 - s2
    e2 = np.exp(-s2 * xi)
    z = d * xi
    small = np.abs(z) < 1.0
    # exp(-s1 xi) - exp(-s2 xi) = exp(-s2 xi) expm1(-d xi): no cancellation when d xi is small.
    h = np.where(small, e2 * np.expm1(-np.where(small, z, 0.0)), np.exp(-s1 * xi) - e2) / d
    g = (0.0, -1.0, s1 + s2, -(s1 * s1 + s1 * s2 + s2 * s2))[k]
    return (-s2) ** k * e2, (-s1) ** k * h + g * e2


def _green_coefficients(D, s1, s2):
    """Coefficients of the infinite-strip Green function in the basis of ``_basis``.

    ``G(r) = [exp(-s2 r) / s2 - exp(-s1 r) / s1] / (4 D kappa^2)``, ``r = |x - x0|``, solves
    ``D (G'''' - 2 alpha^2 G'' + alpha^4 G) - rho_h omega^2 G = delta(x - x0)``
    (``G'(0) = 0``, jump of ``G'''`` equal to ``1/D``).  Using ``s1^2 - s2^2 = 2 kappa^2``,

        G = [phi_1 / (s1 s2) - phi_2 / s1] / (2 D (s1 + s2)).
    """
    c = 1.0 / (2.0 * D * (s1 + s2))
    return c / (s1 * s2), -c / s1


def _graded_breakpoints(a, b, h0, hcap):
    """Panel ends on ``[a, b]``, geometrically graded (ratio 2) from both ends.

    Panels start at ``h0`` next to ``a`` and ``b``, double until ``hcap`` and stay at
    ``hcap`` in between: this resolves both the boundary layers ``exp(-alpha |x - a|)`` of
    high harmonics and the waves of the low ones.
    """
    half = 0.5 * (b - a)
    dist = [0.0]
    step = h0
    while dist[-1] + step < half:
        dist.append(dist[-1] + step)
        step = min(2.0 * step, hcap)
    dist = np.array(dist)
    return np.unique(np.concatenate([a + dist, [a + half], b - dist]))


# --------------------------------------------------------------------------------------
# Solution objects
# --------------------------------------------------------------------------------------



class LevyPlateField:
    """Response of one plate of a Levy solution, ``w = sum_m W_m(x) sin(alpha_m y)``.

    Per harmonic, with the basis pair ``phi_1, phi_2`` decaying away from the left
    (``xi = x``) or the right (``xi = Lx - x``) edge and the point forces ``f`` of the plate,

        W_m(x) = a_1 phi_1(x) + a_2 phi_2(x) + b_1 phi_1(Lx - x) + b_2 phi_2(Lx - x)
                 + sum_f q_{f,m} G_m(|x - x0_f|),    q_{f,m} = 2 F_f sin(alpha_m y0_f) / Ly,

    ``phi_1 = exp(-s2 xi)``, ``phi_2 = (exp(-s1 xi) - exp(-s2 xi)) / (s1 - s2)`` and ``G_m``
    the infinite-strip Green function of the harmonic.  Instances are created by
    ``levy_chain``; the evaluators broadcast ``x`` (local, in ``[0, Lx]``) with ``y`` (in
    ``[0, Ly]``) and return complex arrays.

    Attributes
    ----------
    section : Section
    Ly, omega : float
    alpha : numpy.ndarray
        Harmonic wavenumbers ``m pi / Ly``, ``m = 1..n_terms``.
    s1, s2 : numpy.ndarray
        Roots ``sqrt(alpha^2 + kappa^2)`` and ``sqrt(alpha^2 - kappa^2)`` (principal
        branch, ``Re s >= 0``), ``kappa^2 = sqrt(rho_h omega^2 / D*)``.
    coefficients : numpy.ndarray
        ``(n_terms, 4)`` array of ``(a_1, a_2, b_1, b_2)``.
    forces : list of (float, numpy.ndarray)
        ``(x0_f, q_{f,m})`` of the point forces of this plate.
    """

    def __init__(self, section, Ly, omega, alpha, forces):
        self.section = section
        self.Ly = Ly
        self.omega = omega
        self.alpha = alpha
        kappa2 = np.sqrt(section.rho_h * omega**2 / section.D + 0j)
        self.s1 = np.sqrt(alpha**2 + kappa2)
        self.s2 = np.sqrt(alpha**2 - kappa2)
        self.forces = forces
        self.coefficients = np.zeros((alpha.size, 4), complex)
        self._green = _green_coefficients(section.D, self.s1, self.s2)

    def homogeneous_basis(self, x, k):
        """k-th x-derivative of the four basis functions, shape ``(len(x), n_terms, 4)``."""
        x = np.asarray(x, float)[:, None]
        pl1, pl2 = _basis(self.s1, self.s2, x, k)
        pr1, pr2 = _basis(self.s1, self.s2, self.section.Lx - x, k)
        sign = (-1.0) ** k
        return np.stack([pl1, pl2, sign * pr1, sign * pr2], axis=-1)

    def particular(self, x, k):
        """k-th x-derivative of the point-force part, shape ``(len(x), n_terms)``.

        ``d^k/dx^k G(|x - x0|) = sign(x - x0)^k G^(k)(|x - x0|)``; at ``x = x0`` the odd
        derivatives are the mean of both sides.
        """
        x = np.asarray(x, float)[:, None]
        g1, g2 = self._green
        out = np.zeros((x.shape[0], self.alpha.size), complex)
        for x0, q in self.forces:
            p1, p2 = _basis(self.s1, self.s2, np.abs(x - x0), k)
            out += q * np.sign(x - x0) ** k * (g1 * p1 + g2 * p2)
        return out

    def harmonic_derivative(self, x, k):
        """``d^k W_m / dx^k`` (``k = 0..3``) at the points ``x``, shape ``(len(x), n_terms)``."""
        return (np.einsum("pmj,mj->pm", self.homogeneous_basis(x, k), self.coefficients)
                + self.particular(x, k))

    def derivative(self, x, y, nx=0, ny=0):
        """Partial derivative ``d^(nx+ny) w / dx^nx dy^ny`` (``nx <= 3``, any ``ny``).

        ``sum_m W_m^(nx)(x) alpha_m^ny sin(alpha_m y + ny pi / 2)``.
        """
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        L = self.section.Lx
        if np.any(x < -1e-12 * L) or np.any(x > L * (1 + 1e-12)):
            raise ValueError("x outside the plate [0, Lx]")
        xf, yf = x.ravel(), y.ravel()
        out = np.empty(xf.size, complex)
        step = max(1, _CHUNK_ENTRIES // (4 * self.alpha.size))
        for start in range(0, xf.size, step):
            sl = slice(start, start + step)
            ydep = self.alpha**ny * np.sin(np.outer(yf[sl], self.alpha) + ny * np.pi / 2)
            out[sl] = np.sum(self.harmonic_derivative(xf[sl], nx) * ydep, axis=1)
        return out.reshape(x.shape)

    def w(self, x, y):
        """Deflection ``w(x, y)``."""
        return self.derivative(x, y)

    def edge_position(self, edge):
        """``(x, n_x)`` of ``edge``: ``(0, -1)`` for 'left', ``(Lx, +1)`` for 'right'."""
        if edge not in EDGES:
            raise ValueError(f"edge must be 'left' or 'right', not {edge!r}")
        return (0.0, -1.0) if edge == "left" else (self.section.Lx, 1.0)

    def edge_slope(self, edge, y):
        """Normal slope ``theta = dw/dn = n_x w_x`` on ``edge`` at ``y``."""
        x, n = self.edge_position(edge)
        return n * self.derivative(x, y, 1, 0)

    def edge_moment(self, edge, y):
        """Bending moment ``M_n = -D* (w_xx + nu w_yy)`` on ``edge`` at ``y``."""
        x, _ = self.edge_position(edge)
        sec = self.section
        return -sec.D * (self.derivative(x, y, 2, 0) + sec.nu * self.derivative(x, y, 0, 2))

    def edge_shear(self, edge, y):
        """Kirchhoff shear ``K_n = -n_x D* (w_xxx + (2 - nu) w_xyy)`` on ``edge`` at ``y``."""
        x, n = self.edge_position(edge)
        sec = self.section
        return -n * sec.D * (self.derivative(x, y, 3, 0)
                             + (2 - sec.nu) * self.derivative(x, y, 1, 2))

    def bending_form(self):
        """Real bending form ``a(w, w*) / D*`` of the plate.

        ``int [|w_xx|^2 + |w_yy|^2 + 2 nu Re(w_xx conj(w_yy)) + 2 (1 - nu) |w_xy|^2] dA``
        ``= Ly/2 sum_m int_0^Lx [|W''|^2 + alpha^4 |W|^2 - 2 nu alpha^2 Re(W'' conj(W))
        + 2 (1 - nu) alpha^2 |W'|^2] dx``.

        The ``x`` integrals use composite 16-point Gauss-Legendre quadrature on panels
        graded (ratio 2) towards the edges and the force positions, from ``1/(4 max|s|)``
        up to ``2/|kappa|``: the boundary layers of the high harmonics and the waves of the
        low ones are both resolved to ~1e-13 relative.
        """
        sec = self.section
        kappa = np.abs(sec.rho_h * self.omega**2 / sec.D) ** 0.25
        h0 = 0.25 / np.max(np.abs(self.s1))
        hcap = min(2.0 / kappa, sec.Lx)
        cuts = np.unique([0.0, sec.Lx] + [x0 for x0, _ in self.forces])
        ends = np.unique(np.concatenate(
            [_graded_breakpoints(a, b, h0, hcap) for a, b in zip(cuts[:-1], cuts[1:])]))
        t, wt = np.polynomial.legendre.leggauss(_GAUSS_NODES)
        mid, half = 0.5 * (ends[1:] + ends[:-1]), 0.5 * np.diff(ends)
        nodes = (mid[:, None] + half[:, None] * t).ravel()
        weights = (half[:, None] * wt).ravel()
        a2 = self.alpha**2
        total = 0.0
        step = max(1, _CHUNK_ENTRIES // (4 * self.alpha.size))
        for start in range(0, nodes.size, step):
            sl = slice(start, start + step)
            W0, W1, W2 = (self.harmonic_derivative(nodes[sl], k) for k in range(3))
            density = (np.abs(W2) ** 2 + a2**2 * np.abs(W0) ** 2
                       - 2 * sec.nu * a2 * np.real(W2 * np.conj(W0))
                       + 2 * (1 - sec.nu) * a2 * np.abs(W1) ** 2)
            total += weights[sl] @ density.sum(axis=1)
        return 0.5 * self.Ly * total

    def dissipated_power(self):
        """Time-averaged power dissipated in the plate, ``0.5 omega Im(D*) a(w, w*)/D*``.

        ``Im(D*) = eta D`` with ``D`` the real rigidity.
        """
        return 0.5 * self.omega * self.section.D.imag * self.bending_form()

    def edge_maps(self, edge):
        """Affine maps from ``(a_1, a_2, b_1, b_2)`` to the edge quantities of each harmonic.

        Returns ``{'w', 'theta', 'M', 'K'} -> (n_terms, 5)`` arrays: columns 0..3 multiply
        the coefficients, column 4 is the point-force contribution.  With ``W^(k)`` at the
        edge and ``n = n_x``::

            w = W,  theta = n W',  M = -D* (W'' - nu alpha^2 W),
            K = -n D* (W''' - (2 - nu) alpha^2 W').
        """
        x, n = self.edge_position(edge)
        W = [np.concatenate([self.homogeneous_basis([x], k)[0],
                             self.particular([x], k)[0][:, None]], axis=1)
             for k in range(4)]
        a2 = (self.alpha**2)[:, None]
        D, nu = self.section.D, self.section.nu
        return {
            "w": W[0],
            "theta": n * W[1],
            "M": -D * (W[2] - nu * a2 * W[0]),
            "K": -n * D * (W[3] - (2 - nu) * a2 * W[1]),
        }


class LevySolution:
    """Levy solution of a plate or of a chain of plates (returned by ``levy_chain``).

    Attributes
    ----------
    plates : list of LevyPlateField
        Per-plate fields, in local coordinates.
    joints : list of Joint
    edge_loads : list of EdgeLoad
    point_forces : list of (int, float, float, complex)
        ``(plate, x0, y0, F)``.
    n_terms : int
        Number of harmonics.
    """

    def __init__(self, plates, joints, edge_loads, point_forces):
        self.plates = plates
        self.joints = joints
        self.edge_loads = edge_loads
        self.point_forces = point_forces
        self.n_terms = plates[0].alpha.size

    def w(self, x, y, plate=0):
        """Deflection of plate ``plate`` at the local point ``(x, y)``."""
        return self.plates[plate].w(x, y)

    def joint_dissipated_power(self, j):
        """Power dissipated by joint ``j``, ``0.5 omega k zeta int |theta_A + theta_B|^2 dy``.

        ``int |Theta|^2 dy = Ly/2 sum_m |W_A'(L_A) - W_B'(0)|^2``.
        """
        a, b = self.plates[j], self.plates[j + 1]
        theta = a.harmonic_derivative([a.section.Lx], 1)[0] - b.harmonic_derivative([0.0], 1)[0]
        integral = 0.5 * a.Ly * np.sum(np.abs(theta) ** 2)
        return 0.5 * a.omega * self.joints[j].k_star.imag * integral

    def dissipated_power(self):
        """Total dissipated power of the plates and the joints."""
        return (sum(p.dissipated_power() for p in self.plates)
                + sum(self.joint_dissipated_power(j) for j in range(len(self.joints))))

    def input_power(self):
        """Time-averaged power injected by the loads.

        ``0.5 omega Im[sum_f F_f conj(w(x0_f, y0_f)) + int (p conj(w) - m conj(theta)) ds]``,
        i.e. ``0.5 Re[conj(F) j omega w(x0)]`` per force.  The edge integrals are the exact
        sums ``Ly/2 sum_m c_m conj(.)_m``; the force terms use the same truncated series,
        so the balance with ``dissipated_power`` holds whatever ``n_terms``.
        """
        total = 0j
        for i, x0, y0, F in self.point_forces:
            total += F * np.conj(self.plates[i].w(x0, y0))
        for load in self.edge_loads:
            plate = self.plates[0] if load.edge == "left" else self.plates[-1]
            coef = load.harmonics(np.arange(1, self.n_terms + 1))
            maps = plate.edge_maps(load.edge)
            full = np.concatenate([plate.coefficients, np.ones((self.n_terms, 1))], axis=1)
            if load.kind == "edge_shear":
                total += 0.5 * plate.Ly * np.sum(coef * np.conj(np.sum(maps["w"] * full, 1)))
            else:
                total -= 0.5 * plate.Ly * np.sum(coef * np.conj(np.sum(maps["theta"] * full, 1)))
        return 0.5 * self.plates[0].omega * total.imag


# --------------------------------------------------------------------------------------
# Solvers
# --------------------------------------------------------------------------------------


def levy_chain(sections, Ly, omega, joints=(), left="simply_supported",
               right="simply_supported", point_forces=(), edge_loads=(), n_terms=None):
    """Levy solution of a chain of plates along ``x``, simply supported on ``y = 0, Ly``.

    Plate ``i`` (``Section`` ``i``) occupies its local ``[0, Lx_i] x [0, Ly]``; joint ``i``
    links the right edge of plate ``i`` to the left edge of plate ``i + 1``.  The response is
    ``w_i = sum_m W_{i,m}(x) sin(alpha_m y)``, ``alpha_m = m pi / Ly``.  Each ``W_{i,m}``
    solves

        D_i (W'''' - 2 alpha^2 W'' + alpha^4 W) - rho_h_i omega^2 W
            = sum_f q_{f,m} delta(x - x0_f),      q_{f,m} = 2 F_f sin(alpha_m y0_f) / Ly,

    whose homogeneous solutions are ``exp(-/+ s x)`` with ``(s^2 - alpha^2)^2 = kappa^4``,
    i.e. ``s^2 = alpha^2 +/- kappa^2``.  Per harmonic the ``4 N`` coefficients of the
    edge-referenced decaying exponentials (see ``LevyPlateField``) follow from 2 conditions
    per outer edge and 4 per joint, solved as a row-equilibrated ``4N x 4N`` system; edge
    loads enter through their sine coefficients (``EdgeLoad.harmonics``).

    Parameters
    ----------
    sections : sequence of Section
        The ``N`` plates, from left to right.
    Ly : float
        Common width (m).
    omega : float
        Angular frequency (rad/s), > 0.
    joints : sequence of Joint
        ``N - 1`` joints (``coplanar`` or ``hinge``).
    left, right : {'clamped', 'simply_supported', 'free'}
        Conditions of the outer left edge of plate 0 and outer right edge of plate N-1.
    point_forces : sequence of (int, float, float, complex)
        ``(plate, x0, y0, F)``, local coordinates with ``0 < x0 < Lx`` (forces on an edge
        line must be given as edge loads).
    edge_loads : sequence of EdgeLoad
        Loads on the outer edges; ``edge_shear`` on free edges only, ``edge_moment`` on
        free or simply supported edges.
    n_terms : int, optional
        Number of harmonics; ``default_n_terms`` when omitted.

    Returns
    -------
    LevySolution

    Notes
    -----
    The Green function contains ``1/s2``: a harmonic exactly at the strip cut-on
    ``alpha_m = kappa`` is singular, which cannot happen with damping (``Im D* > 0``).
    """
    sections = list(sections)
    joints = list(joints)
    edge_loads = list(edge_loads)
    point_forces = [(int(i), float(x0), float(y0), F) for i, x0, y0, F in point_forces]
    n = len(sections)
    if len(joints) != n - 1:
        raise ValueError(f"{n} plates need {n - 1} joints, got {len(joints)}")
    bcs = {"left": left, "right": right}
    for bc in bcs.values():
        if bc not in BOUNDARY_CONDITIONS:
            raise ValueError(f"unknown boundary condition {bc!r}")
    for load in edge_loads:
        bc = bcs[load.edge]
        if load.kind == "edge_shear" and bc != "free":
            raise ValueError(f"edge_shear on a {bc} edge")
        if load.kind == "edge_moment" and bc == "clamped":
            raise ValueError("edge_moment on a clamped edge")
    for i, x0, y0, _ in point_forces:
        if not (0.0 < x0 < sections[i].Lx and 0.0 <= y0 <= Ly):
            raise ValueError(f"point force ({x0}, {y0}) not inside plate {i}")

    if n_terms is None:
        kappa = max(abs(s.rho_h * omega**2 / s.D) ** 0.25 for s in sections)
        needs_many = bool(point_forces) or any(
            load.distribution == "uniform" for load in edge_loads)
        n_terms = default_n_terms(Ly, kappa, needs_many)
    m = np.arange(1, n_terms + 1)
    alpha = m * np.pi / Ly

    plates = []
    for i, sec in enumerate(sections):
        forces = [(x0, 2.0 * F * np.sin(alpha * y0) / Ly)
                  for j, x0, y0, F in point_forces if j == i]
        plates.append(LevyPlateField(sec, Ly, omega, alpha, forces))

    maps = {(i, e): plates[i].edge_maps(e) for i in range(n) for e in EDGES}
    zero = np.zeros(n_terms, complex)

    def equation(terms, value=zero):
        """Row of ``sum coef * quantity(plate, edge) = value`` -> (row, rhs)."""
        row = np.zeros((n_terms, 4 * n), complex)
        rhs = np.array(value, complex)
        for coef, i, edge, quantity in terms:
            q = maps[(i, edge)][quantity]
            row[:, 4 * i:4 * i + 4] += coef * q[:, :4]
            rhs = rhs - coef * q[:, 4]
        return row, rhs

    def load_harmonics(edge, kind):
        return sum((load.harmonics(m) for load in edge_loads
                    if load.edge == edge and load.kind == kind), zero)

    equations = []
    for edge, plate in (("left", 0), ("right", n - 1)):
        moment = load_harmonics(edge, "edge_moment")
        shear = load_harmonics(edge, "edge_shear")
        conditions = {
            "clamped": [("w", zero), ("theta", zero)],
            "simply_supported": [("w", zero), ("M", moment)],
            "free": [("M", moment), ("K", shear)],
        }[bcs[edge]]
        equations += [equation([(1.0, plate, edge, q)], value) for q, value in conditions]
    for j, joint in enumerate(joints):
        a, b = (j, "right"), (j + 1, "left")
        ks = joint.k_star
        equations.append(equation([(1.0, *a, "M"), (-1.0, *b, "M")]))
        equations.append(equation([(1.0, *a, "M"), (-ks, *a, "theta"), (-ks, *b, "theta")]))
        if joint.kind == "coplanar":
            equations.append(equation([(1.0, *a, "w"), (-1.0, *b, "w")]))
            equations.append(equation([(1.0, *a, "K"), (1.0, *b, "K"),
                                       (-omega**2 * joint.mu, *a, "w")]))
        else:
            equations.append(equation([(1.0, *a, "w")]))
            equations.append(equation([(1.0, *b, "w")]))

    matrix = np.stack([row for row, _ in equations], axis=1)
    rhs = np.stack([r for _, r in equations], axis=1)
    scale = np.max(np.abs(matrix), axis=2)
    coefficients = np.linalg.solve(matrix / scale[:, :, None], (rhs / scale)[:, :, None])[..., 0]
    for i, plate in enumerate(plates):
        plate.coefficients = coefficients[:, 4 * i:4 * i + 4]
    return LevySolution(plates, joints, edge_loads, point_forces)


def levy_plate(Lx, Ly, D, nu, rho_h, omega, left="simply_supported",
               right="simply_supported", point_forces=(), edge_loads=(), n_terms=None):
    """Levy solution of one plate simply supported on ``y = 0`` and ``y = Ly``.

    Thin wrapper of ``levy_chain`` with a single ``Section(Lx, D, nu, rho_h)``.

    Parameters
    ----------
    Lx, Ly : float
        Dimensions (m).
    D : complex
        Complex rigidity ``D*``.
    nu, rho_h, omega : float
        Poisson ratio, mass per area (kg/m^2), angular frequency (rad/s).
    left, right : {'clamped', 'simply_supported', 'free'}
        Conditions on ``x = 0`` and ``x = Lx``.
    point_forces : sequence of (float, float, complex)
        ``(x0, y0, F)`` with ``0 < x0 < Lx``.
    edge_loads : sequence of EdgeLoad
        Loads on the ``left`` / ``right`` edges.
    n_terms : int, optional
        Number of harmonics (``default_n_terms`` when omitted).

    Returns
    -------
    LevySolution
        ``.w(x, y)`` evaluates the deflection; ``.plates[0]`` is the ``LevyPlateField``.
    """
    return levy_chain([Section(Lx, D, nu, rho_h)], Ly, omega, (), left, right,
                      [(0, x0, y0, F) for x0, y0, F in point_forces], edge_loads, n_terms)
