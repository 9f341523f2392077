"""Kernel checks of the single-plate VTCR against quantities computed independently.

Notes section 9: G1 (Green function), R1 (reciprocity), D1 (dissipation), plus the two
quadratures the solver relies on (sector means and edge integrals), each compared with a slow,
obvious evaluation written here.
"""

import numpy as np
import pytest
from scipy import integrate, special

from assembly.geometry import EDGE_NAMES, plate_edges
from solver.kirchhoff import (
    complex_bending_stiffness,
    point_force_derivatives,
    point_force_radial,
)
from solver.plate import EdgeCondition, PlateProblem, assemble_plate, boundary_traces
from solver.rays import (
    automatic_ray_counts,
    build_ray_basis,
    edge_exponentials,
    line_exponentials,
    node_exponentials,
    ray_field,
)

STEEL = dict(young_modulus=210e9, poisson_ratio=0.3, density=7800.0)
SIZE = (0.5, 0.4)
THICKNESS = 1e-3


def plate(frequency=400.0, eta=0.01, edges=None):
    d = complex_bending_stiffness(STEEL["young_modulus"], THICKNESS, STEEL["poisson_ratio"], eta)
    conditions = edges or {e: EdgeCondition("simply_supported") for e in EDGE_NAMES}
    return PlateProblem(SIZE, d, STEEL["poisson_ratio"], STEEL["density"] * THICKNESS,
                        2 * np.pi * frequency, conditions)


def basis_for(problem, resolution=1.0, n_q=8):
    counts = automatic_ray_counts(problem.kappa.real, problem.size, resolution)
    return build_ray_basis(problem.size, problem.kappa, counts, n_q=n_q)


# ------------------------------------------------------------------------------------------
# G1: Green function
# ------------------------------------------------------------------------------------------

def test_hankel_of_imaginary_argument_is_bessel_k():
    """H0^(2)(-j z) = (2j/pi) K0(z): the identity that turns the Green function into one form."""
    z = np.array([0.3, 1.7 - 0.02j, 6.0 - 0.1j])
    assert np.allclose(special.hankel2(0, -1j * z), 2j / np.pi * special.kv(0, z), rtol=1e-13)


def test_drive_point_mobility_of_the_infinite_plate():
    """j omega w(0) = F / (8 sqrt(D* rho h)) (Cremer & Heckl), approached as r -> 0."""
    problem = plate()
    f, *_ = point_force_radial(np.array([1e-9]), problem.kappa, problem.bending_stiffness, 1.0)
    mobility = 1j * problem.omega * f[0]
    exact = 1.0 / (8.0 * np.sqrt(problem.bending_stiffness * problem.mass_per_area))
    # the next term of f near 0 is O((kappa r)^2 log r) ~ 1e-15 at r = 1e-9 m
    assert abs(mobility - exact) / abs(exact) < 1e-10


def test_green_function_satisfies_the_plate_equation_off_the_source():
    """D* lap^2 w - rho h omega^2 w = 0 away from the source, by a 13-point FD stencil.

    The stencil's truncation error is O(h^2 kappa^2) relative: 1e-4 at h = 0.5 mm, 400 Hz.
    """
    problem = plate()
    h = 5e-4
    x0 = np.array([0.13, 0.07])
    offsets = [(0, 0, 20), (1, 0, -8), (-1, 0, -8), (0, 1, -8), (0, -1, -8), (1, 1, 2),
               (1, -1, 2), (-1, 1, 2), (-1, -1, 2), (2, 0, 1), (-2, 0, 1), (0, 2, 1), (0, -2, 1)]
    points = np.array([x0 + h * np.array([i, j]) for i, j, _ in offsets])
    w = point_force_derivatives(points, (0.0, 0.0), problem.kappa,
                                problem.bending_stiffness, 1.0)["w"]
    bilaplacian = sum(c * wi for (_, _, c), wi in zip(offsets, w)) / h**4
    residual = problem.bending_stiffness * bilaplacian - problem.mass_per_area * problem.omega**2 * w[0]
    scale = abs(problem.mass_per_area * problem.omega**2 * w[0])
    assert abs(residual) / scale < 1e-3


