"""Junction points where moving lines meet (``docs/method.md`` section 6.4): the point
translates in 3D as one body, so its static corners' deflections are the components of one
translation along their plates' normals, and their corner forces balance as 3D vectors along
every direction the point is free to move in.

The assembly is the box with an inner wall of ``cases/box_with_wall.toml`` with every fold a
junction line (two members, log10 k = 3) and every line moving (``held = false``): at each of
the box's eight corners three moving lines meet (three static corners, normals along x, y and
z: their corner forces vanish), at each of the wall's four corners two welds and two folds
(five static corners of three normals). No supports: the box floats.
"""

from __future__ import annotations

import numpy as np
from support import inner_grid

from assembly import parse_case
from assembly.generate import box_with_wall
from solver.substructure import solve_assembly

FREQUENCY = 250.0
WELDS = ("W_top", "W_bottom", "W_front", "W_back")


def _moving_box(load: tuple[str, tuple[float, float]] = ("Top1", (0.17, 0.13))) -> dict:
    """Every joint of the box a moving junction line; a unit force at ``load``."""
    description = box_with_wall(resolution=1.0)
    for joint in description["joints"].values():
        if joint["kind"] == "hinge":
            owners = [member.split(".")[0] for member in joint["between"]]
            joint.update(kind="junction", log10_stiffness=dict.fromkeys(owners, 3.0),
                         loss_factor=0.02)
        joint["held"] = False
    description["loads"] = [{"kind": "point_force", "plate": load[0], "at": list(load[1]),
                             "amplitude": 1.0}]
    return description


def _corner_point(case, pid: str, corner: int) -> np.ndarray:
    """A plate corner's local coordinates (corners counter-clockwise from the origin)."""
    lx, ly = case.plates[pid].size
    return np.array([(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly)][corner])


def test_moving_lines_may_meet_at_a_junction_point():
    """Every line of box_with_wall moves by default: its 16 folds (hinges between framed
    plates) and its welds. With the folds held, the welds still move, their ends meeting at
    the wall's corners (they were held, and ``held = false`` was refused there); ``held =
    true`` holds them (module notes of ``assembly.lines``)."""
    description = box_with_wall(resolution=1.0)
    assert set(parse_case(description).moving_lines()) == set(description["joints"])
    description = box_with_wall(resolution=1.0, held_folds=True)
    assert parse_case(description).moving_lines() == WELDS
    for weld in WELDS:
        description["joints"][weld]["held"] = True
    assert parse_case(description).moving_lines() == ()
    for weld in WELDS:
        description["joints"][weld]["held"] = None
    del description["joints"]["top1_front1"]  # a weld's end on a free edge: it still moves
    assert parse_case(description).moving_lines() == WELDS


def test_the_corner_forces_balance_in_3d_and_the_point_translates_as_one_body():
    """At every junction point: the corner forces :math:`P_c` (the interface unknowns of the
    static corners) sum to zero as 3D vectors, :math:`\\sum_cP_c\\mathbf e_{z,c} = 0`, and the
    corners' deflections, read from the plates' fields, are :math:`\\mathbf e_{z,c}\\cdot
    \\mathbf X_P` for one translation :math:`\\mathbf X_P` (least squares). Both are
    constraints, so both hold to round-off: measured 5e-16 of the largest corner force (the
    box's corners: forces of 0) and 1.1e-11 of the corner deflections (the fields' values at
    the corners); tolerances 1e-12 and 1e-8. The coplanar rule of section 6.4 (equal
    deflections, :math:`\\sum_cP_c = 0`) leaves 2.5 times the largest force unbalanced."""
    case = parse_case(_moving_box())
    solution = solve_assembly(case, FREQUENCY, residuals=False)
    layout = _layout(case)
    assert len(layout.junctions) == 12
    points = []
    for flags in layout.junctions:
        assert not any(kinematic for _, kinematic in flags)
        normals = np.array([case.plates[pid].frame.normal for (pid, _), _ in flags])
        forces = np.array([solution.interface[layout.corner_columns[corner]]
                           for corner, _ in flags])
        deflections = np.array([solution.plates[pid].field(
            _corner_point(case, pid, c)[None, :])["w"][0] for (pid, c), _ in flags])
        points.append((flags, normals, forces, deflections))
    scale = max(np.max(np.abs(forces)) for _, _, forces, _ in points)
    assert scale > 0.0
    for flags, normals, forces, deflections in points:
        assert np.linalg.norm(forces @ normals) < 1e-12 * scale, flags
        translation, *_ = np.linalg.lstsq(normals.astype(complex), deflections, rcond=None)
        gap = np.linalg.norm(normals @ translation - deflections)
        assert gap < 1e-8 * np.linalg.norm(deflections), (flags, gap)


