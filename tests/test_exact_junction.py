r"""Self-checks of the junction-line Levy reference in ``tests/exact_junction.py``.

Each check compares ``junction_levy`` with something it does not compute itself: the hinge
chain of ``tests/exact.py`` (``levy_chain``, separate code), the same assembly described with
other frames (displacement vectors compared in 3D), the power balance, reciprocity, the
junction laws re-derived here with 3D vectors, and the limit of a vanishing stiffener spring.

Plates: steel, ``Ly = 0.4`` m, 0.45-0.6 m long, skin 1 mm, stiffeners 1 or 2 mm, 250 Hz.  The
identities hold harmonic by harmonic, so ``N_TERMS = 400`` harmonics suffice (both sides of a
comparison use the same truncation).

The T: skin ``S1 | S2`` in the ``x-y`` plane meeting on the line ``x = 0.5``, ``z = 0``,
``0 <= y <= Ly``, and stiffener ``T1`` standing on that line along ``+z``.  The X adds ``T2``
hanging along ``-z``.
"""

import math

import numpy as np
import pytest
from exact import Section, complex_rigidity, hinge, levy_chain
from exact_junction import JunctionLine, StripPlate, junction_levy

E, NU, RHO, ETA = 2.1e11, 0.3, 7800.0, 0.01
D_SKIN, RHO_H_SKIN = complex_rigidity(E, 1e-3, NU, ETA), RHO * 1e-3
D_STIFF, RHO_H_STIFF = complex_rigidity(E, 2e-3, NU, ETA), RHO * 2e-3
LY = 0.4
OMEGA = 2 * np.pi * 250.0
N_TERMS = 400
L_S1, L_S2, L_T1, L_T2 = 0.5, 0.6, 0.45, 0.55
X_LINE = L_S1

X_HAT, Y_HAT, Z_HAT = np.eye(3)
# Load of the T and X checks: unit force along +z on S1 at this 3D point.
LOAD_POINT, LOAD_DIRECTION = np.array([0.3, 0.13, 0.0]), Z_HAT
# Finite lossy springs (N m/rad per m; D* kappa ~ 600 N m/rad/m for the 1 mm skin at 250 Hz).
K_T1, K_S2, K_T2 = 300.0 * (1 + 0.3j), 200.0 * (1 + 0.1j), 80.0 * (1 + 0.05j)


def strip(length, origin, x_axis, y_axis, thick=False, left="simply_supported",
          right="simply_supported"):
    """Steel ``StripPlate`` (1 mm, or 2 mm if ``thick``) placed by the given frame."""
    D, rho_h = (D_STIFF, RHO_H_STIFF) if thick else (D_SKIN, RHO_H_SKIN)
    return StripPlate(length, D, NU, rho_h, tuple(np.asarray(origin, float)),
                      tuple(np.asarray(x_axis, float)), tuple(np.asarray(y_axis, float)),
                      left, right)


def normal(plate):
    """Unit vector ``e_z = x_axis x y_axis`` along which the plate's ``w`` points."""
    return np.cross(plate.x_axis, plate.y_axis)


def to_local(plate, points):
    """Local ``(x, y)`` of 3D ``points`` (shape ``(..., 3)``) lying on ``plate``."""
    rel = np.asarray(points, float) - np.asarray(plate.origin, float)
    return rel @ np.asarray(plate.x_axis, float), rel @ np.asarray(plate.y_axis, float)


def to_global(plate, x, y):
    """3D points of the local ``(x, y)`` of ``plate``."""
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    return (np.asarray(plate.origin, float) + x[..., None] * np.asarray(plate.x_axis, float)
            + y[..., None] * np.asarray(plate.y_axis, float))


def displacement(sol, name, points):
    """Displacement vector ``w e_z`` of plate ``name`` at 3D ``points`` on it."""
    plate = sol.plates[name]
    x, y = to_local(plate, points)
    return sol.w(name, x, y)[..., None] * normal(plate)


def local_grid(length, nx=13, ny=11):
    """Local grid of a plate, edges included."""
    return np.meshgrid(np.linspace(0.0, length, nx), np.linspace(0.0, LY, ny))