def test_green_function_derivatives_match_finite_differences():
    """Gradient and Hessian formulas against central differences of w (relative 1e-6)."""
    problem = plate()
    h = 1e-5
    x = np.array([[0.21, -0.05]])
    g = point_force_derivatives(x, (0.0, 0.0), problem.kappa, problem.bending_stiffness, 1.0)

    def w_at(p):
        return point_force_derivatives(np.atleast_2d(p), (0.0, 0.0), problem.kappa,
                                       problem.bending_stiffness, 1.0)

    e = np.eye(2) * h
    grad = np.array([(w_at(x[0] + e[i])["w"] - w_at(x[0] - e[i])["w"])[0] / (2 * h)
                     for i in range(2)])
    hess = np.array([(w_at(x[0] + e[i])["grad"] - w_at(x[0] - e[i])["grad"])[0] / (2 * h)
                     for i in range(2)])
    assert np.allclose(g["grad"][0], grad, rtol=1e-6)
    assert np.allclose(g["hess"][0], hess, rtol=1e-6)


# ------------------------------------------------------------------------------------------
# quadratures
# ------------------------------------------------------------------------------------------

def test_sector_means_match_adaptive_quadrature():
    """Each shape function is the mean of its family's exponential over its sector.

    Recomputed here with adaptive quadrature (scipy.integrate.quad) from the loci of
    ``docs/method.md`` section 5.1 for one sector of every family. Every shape function is
    bounded by about 1 in the plate, so the 8-point Gauss rule must agree to 1e-8 in absolute
    value (measured: 1e-9 on the first propagating-edge sector and 3e-10 on the single corner
    sector at 1.6 kHz), far below the discretisation errors we accept (1e-3). A quadrature error
    here cannot spoil the solution anyway: every node is an exact plate solution, so it only
    perturbs which Trefftz function the sector stands for.
    """
    problem = plate(frequency=1600.0)
    counts = automatic_ray_counts(problem.kappa.real, problem.size, 1.0)
    basis = build_ray_basis(problem.size, problem.kappa, counts)
    kappa, k0, tau = problem.kappa, problem.kappa.real, 2.5
    x = np.array([0.31, 0.17])
    values = ray_field(basis, x[None, :])["w"][0]
    bottom = plate_edges(SIZE)[0]

    def mean(fun, a, b):
        re = integrate.quad(lambda t: fun(t).real, a, b, epsabs=0, epsrel=1e-13, limit=200)[0]
        im = integrate.quad(lambda t: fun(t).imag, a, b, epsabs=0, epsrel=1e-13, limit=200)[0]
        return (re + 1j * im) / (b - a)

    def sqrt_pos(z):
        s = np.sqrt(complex(z))
        return s if s.real >= 0 else -s

    centre = np.array(SIZE) / 2
    n_int = counts.interior
    checks = {
        basis.family.index("interior") + 3: mean(
            lambda t: np.exp(-1j * kappa * ((x - centre) @ [np.cos(t), np.sin(t)])),
            3 * 2 * np.pi / n_int, 4 * 2 * np.pi / n_int),
    }
    first_m = basis.family.index("edge_evanescent:bottom")
    n_m = counts.edge_evanescent[0]
    betas = np.linspace(-tau * k0, tau * k0, n_m + 1)
    checks[first_m + 2] = mean(
        lambda b: np.exp(-1j * b * x[0] - sqrt_pos(b * b + kappa**2) * x[1]), betas[2], betas[3])
    first_h = basis.family.index("edge_propagating:bottom")
    n_half = counts.edge_propagating[0] // 2
    psis = np.arccosh(np.linspace(1.0, tau, n_half + 1))
    checks[first_h + n_half] = mean(
        lambda p: np.exp(-1j * kappa * np.cosh(p) * x[0] - kappa * np.sinh(p) * x[1]),
        psis[0], psis[1])
    checks[basis.family.index("corner:0")] = mean(
        lambda t: np.exp(-kappa * (x @ [np.cos(t), np.sin(t)])), 0.0, np.pi / 2)
    assert bottom.name == "bottom"
    for dof, expected in checks.items():
        assert abs(values[dof] - expected) <= 1e-8, basis.family[dof]


