r"""JSON Schema of an assembly description, for editor completion and checking.

``vtcr schema --out vtcr.schema.json`` writes it; TOML editors that read JSON Schema (taplo,
and VS Code's *Even Better TOML* built on it) then complete keys, show the documentation of
each field and flag wrong types when a description starts with the directive::

    #:schema ./vtcr.schema.json

The schema is pydantic's :meth:`~pydantic.BaseModel.model_json_schema` of :class:`Case`,
completed from the models' numpydoc docstrings (one source for the documentation): each
model's summary line and each field's description come from its docstring, enumerations
(``kind``, ``condition``, ``distribution``, ``identify``) are listed, ids and edge
references get their patterns, ``kind`` is required in joints and loads as the loader requires
it, and "give either ``frequency`` or ``frequencies``" is stated with ``oneOf``. What a schema
cannot say -- cross-references such as a joint naming an existing plate, physical sanity --
stays with ``vtcr check``.
"""

from __future__ import annotations

import copy
import math
import re
from typing import Any

from . import joints, models, settings
from .case import Case
from .types import EDGE_NAMES

__all__ = ["case_json_schema", "SCHEMA_DIALECT"]

SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"
"""The JSON Schema dialect of :func:`case_json_schema` (pydantic's)."""

_ID_PATTERN = r"^[A-Za-z0-9_-]+$"
_EDGE_PATTERN = r"^[A-Za-z0-9_-]+\.(" + "|".join(EDGE_NAMES) + r")$"
_PARAM = re.compile(r"^(\w+) : (.+)$")


_TEX = {r"\log_{10}": "log10", r"\zeta": "ζ", r"\eta": "η", r"\mu": "μ", r"\nu": "ν",
        r"\rho": "ρ", r"\tau_{max}": "τ_max", r"\tau": "τ", r"\kappa": "κ",
        r"\theta": "θ", r"\omega": "ω", r"\partial": "∂", r"\ge": ">=", r"\le": "<="}


def _clean(text: str) -> str:
    """Docstring text as plain one-line prose (rst roles, literals and TeX removed)."""
    text = re.sub(r":(?:math|class|func|meth|data|attr):`~?([^`]*)`", r"\1", text)
    text = text.replace("``", "")
    for tex, plain in _TEX.items():
        text = text.replace(tex, plain)
    return " ".join(text.split())


def _docstring_parts(cls: type) -> tuple[str, dict[str, str]]:
    """``(summary, {parameter: description})`` of a numpydoc class docstring."""
    doc = (cls.__doc__ or "").strip("\n")
    lines = [line.rstrip() for line in doc.splitlines()]
    indent = min((len(x) - len(x.lstrip()) for x in lines[1:] if x.strip()), default=0)
    lines = [lines[0].strip()] + [x[indent:] for x in lines[1:]]
    summary = []
    for line in lines:
        if not line.strip():
            break
        summary.append(line)
    params: dict[str, str] = {}
    try:
        start = lines.index("Parameters") + 2
    except ValueError:
        return _clean(" ".join(summary)), params
    name, kind, body = None, "", []

    def flush() -> None:
        if name is not None:
            text = _clean(" ".join(body))
            params[name] = f"{text} [{kind}]" if text else f"[{kind}]"

    for line in lines[start:]:
        if line and not line.startswith(" "):
            match = _PARAM.match(line)
            if match is None:  # the next section
                break
            flush()
            name, kind, body = match.group(1), _clean(match.group(2)), []
        elif line.strip():
            body.append(line.strip())
    flush()
    return _clean(" ".join(summary)), params


def _strip_null(prop: dict[str, Any]) -> dict[str, Any]:
    """``anyOf: [X, null]`` (optional fields) -> ``X``: TOML has no null."""
    options = prop.get("anyOf")
    if isinstance(options, list) and len(options) == 2 and {"type": "null"} in options:
        kept = next(o for o in options if o != {"type": "null"})
        rest = {k: v for k, v in prop.items() if k not in ("anyOf", "default")}
        return {**kept, **rest}
    return prop


def _document(schema: dict[str, Any], cls: type) -> None:
    summary, params = _docstring_parts(cls)
    if summary:
        schema["description"] = summary
    for name, prop in list(schema.get("properties", {}).items()):
        prop = _strip_null(prop)
        if name in params:
            prop["description"] = params[name]
        schema["properties"][name] = prop


def case_json_schema() -> dict[str, Any]:
    """Return the JSON Schema (draft 2020-12) of an assembly description.

    Returns
    -------
    dict
        A JSON-serialisable schema whose top-level properties are the description's tables
        (``name``, ``frequency``, ``materials``, ``plates``, ``joints``, ...), with a
        description for every model and field.

    Examples
    --------
    >>> schema = case_json_schema()
    >>> sorted(schema["properties"])[:3]
    ['boundaries', 'discretisation', 'frequencies']
    >>> schema["$defs"]["Boundary"]["properties"]["condition"]["enum"]
    ['clamped', 'simply_supported', 'free', 'symmetric']
    """
    schema = copy.deepcopy(Case.model_json_schema())
    defs = schema.setdefault("$defs", {})
    for name, sub in defs.items():
        cls = next((getattr(module, name) for module in (models, joints, settings)
                    if hasattr(module, name)), None)
        if isinstance(cls, type):
            _document(sub, cls)
        if "kind" in sub.get("properties", {}):
            sub["required"] = ["kind", *[r for r in sub.get("required", []) if r != "kind"]]
    _document(schema, Case)
    props = schema["properties"]

    # ids and edge references
    for table in ("materials", "plates", "joints"):
        props[table]["propertyNames"] = {"pattern": _ID_PATTERN}
    for owner, field in (("Discretisation", "plates"), ("Truth", "joints"), ("Updating", "alpha")):
        defs[owner]["properties"][field]["propertyNames"] = {"pattern": _ID_PATTERN}
    edge = {"type": "string", "pattern": _EDGE_PATTERN}
    for owner in ("CoplanarJoint", "HingeJoint"):
        between = defs[owner]["properties"]["between"]
        between["prefixItems"] = [dict(edge), dict(edge)]
    for owner in ("Boundary", "EdgeShear", "EdgeMoment"):
        defs[owner]["properties"]["edge"].update(edge)

    # what the validators add to the field types
    defs["Material"]["properties"]["loss_factor"]["exclusiveMinimum"] = 0
    frequencies = props["frequencies"]
    frequencies.update(minItems=1, uniqueItems=True)
    schema["oneOf"] = [
        {"required": ["frequency"], "not": {"required": ["frequencies"]}},
        {"required": ["frequencies"], "not": {"required": ["frequency"]}},
    ]
    _drop_non_finite_defaults(schema)
    result = {"$schema": SCHEMA_DIALECT, "title": "vtcr assembly description"}
    result.update({k: v for k, v in schema.items() if k != "title"})
    return result


def _drop_non_finite_defaults(node: Any) -> None:
    """Move every non-finite ``default`` (TOML's ``inf``, a rigid spring) into its field's
    description: JSON has no infinity, and editors read the schema as strict JSON."""
    if isinstance(node, dict):
        default = node.get("default")
        if isinstance(default, float) and not math.isfinite(default):
            del node["default"]
            node["description"] = f"{node.get('description', '')} Default: {default!r}.".lstrip()
        for value in node.values():
            _drop_non_finite_defaults(value)
    elif isinstance(node, list):
        for value in node:
            _drop_non_finite_defaults(value)