def solve(plates, lines, load_plate, point=LOAD_POINT, direction=LOAD_DIRECTION,
          n_terms=N_TERMS):
    """``junction_levy`` under a unit force given in 3D (point on ``load_plate``, direction)."""
    x0, y0 = to_local(plates[load_plate], point)
    force = float(np.dot(normal(plates[load_plate]), direction))
    return junction_levy(plates, lines, LY, OMEGA, (load_plate, x0, y0, force), n_terms)


# --------------------------------------------------------------------------------------
# Assemblies.  Each description returns ``(plates, members)``: the plates and the
# ``JunctionLine`` members ``name -> (end, k)``.  Variants describe the same physical plate.
# --------------------------------------------------------------------------------------


def skin_s1(k, variant="plain"):
    """S1 on ``[0, 0.5] x [0, Ly] x {0}``, clamped at ``x = 0``, right edge on the line."""
    if variant == "plain":
        return strip(L_S1, (0, 0, 0), X_HAT, Y_HAT, left="clamped"), ("right", k)
    if variant == "y_reversed":  # y_axis = -e: sigma = -1 for the line's first member
        return strip(L_S1, (0, LY, 0), X_HAT, -Y_HAT, left="clamped"), ("right", k)
    assert variant == "both_reversed"  # x and y reversed: same normal, line on its left edge
    return strip(L_S1, (X_LINE, LY, 0), -X_HAT, -Y_HAT, right="clamped"), ("left", k)


def skin_s2(k):
    """S2 on ``[0.5, 1.1] x [0, Ly] x {0}``, simply supported at ``x = 1.1``."""
    return strip(L_S2, (X_LINE, 0, 0), X_HAT, Y_HAT), ("left", k)


def stiffener_t1(k, variant="plain"):
    """T1 (2 mm) on ``{0.5} x [0, Ly] x [0, 0.45]``, free at its top edge.

    ``plain``: ``x_axis = +z``, ``y_axis = +y``, ``e_z = -x``, line on its left edge.
    ``normal_flipped``: ``x_axis = -z`` from the top, line on its right edge, ``e_z = +x``.
    ``y_reversed``: ``y_axis = -y`` from ``y = Ly`` (sigma = -1), ``e_z = +x``.
    ``both_reversed``: ``x_axis = -z`` and ``y_axis = -y``, ``e_z = -x``.
    """
    top = L_T1 * Z_HAT
    start, end = np.array([X_LINE, 0, 0]), np.array([X_LINE, LY, 0])
    if variant == "plain":
        return strip(L_T1, start, Z_HAT, Y_HAT, True, right="free"), ("left", k)
    if variant == "normal_flipped":
        return strip(L_T1, start + top, -Z_HAT, Y_HAT, True, left="free"), ("right", k)
    if variant == "y_reversed":
        return strip(L_T1, end, Z_HAT, -Y_HAT, True, right="free"), ("left", k)
    assert variant == "both_reversed"
    return strip(L_T1, end + top, -Z_HAT, -Y_HAT, True, left="free"), ("right", k)


def stiffener_t2(k):
    """T2 (1 mm) on ``{0.5} x [0, Ly] x [-0.55, 0]``, clamped at its bottom edge.

    Described with ``y_axis = -y`` from ``y = Ly`` (sigma = -1) and ``x_axis = -z``.
    """
    return strip(L_T2, (X_LINE, LY, 0), -Z_HAT, -Y_HAT, right="clamped"), ("left", k)


def assemble(parts):
    """``(plates, [JunctionLine])`` from ``{name: (plate, (end, k))}`` (order kept)."""
    plates = {name: plate for name, (plate, _) in parts.items()}
    return plates, [JunctionLine({name: member for name, (_, member) in parts.items()})]


def t_junction(k_t1, k_skin=math.inf, s1="plain", t1="plain"):
    """The T: rigid (or ``k_skin``) skin members, stiffener spring ``k_t1``."""
    return assemble({"S1": skin_s1(k_skin, s1), "S2": skin_s2(k_skin),
                     "T1": stiffener_t1(k_t1, t1)})


def x_junction():
    """The X: S1 rigid, S2, T1 and T2 on finite lossy springs."""
    return assemble({"S1": skin_s1(math.inf), "S2": skin_s2(K_S2), "T1": stiffener_t1(K_T1),
                     "T2": stiffener_t2(K_T2)})


def max_relative(a, b):
    """``max |a - b| / max |b|``."""
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(b))


# --------------------------------------------------------------------------------------
# 1. Two members of stiffness 2k = the hinge(k) joint of exact.py
# --------------------------------------------------------------------------------------