def test_plate_edges_are_made_once_per_size_and_shared_read_only():
    """A list, a tuple or an array of the same size give the same edges (made once: a solve
    asks for them hundreds of times), whose arrays are shared and so cannot be written."""
    edges = plate_edges((0.5, 0.4))
    assert plate_edges([0.5, 0.4]) is edges and plate_edges(np.array([0.5, 0.4])) is edges
    assert [e.name for e in edges] == list(EDGE_NAMES)
    np.testing.assert_array_equal(edges[2].start, [0.5, 0.4])  # top runs from (Lx, Ly)
    with pytest.raises(ValueError):
        edges[1].normal[0] = 0.0


def test_edge_gauss_rule_matches_closed_form_exponential_integrals():
    """Edge integrals of trace products against the closed form node pair by node pair.

    For node exponentials with trace :math:`c_p e^{\\alpha_p s}`,
    :math:`\\int_0^L \\overline{c_p e^{\\alpha_p s}}\\,c_q e^{\\alpha_q s}ds
    = \\bar c_p c_q\\,\\mathrm{expm1}(zL)/z`, :math:`z = \\bar\\alpha_p + \\alpha_q` (the slow,
    exact assembly of ``docs/method.md`` section 5.3). The Gram matrix of the sector-averaged
    traces on every edge must agree with the Gauss rule to 1e-11 relative to its largest entry.
    """
    problem = plate(frequency=1000.0)
    basis = basis_for(problem)
    boundary = boundary_traces(problem, basis)
    for edge in plate_edges(SIZE):
        c = np.exp((edge.start - basis.origin) @ np.array([1, 0]) * basis.k[:, 0]
                   + (edge.start - basis.origin) @ np.array([0, 1]) * basis.k[:, 1])
        alpha = basis.k @ edge.tangent
        z = alpha.conj()[:, None] + alpha[None, :]
        small = np.abs(z * edge.length) < 1e-8
        integral = np.where(small, edge.length,
                            np.expm1(z * edge.length) / np.where(small, 1.0, z))
        node_gram = (c.conj() * basis.weight)[:, None] * integral * (c * basis.weight)[None, :]
        n, q = basis.n_dof, basis.n_q
        exact = node_gram.reshape(n, q, n, q).sum(axis=(1, 3))
        traces = boundary.edges[edge.name]
        gauss = traces.w.conj().T @ (traces.weights[:, None] * traces.w)
        assert np.abs(gauss - exact).max() <= 1e-11 * np.abs(exact).max(), edge.name


