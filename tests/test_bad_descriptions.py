"""A catalogue of bad assembly descriptions and the messages they must produce.

Each entry starts from a valid two-plate description (``BASE``), breaks one thing, and
checks that :class:`assembly.DescriptionError` names the right field path and says how to
fix it.  Every message is one line ``source: path: what is wrong; how to fix it``.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import STEEL

from assembly import Case, DescriptionError, load_case, load_case_text, parse_case

SOURCE = "cases/bad.toml"

BASE = ('''\
name = "two-plates"
frequency = 155.0

''' + STEEL + '''
[plates.P1]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[plates.P2]
material = "steel"
thickness = 0.001
size = [0.4, 0.4]
origin = [0.5, 0.0]

[joints.G1]
kind = "coplanar"
between = ["P1.right", "P2.left"]
log10_stiffness = 2.0
loss_factor = 0.1

[[boundaries]]
edge = "P2.right"
condition = "clamped"

[[loads]]
kind = "edge_shear"
edge = "P1.left"
amplitude = 1.0

[[loads]]
kind = "point_force"
plate = "P1"
at = [0.12, 0.31]
amplitude = [1.0, 0.5]

[discretisation]
resolution = 1.0

[discretisation.plates.P1]
interior = 48

[measurement]
spacing = 0.1
plates = ["P1", "P2"]
noise = 0.1

[[measurement.points]]
plate = "P2"
at = [0.2, 0.2]

[updating]
r = 0.8
alpha = {G1 = 1.0}
bounds = [-3.0, 7.0]

[truth.joints.G1]
log10_stiffness = 1.5
''')


def replace(old: str, new: str, count: int = 1) -> Callable[[str], str]:
    """Return a mutation replacing the first `count` occurrences of `old` (must exist)."""

    def mutate(text: str) -> str:
        assert old in text, f"{old!r} not in the base description"
        return text.replace(old, new, count)

    return mutate


def append(extra: str) -> Callable[[str], str]:
    """Return a mutation appending TOML to the description."""
    return lambda text: text + "\n" + extra


def chain(*mutations: Callable[[str], str]) -> Callable[[str], str]:
    def mutate(text: str) -> str:
        for m in mutations:
            text = m(text)
        return text

    return mutate


P1_TABLE = '[plates.P1]\nmaterial = "steel"\n'
G1_KIND = 'kind = "coplanar"\nbetween = ["P1.right", "P2.left"]'
SHEAR = 'kind = "edge_shear"\nedge = "P1.left"'

# (id, mutation, expected field path, fragments the message must contain)
CATALOGUE: list[tuple[str, Callable[[str], str], str, tuple[str, ...]]] = [
    ("unknown-material", replace('material = "steel"\nthickness = 0.001\nsize = [0.4',
                                 'material = "alu"\nthickness = 0.001\nsize = [0.4'),
     "plates.P2.material", ("'alu' is not defined", "add a [materials.alu] table")),
    ("unknown-plate-in-joint", replace('"P2.left"]', '"P9.left"]'),
     "joints.G1.between[1]", ("plate 'P9' is not in the assembly (plates: P1, P2)",
                              "fix the edge reference")),
    ("unknown-edge-name", replace('"P2.left"]', '"P2.lefft"]'),
     "joints.G1.between[1]", ("not an edge name", "did you mean 'left'", "fix the edge")),
    ("malformed-edge-reference", replace('"P2.left"]', '"P2left"]'),
     "joints.G1.between[1]", ("malformed edge reference", "write 'PLATE.EDGE'")),
    ("joint-one-edge-only", replace('["P1.right", "P2.left"]', '["P1.right"]'),
     "joints.G1.between", ("too few items", 'between = ["P1.right", "P2.left"]')),
    ("joint-edges-of-different-length", replace("size = [0.4, 0.4]", "size = [0.4, 0.3]"),
     "joints.G1.between", ("'P1.right' is 0.4 m", "'P2.left' is 0.3 m", "equal length")),
    ("joint-edge-to-itself", replace('["P1.right", "P2.left"]', '["P1.right", "P1.right"]'),
     "joints.G1.between", ("to itself", "different plates")),
    ("joint-same-plate", replace('["P1.right", "P2.left"]', '["P1.right", "P1.left"]'),
     "joints.G1.between", ("same plate 'P1'", "fix the edge references")),
    ("edge-joined-twice", append('[joints.G2]\nkind = "hinge"\nbetween = ["P1.right", '
                                 '"P2.left"]\nlog10_stiffness = 1.0'),
     "joints.G2.between[0]", ("already joined by joint 'G1'", "remove one of the joints")),
    ("joined-edge-with-boundary", append('[[boundaries]]\nedge = "P1.right"\n'
                                         'condition = "clamped"'),
     "boundaries[1].edge", ("joined by joint 'G1'", "remove this [[boundaries]] entry")),
    ("two-boundary-conditions", append('[[boundaries]]\nedge = "P2.right"\n'
                                       'condition = "simply_supported"'),
     "boundaries[1].edge", ("already has a boundary condition (clamped in boundaries[0])",
                            "remove one entry")),
    ("edge-shear-on-clamped-edge", replace(SHEAR, 'kind = "edge_shear"\nedge = "P2.right"'),
     "loads[0].edge", ("clamped", "K_n is a reaction", "load a free edge")),
    ("edge-shear-on-joined-edge", replace(SHEAR, 'kind = "edge_shear"\nedge = "P1.right"'),
     "loads[0].edge", ("joined by joint 'G1'", "load a free edge")),
    ("edge-shear-on-simply-supported-edge",
     append('[[boundaries]]\nedge = "P1.left"\ncondition = "simply_supported"'),
     "loads[0].edge", ("simply supported", "K_n is a reaction", "use a point_force")),
    ("edge-moment-on-clamped-edge", replace(SHEAR, 'kind = "edge_moment"\nedge = "P2.right"'),
     "loads[0].edge", ("M_n is a reaction", "load a free or simply supported edge")),
    ("edge-moment-on-joined-edge", replace(SHEAR, 'kind = "edge_moment"\nedge = "P2.left"'),
     "loads[0].edge", ("joined by joint 'G1'", "load a free or simply supported edge")),
    ("two-shears-on-one-edge", append('[[loads]]\nkind = "edge_shear"\nedge = "P1.left"\n'
                                      'amplitude = 2.0'),
     "loads[2].edge", ("already carries an edge_shear load (loads[0])", "amplitudes summed")),
    ("zero-thickness", replace("thickness = 0.001", "thickness = 0.0"),
     "plates.P1.thickness", ("must be > 0", "thickness = 0.001 (m)")),
    ("negative-size", replace("size = [0.5, 0.4]", "size = [-0.5, 0.4]"),
     "plates.P1.size[0]", ("must be > 0", "size = [0.5, 0.4]")),
    ("nan-thickness", replace("thickness = 0.001", "thickness = nan"),
     "plates.P1.thickness", ("finite number", "thickness = 0.001")),
    ("negative-frequency", replace("frequency = 155.0", "frequency = -155.0"),
     "frequency", ("must be > 0", "frequency = 155.0 (Hz)")),
    ("no-frequency", replace("frequency = 155.0", ""),
     "frequency", ("no frequency given", "add frequency = 155.0")),
    ("frequency-and-frequencies", replace("frequency = 155.0",
                                          "frequency = 155.0\nfrequencies = [150.0]"),
     "frequencies", ("both", "keep only one")),
    ("duplicate-frequencies", replace("frequency = 155.0", "frequencies = [150.0, 150.0]"),
     "frequencies", ("150 Hz is listed twice", "list each frequency once")),
    ("empty-frequencies", replace("frequency = 155.0", "frequencies = []"),
     "frequencies", ("empty", "at least one frequency")),
    ("material-without-damping", replace("loss_factor = 0.01", "loss_factor = 0.0"),
     "materials.steel.loss_factor", ("the VTCR needs eta > 0", "e.g. 0.01")),
    ("poisson-ratio-too-large", replace("poisson_ratio = 0.3", "poisson_ratio = 0.5"),
     "materials.steel.poisson_ratio", ("must be < 0.5", "poisson_ratio = 0.3")),
    ("point-force-outside-plate", replace("at = [0.12, 0.31]", "at = [0.6, 0.1]"),
     "loads[1].at", ("not strictly inside plate 'P1'", "move the force inside the plate")),
    ("point-force-on-edge", replace("at = [0.12, 0.31]", "at = [0.0, 0.1]"),
     "loads[1].at", ("not strictly inside", "move the force inside the plate")),
    ("point-force-unknown-plate", replace('plate = "P1"', 'plate = "P3"'),
     "loads[1].plate", ("plate 'P3' is not in the assembly", "fix the plate id")),
    ("unknown-key", replace(P1_TABLE, P1_TABLE + 'colour = "red"\n'),
     "plates.P1.colour", ("unknown key `colour`", "remove it", "allowed: material")),
    ("misspelt-key", replace("thickness = 0.001\nsize = [0.5", "thicknes = 0.001\nsize = [0.5"),
     "plates.P1.thicknes", ("did you mean 'thickness'", "remove it or fix its spelling")),
    ("missing-key", replace("thickness = 0.001\nsize = [0.5", "size = [0.5"),
     "plates.P1.thickness", ("`thickness` is missing", "add it")),
    ("misspelt-section", replace("[discretisation]", "[discretization]"),
     "discretization", ("did you mean 'discretisation'",)),
    ("duplicate-plate-table", append('[plates.P1]\nmaterial = "steel"'),
     "line 65, column 11", ("table [plates.P1] is declared twice", "ids must be unique")),
    ("duplicate-key", replace("thickness = 0.001\n", "thickness = 0.001\nthickness = 0.002\n"),
     "line 13, column 18", ("key 'thickness' is given twice", "remove or rename")),
    ("toml-syntax", replace("thickness = 0.001", "thickness = 0,001"),
     "line 12, column 14", ("TOML syntax error", "fix the syntax")),
    ("unknown-joint-kind", replace(G1_KIND, 'kind = "weld"\nbetween = ["P1.right", "P2.left"]'),
     "joints.G1.kind", ("unknown kind 'weld'", 'use kind = "coplanar" or "hinge"')),
    ("missing-joint-kind", replace(G1_KIND, 'between = ["P1.right", "P2.left"]'),
     "joints.G1.kind", ("`kind` is missing", 'add kind = "coplanar" or "hinge"')),
    ("hinge-with-mass", replace(G1_KIND, 'kind = "hinge"\nmass = 1.0\nbetween = ["P1.right", '
                                         '"P2.left"]'),
     "joints.G1.mass", ("unknown key `mass`", "remove it")),
    ("negative-joint-loss-factor", replace("loss_factor = 0.1", "loss_factor = -0.1"),
     "joints.G1.loss_factor", ("must be >= 0", "zeta >= 0")),
    ("misspelt-condition", replace('condition = "clamped"', 'condition = "clampd"'),
     "boundaries[0].condition", ("did you mean 'clamped'", "use one of them")),
    ("unknown-load-kind", replace(SHEAR, 'kind = "pressure"\nedge = "P1.left"'),
     "loads[0].kind", ("unknown kind 'pressure'", 'use kind = "edge_shear"')),
    ("amplitude-string", replace("amplitude = 1.0", 'amplitude = "1.0"'),
     "loads[0].amplitude", ("number or [re, im]", "write e.g. 1.0 or [1.0, 0.5]")),
    ("amplitude-three-numbers", replace("amplitude = [1.0, 0.5]", "amplitude = [1.0, 0.5, 2.0]"),
     "loads[1].amplitude", ("number or [re, im]", "write e.g.")),
    ("thickness-as-string", replace("thickness = 0.001", 'thickness = "0.001"'),
     "plates.P1.thickness", ("must be a number", "a string", "write a number")),
    ("bad-plate-id", append('[plates."P 3"]\nmaterial = "steel"\nthickness = 0.001\n'
                            'size = [0.2, 0.2]'),
     'plates."P 3"', ("may only contain letters, digits", "rename it")),
    ("discretisation-unknown-plate", replace("[discretisation.plates.P1]",
                                             "[discretisation.plates.P9]"),
     "discretisation.plates.P9", ("plate 'P9' is not in the assembly", "remove the table")),
    ("too-few-interior-rays", replace("interior = 48", "interior = 2"),
     "discretisation.plates.P1.interior", ("must be >= 4", "interior = 48")),
    ("quadrature-not-whole", append("[discretisation.plates.P2]\ncorner = 1.5"),
     "discretisation.plates.P2.corner", ("whole number", "corner = 1")),
    ("plate-reach-too-short", append("[discretisation.plates.P2]\nedge_wavenumber_ratio = 1.0"),
     "discretisation.plates.P2.edge_wavenumber_ratio",
     ("must be > 1", "edge_wavenumber_ratio = 10.0")),
    ("measurement-unknown-plate", replace('plates = ["P1", "P2"]', 'plates = ["P1", "P7"]'),
     "measurement.plates[1]", ("plate 'P7' is not in the assembly", "fix the plate id")),
    ("measurement-point-outside", replace("at = [0.2, 0.2]", "at = [0.5, 0.2]"),
     "measurement.points[0].at", ("outside plate 'P2'", "move the point onto the plate")),
    ("negative-noise", replace("noise = 0.1", "noise = -0.1"),
     "measurement.noise", ("must be >= 0", "noise = 0.1")),
    ("alpha-unknown-joint", replace("alpha = {G1 = 1.0}", "alpha = {G9 = 1.0}"),
     "updating.alpha.G9", ("joint 'G9' is not in the assembly (joints: G1)",
                           "remove its weight")),
    ("alpha-all-zero", replace("alpha = {G1 = 1.0}", "alpha = {G1 = 0.0}"),
     "updating.alpha", ("sum to 0", "positive weight")),
    ("bounds-order", replace("bounds = [-3.0, 7.0]", "bounds = [7.0, -3.0]"),
     "updating.bounds", ("not below upper bound", "lo < hi")),
    ("r-zero", replace("r = 0.8", "r = 0.0"),
     "updating.r", ("must be > 0", "r = 0.8")),
    ("updating-unknown-table", append('[updating.extra]\n'),
     "updating.extra", ("unknown key `extra`", "allowed: r, alpha")),
    ("identify-unknown", replace("r = 0.8", 'r = 0.8\nidentify = ["stifness"]'),
     "updating.identify[0]", ("did you mean 'stiffness'",)),
    ("truth-unknown-joint", replace("[truth.joints.G1]", "[truth.joints.G7]"),
     "truth.joints.G7", ("joint 'G7' is not in the assembly", "remove its table")),
    ("truth-mass-not-a-number", chain(replace(G1_KIND, 'kind = "hinge"\nbetween = ["P1.right", '
                                                   '"P2.left"]'),
                                  append("[truth.joints.G1.mass]\n")),
     "truth.joints.G1.mass", ("must be a number",)),
    ("truth-mass-value-on-hinge", chain(replace(G1_KIND, 'kind = "hinge"\nbetween = '
                                                         '["P1.right", "P2.left"]'),
                                        replace("log10_stiffness = 1.5",
                                                "log10_stiffness = 1.5\nmass = 2.0")),
     "truth.joints.G1.mass", ("is a hinge, which has no line mass", "remove `mass`")),
    ("no-plates", lambda text: 'name = "x"\nfrequency = 1.0\n[materials.steel]\n'
                               "young_modulus = 1.0\npoisson_ratio = 0.3\ndensity = 1.0\n"
                               "loss_factor = 0.01\n[plates]\n",
     "plates", ("no plates defined", "add at least one [plates.ID] table")),
    ("name-not-string", replace('name = "two-plates"', "name = 3"),
     "name", ("must be a non-empty string", "quote it")),
]


def test_base_is_valid() -> None:
    case = load_case_text(BASE, source=SOURCE)
    assert isinstance(case, Case)
    assert set(case.plates) == {"P1", "P2"}


def test_catalogue_is_large_and_unique() -> None:
    ids = [entry[0] for entry in CATALOGUE]
    assert len(ids) >= 25
    assert len(set(ids)) == len(ids)


@pytest.mark.parametrize(
    ("mutate", "path", "fragments"),
    [pytest.param(m, p, f, id=i) for i, m, p, f in CATALOGUE],
)
def test_bad_description(
    mutate: Callable[[str], str], path: str, fragments: tuple[str, ...]
) -> None:
    text = mutate(BASE)
    with pytest.raises(DescriptionError) as info:
        load_case_text(text, source=SOURCE)
    err = info.value
    assert isinstance(err, ValueError)
    assert str(err) == "\n".join(err.messages)
    for message in err.messages:
        assert "\n" not in message
        assert message.startswith(f"{SOURCE}: ")
    prefix = f"{SOURCE}: {path}: "
    matching = [m for m in err.messages if m.startswith(prefix)]
    assert matching, f"no message for {path!r} in:\n{err}"
    assert any(all(f in m for f in fragments) for m in matching), (
        f"expected {fragments} in a message for {path!r}; got:\n{err}"
    )


def test_several_errors_are_all_reported() -> None:
    text = chain(
        replace("thickness = 0.001", "thickness = -1.0"),  # P1, schema
        replace('material = "steel"\nthickness = 0.001\nsize = [0.4',
                'material = "alu"\nthickness = 0.001\nsize = [0.4'),  # P2, reference
        replace('"P2.left"]', '"P9.left"]'),  # joint, reference
        replace('condition = "clamped"', 'condition = "fixed"'),  # boundary, schema
        replace("at = [0.12, 0.31]", "at = [0.6, 0.31]"),  # point force, reference
        append("[[boundaries]]\nedge = \"P1.right\"\ncondition = \"free\""),  # joined edge
        replace("noise = 0.1", "noise = 0.1\nnoize = 0.2"),  # unknown key
    )(BASE)
    with pytest.raises(DescriptionError) as info:
        load_case_text(text, source=SOURCE)
    paths = {issue.path for issue in info.value.issues}
    expected = {
        "plates.P1.thickness",
        "plates.P2.material",
        "joints.G1.between[1]",
        "boundaries[0].condition",
        "loads[1].at",
        "boundaries[1].edge",
        "measurement.noize",
    }
    assert expected <= paths, str(info.value)
    assert len(info.value.messages) == len(set(info.value.messages))


def test_all_reference_errors_at_once() -> None:
    text = chain(
        replace('"P2.left"]', '"P9.left"]'),
        replace('plates = ["P1", "P2"]', 'plates = ["P1", "P7"]'),
        replace("alpha = {G1 = 1.0}", "alpha = {G9 = 1.0}"),
    )(BASE)
    with pytest.raises(DescriptionError) as info:
        load_case_text(text, source=SOURCE)
    paths = [issue.path for issue in info.value.issues]
    assert paths == ["joints.G1.between[1]", "measurement.plates[1]", "updating.alpha.G9"]


def test_missing_file(tmp_path) -> None:
    missing = tmp_path / "nope.toml"
    with pytest.raises(DescriptionError, match="file not found") as info:
        load_case(missing)
    assert info.value.messages[0].startswith(str(missing))


def test_directory_and_bad_encoding(tmp_path) -> None:
    with pytest.raises(DescriptionError, match="is a directory"):
        load_case(tmp_path)
    bad = tmp_path / "latin.toml"
    bad.write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(DescriptionError, match="line 1: is not valid UTF-8"):
        load_case(bad)


def test_syntax_error_names_file_and_line(tmp_path) -> None:
    path = tmp_path / "x.toml"
    path.write_text(BASE.replace("size = [0.5, 0.4]", "size = [0.5, 0.4"), encoding="utf-8")
    with pytest.raises(DescriptionError) as info:
        load_case(path)
    (message,) = info.value.messages
    assert message.startswith(f"{path}: line ")
    assert "unclosed array" in message


def test_parse_case_rejects_non_mapping() -> None:
    with pytest.raises(DescriptionError, match="must be a table of sections"):
        parse_case([1, 2, 3], source="<x>")  # type: ignore[arg-type]


# ----------------------------------------------------------------------------------------
# Fuzzing: a mutated description either loads or raises DescriptionError, nothing else.
# ----------------------------------------------------------------------------------------
BASE_DATA = tomllib.loads(BASE)


def _paths(node: object, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _paths(value, (*prefix, i))
    return out


PATHS = _paths(BASE_DATA)[1:]

scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**20), max_value=10**20),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["", "P1", "P2", "P1.right", "P2.left", "P1.", ".left", "G1", "steel",
                     "coplanar", "hinge", "clamped", "edge_shear", "point_force", "x.y.z"]),
    st.text(max_size=8),
)
values = st.recursive(
    scalars,
    lambda children: st.one_of(
        st.lists(children, max_size=3),
        st.dictionaries(st.sampled_from(["kind", "edge", "plate", "at", "size", "x", "G1",
                                         "P1", "mass", "between"]), children, max_size=3),
    ),
    max_leaves=6,
)


def _mutate(data: object, path: tuple, action: str, value: object) -> None:
    parent = data
    for key in path[:-1]:
        parent = parent[key]  # type: ignore[index]
    key = path[-1]
    if action == "delete":
        del parent[key]  # type: ignore[attr-defined]
    elif action == "set":
        parent[key] = value  # type: ignore[index]
    elif action == "add" and isinstance(parent, dict):
        parent[f"{key}_extra"] = value
    elif action == "add" and isinstance(parent, list):
        parent.append(value)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_fuzz_mutated_dicts(data: st.DataObject) -> None:
    description = tomllib.loads(BASE)
    for _ in range(data.draw(st.integers(1, 3))):
        paths = _paths(description)[1:]
        if not paths:
            break
        path = data.draw(st.sampled_from(paths))
        action = data.draw(st.sampled_from(["delete", "set", "add"]))
        _mutate(description, path, action, data.draw(values))
    try:
        case = parse_case(description, source=SOURCE)
    except DescriptionError as err:
        assert err.messages
        for message in err.messages:
            assert message.startswith(f"{SOURCE}: ") and "\n" not in message
    else:
        assert isinstance(case, Case)
        assert case.frequencies and all(f > 0 and math.isfinite(f) for f in case.frequencies)


@settings(max_examples=150, deadline=None)
@given(
    st.integers(0, len(BASE) - 1),
    st.integers(0, 6),
    st.text(alphabet='[]{}=".,0123456789-+ex\n PGlrfa', max_size=6),
)
def test_fuzz_mutated_text(start: int, length: int, insert: str) -> None:
    text = BASE[:start] + insert + BASE[start + length:]
    try:
        load_case_text(text, source=SOURCE)
    except DescriptionError as err:
        for message in err.messages:
            assert message.startswith(f"{SOURCE}: ") and "\n" not in message
