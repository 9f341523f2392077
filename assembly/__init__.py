"""Assembly descriptions of jointed plates: validated models, TOML loading, graph, summary.

Import direction: ``assembly`` <- ``solver`` <- ``updating``.  This package imports
neither ``solver`` nor ``updating``; ``solver`` never imports ``updating``.

Contents
--------
load_case, load_case_text, parse_case
    Read a TOML description (file, text, dict) into a :class:`Case`; every problem is
    reported at once as a :class:`DescriptionError`.
Case, Material, Plate, CoplanarJoint, HingeJoint, Boundary, EdgeShear, EdgeMoment, PointForce
    The frozen pydantic models (more in :mod:`assembly.models`).
EdgeId, parse_edge_ref
    Edge references ``"PLATE.EDGE"``.
build_graph, joint_ids
    The assembly as a ``networkx.MultiGraph`` (plates = nodes, joints = keyed edges).
summarise
    A summary for ``vtcr check``.
generate.plate_grid, generate.description_toml
    Descriptions built by program (N x M grids and chains of plates) and their TOML text.
AssemblyError, DescriptionError
    Exceptions.
"""

from .case import Case
from .errors import AssemblyError, DescriptionError
from .graph import build_graph, joint_ids
from .joints import CoplanarJoint, HingeJoint, JunctionJoint
from .loading import load_case, load_case_text, parse_case
from .models import (
    Boundary,
    EdgeMoment,
    EdgeShear,
    Material,
    Plate,
    PointForce,
)
from .summary import summarise
from .types import EdgeId, parse_edge_ref

__all__ = [
    "AssemblyError",
    "Boundary",
    "Case",
    "CoplanarJoint",
    "DescriptionError",
    "EdgeId",
    "EdgeMoment",
    "EdgeShear",
    "HingeJoint",
    "JunctionJoint",
    "Material",
    "Plate",
    "PointForce",
    "build_graph",
    "joint_ids",
    "load_case",
    "load_case_text",
    "parse_case",
    "parse_edge_ref",
    "summarise",
]