@pytest.mark.parametrize("size, frequency", [(SIZE, 155.0), (SIZE, 1600.0), ((2.0, 1.5), 8000.0)])
def test_line_exponentials_match_direct_evaluation(size, frequency):
    r"""The factored edge exponentials :math:`C_q G_q(u)` equal :math:`e^{k_q(x - x_r)}`.

    Both evaluations round the exponent, an error of about eps :math:`|k\cdot(x - x_r)|`
    relative to the value (up to 1e-13 here). On the 2 x 1.5 m plate at 8 kHz the edge rays
    decay by :math:`e^{-960}` across the plate, beyond the double range, where a factor
    anchored anywhere but at the segment's larger end would overflow: every value must stay
    finite, and those the direct evaluation resolves must agree.
    """
    d = complex_bending_stiffness(STEEL["young_modulus"], THICKNESS, STEEL["poisson_ratio"], 0.01)
    problem = PlateProblem(size, d, STEEL["poisson_ratio"], STEEL["density"] * THICKNESS,
                           2 * np.pi * frequency)
    basis = basis_for(problem, resolution=0.3)
    x, _ = np.polynomial.legendre.leggauss(40)
    for axis in (0, 1):
        length, other = size[axis], size[1 - axis]
        u = np.concatenate([[0.0], 0.5 * length * (x + 1.0), [length]])
        shared, constants = line_exponentials(basis, axis, u, [0.0, 0.3 * other, other])
        for c, constant in zip([0.0, 0.3 * other, other], constants):
            points = np.empty((len(u), 2))
            points[:, axis], points[:, 1 - axis] = u, c
            direct = node_exponentials(basis, points)
            factored = constant * shared
            assert np.isfinite(factored).all()
            exponent = np.abs(np.max(np.abs(basis.k)) * np.hypot(*size))
            resolved = np.abs(direct) > 1e-250
            error = np.abs(factored - direct)[resolved] / np.abs(direct)[resolved]
            assert error.max() <= 8 * np.finfo(float).eps * exponent, (axis, c)
            assert np.all(np.abs(factored[~resolved]) <= 1e-240)


def test_edge_exponentials_match_direct_evaluation():
    r"""On every edge, the node exponentials at a joint's Gauss points (both directions of
    travel, so in either order along the edge) and at points without symmetry (the direct
    evaluation's fallback) equal :math:`e^{k_q(x - x_r)}` evaluated point by point, to the
    rounding of the exponent (as in the test above)."""
    from solver.joint_rules import joint_gauss

    basis = basis_for(plate(frequency=1600.0))
    exponent = np.max(np.abs(basis.k)) * np.hypot(*SIZE)
    for edge in plate_edges(SIZE):
        sigma, _ = joint_gauss(edge.length, float(np.max(np.abs(basis.k))))
        for s in (sigma, edge.length - sigma, np.array([0.1, 0.05, 0.33]) * edge.length):
            direct = node_exponentials(basis, edge.start + s[:, None] * edge.tangent)
            error = np.abs(edge_exponentials(basis, edge, s) - direct) / np.abs(direct)
            assert error.max() <= 8 * np.finfo(float).eps * exponent, edge.name


def test_ray_nodes_share_their_edge_exponentials():
    r"""Opposite edges, both signs of :math:`\beta`, both propagating signs, the corners and the
    interior rays at :math:`\pm\theta`, :math:`\theta+\pi` have wave-vector components
    equal up to sign to the last bit, so :func:`line_exponentials` evaluates one exponential
    per point for about a quarter of the nodes (the speed of the edge traces rests on it).
    """
    basis = basis_for(plate(frequency=1600.0))
    for axis in (0, 1):
        a = basis.k[:, axis]
        canonical = np.where((a.real > 0) | ((a.real == 0) & (a.imag > 0)), -a, a)
        assert len(np.unique(canonical)) <= 0.26 * len(a)


# ------------------------------------------------------------------------------------------
# R1 reciprocity and D1 dissipation
# ------------------------------------------------------------------------------------------

def boundary_work(boundary):
    """G[a, b] = <g(phi_b), q(phi_a)>: closed-boundary work, corners included, no conjugation."""
    g = sum(t.w.T @ (t.weights[:, None] * t.shear) - t.slope.T @ (t.weights[:, None] * t.moment)
            for t in boundary.edges.values())
    return g + boundary.corner_w.T @ boundary.corner_force


@pytest.mark.parametrize("frequency", [155.0, 1600.0])
def test_reciprocity_of_ray_fields(frequency):
    """R1: <g(u), q(v)> = <g(v), q(u)> for Trefftz fields u, v (Green identity 2.1, f = 0).

    The left side of (2.1) is symmetric in (u, v), so the boundary work matrix is symmetric to
    quadrature accuracy; dropping the corner forces breaks it at O(1).
    """
    problem = plate(frequency)
    boundary = boundary_traces(problem, basis_for(problem))
    g = boundary_work(boundary)
    assert np.abs(g - g.T).max() <= 1e-9 * np.abs(g).max()
    without_corners = g - boundary.corner_w.T @ boundary.corner_force
    assert np.abs(without_corners - without_corners.T).max() > 1e-3 * np.abs(g).max()


