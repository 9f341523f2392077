"""Valid descriptions: loading, defaults, complex inputs, immutability, derived cases."""

from __future__ import annotations

import copy
import json
import math
import pickle

import numpy as np
import pytest
from pydantic import ValidationError
from support import ROOT, STEEL

from assembly import (
    AssemblyError,
    Case,
    CoplanarJoint,
    DescriptionError,
    EdgeId,
    HingeJoint,
    PointForce,
    load_case,
    load_case_text,
    parse_case,
    parse_edge_ref,
    summarise,
)
from assembly.models import EdgeShear, Material, Plate
from assembly.summary import summary_text
from assembly.types import FrozenDict, JointParameters

MINIMAL = ('''\
name = "minimal"
frequency = 155.0

''' + STEEL + '''
[plates.P1]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]
''')

TWO_PLATES = ('''\
name = "two-plates"
frequencies = [150.0, 155.0]

''' + STEEL + '''
[plates.P1]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[plates.P2]
material = "steel"
thickness = 0.002
size = [0.4, 0.4]
origin = [0.5, 0.0]
rotation = 90.0

[plates.P3]
material = "steel"
thickness = 0.001
size = [0.4, 0.3]

[joints.G1]
kind = "coplanar"
between = ["P1.right", "P2.left"]
log10_stiffness = 2.0
loss_factor = 0.1
mass = 0.5

[joints.G2]
kind = "hinge"
between = ["P2.top", "P3.bottom"]
log10_stiffness = 3

[[boundaries]]
edge = "P2.right"
condition = "clamped"

[[boundaries]]
edge = "P1.bottom"
condition = "simply_supported"

[[loads]]
kind = "edge_shear"
edge = "P1.left"
amplitude = [1.0, -0.5]
distribution = "half_sine"

[[loads]]
kind = "edge_moment"
edge = "P1.bottom"
amplitude = 2

[[loads]]
kind = "point_force"
plate = "P3"
at = [0.1, 0.1]
amplitude = 1.5

[discretisation]
resolution = 1.5
interface_functions = 16

[discretisation.plates.P1]
interior = 48
corner = 1

[measurement]
spacing = 0.05
plates = ["P1"]
noise = 0.2
seed = 7
points = [{plate = "P3", at = [0.0, 0.3]}]

[updating]
r = 0.5
alpha = {G1 = 3.0}
bounds = [-1.0, 6.0]
identify = ["stiffness", "damping"]

[truth.joints.G1]
log10_stiffness = 1.0
mass = 0.0

[truth.joints.G2]
loss_factor = 0.2
''')


@pytest.fixture(scope="module")
def two() -> Case:
    return load_case_text(TWO_PLATES, source="two.toml")


def test_minimal_description_gets_defaults() -> None:
    case = load_case_text(MINIMAL)
    assert case.name == "minimal"
    assert case.frequency == 155.0
    assert case.frequencies == (155.0,)
    assert case.joints == {} and case.boundaries == () and case.loads == ()
    plate = case.plates["P1"]
    assert plate.origin == (0.0, 0.0) and plate.rotation == 0.0
    d = case.discretisation
    assert (d.resolution, d.quadrature_per_sector, d.edge_wavenumber_ratio) == (1.0, 8, 2.5)
    assert d.interface_functions is None and d.plates == {}
    assert d.for_plate("P1").interior is None
    m = case.measurement
    assert (m.spacing, m.plates, m.noise, m.seed, m.resolution, m.points) == (
        0.1, None, 0.0, 1, 1.6, ())
    u = case.updating
    assert (u.r, u.bounds, u.identify, u.max_steps, u.stop_ratio, u.min_decrease) == (
        "auto", (-3.0, 7.0), ("stiffness",), 8, 3.0, 0.01)
    assert (u.balance, u.misfit, u.misfit_kind) == (2000.0, None, "per_plate")
    assert u.alpha == {}
    assert case.truth.joints == {}
    assert case.edge_conditions()[EdgeId("P1", "left")] == "free"


def test_full_description(two: Case) -> None:
    assert two.frequency is None
    assert two.frequencies == (150.0, 155.0)
    g1, g2 = two.joints["G1"], two.joints["G2"]
    assert isinstance(g1, CoplanarJoint) and isinstance(g2, HingeJoint)
    assert (g1.log10_stiffness, g1.loss_factor, g1.mass) == (2.0, 0.1, 0.5)
    assert (g2.log10_stiffness, g2.loss_factor, g2.mass) == (3.0, 0.0, 0.0)
    assert isinstance(g2.log10_stiffness, float)
    assert g1.sides == (EdgeId("P1", "right"), EdgeId("P2", "left"))
    assert g1.plates == ("P1", "P2")
    assert g1.stiffness == pytest.approx(100.0)
    assert g1.complex_stiffness == pytest.approx(100.0 + 10.0j)
    assert two.discretisation.for_plate("P1").interior == 48
    assert two.discretisation.interface_functions == 16
    assert two.measured_plates() == ("P1",)
    assert two.edge_length("P2.top") == 0.4
    assert two.material_of("P2").density == 7800.0