def _layout(case):
    from solver.layout import interface_layout
    from solver.problems import plate_problems
    return interface_layout(case, plate_problems(case, FREQUENCY))


def test_reciprocity_across_points_where_moving_lines_meet():
    """A unit force on the top gives at a point of the front and of the wall what a unit force
    there gives on the top, across the twelve junction points. Measured at resolution 1:
    2.9e-5 (front) and 4.9e-7 (wall), at 1.5: 1e-8 and 3e-8 (so the difference is
    discretisation); with the usual edge reach on the lines' members (not
    :data:`solver.line_ends.MEETING_END_REACH` times it) 5.0e-4 and 4.1e-5; with the coplanar
    rule of section 6.4 at these points, 2.1e-2 and 5.6e-4. Tolerance 2e-4: seven times the
    measured, below both."""
    top, others = ("Top1", (0.17, 0.13)), [("Front2", (0.07, 0.19)), ("Wall", (0.11, 0.21))]

    def response(source, target):
        solution = solve_assembly(parse_case(_moving_box(source)), FREQUENCY, residuals=False)
        return solution.w(target[0], np.array([target[1]]))[0]

    for other in others:
        there, back = response(top, other), response(other, top)
        assert abs(there - back) < 2e-4 * abs(there), other[0]


def _split_along_the_line(description: dict, cut: float, log10_stiffness: float) -> dict:
    """Every plate of a folded plate cut across at ``y = cut`` into ``<name>1`` (below) and
    ``<name>2`` (above), joined again by a coplanar joint of ``log10_stiffness``; every line
    cut likewise into ``<line>1`` and ``<line>2``, whose ends meet those joints."""
    plates, joints, boundaries = {}, {}, []
    for name, plate in description["plates"].items():
        length, width = plate["size"]
        frame = plate["frame"]
        upper = np.add(frame["origin"], cut * np.asarray(frame["y_axis"])).tolist()
        plates[f"{name}1"] = plate | {"size": [length, cut]}
        plates[f"{name}2"] = plate | {"size": [length, width - cut],
                                      "frame": frame | {"origin": upper}}
        joints[f"G{name}"] = {"kind": "coplanar", "between": [f"{name}1.top", f"{name}2.bottom"],
                              "log10_stiffness": log10_stiffness}
    for boundary in description["boundaries"]:
        name, edge = boundary["edge"].split(".")
        parts = {"bottom": "1", "top": "2"}.get(edge, "12")
        boundaries += [boundary | {"edge": f"{name}{part}.{edge}"} for part in parts]
    for jid, joint in description["joints"].items():
        for part in "12":
            members = [m.split(".") for m in joint["between"]]
            joints[f"{jid}{part}"] = joint | {
                "between": [f"{name}{part}.{edge}" for name, edge in members],
                "log10_stiffness": {f"{name}{part}": k
                                    for name, k in joint["log10_stiffness"].items()}}
    (load,) = description["loads"]
    x, y = load["at"]
    part, y = ("1", y) if y < cut else ("2", y - cut)
    return description | {"plates": plates, "joints": joints, "boundaries": boundaries,
                          "loads": [load | {"plate": load["plate"] + part, "at": [x, y]}]}


def test_moving_lines_cross_a_coplanar_skin_joint():
    """A stiffener crossing a joint of the skin: the L fold of ``tests/test_moving_lines.py``
    cut across at y = 0.3 m, each leg's halves joined by a stiff coplanar joint (log10 k = 12),
    so that each half of the line ends where it meets the two joints. Its lines move by
    default, and the field is the exact uncut fold's: measured at 1 kHz (resolution 1.5),
    2.8e-8 to 2.9e-7 on the four plates; 3e-6 with log10 k = 10 and 3e-4 with 8 (the joint's
    compliance), and 1e-2 with the lines held. Tolerance 1e-5."""
    from test_moving_lines import L_FOLD, LY, _description, _reference

    plates, lines, load = L_FOLD
    case = parse_case(_split_along_the_line(_description(plates, lines, load, 1000.0, None),
                                            0.3, 12.0))
    assert case.moving_lines() == ("F1", "F2")
    solution = solve_assembly(case, 1000.0, residuals=False)
    reference = _reference(plates, lines, load, 1000.0, False)
    for name, (length, *_) in plates.items():
        for part, y0, width in (("1", 0.0, 0.3), ("2", 0.3, LY - 0.3)):
            x, y = inner_grid(length, width).T
            w = solution.plates[name + part].field(np.column_stack([x, y]))["w"]
            exact = reference.w(name, x, y + y0)
            assert np.linalg.norm(w - exact) < 1e-5 * np.linalg.norm(exact), name + part
