"""Read assembly descriptions (TOML) into validated :class:`~assembly.case.Case` objects.

Every problem of a description is reported at once, as one
:class:`~assembly.errors.DescriptionError` whose lines read (on one line)::

    cases/x.toml: joints.G2.between[1]: plate 'P9' is not in the assembly
    (plates: P1, P2); fix the edge reference

i.e. source, dotted field path (``[i]`` for list indices), what is wrong and how to fix it.
Schema problems (types, ranges, unknown keys) come from pydantic and are translated here;
cross-reference problems (unknown plates, edges joined twice, ...) come from the checks of
:mod:`assembly.models`.  When a description has schema problems, the cross-reference checks
still run on the parts that are valid, so one run shows (nearly) everything.
"""

from __future__ import annotations

import ast
import math
import os
import re
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, TypeAdapter, ValidationError

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser, as the tomli package
    import tomli as tomllib  # type: ignore[no-redef]

from .case import Case
from .checks import View, cross_check
from .errors import CrossReferenceError, DescriptionError, Issue, did_you_mean, format_path
from .joints import CoplanarJoint, HingeJoint, Joint, JunctionJoint
from .models import Boundary, EdgeMoment, EdgeShear, Load, Material, Plate, PlateFrame, PointForce
from .settings import (
    Compute,
    Discretisation,
    JointTruth,
    Measurement,
    PlateDiscretisation,
    PointMeasurement,
    Truth,
    Updating,
)
from .types import Positive, show_value

__all__ = ["load_case", "load_case_text", "parse_case"]

Loc = tuple[Any, ...]

_JOINT_KINDS: dict[str, type[BaseModel]] = {
    "coplanar": CoplanarJoint, "hinge": HingeJoint, "junction": JunctionJoint}
_LOAD_KINDS: dict[str, type[BaseModel]] = {
    "edge_shear": EdgeShear,
    "edge_moment": EdgeMoment,
    "point_force": PointForce,
}
_UNION_TAGS = {"joints": _JOINT_KINDS, "loads": _LOAD_KINDS}

# Location patterns ("*" an id, "[]" a list index) -> model of the table found there.
_MODELS: dict[str, type[BaseModel]] = {
    "": Case,
    "materials.*": Material,
    "plates.*": Plate,
    "boundaries[]": Boundary,
    "discretisation": Discretisation,
    "discretisation.plates.*": PlateDiscretisation,
    "measurement": Measurement,
    "measurement.points[]": PointMeasurement,
    "updating": Updating,
    "compute": Compute,
    "truth": Truth,
    "truth.joints.*": JointTruth,
}

