r"""The modified constitutive-relation error and its reduced cost function p -> E_mod^2(p).

For each measured frequency (``docs/method.md`` sections 6.3 and 7.3):

.. math::
    E_{mod}^2(p) = \min_{S:\ GS = g}\ (1 - r)\sum_\Gamma\alpha_\Gamma E_\Gamma^2(S; p)
                   + r\,E_{mes}^2(S),\qquad
    E_{mes}^2 = \frac{\sum_n|\Pi_n u(S) - \tilde u_n|^2}{\sum_n|\tilde u_n|^2}
    \quad\text{or}\quad
    E_{mes}^2 = \sum_p\frac{m_p}{M}\frac{\sum_{n\in p}|\Pi_n u(S) - \tilde u_n|^2}
                                    {\sum_{n\in p}|\tilde u_n|^2},

where the plate fields are :math:`u_i = \Phi_i(U_i^0 + T_iS) + w_{p,i}` (admissibility holds
exactly for every S). Both terms are sums of squares of residual samples affine in S; the
measurement term has the linear part that the paper's printed eq. 30 omits. The first
:math:`E_{mes}^2` is the paper's (``[updating] misfit = "global"``, the default with a number
for r); the second (``"per_plate"``, the default with the scale-free weights,
:mod:`updating.inverse.weights`) is the mean over the M measured values of their plate's misfit
relative to its own measured field (:math:`m_p` values on plate p): under relative noise a plate far
from the load, whose field is weak, then counts as much as the loaded one, and a joint there is
judged by its own data rather than by a fraction of the whole structure's. With several
frequencies the costs are summed, each with its own fixed normalisation (its :math:`E_{ref}`
and :math:`\|\tilde u\|^2`).

Everything that does not depend on p — plate factorisations, transfer operators, residual
samples of each joint channel, the measurement operator of each plate and :math:`E_{ref}`
(fixed at the initial parameters) — is built once in :class:`ModifiedProblem`, each piece over
the interface unknowns of its own plates. One evaluation weighs the channel samples by the
parameters and factorises the sparse interface problem (:mod:`solver.interface`). While one
joint is corrected, a :class:`~updating.inverse.correction.JointCorrection` condenses the
problem on that joint's residual samples once, and each cost evaluation is then a dense solve
of their size. What the problem holds per frequency and what an evaluation gives are the
records of :mod:`updating.inverse.problem_data`.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from assembly.types import JointParameters
from solver.channels import channel_blocks, joint_residuals
from solver.errors import NumericalError, condition_warnings
from solver.estimate import enriched_solve, estimate_error
from solver.guards import check_description
from solver.joint_rules import channel_parameters
from solver.plate import particular_field
from solver.rays import ray_field
from solver.substructure import (
    AssemblySystem,
    build_assembly_system,
    solve_assembly,
    solve_interface,
)
from updating.executor import thread_map
from updating.inverse.correction import JointCorrection
from updating.inverse.problem_data import Evaluation, FrequencyData
from updating.inverse.weights import ScaleFreeWeights, scale_free_weights

if TYPE_CHECKING:
    from assembly import Case
    from solver.estimate import ErrorEstimate
    from solver.interface import InterfaceFactor
    from updating.data.measurements import Measurements
    from updating.executor import Executor

_R = TypeVar("_R")

__all__ = ["ModifiedProblem", "channel_parameters", "with_joint", "direct_factor",
           "direct_interface", "direct_amplitudes", "PARAMETER_NAMES", "PARAMETER_BOUNDS",
           "SMALLEST_MASS"]

PARAMETER_NAMES = ("log10_stiffness", "loss_factor", "mass")

SMALLEST_MASS = 1e-6
"""kg/m: the smallest line mass the updating considers (its optimisation is on log10 m)."""

PARAMETER_BOUNDS = {"loss_factor": (0.0, 10.0), "mass": (SMALLEST_MASS, 10.0)}
"""Bounds of the joint parameters besides log10 k (whose bounds are ``[updating] bounds``)."""

KEPT_FACTOR_ENTRIES = 5e6
"""LU entries (all frequencies) up to which the model response's factors are kept between
calls (80 MB of complex entries); the 10 x 10 grid's hold 2.0e7."""

