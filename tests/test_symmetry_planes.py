"""The ``symmetric`` edge (``dw/dn = 0``, ``K_n = 0``: a plane of symmetry of the structure,
``docs/method.md`` section 3) and the ends of junction lines on planes of symmetry
(``docs/method.md`` section 10.4).

Plate: the 1 mm steel plate 0.5 x 0.4 m of ``tests/test_plate_accuracy.py``.
"""

import numpy as np
import pytest
from support import folded_description, folded_reference, folded_w, inner_grid
from test_moving_lines import L_FOLD, SHAPES, _true_errors
from test_moving_lines import LY as FOLD_LENGTH
from test_plate_accuracy import (
    FORCE_AT,
    GRID,
    LX,
    LY,
    RHO,
    D,
    H,
    dissipated_power,
    rel_error,
    solve_with,
)

import solver.line_ends
from assembly import AssemblyError, parse_case
from assembly.types import EdgeId
from solver.estimate import estimate_error
from solver.guards import check_description
from solver.plate import EdgeCondition, EdgeLoad, PlateProblem, PointForce, solve_plate
from solver.power import power_flow
from solver.rays import automatic_ray_counts, build_ray_basis
from solver.substructure import solve_assembly


def navier_symmetric(frequency, x0, y0, x, y, n_terms=400):
    r"""Simply supported on x = 0, LX and symmetric on y = 0, LY: the double series
    :math:`w = \sum_{p\ge1}\sum_{q\ge0} c_{pq}\sin(p\pi x/L_x)\cos(q\pi y/L_y)` of a unit point
    force at ``(x0, y0)``, each term meeting the four conditions,
    :math:`c_{pq} = \frac{2\epsilon_q}{L_xL_y}\sin(p\pi x_0/L_x)\cos(q\pi y_0/L_y)/(D^*k_{pq}^4
    - \rho h\omega^2)`, :math:`\epsilon_0 = 1`, :math:`\epsilon_{q>0} = 2`."""
    omega = 2 * np.pi * frequency
    kp = np.arange(1, n_terms + 1) * np.pi / LX
    kq = np.arange(0, n_terms + 1) * np.pi / LY
    eps = np.where(kq == 0.0, 1.0, 2.0)
    denominator = D * (kp[:, None] ** 2 + kq[None, :] ** 2) ** 2 - RHO * H * omega**2
    c = (2 / (LX * LY)) * eps * np.sin(kp * x0)[:, None] * np.cos(kq * y0) / denominator
    return np.einsum("pq,ip,iq->i", c, np.sin(np.outer(x, kp)), np.cos(np.outer(y, kq)))


SUPPORTED_SYMMETRIC = {"left": EdgeCondition("simply_supported"),
                       "right": EdgeCondition("simply_supported"),
                       "bottom": EdgeCondition("symmetric"), "top": EdgeCondition("symmetric")}


@pytest.mark.parametrize("frequency, coarse, fine", [(155.0, 1.4e-4, 5.3e-6),
                                                     (400.0, 4.3e-6, 1.3e-8)])
def test_symmetric_edges_against_navier(frequency, coarse, fine):
    """Against the double series: resolutions 1 and 1.25 measured 1.4e-4, 5.3e-6 at 155 Hz and
    4.3e-6, 1.3e-8 at 400 Hz (the series' own tail is below 1e-9 on the grid); the bounds are
    three times these. With the slope and moment swapped (the symmetric edge read as simply
    supported) the error is order one."""
    reference = navier_symmetric(frequency, *FORCE_AT, GRID[:, 0], GRID[:, 1])
    errors = []
    for resolution in (1.0, 1.25):
        solution, _ = solve_with(frequency, SUPPORTED_SYMMETRIC, [(FORCE_AT, 1.0)], resolution)
        errors.append(rel_error(solution.field(GRID)["w"], reference))
    assert errors[0] < 3 * coarse and errors[1] < 3 * fine, errors


