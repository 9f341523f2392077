"""The plate/joint graph of an assembly."""

from __future__ import annotations

import networkx as nx
import pytest
from support import STEEL

from assembly import CoplanarJoint, build_graph, joint_ids, load_case_text
from assembly.graph import components, is_connected, joint_attribute, joints_of_plate, plate_degrees

HEADER = '''\
name = "{name}"
frequency = 155.0

''' + STEEL


def plate(pid: str, origin: tuple[float, float], size: tuple[float, float] = (0.5, 0.4)) -> str:
    return (f"[plates.{pid}]\nmaterial = \"steel\"\nthickness = 0.001\n"
            f"size = [{size[0]}, {size[1]}]\norigin = [{origin[0]}, {origin[1]}]\n")


def joint(jid: str, a: str, b: str, log10_k: float, kind: str = "coplanar") -> str:
    return (f"[joints.{jid}]\nkind = \"{kind}\"\nbetween = [\"{a}\", \"{b}\"]\n"
            f"log10_stiffness = {log10_k}\n")


# Four identical plates around a common centre (the paper's section 5.2 inference):
#     P1 | P2          joints along the cross arms:
#     ---+---          G1 = P1.right-P2.left (upper arm), G2 = P2.bottom-P4.top (right arm),
#     P3 | P4          G3 = P3.right-P4.left (lower arm), G4 = P1.bottom-P3.top (left arm)
TWO_BY_TWO = (
    HEADER.format(name="two-by-two")
    + plate("P1", (0.0, 0.4)) + plate("P2", (0.5, 0.4))
    + plate("P3", (0.0, 0.0)) + plate("P4", (0.5, 0.0))
    + joint("G1", "P1.right", "P2.left", 1.0)
    + joint("G2", "P2.bottom", "P4.top", 3.0)
    + joint("G3", "P3.right", "P4.left", 2.0)
    + joint("G4", "P1.bottom", "P3.top", 1.5)
    + '[[boundaries]]\nedge = "P1.left"\ncondition = "clamped"\n'
    + '[[loads]]\nkind = "point_force"\nplate = "P4"\nat = [0.3, 0.2]\namplitude = 1.0\n'
)


@pytest.fixture(scope="module")
def graph() -> nx.MultiGraph:
    return build_graph(load_case_text(TWO_BY_TWO))


def test_two_by_two_nodes_and_edges(graph: nx.MultiGraph) -> None:
    assert isinstance(graph, nx.MultiGraph)
    assert list(graph.nodes) == ["P1", "P2", "P3", "P4"]
    assert graph.number_of_edges() == 4
    assert joint_ids(graph) == ["G1", "G2", "G3", "G4"]
    expected = {("P1", "P2"): "G1", ("P2", "P4"): "G2", ("P3", "P4"): "G3", ("P1", "P3"): "G4"}
    for (u, v), jid in expected.items():
        assert graph.has_edge(u, v, key=jid)
        data = graph.edges[u, v, jid]
        assert data["id"] == jid
        assert isinstance(data["joint"], CoplanarJoint)
        assert data["edges"] == data["joint"].between
    assert not graph.has_edge("P1", "P4") and not graph.has_edge("P2", "P3")


def test_two_by_two_structure(graph: nx.MultiGraph) -> None:
    assert is_connected(graph)
    assert components(graph) == [["P1", "P2", "P3", "P4"]]
    assert plate_degrees(graph) == {"P1": 2, "P2": 2, "P3": 2, "P4": 2}
    cycles = nx.cycle_basis(nx.Graph(graph))
    assert len(cycles) == 1 and sorted(cycles[0]) == ["P1", "P2", "P3", "P4"]
    assert joints_of_plate(graph, "P4") == ["G2", "G3"]
    assert graph.graph["name"] == "two-by-two"


def test_node_attributes(graph: nx.MultiGraph) -> None:
    p2 = graph.nodes["P2"]
    assert p2["plate"].origin == (0.5, 0.4)
    assert p2["material"].young_modulus == 210e9


def test_joint_attribute_by_name_or_callable(graph: nx.MultiGraph) -> None:
    assert joint_attribute(graph, "edges")["G2"] == ("P2.bottom", "P4.top")
    log_k = joint_attribute(graph, lambda u, v, d: d["joint"].log10_stiffness)
    assert log_k == {"G1": 1.0, "G2": 3.0, "G3": 2.0, "G4": 1.5}
    assert list(joint_attribute(graph)) == ["G1", "G2", "G3", "G4"]


def test_graph_follows_updated_case() -> None:
    case = load_case_text(TWO_BY_TWO)
    new = build_graph(case.with_joint_parameters({"G3": {"log10_stiffness": 4.5}}))
    assert new.edges["P3", "P4", "G3"]["joint"].log10_stiffness == 4.5
    assert build_graph(case).edges["P3", "P4", "G3"]["joint"].log10_stiffness == 2.0


def test_two_joints_between_the_same_plates() -> None:
    """A tube unrolled: P1.right-P2.left and P2.right-P1.left join the same pair twice."""
    text = (HEADER.format(name="ring") + plate("P1", (0.0, 0.0)) + plate("P2", (0.5, 0.0))
            + joint("A", "P1.right", "P2.left", 2.0)
            + joint("B", "P2.right", "P1.left", 2.0, kind="hinge"))
    graph = build_graph(load_case_text(text))
    assert graph.number_of_edges() == 2
    assert joint_ids(graph) == ["A", "B"]
    assert set(graph["P1"]["P2"]) == {"A", "B"}
    assert graph.edges["P1", "P2", "B"]["edges"] == ("P2.right", "P1.left")
    assert plate_degrees(graph) == {"P1": 2, "P2": 2}


def test_disconnected_assembly_is_allowed() -> None:
    text = (HEADER.format(name="apart") + plate("P1", (0.0, 0.0)) + plate("P2", (0.5, 0.0))
            + plate("P3", (2.0, 0.0)) + joint("G1", "P1.right", "P2.left", 2.0))
    graph = build_graph(load_case_text(text))
    assert not is_connected(graph)
    assert components(graph) == [["P1", "P2"], ["P3"]]
    assert plate_degrees(graph)["P3"] == 0
    assert joints_of_plate(graph, "P3") == []
