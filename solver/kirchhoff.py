r"""Kirchhoff plate operators in the frequency domain.

Conventions (``docs/method.md`` section 1): time factor
:math:`e^{+j\omega t}`; transverse displacement :math:`w` along the plate's local
:math:`z`; hysteretic bending stiffness

.. math:: D^* = \frac{E h^3 (1 + j\eta)}{12 (1 - \nu^2)} \quad [\mathrm{N\,m}],

plate equation :math:`D^* \Delta^2 w - \rho h \omega^2 w = f`, complex wavenumber
:math:`\kappa^4 = \rho h \omega^2 / D^*` (principal root: :math:`\mathrm{Re}\,\kappa > 0`,
:math:`\mathrm{Im}\,\kappa < 0`).

On an edge of outward normal :math:`n` and tangent :math:`t = e_z \times n`:

.. math::
    M_n = -D^*(w_{nn} + \nu w_{tt}), \qquad
    M_{nt} = -D^*(1 - \nu) w_{nt}, \qquad
    Q_n = -D^* (\Delta w)_{,n}, \qquad
    K_n = Q_n + \partial_s M_{nt} = -D^*(w_{nnn} + (2 - \nu) w_{ntt}).

For an exponential :math:`e^{\mathbf k \cdot \mathbf x}` every derivative is a product of
components of :math:`\mathbf k`, which gives the closed forms of :func:`wave_edge_factors`.
The point-force particular solution is the outgoing infinite-plate Green function
(:func:`point_force_radial`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

__all__ = [
    "complex_bending_stiffness",
    "bending_wavenumber",
    "wave_edge_factors",
    "point_force_radial",
    "point_force_derivatives",
]


def complex_bending_stiffness(young_modulus: float, thickness: float, poisson_ratio: float,
                              loss_factor: float) -> complex:
    r"""Hysteretic bending stiffness :math:`D^* = E h^3 (1 + j\eta) / (12(1-\nu^2))`, N·m."""
    return (
        young_modulus * thickness**3 * (1.0 + 1j * loss_factor) / (12.0 * (1.0 - poisson_ratio**2))
    )


def bending_wavenumber(mass_per_area: float, omega: float, bending_stiffness: complex) -> complex:
    r"""Complex bending wavenumber :math:`\kappa = (\rho h \omega^2 / D^*)^{1/4}`, 1/m.

    The principal fourth root is taken; for :math:`\eta > 0` it has
    :math:`\mathrm{Re}\,\kappa > 0` and :math:`\mathrm{Im}\,\kappa < 0`, so that
    :math:`e^{-j\kappa r}` is an outgoing wave decaying along its path.
    """
    return (mass_per_area * omega**2 / complex(bending_stiffness)) ** 0.25


def wave_edge_factors(k: np.ndarray, normal: ArrayLike, tangent: ArrayLike,
                      bending_stiffness: complex, poisson_ratio: float) -> dict[str, np.ndarray]:
    r"""Edge quantities of exponentials :math:`e^{\mathbf k\cdot\mathbf x}`, per unit amplitude.

    With :math:`k_n = \mathbf k\cdot\mathbf n`, :math:`k_t = \mathbf k\cdot\mathbf t` and
    :math:`k^2 = \mathbf k\cdot\mathbf k` (no conjugation):

    .. math::
        \partial_n w = k_n,\quad
        M_n = -D^*\big[(1-\nu)k_n^2 + \nu k^2\big],\quad
        M_{nt} = -D^*(1-\nu)k_t k_n,\quad
        K_n = -D^*\big[k^2 k_n + (1-\nu)k_t^2 k_n\big],\quad
        \partial_s w = k_t .

    Parameters
    ----------
    k : ndarray of complex, shape (n, 2)
        Wave vectors.
    normal, tangent : array_like, shape (2,)
        Outward unit normal and unit tangent of the edge.
    bending_stiffness : complex
        :math:`D^*`, N·m.
    poisson_ratio : float

    Returns
    -------
    dict of str to ndarray of complex, shape (n,)
        Keys ``"slope"``, ``"moment"``, ``"twist"``, ``"shear"``, ``"tangential"``.
    """
    kn = k @ np.asarray(normal, dtype=float)
    kt = k @ np.asarray(tangent, dtype=float)
    kk = kn * kn + kt * kt
    nu = poisson_ratio
    return {
        "slope": kn,
        "moment": -bending_stiffness * ((1.0 - nu) * kn * kn + nu * kk),
        "twist": -bending_stiffness * (1.0 - nu) * kt * kn,
        "shear": -bending_stiffness * (kk * kn + (1.0 - nu) * kt * kt * kn),
        "tangential": kt,
    }


def point_force_radial(r: ArrayLike, kappa: complex, bending_stiffness: complex,
                       force: complex) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    r"""Radial function and derivatives of the point-force Green function.

    .. math::
        f(r) = A\Big[j H_0^{(2)}(\kappa r) + \tfrac{2}{\pi} K_0(\kappa r)\Big],
        \qquad A = -\frac{F}{8\kappa^2 D^*},

    solution of :math:`D^*\Delta^2 f - \rho h\omega^2 f = F\delta` in the infinite plate,
    outgoing for :math:`e^{+j\omega t}`, with :math:`f(0) = jA` finite.

    Returns
    -------
    f, df, d2f, dlap : ndarray of complex
        :math:`f`, :math:`f'`, :math:`f''` and :math:`(\Delta f)'` at ``r`` (``r > 0``).
    """
    z = kappa * np.asarray(r, dtype=float)
    amplitude = -force / (8.0 * kappa**2 * bending_stiffness)
    h0, h1 = special.hankel2(0, z), special.hankel2(1, z)
    k0, k1 = special.kv(0, z), special.kv(1, z)
    two_pi = 2.0 / np.pi
    f = amplitude * (1j * h0 + two_pi * k0)
    df = -kappa * amplitude * (1j * h1 + two_pi * k1)
    d2f = amplitude * kappa**2 * (-1j * (h0 - h1 / z) + two_pi * (k0 + k1 / z))
    dlap = amplitude * kappa**3 * (1j * h1 - two_pi * k1)
    return f, df, d2f, dlap


def point_force_derivatives(points: ArrayLike, source: ArrayLike, kappa: complex,
                            bending_stiffness: complex, force: complex) -> dict[str, np.ndarray]:
    r"""Displacement, gradient, Hessian and shear force of the point-force field.

    For a radial field :math:`f(r)` with :math:`\mathbf e = (\mathbf x - \mathbf x_0)/r`:
    :math:`w_{,i} = f' e_i`, :math:`w_{,ij} = f'' e_i e_j + (f'/r)(\delta_{ij} - e_i e_j)`,
    :math:`Q_i = -D^* (\Delta f)' e_i`.

    Parameters
    ----------
    points : ndarray of float, shape (n, 2)
        Evaluation points. At the source itself ``w`` is the finite limit and the slope 0;
        the curvatures and shear forces are infinite there.
    source : array_like, shape (2,)

    Returns
    -------
    dict of str to ndarray of complex
        ``"w"`` (n,), ``"grad"`` (n, 2), ``"hess"`` (n, 2, 2), ``"shear_force"`` (n, 2).
    """
    d = np.asarray(points, dtype=float) - np.asarray(source, dtype=float)
    r = np.hypot(d[:, 0], d[:, 1])
    at_source = r == 0.0
    r_safe = np.where(at_source, 1.0, r)
    e = d / r_safe[:, None]
    f, df, d2f, dlap = point_force_radial(r_safe, kappa, bending_stiffness, force)
    ee = e[:, :, None] * e[:, None, :]
    hess = d2f[:, None, None] * ee + (df / r_safe)[:, None, None] * (np.eye(2) - ee)
    if at_source.any():
        # w is finite at the force (f(0) = jA), the slope vanishes by symmetry, and the
        # curvatures and shear are infinite (log and 1/r singularities)
        f = np.where(at_source, -1j * force / (8.0 * kappa**2 * bending_stiffness), f)
        df = np.where(at_source, 0.0, df)
        hess[at_source] = np.inf
    shear = -bending_stiffness * dlap[:, None] * e
    shear[at_source] = np.inf
    return {"w": f, "grad": df[:, None] * e, "hess": hess, "shear_force": shear}