def _plate(size, edges, forces, frequency=300.0, resolution=1.5):
    problem = PlateProblem(size, D, 0.3, RHO * H, 2 * np.pi * frequency, edges,
                           tuple(PointForce(p, 1.0) for p in forces))
    counts = automatic_ray_counts(problem.kappa.real, problem.size, resolution)
    return solve_plate(problem, build_ray_basis(problem.size, problem.kappa, counts))


def test_half_plate_equals_the_symmetric_whole():
    """A plate 0.5 x 0.8 m (simply supported but for a free right edge) under two forces placed
    symmetrically about y = 0.4 is symmetric about that line: its lower half is the plate 0.5 x
    0.4 m with a symmetric top edge and one force. The half has a symmetric-free corner (top
    right), where the corner force vanishes with the free edge's twist. Measured: 1.7e-9 at 300
    Hz (resolution 1.5), and the whole plate's own symmetry 3.0e-9; 1e-6 allows both solves'
    discretisation errors with a wide margin."""
    x0, y0 = FORCE_AT[0], 0.17
    edges = {"left": EdgeCondition("simply_supported"), "right": EdgeCondition("free"),
             "bottom": EdgeCondition("simply_supported")}
    whole = _plate((LX, 2 * LY), edges | {"top": EdgeCondition("simply_supported")},
                   [(x0, y0), (x0, 2 * LY - y0)])
    half = _plate((LX, LY), edges | {"top": EdgeCondition("symmetric")}, [(x0, y0)])
    points = np.column_stack([GRID[:, 0], GRID[:, 1] * (LY - 0.01) / LY + 0.005])
    assert rel_error(half.field(points)["w"], whole.field(points)["w"]) < 1e-6
    mirrored = points * [1.0, -1.0] + [0.0, 2 * LY]
    assert rel_error(whole.field(mirrored)["w"], whole.field(points)["w"]) < 1e-6


def test_power_balance_with_a_shear_on_a_symmetric_edge():
    """E1 on a symmetric edge loaded by a half-sine Kirchhoff shear p: P_in = 1/2 Re int
    conj(p) j omega w ds (the slope vanishes there, so the reacting moment does no work) equals
    1/2 omega eta D a(w, w*); both from the field, agreeing to the discretisation error."""
    frequency = 400.0
    omega = 2 * np.pi * frequency
    edges = SUPPORTED_SYMMETRIC | {"bottom": EdgeCondition("symmetric",
                                                           EdgeLoad(1.0, "half_sine"))}
    solution, _ = solve_with(frequency, edges, resolution=1.25)
    x, wx = np.polynomial.legendre.leggauss(80)
    x, wx = 0.5 * LX * (x + 1), 0.5 * LX * wx
    edge = solution.field(np.c_[x, np.zeros_like(x)], ("w", "w_y"))
    p = np.sin(np.pi * x / LX)
    injected = 0.5 * np.real(np.sum(wx * np.conj(p) * 1j * omega * edge["w"]))
    assert np.max(np.abs(edge["w_y"])) < 1e-4 * np.max(np.abs(edge["w"])) / LY
    dissipated = dissipated_power(solution, omega)
    assert injected > 0
    assert abs(injected - dissipated) <= 1e-5 * injected


def _fold(ends="symmetric", held=None, **edges):
    """The L fold of ``tests/test_moving_lines.py`` with both ends as ``ends`` says
    (``support.FOLD_ENDS``), then ``edges`` (``{"A_bottom": (condition, in_plane)}``) changed."""
    description = folded_description(*L_FOLD, 1000.0, held, FOLD_LENGTH, ends=ends)
    for boundary in description["boundaries"]:
        key = boundary["edge"].replace(".", "_")
        if key in edges:
            boundary["condition"], boundary["in_plane"] = edges[key]
    return parse_case(description)


