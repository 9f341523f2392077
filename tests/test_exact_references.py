"""Self-checks of the exact series references in ``tests/exact.py``.

Every check compares the references with something derived independently of the code
path under test (another series, a hand closed form, the plate equation, the boundary and
joint laws written again here from the conventions, reciprocity, the power balance).
"""

import numpy as np
import pytest
from exact import (
    EdgeLoad,
    Section,
    complex_rigidity,
    coplanar,
    hinge,
    levy_chain,
    levy_plate,
    navier_point_force,
)

# Steel, 1 mm.
E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 1e-3, 0.01
D = complex_rigidity(E, H, NU, ETA)
RHO_H = RHO * H
STEEL = Section(0.30, D, NU, RHO_H)
# Aluminium, 2 mm, for chains of dissimilar plates.
ALU = Section(0.22, complex_rigidity(70e9, 2e-3, 0.33, 0.02), 0.33, 2700.0 * 2e-3)
# Three dissimilar plates and two damped joints (one coplanar with a line mass, one hinge).
CHAIN3 = [STEEL, ALU, Section(0.25, D, NU, RHO_H)]
JOINTS3 = [coplanar(10**1.5, 0.1, 0.05), hinge(10**0.5, 0.3)]
LX, LY = 0.5, 0.4
OMEGA = 2 * np.pi * 400.0


def interior_grid(Lx, Ly, n=10):
    """Cell-centred ``n x n`` grid of the plate."""
    x = (np.arange(n) + 0.5) / n * Lx
    y = (np.arange(n) + 0.5) / n * Ly
    return np.meshgrid(x, y)


def rel(a, b):
    """Relative L2 difference of ``a`` with respect to ``b``."""
    return np.linalg.norm(np.ravel(a - b)) / np.linalg.norm(np.ravel(b))


def edge_quantities(field, edge, y):
    """``w, theta, M_n, K_n`` on a left/right edge, written from the conventions."""
    sec = field.section
    x, n = (0.0, -1.0) if edge == "left" else (sec.Lx, 1.0)
    d = field.derivative
    w = d(x, y)
    theta = n * d(x, y, 1, 0)
    moment = -sec.D * (d(x, y, 2, 0) + sec.nu * d(x, y, 0, 2))
    shear = -n * sec.D * (d(x, y, 3, 0) + (2 - sec.nu) * d(x, y, 1, 2))
    return w, theta, moment, shear


def scales(field):
    """Deflection, slope, moment and shear scales of a plate response."""
    X, Y = interior_grid(field.section.Lx, LY)
    w_ref = np.max(np.abs(field.w(X, Y)))
    kappa = np.abs(field.section.rho_h * field.omega**2 / field.section.D) ** 0.25
    Dm = np.abs(field.section.D)
    return w_ref, w_ref * kappa, Dm * w_ref * kappa**2, Dm * w_ref * kappa**3


@pytest.mark.parametrize("freq", [155.0, 400.0])
def test_levy_matches_navier_simply_supported(freq):
    omega = 2 * np.pi * freq
    X, Y = interior_grid(LX, LY)
    x0, y0 = 0.13, 0.17
    levy = levy_plate(LX, LY, D, NU, RHO_H, omega, point_forces=[(x0, y0, 1.0)])
    navier = navier_point_force(LX, LY, D, RHO_H, omega, x0, y0, 1.0, X, Y)
    # Grid points are >= 5 mm from the force, where both truncated series converge
    # exponentially/with oscillating tails: the measured difference is ~1e-12.
    assert rel(levy.w(X, Y), navier) < 1e-6


def test_half_sine_edge_moment_closed_form():
    m0 = 2.0 - 0.5j
    sol = levy_plate(LX, LY, D, NU, RHO_H, OMEGA,
                     edge_loads=[EdgeLoad("left", "edge_moment", m0, "half_sine")])
    # Hand solution: W'''' - 2 a^2 W'' + (a^4 - kappa^4) W = 0 factorises into
    # (d^2 - s1^2)(d^2 - s2^2); sinh(s (L - x)) / sinh(s L) satisfy W(L) = W''(L) = 0 and
    # W(0) = 0, W''(0) = -m0 / D* (from M_n = -D* W'' on a SS edge) fix their weights.
    a = np.pi / LY
    kappa2 = np.sqrt(RHO_H * OMEGA**2 / D)
    s1, s2 = np.sqrt(a**2 + kappa2), np.sqrt(a**2 - kappa2)
    X, Y = interior_grid(LX, LY)
    W = m0 / (2 * kappa2 * D) * (np.sinh(s2 * (LX - X)) / np.sinh(s2 * LX)
                                 - np.sinh(s1 * (LX - X)) / np.sinh(s1 * LX))
    # Both are exact single-harmonic expressions: only round-off separates them.
    assert rel(sol.w(X, Y), W * np.sin(a * Y)) < 1e-10