def test_complex_amplitudes(two: Case) -> None:
    shear, moment, force = two.loads
    assert isinstance(shear, EdgeShear) and isinstance(force, PointForce)
    assert shear.amplitude == complex(1.0, -0.5)
    assert moment.amplitude == 2 + 0j and isinstance(moment.amplitude, complex)
    assert force.amplitude == 1.5 + 0j
    assert shear.distribution == "half_sine" and moment.distribution == "uniform"
    s = np.linspace(0.0, 0.4, 5)
    np.testing.assert_allclose(shear.profile(s, 0.4), (1 - 0.5j) * np.sin(np.pi * s / 0.4))
    np.testing.assert_allclose(moment.profile(s, 0.4), np.full(5, 2 + 0j))
    # Complex values serialise as [re, im] and read back.
    assert shear.model_dump()["amplitude"] == [1.0, -0.5]
    assert EdgeShear.model_validate(shear.model_dump()) == shear
    assert EdgeShear(edge="P1.left", amplitude=3 - 1j).amplitude == 3 - 1j


@pytest.mark.parametrize("bad", [True, "1", [1.0], [1.0, 2.0, 3.0], {"re": 1}, [1.0, "x"],
                                 float("nan"), [1.0, float("inf")]])
def test_complex_rejects(bad: object) -> None:
    with pytest.raises(ValidationError, match=r"number or \[re, im\]|finite"):
        EdgeShear(edge="P1.left", amplitude=bad)


def test_edge_conditions_and_joints(two: Case) -> None:
    conditions = two.edge_conditions()
    assert len(conditions) == 12
    assert conditions[EdgeId("P1", "right")] == "joined"
    assert conditions[EdgeId("P2", "right")] == "clamped"
    assert conditions[EdgeId("P1", "bottom")] == "simply_supported"
    assert conditions[EdgeId("P3", "left")] == "free"
    assert two.edge_joints() == {
        EdgeId("P1", "right"): "G1", EdgeId("P2", "left"): "G1",
        EdgeId("P2", "top"): "G2", EdgeId("P3", "bottom"): "G2",
    }


def test_alpha_is_completed_and_normalised(two: Case) -> None:
    assert two.updating.alpha == pytest.approx({"G1": 0.75, "G2": 0.25})
    default = load_case_text(TWO_PLATES.replace("alpha = {G1 = 3.0}\n", ""))
    assert default.updating.alpha == pytest.approx({"G1": 0.5, "G2": 0.5})


def test_measurement_points(two: Case) -> None:
    points = two.measurement_points()
    grid = [p for p in points if p[0] == "P1"]
    # 0.5 x 0.4 m at 0.05 m: 10 x 8 cell centres.
    assert len(grid) == 10 * 8
    xs = sorted({round(x, 12) for _, x, _ in grid})
    assert xs[0] == pytest.approx(0.025) and xs[-1] == pytest.approx(0.475)
    assert [p[0] for p in grid[:2]] == ["P1", "P1"]
    np.testing.assert_allclose([p[1:] for p in grid[:2]], [[0.025, 0.025], [0.025, 0.075]])
    assert points[-1] == ("P3", 0.0, 0.3)


def test_joint_parameters_are_read_only_and_change_by_copy(four_plates_case) -> None:
    """The updating passes one set of joint parameters from step to step without copying it:
    neither level can be changed in place, a change makes a new set that shares the other
    joints, and a set compares, hashes and serialises like the plain dicts it replaces."""
    case = four_plates_case
    parameters = case.updatable_parameters()
    assert isinstance(parameters, JointParameters)
    with pytest.raises(TypeError):
        parameters["G1"] = {}
    with pytest.raises(TypeError):
        parameters["G1"]["log10_stiffness"] = 0.0
    changed = parameters.with_joint("G2", log10_stiffness=1.5)
    assert changed["G2"]["log10_stiffness"] == 1.5
    assert parameters["G2"]["log10_stiffness"] == case.joints["G2"].log10_stiffness
    assert changed["G1"] is parameters["G1"]
    plain = {j: dict(p) for j, p in parameters.items()}
    assert JointParameters.of(plain) == parameters == plain
    assert JointParameters.of(parameters) is parameters
    assert hash(JointParameters.of(plain)) == hash(parameters)
    assert json.loads(json.dumps(changed)) == {j: dict(p) for j, p in changed.items()}