MAX_KEPT_CORRECTIONS = 8
"""Condensations kept per set of parameters: each holds, per frequency, the joint's solves
through the whole interface problem (interface unknowns x residual samples)."""


def with_joint(parameters: Mapping[str, Mapping[str, float]], joint: str,
               **values: float) -> JointParameters:
    """A copy of ``parameters`` with ``values`` set on ``joint`` (the others untouched)."""
    return JointParameters.of(parameters).with_joint(joint, **values)


def direct_factor(system: AssemblySystem, parameters: Mapping[str, Mapping[str, float]],
                  alpha: Mapping[str, float]) -> InterfaceFactor:
    r"""The factorised model response (r = 0): minimise the weighted joint error
    :math:`\sum\alpha_\Gamma e_\Gamma^2` under admissibility, as
    :func:`solver.substructure.solve_assembly` does, on an already built system."""
    params = channel_parameters(parameters, system.omega)
    return solve_interface(system, channel_blocks(system.channels, params, alpha))


def direct_interface(system: AssemblySystem, parameters: Mapping[str, Mapping[str, float]],
                     alpha: Mapping[str, float]) -> np.ndarray:
    """Interface unknowns S of the model response (:func:`direct_factor`)."""
    return direct_factor(system, parameters, alpha).s


def direct_amplitudes(system: AssemblySystem, parameters: Mapping[str, Mapping[str, float]],
                      alpha: Mapping[str, float]) -> dict[str, np.ndarray]:
    """Plate ray amplitudes of the model response (r = 0) for joint ``parameters``."""
    return system.plate_amplitudes(direct_interface(system, parameters, alpha))


def _frequency_data(case: Case, resolution: float | Mapping[str, float] | None, estimate: bool,
                    discretisation: bool,
                    task: tuple[float, Mapping[str, tuple[np.ndarray, ArrayLike]]]
                    ) -> FrequencyData:
    """One measured frequency's :class:`~updating.inverse.problem_data.FrequencyData` (a task
    of :class:`ModifiedProblem`'s executor): its system, :math:`E_{ref}` at p0, the measurement
    operators and, if ``estimate``, the discretisation error estimate of the model's response
    at p0; with ``discretisation``, that response's error at the measured points (the floors'
    and the intervals'). Both come from one enriched solve, made only when one of them is
    asked for."""
    frequency, measured_plates = task
    system = build_assembly_system(case, frequency, resolution)
    initial = solve_assembly(case, frequency, resolution, system=system)  # E_ref at p0
    enriched = (enriched_solve(case, frequency, resolution) if estimate or discretisation
                else None)
    error = estimate_error(case, initial, resolution, enriched) if estimate else None
    finer, reason = (enriched.plates, enriched.reason) if discretisation else (None, "")
    plates, operators, data, offsets = [], [], [], []
    for pid, (points, measured) in measured_plates.items():
        problem, basis = system.problems[pid], system.bases[pid]
        rays = ray_field(basis, points)["w"]
        particular = particular_field(problem, points)["w"]
        plates.append(pid)
        operators.append(system.affine_plate_operator(pid, rays, particular))
        data.append(np.asarray(measured))
        if finer is not None:
            offsets.append(finer[pid].field(points)["w"] - operators[-1].residual(
                initial.interface))
    return FrequencyData(system, initial.reference, plates, operators, data, initial.interface,
                         error, case.updating.misfit_kind == "per_plate",
                         offsets if finer is not None else None, reason)