def test_derivatives_match_finite_differences():
    sol = levy_plate(LX, LY, D, NU, RHO_H, OMEGA, "clamped", "free",
                     point_forces=[(0.13, 0.17, 1.0)],
                     edge_loads=[EdgeLoad("right", "edge_shear", 3.0, "half_sine")])
    p = sol.plates[0]
    x = np.array([0.05, 0.3, 0.42])
    y = np.array([0.07, 0.25, 0.33])
    h = 1e-5
    # Central differences: truncation (s h)^2 / 6 plus round-off eps / (s h), with the
    # relevant wavenumbers s ~ 40..100 /m at these points (>= 8 cm from the force);
    # measured 2e-8, tolerance 1e-5 (a wrong derivative order or sign gives O(1)).
    for k in (1, 2, 3):
        fd = (p.derivative(x + h, y, k - 1, 0) - p.derivative(x - h, y, k - 1, 0)) / (2 * h)
        exact = p.derivative(x, y, k, 0)
        assert np.max(np.abs(fd - exact)) < 1e-5 * np.max(np.abs(exact)), k
    fd = (p.derivative(x, y + h, 1, 1) - p.derivative(x, y - h, 1, 1)) / (2 * h)
    assert np.max(np.abs(fd - p.derivative(x, y, 1, 2))) < 1e-5 * np.max(np.abs(fd))


def test_plate_equation_holds_in_chain():
    # Residual of D* biharmonic(w) - rho_h omega^2 w at points away from the forces, with
    # w_xxxx by a central difference of the analytic w_xxx.
    sol = levy_chain(CHAIN3, LY, OMEGA, JOINTS3, "clamped", "free",
                     point_forces=[(1, 0.1, 0.21, 1.0)],
                     edge_loads=[EdgeLoad("right", "edge_shear", 2.0, "half_sine")])
    h = 1e-5
    for p in sol.plates:
        sec = p.section
        x = np.array([0.2, 0.5, 0.8]) * sec.Lx
        y = np.array([0.1, 0.3, 0.37])
        d = p.derivative
        w4x = (d(x + h, y, 3, 0) - d(x - h, y, 3, 0)) / (2 * h)
        bih = w4x + 2 * d(x, y, 2, 2) + d(x, y, 0, 4)
        inertia = sec.rho_h * OMEGA**2 * d(x, y)
        # Finite-difference error of w_xxxx (see above): measured <= 2.4e-8 relative.
        assert np.max(np.abs(sec.D * bih - inertia)) < 1e-6 * np.max(np.abs(inertia))


@pytest.mark.parametrize("left, right", [
    ("clamped", "free"),
    ("simply_supported", "clamped"),
    ("free", "simply_supported"),
    ("free", "free"),
])
def test_boundary_conditions(left, right):
    bcs = {"left": left, "right": right}
    loads = []
    amplitude = {"edge_moment": 0.7 - 0.2j, "edge_shear": 3.0 + 1.0j}
    for edge, bc in bcs.items():
        if bc in ("simply_supported", "free"):
            loads.append(EdgeLoad(edge, "edge_moment", amplitude["edge_moment"], "half_sine"))
        if bc == "free":
            loads.append(EdgeLoad(edge, "edge_shear", amplitude["edge_shear"], "half_sine"))
    sol = levy_plate(LX, LY, D, NU, RHO_H, OMEGA, left, right,
                     point_forces=[(0.13, 0.17, 1.0), (0.41, 0.3, -0.5j)], edge_loads=loads)
    p = sol.plates[0]
    w_s, t_s, m_s, k_s = scales(p)
    y = np.linspace(0.02, LY - 0.02, 7)
    shape = np.sin(np.pi * y / LY)
    for edge, bc in bcs.items():
        w, theta, moment, shear = edge_quantities(p, edge, y)
        # The field quantities of LevyPlateField agree with the conventions written here.
        np.testing.assert_allclose(p.edge_slope(edge, y), theta, rtol=1e-12, atol=0)
        np.testing.assert_allclose(p.edge_moment(edge, y), moment, rtol=1e-12, atol=0)
        np.testing.assert_allclose(p.edge_shear(edge, y), shear, rtol=1e-12, atol=0)
        m_load = amplitude["edge_moment"] * shape
        p_load = amplitude["edge_shear"] * shape
        # Edge values of the series: the force terms converge like exp(-alpha d) (d >= 9 cm)
        # and each harmonic satisfies its condition exactly, so only round-off remains.
        tol = 1e-9
        if bc == "clamped":
            assert np.max(np.abs(w)) < tol * w_s
            assert np.max(np.abs(theta)) < tol * t_s
        if bc == "simply_supported":
            assert np.max(np.abs(w)) < tol * w_s
            assert np.max(np.abs(moment - m_load)) < tol * m_s
        if bc == "free":
            assert np.max(np.abs(moment - m_load)) < tol * m_s
            assert np.max(np.abs(shear - p_load)) < tol * k_s
            assert np.max(np.abs(w)) > 1e-3 * w_s


