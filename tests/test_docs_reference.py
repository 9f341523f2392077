"""The reference documents of docs/ against the code they describe.

``docs/description.md``: each model reachable from :class:`assembly.case.Case` has a section
whose heading names the model in backticks; the section's table has a row per field of the
model, its first cell the field name in backticks.

``docs/cli.md``: one table ``command | option | argument | default | meaning`` with a row per
(command, option) pair of the real parser (:func:`updating.cli.build_parser`); options before
the command belong to the command ``vtcr``, the positional description is ``CASE``.
"""

from __future__ import annotations

import argparse
import re
import typing

from pydantic import BaseModel
from support import ROOT

from assembly import load_case_text
from assembly.case import Case
from updating.cli import build_parser

DOCS = ROOT / "docs"
BACKTICKED = re.compile(r"`([^`]+)`")
CELL_SPLIT = re.compile(r"(?<!\\)\|")
CLI_HEADER = ["command", "option", "argument", "default", "meaning"]


# --------------------------------------------------------------------------------------
# Markdown helpers
# --------------------------------------------------------------------------------------
def _lines_outside_code(text):
    """``(line, in_code)`` for every line; fenced code blocks hold TOML comments like ``# m``,
    which are not headings."""
    fenced = False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            yield line, True
            continue
        yield line, fenced


def _cells(line):
    """The cells of a Markdown table row (``\\|`` is a pipe inside a cell)."""
    return [cell.strip() for cell in CELL_SPLIT.split(line.strip().strip("|"))]


def _only_backticked(cell):
    """The text of a cell that is exactly one backticked span, else None."""
    match = re.fullmatch(r"`([^`]+)`", cell.strip())
    return match.group(1) if match else None