class ModifiedProblem:
    """The parameter-independent part of the updating problem, built once.

    Parameters
    ----------
    case : assembly.Case
        The model; its joints give the initial parameters p0 that fix :math:`E_{ref}`.
    measurements : updating.data.measurements.Measurements
    r : float, optional
        Weight of the measurement term (default ``[updating] r``).
    resolution : float or mapping of str to float, optional
        Discretisation resolution, per plate if a mapping (default ``[discretisation]
        resolution``).
    executor : updating.executor.Executor, optional
        Builds the frequencies in parallel (default: one after the other, in this process).
    estimate : bool, optional
        Estimate the discretisation error of the model's response at p0 at each frequency
        (:attr:`error_estimates`; an enriched solve each).
    discretisation : bool, optional
        Take that response's error at the measured points, from the same enriched solve, into
        the floors (:meth:`noise_floor`) and the intervals (default True; a cost curve needs
        neither).
    threads : int, optional
        Threads on which the frequencies of one evaluation are factorised side by side
        (default 1; :func:`updating.executor.frequency_threads` chooses from the memory).
    check : bool, optional
        Run the description's guard rails at the measured frequencies first
        (:func:`solver.guards.check_description`): errors raise
        :class:`assembly.DescriptionError`, warnings join :attr:`warnings` (default True;
        False where they ran already).
    """

    def __init__(self, case: Case, measurements: Measurements, r: float | None = None,
                 resolution: float | Mapping[str, float] | None = None,
                 executor: Executor | None = None, estimate: bool = False, threads: int = 1,
                 discretisation: bool = True, check: bool = True) -> None:
        self._description_warnings = tuple(check_description(
            case, case.name, measurements.frequencies, need_loads=True)) if check else ()
        self.case = case
        self.threads = threads
        self.joints = tuple(case.updatable_joints())
        self._last = None  # (parameters, {frequency: InterfaceFactor}) of the last evaluation
        self._corrections = (None, {})  # (parameters, {joint: JointCorrection} there)
        self.evaluation_times = []  # wall time of each evaluation on the measured data (s)
        self._neighbourhoods = None  # joint -> (joints, plates) around it, found once
        self._direct = None  # (parameters, {frequency: InterfaceFactor}) of the model response
        tasks = [(frequency, measurements.data[frequency])
                 for frequency in measurements.frequencies]
        build = functools.partial(_frequency_data, case, resolution, estimate, discretisation)
        built = executor.map(build, tasks) if executor else thread_map(build, tasks, threads)
        self.frequencies = {frequency: data for (frequency, _), data in zip(tasks, built)}
        self.weights = None  # the scale-free weights, when they are the ones in use
        if r is None and case.updating.automatic:
            self.weights = self._scale_free_weights()
            self.r, self.alpha = self.weights.r, self.weights.alpha
        else:
            self.r = case.updating.r if r is None else r
            self.alpha = case.updatable_alpha()

    def _scale_free_weights(self) -> ScaleFreeWeights:
        """:func:`updating.inverse.weights.scale_free_weights` of the model at p0 and the measured
        points, at the stated noise and ``[updating] balance``."""
        case = self.case
        plates = {name: case.joints[jid].plates
                  for name, (jid, _) in case.updatable_joints().items()}
        return scale_free_weights(
            plates, [freq.reference.plates for freq in self.frequencies.values()],
            [sum(np.size(v) for v in freq.data) for freq in self.frequencies.values()],
            case.measurement.noise, case.updating.balance, case.updatable_alpha())

    def with_data(self, data: Mapping[float, Sequence[ArrayLike]]) -> ModifiedProblem:
        """The same problem on other measured values on the same points (``{frequency: [values
        per measured plate]}``, as :meth:`synthetic_data` gives): the systems, the measurement
        operators and :math:`E_{ref}` are shared, nothing is rebuilt."""
        other = copy.copy(self)
        other.frequencies = {f: dataclasses.replace(freq, data=[np.asarray(v) for v in data[f]])
                             for f, freq in self.frequencies.items()}
        other._last, other._corrections, other.evaluation_times = None, (None, {}), []
        other._direct = None
        return other

    @property
    def error_estimates(self) -> dict[float, ErrorEstimate]:
        """``{frequency: ErrorEstimate}`` of the model's response at p0 (empty unless built
        with ``estimate=True``)."""
        return {f: data.estimate for f, data in self.frequencies.items()
                if data.estimate is not None}

    def initial_parameters(self) -> JointParameters:
        """``{joint: {log10_stiffness, loss_factor, mass}}`` of the model."""
        return self.case.updatable_parameters()

    def has_line_mass(self, joint: str) -> bool:
        """Whether ``joint`` carries a line mass to identify: coplanar joints do; hinges and
        junction members hold their line fixed."""
        jid, member = self.case.updatable_joints()[joint]
        return member is None and self.case.joints[jid].kind == "coplanar"

    def joint_weights(self, freq: FrequencyData) -> dict[str, float]:
        """Per joint, the weight of its energy (J) in E_mod^2 at one measured frequency:
        alpha (1 - r) / E_ref."""
        return {jid: (1.0 - self.r) * a / freq.reference.total for jid, a in self.alpha.items()}

    def evaluate(self, parameters: Mapping[str, Mapping[str, float]],
                 data: Mapping[float, Sequence[np.ndarray]] | None = None) -> Evaluation:
        """:math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and every :math:`E_\\Gamma^2`.

        ``data`` (``{frequency: [values per measured plate]}``, see :meth:`synthetic_data`)
        replaces the measured data by other data on the same points.
        """
        t0 = time.perf_counter()

        def factorise(frequency: float) -> InterfaceFactor:
            freq = self.frequencies[frequency]
            values = freq.data if data is None else data[frequency]
            system = freq.system
            params = channel_parameters(parameters, system.omega)
            blocks = channel_blocks(system.channels, params, self.joint_weights(freq))
            return solve_interface(system, blocks + freq.blocks(values, self.r))

        factors = dict(zip(self.frequencies, self._map(factorise, self.frequencies)))
        interfaces = {frequency: factor.s for frequency, factor in factors.items()}
        evaluation = self.evaluation_at(parameters, interfaces, data)
        if data is None:
            self._last = (JointParameters.of(parameters), factors)
            self.evaluation_times.append(time.perf_counter() - t0)
        return evaluation

    def _map(self, function: Callable[[float], _R], frequencies: Iterable[float]) -> list[_R]:
        """``[function(f) for f in frequencies]`` on the problem's threads."""
        return thread_map(function, list(frequencies), self.threads)

    def evaluation_at(self, parameters: Mapping[str, Mapping[str, float]],
                      interfaces: dict[float, np.ndarray],
                      data: Mapping[float, Sequence[np.ndarray]] | None = None) -> Evaluation:
        """The :class:`~updating.inverse.problem_data.Evaluation` of given interface unknowns
        ``{frequency: S}`` (for instance a :class:`~updating.inverse.correction.JointCorrection`'s
        minimisers): residuals, misfits and costs, no solve."""
        residuals = dict.fromkeys(self.joints, 0.0)
        misfits = {}
        for frequency, freq in self.frequencies.items():
            values = freq.data if data is None else data[frequency]
            s = interfaces[frequency]
            params = channel_parameters(parameters, freq.system.omega)
            for pid, value in freq.misfits(s, values).items():
                misfits[pid] = misfits.get(pid, 0.0) + value
            for jid, value in joint_residuals(freq.system.channels, params, s,
                                                 freq.reference.total).items():
                residuals[jid] += value
        e_int = sum(self.alpha[jid] * value for jid, value in residuals.items())
        e_mes = sum(misfits.values())
        e_mod = (1.0 - self.r) * e_int + self.r * e_mes
        if not math.isfinite(e_mod):  # an optimiser fed NaN would wander silently
            raise NumericalError(
                "E_mod^2 is not finite at " + ", ".join(
                    f"{j} log10 k {p['log10_stiffness']:.3g}" for j, p in parameters.items())
                + f" (residuals {residuals}, E_mes^2 {e_mes})")
        return Evaluation(e_mod, e_int, e_mes, residuals, interfaces, misfits)

    def cost(self, parameters: Mapping[str, Mapping[str, float]],
             data: Mapping[float, Sequence[np.ndarray]] | None = None) -> float:
        """:math:`E_{mod}^2(p)` (the reduced cost function)."""
        return self.evaluate(parameters, data).e_mod

    def neighbourhood(self, joint: str) -> tuple[list[str], list[str]]:
        """``(joints, plates)`` around ``joint``: its plates (a junction member's: every member
        plate of its line) and every updatable joint of theirs."""
        if self._neighbourhoods is None:
            plates_of = {name: set(self.case.joints[jid].plates)
                         for name, (jid, _) in self.case.updatable_joints().items()}
            joints_of = {}
            for jid, plates in plates_of.items():
                for plate in plates:
                    joints_of.setdefault(plate, []).append(jid)
            order = {jid: i for i, jid in enumerate(self.joints)}
            self._neighbourhoods = {
                jid: (sorted({j for p in plates for j in joints_of[p]}, key=order.get),
                      sorted(plates))
                for jid, plates in plates_of.items()}
        return self._neighbourhoods[joint]

    def neighbourhood_cost(self, joint: str, residuals: Mapping[str, float],
                           misfits: Mapping[str, float]) -> float:
        r"""The part of :math:`E_{mod}^2` that lives around ``joint``:
        :math:`(1-r)\sum_{\Gamma\in N}\alpha_\Gamma E_\Gamma^2 + r\sum_{i\in N}E_{mes,i}^2` over
        the joints and plates of :meth:`neighbourhood`, from per-joint residuals and per-plate
        misfits (an :class:`~updating.inverse.problem_data.Evaluation`'s, or a localisation
        step's)."""
        joints, plates = self.neighbourhood(joint)
        return ((1.0 - self.r) * sum(self.alpha[j] * residuals[j] for j in joints)
                + self.r * sum(misfits.get(p, 0.0) for p in plates))

    def correction(self, parameters: Mapping[str, Mapping[str, float]],
                   joint: str) -> JointCorrection:
        """:math:`E_{mod}^2` as a function of one joint's parameters, the others at
        ``parameters``: a :class:`~updating.inverse.correction.JointCorrection`, condensed once
        on that joint (it reuses the factorisations of the last evaluation when it was at
        ``parameters``, and the joint's condensation when it was made from them: the
        re-corrections that end a run and the identification intervals after it condense at
        the same final parameters)."""
        key, kept = self._corrections
        if key != parameters:
            key, kept = JointParameters.of(parameters), {}
            self._corrections = (key, kept)
        if joint not in kept:
            if self._last is None or self._last[0] != parameters:
                self.evaluate(parameters)
            if len(kept) >= MAX_KEPT_CORRECTIONS:
                kept.pop(next(iter(kept)))
            kept[joint] = JointCorrection(self, parameters, joint, self._last[1])
        return kept[joint]

    def synthetic_data(self, parameters: Mapping[str, Mapping[str, float]], noise: float,
                       seed: int = 0, realisations: int = 4, discretisation: bool = False
                       ) -> list[dict[float, list[np.ndarray]]]:
        r"""Measured values of synthetic experiments on the measured points.

        The data are the model's own prediction at ``parameters`` (the interface solution of
        :math:`E_{int}^2` alone) times :math:`1 + e`, :math:`e\sim U[-noise, noise]`: what the
        measurements would be if the model were right and only the stated noise were at work.
        With ``discretisation``, the prediction is first moved by the model's discretisation
        error at the measured points, estimated at p0 by the enriched solve
        (:math:`w^+ - w_h`, :func:`solver.estimate.enriched_solve`): what they would be if the
        model's joints were right and its discretisation and the noise were at work (the
        error changes little with the joint parameters). Returns ``realisations`` dicts
        ``{frequency: [values per measured plate]}``.
        """
        rng = np.random.default_rng(seed)
        at_start = parameters == self.initial_parameters()  # solved in the set-up already

        if at_start:
            interfaces = {f: freq.initial_s for f, freq in self.frequencies.items()}
        else:
            interfaces = {f: factor.s for f, factor in self.direct_factors(parameters).items()}
        predictions = {f: [op.residual(interfaces[f]) for op in freq.operators]
                       for f, freq in self.frequencies.items()}
        if discretisation:
            predictions = {f: [w + d for w, d in zip(plates, self.frequencies[f].discretisation)]
                           if self.frequencies[f].discretisation is not None else plates
                           for f, plates in predictions.items()}
        return [{f: [w * (1.0 + rng.uniform(-noise, noise, w.shape)) for w in plates]
                 for f, plates in predictions.items()}
                for _ in range(realisations)]

    def release_factors(self) -> None:
        """Forget the last evaluation's factorisations (and the model response's): the
        condensations made from them keep what they need. The next correction evaluates
        again."""
        self._last, self._direct = None, None

    def direct_factors(self, parameters: Mapping[str, Mapping[str, float]]
                       ) -> dict[float, InterfaceFactor]:
        """Per frequency, the factorised model response (r = 0) at ``parameters``
        (:func:`direct_interface`). The last parameters' are kept (the noise floor of a
        localisation and the confidence intervals after the last one ask for the same) when
        their factors are small: a large structure's would double the peak memory."""
        key = JointParameters.of(parameters)
        if self._direct is not None and self._direct[0] == key:
            return self._direct[1]

        def factorise(frequency: float) -> InterfaceFactor:
            return direct_factor(self.frequencies[frequency].system, parameters, self.alpha)

        factors = dict(zip(self.frequencies, self._map(factorise, self.frequencies)))
        entries = sum(f.lu.nnz for f in factors.values())  # not .L, .U: they copy the factors
        self._direct = (key, factors) if entries <= KEPT_FACTOR_ENTRIES else None
        return factors

    def noise_floor(self, parameters: Mapping[str, Mapping[str, float]], noise: float,
                    seed: int = 0, realisations: int = 4) -> tuple[dict[str, float], float]:
        r"""What a model with right joints would show under measurement noise and its own
        discretisation error: ``({joint: E_Gamma^2}, E_mod^2)``, the means over the draws of
        :meth:`floor_draws`, the levels below which a joint's residual, and the cost, cannot
        be told from noise and discretisation error."""
        draws, e_mod = self.floor_draws(parameters, noise, seed, realisations)
        return dict(zip(self.joints, draws.mean(axis=1))), float(e_mod.mean())

    def floor_draws(self, parameters: Mapping[str, Mapping[str, float]], noise: float,
                    seed: int = 0, realisations: int = 4) -> tuple[np.ndarray, np.ndarray]:
        r"""The residuals and cost of a model with right joints in ``realisations`` synthetic
        experiments (:meth:`synthetic_data`: the prediction moved by the discretisation error
        the enriched solve estimates, then the noise): ``(draws, e_mod)``, ``draws[j, k]`` the
        :math:`E_\Gamma^2` of joint ``self.joints[j]`` in experiment k (summed over the
        frequencies), ``e_mod[k]`` its :math:`E_{mod}^2`. Without the enriched solve (too large
        for the machine, :attr:`~updating.inverse.problem_data.FrequencyData.no_discretisation`)
        the noise alone. The draws of one frequency are normalised by the mean of their norms
        :math:`\|\tilde u_k\|^2` (which differ by about noise / sqrt(points)) rather than each
        by its own, so that one factorisation of the interface problem serves them all.
        """
        draws = self.synthetic_data(parameters, noise, seed, realisations, discretisation=True)

        def floor(frequency: float) -> tuple[np.ndarray, np.ndarray]:
            freq = self.frequencies[frequency]
            system = freq.system
            data = [draw[frequency] for draw in draws]
            norm = np.mean([freq.norms(values) for values in data], axis=0)
            params = channel_parameters(parameters, system.omega)
            blocks = channel_blocks(system.channels, params, self.joint_weights(freq))
            factor = solve_interface(system, blocks + freq.blocks(data[0], self.r, norm))
            offsets = [[b.offset for b in blocks + freq.blocks(values, self.r, norm)]
                       for values in data]
            columns = factor.resolve(offsets).T  # the draws' interface unknowns, by columns
            at_draws = joint_residuals(system.channels, params, columns, freq.reference.total)
            by_plate = [np.column_stack(plate) for plate in zip(*data)]  # points x draws
            return (np.array([at_draws[jid] for jid in self.joints]),
                    sum(freq.misfits(columns, by_plate, norm).values()))

        alpha = np.array([self.alpha[jid] for jid in self.joints])
        residuals, e_mod = np.zeros((len(self.joints), realisations)), np.zeros(realisations)
        for at_frequency, e_mes in self._map(floor, self.frequencies):
            residuals += at_frequency
            e_mod += (1.0 - self.r) * alpha @ at_frequency + self.r * e_mes
        return residuals, e_mod

    def field(self, frequency: float, interface: np.ndarray) -> dict[str, np.ndarray]:
        """Plate amplitudes for interface unknowns S (to plot or export the updated field)."""
        return self.frequencies[frequency].system.plate_amplitudes(interface)

    def evaluation_seconds(self, parameters: Mapping[str, Mapping[str, float]],
                           joint: str | None = None, repeats: int = 3) -> float:
        """Best wall time of one :meth:`cost` evaluation at ``parameters`` (all frequencies,
        a sparse factorisation each), or with ``joint``, of one evaluation of its condensed
        :class:`~updating.inverse.correction.JointCorrection` (built once, untimed), as during
        a correction."""
        if joint is not None:
            local = self.correction(parameters, joint)
            value = parameters[joint]["log10_stiffness"]
        best = math.inf
        for i in range(repeats):
            t0 = time.perf_counter()
            if joint is None:
                self.cost(parameters)
            else:  # a new value each time: the condensation keeps the values it has solved
                local.cost(log10_stiffness=value + 0.1 * (i + 1))
            best = min(best, time.perf_counter() - t0)
        return best

    @property
    def factorisation_seconds(self) -> dict[float, float]:
        """Per frequency: the time to assemble and factorise the full admissibility system (plate
        blocks and their transfer operators, interface layout), done once in the set-up."""
        return {f: sum(d.system.timings.values()) for f, d in self.frequencies.items()}

    @property
    def reference_energies(self) -> dict[float, float]:
        return {f: d.reference.total for f, d in self.frequencies.items()}

    @property
    def warnings(self) -> tuple[str, ...]:
        """One line each: the description's guard-rail warnings (with ``check``), the condition
        warnings of the plate solves (as ``CaseSolution.warnings``), and the frequencies whose
        floors lack the discretisation error (its enriched solve was not made)."""
        lines = list(self._description_warnings)
        lines += [line for f, d in self.frequencies.items()
                  for line in condition_warnings(d.system.rcond, f)]
        lines += [f"{f:g} Hz: the floors hold the measurement noise only, not the model's "
                  f"discretisation error: {d.no_discretisation}"
                  for f, d in self.frequencies.items() if d.no_discretisation]
        return tuple(lines)

    @property
    def size(self) -> tuple[int, int, int]:
        """``(ray unknowns, interface unknowns, constraints)`` at the first frequency, the ray
        unknowns bending and in-plane (as ``vtcr check`` and ``vtcr solve`` count them)."""
        data = next(iter(self.frequencies.values()))
        return data.system.ray_unknowns, data.system.n_s, data.system.constraints[0].shape[0]


def log_grid(bounds: tuple[float, float], n: int) -> np.ndarray:
    """``n`` equally spaced values of log10 k over ``bounds``."""
    lo, hi = bounds
    return np.linspace(lo, hi, n) if n > 1 else np.array([0.5 * (lo + hi)])


def cost_curve(problem: ModifiedProblem, parameters: Mapping[str, Mapping[str, float]],
               joint: str, values: Iterable[float], on_point: Callable[[], object] | None = None
               ) -> list[tuple[float, float, float, float, float]]:
    """E_mod^2, E_int^2, E_mes^2 and E_Gamma^2 of ``joint`` against its log10 k.

    The problem is condensed once on the joint (:meth:`ModifiedProblem.correction`); each
    point is then a small dense solve. ``on_point()`` is called after each value (progress
    display).
    """
    local = problem.correction(parameters, joint)
    rows = []
    for value in values:
        ev = local.evaluate(log10_stiffness=float(value))
        rows.append((float(value), ev.e_mod, ev.e_int, ev.e_mes, ev.residuals[joint]))
        if on_point:
            on_point()
    return rows

