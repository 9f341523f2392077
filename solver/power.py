r"""Where the power goes: energies and powers of a solved plate or assembly, and their balance.

Time-averaged quantities with the convention :math:`e^{+j\omega t}`
(``docs/method.md`` sections 1, 2 and 6.2): a force :math:`F` on a displacement :math:`w`
delivers :math:`\tfrac12\mathrm{Re}[F\,(j\omega w)^*] = \tfrac12\omega\,\mathrm{Im}(F\bar w)`.

* **Injected** by the loads of plate :math:`i`:
  :math:`P_{in,i} = \tfrac12\omega\,\mathrm{Im}\big[\sum_f F_f\bar w(\mathbf x_f)
  + \int_{\partial\Omega_i}(T\bar w - M\,\partial_n\bar w)\,ds\big]` (point forces, edge shear
  :math:`T` and edge moment :math:`M`).
* **Kinetic energy** of plate :math:`i`: :math:`T_i = \tfrac14\omega^2\rho_ih_i\int|w|^2dA`.
* **Dissipated** in plate :math:`i` (hysteretic :math:`D^* = D(1+j\eta)`):
  :math:`P_{d,i} = \tfrac12\omega\,\mathrm{Im}(D^*)\,a(w,\bar w)`,
  :math:`a = \int\big[|w_{,xx}|^2 + |w_{,yy}|^2 + 2\nu\,\mathrm{Re}(w_{,xx}\bar w_{,yy})
  + 2(1-\nu)|w_{,xy}|^2\big]dA`. The field solves the plate equation exactly, so the Green
  identity (``docs/method.md`` section 2.1 with :math:`v = \bar w`) turns this domain integral into
  what the point forces and the boundary tractions deliver: :math:`P_{d,i} =
  \tfrac12\omega\,\mathrm{Im}[\sum_fF_f\bar w(\mathbf x_f) + \oint(Q_n\bar w -
  M_{nt}\partial_s\bar w - M_n\partial_n\bar w)\,ds]` (the corner forces folded into the
  :math:`M_{nt}` term by parts; edge loads are tractions, already in the pairing). Edge Gauss
  rules of the VTCR's own size integrate it to round-off; a domain rule graded at the point
  forces (log-singular curvatures) gives the same values to 1e-9 and costs 56 times more
  (13.5 s against 0.24 s for the three-plate chain of ``tests/test_sweep.py``).
* **Dissipated** in a joint, from its law: :math:`\tfrac12\omega\sum_c\mathrm{Im}(c)
  \int_\Gamma|[q_c]|^2ds` over its channels (rotation spring :math:`c = k(1+j\zeta)`; the line
  mass is conservative).
* **Transmitted** across a joint from its first plate to its second: the mean of the power
  leaving the first plate and the power entering the second through the joint line,
  :math:`P_{\to i} = \tfrac12\omega\,\mathrm{Im}\int_\Gamma(K_i\bar w_i - M_i\,\partial_n\bar w_i)\,ds`
  with the joint's loads :math:`K_i, M_i` on plate :math:`i` (the interface unknowns) and the
  plate's traces. Corner forces at junction corners are not attributed to a joint.

**Balance.** For the exact field, :math:`\sum_iP_{in,i} = \sum_iP_{d,i} + \sum_\Gamma P_{d,\Gamma}`:
the outer boundaries absorb nothing and every joint law holds. The two sides are computed from
different ingredients: the plates' dissipation is what their own boundary tractions deliver,
the joints' is their law applied to the trace jumps. Their difference is the power the outer
edges absorb (zero for exact supports) plus, on each joint line, the mismatch between the
plates' tractions and the joint law: what the discretisation leaves unsatisfied of the
conditions the VTCR imposes weakly.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Hashable, Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from assembly.case import Case
from assembly.geometry import EdgeGeometry, plate_edges
from solver.interface_loads import (
    FORCE_COMPONENTS,
    LoadTerms,
    load_values,
    member_axes,
    member_load,
    traction_loads,
)
from solver.joint_rules import (
    joint_gauss,
    joint_parameters,
    load_function_values,
    translational_stiffness,
)
from solver.membrane import membrane_dissipated_power
from solver.plate import (
    PlateProblem,
    edge_rule_size,
    edge_values,
    evaluate_field,
    particular_field,
    particular_traces,
    shape_traces,
)
from solver.rays import RayBasis, edge_rule, gauss_legendre, tensor_grid_field
from solver.solution import CaseSolution

__all__ = ["PowerFlow", "power_flow", "plate_powers", "injected_power", "carries_loads",
           "kinetic_energies", "plate_gauss_axes", "grid_deflections"]

_Key = TypeVar("_Key", bound=Hashable)


@dataclass(frozen=True)
class PowerFlow:
    """Energies and powers of one solution (W and J, time-averaged).

    ``injected``, ``kinetic`` and ``dissipated`` are per plate; ``joint_dissipated`` and
    ``transmitted`` (from the joint's first plate to its second; for a junction, from its first
    member to the others) per joint; ``delivered`` per joint and member plate: the power the
    joint's loads put into that plate (a passive joint's sum over its members is minus its
    dissipated power); ``corners`` per plate with static junction corners: the power their
    corner forces put into it (the forces at a junction point do no net work, so these sum to
    zero over a point's plates). A plate's injected, delivered and corner powers sum to what it
    dissipates.
    """

    frequency: float
    injected: dict
    kinetic: dict
    dissipated: dict
    joint_dissipated: dict
    transmitted: dict
    delivered: dict = dataclasses.field(default_factory=dict)
    corners: dict = dataclasses.field(default_factory=dict)

    @property
    def total_injected(self) -> float:
        return float(sum(self.injected.values()))

    @property
    def total_dissipated(self) -> float:
        """Dissipated in the plates and the joints."""
        return float(sum(self.dissipated.values()) + sum(self.joint_dissipated.values()))

    @property
    def imbalance(self) -> float:
        """``|injected - dissipated| / injected`` (0 for an exact field)."""
        injected = self.total_injected
        if injected == 0.0:
            return 0.0 if self.total_dissipated == 0.0 else math.inf
        return abs(injected - self.total_dissipated) / abs(injected)

    def to_json(self) -> dict[str, Any]:
        return {"frequency": self.frequency, "injected": self.total_injected,
                "dissipated": self.total_dissipated, "imbalance": self.imbalance,
                "plates": {pid: {"injected": self.injected[pid], "kinetic_energy": self.kinetic[pid],
                                 "dissipated": self.dissipated[pid]}
                           | ({"delivered_at_corners": self.corners[pid]}
                              if pid in self.corners else {}) for pid in self.injected},
                "joints": {jid: {"transmitted": self.transmitted[jid],
                                 "dissipated": self.joint_dissipated[jid],
                                 "delivered": dict(self.delivered.get(jid, {}))}
                           for jid in self.transmitted}}


def _edge_field(problem: PlateProblem, basis: RayBasis, amplitudes: np.ndarray,
                edge: EdgeGeometry, s: ArrayLike) -> dict[str, np.ndarray]:
    """Field quantities on an edge at arc lengths ``s``: ``w``, ``slope`` (outward
    :math:`\\partial_nw`), ``tangential`` (:math:`\\partial_sw`), ``moment`` (:math:`M_n`),
    ``twist`` (:math:`M_{nt}`) and ``shear_q`` (:math:`Q_n`)."""
    s = np.asarray(s, dtype=float)
    keys = ("w", "slope", "tangential", "moment", "twist", "shear_q")
    traces = shape_traces(problem, basis, edge, s, keys)
    particular = particular_traces(problem, edge.start + s[:, None] * edge.tangent, edge.normal,
                                   edge.tangent)
    return {key: traces[key] @ amplitudes + particular[key] for key in keys}


def _loaded(condition) -> bool:
    """Whether an edge condition prescribes a shear or a moment (an edge load)."""
    return condition.shear is not None or condition.moment is not None


def carries_loads(problem: PlateProblem) -> bool:
    """Whether a plate has point forces or edge loads: only such a plate injects power."""
    return bool(problem.point_forces) or any(_loaded(problem.condition(edge.name))
                                             for edge in plate_edges(problem.size))


def _power_edges(problem: PlateProblem, basis: RayBasis, amplitudes: np.ndarray,
                 loaded_only: bool):
    """``(s, weights, field, condition, length)`` per edge of the plate (only those with an
    edge load if ``loaded_only``): the field at the points ``s`` of the edge's rule of the
    VTCR's size."""
    k_max = float(np.max(np.abs(basis.k)))
    sources = [f.position for f in problem.point_forces]
    for edge in plate_edges(problem.size):
        condition = problem.condition(edge.name)
        if loaded_only and not _loaded(condition):
            continue
        s, wq = edge_rule([edge], edge_rule_size(edge.length, k_max, sources, edge),
                          [family.point for family in basis.wedges])
        yield s, wq, _edge_field(problem, basis, amplitudes, edge, s), condition, edge.length


def _load_work(problem: PlateProblem, basis: RayBasis, amplitudes: np.ndarray,
               edges) -> tuple[complex, complex]:
    r"""The loads' pairings with the field, :math:`\sum_fF_f\bar w(\mathbf x_f)` and
    :math:`\int(T\bar w - M\,\partial_n\bar w)\,ds` over ``edges`` (:func:`_power_edges`)."""
    forces, edge_loads = 0j, 0j
    for force in problem.point_forces:
        w = evaluate_field(problem, basis, amplitudes, np.array([force.position]))["w"][0]
        forces += force.amplitude * np.conj(w)
    for s, wq, field, condition, length in edges:
        if condition.shear is not None:
            edge_loads += wq @ (condition.shear.values(s, length) * np.conj(field["w"]))
        if condition.moment is not None:
            edge_loads -= wq @ (condition.moment.values(s, length) * np.conj(field["slope"]))
    return forces, edge_loads


def injected_power(problem: PlateProblem, basis: RayBasis, amplitudes: np.ndarray) -> float:
    r"""The power one plate's loads inject (W), :math:`P_{in}` of the module docstring: the
    field evaluated at its point forces and on its loaded edges only."""
    forces, edge_loads = _load_work(problem, basis, amplitudes,
                                    _power_edges(problem, basis, amplitudes, loaded_only=True))
    return 0.5 * problem.omega * float((forces + edge_loads).imag)


def plate_powers(problem: PlateProblem, basis: RayBasis,
                 amplitudes: np.ndarray) -> tuple[float, float]:
    """``(injected, dissipated)`` power of one plate (W): its loads' and, by the Green identity,
    its bending dissipation (module docstring)."""
    edges = list(_power_edges(problem, basis, amplitudes, loaded_only=False))
    boundary = sum(wq @ (field["shear_q"] * np.conj(field["w"])
                         - field["twist"] * np.conj(field["tangential"])
                         - field["moment"] * np.conj(field["slope"]))
                   for _, wq, field, _, _ in edges)
    forces, edge_loads = _load_work(problem, basis, amplitudes, edges)
    # an edge load is a boundary traction: the boundary pairing already holds its power
    half_omega = 0.5 * problem.omega
    return (half_omega * float((forces + edge_loads).imag),
            half_omega * float((forces + boundary).imag))


def plate_gauss_axes(problem: PlateProblem) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    r"""1D Gauss rules ``(x, wx), (y, wy)`` over a plate, :math:`\lceil\kappa_0L\rceil + 12`
    points per side (:math:`\kappa_0 = \mathrm{Re}\,\kappa`): the domain rule of the kinetic
    energy and of the error estimate's L2 integrals."""
    rules = []
    for length in problem.size:
        x, w = gauss_legendre(math.ceil(problem.kappa.real * length) + 12)
        rules.append((0.5 * length * (x + 1.0), 0.5 * length * w))
    return tuple(rules)


def _grid_particular(problem: PlateProblem, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The particular solution's ``w`` on the tensor grid ``x`` x ``y``."""
    X, Y = np.meshgrid(x, y, indexing="ij")
    return particular_field(problem, np.c_[X.ravel(), Y.ravel()])["w"].reshape(X.shape)


def grid_deflections(
    plates: Mapping[_Key, tuple[PlateProblem, RayBasis, np.ndarray]],
) -> dict[_Key, np.ndarray]:
    r"""``{key: w}`` on each plate's Gauss grid (:func:`plate_gauss_axes`), shape (n_x, n_y),
    for ``plates`` ``{key: (problem, basis, amplitudes)}``: the rays summed as a product of 1D
    exponentials (:func:`solver.rays.tensor_grid_field`), plus the particular solution. The
    plates that share a basis object (hence size and wavenumber: a grid's identical plates)
    are evaluated together, their rays' exponentials computed once."""
    by_basis = {}
    for key, (problem, basis, amplitudes) in plates.items():
        by_basis.setdefault(id(basis), []).append(key)
    out = {}
    for keys in by_basis.values():
        problem, basis, _ = plates[keys[0]]
        (x, _), (y, _) = plate_gauss_axes(problem)
        rays = tensor_grid_field(basis, np.column_stack([plates[k][2] for k in keys]), x, y)
        for key, field in zip(keys, rays):
            out[key] = field + _grid_particular(plates[key][0], x, y)
    return out


def kinetic_energies(
    plates: Mapping[_Key, tuple[PlateProblem, RayBasis, np.ndarray]],
) -> dict[_Key, float]:
    r"""``{key:`` :math:`\tfrac14\omega^2\rho h\int|w|^2dA` ``}`` (J), the time-averaged
    kinetic energy of each of ``plates`` ``{key: (problem, basis, amplitudes)}`` on the rule of
    :func:`plate_gauss_axes` (fields by :func:`grid_deflections`)."""
    fields = grid_deflections(plates)
    energies = {}
    for key, (problem, _, _) in plates.items():
        (_, wx), (_, wy) = plate_gauss_axes(problem)
        integral = float(np.sum(np.outer(wx, wy) * np.abs(fields[key]) ** 2))
        energies[key] = 0.25 * problem.omega**2 * problem.mass_per_area * integral
    return energies


# system is the solution's solver.substructure.AssemblySystem, typed Any: substructure imports
# this module, and importing it here, even for annotations only, would close an import circle
def _joint_rule(case: Case, system: Any, jid: str
                ) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """A joint's length, its Gauss points and weights (:func:`solver.joint_rules.joint_gauss`,
    fine enough for every member's rays) and its load functions at them."""
    joint = case.joints[jid]
    length = case.edge_length(joint.sides[0])
    k_max = max(float(np.max(np.abs(system.bases[side.plate].k))) for side in joint.sides)
    ends = system.load_ends[jid]
    sigma, wq = joint_gauss(length, k_max, ends)
    slots = system.layout[jid]
    count = next(iter(slots.values())).stop - next(iter(slots.values())).start
    return length, sigma, wq, load_function_values(sigma, length, count, ends)


def _side_powers(case: Case, system: Any, jid: str, amplitudes: Mapping[str, np.ndarray],
                 membrane_amplitudes: Mapping[str, np.ndarray], s: np.ndarray) -> list[float]:
    """Power the joint ``jid`` delivers to each of its plates (W), from its loads (interface
    unknowns ``s``) and the plates' traces on the joint line."""
    joint = case.joints[jid]
    length, sigma, wq, psi = _joint_rule(case, system, jid)
    slots = system.layout[jid]
    directions = case.member_directions(jid)

    def load(terms: LoadTerms) -> np.ndarray:
        return psi @ load_values(terms, s)

    if case.is_line(jid):  # M_n = s_i C_i on member i, K_n = K_i on a moving line
        moments = [d * load(member_load(case, jid, slots, side.plate, "C"))
                   for side, d in zip(joint.sides, directions)]
        shears = [load(terms) if (terms := member_load(case, jid, slots, side.plate, "K"))
                  else None for side in joint.sides]
    else:
        moments = [psi @ s[slots["C"]]] * 2
        shears = ((psi @ s[slots["F"]], -(psi @ s[slots["F"]])) if "F" in slots
                  else (psi @ s[slots["FA"]], psi @ s[slots["FB"]]) if "FA" in slots
                  else (None, None))  # a hinge
    powers = []
    for side, d, moment, shear in zip(joint.sides, directions, moments, shears):
        arc = sigma if d > 0 else length - sigma
        rays, part = edge_values(system.problems[side.plate], system.bases[side.plate],
                                 side.edge, arc)
        w = rays["w"] @ amplitudes[side.plate] + part["w"]
        slope = rays["slope"] @ amplitudes[side.plate] + part["slope"]
        pairing = -(wq @ (moment * np.conj(slope)))
        if shear is not None:
            pairing += wq @ (shear * np.conj(w))
        tractions = traction_loads(case, jid, slots, side.plate)
        if tractions is not None:  # and its in-plane tractions N_nn, N_nt
            traces = system.membranes[side.plate].edge_traces(side.edge, arc)
            u = membrane_amplitudes[side.plate]
            pairing += wq @ (load(tractions[0]) * np.conj(traces["u_n"] @ u)
                             + load(tractions[1]) * np.conj(traces["u_t"] @ u))
        powers.append(0.5 * system.omega * float(pairing.imag))
    return powers


def power_flow(case: Case, solution: CaseSolution) -> PowerFlow:
    """The :class:`PowerFlow` of a solution of ``case`` (:func:`solver.solve_case`'s result).

    Joint quantities need the assembly's interface solution
    (:class:`solver.substructure.AssemblySolution`); a plate without joints has none.
    """
    omega = 2.0 * math.pi * solution.frequency
    injected, dissipated = {}, {}
    for pid, plate in solution.plates.items():
        problem, basis, x = plate.problem, plate.basis, plate.amplitudes
        injected[pid], dissipated[pid] = plate_powers(problem, basis, x)
    kinetic = kinetic_energies({pid: (plate.problem, plate.basis, plate.amplitudes)
                                for pid, plate in solution.plates.items()})
    joint_dissipated, transmitted, delivered = {}, {}, {}
    system = getattr(solution, "system", None)
    if case.joints and system is not None:
        s = solution.interface
        params = joint_parameters(case, omega)
        amplitudes = {pid: p.amplitudes for pid, p in solution.plates.items()}
        membrane_amplitudes = system.membrane_amplitudes(s)
        for pid, block in system.membranes.items():  # the in-plane fields dissipate too
            dissipated[pid] += membrane_dissipated_power(block.problem, block.basis,
                                                         membrane_amplitudes[pid])
        joint_dissipated = dict.fromkeys(case.joints, 0.0)
        for channel in system.channels:
            joint_dissipated[channel.joint] += channel.dissipated_power(
                s, params[channel.name, channel.kind], omega)
        for jid, joint in case.joints.items():
            if case.is_line(jid) and joint.translational_springs():
                joint_dissipated[jid] += _translational_spring_power(case, system, jid, s)
            to_first, *to_others = powers = _side_powers(case, system, jid, amplitudes,
                                                         membrane_amplitudes, s)
            transmitted[jid] = 0.5 * (sum(to_others) - to_first)
            delivered[jid] = {side.plate: p for side, p in zip(joint.sides, powers)}
    corners = _corner_powers(solution, system.corner_columns) if system is not None else {}
    return PowerFlow(solution.frequency, injected, kinetic, dissipated, joint_dissipated,
                     transmitted, delivered, corners)


def _translational_spring_power(case: Case, system: Any, jid: str, s: np.ndarray) -> float:
    r"""Power dissipated by the translational springs of a moving line's members
    (``docs/method.md`` section 10.4): with the line's force :math:`\mathbf f_i` on member
    :math:`i` and :math:`\mathbf X_J - \mathbf X_i = \mathbf f_i/k_{t,i}^*`,
    :math:`\tfrac12\omega\,\mathrm{Re}\int\mathbf f_i\cdot\overline{j(\mathbf X_J -
    \mathbf X_i)}\,d\sigma = \tfrac12\omega\,\mathrm{Im}(k_{t,i}^*)/|k_{t,i}^*|^2
    \int|\mathbf f_i|^2d\sigma` (W), exact on the loads' functions, where the law holds."""
    joint = case.joints[jid]
    _, _, wq, psi = _joint_rule(case, system, jid)
    slots = system.layout[jid]
    power = 0.0
    for plate in joint.translational_springs():
        side = next(side for side in joint.sides if side.plate == plate)
        force = sum(np.outer(psi @ load_values(terms, s), axis)
                    for name, axis in zip(FORCE_COMPONENTS, member_axes(case, side))
                    if (terms := member_load(case, jid, slots, plate, name)))
        stiffness = translational_stiffness(joint, plate)
        power += 0.5 * system.omega * stiffness.imag / abs(stiffness) ** 2 * float(
            wq @ np.sum(np.abs(force) ** 2, axis=1))
    return power


def _corner_powers(solution: CaseSolution, corner_columns: Mapping[tuple[str, int], int]
                   ) -> dict[str, float]:
    r"""Per plate with static junction corners, the power their forces :math:`P_c` (interface
    unknowns, applied as a corner's Kirchhoff force) put into it:
    :math:`\tfrac12\omega\,\mathrm{Im}\sum_c P_c\bar w_c` (W), with the plate's deflection
    :math:`w_c` at the corner, as an edge's shear load delivers
    :math:`\tfrac12\omega\,\mathrm{Im}\int K_n\bar w`."""
    omega = 2.0 * math.pi * solution.frequency
    powers: dict[str, float] = {}
    for (pid, corner), column in corner_columns.items():
        # corner c starts edge c (solver.plate's corner_w)
        start = plate_edges(solution.plates[pid].problem.size)[corner].start
        w = solution.w(pid, start[None, :])[0]
        force = solution.interface[column]
        powers[pid] = powers.get(pid, 0.0) + 0.5 * omega * float((force * np.conj(w)).imag)
    return powers