def test_uniform_edge_loads():
    p0, m0 = 2.0, -1.5
    n_terms = 2001
    sol = levy_plate(LX, LY, D, NU, RHO_H, OMEGA, "simply_supported", "free",
                     edge_loads=[EdgeLoad("left", "edge_moment", m0),
                                 EdgeLoad("right", "edge_shear", p0)], n_terms=n_terms)
    p = sol.plates[0]
    y = np.array([LY / 2])
    _, _, moment, _ = edge_quantities(p, "left", y)
    _, _, _, shear = edge_quantities(p, "right", y)
    # At mid-edge the sine series of a uniform load, sum_{m odd} 4 c / (m pi) sin(m pi / 2),
    # alternates with decreasing terms: its error is below the first omitted term.
    bound = 4.0 / (np.pi * (n_terms + 2))
    assert abs(moment[0] - m0) < bound * abs(m0)
    assert abs(shear[0] - p0) < bound * abs(p0)
    # ... and the deflection series (terms ~ m^-3, m^-4) is converged: doubling the
    # harmonics changes w by far less than 1e-4.
    X, Y = interior_grid(LX, LY)
    finer = levy_plate(LX, LY, D, NU, RHO_H, OMEGA, "simply_supported", "free",
                       edge_loads=sol.edge_loads, n_terms=2 * n_terms)
    assert rel(finer.w(X, Y), sol.w(X, Y)) < 1e-7


def test_stiff_coplanar_joint_is_a_continuous_plate():
    a, b = Section(0.3, D, NU, RHO_H), Section(0.25, D, NU, RHO_H)
    edge_loads = [EdgeLoad("right", "edge_shear", 2.0 - 1.0j, "half_sine")]
    chain = levy_chain([a, b], LY, OMEGA, [coplanar(1e8, 0.1)], "clamped", "free",
                       point_forces=[(0, 0.1, 0.17, 1.0), (1, 0.15, 0.23, 0.5j)],
                       edge_loads=edge_loads)
    whole = levy_plate(0.55, LY, D, NU, RHO_H, OMEGA, "clamped", "free",
                       point_forces=[(0.1, 0.17, 1.0), (0.45, 0.23, 0.5j)],
                       edge_loads=edge_loads)
    Xa, Ya = interior_grid(0.3, LY)
    Xb, Yb = interior_grid(0.25, LY)
    chain_w = np.concatenate([chain.w(Xa, Ya, 0).ravel(), chain.w(Xb, Yb, 1).ravel()])
    whole_w = np.concatenate([whole.w(Xa, Ya).ravel(), whole.w(Xb + 0.3, Yb).ravel()])
    # The joint compliance makes a difference O(|D| / (k L)): measured 2.6e-6, scaling
    # exactly as 1/k (2.6e-4 at k = 1e6, 2.6e-8 at k = 1e10); the brief asks <= 1e-3.
    assert rel(chain_w, whole_w) < 2e-5


@pytest.mark.parametrize("joint", [coplanar(1e-6, 0.1, 0.05), hinge(1e-6, 0.1)])
def test_soft_joint_is_moment_free(joint):
    chain = levy_chain([STEEL, ALU], LY, OMEGA, [joint], "clamped", "simply_supported",
                       point_forces=[(0, 0.1, 0.17, 1.0)])
    y = np.linspace(0.02, LY - 0.02, 9)
    _, _, m_a, _ = edge_quantities(chain.plates[0], "right", y)
    _, _, m_b, _ = edge_quantities(chain.plates[1], "left", y)
    _, _, m_clamp, _ = edge_quantities(chain.plates[0], "left", y)
    typical = np.max(np.abs(m_clamp))
    # |M| = |k* Theta| ~ k |theta| ~ 1e-9 of the clamping moment (measured 7e-10, 8e-10).
    assert np.max(np.abs(m_a)) < 1e-6 * typical
    assert np.max(np.abs(m_b)) < 1e-6 * typical
    if joint.kind == "hinge":
        # Pinned line with (almost) no moment: plate A is a plate simply supported there.
        alone = levy_plate(STEEL.Lx, LY, D, NU, RHO_H, OMEGA, "clamped", "simply_supported",
                           point_forces=[(0.1, 0.17, 1.0)])
        X, Y = interior_grid(STEEL.Lx, LY)
        # Measured 9e-10 (the residual moment k* Theta).
        assert rel(chain.w(X, Y, 0), alone.w(X, Y)) < 1e-6


