"""The assembly description as a whole: :class:`Case`, validated across its tables, and the
assemblies derived from it (``docs/description.md``).

Its tables are the models of :mod:`assembly.models`; the checks across tables (materials, plates,
edges, joints, loads and measurements that refer to each other) are :func:`assembly.checks.
cross_check`, run once by the validator of :class:`Case`, which reports every problem at once.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Annotated, Any

import numpy as np
from pydantic import AfterValidator, Field, ValidationError, model_serializer, model_validator

from .checks import View, cross_check
from .errors import AssemblyError, CrossReferenceError, listing
from .grid import grid_points
from .joints import CoplanarJoint, HingeJoint, Joint, JunctionJoint
from .lines import (LINE_JOINTS, given_supports, hanging_members, line_moves,
                    member_directions, moving_lines, pinned_ends, singular_ends,
                    singular_line_ends)
from .models import Boundary, Load, Material, Plate
from .settings import Compute, Discretisation, Measurement, Truth, Updating, default_spacing
from .types import (
    EDGE_NAMES,
    JOINT_PARAMETERS,
    EdgeId,
    Frequency,
    FrozenDict,
    FrozenModel,
    Id,
    JointParameters,
    check_frequencies,
    freeze,
    is_real,
    parse_edge_ref,
    show_value,
)

__all__ = ["Case"]


def _junction_with(joint: JunctionJoint, changes: Mapping[str, Any],
                   member: str | None) -> JunctionJoint:
    """A junction with new member values: ``changes`` ``{name: number or table by plate}``
    for every member, or for ``member`` only."""
    data = joint.model_dump()
    for name, value in changes.items():
        if name == "mass":
            if value != 0.0:
                raise AssemblyError(f"junction {' - '.join(joint.between)} has no line mass; "
                                    f"got mass = {value!r}")
            continue
        if name not in ("log10_stiffness", "loss_factor"):
            raise AssemblyError(f"{name!r} is not a parameter of a junction's members "
                                "(parameters: log10_stiffness, loss_factor)")
        current = data[name]
        table = dict(current) if isinstance(current, Mapping) else dict.fromkeys(
            joint.plates, current)
        if member is not None:
            table[member] = value
        elif isinstance(value, Mapping):
            table.update(value)
        else:
            table = dict.fromkeys(joint.plates, value)
        data[name] = {p: float(v) for p, v in table.items()}
    try:
        return JunctionJoint.model_validate(data)
    except ValidationError as exc:
        problems = "; ".join(e["msg"].removeprefix("Value error, ") for e in exc.errors())
        raise AssemblyError(f"invalid member parameters of junction "
                            f"{' - '.join(joint.between)}: {problems}") from None


def _two_edge_with(jid: str, joint: CoplanarJoint | HingeJoint,
                   changes: Mapping[str, Any]) -> CoplanarJoint | HingeJoint:
    """Joint ``jid``, a two-edge joint, with new values: ``changes`` ``{name: real number}``
    of :data:`~assembly.types.JOINT_PARAMETERS`, each checked (a hinge has no line mass: only
    ``mass = 0`` is accepted, and ignored)."""
    data = joint.model_dump()
    for name, value in changes.items():
        if name not in JOINT_PARAMETERS:
            raise AssemblyError(
                f"{name!r} is not a joint parameter of joint {jid!r} (parameters: "
                f"{', '.join(JOINT_PARAMETERS)})"
            )
        scalar_array = isinstance(value, np.ndarray) and (
            value.shape == () and value.dtype.kind in "iuf"
        )
        if not (is_real(value) or scalar_array):
            raise AssemblyError(
                f"{name} of joint {jid!r} must be a real number, got {show_value(value)}"
            )
        value = float(value)
        if name == "mass" and isinstance(joint, HingeJoint):
            if value != 0.0:
                raise AssemblyError(
                    f"joint {jid!r} is a hinge, which has no line mass; got mass = "
                    f"{value:g}"
                )
            continue
        data[name] = value
    try:
        return type(joint).model_validate(data)
    except ValidationError as exc:
        problems = "; ".join(
            f"{'.'.join(map(str, e['loc']))} {e['msg'].lower()}, "
            f"got {show_value(e['input'])}"
            for e in exc.errors()
        )
        raise AssemblyError(f"invalid parameters for joint {jid!r}: {problems}") from None


class Case(FrozenModel):
    r"""An assembly description: plates, joints, boundary conditions, loads and settings.

    Build it with :func:`assembly.load_case` (TOML file), :func:`assembly.load_case_text`
    or :func:`assembly.parse_case` (dict), which report every problem at once as a
    :class:`~assembly.errors.DescriptionError`.  ``Case.model_validate(data)`` works too but
    raises pydantic's ``ValidationError``.

    Parameters
    ----------
    name : str
        Name of the assembly.
    frequency : float, optional
        Single excitation frequency in Hz, > 0.  Give exactly one of `frequency` and
        `frequencies`.
    frequencies : tuple of float, optional
        Distinct frequencies in Hz, > 0.  After validation always set: ``(frequency,)``
        when `frequency` was given.
    materials : mapping of str to Material
        ``[materials.ID]`` tables; ids use letters, digits, ``_`` and ``-``.
    plates : mapping of str to Plate
        ``[plates.ID]`` tables, at least one.
    joints : mapping of str to CoplanarJoint or HingeJoint, optional
        ``[joints.ID]`` tables.
    boundaries : tuple of Boundary, optional
        ``[[boundaries]]``; edges neither joined nor listed are free.
    loads : tuple of EdgeShear, EdgeMoment or PointForce, optional
        ``[[loads]]``.
    discretisation : Discretisation, optional
    measurement : Measurement, optional
    updating : Updating, optional
        After validation ``updating.alpha`` holds every joint's weight, normalised to sum 1.
    compute : Compute, optional
        Where independent tasks run (local processes or a Dask scheduler).
    truth : Truth, optional
        True joint parameters of a simulated experiment.

    Notes
    -----
    The model is frozen and its tables are :class:`FrozenDict`; derived assemblies are built
    by copy (:meth:`with_joint_parameters`, :meth:`true_case`), so an updating history stays
    reproducible.

    Examples
    --------
    >>> from assembly import load_case
    >>> case = load_case("cases/single_plate.toml")
    >>> case.frequencies, case.plates["P1"].size
    ((155.0,), (0.5, 0.4))
    """

    name: Annotated[str, Field(min_length=1)]
    frequency: Frequency | None = None
    frequencies: Annotated[tuple[Frequency, ...], AfterValidator(check_frequencies)] | None = (
        None
    )
    materials: Annotated[dict[Id, Material], AfterValidator(freeze)]
    plates: Annotated[dict[Id, Plate], Field(min_length=1), AfterValidator(freeze)]
    joints: Annotated[dict[Id, Joint], AfterValidator(freeze)] = Field(
        default_factory=FrozenDict
    )
    boundaries: tuple[Boundary, ...] = ()
    loads: tuple[Load, ...] = ()
    discretisation: Discretisation = Field(default_factory=Discretisation)
    measurement: Measurement = Field(default_factory=Measurement)
    updating: Updating = Field(default_factory=Updating)
    compute: Compute = Field(default_factory=Compute)
    truth: Truth = Field(default_factory=Truth)

    # ---------------------------------------------------------------- validation
    @model_validator(mode="after")
    def _check_references(self) -> Case:
        if self.measurement.spacing is None:  # relative to the structure, not to the metre
            object.__setattr__(self, "measurement", self.measurement.model_copy(
                update={"spacing": default_spacing(self.plates)}))
        issues = cross_check(
            View(
                materials=self.materials,
                plates=self.plates,
                joints=self.joints,
                boundaries=self.boundaries,
                loads=self.loads,
                discretisation=self.discretisation,
                measurement=self.measurement,
                updating=self.updating,
                truth=self.truth,
                has_frequency=self.frequency is not None,
                has_frequencies=self.frequencies is not None,
            )
        )
        if issues:
            raise CrossReferenceError(issues)
        # Normalisations on a frozen model, done once here (before anyone sees the object).
        if self.frequency is not None:
            object.__setattr__(self, "frequencies", (self.frequency,))
        weights = {jid: (self.updating.alpha or {}).get(jid, 1.0) for jid in self.joints}
        total = sum(weights.values())
        if weights and abs(total - 1.0) > 1e-12:
            weights = {jid: w / total for jid, w in weights.items()}
        object.__setattr__(
            self, "updating", self.updating.model_copy(update={"alpha": FrozenDict(weights)})
        )
        return self

    @model_serializer(mode="wrap")
    def _serialise(self, handler: Any) -> Any:
        # Dump the frequency the way it was given, so that a dump validates again.
        data = handler(self)
        if isinstance(data, dict):
            data.pop("frequencies" if self.frequency is not None else "frequency", None)
        return data

    # ---------------------------------------------------------------- look-ups
    def edge(self, ref: str | EdgeId) -> EdgeId:
        """Resolve an edge reference of this assembly.

        Parameters
        ----------
        ref : str or EdgeId
            ``"PLATE.EDGE"`` or an :class:`EdgeId`.

        Returns
        -------
        EdgeId

        Raises
        ------
        AssemblyError
            If the reference is malformed or the plate is not in the assembly.
        """
        edge = EdgeId(*ref) if isinstance(ref, tuple) else parse_edge_ref(ref)
        if edge.plate not in self.plates:
            raise AssemblyError(
                f"plate {edge.plate!r} is not in the assembly (plates: {listing(self.plates)})"
            )
        if edge.edge not in EDGE_NAMES:
            raise AssemblyError(f"{edge.edge!r} is not an edge name ({', '.join(EDGE_NAMES)})")
        return edge

    def edge_length(self, ref: str | EdgeId) -> float:
        """Return the length in m of an edge ``"PLATE.EDGE"``."""
        edge = self.edge(ref)
        return self.plates[edge.plate].edge_length(edge.edge)

    def material_of(self, plate_id: str) -> Material:
        """Return the material of a plate."""
        return self.materials[self.plates[plate_id].material]

    def edge_conditions(self) -> dict[EdgeId, str]:
        """Return the condition of every plate edge.

        Returns
        -------
        dict of EdgeId to str
            For each plate (description order) and edge (:data:`~assembly.geometry.EDGE_NAMES`):
            ``"joined"``, ``"clamped"``, ``"simply_supported"``, ``"free"`` or
            ``"symmetric"``.
        """
        joined = self.edge_joints()
        given = {parse_edge_ref(bc.edge): bc.condition for bc in self.boundaries}
        return {
            EdgeId(pid, e): "joined"
            if EdgeId(pid, e) in joined
            else given.get(EdgeId(pid, e), "free")
            for pid in self.plates
            for e in EDGE_NAMES
        }

    def moving_lines(self) -> tuple[str, ...]:
        """The junction lines and hinges that move (:func:`assembly.lines.moving_lines`:
        ``held = false``, or by default non-coplanar members)."""
        return moving_lines(self.joints, self.plates, self.boundaries)

    def is_line(self, joint_id: str) -> bool:
        """Whether a joint follows the rules of a junction line (``docs/method.md`` section
        6.2b): a junction, or a hinge that moves (a line of two members, the first rigid)."""
        joint = self.joints[joint_id]
        # one joint's decision, not the assembly's: the solver asks joint by joint
        return joint.kind == "junction" or (
            joint.kind == "hinge"
            and line_moves(joint, self.plates, given_supports(self.boundaries)))

    def edge_joints(self) -> dict[EdgeId, str]:
        """Return ``{edge: joint id}`` for every joined edge."""
        return {side: jid for jid, joint in self.joints.items() for side in joint.sides}

    def singular_ends(self, joint_id: str) -> list[EdgeId]:
        """The end edges of a junction line that are a plane of symmetry for part of the
        motion only (:func:`assembly.lines.singular_ends`); none for another joint."""
        return self._of_line(joint_id, singular_ends)

    def singular_line_ends(self, joint_id: str) -> tuple[bool, bool]:
        """Whether a junction line's start and end (along the line) are singular
        (:func:`assembly.lines.singular_line_ends`); neither for another joint."""
        return tuple(self._of_line(joint_id, singular_line_ends)) or (False, False)

    def pinned_ends(self, joint_id: str) -> list[EdgeId]:
        """The end edges of a junction line at its ends where a member is pinned at its corner
        (:func:`assembly.lines.pinned_ends`); none for another joint."""
        conditions = self.edge_conditions()
        return self._of_line(joint_id, lambda joint, plates, supports: pinned_ends(
            joint, plates, conditions, supports))

    def hanging_members(self, joint_id: str) -> list[str]:
        """The members of a junction line held across it in their plane by no boundary of
        their own (:func:`assembly.lines.hanging_members`); none for another joint."""
        return self._of_line(joint_id, hanging_members)

    def _of_line(self, joint_id: str, find: Callable[..., list]) -> list:
        """``find(joint, plates, supports)`` for a junction line, none for another joint."""
        joint = self.joints[joint_id]
        if not isinstance(joint, LINE_JOINTS):
            return []
        return find(joint, self.plates, given_supports(self.boundaries))

    def member_directions(self, joint_id: str) -> tuple[int, ...]:
        """For each edge of a joint, +1 if it runs (counter-clockwise) along the joint line's
        direction, -1 if against it (:func:`assembly.lines.member_directions`)."""
        return member_directions(self.joints[joint_id], self.plates)

    def joint_parameters(self) -> dict[str, dict[str, float]]:
        """Return the current joint parameters, ``{joint id: {name: value}}``.

        Every joint has ``log10_stiffness`` and ``loss_factor``; coplanar joints also
        ``mass`` (kg/m).
        """
        return {jid: joint.parameters() for jid, joint in self.joints.items()}

    def measured_plates(self) -> tuple[str, ...]:
        """Return the plates carrying the measurement grid (all plates by default)."""
        chosen = self.measurement.plates
        return tuple(self.plates) if chosen is None else chosen

    def measurement_points(self) -> tuple[tuple[str, float, float], ...]:
        """Return the measurement points ``(plate, x, y)`` in plate-local m.

        The grid of each measured plate (:meth:`measured_plates`) consists of the cell
        centres of a uniform mesh: ``nx = max(1, round(Lx / spacing))`` cells and points
        ``x_i = (i + 1/2) Lx / nx``, ``i = 0 .. nx - 1`` (likewise in y), ordered by plate,
        then x, then y -- the rule of ``solver.field_grid``.  The explicit
        ``measurement.points`` follow.

        Returns
        -------
        tuple of (str, float, float)

        Examples
        --------
        >>> from assembly import load_case
        >>> case = load_case("cases/single_plate.toml")
        >>> len(case.measurement_points())  # 5 x 4 cell centres of a 0.1 m mesh
        20
        """
        spacing = self.measurement.spacing
        points: list[tuple[str, float, float]] = []
        for pid in self.measured_plates():
            points.extend((pid, x, y) for x, y in grid_points(self.plates[pid].size, spacing))
        points.extend((p.plate, p.at[0], p.at[1]) for p in self.measurement.points)
        return tuple(points)

    # ---------------------------------------------------------------- derived cases
    def with_joint_parameters(self, parameters: Mapping[str, Mapping[str, float]]) -> Case:
        """Return a copy of the assembly with some joint parameters replaced.

        The assembly itself is not changed.

        Parameters
        ----------
        parameters : mapping of str to mapping of str to float
            ``{joint id: {name: value}}`` with names ``log10_stiffness``, ``loss_factor``
            and (coplanar joints) ``mass``.  Parameters not given keep their value.

        Returns
        -------
        Case
            The new assembly.

        Raises
        ------
        AssemblyError
            For an unknown joint or parameter, a value that is not a real number or is out
            of range, or a non-zero mass on a hinge.

        Examples
        --------
        >>> from assembly import load_case_text
        >>> case = load_case_text('''
        ... name = "two"
        ... frequency = 155.0
        ... [materials.steel]
        ... young_modulus = 210e9
        ... poisson_ratio = 0.3
        ... density = 7800.0
        ... loss_factor = 0.01
        ... [plates.P1]
        ... material = "steel"
        ... thickness = 0.001
        ... size = [0.5, 0.4]
        ... [plates.P2]
        ... material = "steel"
        ... thickness = 0.001
        ... size = [0.4, 0.4]
        ... [joints.G1]
        ... kind = "coplanar"
        ... between = ["P1.right", "P2.left"]
        ... log10_stiffness = 2.0
        ... ''')
        >>> new = case.with_joint_parameters({"G1": {"log10_stiffness": 1.5}})
        >>> new.joints["G1"].log10_stiffness, case.joints["G1"].log10_stiffness
        (1.5, 2.0)
        """
        if not isinstance(parameters, Mapping):
            raise AssemblyError(
                f"joint parameters must be a mapping {{joint id: {{name: value}}}}, got "
                f"{show_value(parameters)}"
            )
        joints = dict(self.joints)
        for key, changes in parameters.items():
            jid, _, member = str(key).partition(".")
            if jid not in self.joints or (member and member not in self.joints[jid].plates):
                raise AssemblyError(
                    f"joint {key!r} is not in the assembly (joints: {listing(self.joints)}; "
                    "a junction's member as JOINT.PLATE)"
                )
            if not isinstance(changes, Mapping):
                raise AssemblyError(
                    f"parameters of joint {key!r} must be a mapping {{name: value}}, got "
                    f"{show_value(changes)}"
                )
            if isinstance(joints[jid], JunctionJoint):
                joints[jid] = _junction_with(joints[jid], changes, member or None)
            else:
                joints[jid] = _two_edge_with(jid, self.joints[jid], changes)
        return self.model_copy(update={"joints": FrozenDict(joints)})

    def updatable_joints(self) -> dict[str, tuple[str, str | None]]:
        """The joints the updating localises and corrects, by name.

        Every two-edge joint by its id; every finite member of a junction as ``JOINT.PLATE``
        (each member's spring is a channel of its own; rigid members are not updatable).

        Returns
        -------
        dict of str to (str, str or None)
            ``{name: (joint id, member plate or None)}``, in description order.
        """
        out: dict[str, tuple[str, str | None]] = {}
        for jid, joint in self.joints.items():
            if isinstance(joint, JunctionJoint):
                out.update({f"{jid}.{p}": (jid, p) for p in joint.finite_members()})
            else:
                out[jid] = (jid, None)
        return out

    def updatable_parameters(self) -> JointParameters:
        """``{name: {log10_stiffness, loss_factor, mass}}`` of :meth:`updatable_joints`."""
        out = {}
        for name, (jid, member) in self.updatable_joints().items():
            joint = self.joints[jid]
            if member is None:
                out[name] = {"log10_stiffness": joint.log10_stiffness,
                             "loss_factor": joint.loss_factor, "mass": joint.mass}
            else:
                out[name] = {"log10_stiffness": joint.member_log10_stiffness(member),
                             "loss_factor": joint.member_loss_factor(member), "mass": 0.0}
        return JointParameters.of(out)

    def updatable_alpha(self) -> dict[str, float]:
        """The weight of each updatable joint's residual in :math:`E_{int}^2`: its joint's
        ``[updating] alpha`` (a junction's members share it)."""
        return {name: self.updating.alpha[jid]
                for name, (jid, _) in self.updatable_joints().items()}

    def true_log10_stiffness(self) -> dict[str, float]:
        """``{updatable joint: true log10 k}`` of the joints whose ``[truth]`` gives a
        stiffness (every finite member of such a junction; members it does not name keep
        their model values)."""
        true = self.true_case().updatable_parameters()
        return {name: true[name]["log10_stiffness"]
                for name, (jid, _) in self.updatable_joints().items()
                if jid in self.truth.joints and self.truth.joints[jid].log10_stiffness is not None}

    def true_parameters(self) -> dict[str, dict[str, float]]:
        """``{updatable joint: {parameter: true value}}`` of the parameters (``log10_stiffness``,
        ``loss_factor``, ``mass``) that ``[truth]`` gives, for the joints it names."""
        true = self.true_case().updatable_parameters()
        out: dict[str, dict[str, float]] = {}
        for name, (jid, _) in self.updatable_joints().items():
            given = self.truth.joints[jid].changes() if jid in self.truth.joints else {}
            if given:
                out[name] = {key: true[name][key] for key in given}
        return out

    def true_case(self) -> Case:
        """Return the assembly with its joints replaced by the ``[truth]`` parameters.

        Joints not listed in ``[truth.joints]`` keep their model values; the truth table
        itself is kept, so ``case.true_case().true_case() == case.true_case()``.

        Returns
        -------
        Case
        """
        changes = {jid: true.changes() for jid, true in self.truth.joints.items()}
        return self.with_joint_parameters({j: c for j, c in changes.items() if c})
