"""Three moving lines that meet at one point (``docs/method.md`` sections 6.4 and 10.4), against
independent finite elements: the trihedral corner of a box.

Three 2 mm steel plates on the faces of the positive octant, joined by rigid folds along the
three axes, which meet at the origin: A (0.4 x 0.3 m) in the plane Z = 0, B (0.4 x 0.25 m) in
Y = 0, C (0.3 x 0.25 m) in X = 0, each framed with its normal outward, as the faces of
``cases/box_with_wall.toml`` are. Their other edges are simply supported and fixed in plane;
1 N on A. The corner where the lines meet translates in 3D as one body, the members of
lines that meet reach further with their edge waves
(:data:`solver.line_ends.MEETING_END_REACH`, growing with the resolution from
:data:`solver.line_ends.REACH_GROWTH_FROM`), and the lines' Legendre count has a floor
(:func:`solver.joint_rules.end_layer_count`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from support import MATERIAL, inner_grid

from assembly import load_case, parse_case
from solver.estimate import estimate_error
from solver.line_ends import meeting_end_plates
from solver.substructure import solve_assembly

PLATES = {  # size, frame origin, x axis, y axis (the normal x axis ^ y axis points outward)
    "A": ((0.4, 0.3), (0.0, 0.3, 0.0), (1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
    "B": ((0.4, 0.25), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "C": ((0.3, 0.25), (0.0, 0.3, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
}
FOLDS = {"AB": ("A.top", "B.bottom"), "AC": ("A.left", "C.bottom"), "BC": ("B.left", "C.right")}
"""The three folds, along X, Y and Z, meeting at the origin (A's (0, 0.3), B's (0, 0), C's
(0.3, 0))."""
ON_A, ON_C = ("A", (0.17, 0.13)), ("C", (0.11, 0.09))

FINITE_ELEMENTS = Path(__file__).parent / "data" / "fem_corner.npz"
"""``w`` and ``(u, v)`` of the corner at 300 Hz and 1 kHz (keys ``w_A_300``, ``uv_C_1000``,
...) on each plate's :func:`support.inner_grid`, by the independent finite elements of
``bench/fem_corner.py`` (Argyris and P5 triangles, conforming on the three folds, level 8;
``python bench/fem_corner.py --write``): ``w`` within about 3e-8 (300 Hz) and 6e-8 (1 kHz),
``(u, v)`` within a few 1e-6, from the changes between levels 4, 6 and 8."""


FLOATING_FINITE_ELEMENTS = Path(__file__).parent / "data" / "fem_corner_floating.npz"
"""The same as :data:`FINITE_ELEMENTS` for the floating corner (every supported edge free in
plane) at 300 Hz (``python bench/fem_corner.py --write-floating``): ``w`` within about 3e-7
and ``(u, v)`` within about 1e-5, the round-off of its worse-conditioned system."""


def corner(frequency: float, resolution: float = 1.5,
           load: tuple[str, tuple[float, float]] = ON_A, floating: bool = False) -> dict:
    """The corner's description: rigid folds, far edges simply supported, fixed in plane or, if
    ``floating``, free in plane (``in_plane = "free"``), 1 N at ``load``."""
    joined = {edge for pair in FOLDS.values() for edge in pair}
    in_plane = {"in_plane": "free"} if floating else {}
    return {
        "name": "corner",
        "frequency": frequency,
        "materials": {"steel": MATERIAL},
        "plates": {name: {"material": "steel", "thickness": 0.002, "size": list(size),
                          "frame": {"origin": list(origin), "x_axis": list(x_axis),
                                    "y_axis": list(y_axis)}}
                   for name, (size, origin, x_axis, y_axis) in PLATES.items()},
        "joints": {jid: {"kind": "junction", "between": list(pair),
                         "log10_stiffness": {pair[0][0]: math.inf, pair[1][0]: math.inf}}
                   for jid, pair in FOLDS.items()},
        "boundaries": [{"edge": f"{name}.{edge}", "condition": "simply_supported"} | in_plane
                       for name in PLATES for edge in ("left", "right", "bottom", "top")
                       if f"{name}.{edge}" not in joined],
        "discretisation": {"resolution": resolution},
        "loads": [{"kind": "point_force", "plate": load[0], "at": list(load[1]),
                   "amplitude": 1.0}],
    }


def test_the_three_lines_move_and_meet():
    """Every fold moves by default and meets the other two at the origin."""
    case = parse_case(corner(300.0))
    assert case.moving_lines() == ("AB", "AC", "BC")
    assert meeting_end_plates(case) == {"A", "B", "C"}


def test_reciprocity_across_the_corner():
    """A unit force on A gives at a point of C what a unit force there gives on A. Measured at
    resolution 1.5: 2e-7 (the discretisation); tolerance 1e-5."""
    def response(source, target):
        case = parse_case(corner(300.0, load=source))
        return solve_assembly(case, 300.0, residuals=False).w(target[0], np.array([target[1]]))[0]

    there, back = response(ON_A, ON_C), response(ON_C, ON_A)
    assert abs(there - back) < 1e-5 * abs(there)


def _errors(frequency: float, resolution: float, floating: bool = False
            ) -> dict[str, tuple[float, float, float, float]]:
    """Per plate, the errors of ``w`` and ``(u, v)`` against :data:`FINITE_ELEMENTS` (or
    :data:`FLOATING_FINITE_ELEMENTS`) and their estimates."""
    reference = np.load(FLOATING_FINITE_ELEMENTS if floating else FINITE_ELEMENTS)
    case = parse_case(corner(frequency, resolution, floating=floating))
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution)
    out = {}
    for name, (size, *_) in PLATES.items():
        points = inner_grid(*size)
        w, uv = solution.plates[name].field(points)["w"], solution.in_plane(name, points)
        w_ref, uv_ref = (reference[f"{key}_{name}_{frequency:g}"] for key in ("w", "uv"))
        out[name] = (float(np.linalg.norm(w - w_ref) / np.linalg.norm(w_ref)),
                     estimate.plates[name],
                     float(np.linalg.norm(uv - uv_ref) / np.linalg.norm(uv_ref)),
                     estimate.in_plane[name])
    return out


def test_the_corner_meets_independent_finite_elements():
    """Against :data:`FINITE_ELEMENTS`, worst plate: ``w`` 3.1e-4, 8.9e-6, 1.0e-6, 3.0e-7 at
    resolutions 1, 1.5, 2.25, 3.375 (300 Hz) and 1.2e-4, 2.2e-6 at 1, 1.5 (1 kHz); ``(u, v)``
    7.4e-3, 5.8e-4, 1.2e-4, 3.5e-5 and 2.2e-4, 3.0e-5; the estimates 0.65 to 2.15 times the
    errors of ``w`` and 0.81 to 2.17 of ``(u, v)`` (``bench/bench_corner.py``). Checked at
    300 Hz and resolution 2.25 and at 1 kHz and 1.5, with bounds about twice the measured
    errors and the issue's [0.5, 3] for the estimates."""
    bounds = {(300.0, 2.25): (2e-6, 2.5e-4), (1000.0, 1.5): (5e-6, 6e-5)}
    for (frequency, resolution), (w_bound, uv_bound) in bounds.items():
        for plate, (w, w_estimate, uv, uv_estimate) in _errors(frequency, resolution).items():
            assert w < w_bound and uv < uv_bound, (frequency, plate, w, uv)
            assert 0.5 < w_estimate / w < 3.0 and 0.5 < uv_estimate / uv < 3.0, \
                (frequency, plate, w_estimate / w, uv_estimate / uv)