# --------------------------------------------------------------------------------------
# docs/description.md
# --------------------------------------------------------------------------------------
def _models_in(annotation):
    """The pydantic models anywhere in a type: unions (discriminated or optional), containers
    (dict values, tuples, lists) and ``Annotated`` types."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    found = []
    for argument in typing.get_args(annotation):
        found += _models_in(argument)
    return found


def reachable_models(root=Case):
    """Every model reachable from ``root`` through its fields, ``root`` first."""
    seen, queue = [], [root]
    while queue:
        model = queue.pop(0)
        if model in seen:
            continue
        seen.append(model)
        for info in model.model_fields.values():
            queue += _models_in(info.annotation)
    return seen


def _field_names(model):
    return [info.alias or name for name, info in model.model_fields.items()]


def description_sections(text, model_names):
    """``({model: [field rows]}, [models with more than one section])``.

    A heading starts a model's section when one of its backticked spans is a model name; any
    other heading ends it. A row belongs to the section when its first cell is exactly one
    backticked name.
    """
    rows, repeated, current = {}, [], None
    for line, in_code in _lines_outside_code(text):
        if in_code:
            continue
        if line.startswith("#"):
            named = [name for name in BACKTICKED.findall(line) if name in model_names]
            current = named[0] if named else None
            if current is not None:
                if current in rows:
                    repeated.append(current)
                rows.setdefault(current, [])
            continue
        if current is not None and line.lstrip().startswith("|"):
            name = _only_backticked(_cells(line)[0])
            if name is not None:
                rows[current].append(name)
    return rows, repeated


def _description():
    return (DOCS / "description.md").read_text(encoding="utf-8")


def test_the_walk_reaches_every_table():
    """The walk follows nested models, discriminated unions and containers (a guard on the
    walk itself: a walk that stopped early would let the next test pass vacuously)."""
    names = {model.__name__ for model in reachable_models()}
    expected = {"Case", "Material", "Plate", "PlateFrame", "CoplanarJoint", "HingeJoint",
                "JunctionJoint", "Boundary", "EdgeShear", "EdgeMoment", "PointForce",
                "Discretisation", "PlateDiscretisation", "Measurement", "PointMeasurement",
                "Updating", "Compute", "Truth", "JointTruth"}
    assert expected <= names, f"the walk missed {sorted(expected - names)}"


def test_description_reference_names_every_field():
    models = reachable_models()
    rows, repeated = description_sections(_description(), {m.__name__ for m in models})
    problems = [f"model {name} has {repeated.count(name) + 1} sections; give it one"
                for name in dict.fromkeys(repeated)]
    for model in models:
        if model.__name__ not in rows:
            problems.append(f"model {model.__name__} has no section (a heading naming "
                            f"`{model.__name__}`); its fields: {', '.join(_field_names(model))}")
            continue
        problems += [f"{model.__name__}.{name}: no row `{name}` in the section of "
                     f"`{model.__name__}`" for name in _field_names(model)
                     if name not in rows[model.__name__]]
    assert not problems, "docs/description.md lacks:\n" + "\n".join(problems)


def test_description_reference_names_no_stale_field():
    models = {m.__name__: m for m in reachable_models()}
    rows, _ = description_sections(_description(), set(models))
    problems = [f"{name}.{row}: documented, but {name} has no field {row!r}"
                for name, names in rows.items() for row in names
                if row not in _field_names(models[name])]
    problems += [f"{name}.{row}: {names.count(row)} rows; give it one"
                 for name, names in rows.items() for row in dict.fromkeys(names)
                 if names.count(row) > 1]
    assert not problems, "docs/description.md:\n" + "\n".join(problems)


def test_description_examples_are_valid_descriptions():
    blocks, block, fenced = [], [], False
    for line in _description().splitlines():
        if line.startswith("```"):
            if fenced and block and block[0].startswith("name ="):
                blocks.append("\n".join(block) + "\n")
            fenced, block = line.strip() == "```toml", []
        elif fenced:
            block.append(line)
    assert blocks, "docs/description.md has no complete TOML example (```toml, name = ...)"
    for text in blocks:
        load_case_text(text)  # raises DescriptionError naming every problem


# --------------------------------------------------------------------------------------
# docs/cli.md
# --------------------------------------------------------------------------------------
def _option_name(action):
    """The name of an action in the table: its longest option string, or the positional's
    metavar / dest in capitals (``CASE``)."""
    if action.option_strings:
        return max(action.option_strings, key=len)
    return str(action.metavar or action.dest).upper()


def parser_options():
    """``{(command, option): action}`` of the real parser, help actions left out."""
    parser = build_parser()
    found = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for command, sub in action.choices.items():
                for inner in sub._actions:
                    if not isinstance(inner, argparse._HelpAction):
                        found[command, _option_name(inner)] = inner
        elif not isinstance(action, argparse._HelpAction):
            found["vtcr", _option_name(action)] = action
    return found


def _cli():
    return (DOCS / "cli.md").read_text(encoding="utf-8")


def cli_table(text):
    """The rows of cli.md's option table as ``{(command, option): [cells]}``, and problems."""
    lines = [line for line, in_code in _lines_outside_code(text) if not in_code]
    starts = [i for i, line in enumerate(lines) if line.lstrip().startswith("|")
              and [c.lower() for c in _cells(line)] == CLI_HEADER]
    if len(starts) != 1:
        return {}, [f"{len(starts)} tables headed | {' | '.join(CLI_HEADER)} |; need one"]
    rows, problems = {}, []
    for line in lines[starts[0] + 2:]:
        if not line.lstrip().startswith("|"):
            break
        cells = _cells(line)
        command, option = (_only_backticked(c) for c in cells[:2])
        if len(cells) != len(CLI_HEADER) or command is None or option is None:
            problems.append(f"malformed row: {line.strip()}")
        elif (command, option) in rows:
            problems.append(f"({command}, {option}) has two rows")
        else:
            rows[command, option] = cells
    return rows, problems


def test_cli_reference_table_matches_the_parser():
    options = parser_options()
    rows, problems = cli_table(_cli())
    problems += [f"({command}, {option}): in the parser, missing from the table"
                 for command, option in options if (command, option) not in rows]
    problems += [f"({command}, {option}): in the table, not in the parser"
                 for command, option in rows if (command, option) not in options]
    assert not problems, "docs/cli.md:\n" + "\n".join(problems)


def test_cli_reference_states_the_parser_defaults():
    options = parser_options()
    rows, _ = cli_table(_cli())
    problems = []
    for key, action in options.items():
        default = action.default
        if key not in rows or default in (None, False, argparse.SUPPRESS) or isinstance(
                default, (list, tuple)):
            continue
        if str(default) not in rows[key][3]:
            problems.append(f"{key}: the parser's default is {default!r}, the table says "
                            f"{rows[key][3]!r}")
    assert not problems, "docs/cli.md:\n" + "\n".join(problems)


def test_cli_reference_has_a_section_per_command():
    commands = sorted({command for command, _ in parser_options()} - {"vtcr"})
    headings = [line for line, in_code in _lines_outside_code(_cli())
                if not in_code and line.startswith("#")]
    missing = [command for command in commands
               if not any(f"`vtcr {command}`" in line for line in headings)]
    assert not missing, f"docs/cli.md has no section headed `vtcr COMMAND` for {missing}"