# Location pattern -> an example of a correct entry (used in the "how to fix" part).
_EXAMPLES: dict[str, str] = {
    "name": 'name = "two-plates"',
    "frequency": "frequency = 155.0 (Hz)",
    "frequencies": "frequencies = [150.0, 155.0] (Hz)",
    "frequencies[]": "frequencies = [150.0, 155.0] (Hz)",
    "materials": "[materials.steel] tables",
    "materials.*": "a [materials.ID] table",
    "materials.*.young_modulus": "young_modulus = 210e9 (Pa)",
    "materials.*.poisson_ratio": "poisson_ratio = 0.3 (in (-1, 0.5))",
    "materials.*.density": "density = 7800.0 (kg/m^3)",
    "materials.*.loss_factor": "loss_factor = 0.01 (eta > 0)",
    "plates": "[plates.P1] tables",
    "plates.*": "a [plates.ID] table",
    "plates.*.material": 'material = "steel" (a [materials.ID] id)',
    "plates.*.thickness": "thickness = 0.001 (m)",
    "plates.*.size": "size = [0.5, 0.4] ([Lx, Ly] in m)",
    "plates.*.size[]": "size = [0.5, 0.4] ([Lx, Ly] in m)",
    "plates.*.origin": "origin = [0.0, 0.0] (m)",
    "plates.*.origin[]": "origin = [0.0, 0.0] (m)",
    "plates.*.rotation": "rotation = 0.0 (degrees)",
    "plates.*.frame": "frame = { origin = [0, 0, 0], x_axis = [1, 0, 0], y_axis = [0, 1, 0] }",
    "plates.*.frame.origin": "origin = [0.0, 0.0, 0.0] (m)",
    "plates.*.frame.x_axis": "x_axis = [1.0, 0.0, 0.0] (a unit vector)",
    "plates.*.frame.y_axis": "y_axis = [0.0, 1.0, 0.0] (a unit vector, normal to x_axis)",
    "joints": "[joints.G1] tables",
    "joints.*": "a [joints.ID] table",
    "joints.*.kind": 'kind = "coplanar", "hinge" or "junction"',
    "joints.*.between": 'between = ["P1.right", "P2.left"]',
    "joints.*.between[]": 'between = ["P1.right", "P2.left"]',
    "joints.*.log10_stiffness": "log10_stiffness = 2.0 (log10 of k in N·m/m per rad)",
    "joints.*.loss_factor": "loss_factor = 0.0 (zeta >= 0)",
    "joints.*.mass": "mass = 0.0 (kg/m)",
    "boundaries": '[[boundaries]] tables with edge = "P1.left" and condition = "clamped"',
    "boundaries[]": "a [[boundaries]] table",
    "boundaries[].edge": 'edge = "P1.left"',
    "boundaries[].condition": 'condition = "clamped", "simply_supported", "free" or "symmetric"',
    "loads": '[[loads]] tables, e.g. kind = "point_force"',
    "loads[]": "a [[loads]] table",
    "loads[].kind": 'kind = "edge_shear", "edge_moment" or "point_force"',
    "loads[].edge": 'edge = "P1.left"',
    "loads[].amplitude": "amplitude = 1.0 or amplitude = [1.0, 0.5] ([re, im])",
    "loads[].distribution": 'distribution = "uniform" or "half_sine"',
    "loads[].plate": 'plate = "P1"',
    "loads[].at": "at = [0.12, 0.31] (plate-local m)",
    "loads[].at[]": "at = [0.12, 0.31] (plate-local m)",
    "discretisation": "a [discretisation] table",
    "discretisation.resolution": "resolution = 1.0 (> 0)",
    "discretisation.quadrature_per_sector": "quadrature_per_sector = 8 (>= 2)",
    "discretisation.edge_wavenumber_ratio": "edge_wavenumber_ratio = 2.5 (> 1)",
    "discretisation.interface_functions": "interface_functions = 16 (>= 1)",
    "discretisation.tolerance": "tolerance = 1e-3 (0 < tolerance < 1)",
    "discretisation.plates": "[discretisation.plates.P1] tables",
    "discretisation.plates.*.interior": "interior = 48 (>= 4)",
    "discretisation.plates.*.edge_propagating": "edge_propagating = 10 (>= 0)",
    "discretisation.plates.*.edge_evanescent": "edge_evanescent = 24 (>= 0)",
    "discretisation.plates.*.corner": "corner = 1 (>= 0)",
    "discretisation.plates.*.edge_wavenumber_ratio": "edge_wavenumber_ratio = 10.0 (> 1)",
    "measurement": "a [measurement] table",
    "measurement.spacing": "spacing = 0.1 (m; default a fifth of the largest plate side)",
    "measurement.plates": 'plates = ["P1", "P2"]',
    "measurement.plates[]": 'plates = ["P1", "P2"]',
    "measurement.noise": "noise = 0.1 (fraction >= 0)",
    "measurement.seed": "seed = 1 (>= 0)",
    "measurement.resolution": "resolution = 1.6 (> 0)",
    "measurement.points": 'points = [{plate = "P1", at = [0.1, 0.2]}]',
    "measurement.points[].plate": 'plate = "P1"',
    "measurement.points[].at": "at = [0.1, 0.2] (plate-local m)",
    "measurement.points[].at[]": "at = [0.1, 0.2] (plate-local m)",
    "updating": "an [updating] table",
    "updating.r": "r = \"auto\" or r = 0.8 (in (0, 1])",
    "updating.alpha": "alpha = {G1 = 1.0, G2 = 0.5}",
    "updating.alpha.*": "G1 = 1.0 (weight >= 0)",
    "updating.bounds": "bounds = [-3.0, 7.0] (log10 k)",
    "updating.bounds[]": "bounds = [-3.0, 7.0] (log10 k)",
    "updating.identify": 'identify = ["stiffness", "damping", "mass"]',
    "compute": "a [compute] table",
    "compute.workers": "workers = 2 (local processes, >= 1)",
    "compute.scheduler": 'scheduler = "tcp://node1:8786" (a Dask scheduler)',
    "updating.identify[]": 'identify = ["stiffness", "damping", "mass"]',
    "updating.max_steps": "max_steps = 8 (>= 1)",
    "updating.stop_ratio": "stop_ratio = 3.0 (> 1)",
    "updating.min_decrease": "min_decrease = 0.01 (in [0, 1))",
    "updating.confidence": "confidence = 0.9 (a level in (0, 1))",
    "updating.significance": "significance = 0.05 (in (0, 0.5))",
    "truth": "a [truth.joints.ID] table",
    "truth.joints": "[truth.joints.G1] tables",
    "truth.joints.*": "a [truth.joints.ID] table",
    "truth.joints.*.log10_stiffness": "log10_stiffness = 1.5",
    "truth.joints.*.loss_factor": "loss_factor = 0.1 (zeta >= 0)",
    "truth.joints.*.mass": "mass = 0.0 (kg/m)",
}