def series_hinge(k_a, k_b):
    """``hinge`` of the two member springs in series, ``k* = k_a k_b / (k_a + k_b)``."""
    if np.isinf(k_a) or np.isinf(k_b):
        k_star = k_b if np.isinf(k_a) else k_a
    else:
        k_star = k_a * k_b / (k_a + k_b)
    k_star = complex(k_star)
    return hinge(k_star.real, k_star.imag / k_star.real if k_star.real else 0.0)


TWO_MEMBER_SPRINGS = [
    (60.0, 60.0),                                # 2k, 2k: hinge(30)
    (1200.0 * (1 + 0.2j), 1200.0 * (1 + 0.2j)),  # hinge(600, 0.2)
    (2e4 * (1 + 0.05j), 2e4 * (1 + 0.05j)),      # hinge(1e4, 0.05)
    (100.0 * (1 + 0.1j), 300.0 * (1 + 0.3j)),    # unequal springs in series
    (math.inf, 600.0 * (1 + 0.2j)),              # rigid + spring: hinge(600, 0.2)
    (0.0, math.inf),                             # free rotation: two simply supported edges
]


@pytest.mark.parametrize("angle", [0.0, 90.0, 135.0])
@pytest.mark.parametrize("k_a, k_b", TWO_MEMBER_SPRINGS)
def test_two_members_equal_hinge_chain(k_a, k_b, angle):
    """Two members on springs ``k_a``, ``k_b`` give ``exact.levy_chain`` with a hinge.

    A (0.5 m, clamped at ``x = 0``) ends on the line with its right edge, B (0.6 m, free at
    its far end) starts with its left edge; B's frame is A's rotated by ``angle`` about the
    line (0: coplanar, same frame orientation; 90: an L; 135).  ``m_A + m_B = 0`` makes the
    two springs act in series: ``M_A = M_B = k* (theta_A + theta_B)`` with
    ``k* = k_a k_b / (k_a + k_b)`` (``2k, 2k -> k``; ``inf, k -> k``; ``0, inf -> 0``), the
    ``hinge`` joint of ``tests/exact.py``.  The line holds translation and the model has no
    membrane coupling, so the fold angle is irrelevant to the local fields.  Both sides use
    the same 400 harmonics and the same ``LevyPlateField`` basis, so they agree harmonic by
    harmonic up to the round-off of two differently assembled 8x8 solves: 1e-9 relative to
    the largest ``|w|`` of the pair (~1e-15 measured; with ``0, inf`` the unloaded B is
    decoupled and both fields of B are round-off noise ~1e-32 of A's).
    """
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    plates = {"A": strip(L_S1, (0, 0, 0), X_HAT, Y_HAT, left="clamped"),
              "B": strip(L_S2, (L_S1, 0, 0), c * X_HAT + s * Z_HAT, Y_HAT, right="free")}
    line = JunctionLine({"A": ("right", k_a), "B": ("left", k_b)})
    sol = junction_levy(plates, [line], LY, OMEGA, ("A", 0.3, 0.13, 1.0), N_TERMS)
    ref = levy_chain([Section(L_S1, D_SKIN, NU, RHO_H_SKIN), Section(L_S2, D_SKIN, NU, RHO_H_SKIN)],
                     LY, OMEGA, [series_hinge(k_a, k_b)], "clamped", "free",
                     [(0, 0.3, 0.13, 1.0)], n_terms=N_TERMS)
    grids = [local_grid(plates[name].length) for name in ("A", "B")]
    scale = max(np.max(np.abs(ref.w(x, y, i))) for i, (x, y) in enumerate(grids))
    for i, (name, (x, y)) in enumerate(zip(("A", "B"), grids)):
        assert np.max(np.abs(sol.w(name, x, y) - ref.w(x, y, i))) < 1e-9 * scale