def test_lines_ending_on_planes_of_symmetry_move_and_mixed_ends_stay_held():
    """A line moves by default where each of its ends is a plane of symmetry on every member
    (``symmetric`` with ``roller``, the default in-plane condition of ``symmetric``) or on
    none; one end may be one and the other not. Where an end mixes them it stays held, and
    ``vtcr check`` names the edges and the two consistent choices. The line's loads are
    log-singular at a mixed end where a ``roller`` edge meets a ``simply_supported`` one
    (:func:`assembly.lines.singular_line_ends`: the kink of ``docs/method.md`` section 10.4),
    at no other mix."""
    assert _fold().moving_lines() == ("F",)
    assert check_description(_fold(), "fold.toml") == []
    top_diaphragm = {"A_top": ("simply_supported", "diaphragm"),
                     "B_top": ("simply_supported", "diaphragm")}
    assert _fold(**top_diaphragm).moving_lines() == ("F",)
    for mixed, kinked in (
            ({"B_bottom": ("simply_supported", "diaphragm")}, True),  # across the members
            ({"A_bottom": ("symmetric", "fixed")}, False),  # on one edge
            ({"A_bottom": ("symmetric", "diaphragm"), "B_bottom": ("symmetric", "diaphragm")},
             False)):
        case = _fold(**mixed)
        assert case.moving_lines() == (), mixed
        assert case.singular_ends("F") == [EdgeId("A", "bottom"), EdgeId("B", "bottom")], mixed
        assert case.singular_line_ends("F") == (kinked, False), mixed
        (warning,) = check_description(case, "fold.toml")
        assert warning.startswith("fold.toml: joints.F.held: junction line F is held")
        assert "A.bottom, B.bottom" in warning and 'condition = "symmetric"' in warning
        assert check_description(_fold(held=True, **mixed), "fold.toml") == []
    # B's frame turned end for end: its top edge now meets A's bottom at the line's start
    flipped = folded_description(*L_FOLD, 1000.0, None, FOLD_LENGTH, ends="symmetric")
    flipped["plates"]["B"]["frame"] = {"origin": [0.4, FOLD_LENGTH, 0.0],
                                       "x_axis": [0.0, 0.0, 1.0], "y_axis": [0.0, -1.0, 0.0]}
    for boundary in flipped["boundaries"]:
        if boundary["edge"] == "A.bottom":
            boundary["condition"], boundary["in_plane"] = "simply_supported", "diaphragm"
    case = parse_case(flipped)
    assert case.member_directions("F") == (1, 1)
    assert case.singular_ends("F") == [EdgeId("A", "bottom"), EdgeId("B", "top")]
    assert case.singular_line_ends("F") == (True, False)
    assert _fold(**ROLLER_ENDS).singular_line_ends("F") == (True, True)
    clamped = {key: ("clamped", "roller") for key in ROLLER_ENDS}
    assert _fold(**clamped).singular_line_ends("F") == (False, False)


ROLLER_ENDS = {f"{plate}_{end}": ("simply_supported", "roller")
               for plate in ("A", "B") for end in ("bottom", "top")}


def test_a_member_that_nothing_holds_across_the_line_hangs_on_it():
    """A member hangs on a line when no boundary edge of its own, nor of a coplanar member,
    holds it across the line in its plane (``docs/method.md`` section 10.4): its end edges not
    ``fixed`` or ``diaphragm``, its far edge not ``fixed`` or ``roller``. With mixed ends
    ``vtcr check`` names it: moving such a line does not converge."""
    assert _fold(**ROLLER_ENDS).hanging_members("F") == []  # B's far edge fixed in-plane
    for far, hangs in (("diaphragm", ["B"]), ("roller", []), ("free", ["B"])):
        case = _fold(**ROLLER_ENDS, B_right=("simply_supported", far))
        assert case.hanging_members("F") == hangs, far
        (warning,) = check_description(case, "fold.toml")
        assert ("B hangs on it" in warning) == bool(hangs), warning
    # B's far edge free, but its ends hold it: diaphragm on one end edge is enough
    held_end = _fold(**ROLLER_ENDS | {"B_bottom": ("simply_supported", "diaphragm")},
                     B_right=("simply_supported", "diaphragm"))
    assert held_end.hanging_members("F") == []
    # with roller ends the T junction's stiffener (free top) hangs; its skin bays, fixed at
    # their far edges, do not, and the inner bay of a panel is held through the coplanar bay
    # beside it; diaphragm ends hold every member
    from test_moving_lines import PANEL
    for ends, hanging in (("symmetric", ["T1"]), ("diaphragm", [])):
        tee = parse_case(folded_description(*SHAPES["T"], 1000.0, None, FOLD_LENGTH, ends=ends))
        assert tee.hanging_members("W") == hanging, ends
    panel = parse_case(folded_description(*PANEL, 1000.0, None, FOLD_LENGTH, ends="symmetric"))
    assert (panel.hanging_members("W1"), panel.hanging_members("W2")) == (["T1"], ["T2"])


