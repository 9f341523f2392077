"""The geometry of a rectangular plate's edges: their names in one order, and each edge's start,
tangent, outward normal and length in the plate's frame. The description, the solver and the
figures all take edges from here.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["EDGE_NAMES", "EdgeGeometry", "plate_edges", "edge_geometry"]

EDGE_NAMES: tuple[str, ...] = ("bottom", "right", "top", "left")
"""The edges of ``[0, Lx] x [0, Ly]`` counter-clockwise: edge ``i`` runs from corner ``i`` to
corner ``i + 1`` (corners (0, 0), (Lx, 0), (Lx, Ly), (0, Ly)), so it meets edges ``i - 1`` and
``i + 1``."""


@dataclass(frozen=True)
class EdgeGeometry:
    r"""A straight edge of the rectangle, traversed counter-clockwise: arc length :math:`s`
    from ``start`` along ``tangent`` :math:`\mathbf t = \mathbf e_z\times\mathbf n`, with the
    outward unit ``normal`` :math:`\mathbf n`."""

    name: str
    start: np.ndarray  # (2,)
    tangent: np.ndarray  # (2,), unit
    normal: np.ndarray  # (2,), outward unit
    length: float


def plate_edges(size: Sequence[float]) -> tuple[EdgeGeometry, ...]:
    """The four edges of ``[0, Lx] x [0, Ly]`` in the order of :data:`EDGE_NAMES`: made once per
    size (a solve asks for them hundreds of times), their arrays read-only."""
    lx, ly = size
    return _edges(float(lx), float(ly))


@functools.lru_cache(maxsize=256)
def _edges(lx: float, ly: float) -> tuple[EdgeGeometry, ...]:
    corners = np.array([[0.0, 0.0], [lx, 0.0], [lx, ly], [0.0, ly]])
    edges = []
    for i, name in enumerate(EDGE_NAMES):
        start, end = corners[i], corners[(i + 1) % 4]
        length = float(np.linalg.norm(end - start))
        tangent = (end - start) / length
        normal = np.array([tangent[1], -tangent[0]])  # t = e_z x n  <=>  n = t x e_z
        for vector in (start, tangent, normal):
            vector.setflags(write=False)
        edges.append(EdgeGeometry(name, start, tangent, normal, length))
    return tuple(edges)


def edge_geometry(size: Sequence[float], name: str) -> EdgeGeometry:
    """The edge ``name`` of ``[0, Lx] x [0, Ly]`` (:func:`plate_edges`)."""
    return plate_edges(size)[EDGE_NAMES.index(name)]