def test_two_lines_equal_hinge_chain():
    """A U of three plates on two lines gives ``levy_chain`` with two hinges.

    P1 (0.5 m, ``z = 0``, clamped at ``x = 0``), P2 (0.45 m) standing on ``x = 0.5`` and P3
    (0.6 m, free end) lying at ``z = 0.45`` back over P1.  Line 0: P1 rigid, P2 on
    ``2 k1``; line 1 lists P3 first (so it defines ``e``), rigid, and P2 on ``k2``; P3 is
    described with ``x_axis = -x``, ``y_axis = -y`` (P2 has ``sigma = -1`` on line 1).  The
    chain's P3 frame is P2's rotated about line 1 (``x = -x``, ``y = +y``), so its local
    ``(x, y)`` is our ``(x, Ly - y)`` with ``w`` reversed (the normals are ``-z`` and
    ``+z``).  A rigid tie in series with a spring ``k`` is ``hinge(k)``: the chain has
    ``hinge(2 k1)`` and ``hinge(k2)``.  This exercises the bookkeeping of several lines
    (unknowns, ``sigma``, ``T_m``); same harmonics on both sides: 1e-9 relative (~1e-15
    measured).
    """
    k1, k2 = 150.0 * (1 + 0.1j), 900.0 * (1 + 0.25j)
    plates = {"P1": strip(L_S1, (0, 0, 0), X_HAT, Y_HAT, left="clamped"),
              "P2": strip(L_T1, (X_LINE, 0, 0), Z_HAT, Y_HAT),
              "P3": strip(L_S2, (X_LINE, LY, L_T1), -X_HAT, -Y_HAT, right="free")}
    lines = [JunctionLine({"P1": ("right", math.inf), "P2": ("left", 2 * k1)}),
             JunctionLine({"P3": ("left", math.inf), "P2": ("right", k2)})]
    sol = junction_levy(plates, lines, LY, OMEGA, ("P1", 0.3, 0.13, 1.0), N_TERMS)
    assert sol.sigmas[1] == {"P3": 1.0, "P2": -1.0}
    sections = [Section(p.length, p.D, NU, p.rho_h) for p in plates.values()]
    ref = levy_chain(sections, LY, OMEGA, [series_hinge(math.inf, 2 * k1),
                                           series_hinge(math.inf, k2)],
                     "clamped", "free", [(0, 0.3, 0.13, 1.0)], n_terms=N_TERMS)
    for i, name in enumerate(("P1", "P2")):
        x, y = local_grid(plates[name].length)
        assert max_relative(sol.w(name, x, y), ref.w(x, y, i)) < 1e-9
    x, y = local_grid(L_S2)
    assert max_relative(sol.w("P3", x, LY - y), -ref.w(x, y, 2)) < 1e-9


# --------------------------------------------------------------------------------------
# 2. Power balance
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("assembly, load_plate, point", [
    ("T", "S1", LOAD_POINT),
    ("T", "T1", np.array([X_LINE, 0.27, 0.2])),
    ("X", "S1", LOAD_POINT),
    ("X", "T2", np.array([X_LINE, 0.31, -0.35])),
])
def test_power_balance(assembly, load_plate, point):
    """Input power of the force = power dissipated in the plates and the springs.

    T: skin members rigid, stiffener on ``300 (1 + 0.3j)``; X: S1 rigid, S2, T1, T2 on
    finite lossy springs (T2 with ``sigma = -1``), loaded on the skin or on a stiffener.  The
    massless line does no work and the harmonics are orthogonal in every term, so the
    balance holds harmonic by harmonic for any truncation.  The only error left is the
    Gauss quadrature of the bending energy (~1e-13 relative, ``exact.LevyPlateField``):
    1e-10 relative (~1e-14 measured).  The springs must dissipate a sizeable share of the
    total (1.5 % to 29 % here), otherwise a wrong spring term would go unnoticed.
    """
    plates, lines = t_junction(K_T1) if assembly == "T" else x_junction()
    sol = solve(plates, lines, load_plate, point, normal(plates[load_plate]))
    p_in = sol.input_power()
    springs = sum(sol.spring_dissipated_power(0, name) for name in lines[0].members)
    assert p_in > 0
    assert springs > 1e-3 * p_in
    assert abs(sol.dissipated_power() - p_in) < 1e-10 * p_in