def test_parse_edge_ref() -> None:
    assert parse_edge_ref("P1.right") == EdgeId("P1", "right")
    assert parse_edge_ref("P1.right").ref == "P1.right"
    for bad in ["P1", "P1.", ".right", "P1.up", "a.b.c", 3]:
        with pytest.raises(AssemblyError):
            parse_edge_ref(bad)  # type: ignore[arg-type]


def test_case_edge_lookup(two: Case) -> None:
    assert two.edge("P3.top") == EdgeId("P3", "top")
    assert two.edge(EdgeId("P3", "top")) == EdgeId("P3", "top")
    with pytest.raises(AssemblyError, match="'P9' is not in the assembly"):
        two.edge("P9.top")


def test_plate_geometry() -> None:
    plate = Plate(material="steel", thickness=0.001, size=(0.5, 0.4), origin=(1.0, 2.0),
                  rotation=90.0)
    assert plate.edge_length("left") == 0.4 and plate.edge_length("top") == 0.5
    for edge in ("left", "right", "bottom", "top"):
        start, t, n, length = plate.edge_frame(edge)
        # t = e_z x n, and the edge ends where the next (counter-clockwise) one starts.
        np.testing.assert_allclose(t, [-n[1], n[0]])
        end = start + length * t
        assert plate.contains(*(0.5 * (start + end)), strict=False)
        assert not plate.contains(*(0.5 * (start + end)))
    assert plate.contains(0.25, 0.2) and not plate.contains(0.5, 0.2)
    x, y = plate.to_global([0.5], [0.0])
    np.testing.assert_allclose([x[0], y[0]], [1.0, 2.5], atol=1e-12)
    with pytest.raises(AssemblyError):
        plate.edge_length("north")


def test_bending_wavelength_matches_design_check_t1() -> None:
    """T1 of ``docs/method.md`` section 8.1: steel, h = 2 mm, 500 Hz: D = 153.85 N m,
    kappa0 = 31.63."""
    steel = Material(young_modulus=210e9, poisson_ratio=0.3, density=7800.0, loss_factor=0.01)
    assert steel.flexural_rigidity(0.002) == pytest.approx(153.846, rel=1e-4)
    assert steel.bending_wavenumber(0.002, 500.0) == pytest.approx(31.63, rel=1e-3)
    assert steel.bending_wavelength(0.002, 500.0) == pytest.approx(0.1986, rel=1e-3)
    kappa = steel.bending_wavenumber(0.002, [500.0, 2000.0])
    assert kappa.shape == (2,) and kappa[1] == pytest.approx(2 * kappa[0])


def test_models_are_immutable(two: Case) -> None:
    with pytest.raises(ValidationError):
        two.name = "other"  # type: ignore[misc]
    with pytest.raises(ValidationError):
        two.joints["G1"].log10_stiffness = 5.0  # type: ignore[misc]
    with pytest.raises(TypeError, match="read-only"):
        two.joints["G3"] = two.joints["G1"]  # type: ignore[index]
    with pytest.raises(TypeError, match="read-only"):
        two.plates.pop("P1")
    assert isinstance(two.joints, FrozenDict) and isinstance(two.updating.alpha, FrozenDict)
    assert copy.deepcopy(two) == two
    assert pickle.loads(pickle.dumps(two)) == two
    assert hash(two) == hash(copy.deepcopy(two))


def test_with_joint_parameters_builds_a_copy(two: Case) -> None:
    before = two.model_dump()
    new = two.with_joint_parameters(
        {"G1": {"log10_stiffness": 1.0, "mass": 0.25}, "G2": {"loss_factor": np.float64(0.3)}}
    )
    assert two.model_dump() == before  # the original is untouched
    assert new is not two and new != two
    assert new.joints["G1"].log10_stiffness == 1.0 and new.joints["G1"].mass == 0.25
    assert new.joints["G1"].loss_factor == 0.1  # not given: kept
    assert new.joints["G2"].loss_factor == 0.3 and type(new.joints["G2"].loss_factor) is float
    assert new.plates is two.plates  # unchanged tables are shared, not copied
    assert new.joint_parameters() == {
        "G1": {"log10_stiffness": 1.0, "loss_factor": 0.1, "mass": 0.25},
        "G2": {"log10_stiffness": 3.0, "loss_factor": 0.3},
    }
    assert two.with_joint_parameters({}) == two
    # A hinge accepts mass = 0 (no-op), nothing else.
    assert two.with_joint_parameters({"G2": {"mass": 0.0}}) == two