@pytest.mark.parametrize("joint", [coplanar(10**1.5, 0.1, 0.05), hinge(10**1.5, 0.1)])
def test_joint_laws(joint):
    chain = levy_chain([STEEL, ALU], LY, OMEGA, [joint], "simply_supported", "free",
                       point_forces=[(0, 0.1, 0.17, 1.0), (1, 0.12, 0.3, 0.4 - 0.2j)])
    A, B = chain.plates
    y = np.linspace(0.02, LY - 0.02, 9)
    w_a, th_a, m_a, k_a = edge_quantities(A, "right", y)
    w_b, th_b, m_b, k_b = edge_quantities(B, "left", y)
    w_s, t_s, m_s, k_s = scales(A)
    kstar = joint.k * (1 + 1j * joint.zeta)
    # Each harmonic satisfies the laws exactly and the series converge exponentially at
    # the joint (forces >= 10 cm away): round-off level.
    tol = 1e-9
    assert np.max(np.abs(m_a - m_b)) < tol * m_s
    assert np.max(np.abs(m_a - kstar * (th_a + th_b))) < tol * m_s
    assert np.max(np.abs(m_a)) > 1e-3 * m_s
    if joint.kind == "coplanar":
        assert np.max(np.abs(w_a - w_b)) < tol * w_s
        assert np.max(np.abs(k_a + k_b - OMEGA**2 * joint.mu * w_a)) < tol * k_s
        assert np.max(np.abs(w_a)) > 1e-3 * w_s
    else:
        assert np.max(np.abs(w_a)) < tol * w_s
        assert np.max(np.abs(w_b)) < tol * w_s


def test_reciprocity_three_plate_chain():
    a, b = (0, 0.11, 0.13), (2, 0.17, 0.29)

    def response(source, target):
        sol = levy_chain(CHAIN3, LY, OMEGA, JOINTS3, "free", "clamped",
                         point_forces=[(*source, 1.0)])
        return sol.w(target[1], target[2], target[0])

    w_ab, w_ba = response(a, b), response(b, a)
    # The per-harmonic operators are complex symmetric, so reciprocity holds harmonic by
    # harmonic: only round-off (~1e-14) separates the two.
    assert abs(w_ab - w_ba) < 1e-8 * abs(w_ab)


@pytest.mark.parametrize("case", ["edge_shear", "point_force"])
def test_power_balance(case):
    if case == "edge_shear":
        # A half-sine line load excites harmonic 1 only: exact input power.
        sol = levy_chain(CHAIN3, LY, OMEGA, JOINTS3, "free", "clamped",
                         edge_loads=[EdgeLoad("left", "edge_shear", 1.0, "half_sine")])
        y = np.linspace(0, LY, 2001)
        w_edge = sol.w(np.zeros_like(y), y, 0)
        # Independent quadrature of 0.5 Re[int p* j omega w ds]: the trapezoid rule is
        # spectrally accurate for this sin^2-shaped integrand (measured 1e-15).
        p_in = 0.5 * np.real(np.trapezoid(np.sin(np.pi * y / LY) * 1j * OMEGA * w_edge, y))
        assert abs(p_in - sol.input_power()) < 1e-6 * abs(p_in)
    else:
        # Point force and uniform edge moment (plus an edge shear): the truncated series
        # balances exactly
        # harmonic by harmonic, so a few harmonics suffice.
        sol = levy_chain(CHAIN3, LY, OMEGA, JOINTS3, "simply_supported", "free",
                         point_forces=[(1, 0.09, 0.17, 1.0)],
                         edge_loads=[EdgeLoad("left", "edge_moment", 0.3j),
                                     EdgeLoad("right", "edge_shear", -0.5, "half_sine")],
                         n_terms=40)
    injected = sol.input_power()
    joint_power = sum(sol.joint_dissipated_power(j) for j in range(2))
    dissipated = sol.dissipated_power()
    assert injected > 0
    # The joints take a significant share, so their law and sign are tested too.
    assert joint_power > 1e-2 * dissipated
    # Limited by the Gauss quadrature of the bending form (~1e-13) and round-off in the
    # imaginary parts (terms ~1/eta = 100 times the dissipation): measured 4e-15.
    assert abs(injected - dissipated) < 1e-8 * injected


def test_invalid_loads_rejected():
    with pytest.raises(ValueError):
        levy_plate(LX, LY, D, NU, RHO_H, OMEGA, "clamped", "free",
                   edge_loads=[EdgeLoad("left", "edge_shear", 1.0)])
    with pytest.raises(ValueError):
        levy_plate(LX, LY, D, NU, RHO_H, OMEGA, "clamped", "free",
                   point_forces=[(0.0, 0.2, 1.0)])