def test_without_the_count_floor_the_corner_converges_slower(monkeypatch):
    """The lines end where they meet, and there their loads form a layer as at an end that
    slides: their count has the same floor (:func:`solver.joint_rules.end_layer_count`: 22, 19
    and 18 functions on AB, AC and BC at resolution 1.5 and 300 Hz, instead of 14, 11 and 9).
    Without it, as until 2026-11-28, ``w`` is 4.7e-5 off on the worst plate at resolution 1.5
    (8.9e-6 with it) and 8.2e-6 at 2.25 (1.0e-6). Threshold: 3e-5 at 1.5."""
    import solver.joint_rules

    monkeypatch.setattr(solver.joint_rules, "END_LAYER_FROM", math.inf)
    assert max(w for w, *_ in _errors(300.0, 1.5).values()) > 3e-5


def test_with_the_usual_reach_the_corner_stalls(monkeypatch):
    """The members of lines that meet reach further (three times, growing with the resolution
    from 1.5): with the usual reach the corner stalls, ``w`` 4.1e-4, 5.9e-4, 2.1e-4 off the
    finite elements at resolutions 1.5, 2.25, 3.375 (300 Hz, worst plate; 8.2e-6 at 2.25 with
    the rule); with three times the reach fixed, as until 2026-11-27, it converged to 2.25
    (the rule's figures) and stalled at 5.4e-6 at 3.375, the estimate 6 to 42 times the
    error (1.6e-6 with the rule, the estimate 1.0 to 1.4 times). Threshold: 3e-4 at 2.25."""
    import solver.line_ends

    monkeypatch.setattr(solver.line_ends, "MEETING_END_REACH", 1.0)
    monkeypatch.setattr(solver.line_ends, "REACH_GROWTH_FROM", math.inf)
    assert max(w for w, *_ in _errors(300.0, 2.25).values()) > 3e-4