@pytest.mark.parametrize(
    ("parameters", "match"),
    [
        ({"G9": {"log10_stiffness": 1.0}}, "'G9' is not in the assembly"),
        ({"G1": {"stiffness": 1.0}}, "not a joint parameter"),
        ({"G1": {"log10_stiffness": "1"}}, "must be a real number"),
        ({"G1": {"log10_stiffness": True}}, "must be a real number"),
        ({"G1": {"loss_factor": -1.0}}, "invalid parameters for joint 'G1'"),
        ({"G1": {"log10_stiffness": math.nan}}, "invalid parameters"),
        ({"G2": {"mass": 1.0}}, "is a hinge"),
        ({"G1": 2.0}, "must be a mapping"),
    ],
)
def test_with_joint_parameters_rejects(two: Case, parameters: dict, match: str) -> None:
    with pytest.raises(AssemblyError, match=match):
        two.with_joint_parameters(parameters)


def test_true_case(two: Case) -> None:
    true = two.true_case()
    assert true.joints["G1"].log10_stiffness == 1.0 and true.joints["G1"].mass == 0.0
    assert true.joints["G1"].loss_factor == 0.1  # not in truth: model value
    assert true.joints["G2"].loss_factor == 0.2 and true.joints["G2"].log10_stiffness == 3.0
    assert two.joints["G1"].log10_stiffness == 2.0  # the model is untouched
    assert true.true_case() == true
    assert load_case_text(MINIMAL).true_case() == load_case_text(MINIMAL)


def test_dump_round_trip(two: Case) -> None:
    assert parse_case(two.model_dump()) == two
    minimal = load_case_text(MINIMAL)
    dumped = minimal.model_dump()
    assert "frequency" in dumped and "frequencies" not in dumped
    assert parse_case(dumped) == minimal
    assert Case.model_validate_json(two.model_dump_json()) == two


def test_model_validate_reports_references() -> None:
    data = {"name": "x", "frequency": 1.0, "materials": {},
            "plates": {"P1": {"material": "steel", "thickness": 1.0, "size": [1.0, 1.0]}}}
    with pytest.raises(ValidationError, match="plates.P1.material: material 'steel'"):
        Case.model_validate(data)


def test_example_cases_load() -> None:
    for path in sorted((ROOT / "cases").glob("*.toml")):
        case = load_case(path)
        assert case.frequencies
    single = load_case(ROOT / "cases" / "single_plate.toml")
    assert single.plates["P1"].size == (0.5, 0.4)
    assert set(single.edge_conditions().values()) == {"simply_supported"}
    (force,) = single.loads
    assert isinstance(force, PointForce) and force.at == (0.12, 0.31) and force.amplitude == 1


def test_description_error_is_value_error() -> None:
    with pytest.raises(ValueError) as info:
        load_case_text('name = "x"', source="x.toml")
    err = info.value
    assert isinstance(err, DescriptionError)
    assert [i.path for i in err.issues] == ["frequency", "materials", "plates"]
    assert err.source == "x.toml"


def test_summary_text(two: Case) -> None:
    text = summary_text(two)
    assert text.splitlines()[0].startswith("Assembly 'two-plates': 3 plate(s), 2 joint(s)")
    assert "lambda @ 150 Hz" in text and "lambda @ 155 Hz" in text
    assert "P1.right - P2.left" in text and "hinge" in text
    assert "Graph: connected" in text
    assert "half_sine" in text and "1 - 0.5j N/m" in text
    steel = two.materials["steel"]
    lam = steel.bending_wavelength(0.001, 155.0)
    assert f"{lam:.3g} ({0.5 / lam:.1f} x {0.4 / lam:.1f})" in text
    assert summarise(two, style="text") == text


def test_summary_mentions_disconnected_assembly(two: Case) -> None:
    apart = load_case_text(TWO_PLATES.replace(
        '[joints.G2]\nkind = "hinge"\nbetween = ["P2.top", "P3.bottom"]\nlog10_stiffness = 3\n',
        "").replace("[truth.joints.G2]\nloss_factor = 0.2\n", ""))
    text = summary_text(apart)
    assert "NOT connected, 2 sub-assemblies: {P1, P2}; {P3}" in text


def test_summary_rich() -> None:
    pytest.importorskip("rich")
    from rich.console import Console

    console = Console(record=True, width=200)
    console.print(summarise(load_case_text(TWO_PLATES), style="rich"))
    out = console.export_text()
    assert "Plates" in out and "two-plates" in out and "P1.right - P2.left" in out