# Positions of ids in a location: top-level tables, then nested ones.
_ID_TABLES_1 = {"materials", "plates", "joints"}
_ID_TABLES_2 = {("discretisation", "plates"), ("truth", "joints"), ("updating", "alpha")}


# --------------------------------------------------------------------------------------
# Public functions
# --------------------------------------------------------------------------------------
def load_case(path: str | os.PathLike[str]) -> Case:
    """Read an assembly description from a TOML file.

    Parameters
    ----------
    path : str or path-like
        The ``.toml`` file, e.g. ``cases/single_plate.toml``.  Messages name it as given.

    Returns
    -------
    Case
        The validated assembly.

    Raises
    ------
    DescriptionError
        If the file is missing or unreadable, is not UTF-8, is not valid TOML (the message
        gives the line), or does not describe a valid assembly.  Every problem is reported,
        one line each: ``file: field.path: what is wrong; how to fix it``.

    Examples
    --------
    >>> case = load_case("cases/single_plate.toml")
    >>> sorted(case.plates)
    ['P1']
    """
    source = os.fspath(path)
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise DescriptionError(
            [Issue(source, "", "file not found; check the path of the TOML description")]
        ) from None
    except IsADirectoryError:
        raise DescriptionError(
            [Issue(source, "", "is a directory; give the path of a .toml description")]
        ) from None
    except OSError as exc:
        raise DescriptionError(
            [Issue(source, "", f"cannot be read ({exc.strerror}); check the path and permissions")]
        ) from None
    try:
        text = raw.decode("utf-8-sig")  # a byte-order mark, as some editors write, is not TOML
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise DescriptionError(
            [Issue(source, f"line {line}", "is not valid UTF-8 text; save the file as UTF-8")]
        ) from None
    return load_case_text(text, source=source)


def load_case_text(text: str, source: str = "<string>") -> Case:
    r"""Read an assembly description from TOML text.

    Parameters
    ----------
    text : str
        TOML text.
    source : str, optional
        Name used in messages (e.g. the file name).  Default ``"<string>"``.

    Returns
    -------
    Case

    Raises
    ------
    DescriptionError
        As :func:`load_case`.

    Examples
    --------
    >>> try:
    ...     load_case_text('name = "x"\nfrequency = 1,5\n', source="x.toml")
    ... except DescriptionError as err:
    ...     print(err)  # doctest: +ELLIPSIS
    x.toml: line 2, column 14: TOML syntax error: expected newline or end of document ...
    """
    try:
        data = tomllib.loads(text)
        return parse_case(data, source=source)
    except tomllib.TOMLDecodeError as exc:
        raise DescriptionError([_toml_issue(exc, text, source)]) from None
    except RecursionError:  # arrays or inline tables nested thousands deep
        raise DescriptionError([Issue(
            source, "", "nests arrays or tables too deeply to be read; a description needs a "
                        "few levels at most (e.g. size = [0.5, 0.4])")]) from None