# --------------------------------------------------------------------------------------
# 3. Reciprocity
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("t1", ["plain", "y_reversed"])
def test_reciprocity_skin_stiffener(t1):
    """``w_T1(Q)`` under a unit force at P on S1 = ``w_S1(P)`` under a unit force at Q on T1.

    T with rigid skin members and T1 on the lossy spring ``300 (1 + 0.3j)``; T1 described
    with ``sigma = +1`` or ``-1``.  Forces and deflections are along the plates' own normals,
    the bending forms and the spring energy are complex symmetric, so the transfer is
    symmetric, harmonic by harmonic: it holds for any truncation and the tolerance 1e-8 only
    covers round-off (~1e-15 measured).  The transfer must not be negligible (it is ~1e-2
    of the drive-point deflection), otherwise the check would be empty.
    """
    plates, lines = t_junction(K_T1, t1=t1)
    p_point, q_point = LOAD_POINT, np.array([X_LINE, 0.27, 0.2])
    sol_p = solve(plates, lines, "S1", p_point, normal(plates["S1"]))
    sol_q = solve(plates, lines, "T1", q_point, normal(plates["T1"]))
    w_qp = sol_p.w("T1", *to_local(plates["T1"], q_point))
    w_pq = sol_q.w("S1", *to_local(plates["S1"], p_point))
    assert abs(w_qp) > 1e-3 * abs(sol_p.w("S1", *to_local(plates["S1"], p_point)))
    assert abs(w_qp - w_pq) < 1e-8 * abs(w_pq)


# --------------------------------------------------------------------------------------
# 4. Frames: the same physical assembly described otherwise
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("s1, t1", [
    ("plain", "normal_flipped"),
    ("plain", "y_reversed"),
    ("plain", "both_reversed"),
    ("y_reversed", "plain"),
    ("both_reversed", "y_reversed"),
])
def test_frame_redescription(s1, t1):
    """Describing members with other frames leaves the displacement vectors unchanged.

    ``normal_flipped`` T1 (``x_axis = -z`` from the top edge, line on its right edge) has
    ``e_z`` reversed: its local ``w`` flips sign while S1, S2 are unchanged.  ``y_reversed``
    (``y_axis = -e``, origin at the other end: ``sigma = -1``, harmonic signs ``(-1)^(m+1)``)
    is the same plate mapped point by point.  Reversing S1, the member that defines the
    line's direction and start, reverses ``e`` for all.  The force is given in 3D and
    converted to each description.  ``w e_z`` is compared at the same 3D points (the plain
    description's grids, edges included); the two solves differ by row/column signs and
    orderings only, so the agreement is to round-off: 1e-11 relative to the largest
    displacement of the assembly (~1e-15 measured).
    """
    plain_plates, plain_lines = t_junction(K_T1, k_skin=2e3 * (1 + 0.1j))
    plates, lines = t_junction(K_T1, k_skin=2e3 * (1 + 0.1j), s1=s1, t1=t1)
    ref, sol = solve(plain_plates, plain_lines, "S1"), solve(plates, lines, "S1")
    points = {name: to_global(p, *local_grid(p.length)) for name, p in plain_plates.items()}
    scale = max(np.max(np.abs(displacement(ref, n, pts))) for n, pts in points.items())
    for name, pts in points.items():
        diff = displacement(sol, name, pts) - displacement(ref, name, pts)
        assert np.max(np.abs(diff)) < 1e-11 * scale
    if t1 == "normal_flipped":  # the same statement in local terms: w_T1 changes sign
        x, y = local_grid(L_T1)
        assert max_relative(sol.w("T1", L_T1 - x, y), -ref.w("T1", x, y)) < 1e-11


def test_rigid_motion_of_the_assembly():
    """A rigid rotation + translation of every frame leaves every local field unchanged.

    Only the relative orientations of the frames enter ``junction_levy``; the rotation is a
    generic one (axes orthonormal to round-off, far inside the 1e-9 geometry tolerance) and
    the local fields of the X must agree to round-off (1e-11 relative).
    """
    rotation = np.linalg.qr(np.array([[0.3, -1.2, 0.5], [0.9, 0.4, -0.7], [0.2, 0.8, 1.1]]))[0]
    shift = np.array([1.5, -0.3, 2.0])
    plates, lines = x_junction()
    moved = {name: StripPlate(p.length, p.D, p.nu, p.rho_h,
                              tuple(rotation @ np.asarray(p.origin) + shift),
                              tuple(rotation @ np.asarray(p.x_axis)),
                              tuple(rotation @ np.asarray(p.y_axis)), p.left, p.right)
             for name, p in plates.items()}
    ref = solve(plates, lines, "S1")
    sol = solve(moved, lines, "S1", rotation @ LOAD_POINT + shift, rotation @ LOAD_DIRECTION)
    for name, p in plates.items():
        x, y = local_grid(p.length)
        assert max_relative(sol.w(name, x, y), ref.w(name, x, y)) < 1e-11


