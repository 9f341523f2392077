r"""Junction lines: plates placed in 3D, n >= 2 members on one line (issue 15).

The members of a junction are held in translation on the line and tied to the line's rotation
by one spring each (``docs/method.md`` section 6.2b). Checked here against exact identities of the
formulation, independent of any reference solution: two members of stiffness 2k are a hinge of
stiffness k, flipping a member's frame flips its field and nothing else, reciprocity across
the line; the description's checks; every finite member as an updatable channel
``JOINT.PLATE`` (truth, parameters, localise, curve); and the two junction cases, the
stiffened panel's updating among them. The exact Levy-strip comparisons are in
``test_junction_accuracy.py``.
"""

import json
import math
import tomllib

import numpy as np
import pytest
from support import CASES

from assembly import DescriptionError, load_case, parse_case
from assembly.generate import box_with_wall, description_toml, stiffened_panel
from assembly.joints import JunctionJoint
from solver.substructure import solve_assembly
from updating.cli import main

STEEL = {"young_modulus": 210e9, "poisson_ratio": 0.3, "density": 7800.0, "loss_factor": 0.01}
SKIN_LENGTHS = (0.5, 0.4)
STIFFENER_HEIGHT = 0.3
LY = 0.4


def _plate(size, origin, x_axis, y_axis=(0.0, 1.0, 0.0)):
    return {"material": "steel", "thickness": 0.001, "size": list(size),
            "frame": {"origin": list(origin), "x_axis": list(x_axis), "y_axis": list(y_axis)}}