def parse_case(data: Mapping[str, Any], source: str = "<dict>") -> Case:
    """Validate an assembly description given as a dict (the parsed TOML).

    Parameters
    ----------
    data : mapping
        The description, as ``tomllib`` returns it.
    source : str, optional
        Name used in messages.  Default ``"<dict>"``.

    Returns
    -------
    Case

    Raises
    ------
    DescriptionError
        With every problem of the description.

    Notes
    -----
    Cross-reference checks need valid parts: when the schema check fails they run on the
    valid tables only, so a problem hidden behind an invalid table (say, a joint edge on a
    plate whose size is malformed) shows once that table is fixed.
    """
    if not isinstance(data, Mapping):
        raise DescriptionError(
            [
                Issue(
                    source,
                    "",
                    f"the description must be a table of sections, got {_describe_value(data)}; "
                    "give name, frequency, [materials.ID] and [plates.ID]",
                )
            ]
        )
    data = dict(data)
    try:
        return Case.model_validate(data)
    except ValidationError as exc:
        located = _located_issues(exc, data)
    raise DescriptionError(Issue(source, format_path(loc), msg) for loc, msg in located)


# --------------------------------------------------------------------------------------
# TOML syntax errors
# --------------------------------------------------------------------------------------
_TOML_POSITION = re.compile(
    r"^(?P<msg>.*?)\s*\(at (?:line (?P<line>\d+), column (?P<col>\d+)|end of document)\)$"
)


def _toml_issue(exc: tomllib.TOMLDecodeError, text: str, source: str) -> Issue:
    match = _TOML_POSITION.match(str(exc))
    msg = match.group("msg") if match else str(exc)
    if match and match.group("line"):
        line, col = int(match.group("line")), int(match.group("col"))
        where = f"line {line}, column {col}"
    else:
        line = max(1, len(text.splitlines()))
        where = f"line {line} (end of file)"
    declared = re.match(r"Cannot declare (\(.*\)) twice", msg)
    if declared:
        try:
            key = ".".join(str(k) for k in ast.literal_eval(declared.group(1)))
        except (ValueError, SyntaxError):
            key = declared.group(1)
        what = (
            f"table [{key}] is declared twice; ids must be unique, so rename one of the tables "
            "or merge them"
        )
    elif msg.startswith("Cannot overwrite a value"):
        lines = text.splitlines()
        current = lines[line - 1] if 0 < line <= len(lines) else ""
        key_match = re.match(r"\s*([^=\s\[]+)\s*=", current)
        key = f"{key_match.group(1)!r} " if key_match else ""
        what = (
            f"key {key}is given twice in the same table (a duplicate key, or an id defined "
            "twice); remove or rename the duplicate"
        )
    elif msg.startswith("Invalid value"):
        what = (
            "TOML syntax error: invalid value; quote strings (material = \"steel\"), write "
            "numbers as 0.5 or 2e-3, lists as [a, b] and booleans as true/false"
        )
    else:
        what = (
            f"TOML syntax error: {msg[:1].lower()}{msg[1:]}; fix the syntax (one key = value per "
            "line, strings in quotes, lists as [a, b], tables as [plates.P1])"
        )
    return Issue(source, where, what)


# --------------------------------------------------------------------------------------
# Translation of pydantic errors
# --------------------------------------------------------------------------------------
def _located_issues(exc: ValidationError, data: dict[str, Any]) -> list[tuple[Loc, str]]:
    """Turn a ValidationError of Case into ``(loc, message)`` pairs, every problem once."""
    issues: list[tuple[Loc, str]] = []
    schema_failed = False
    for err in exc.errors(include_url=False):
        ctx_error = (err.get("ctx") or {}).get("error")
        if isinstance(ctx_error, CrossReferenceError):
            issues.extend((tuple(err["loc"]) + loc, msg) for loc, msg in ctx_error.issues)
            continue
        schema_failed = True
        issues.append(_translate(err))
    if schema_failed:
        issues.extend(cross_check(_partial_view(data)))
    order = {name: i for i, name in enumerate(Case.model_fields)}
    unique = list(dict.fromkeys(issues))
    unique.sort(key=lambda item: order.get(item[0][0], len(order)) if item[0] else -1)
    return unique


def _strip_tag(loc: Loc) -> tuple[Loc, str | None]:
    """Remove the discriminator tag pydantic inserts in locations inside unions."""
    if len(loc) >= 3 and loc[0] in _UNION_TAGS and loc[2] in _UNION_TAGS[loc[0]]:
        return loc[:2] + loc[3:], loc[2]
    return loc, None