# --------------------------------------------------------------------------------------
# Junction laws re-derived with 3D vectors
# --------------------------------------------------------------------------------------


def test_junction_laws_in_3d():
    """On the X, the solution satisfies the junction laws written here with 3D vectors.

    At points ``s`` along the line and for each member (frame, ``Theta_J`` from
    ``line_rotation``): ``w = 0``; the rotation of the normal ``phi = grad(w) x e_z`` gives
    ``Theta_i = phi . e``; the edge couple ``M_n (e_z x n)``, ``n = n_x x_axis`` outward,
    gives ``m_i = M_n (e_z x n) . e = k_i (Theta_J - Theta_i)`` (``Theta_i = Theta_J`` if
    rigid); and ``sum_i m_i = 0``.  Every quantity is a linear combination of the same 400
    harmonics, each of which satisfies the laws, so they hold to round-off of the sums:
    1e-9 relative to the largest ``|m_i|`` or ``|Theta_J|`` (~5e-16 measured).
    """
    plates, lines = x_junction()
    sol = solve(plates, lines, "S1")
    p0, e = sol.line_frames[0]
    s = np.linspace(0.0, LY, 41)[1:-1]
    theta_line = sol.line_rotation(0, s)
    total = np.zeros(s.size, complex)
    moments, mismatch = [], []
    for name, (end, k) in lines[0].members.items():
        plate, field = plates[name], sol.fields[name]
        x_edge, n_x = (0.0, -1.0) if end == "left" else (plate.length, 1.0)
        x, y = to_local(plate, p0 + s[:, None] * e)
        assert np.allclose(x, x_edge, atol=1e-12)
        ex, ey, ez = np.asarray(plate.x_axis), np.asarray(plate.y_axis), normal(plate)
        w, w_x, w_y = (field.derivative(x, y, *d) for d in ((0, 0), (1, 0), (0, 1)))
        grad = w_x[:, None] * ex + w_y[:, None] * ey
        theta_member = np.cross(grad, ez) @ e
        m_n = -plate.D * (field.derivative(x, y, 2, 0) + NU * field.derivative(x, y, 0, 2))
        m = m_n * (np.cross(ez, n_x * ex) @ e)
        assert np.max(np.abs(w)) < 1e-12 * np.max(np.abs(sol.w("S1", *local_grid(L_S1))))
        if np.isinf(k):
            mismatch.append(theta_member - theta_line)
        else:
            mismatch.append((m - k * (theta_line - theta_member)) / abs(k))
        moments.append(m)
        total += m
    m_scale = max(np.max(np.abs(m)) for m in moments)
    assert np.max(np.abs(total)) < 1e-9 * m_scale
    assert max(np.max(np.abs(d)) for d in mismatch) < 1e-9 * np.max(np.abs(theta_line))


# --------------------------------------------------------------------------------------
# 5. Limit of a vanishing stiffener spring
# --------------------------------------------------------------------------------------


def test_vanishing_stiffener_spring():
    """Stiffener spring -> 0: the skin becomes S1 | S2 on a rigid hinge line, T1 -> 0.

    Independent route: ``exact.levy_chain`` of S1, S2 with ``hinge(1e14)``, i.e. ``w = 0`` on
    the line and ``theta_A + theta_B = M / 1e14`` (continuous slope; ``M / theta <~ D* alpha
    ~ 6e4`` N m/rad/m at the 400th harmonic, so the slope defect is < 1e-9 relative).  With
    ``k_T1 = 1e-8`` the stiffener perturbs the skin by ``~ k_T1 / (D* kappa)`` (``D* kappa
    ~ 3e3`` N m/rad/m for T1) times a resonant amplification ``<~ 1 / eta``: < 1e-9.  Hence
    the tolerance 1e-8 (4e-11 measured, the hinge's ``1 / k`` defect: 3e-9 with ``1e12``).

    The stiffener's field is driven by ``m = k_T1 (Theta_J - Theta_T1)``: it must be tiny
    (< 1e-9 of the skin's; ~1e-12 measured) and proportional to ``k_T1``: ``k_T1 = 1e-8``
    and ``1e-6`` give fields in the ratio 1e-2 up to ``O(k_T1)`` corrections (~1e-9 here)
    and round-off: a field ~1e-12 of the skin's, solved together with the skin, carries
    ~1e-16 / 1e-12 relative errors, hence the tolerance 1e-3 (1e-5 measured).
    """
    plates, lines = t_junction(1e-8)
    sol = solve(plates, lines, "S1")
    sol_1e6 = solve(*t_junction(1e-6), "S1")
    ref = levy_chain([Section(L_S1, D_SKIN, NU, RHO_H_SKIN), Section(L_S2, D_SKIN, NU, RHO_H_SKIN)],
                     LY, OMEGA, [hinge(1e14)], "clamped", "simply_supported",
                     [(0, *to_local(plates["S1"], LOAD_POINT), 1.0)], n_terms=N_TERMS)
    skin_max = 0.0
    for i, name in enumerate(("S1", "S2")):
        x, y = local_grid(plates[name].length)
        assert max_relative(sol.w(name, x, y), ref.w(x, y, i)) < 1e-8
        skin_max = max(skin_max, np.max(np.abs(ref.w(x, y, i))))
    x, y = local_grid(L_T1)
    w_t1 = sol.w("T1", x, y)
    assert np.max(np.abs(w_t1)) < 1e-9 * skin_max
    assert max_relative(100.0 * w_t1, sol_1e6.w("T1", x, y)) < 1e-3