def tee_description(stiffener=2.0, skin=math.inf, flip=False, load=("S1", (0.17, 0.13))):
    """A skin S1 | S2 in the x-y plane and a stiffener T1 standing along +z on their common
    line x = 0.5, all simply supported on y = 0 and y = 0.4; ``flip`` gives T1 the frame
    with y_axis -> -y_axis (origin at the line's other end), which flips its normal."""
    a, b = SKIN_LENGTHS
    if flip:
        stiffener_plate = _plate((STIFFENER_HEIGHT, LY), (a, LY, 0.0), (0.0, 0.0, 1.0),
                                 (0.0, -1.0, 0.0))
    else:
        stiffener_plate = _plate((STIFFENER_HEIGHT, LY), (a, 0.0, 0.0), (0.0, 0.0, 1.0))
    plate, at = load
    return {
        "name": "tee", "frequency": 250.0, "materials": {"steel": STEEL},
        "plates": {"S1": _plate((a, LY), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
                   "S2": _plate((b, LY), (a, 0.0, 0.0), (1.0, 0.0, 0.0)),
                   "T1": stiffener_plate},
        "joints": {"W1": {"kind": "junction", "between": ["S1.right", "S2.left", "T1.left"],
                          "log10_stiffness": {"S1": skin, "S2": skin, "T1": stiffener}}},
        "boundaries": [{"edge": f"{p}.{e}", "condition": "simply_supported"}
                       for p, e in (("S1", "left"), ("S2", "right"), ("S1", "bottom"),
                                    ("S1", "top"), ("S2", "bottom"), ("S2", "top"),
                                    ("T1", "bottom"), ("T1", "top"))],
        "loads": [{"kind": "point_force", "plate": plate, "at": list(at), "amplitude": 1.0}],
    }


def test_two_member_junction_of_2k_is_a_hinge_of_k():
    """Two members of 2k in series are a hinge of k (``docs/method.md`` section 6.2b): the
    folded plate's hinge as a junction gives the same field and, summed over the members, the
    same residual. The tolerance, 1e-8 of the largest |w|, is the round-off of the interface
    solves on this case (condition estimate 1e11 of the plates' ray systems)."""
    case = load_case("cases/folded_plate.toml")
    hinge = case.joints["G1"]
    junction = JunctionJoint(between=hinge.between, loss_factor=0.05,
                             log10_stiffness=hinge.log10_stiffness + math.log10(2.0))
    damped = {"G1": hinge.model_copy(update={"loss_factor": 0.05})}
    a = solve_assembly(case.model_copy(update={"joints": damped}), case.frequencies[0])
    b = solve_assembly(case.model_copy(update={"joints": {"G1": junction}}),
                       case.frequencies[0])
    points = np.array([[0.05, 0.05], [0.2, 0.3], [0.33, 0.05], [0.1, 0.37]])
    for plate in case.plates:
        wa, wb = a.w(plate, points), b.w(plate, points)
        assert np.max(np.abs(wa - wb)) < 1e-8 * np.max(np.abs(wa))
    assert set(b.residuals) == {"G1.P1", "G1.P2"}
    assert sum(b.residuals.values()) == pytest.approx(a.residuals["G1"], rel=1e-6)


def test_flipping_a_member_frame_flips_its_field_and_nothing_else():
    """T1 described with y_axis -> -y_axis (and the origin at the other end of the line)
    is the same plate with its normal reversed: its w at the same physical points changes
    sign, the skin's does not change. Not to round-off: T1's rays are not mirror-symmetric,
    so the two descriptions discretise T1 differently; the tolerance is the discretisation
    error of T1, 2.6e-3 by `vtcr solve`'s estimate (measured: 8.5e-4 on T1, 2e-6 on the
    skin). A wrong sign would differ by 2."""
    base = solve_assembly(parse_case(tee_description()), 250.0)
    flipped = solve_assembly(parse_case(tee_description(flip=True)), 250.0)
    x = np.array([0.05, 0.12, 0.21, 0.27])
    y = np.array([0.07, 0.19, 0.26, 0.33])
    stiffener = base.w("T1", np.c_[x, y])
    assert np.max(np.abs(flipped.w("T1", np.c_[x, LY - y]) + stiffener)) \
        < 2.6e-3 * np.max(np.abs(stiffener))
    for plate in ("S1", "S2"):
        skin = base.w(plate, np.c_[x, y])
        assert np.max(np.abs(flipped.w(plate, np.c_[x, y]) - skin)) \
            < 2.6e-3 * np.max(np.abs(skin))


def test_reciprocity_across_a_junction():
    """A unit force on the skin at A gives at B on the stiffener what a unit force at B
    gives at A (the assembled operator is symmetric for a symmetric spring, damped or not).
    Each side carries its own discretisation error: they differ by 2.7e-4 at resolution 1,
    1.5e-7 at 1.5 and 1.0e-6 at 2 (round-off of the richer bases); tolerance 1e-5 at 1.5."""
    skin_point, stiffener_point = (0.31, 0.23), (0.14, 0.29)
    on_skin = parse_case(tee_description(stiffener=2.3, load=("S1", skin_point)))
    on_stiffener = parse_case(tee_description(stiffener=2.3, load=("T1", stiffener_point)))
    ab = solve_assembly(on_skin, 250.0, 1.5).w("T1", np.array([stiffener_point]))[0]
    ba = solve_assembly(on_stiffener, 250.0, 1.5).w("S1", np.array([skin_point]))[0]
    assert abs(ab - ba) < 1e-5 * abs(ab)


def test_reciprocity_across_junction_and_fold_corners():
    """The box with an inner wall: junction lines end on fold lines at its corners. A unit
    force on the top gives at a point of the front (across folds and the wall's T-junctions)
    and of the wall (through a lossy weld) what a unit force there gives on the top. At
    resolution 1.5 they differ by 1.5e-5 and 9.4e-7 (4.2e-3 and 1.0e-5 at resolution 1, so
    the difference is discretisation): tolerance 1e-4."""
    top, front, wall = ("Top1", (0.17, 0.13)), ("Front2", (0.07, 0.19)), ("Wall", (0.11, 0.21))

    def response(source, target):
        description = box_with_wall(resolution=1.5)
        description["joints"]["W_top"]["loss_factor"] = {"Top1": 0.0, "Top2": 0.0,
                                                         "Wall": 0.1}
        description["loads"] = [{"kind": "point_force", "plate": source[0],
                                 "at": list(source[1]), "amplitude": 1.0}]
        solution = solve_assembly(parse_case(description), 250.0, 1.5)
        return solution.w(target[0], np.array([target[1]]))[0]

    for other in (front, wall):
        there, back = response(top, other), response(other, top)
        assert abs(there - back) < 1e-4 * abs(there), other[0]


def test_junction_residuals_are_per_finite_member():
    """Each finite member is a channel JOINT.PLATE; rigid members are not channels. At the
    model's own parameters every residual is the discretisation floor."""
    solution = solve_assembly(parse_case(tee_description()), 250.0)
    assert set(solution.residuals) == {"W1.T1"}
    assert solution.residuals["W1.T1"] < 1e-7
    every = solve_assembly(parse_case(tee_description(skin=3.0)), 250.0)
    assert set(every.residuals) == {"W1.S1", "W1.S2", "W1.T1"}
    assert max(every.residuals.values()) < 1e-7


def test_power_balances_member_by_member():
    """Per junction member, the power the line delivers into the plate (``delivered``): each
    plate's injected plus delivered power equals what it dissipates, and the members'
    deliveries sum to minus the weld's dissipation (a lossy stiffener spring, 4 % of the
    injected power). The T's line moves (the default between non-coplanar plates), so each
    plate's balance holds its in-plane power too. Exact for the exact field; the
    discretisation leaves, of the injected power at resolution 1, 1.3e-5 on the driven skin
    S1 and 1e-8 on the others (2e-7 everywhere at resolution 1.25; held lines: 2e-7), and 6e-14
    on the junction, whose deliveries balance its law exactly; so 3e-5 and 1e-10."""
    from solver.power import power_flow

    description = tee_description(stiffener=2.3)
    description["joints"]["W1"]["loss_factor"] = {"S1": 0.0, "S2": 0.0, "T1": 0.2}
    case = parse_case(description)
    power = power_flow(case, solve_assembly(case, 250.0))
    injected = power.total_injected
    assert power.joint_dissipated["W1"] > 0.01 * injected
    delivered = power.delivered["W1"]
    assert set(delivered) == {"S1", "S2", "T1"}
    assert abs(sum(delivered.values()) + power.joint_dissipated["W1"]) < 1e-10 * injected
    for plate in case.plates:
        balance = power.injected[plate] + delivered[plate] - power.dissipated[plate]
        assert abs(balance) < 3e-5 * injected, plate


@pytest.mark.parametrize("source", ["four_plates", "moving_box"])
def test_junction_corner_forces_close_each_plates_balance(source):
    """Where plate corners meet at a junction point (the centre of the four plates of Table 4,
    the corners of a box whose every fold moves), the corner forces do work on each plate and
    none in all: a plate's injected and delivered powers sum to what it dissipates only with
    its corners' power (``PowerFlow.corners``). Measured, of the injected power: the worst
    plate 8.5e-2 (four plates) and 3.0e-3 (box) without them, 3.1e-7 and 2.2e-7 with them;
    the corner powers sum to 3e-13 and 5e-15. Tolerances 1e-5 and 1e-10."""
    from solver.power import power_flow
    from test_junction_points import FREQUENCY, _moving_box

    if source == "four_plates":
        case = load_case(CASES / "four_plates.toml")
        frequency = case.frequencies[0]
    else:
        case, frequency = parse_case(_moving_box()), FREQUENCY
    power = power_flow(case, solve_assembly(case, frequency))
    injected = power.total_injected
    assert max(abs(p) for p in power.corners.values()) > 1e-3 * injected
    assert abs(sum(power.corners.values())) < 1e-10 * injected
    for plate in case.plates:
        delivered = sum(joint.get(plate, 0.0) for joint in power.delivered.values())
        balance = (power.injected[plate] + delivered + power.corners.get(plate, 0.0)
                   - power.dissipated[plate])
        assert abs(balance) < 1e-5 * injected, (plate, balance / injected)


def _problems(description):
    with pytest.raises(DescriptionError) as info:
        parse_case(description)
    return str(info.value)


def test_bad_junction_descriptions_are_refused_with_their_fix():
    tee = tee_description()
    table = tee["joints"]["W1"]["log10_stiffness"]
    cases = {
        "not a member of junction": {**table, "T2": 1.0},
        "gives no stiffness for member T1": {"S1": math.inf, "S2": math.inf},
    }
    for message, stiffness in cases.items():
        bad = {**tee, "joints": {"W1": {**tee["joints"]["W1"], "log10_stiffness": stiffness}}}
        assert message in _problems(bad)
    nan = {**tee, "joints": {"W1": {**tee["joints"]["W1"], "log10_stiffness": math.nan}}}
    assert "or inf (rigid)" in _problems(nan)
    loss = {**tee, "joints": {"W1": {**tee["joints"]["W1"], "loss_factor": math.inf}}}
    assert "must be a finite number >= 0" in _problems(loss)

    shifted = {**tee, "plates": {**tee["plates"], "T1": _plate(
        (STIFFENER_HEIGHT, LY), (0.51, 0.0, 0.0), (0.0, 0.0, 1.0))}}
    assert "do not meet in space (ends 0.01 m apart)" in _problems(shifted)
    skewed = {**tee, "plates": {**tee["plates"], "T1": _plate(
        (STIFFENER_HEIGHT, LY), (0.5, 0.0, 0.0), (0.0, 0.1, 1.0))}}
    assert "has length 1.00499, not 1" in _problems(skewed)
    oblique = {**tee, "plates": {**tee["plates"], "T1": _plate(
        (STIFFENER_HEIGHT, LY), (0.5, 0.0, 0.0), (0.0, 0.6, 0.8))}}
    assert "are not orthogonal" in _problems(oblique)
    flat = {**tee, "plates": {pid: {k: v for k, v in p.items() if k != "frame"}
                              for pid, p in tee["plates"].items()}}
    assert "needs a frame on every member plate" in _problems(flat)
    mixed = {**tee, "plates": {**tee["plates"], "S2": flat["plates"]["S2"]}}
    assert "plate 'S2' has no frame while plate 'S1' has one" in _problems(mixed)
    short = {**tee, "plates": {**tee["plates"], "T1": {**tee["plates"]["T1"],
                                                       "size": [STIFFENER_HEIGHT, 0.3]}}}
    assert "differ in length" in _problems(short)


def test_framed_two_plate_joints_must_match_their_kind():
    """A coplanar joint between plates folded at 90 degrees, or along edges running the same
    way, is refused with the kind that would fit."""
    tee = tee_description()
    plates = {"S1": tee["plates"]["S1"], "T1": tee["plates"]["T1"]}
    fold = {**tee, "plates": plates, "boundaries": [], "loads": [],
            "joints": {"G1": {"kind": "coplanar", "between": ["S1.right", "T1.left"],
                              "log10_stiffness": 2.0}}}
    assert "normals are 90 degrees apart" in _problems(fold)
    same_way = {**fold, "plates": {**plates, "T1": tee_description(flip=True)["plates"]["T1"]},
                "joints": {"G1": {**fold["joints"]["G1"], "kind": "hinge"}}}
    assert "run the same way along the line" in _problems(same_way)
    hinge = {**fold, "joints": {"G1": {**fold["joints"]["G1"], "kind": "hinge"}}}
    assert parse_case(hinge).member_directions("G1") == (1, -1)


def test_junction_truth_takes_the_joint_form():
    """``[truth.joints.W1]`` is a number for every member or a table by member plate; a table
    or ``inf`` on a two-edge joint, and a plate that is not a member, are refused."""
    tee = tee_description()
    member = {**tee, "truth": {"joints": {"W1": {"log10_stiffness": {"T1": 0.5}}}}}
    true = parse_case(member).true_case()
    assert true.joints["W1"].member_log10_stiffness("T1") == 0.5
    assert math.isinf(true.joints["W1"].member_log10_stiffness("S1"))
    every = {**tee, "truth": {"joints": {"W1": {"log10_stiffness": 1.5}}}}
    assert parse_case(every).true_case().updatable_joints().keys() == {"W1.S1", "W1.S2", "W1.T1"}
    stranger = {**tee, "truth": {"joints": {"W1": {"log10_stiffness": {"B7": 0.5}}}}}
    assert "plate 'B7' is not a member of junction 'W1'" in _problems(stranger)
    with open("cases/folded_plate.toml", "rb") as f:
        fold = tomllib.load(f)
    table = {**fold, "truth": {"joints": {"G1": {"log10_stiffness": {"P1": 1.0}}}}}
    assert "is a hinge joint: give one number, not a table" in _problems(table)
    rigid = {**fold, "truth": {"joints": {"G1": {"log10_stiffness": math.inf}}}}
    assert "whose stiffness must be finite" in _problems(rigid)


def test_member_parameters_by_joint_plate_name():
    """``with_joint_parameters`` takes a member as ``JOINT.PLATE`` and changes that member
    only; the updating sees the finite members as its joints."""
    case = parse_case(tee_description(skin=3.0))
    assert list(case.updatable_joints()) == ["W1.S1", "W1.S2", "W1.T1"]
    moved = case.with_joint_parameters({"W1.T1": {"log10_stiffness": 0.7}})
    assert moved.updatable_parameters()["W1.T1"]["log10_stiffness"] == 0.7
    assert moved.updatable_parameters()["W1.S1"]["log10_stiffness"] == 3.0
    with pytest.raises(Exception, match="a junction's member as JOINT.PLATE"):
        case.with_joint_parameters({"W1.B7": {"log10_stiffness": 0.7}})


def test_tee_is_localised_and_its_member_curve_drawn(tmp_path, capsys):
    """The TOML form (``inf`` in a table) runs through localise, plan and curve, the
    channels named JOINT.PLATE; ``--joint`` of a junction without its member is refused with
    the names to use."""
    path = tmp_path / "tee.toml"
    path.write_text(TEE_TOML)
    out = tmp_path / "localise.json"
    assert main(["localise", str(path), "--quiet", "--json", str(out)]) == 0
    assert "W1.T1" in out.read_text()
    assert main(["curve", str(path), "--joint", "W1.T1", "--samples", "5", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["curve", str(path), "--joint", "W1", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "(joints: W1.T1; a junction's finite member as JOINT.PLATE)" \
        in err[0]


def test_a_junction_member_has_no_line_mass_to_identify(tmp_path):
    """``identify = ["stiffness", "mass"]`` identifies a line mass where a joint has one
    (coplanar joints): a junction member is identified in stiffness alone, with no crash and
    no mass interval."""
    path = tmp_path / "tee.toml"
    path.write_text(TEE_TOML + '\n[updating]\nidentify = ["stiffness", "mass"]\n'
                    "[truth.joints.W1]\nlog10_stiffness = { T1 = 0.5 }\n")
    out = tmp_path / "tee.json"
    assert main(["update", str(path), "--quiet", "--json", str(out)]) in (0, 3)
    identified = json.loads(out.read_text())["identified"]
    assert set(identified) == {"W1.T1"} and "parameters" not in identified["W1.T1"]
    assert identified["W1.T1"]["log10_stiffness"] == pytest.approx(0.5, abs=0.1)


def _body(path):
    return "\n".join(line for line in path.read_text().splitlines()
                     if not line.startswith("#")).strip()


def test_junction_case_files_are_their_generator_output():
    panel = stiffened_panel(4, log10_stiffness=3.5, truth={"W2": 2.0},
                            frequency=[184.8, 230.0, 257.0], resolution=1.25,
                            name="stiffened-panel")
    assert _body(CASES / "stiffened_panel.toml") == description_toml(panel).strip()
    box = box_with_wall(truth={"W_top": 1.0}, resolution=1.5,
                        frequency=[189.6, 268.0, 277.5, 282.75])
    assert _body(CASES / "box_with_wall.toml") == description_toml(box).strip()
    case = load_case(CASES / "box_with_wall.toml")
    kinds = [j.kind for j in case.joints.values()]
    assert kinds.count("junction") == 4 and kinds.count("hinge") == 16


def test_stiffened_panel_update_corrects_the_weak_weld_only(tmp_path):
    """``vtcr update cases/stiffened_panel.toml``, measured on the skin only: W2.T2 stands
    out first, is corrected with its truth inside its interval, and W1.T1 and W3.T3 keep
    their model values (JSON keys by member channel)."""
    case = load_case(CASES / "stiffened_panel.toml")
    assert set(case.measurement.plates) == {"B1", "B2", "B3", "B4"}
    out = tmp_path / "panel.json"
    assert main(["update", str(CASES / "stiffened_panel.toml"), "--quiet", "--json", str(out),
                 "--run", str(tmp_path / "panel.run.json")]) == 0
    result = json.loads(out.read_text())
    first = result["steps"][0]["joints"]
    assert max(first, key=lambda j: first[j]["residual_percent"]) == "W2.T2"
    assert result["steps"][1]["selected"] == "W2.T2"
    assert set(result["identified"]) == {"W2.T2"}
    low, high = result["identified"]["W2.T2"]["interval"]
    assert (low is None or low <= 2.0) and (high is None or 2.0 <= high)
    last = result["steps"][-1]["joints"]
    assert last["W1.T1"]["log10_stiffness"] == last["W3.T3"]["log10_stiffness"] == 3.5


TEE_TOML = """
name = "tee"
frequency = 250.0
[materials.steel]
young_modulus = 210e9
poisson_ratio = 0.3
density = 7800.0
loss_factor = 0.01
[plates.S1]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]
frame = { origin = [0.0, 0.0, 0.0], x_axis = [1, 0, 0], y_axis = [0, 1, 0] }
[plates.S2]
material = "steel"
thickness = 0.001
size = [0.4, 0.4]
frame = { origin = [0.5, 0.0, 0.0], x_axis = [1, 0, 0], y_axis = [0, 1, 0] }
[plates.T1]
material = "steel"
thickness = 0.001
size = [0.3, 0.4]
frame = { origin = [0.5, 0.0, 0.0], x_axis = [0, 0, 1], y_axis = [0, 1, 0] }
[joints.W1]
kind = "junction"
between = ["S1.right", "S2.left", "T1.left"]
log10_stiffness = { S1 = inf, S2 = inf, T1 = 2.0 }
[[boundaries]]
edge = "S1.left"
condition = "simply_supported"
[[boundaries]]
edge = "S2.right"
condition = "simply_supported"
[[loads]]
kind = "point_force"
plate = "S1"
at = [0.17, 0.13]
amplitude = 1.0
"""