def test_a_member_is_pinned_where_its_end_slides_and_another_member_is_supported():
    """An end of a line pins a member at its corner (:func:`assembly.lines.pinned_ends`) when
    the member's end edge leaves its displacement across the line free (``free`` or ``roller``
    in plane, or a free edge) and the end edge of a member not coplanar with it holds that
    member's deflection (``simply_supported`` or ``clamped``): per end, all of that end's
    edges, or none."""
    bottom = [EdgeId("A", "bottom"), EdgeId("B", "bottom")]
    for a_bottom, b_bottom, pinned in (
            (("simply_supported", "free"), ("simply_supported", "free"), bottom),
            (("simply_supported", "fixed"), ("free", "free"), bottom),  # B hangs at its end
            (("clamped", "diaphragm"), ("simply_supported", "roller"), bottom),
            (("simply_supported", "diaphragm"), ("simply_supported", "diaphragm"), []),
            (("symmetric", "free"), ("symmetric", "free"), []),  # no deflection held
            (("free", "free"), ("free", "free"), [])):  # a free end: nothing pins it
        case = _fold("diaphragm", A_bottom=a_bottom, B_bottom=b_bottom)
        assert case.pinned_ends("F") == pinned, (a_bottom, b_bottom)
    # the solver gives such a line's members their families unless every member hangs on it
    sliding = {f"{plate}_{end}": ("simply_supported", "free")
               for plate in ("A", "B") for end in ("bottom", "top")}
    assert solver.line_ends.singular_end_plates(_fold(**sliding)) == {"A", "B"}
    floating = _fold(**sliding, A_left=("simply_supported", "free"),
                     B_right=("simply_supported", "free"))
    assert floating.pinned_ends("F") and floating.hanging_members("F") == ["A", "B"]
    assert solver.line_ends.singular_end_plates(floating) == frozenset()
    # the T junction's coplanar skin bays do not pin each other: its stiffener's free ends do
    tee = folded_description(*SHAPES["T"], 1000.0, None, FOLD_LENGTH, ends="fixed")
    assert parse_case(tee).pinned_ends("W") == []
    for boundary in tee["boundaries"]:
        if boundary["edge"] in ("T1.bottom", "T1.top"):
            boundary["in_plane"] = "free"
    assert len(parse_case(tee).pinned_ends("W")) == 6


def test_an_edge_moment_cannot_act_on_a_symmetric_edge():
    """A symmetric edge fixes its slope, so its moment is a reaction; a shear may act on it."""
    description = folded_description(*L_FOLD, 1000.0, None, FOLD_LENGTH, ends="symmetric")
    description["loads"].append({"kind": "edge_shear", "edge": "A.bottom", "amplitude": 1.0})
    parse_case(description)
    description["loads"][-1]["kind"] = "edge_moment"
    with pytest.raises(AssemblyError, match="symmetric: its rotation is fixed"):
        parse_case(description)


# the worst plate's error of w against the exact folded plate with symmetric ends, resolution
# 1.5, 600 harmonics (the reference's tail: 1.5e-8 on these grids at 1 kHz)
SYMMETRIC_CASES = [("L", 300.0), ("L", 3000.0), ("U", 1000.0), ("T", 3000.0)]


