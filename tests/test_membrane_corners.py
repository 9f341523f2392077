"""The in-plane corner functions of fixed-free corners (``solver/membrane_corners.py``,
``docs/method.md`` section 10.5), checked against what they must be independently of how they
are built: the wedge's characteristic equation against the static boundary conditions, the
membrane equation by finite differences, the wedge conditions near the corner, the field of an
exact strip that they must not disturb, and refinement of an assembly whose in-plane field did
not converge without them.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib

import numpy as np
import pytest
from support import (
    CASES,
    STRIP_A,
    STRIP_H,
    folded_description,
    membrane_strip,
    membrane_strip_fields,
    membrane_strip_problem,
)

from assembly import parse_case
from assembly.generate import stiffened_panel
from assembly.geometry import EDGE_NAMES
from solver.guards import description_issues
from solver.in_plane import membrane_bases, membrane_problems
from solver.membrane import (
    MembraneEdge,
    MembraneProblem,
    membrane_edge_rule,
    membrane_wavenumbers,
    solve_membrane,
)
from solver.membrane_basis import (
    build_membrane_basis,
    membrane_edge_traces,
    membrane_field,
    membrane_grid_displacement,
    membrane_ray_counts,
)
from solver.membrane_corners import (
    _closed_fields,
    _local_fields,
    _static_null_vector,
    corner_family,
    corner_fields,
    fixed_free_corners,
    fixed_free_exponents,
    logarithmic_family,
)
from solver.problems import plate_problems
from solver.rays import plate_edges
from solver.substructure import solve_assembly

E, NU, RHO, H = 210e9, 0.3, 7800.0, STRIP_H
A_STAR = STRIP_A


def _wavenumbers(frequency: float) -> tuple[complex, complex]:
    """:math:`(k_L, k_S)` of the 2 mm steel strip."""
    return membrane_wavenumbers(RHO * H, 2.0 * math.pi * frequency, A_STAR, NU)


def test_the_exponents_are_the_roots_of_the_wedge_equation():
    r"""The exponents (:math:`1 + \kappa^2 + 2\kappa\cos\pi\lambda = 4\lambda^2`) against the
    static wedge itself: building a family solves, for each, the 4 x 4 system of its four
    static solutions' displacements on the fixed edge and tractions on the free one, and
    refuses an exponent whose system is not singular (smallest over largest singular value
    above 1e-9; measured 1e-16). So each root is checked, and so is a number that is not one:
    the real root moved by 1e-6 is refused. For nu = 0.3: 0.758 then 1.719 -+ 0.448j and
    3.812 -+ 1.060j, each a pair with its conjugate."""
    exponents = fixed_free_exponents(NU)
    assert len(exponents) == 5
    assert exponents[0] == pytest.approx(0.7583491578824921, abs=1e-12)
    assert all(e in exponents or np.conj(e) in exponents for e in exponents)
    kappa = (3 - NU) / (1 + NU)
    for lam in exponents:
        assert abs(1 + kappa**2 + 2 * kappa * np.cos(np.pi * lam) - 4 * lam**2) < 1e-12
    k_long, k_shear = _wavenumbers(1000.0)
    for fixed, free in (((1.0, 0.0), (0.0, 1.0)), ((0.0, 1.0), (1.0, 0.0))):
        corner_family(np.zeros(2), np.array(fixed), np.array(free), NU, k_long, k_shear, 0.6)

    with pytest.raises(ArithmeticError):
        _static_null_vector(exponents[0] + 1e-6, True, NU)


def _series_and_closed_forms(family, k_shear: complex, gradient: bool):
    """The four functions of each exponent of ``family`` (and, if ``gradient``, their
    derivatives) by their series and in closed form, at 12 points of the quadrant with
    |k_S| r from 1 to 6, where both are accurate."""
    angles = np.linspace(0.0, 0.5 * math.pi, 12)
    radii = np.linspace(1.0, 6.0, 12) / abs(k_shear)
    local = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    return (_local_fields(family.functions, local, gradient),
            _closed_fields(family, local, gradient))


def _equation_residual(family, frequency: float) -> float:
    r"""The largest :math:`|\nabla\cdot\mathbf N + \rho h\omega^2\mathbf u|` of the
    functions of ``family`` at four points of the 0.5 x 0.4 m plate, over the largest inertia
    term, the divergence by fourth-order central differences of the resultants (step 1e-4 m)."""
    points = np.array([[0.45, 0.05], [0.2, 0.3], [0.05, 0.39], [0.48, 0.35]])
    step = 1e-4

    def resultants(p: np.ndarray) -> np.ndarray:
        return corner_fields((family,), p, A_STAR, NU)[1]

    divergence = sum((8.0 * (resultants(points + step * e) - resultants(points - step * e))
                      - resultants(points + 2 * step * e) + resultants(points - 2 * step * e)
                      )[:, :, i] / (12 * step)
                     for i, e in enumerate(np.eye(2)))
    inertia = RHO * H * (2 * math.pi * frequency) ** 2 * corner_fields(
        (family,), points, A_STAR, NU)[0]
    return float(np.max(np.abs(divergence + inertia)) / np.abs(inertia).max())


@pytest.mark.parametrize("frequency", [200.0, 2500.0, 10000.0, 30000.0])
def test_the_corner_functions_solve_the_membrane_equation(frequency):
    r""":math:`\nabla\cdot\mathbf N + \rho h\omega^2\mathbf u = 0` for each corner function,
    damped, at points of the plate, by fourth-order central differences of the resultants
    (step 1e-4 m; the functions vary on the scale of the distance to the corner, 5 cm and
    more, so the truncation is about 1e-14 of the terms): measured 2.2e-9 of the inertia at
    200 Hz (where it is smallest against the terms of the divergence), 1.7e-11 and 7.2e-11 at
    2.5 and 10 kHz (8, 16 and 31 terms per series); asked 1e-8. A term of the series dropped,
    or a wrong sign between the longitudinal and the shear part, fails by orders of
    magnitude."""
    k_long, k_shear = _wavenumbers(frequency)
    family = corner_family(np.array([0.5, 0.0]), np.array([-1.0, 0.0]), np.array([0.0, 1.0]),
                           NU, k_long, k_shear, math.hypot(0.5, 0.4))
    assert _equation_residual(family, frequency) < 1e-8


@pytest.mark.parametrize("frequency", [2000.0, 8000.0])
def test_the_logarithmic_family_solves_the_membrane_equation_in_both_forms(frequency):
    r"""The in-plane logarithmic family (:func:`solver.membrane_corners.logarithmic_family`:
    the four functions of degrees 1 and 2 differenced in the degree) solves
    :math:`\nabla\cdot\mathbf N + \rho h\omega^2\mathbf u = 0`, by the fourth-order
    differences of the test above (measured 1.7e-9 and 1.1e-10 of the inertia at 2 and 8 kHz,
    2 with the inertia's sign turned; asked 1e-8), and
    its closed forms are its series where both hold (|k_S| r from 1 to 6: measured 1.3e-10 at
    2 kHz, 1.2e-12 at 8 kHz; asked 1e-9: the difference quotient over 2e-3 in the degree costs
    three digits of the 1e-10 of the fixed-free family's test)."""
    k_long, k_shear = _wavenumbers(frequency)
    family = logarithmic_family(np.array([0.5, 0.0]), np.array([0.0, 1.0]),
                                np.array([-1.0, 0.0]), k_long, k_shear, math.hypot(0.5, 0.4))
    assert family.n_functions == 8
    assert _equation_residual(family, frequency) < 1e-8
    (u_series, _), (u_closed, _) = _series_and_closed_forms(family, k_shear, False)
    series, closed = u_series @ family.combinations, u_closed @ family.combinations
    assert np.abs(series - closed).max() < 1e-9 * np.abs(series).max()


def test_near_the_corner_they_are_the_wedge_eigenfunctions():
    r"""Approaching the corner the dynamic functions tend to the static eigenfunctions of the
    wedge: the displacement on the fixed edge and the traction on the free one, against their
    size on the bisector at the same distance, fall as :math:`(k_S r)^2` (measured at 1 kHz,
    the largest over the five functions: 2.2e-9 and 3.5e-9 at r = 0.1 mm, 2.2e-7 and 3.5e-7 at
    1 mm, 2.2e-5 and 3.5e-5 at 1 cm, where :math:`(k_S r)^2` is 3.8e-8, 3.8e-6, 3.8e-4); asked
    below :math:`(k_S r)^2`. The static combination taken at a wrong exponent leaves an
    error of order 1 at every distance."""
    k_long, k_shear = _wavenumbers(1000.0)
    fixed, free = np.array([0.0, 1.0]), np.array([1.0, 0.0])
    family = corner_family(np.zeros(2), fixed, free, NU, k_long, k_shear, 0.6)
    for r in (1e-4, 1e-3, 1e-2):
        u_fixed, _ = corner_fields((family,), [r * fixed], A_STAR, NU)
        _, n_free = corner_fields((family,), [r * free], A_STAR, NU)
        u_mid, n_mid = corner_fields((family,), [r * (fixed + free) / math.sqrt(2)], A_STAR, NU)
        traction = np.einsum("pijf,j->pif", n_free, -fixed)  # the free edge's outward normal
        bound = (abs(k_shear) * r) ** 2
        assert np.all(np.abs(u_fixed).max(axis=1) < bound * np.abs(u_mid).max(axis=1))
        assert np.all(np.abs(traction).max(axis=1)
                      < bound * np.abs(n_mid).reshape(1, 4, -1).max(axis=1))


def _strip_problem(frequency: float):
    """The exact strip of ``tests/support.py`` (``membrane_strip``) cut to the rectangle
    [0.2, 0.5] x [0.05, 0.35] with the exact data of a fixed cut on its bottom edge and its own
    free right edge, a free cut on top and a fixed cut on the left: two fixed-free corners
    (right-bottom, top-left) where the exact field is smooth. Returns the problem, the exact
    ``(u, N)`` at points of the rectangle, and the conditions."""
    field, omega = membrane_strip(frequency)
    corner, size = np.array([0.2, 0.05]), (0.3, 0.3)
    conditions = {"bottom": "fixed", "right": "free", "top": "free", "left": "fixed"}

    def exact(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return membrane_strip_fields(field, points[:, 0] + corner[0], points[:, 1] + corner[1])

    return membrane_strip_problem(field, omega, corner, size, conditions), exact, conditions


@pytest.mark.parametrize("frequency", [300.0, 3000.0])
def test_corner_functions_leave_a_smooth_field_exact(frequency):
    """Where the exact field is smooth the corner functions must not disturb it: the strip's
    rectangle (:func:`_strip_problem`) solved with and without them, against the exact field
    on a 25 x 25 grid. Measured (without / with) at resolution 1, 1.5, 2.25: 4.4e-3 / 4.9e-5,
    2.9e-5 / 1.4e-5, 3.1e-6 / 2.5e-6 at 300 Hz; 1.3e-6 / 5.6e-7, 1.2e-9 / 1.1e-9, 1.3e-9 /
    1.5e-9 at 3 kHz (the rays alone converge slowly at a fixed-free corner even where the
    exact field is smooth: their own solve loads it). Asked at resolution 1.5: with them at
    most twice the error without, and below 1e-4. The traces, the graded edge rule, the field
    and the grid evaluation all take part, and the grid agrees with the field point by point
    to 1e-12."""
    problem, exact, conditions = _strip_problem(frequency)
    k_long, k_shear = problem.wavenumbers
    beta_max = 2.5 * max(abs((RHO * H * problem.omega**2 / (E * H**3 / 12)) ** 0.25),
                         abs(k_shear), 5.0 / (0.5 * math.hypot(*problem.size)))
    counts = membrane_ray_counts(problem.size, abs(k_shear), beta_max, 1.5)
    rays = build_membrane_basis(problem.size, k_long, k_shear, counts, beta_max)
    families = fixed_free_corners(problem.size, [conditions[e] for e in EDGE_NAMES], NU,
                                  k_long, k_shear)
    assert [tuple(f.point) for f in families] == [(0.3, 0.0), (0.0, 0.3)]
    with_corners = dataclasses.replace(rays, corners=families)
    xs = np.linspace(0.0, 0.3, 25)
    gx, gy = np.meshgrid(xs, xs, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel()])
    reference, _ = exact(points)
    errors = []
    for basis in (rays, with_corners):
        solution = solve_membrane(problem, basis)
        u = solution.u(points)
        errors.append(np.linalg.norm(u - reference) / np.linalg.norm(reference))
    assert errors[1] < min(2 * errors[0], 1e-4), errors
    grid = membrane_grid_displacement(with_corners, solution.amplitudes, xs, xs)
    np.testing.assert_allclose(np.moveaxis(grid, 0, -1).reshape(-1, 2), u,
                               atol=1e-12 * np.abs(u).max())


def test_traces_carry_the_corner_columns_on_a_graded_rule():
    """The traces of a basis with corner functions end with the corner functions' own
    displacements and tractions (``corner_fields`` at the same points), after the rays'
    columns unchanged; the edge rule is graded towards both ends of an edge that meets a
    corner (its smallest panel 0.25 * 0.15^5 of the edge) and symmetric, and an edge without
    one keeps its Gauss rule."""
    size = (0.5, 0.4)
    k_long, k_shear = _wavenumbers(1000.0)
    counts = membrane_ray_counts(size, abs(k_shear), 60.0, 1.0)
    rays = build_membrane_basis(size, k_long, k_shear, counts, 60.0)
    conditions = ["fixed", "free", "diaphragm", "diaphragm"]  # one corner: bottom-right
    basis = dataclasses.replace(rays, corners=fixed_free_corners(size, conditions, NU, k_long,
                                                                 k_shear))
    assert basis.n_dof == rays.n_dof + 5
    bottom, right, top, left = plate_edges(size)
    s, w = membrane_edge_rule(bottom, basis)
    assert s.min() < 0.25 * 0.15**5 * bottom.length
    np.testing.assert_allclose(s + s[::-1], bottom.length, atol=1e-12)
    assert w.sum() == pytest.approx(bottom.length, rel=1e-13)
    assert np.array_equal(membrane_edge_rule(top, basis)[0], membrane_edge_rule(top, rays)[0])
    traces = membrane_edge_traces(basis, right, s[:40], A_STAR, NU)
    plain = membrane_edge_traces(rays, right, s[:40], A_STAR, NU)
    u, resultants = corner_fields(basis.corners, right.start + s[:40, None] * right.tangent,
                                  A_STAR, NU)
    traction = np.einsum("pijf,j->pif", resultants, right.normal)
    for key, value in (("u_n", np.einsum("pif,i->pf", u, right.normal)),
                       ("N_nt", np.einsum("pif,i->pf", traction, right.tangent))):
        np.testing.assert_array_equal(traces[key][:, :rays.n_dof], plain[key])
        np.testing.assert_allclose(traces[key][:, rays.n_dof:], value, rtol=1e-14)
    x = np.random.default_rng(2).standard_normal(basis.n_dof) + 0j
    point = right.start + s[:3, None] * right.tangent
    field = membrane_field(basis, x, point, A_STAR, NU)
    np.testing.assert_allclose(field["u"] @ right.normal, traces["u_n"][:3] @ x, rtol=1e-12)


def _panel_in_plane(frequency: float, resolution: float) -> dict[str, np.ndarray]:
    description = tomllib.loads((CASES / "stiffened_panel.toml").read_text())
    description["discretisation"]["resolution"] = resolution
    case = parse_case(description)
    solution = solve_assembly(case, frequency, residuals=False)
    fields = {}
    for name, plate in case.plates.items():
        xs = np.linspace(0.0, plate.size[0], 41)[1:-1]
        ys = np.linspace(0.0, plate.size[1], 33)[1:-1]
        gx, gy = np.meshgrid(xs, ys)
        fields[name] = solution.in_plane(name, np.column_stack([gx.ravel(), gy.ravel()]))
    return fields


def test_the_stiffened_panel_in_plane_field_converges():
    """``cases/stiffened_panel.toml`` at 184.8 Hz: every end of its moving lines meets an
    in-plane fixed edge, and every stiffener's top a fixed end. Without corner functions
    the in-plane field changed by 1.7e-2 to 1.8e-1 between resolutions 1.25 and 1.875 on the
    skin, 4.5e-3 to 5.8e-3 between 1.875 and 2.8; with them 2.7e-4 to 7.9e-4, then 1.2e-5
    to 4.2e-5 (stiffeners 4.5e-6 to 2.5e-5). Asked: below 2e-3, then 2e-4 on every plate."""
    fields = [_panel_in_plane(184.8, r) for r in (1.25, 1.875, 2.8)]
    for coarse, fine, bound in ((fields[0], fields[1], 2e-3), (fields[1], fields[2], 2e-4)):
        for name in fine:
            change = np.linalg.norm(coarse[name] - fine[name]) / np.linalg.norm(fine[name])
            assert change < bound, (name, change)


def test_plates_share_a_basis_where_their_corner_layouts_agree():
    """Identical plates share one in-plane basis (and through it their traces) unless their
    fixed-free corners differ: on a three-bay panel with diaphragm ends the end bays, mirror
    images whose conditions differ but which have no such corner, and the inner bay hold one
    basis (keying on the whole conditions made the solve 16 % slower at 600 Hz); on
    ``cases/stiffened_panel.toml`` the inner bays share one, the end bays, whose corners are
    mirrored, one each, and the three stiffeners one. So from resolution 1.5, where the welds'
    held ends add their loaded corners (whose plates' corners were listed in the order the
    lines came, and the lines in a set's order: the inner bays shared in one run of three,
    and a solve of the panel at 257 Hz cost 15 % more), with the welds listed in any order."""

    along_x, up = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    plates = {"B1": (0.4, (0.0, 0.0, 0.0), along_x, 0.001, "simply_supported"),
              "B2": (0.4, (0.4, 0.0, 0.0), along_x, 0.001, "simply_supported"),
              "B3": (0.4, (0.8, 0.0, 0.0), along_x, 0.001, "simply_supported"),
              "T1": (0.08, (0.4, 0.0, 0.0), up, 0.0015, "free"),
              "T2": (0.08, (0.8, 0.0, 0.0), up, 0.0015, "free")}
    lines = {"W1": {"B1": ("right", math.inf), "B2": ("left", math.inf), "T1": ("left", 3.5)},
             "W2": {"B2": ("right", math.inf), "B3": ("left", math.inf), "T2": ("left", 3.5)}}
    stiffened = tomllib.loads((CASES / "stiffened_panel.toml").read_text())
    reordered = stiffened | {"joints": {name: stiffened["joints"][name]
                                        for name in ("W2", "W3", "W1")},
                             "discretisation": stiffened["discretisation"] | {"resolution": 1.5}}
    panels = [parse_case(folded_description(plates, lines, ("B1", 0.17, 0.13), 600.0, False,
                                            0.5)),
              parse_case(stiffened), parse_case(reordered)]
    bases = []
    for case in panels:
        problems = membrane_problems(case, 600.0)
        bases.append(membrane_bases(case, problems, plate_problems(case, 600.0)))
    diaphragm, fixed, loaded = bases
    assert diaphragm["B1"] is diaphragm["B2"] is diaphragm["B3"]
    assert not diaphragm["B1"].corners
    for panel, corners in ((fixed, [2, 4, 4]), (loaded, [4, 8, 6])):
        assert panel["B2"] is panel["B3"] and panel["T1"] is panel["T2"] is panel["T3"]
        assert len({id(panel[p]) for p in ("B1", "B2", "B4")}) == 3
        assert [len(panel[p].corners) for p in ("B1", "B2", "T1")] == corners


def test_corner_functions_are_used_at_every_frequency():
    """The corner functions' closed forms (``_closed_fields``) are the sums of their series:
    at |k_S| r from 1 to 6, where both are accurate, 1e-10 (measured 4e-11 at 2 kHz, 1e-13 at
    8 kHz). So no plate loses them any more: a two-bay stiffened panel (0.5 x 0.4 m bays) at
    13 kHz, where their series would have had to reach |k_S| times the diagonal 16.3 and they
    were dropped, has them on both bays, and its check no longer warns."""
    for frequency in (2000.0, 8000.0):
        k_long, k_shear = _wavenumbers(frequency)
        family = corner_family(np.zeros(2), np.array([1.0, 0.0]), np.array([0.0, 1.0]), NU,
                               k_long, k_shear, 0.6)
        (u_series, gradient_series), (u_closed, gradient_closed) = _series_and_closed_forms(
            family, k_shear, True)
        assert np.abs(u_series - u_closed).max() < 1e-10 * np.abs(u_series).max()
        assert (np.abs(gradient_series - gradient_closed).max()
                < 1e-10 * np.abs(gradient_series).max())
    case = parse_case(stiffened_panel(2, frequency=13000.0))
    bases = membrane_bases(case, membrane_problems(case, 13000.0), plate_problems(case, 13000.0))
    assert [len(bases[p].corners) for p in ("B1", "B2")] == [2, 2]
    _, warnings = description_issues(case)
    assert not [message for _, message in warnings if "corner functions" in message]


def test_beyond_the_series_reach_a_fixed_plate_converges_with_its_corner_functions():
    """A 0.5 x 0.4 m, 2 mm steel membrane fixed on its left edge, free elsewhere, pulled by
    1 N/m on its right edge, at 25 kHz (|k_S| times the diagonal 31, twice what the corner
    functions' series could reach): change of (u, v) between resolutions 2.25 and 3.4, 1.3e-5
    with the functions (their closed forms beyond |k_S| r = 4), 3.9e-3 with the rays alone
    (at 15 kHz, 1.6e-5 and 3.6e-3; at 5 kHz, within the series' reach, 5.2e-6 and 1.8e-3)."""
    size, conditions = (0.5, 0.4), {"left": "fixed", "bottom": "free", "top": "free",
                                    "right": "free"}
    edges = {name: MembraneEdge(condition, {"N_nn": lambda s: 1.0 + 0.0 * s}
                                if name == "right" else {})
             for name, condition in conditions.items()}
    problem = MembraneProblem(size, A_STAR, NU, RHO * H, 2 * math.pi * 25000.0, edges)
    k_long, k_shear = problem.wavenumbers
    beta_max = 2.5 * max(abs(k_shear), 5.0 / (0.5 * math.hypot(*size)))
    families = fixed_free_corners(size, [conditions[e] for e in EDGE_NAMES], NU, k_long, k_shear)
    points = np.array([(a, b) for a in np.linspace(0.01, 0.49, 25)
                       for b in np.linspace(0.01, 0.39, 21)])
    changes = {}
    for corners in (False, True):
        fields = []
        for resolution in (2.25, 3.4):
            rays = build_membrane_basis(size, k_long, k_shear, membrane_ray_counts(
                size, abs(k_shear), beta_max, resolution), beta_max)
            basis = dataclasses.replace(rays, corners=families) if corners else rays
            fields.append(solve_membrane(problem, basis).u(points))
        changes[corners] = np.linalg.norm(fields[1] - fields[0]) / np.linalg.norm(fields[1])
    assert changes[True] < 1e-4 < 1e-3 < changes[False], changes