def _pattern(loc: Loc) -> str:
    """Return a location pattern: ids replaced by ``*``, list indices by ``[]``."""
    out = ""
    for i, item in enumerate(loc):
        if isinstance(item, int):
            out += "[]"
            continue
        is_id = (i == 1 and loc[0] in _ID_TABLES_1) or (i == 2 and tuple(loc[:2]) in _ID_TABLES_2)
        segment = "*" if is_id else str(item)
        out += f".{segment}" if out else segment
    return out


def _model_at(loc: Loc, tag: str | None) -> type[BaseModel] | None:
    pattern = _pattern(loc)
    if pattern in ("joints.*", "loads[]"):
        return _UNION_TAGS[loc[0]].get(tag or "")
    return _MODELS.get(pattern)


def _toml_type(value: object) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, (list, tuple)):
        return "an array"
    if isinstance(value, Mapping):
        return "a table"
    return f"a {type(value).__name__}"


def _describe_value(value: object) -> str:
    return f"{show_value(value)} ({_toml_type(value)})"


def _translate(err: Any) -> tuple[Loc, str]:  # noqa: C901 (one branch per error type)
    """Translate one pydantic error into ``(loc, "what is wrong; how to fix it")``."""
    loc, tag = _strip_tag(tuple(err["loc"]))
    kind = err["type"]
    ctx = err.get("ctx") or {}
    value = err.get("input")
    example = _EXAMPLES.get(_pattern(loc))
    eg = f"e.g. {example}" if example else "see the description format"

    if loc and loc[-1] == "[key]":
        loc = loc[:-1]
        error = ctx.get("error")
        text = str(error) if error is not None else err["msg"]
        return loc, text if ";" in text else f"{text}; rename it"
    if kind == "missing":
        if loc and isinstance(loc[-1], int):
            parent = _EXAMPLES.get(_pattern(loc[:-1]))
            return loc[:-1], "has too few items; " + (f"write {parent}" if parent else "add items")
        name = loc[-1] if loc else "value"
        return loc, f"required key `{name}` is missing; add it, " + eg
    if kind == "extra_forbidden":
        key = str(loc[-1]) if loc else "?"
        model = _model_at(loc[:-1], tag)
        allowed = list(model.model_fields) if model is not None else []
        listing = f" (allowed: {', '.join(allowed)})" if allowed else ""
        return loc, (
            f"unknown key `{key}`{did_you_mean(key, allowed)}; remove it or fix its "
            f"spelling{listing}"
        )
    if kind in ("union_tag_invalid", "union_tag_not_found"):
        kinds = list(_UNION_TAGS.get(loc[0], {})) if loc else []
        choices = " or ".join(f'"{k}"' for k in kinds)
        if kind == "union_tag_not_found" and not isinstance(value, Mapping):
            return loc, f"must be a table, got {_describe_value(value)}; write " + (
                example or "a table"
            )
        if kind == "union_tag_not_found":
            return (*loc, "kind"), f"`kind` is missing; add kind = {choices}"
        found = str(ctx.get("tag", ""))
        return (*loc, "kind"), (
            f"unknown kind {found!r}{did_you_mean(found, kinds)}; use kind = {choices}"
        )
    if kind in ("value_error", "assertion_error"):
        error = ctx.get("error")
        text = str(error) if error is not None else err["msg"]
        return loc, text
    if kind == "literal_error":
        expected = str(ctx.get("expected", ""))
        options = re.findall(r"'([^']*)'", expected)
        hint = did_you_mean(value, options) if isinstance(value, str) else ""
        return loc, f"must be {expected}, got {_describe_value(value)}{hint}; use one of them"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        symbol = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<",
                  "less_than_equal": "<="}[kind]
        bound = next(iter(ctx.values()), "?")
        return loc, f"must be {symbol} {bound}, got {show_value(value)}; {eg}"
    if kind == "finite_number":
        return loc, f"must be a finite number, got {show_value(value)}; {eg}"
    if kind in ("float_type", "float_parsing"):
        return loc, f"must be a number, got {_describe_value(value)}; write a number, {eg}"
    if kind in ("int_type", "int_parsing", "int_from_float"):
        return loc, f"must be a whole number, got {_describe_value(value)}; {eg}"
    if kind in ("bool_type", "bool_parsing"):
        name = loc[-1] if loc else "value"
        return loc, (f"must be true or false, got {_describe_value(value)}; write {name} = true "
                     f"or {name} = false (unquoted)")
    if kind in ("string_type", "string_too_short"):
        return loc, f"must be a non-empty string, got {_describe_value(value)}; quote it, {eg}"
    if kind in ("model_type", "model_attributes_type", "dict_type"):
        return loc, f"must be a table, got {_describe_value(value)}; write " + (
            example or "a table"
        )
    if kind in ("list_type", "tuple_type"):
        return loc, f"must be an array, got {_describe_value(value)}; {eg}"
    if kind in ("too_short", "too_long"):
        actual = ctx.get("actual_length")
        if _pattern(loc) == "plates":
            return loc, "no plates defined; add at least one [plates.ID] table, e.g. [plates.P1]"
        size = ctx.get("max_length") if kind == "too_long" else ctx.get("min_length")
        relation = "at most" if kind == "too_long" else "at least"
        return loc, f"has {actual} item(s), needs {relation} {size}; {eg}"
    return loc, f"{err['msg'][:1].lower()}{err['msg'][1:]}, got {_describe_value(value)}; {eg}"