def domain_strain_energy(problem, basis, x, n=120):
    r""":math:`a(w, w^*) = \int (1-\nu)|\chi|^2 + \nu|\mathrm{tr}\chi|^2 dA` by tensor Gauss."""
    gx, wx = np.polynomial.legendre.leggauss(n)
    xs, ys = (gx + 1) * SIZE[0] / 2, (gx + 1) * SIZE[1] / 2
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    weights = np.outer(wx * SIZE[0] / 2, wx * SIZE[1] / 2).ravel()
    d = ray_field(basis, np.c_[X.ravel(), Y.ravel()], ("w_xx", "w_xy", "w_yy"))
    wxx, wxy, wyy = (d[key] @ x for key in ("w_xx", "w_xy", "w_yy"))
    nu = problem.poisson_ratio
    density = (1 - nu) * (abs(wxx) ** 2 + 2 * abs(wxy) ** 2 + abs(wyy) ** 2) + nu * abs(wxx + wyy) ** 2
    return float(weights @ density)


def test_dissipation_identity_for_every_boundary_condition():
    """D1: Im(x^H K x) = eta D a(w, w*) > 0, whatever the boundary conditions.

    Static terms contribute g q^*, kinematic ones -(g q^*)^*, which have the same imaginary
    part, so the quadratic form's imaginary part is the dissipated-energy functional of the
    field alone (``docs/method.md`` section 4.3); here it is compared with the domain
    integral of the curvatures (Gauss 120 x 120: converged to 1e-9 for these smooth fields).
    """
    rng = np.random.default_rng(3)
    mixes = [
        {e: EdgeCondition("simply_supported") for e in EDGE_NAMES},
        {e: EdgeCondition("clamped") for e in EDGE_NAMES},
        {e: EdgeCondition("free") for e in EDGE_NAMES},
        dict(zip(EDGE_NAMES, [EdgeCondition("clamped"), EdgeCondition("free"),
                         EdgeCondition("simply_supported"), EdgeCondition("free")])),
    ]
    problem = plate(frequency=400.0, edges=mixes[0])
    basis = basis_for(problem, resolution=0.5)
    x = rng.normal(size=basis.n_dof) + 1j * rng.normal(size=basis.n_dof)
    d_real = problem.bending_stiffness.real
    eta = problem.bending_stiffness.imag / d_real
    expected = eta * d_real * domain_strain_energy(problem, basis, x)
    for edges in mixes:
        problem = plate(frequency=400.0, edges=edges)
        K, _ = assemble_plate(problem, boundary_traces(problem, basis))
        quadratic = x.conj() @ K @ x
        assert quadratic.imag > 0
        assert abs(quadratic.imag - expected) <= 1e-7 * expected


def test_truncated_dense_solve_against_lapack():
    """``factorise_dense`` (pivoted QR, Q^H applied from its reflectors, truncated) against
    LAPACK's own solvers: on a full-rank complex system it is ``numpy.linalg.solve`` to 1e-12
    (condition about 1e2, so rounding gives ~1e-14); on a rank-40 frame of 60 columns, column
    scales spread over six decades as a plate's rays are, its residual is the least-squares
    optimum (``lstsq``) to 1e-10 relative, exactly 20 coefficients are zero (the columns the
    pivoting dropped), and a vector right-hand side gives the matrix one's column."""
    from solver.dense import factorise_dense

    rng = np.random.default_rng(7)

    def complex_normal(*shape):
        return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)

    square = complex_normal(50, 50) + 10 * np.eye(50)
    rhs = complex_normal(50, 4)
    solve, rcond = factorise_dense(square)
    assert np.abs(solve(rhs) - np.linalg.solve(square, rhs)).max() < 1e-12 * np.abs(rhs).max()
    assert 1e-4 < rcond <= 1.0

    frame = complex_normal(60, 40) @ complex_normal(40, 60) * np.logspace(0, 6, 60)
    rhs = complex_normal(60, 3)
    solve, _ = factorise_dense(frame)
    x = solve(rhs)
    optimum = np.linalg.lstsq(frame, rhs, rcond=None)[0]
    residual = np.linalg.norm(frame @ x - rhs, axis=0)
    best = np.linalg.norm(frame @ optimum - rhs, axis=0)
    np.testing.assert_allclose(residual, best, rtol=1e-10)
    assert np.all(np.count_nonzero(x, axis=0) == 40)
    np.testing.assert_allclose(solve(rhs[:, 1]), x[:, 1], rtol=0, atol=1e-14 * np.abs(x).max())


