r"""The exponents of the in-plane field where a moving line ends on an edge fixed in its plane
(``docs/method.md`` section 10.4, *Ends held in their plane*), from the static plane-stress
problem of the members' wedges near that end, written apart from the solver.

At a few centimetres from the end the members' bending is far more compliant than their
membranes, so near the end each member is a quadrant of membrane: fixed on its end edge, and on
its line edge tied to the others only through what the membranes carry: the translation along
the line (shared by all), the skin's continuity across a line that carries it on both sides,
and the balance of the forces along the line and in each member's plane. A field homogeneous of
degree :math:`\lambda` in the distance to the end, :math:`\mathbf u \propto r^\lambda`, loads
the line like :math:`r^{\lambda-1}`; the exponents are the :math:`\lambda` for which the
homogeneous problem has a solution.

Each quadrant carries the Kolosov-Muskhelishvili potentials :math:`\varphi = Az^\lambda`,
:math:`\psi = Bz^\lambda` (:math:`A, B` complex: four real unknowns), in its own polar frame:
the line edge the ray :math:`\theta = 0`, the fixed end edge :math:`\theta = \pi/2`. Plane
stress, :math:`\kappa = (3 - \nu)/(1 + \nu)`:

* :math:`2G(u_x + ju_y) = \kappa\varphi - z\overline{\varphi'} - \overline\psi`,
  :math:`u_r + ju_\theta = e^{-j\theta}(u_x + ju_y)`;
* :math:`\sigma_{\theta\theta} + j\sigma_{r\theta} = \varphi' + \overline{\varphi'}
  + e^{2j\theta}(\bar z\varphi'' + \psi')`.

The conditions (real rows, :math:`\lambda` real), with :math:`h_m` the thicknesses:

* every member, :math:`\theta = \pi/2`: :math:`u_r = u_\theta = 0`;
* along the line, :math:`\theta = 0`: :math:`u_r` the same for every member,
  :math:`\sum_m h_m\sigma_{r\theta,m} = 0`;
* a member across which the skin continues (``"skin"``, two of them, on either side):
  :math:`u_{\theta,1} = -u_{\theta,2}` and :math:`h_1\sigma_{\theta\theta,1} =
  h_2\sigma_{\theta\theta,2}`;
* any other member (``"free"``: its in-plane normal is another member's deflection):
  :math:`\sigma_{\theta\theta} = 0`.

Checks (run the module): a single quadrant free on its line edge gives the fixed-free corner's
0.758 of section 10.5 (:math:`\nu = 0.3`), the root of the Williams equation to six digits; the
L fold of two equal plates has 0.758 too (its symmetric mode is two such corners); a stiffener
far thinner than the skin has its exponents tending to 1, no singularity (0.993 and 1.007 at a
thousandth of the skin's thickness: the skin's own edge is straight and fixed, and the
stiffener's line edge then a shear diaphragm, a mirror). ``python
bench/junction_exponents.py`` prints them and the exponents of the shapes of
``tests/test_moving_lines.py`` and ``cases/stiffened_panel.toml``.
"""

from __future__ import annotations

import numpy as np

POISSON = 0.3


def quadrant_columns(lam: float, theta: float, poisson: float = POISSON
                     ) -> tuple[np.ndarray, np.ndarray]:
    """At :math:`r = 1` on the ray ``theta``: ``(u_r, u_theta)`` (times :math:`2G`) and
    ``(sigma_thetatheta, sigma_rtheta)`` of the four real unknowns ``(Re A, Im A, Re B,
    Im B)``, each a (2, 4) real array."""
    kappa = (3.0 - poisson) / (1.0 + poisson)
    z = np.exp(1j * theta)
    displacement, traction = np.zeros((2, 4)), np.zeros((2, 4))
    for k, (a, b) in enumerate(((1, 0), (1j, 0), (0, 1), (0, 1j))):
        phi, dphi, ddphi = a * z**lam, a * lam * z**(lam - 1), a * lam * (lam - 1) * z**(lam - 2)
        psi, dpsi = b * z**lam, b * lam * z**(lam - 1)
        u = kappa * phi - z * np.conj(dphi) - np.conj(psi)
        polar = np.exp(-1j * theta) * u
        stress = dphi + np.conj(dphi) + np.exp(2j * theta) * (np.conj(z) * ddphi + dpsi)
        displacement[:, k] = polar.real, polar.imag
        traction[:, k] = stress.real, stress.imag
    return displacement, traction