def test_check_warns_of_plates_floating_in_their_plane():
    """Supported in bending but held in their plane by no edge, the freed corner's plates are a
    near-mechanism: ``vtcr check`` warns once, naming them and what would hold them
    (:func:`solver.guards._floating_issues`). One edge fixed in plane holds the group, and
    neither the corner as supported nor a structure that nothing supports (the box, which
    floats as a whole) is warned."""
    from solver.guards import check_description

    warnings = check_description(parse_case(corner(300.0, floating=True)), "corner.toml")
    assert len(warnings) == 1, warnings
    assert warnings[0].startswith("corner.toml: boundaries[0].in_plane: plates A, B, C float")
    held_once = corner(300.0, floating=True)
    del held_once["boundaries"][3]["in_plane"]  # simply supported: fixed in plane by default
    assert check_description(parse_case(held_once), "corner.toml") == []
    assert check_description(parse_case(corner(300.0)), "corner.toml") == []
    box = Path(__file__).parents[1] / "cases" / "box_with_wall.toml"
    assert not [w for w in check_description(load_case(box), box.name) if "float" in w]


def test_a_corner_floating_in_its_plane_converges_to_finite_elements():
    """With every supported edge free in plane, the plates are held in their plane only through
    the others' bending, and the folds' far ends slide (they reach as free ends:
    :func:`solver.line_ends.free_end_plates`, and their count has a floor:
    :func:`solver.joint_rules.end_layer_count`). Refinement converges from far off, to the
    independent finite elements: worst plate's ``w`` 2.4e-2, 4.4e-3, 1.8e-3, 3.6e-4, 2.5e-4 at
    resolutions 1.5, 2.25, 3.375, 5, 7.5 (300 Hz), ``(u, v)`` 0.45, 0.12, 4.9e-2, 1.2e-2,
    7.9e-3, the estimates 0.46 to 0.97 times the errors (``bench/bench_corner.py
    --floating``); without the floor ``w`` 2.3, 7.9e-2, 1.0e-2, 9.8e-4 to 5. Checked at 3.375,
    bounds twice the measured errors and the issue's [0.5, 3] for the estimates."""
    for plate, (w, w_estimate, uv, uv_estimate) in _errors(300.0, 3.375, floating=True).items():
        assert w < 4e-3 and uv < 0.1, (plate, w, uv)
        assert 0.5 < w_estimate / w < 3.0 and 0.5 < uv_estimate / uv < 3.0, \
            (plate, w_estimate / w, uv_estimate / uv)
