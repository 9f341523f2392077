"""The assembly as a graph: plates are nodes, joints are edges.

Two plates may be joined by more than one joint (a ring of two plates, a tube), so the
graph is a :class:`networkx.MultiGraph` whose edges are keyed by joint id.  Attribute
dicts hold the validated models; helpers take the attribute name or a callable, in the
spirit of networkx's ``_weight_function``.

Node attributes
    ``plate`` (:class:`~assembly.models.Plate`), ``material``
    (:class:`~assembly.models.Material`).
Edge attributes (key = joint id)
    ``joint`` (:class:`~assembly.joints.CoplanarJoint`, :class:`~assembly.joints.HingeJoint`
    or :class:`~assembly.joints.JunctionJoint`), ``id`` (the joint id), ``edges`` (the edge
    references ``("P1.right", "P2.left")``, in the order of ``between``; use this, not the
    networkx ``(u, v)`` order, to know which edge belongs to which plate).  A junction line
    of n members is n(n-1)/2 graph edges, one per pair of members, all keyed by its id: every
    member plate is a neighbour of every other.
Graph attributes
    ``name`` (the case name), ``joint_order`` (joint ids in description order).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Hashable
from typing import Any

import networkx as nx

from .case import Case

__all__ = [
    "build_graph",
    "components",
    "is_connected",
    "joint_attribute",
    "joint_ids",
    "joints_of_plate",
    "plate_degrees",
]


def build_graph(case: Case) -> nx.MultiGraph:
    """Build the plate/joint graph of an assembly.

    Parameters
    ----------
    case : Case
        A validated assembly.

    Returns
    -------
    networkx.MultiGraph
        One node per plate (description order) with attributes ``plate`` and ``material``;
        one edge per joint, keyed by the joint id, with attributes ``joint``, ``id`` and
        ``edges``.

    Notes
    -----
    A MultiGraph because two plates may share several joints.  Cost O(plates + joints).

    Examples
    --------
    >>> from assembly import load_case
    >>> graph = build_graph(load_case("cases/single_plate.toml"))
    >>> list(graph.nodes), graph.number_of_edges()
    (['P1'], 0)
    """
    graph = nx.MultiGraph(name=case.name, joint_order=tuple(case.joints))
    for pid, plate in case.plates.items():
        graph.add_node(pid, plate=plate, material=case.materials[plate.material])
    for jid, joint in case.joints.items():
        for a, b in itertools.combinations(joint.plates, 2):
            graph.add_edge(a, b, key=jid, joint=joint, id=jid, edges=tuple(joint.between))
    return graph


def _value_function(
    value: str | Callable[..., Any],
) -> Callable[[Hashable, Hashable, dict[str, Any]], Any]:
    if callable(value):
        return value
    return lambda u, v, data: data[value]


def joint_attribute(
    graph: nx.MultiGraph, value: str | Callable[..., Any] = "joint"
) -> dict[str, Any]:
    """Return one value per joint.

    Parameters
    ----------
    graph : networkx.MultiGraph
        As built by :func:`build_graph`.
    value : str or callable, optional
        Edge attribute name, or a function ``value(u, v, data)`` of the two plates and the
        edge attribute dict.  Default ``"joint"`` (the joint model).

    Returns
    -------
    dict of str to object
        ``{joint id: value}``, joints in description order.

    Examples
    --------
    >>> from assembly import load_case
    >>> joint_attribute(build_graph(load_case("cases/single_plate.toml")), "edges")
    {}
    """
    get = _value_function(value)
    values = {key: get(u, v, data) for u, v, key, data in graph.edges(keys=True, data=True)}
    return {key: values[key] for key in joint_ids(graph)}


def joint_ids(graph: nx.MultiGraph) -> list[str]:
    """Return the joint ids of an assembly graph, in description order.

    Parameters
    ----------
    graph : networkx.MultiGraph
        As built by :func:`build_graph` (any MultiGraph works; its edge keys are returned,
        in networkx order when the graph has no ``joint_order`` attribute).

    Returns
    -------
    list of str
    """
    keys = list(dict.fromkeys(key for _, _, key in graph.edges(keys=True)))
    order = {jid: i for i, jid in enumerate(graph.graph.get("joint_order", ()))}
    return sorted(keys, key=lambda k: order.get(k, len(order)))


def joints_of_plate(graph: nx.MultiGraph, plate_id: str) -> list[str]:
    """Return the ids of the joints attached to one plate, in description order."""
    attached = {key for _, _, key in graph.edges(plate_id, keys=True)}
    return [jid for jid in joint_ids(graph) if jid in attached]


def plate_degrees(graph: nx.MultiGraph) -> dict[str, int]:
    """Return the number of joints of every plate, ``{plate id: degree}``."""
    return {pid: len({key for _, _, key in graph.edges(pid, keys=True)}) for pid in graph}


def components(graph: nx.MultiGraph) -> list[list[str]]:
    """Return the connected sub-assemblies, each a list of plate ids.

    Parameters
    ----------
    graph : networkx.MultiGraph
        As built by :func:`build_graph`.

    Returns
    -------
    list of list of str
        Components ordered by their first plate, plates in description (node) order.  A
        connected assembly gives one component.  A disconnected assembly is allowed: each
        sub-assembly is an independent problem.
    """
    nodes = list(graph.nodes)
    position = {n: i for i, n in enumerate(nodes)}
    groups = [sorted(c, key=position.__getitem__) for c in nx.connected_components(graph)]
    return sorted(groups, key=lambda c: position[c[0]])


def is_connected(graph: nx.MultiGraph) -> bool:
    """Tell whether every plate is reachable from every other through joints."""
    return graph.number_of_nodes() > 0 and nx.is_connected(graph)
