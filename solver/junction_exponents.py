r"""The exponents of the in-plane field where a moving line ends on edges fixed in their plane
(``docs/method.md`` section 10.4, *Ends held in their plane*), from the static plane-stress
problem of the members' wedges at that end.

A few centimetres from the end the members' bending is far more compliant than their
membranes, so each member is there a quadrant of membrane, fixed on its end edge and tied to
the others along the line only through what membranes carry: the translation along the line
(shared by every member), the skin's continuity where two members continue each other in one
plane, and the balance of the forces. A field homogeneous of degree :math:`\lambda` in the
distance :math:`r` to the end, :math:`\mathbf u \propto r^\lambda`, loads the line like
:math:`r^{\lambda-1}`; the exponents are the :math:`\lambda` for which the homogeneous problem
has a solution.

Each quadrant carries the Kolosov-Muskhelishvili potentials :math:`\varphi = Az^\lambda`,
:math:`\psi = Bz^\lambda` (four real unknowns), in its own polar frame: the line the ray
:math:`\theta = 0`, the end edge :math:`\theta = \pi/2`. Plane stress,
:math:`\kappa = (3 - \nu)/(1 + \nu)`:

* :math:`2G(u_x + ju_y) = \kappa\varphi - z\overline{\varphi'} - \overline\psi`,
  :math:`u_r + ju_\theta = e^{-j\theta}(u_x + ju_y)`;
* :math:`\sigma_{\theta\theta} + j\sigma_{r\theta} = \varphi' + \overline{\varphi'}
  + e^{2j\theta}(\bar z\varphi'' + \psi')`.

The conditions, :math:`h_m` the thicknesses, :math:`G_m` the shear moduli:

* every member, :math:`\theta = \pi/2`: :math:`u_r = u_\theta = 0`;
* along the line, :math:`\theta = 0`: :math:`u_r` the same for every member,
  :math:`\sum_m h_m\sigma_{r\theta,m} = 0`;
* two members that continue each other in one plane (a skin):
  :math:`u_{\theta,1} = -u_{\theta,2}` (each :math:`\theta` turns into its own plate) and
  :math:`h_1\sigma_{\theta\theta,1} = h_2\sigma_{\theta\theta,2}`;
* any other member: :math:`\sigma_{\theta\theta} = 0` (its in-plane normal displacement is
  the others' deflection, which near the end costs nothing).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

__all__ = ["EndMember", "quadrant_columns", "junction_matrix", "junction_exponents",
           "line_loading_exponents"]


@dataclass(frozen=True)
class EndMember:
    """One member of a line at an end fixed in its plane: its thickness (m), shear modulus
    :math:`G` (Pa) and Poisson ratio, and the index of the member continuing it in its plane
    (None if none)."""

    thickness: float
    shear_modulus: float
    poisson_ratio: float
    partner: int | None = None


def quadrant_columns(lam: float, theta: float, poisson_ratio: float
                     ) -> tuple[np.ndarray, np.ndarray]:
    r"""At :math:`r = 1` on the ray ``theta``: :math:`2G(u_r, u_\theta)` and
    :math:`(\sigma_{\theta\theta}, \sigma_{r\theta})` of the four real unknowns
    :math:`(\mathrm{Re}A, \mathrm{Im}A, \mathrm{Re}B, \mathrm{Im}B)`, each (2, 4)."""
    kappa = (3.0 - poisson_ratio) / (1.0 + poisson_ratio)
    z = np.exp(1j * theta)
    displacement, stress = np.zeros((2, 4)), np.zeros((2, 4))
    for column, (a, b) in enumerate(((1.0, 0.0), (1j, 0.0), (0.0, 1.0), (0.0, 1j))):
        phi, d_phi = a * z**lam, a * lam * z ** (lam - 1.0)
        dd_phi = a * lam * (lam - 1.0) * z ** (lam - 2.0)
        psi, d_psi = b * z**lam, b * lam * z ** (lam - 1.0)
        polar = np.exp(-1j * theta) * (kappa * phi - z * np.conj(d_phi) - np.conj(psi))
        traction = d_phi + np.conj(d_phi) + np.exp(2j * theta) * (np.conj(z) * dd_phi + d_psi)
        displacement[:, column] = polar.real, polar.imag
        stress[:, column] = traction.real, traction.imag
    return displacement, stress


def junction_matrix(lam: float, members: tuple[EndMember, ...]) -> np.ndarray:
    """The square real matrix of the conditions (module notes) on the members' unknowns,
    four per member; singular where ``lam`` is an exponent."""
    n = len(members)

    def row(member: int, values: np.ndarray) -> np.ndarray:
        out = np.zeros(4 * n)
        out[4 * member:4 * member + 4] = values
        return out

    on_line = [quadrant_columns(lam, 0.0, m.poisson_ratio) for m in members]
    on_end = [quadrant_columns(lam, 0.5 * np.pi, m.poisson_ratio)[0] for m in members]
    # displacements in metres per unit potential: 2G u over 2G of each member
    u_line = [u / (2.0 * m.shear_modulus) for (u, _), m in zip(on_line, members)]
    rows = [row(i, end[k]) for i, end in enumerate(on_end) for k in range(2)]
    rows += [row(0, u_line[0][0]) - row(i, u_line[i][0]) for i in range(1, n)]
    rows.append(sum(m.thickness * row(i, on_line[i][1][1]) for i, m in enumerate(members)))
    for i, member in enumerate(members):
        partner = member.partner
        if partner is None:
            rows.append(row(i, on_line[i][1][0]))
        elif i < partner:
            rows.append(row(i, u_line[i][1]) + row(partner, u_line[partner][1]))
            rows.append(member.thickness * row(i, on_line[i][1][0])
                        - members[partner].thickness * row(partner, on_line[partner][1][0]))
    matrix = np.array(rows)
    if matrix.shape != (4 * n, 4 * n):
        raise ValueError(f"members {members}: partners must pair up")
    return matrix


def _scaled_determinant(lam: float, members: tuple[EndMember, ...]) -> float:
    matrix = junction_matrix(lam, members)
    return float(np.linalg.det(matrix / np.abs(matrix).max(axis=1, keepdims=True)))


@functools.lru_cache(maxsize=64)
def junction_exponents(members: tuple[EndMember, ...], upper: float = 2.0,
                       samples: int = 800) -> tuple[float, ...]:
    """The real exponents in (0, ``upper``), integers left out (their fields are
    polynomials, in the rays' span): sign changes of the row-scaled determinant on a grid of
    ``samples``, refined by bisection to round-off."""
    grid = np.linspace(1e-3, upper, samples)
    values = [_scaled_determinant(x, members) for x in grid]
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if fa == 0.0 or fa * fb > 0.0:
            continue
        for _ in range(60):
            c = 0.5 * (a + b)
            fc = _scaled_determinant(c, members)
            a, fa, b = (c, fc, b) if fa * fc > 0.0 else (a, fa, c)
        root = 0.5 * (a + b)
        if abs(root - round(root)) > 1e-6:
            roots.append(float(root))
    return tuple(roots)


def _line_tractions(lam: float, members: tuple[EndMember, ...]) -> float:
    r"""How much the mode of exponent ``lam`` loads the line: the largest force per unit
    length :math:`h_m|\sigma_m|` on it over the largest :math:`2G_mh_m|\mathbf u_m|` there, at
    :math:`r = 1` (0 where every member's line edge is free of traction at the leading order,
    as in the L fold of like plates, whose members are two fixed-free corners)."""
    matrix = junction_matrix(lam, members)
    _, _, vh = np.linalg.svd(matrix)
    mode = vh[-1]
    forces, displacements = [], []
    for i, member in enumerate(members):
        u, stress = quadrant_columns(lam, 0.0, member.poisson_ratio)
        part = mode[4 * i:4 * i + 4]
        forces.append(member.thickness * np.abs(stress @ part).max())
        displacements.append(member.thickness * np.abs(u @ part).max())
    return max(forces) / max(displacements)


LOADING_TOLERANCE = 1e-6
"""A mode whose line forces are below this fraction of its displacements (both as in
:func:`_line_tractions`) does not load the line."""


@functools.lru_cache(maxsize=64)
def line_loading_exponents(members: tuple[EndMember, ...], upper: float = 2.0
                           ) -> tuple[float, ...]:
    r"""The exponents of :func:`junction_exponents` below 1 + ``upper`` whose modes load the
    line: its loads go like :math:`r^{\lambda - 1}` there."""
    return tuple(lam for lam in junction_exponents(members, upper)
                 if _line_tractions(lam, members) > LOADING_TOLERANCE)