# --------------------------------------------------------------------------------------
# Partial validation, for cross-reference checks despite schema errors
# --------------------------------------------------------------------------------------
def _try(adapter: TypeAdapter[Any] | type[BaseModel], value: object) -> Any:
    try:
        if isinstance(adapter, TypeAdapter):
            return adapter.validate_python(value)
        return adapter.model_validate(value)
    except ValidationError:
        return None


_JOINT_ADAPTER: TypeAdapter[Any] = TypeAdapter(Joint)
_LOAD_ADAPTER: TypeAdapter[Any] = TypeAdapter(Load)


_SIZE_ADAPTER: TypeAdapter[Any] = TypeAdapter(
    tuple[Positive, Positive], config=ConfigDict(allow_inf_nan=False)
)


def _plate_geometry(raw: object) -> Plate | None:
    """Validate a plate; if it is invalid but its size is not, return a geometry stand-in.

    The stand-in lets the geometric checks (joint edge lengths, point forces inside) run
    even when, say, the thickness is wrong.  Its ``material`` is None unless given as a
    string, and its other fields are placeholders that the checks do not read.
    """
    plate = _try(Plate, raw)
    if plate is not None or not isinstance(raw, Mapping):
        return plate
    size = _try(_SIZE_ADAPTER, raw.get("size"))
    if size is None:
        return None
    frame = None
    if "frame" in raw:  # an invalid frame is reported on its own; no geometry without it
        frame = _try(PlateFrame, raw["frame"])
        if frame is None:
            return None
    material = raw.get("material")
    return Plate.model_construct(
        material=material if isinstance(material, str) else None, thickness=math.nan, size=size,
        frame=frame,
    )


def _partial_view(data: Mapping[str, Any]) -> View:
    """Validate each table and item on its own; None marks what is absent or invalid."""

    def table(name: str, check: Callable[[object], Any], required: bool) -> Any:
        if name not in data:
            return None if required else {}
        raw = data[name]
        if not isinstance(raw, Mapping):
            return None
        return {k: check(v) for k, v in raw.items() if isinstance(k, str)}

    def array(name: str, model: TypeAdapter[Any] | type[BaseModel]) -> Any:
        raw = data.get(name, [])
        if not isinstance(raw, (list, tuple)):
            return None
        return [_try(model, v) for v in raw]

    def section(name: str, model: type[BaseModel]) -> Any:
        return model() if name not in data else _try(model, data[name])

    return View(
        materials=table("materials", lambda v: _try(Material, v), required=True),
        plates=table("plates", _plate_geometry, required=True),
        joints=table("joints", lambda v: _try(_JOINT_ADAPTER, v), required=False),
        boundaries=array("boundaries", Boundary),
        loads=array("loads", _LOAD_ADAPTER),
        discretisation=section("discretisation", Discretisation),
        measurement=section("measurement", Measurement),
        updating=section("updating", Updating),
        truth=section("truth", Truth),
        has_frequency="frequency" in data,
        has_frequencies="frequencies" in data,
    )