# --------------------------------------------------------------------------------------
# 6. Bad input
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("x_axis, y_axis", [
    ((1, 0, 0), (0.1, 1, 0)),
    ((2, 0, 0), (0, 1, 0)),
    ((1, 0, 0), (0, 0.5, 0)),
    ((1, 0, 0), (1, 0, 0)),
])
def test_non_orthonormal_axes_raise(x_axis, y_axis):
    """Axes that are not orthonormal (skewed, not unit, parallel) raise ``ValueError``."""
    with pytest.raises(ValueError, match="orthonormal"):
        StripPlate(0.5, D_SKIN, NU, RHO_H_SKIN, (0, 0, 0), x_axis, y_axis)


@pytest.mark.parametrize("t1_plate", [
    strip(L_T1, (X_LINE, 0, 1e-3), Z_HAT, Y_HAT, True),          # 1 mm off the line
    strip(L_T1, (X_LINE, 0.05, 0), Z_HAT, Y_HAT, True),          # shifted along the line
    strip(L_T1, (X_LINE, 0, 0), Z_HAT, -Y_HAT, True),            # sigma=-1 from the wrong end
    strip(L_T1, (X_LINE, 0, 0), Z_HAT, -X_HAT, True),            # edge across the line
])
def test_member_edge_off_the_line_raises(t1_plate):
    """A member whose edge does not cover the line's segment raises ``ValueError``."""
    plates, lines = t_junction(K_T1)
    plates["T1"] = t1_plate
    with pytest.raises(ValueError, match="line"):
        solve(plates, lines, "S1")


def test_edge_on_two_lines_raises():
    """One plate edge listed on two junction lines raises ``ValueError``."""
    plates, _ = t_junction(K_T1)
    lines = [JunctionLine({"S1": ("right", math.inf), "S2": ("left", math.inf)}),
             JunctionLine({"S2": ("left", K_S2), "T1": ("left", K_T1)})]
    with pytest.raises(ValueError, match="two junction lines"):
        solve(plates, lines, "S1")


@pytest.mark.parametrize("members", [{}, {"S1": ("right", math.inf)}])
def test_fewer_than_two_members_raise(members):
    """A junction line with fewer than 2 members raises ``ValueError``."""
    with pytest.raises(ValueError, match="at least 2"):
        JunctionLine(members)


@pytest.mark.parametrize("members", [
    {"S1": ("top", math.inf), "S2": ("left", math.inf)},
    {"S1": ("right", -1.0), "S2": ("left", math.inf)},
    {"S1": ("right", float("nan")), "S2": ("left", math.inf)},
])
def test_bad_member_raises(members):
    """An unknown end, a negative or a NaN stiffness raise ``ValueError``."""
    with pytest.raises(ValueError):
        JunctionLine(members)


def test_unknown_member_plate_raises():
    """A line member that is not one of the plates raises ``ValueError``."""
    plates, _ = t_junction(K_T1)
    line = JunctionLine({"S1": ("right", math.inf), "S9": ("left", math.inf)})
    with pytest.raises(ValueError, match="unknown plate"):
        solve(plates, [line], "S1")