def junction_matrix(lam: float, members: list[tuple[str, float]],
                    poisson: float = POISSON) -> np.ndarray:
    """The square real matrix of the conditions (module docstring) on the members ``[(kind,
    thickness), ...]``, ``kind`` ``"skin"`` (exactly two, or none) or ``"free"``."""
    n = len(members)
    rows = []

    def row(member: int, values: np.ndarray) -> np.ndarray:
        out = np.zeros(4 * n)
        out[4 * member:4 * member + 4] = values
        return out

    line = [quadrant_columns(lam, 0.0, poisson) for _ in members]
    end = quadrant_columns(lam, np.pi / 2, poisson)[0]
    for m in range(n):
        rows += [row(m, end[0]), row(m, end[1])]
    for m in range(1, n):
        rows.append(row(0, line[0][0][0]) - row(m, line[m][0][0]))
    rows.append(sum(h * row(m, line[m][1][1]) for m, (_, h) in enumerate(members)))
    skin = [m for m, (kind, _) in enumerate(members) if kind == "skin"]
    if skin:
        first, second = skin
        rows.append(row(first, line[first][0][1]) + row(second, line[second][0][1]))
        rows.append(members[first][1] * row(first, line[first][1][0])
                    - members[second][1] * row(second, line[second][1][0]))
    for m, (kind, _) in enumerate(members):
        if kind == "free":
            rows.append(row(m, line[m][1][0]))
    matrix = np.array(rows)
    assert matrix.shape == (4 * n, 4 * n), matrix.shape
    return matrix


def real_exponents(members: list[tuple[str, float]], upper: float = 2.0,
                   poisson: float = POISSON, samples: int = 4000) -> list[float]:
    """The real :math:`\\lambda` in ``(0, upper)`` where the junction matrix is singular, by
    sign changes of its determinant on a grid refined by bisection; integers left out (their
    fields are the polynomial ones)."""
    def det(lam: float) -> float:
        matrix = junction_matrix(lam, members, poisson)
        return float(np.linalg.det(matrix / np.abs(matrix).max(axis=1, keepdims=True)))

    grid = np.linspace(1e-3, upper, samples)
    values = [det(x) for x in grid]
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if fa == 0.0 or fa * fb > 0.0:
            continue
        for _ in range(60):
            c = 0.5 * (a + b)
            fc = det(c)
            a, fa, b = (c, fc, b) if fa * fc > 0.0 else (a, fa, c)
        root = 0.5 * (a + b)
        if abs(root - round(root)) > 1e-6:
            roots.append(root)
    return roots


def williams_fixed_free(poisson: float = POISSON) -> float:
    r"""The smallest root of the right-angled fixed-free wedge's equation (Williams, 1952),
    :math:`1 + \kappa^2 + 2\kappa\cos\pi\lambda = 4\lambda^2`, by bisection on (0.5, 1): the
    check of :func:`junction_matrix` on one quadrant."""
    kappa = (3.0 - poisson) / (1.0 + poisson)
    a, b = 0.5, 1.0
    for _ in range(60):
        c = 0.5 * (a + b)
        f = 1.0 + kappa**2 + 2.0 * kappa * np.cos(np.pi * c) - 4.0 * c**2
        a, b = (c, b) if f > 0.0 else (a, c)
    return 0.5 * (a + b)


def main() -> None:
    print(f"check: the Williams equation's fixed-free root {williams_fixed_free():.6f}")
    shapes = {
        "one quadrant, line edge free (the fixed-free corner)": [("free", 1.0)],
        "L fold, equal plates": [("free", 2.0), ("free", 2.0)],
        "T, stiffener 1e-3 of the skin": [("skin", 1.0), ("skin", 1.0), ("free", 1e-3)],
        "T junction of tests/test_moving_lines.py (skin 1 mm, stiffener 2 mm)":
            [("skin", 1.0), ("skin", 1.0), ("free", 2.0)],
        "T, stiffener as thick as the skin": [("skin", 1.0), ("skin", 1.0), ("free", 1.0)],
        "L fold, 1 mm and 2 mm": [("free", 1.0), ("free", 2.0)],
    }
    for name, members in shapes.items():
        roots = real_exponents(members)
        print(f"{name}: " + (", ".join(f"{r:.6f}" for r in roots) or "none") + " in (0, 2)")


if __name__ == "__main__":
    main()