def _decade_rule(points: int = 60) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``t``, ``1 - t`` (kept apart: near 1 ``t`` rounds before ``1 - t``) and weights of a rule
    on (0, 1) cut at every decade from 1e-40 towards both ends, ``points`` Gauss points a
    panel: another rule than the solver's for integrands with logarithmic ends."""
    x, w = np.polynomial.legendre.leggauss(points)
    cuts = np.concatenate([[0.0], 10.0 ** -np.arange(40.0, 0.0, -1.0), [0.25, 0.5]])
    half = 0.5 * np.diff(cuts)
    near = ((cuts[:-1] + half)[:, None] + half[:, None] * x).ravel()
    weights = (half[:, None] * w).ravel()
    return (np.concatenate([near, 1.0 - near]), np.concatenate([1.0 - near, near]),
            np.tile(weights, 2))


@pytest.mark.parametrize("n", [21, 70])
def test_a_lines_logarithmic_load_functions_are_orthonormal_parts_that_span_the_singular_terms(n):
    r""":func:`solver.joint_rules.load_function_values` at mixed ends: the functions after the
    Legendre ones are orthonormal and orthogonal to them in :math:`L^2(0, 1)` (Gram matrix
    within 1e-10 of the identity, by a rule graded by decades, not the solver's), and with the
    Legendre ones they span :math:`\ln t`, :math:`t\ln t` at a singular start and
    :math:`\ln(1 - t)`, :math:`(1 - t)\ln(1 - t)` at a singular end (a least-squares fit of
    a combination leaves 1e-10 of it). Without singular ends they are the Legendre
    functions."""
    from solver.joint_rules import (
        _orthonormal_singular_parts,
        _singular_functions,
        load_function_values,
    )

    t, s, weights = _decade_rule()
    for ends in ((True, False), (False, True), (True, True)):
        k = n - 2 * sum(ends)
        legendre = np.polynomial.legendre.legvander(2.0 * t - 1.0, k - 1)
        singular = np.column_stack([legendre, *_singular_functions(t, s, ends)])
        values = np.column_stack([legendre, singular @ _orthonormal_singular_parts(k, ends)])
        gram = values.T @ (weights[:, None] * values)
        assert np.abs(gram[k:, k:] - np.eye(n - k)).max() < 1e-10, ends
        assert np.abs(gram[:k, k:]).max() < 1e-10, ends
        # on a line of 0.8 m, as the solver evaluates them
        u = np.linspace(0.001, 0.999, 400)
        functions = load_function_values(0.8 * u, 0.8, n, ends)
        target = np.column_stack([np.polynomial.legendre.legvander(2.0 * u - 1.0, k - 1),
                                  *_singular_functions(u, 1.0 - u, ends)]) @ np.linspace(1, 2, n)
        fit = functions @ np.linalg.lstsq(functions, target, rcond=None)[0]
        assert np.linalg.norm(fit - target) < 1e-10 * np.linalg.norm(target), ends
    sigma = np.linspace(0.05, 0.75, 9)
    assert np.array_equal(load_function_values(sigma, 0.8, n),
                          np.polynomial.legendre.legvander(2.0 * sigma / 0.8 - 1.0, n - 1))