@pytest.mark.parametrize("shape, frequency", SYMMETRIC_CASES)
def test_lines_ending_on_planes_of_symmetry_match_the_exact_folded_plate(shape, frequency):
    """The exact prismatic folded plate with symmetric ends (``tests/exact_prismatic.py``,
    ``ends = "symmetric"``: ``w`` and ``u`` in cosines of y, ``v`` in sines, the harmonic 0
    included), lines moving by default. Measured, worst plate at 300 Hz / 1 kHz / 3 kHz: L
    7.4e-8 / 3.0e-9 / 1.7e-8, U 2.9e-7 / 1.2e-8 / 2.4e-8, T 1.4e-7 / 1.5e-8 / 1.9e-9 (7e-4 to
    1.4e-2 at resolution 1), as with shear-diaphragm ends. The issue's target for moving lines
    is 2e-3; 1e-5 bounds these with a margin of 30 to 5000, where the L fold with roller ends
    simply supported changed by 1e-2 between resolutions."""
    plates, lines, load = SHAPES[shape]
    case = parse_case(folded_description(plates, lines, load, frequency, None, FOLD_LENGTH,
                                         ends="symmetric"))
    assert case.moving_lines() == tuple(lines)
    solution = solve_assembly(case, frequency, residuals=False)
    reference = folded_reference(plates, lines, load, frequency, False, FOLD_LENGTH, 600,
                                 ends="symmetric")
    errors = {}
    for name, w in folded_w(solution, plates, FOLD_LENGTH).items():
        exact = reference.w(name, *inner_grid(plates[name][0], FOLD_LENGTH).T)
        errors[name] = float(np.linalg.norm(w - exact) / np.linalg.norm(exact))
    assert max(errors.values()) < 1e-5, errors


def test_the_error_estimate_stays_honest_with_symmetric_ends():
    """The estimate against the true error at resolution 1, per plate, of ``w`` and ``(u, v)``:
    measured 1.00 for both on every plate of the L, U and T at 300 Hz, 1 kHz and 3 kHz (true
    errors of w 5.5e-5 to 1.4e-2, of (u, v) 3e-5 to 0.26); the issue asks [0.5, 3] above
    1e-5."""
    plates, lines, load = SHAPES["U"]
    case = parse_case(folded_description(plates, lines, load, 1000.0, None, FOLD_LENGTH, 1.0,
                                         ends="symmetric"))
    solution = solve_assembly(case, 1000.0)
    estimate = estimate_error(case, solution)
    w_errors, in_plane_errors, total = _true_errors(
        solution, folded_reference(plates, lines, load, 1000.0, False, FOLD_LENGTH, 600,
                                   ends="symmetric"), plates)
    assert 0.5 <= estimate.total / total <= 3.0
    for name in plates:
        for estimated, true in ((estimate.plates[name], w_errors[name]),
                                (estimate.in_plane[name], in_plane_errors[name])):
            assert true > 1e-5 and 0.5 <= estimated / true <= 3.0, (name, estimated, true)



def test_the_power_balances_with_lines_ending_on_planes_of_symmetry():
    """The T junction with symmetric ends, its stiffener on a lossy spring (10 % of the injected
    power at 300 Hz): per plate, injected plus delivered by the line plus delivered at the
    junction points where the line meets the planes (its members' corners there are static:
    1e-9 to 1e-7 of the injected power passes between them) equals dissipated. Measured at
    resolution 1.5: 7e-12 at most (300 Hz, 1 and 3 kHz); without the corners' share 9.4e-8 at
    1 kHz. Tolerance 1e-9."""
    plates, lines, load = SHAPES["T"]
    description = folded_description(plates, lines, load, 300.0, None, FOLD_LENGTH,
                                     ends="symmetric")
    description["joints"]["W"]["loss_factor"] = {"T1": 0.2}
    case = parse_case(description)
    power = power_flow(case, solve_assembly(case, 300.0))
    injected = power.total_injected
    delivered = power.delivered["W"]
    assert power.joint_dissipated["W"] > 0.05 * injected
    assert set(power.corners) == set(plates)  # every member meets the planes there
    for plate in case.plates:
        balance = (power.injected[plate] + delivered[plate] + power.corners.get(plate, 0.0)
                   - power.dissipated[plate])
        assert abs(balance) < 1e-9 * injected, (plate, balance / injected)
