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
:mod:`updating.inverse.weights`) is the mean over the M measured values of their plate's misfit relative
to its own measured field (:math:`m_p` values on plate p): under relative noise a plate far
from the load, whose field is weak, then counts as much as the loaded one, and a joint there is
judged by its own data rather than by a fraction of the whole structure's. With several
frequencies the costs are summed, each with its own fixed normalisation (its :math:`E_{ref}`
and :math:`\|\tilde u\|^2`).

Everything that does not depend on p — plate factorisations, transfer operators, residual
samples of each joint channel, the measurement operator of each plate and :math:`E_{ref}`
(fixed at the initial parameters) — is built once in :class:`ModifiedProblem`, each piece over
the interface unknowns of its own plates. One evaluation weighs the channel samples by the
parameters and factorises the sparse interface problem (:mod:`solver.interface`). While one
joint is corrected, :class:`JointCorrection` condenses the problem on that joint's residual
samples once, and each cost evaluation is then a dense solve of their size.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from assembly.types import JointParameters
from solver.channels import channel_blocks, joint_residuals
from solver.errors import NumericalError, condition_warnings
from solver.estimate import enriched_plates, estimate_error
from solver.guards import check_description
from solver.interface import Block, JointCondensation, squared_norm
from solver.joint_rules import channel_parameters
from solver.plate import particular_field
from solver.rays import ray_field
from solver.substructure import (
    AssemblySystem,
    ReferenceEnergy,
    build_assembly_system,
    solve_assembly,
    solve_interface,
)
from updating.executor import thread_map
from updating.inverse.weights import scale_free_weights

__all__ = ["ModifiedProblem", "JointCorrection", "Evaluation", "FrequencyData",
           "channel_parameters", "with_joint", "direct_factor", "direct_interface", "direct_amplitudes",
           "PARAMETER_NAMES", "PARAMETER_BOUNDS", "SMALLEST_MASS"]

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


def direct_factor(system, parameters, alpha):
    r"""The factorised model response (r = 0): minimise the weighted joint error
    :math:`\sum\alpha_\Gamma e_\Gamma^2` under admissibility, as
    :func:`solver.substructure.solve_assembly` does, on an already built system."""
    params = channel_parameters(parameters, system.omega)
    return solve_interface(system, channel_blocks(system.channels, params, alpha))


def direct_interface(system, parameters, alpha):
    """Interface unknowns S of the model response (:func:`direct_factor`)."""
    return direct_factor(system, parameters, alpha).s


def direct_amplitudes(system, parameters, alpha):
    """Plate ray amplitudes of the model response (r = 0) for joint ``parameters``."""
    return system.plate_amplitudes(direct_interface(system, parameters, alpha))


@dataclass(frozen=True)
class Evaluation:
    """E_mod^2 and its parts at one parameter set (dimensionless; sums over frequencies)."""

    e_mod: float
    e_int: float
    e_mes: float
    residuals: dict  # joint -> E_Gamma^2
    interface: dict  # frequency -> S
    misfits: dict  # measured plate -> its part of E_mes^2


def _norm2(values):
    return sum(squared_norm(v) for v in values)


def _norms(values, per_plate):
    r"""Per measured plate, what its squared misfit is divided by: every plate the whole
    data's :math:`\|\tilde u\|^2` (``[updating] misfit = "global"``), or its own
    :math:`\|\tilde u_p\|^2 M/m_p` (``"per_plate"``: :math:`m_p` of the :math:`M` measured
    values on plate p), so that :math:`E_{mes}^2` is the mean over the measured values of
    their plate's relative misfit: under relative noise :math:`\pm\varepsilon` it is about
    :math:`\varepsilon^2/3` whatever the number of plates (``docs/updating.md``, section 2)."""
    if per_plate:
        total = sum(np.size(v) for v in values)
        return np.array([float(np.vdot(v, v).real) * total / max(np.size(v), 1)
                         for v in values])
    return np.full(len(values), _norm2(values))


@dataclass
class FrequencyData:
    """One measured frequency of a :class:`ModifiedProblem` (``problem.frequencies[f]``): its
    assembly system and, per measured plate, the measured ``w`` as a Block over the plate's
    interface unknowns with the measured values, the normalisation of its misfit and the
    model's discretisation error there."""

    system: AssemblySystem
    reference: ReferenceEnergy  # E_ref of the model's response at p0
    plates: list  # measured plates
    operators: list  # Block per measured plate: w at its points per unit S, and at S = 0
    data: list  # measured values per measured plate
    initial_s: np.ndarray  # the model response's S at p0 (the E_ref solve)
    estimate: object = None  # solver.estimate.ErrorEstimate of that response, if asked for
    per_plate: bool = False  # each plate's misfit relative to its own data ([updating] misfit)
    discretisation: list | None = None  # per measured plate, w+ - w_h at its points (p0)
    no_discretisation: str = ""  # why ``discretisation`` is None (the enriched solve's cost)

    def norms(self, data=None):
        """Per measured plate, what its squared misfit is divided by (:func:`_norms`), for
        measured values ``data`` (default the measured ones)."""
        return _norms(self.data if data is None else data, self.per_plate)

    def scale(self, r, data=None, norm=None):
        r"""Per measured plate, :math:`\sqrt{r/N_p}`: the weight of its measurement rows for
        measured values ``data`` (default the measured ones), :math:`N_p` the plates'
        ``norm`` (default :meth:`norms` of the data)."""
        return np.sqrt(r / (self.norms(data) if norm is None else norm))

    def value_scale(self, r):
        """:meth:`scale` of the measured data, one entry per measured value."""
        return np.repeat(self.scale(r), [len(v) for v in self.data])

    def blocks(self, data, r, norm=None):
        r"""The measurement term :math:`r E_{mes}^2` as Blocks, for measured values ``data``
        normalised by ``norm`` (per plate; default :meth:`norms` of the data)."""
        scales = self.scale(r, data, norm)
        return [Block(op.index, scale * op.matrix, scale * (op.offset - v))
                for op, v, scale in zip(self.operators, data, scales)]

    def misfits(self, s, data, norm=None):
        """Per measured plate, its part of :math:`E_{mes}^2` at interface unknowns ``s`` for
        measured values ``data`` (normalised by ``norm``, default :meth:`norms` of the
        data). With ``s`` of shape (n_s, k) and each plate's values of shape (points, k), one
        part per column (``norm`` given: the columns share it)."""
        norm = self.norms(data) if norm is None else norm
        return {pid: squared_norm(op.residual(s) - v) / n
                for pid, op, v, n in zip(self.plates, self.operators, data, norm)}


def _frequency_data(case, resolution, estimate, discretisation, task):
    """One measured frequency's :class:`FrequencyData` (a task of :class:`ModifiedProblem`'s
    executor): its system, :math:`E_{ref}` at p0, the measurement operators and, if
    ``estimate``, the discretisation error estimate of the model's response at p0; with
    ``discretisation``, that response's error at the measured points (the floors' and the
    intervals'). Both come from one enriched solve, made only when one of them is asked for."""
    frequency, measured_plates = task
    system = build_assembly_system(case, frequency, resolution)
    initial = solve_assembly(case, frequency, resolution, system=system)  # E_ref at p0
    enriched = (enriched_plates(case, frequency, resolution) if estimate or discretisation
                else None)
    error = estimate_error(case, initial, resolution, enriched) if estimate else None
    finer, reason, _ = enriched if discretisation else (None, "", 0.0)
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
                         error,
                      case.updating.misfit_kind == "per_plate",
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
    resolution : float, optional
        Discretisation resolution (default ``[discretisation] resolution``).
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

    def __init__(self, case, measurements, r=None, resolution=None, executor=None,
                 estimate=False, threads=1, discretisation=True, check=True):
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

    def _scale_free_weights(self):
        """:func:`updating.inverse.weights.scale_free_weights` of the model at p0 and the measured
        points, at the stated noise and ``[updating] balance``."""
        case = self.case
        plates = {name: case.joints[jid].plates
                  for name, (jid, _) in case.updatable_joints().items()}
        return scale_free_weights(
            plates, [freq.reference.plates for freq in self.frequencies.values()],
            [sum(np.size(v) for v in freq.data) for freq in self.frequencies.values()],
            case.measurement.noise, case.updating.balance, case.updatable_alpha())

    def with_data(self, data):
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
    def error_estimates(self):
        """``{frequency: ErrorEstimate}`` of the model's response at p0 (empty unless built
        with ``estimate=True``)."""
        return {f: data.estimate for f, data in self.frequencies.items()
                if data.estimate is not None}

    def initial_parameters(self):
        """``{joint: {log10_stiffness, loss_factor, mass}}`` of the model."""
        return self.case.updatable_parameters()

    def has_line_mass(self, joint):
        """Whether ``joint`` carries a line mass to identify: coplanar joints do; hinges and
        junction members hold their line fixed."""
        jid, member = self.case.updatable_joints()[joint]
        return member is None and self.case.joints[jid].kind == "coplanar"

    def joint_weights(self, freq: FrequencyData) -> dict[str, float]:
        """Per joint, the weight of its energy (J) in E_mod^2 at one measured frequency:
        alpha (1 - r) / E_ref."""
        return {jid: (1.0 - self.r) * a / freq.reference.total for jid, a in self.alpha.items()}

    def evaluate(self, parameters, data=None) -> Evaluation:
        """:math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and every :math:`E_\\Gamma^2`.

        ``data`` (``{frequency: [values per measured plate]}``, see :meth:`synthetic_data`)
        replaces the measured data by other data on the same points.
        """
        t0 = time.perf_counter()

        def factorise(frequency):
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

    def _map(self, function, frequencies):
        """``[function(f) for f in frequencies]`` on the problem's threads."""
        return thread_map(function, list(frequencies), self.threads)

    def evaluation_at(self, parameters, interfaces, data=None) -> Evaluation:
        """The :class:`Evaluation` of given interface unknowns ``{frequency: S}`` (for instance
        a :class:`JointCorrection`'s minimisers): residuals, misfits and costs, no solve."""
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

    def cost(self, parameters, data=None) -> float:
        """:math:`E_{mod}^2(p)` (the reduced cost function)."""
        return self.evaluate(parameters, data).e_mod

    def neighbourhood(self, joint):
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

    def neighbourhood_cost(self, joint, residuals, misfits):
        r"""The part of :math:`E_{mod}^2` that lives around ``joint``:
        :math:`(1-r)\sum_{\Gamma\in N}\alpha_\Gamma E_\Gamma^2 + r\sum_{i\in N}E_{mes,i}^2` over
        the joints and plates of :meth:`neighbourhood`, from per-joint residuals and per-plate
        misfits (an :class:`Evaluation`'s, or a localisation step's)."""
        joints, plates = self.neighbourhood(joint)
        return ((1.0 - self.r) * sum(self.alpha[j] * residuals[j] for j in joints)
                + self.r * sum(misfits.get(p, 0.0) for p in plates))

    def correction(self, parameters, joint):
        """:math:`E_{mod}^2` as a function of one joint's parameters, the others at
        ``parameters``: a :class:`JointCorrection`, condensed once on that joint (it reuses the
        factorisations of the last evaluation when it was at ``parameters``, and the joint's
        condensation when it was made from them: the re-corrections that end a run and the
        identification intervals after it condense at the same final parameters)."""
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

    def synthetic_data(self, parameters, noise, seed=0, realisations=4, discretisation=False):
        r"""Measured values of synthetic experiments on the measured points.

        The data are the model's own prediction at ``parameters`` (the interface solution of
        :math:`E_{int}^2` alone) times :math:`1 + e`, :math:`e\sim U[-noise, noise]`: what the
        measurements would be if the model were right and only the stated noise were at work.
        With ``discretisation``, the prediction is first moved by the model's discretisation
        error at the measured points, estimated at p0 by the enriched solve
        (:math:`w^+ - w_h`, :func:`solver.estimate.enriched_plates`): what they would be if the
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

    def release_factors(self):
        """Forget the last evaluation's factorisations (and the model response's): the
        condensations made from them keep what they need. The next correction evaluates
        again."""
        self._last, self._direct = None, None

    def direct_factors(self, parameters):
        """Per frequency, the factorised model response (r = 0) at ``parameters``
        (:func:`direct_interface`). The last parameters' are kept (the noise floor of a
        localisation and the confidence intervals after the last one ask for the same) when
        their factors are small: a large structure's would double the peak memory."""
        key = JointParameters.of(parameters)
        if self._direct is not None and self._direct[0] == key:
            return self._direct[1]

        def factorise(frequency):
            return direct_factor(self.frequencies[frequency].system, parameters, self.alpha)

        factors = dict(zip(self.frequencies, self._map(factorise, self.frequencies)))
        entries = sum(f.lu.nnz for f in factors.values())  # not .L, .U: they copy the factors
        self._direct = (key, factors) if entries <= KEPT_FACTOR_ENTRIES else None
        return factors

    def noise_floor(self, parameters, noise, seed=0, realisations=4):
        r"""What a model with right joints would show under measurement noise and its own
        discretisation error: ``({joint: E_Gamma^2}, E_mod^2)``, the means over the draws of
        :meth:`floor_draws`, the levels below which a joint's residual, and the cost, cannot
        be told from noise and discretisation error."""
        draws, e_mod = self.floor_draws(parameters, noise, seed, realisations)
        return dict(zip(self.joints, draws.mean(axis=1))), float(e_mod.mean())

    def floor_draws(self, parameters, noise, seed=0, realisations=4):
        r"""The residuals and cost of a model with right joints in ``realisations`` synthetic
        experiments (:meth:`synthetic_data`: the prediction moved by the discretisation error
        the enriched solve estimates, then the noise): ``(draws, e_mod)``, ``draws[j, k]`` the
        :math:`E_\Gamma^2` of joint ``self.joints[j]`` in experiment k (summed over the
        frequencies), ``e_mod[k]`` its :math:`E_{mod}^2`. Without the enriched solve (too large
        for the machine, :attr:`FrequencyData.no_discretisation`) the noise alone. The draws of one
        frequency are normalised by the mean of their norms :math:`\|\tilde u_k\|^2` (which
        differ by about noise / sqrt(points)) rather than each by its own, so that one
        factorisation of the interface problem serves them all.
        """
        draws = self.synthetic_data(parameters, noise, seed, realisations, discretisation=True)

        def floor(frequency):
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

    def field(self, frequency, interface):
        """Plate amplitudes for interface unknowns S (to plot or export the updated field)."""
        return self.frequencies[frequency].system.plate_amplitudes(interface)

    def evaluation_seconds(self, parameters, joint=None, repeats=3):
        """Best wall time of one :meth:`cost` evaluation at ``parameters`` (all frequencies,
        a sparse factorisation each), or with ``joint``, of one evaluation of its condensed
        :class:`JointCorrection` (built once, untimed), as during a correction."""
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
    def factorisation_seconds(self):
        """Per frequency: the time to assemble and factorise the full admissibility system (plate
        blocks and their transfer operators, interface layout), done once in the set-up."""
        return {f: sum(d.system.timings.values()) for f, d in self.frequencies.items()}

    @property
    def reference_energies(self):
        return {f: d.reference.total for f, d in self.frequencies.items()}

    @property
    def warnings(self):
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
    def size(self):
        """``(ray unknowns, interface unknowns, constraints)`` at the first frequency."""
        data = next(iter(self.frequencies.values()))
        n_rays = sum(b.n_dof for b in data.system.bases.values())
        return n_rays, data.system.n_s, data.system.constraints[0].shape[0]


class JointCorrection:
    """:math:`E_{mod}^2` as a function of one joint's parameters (the others fixed).

    Built once per correction from the factorisations at the current parameters: per
    frequency, a :class:`solver.interface.JointCondensation` on the joint's residual samples,
    so that each :meth:`cost` is a dense solve of that size, whatever the size of the
    structure.
    """

    def __init__(self, problem, parameters, joint, factors):
        self.problem = problem
        self.joint = joint
        self.parameters = JointParameters.of(parameters)
        neighbourhood = problem.neighbourhood(joint)

        def condense(frequency):
            freq = problem.frequencies[frequency]
            system = freq.system
            kappa = problem.joint_weights(freq)[joint]
            params = channel_parameters(parameters, system.omega)
            channels = [ch for ch in system.channels if ch.name == joint]
            factor = factors[frequency]
            # the measurement blocks come last in the factorised problem (evaluate)
            measured = factor.block_rows[-len(freq.operators):]
            condensation = JointCondensation(
                factor, [(ch.load, ch.kinematic, kappa, params[joint, ch.kind], ch.crossover)
                         for ch in channels], keep=slice(measured[0].start, measured[-1].stop))
            return (system.omega, [ch.kind for ch in channels], condensation)

        self._frequencies = dict(zip(problem.frequencies,
                                     problem._map(condense, problem.frequencies)))
        self._neighbourhood = {f: self._local_data(freq, neighbourhood)
                               for f, freq in problem.frequencies.items()}

    def condensation(self, frequency):
        """The joint's :class:`solver.interface.JointCondensation` at ``frequency``; it keeps
        the samples' response to the measured values (``kept_rows``, one row per value)."""
        return self._frequencies[frequency][2]

    @staticmethod
    def _local_data(freq, neighbourhood):
        """The neighbourhood's channels and measured plates at one frequency, the interface
        unknowns they see, and each measured plate's misfit norm (:meth:`FrequencyData.norms`)."""
        joints, plates = neighbourhood
        channels = [ch for ch in freq.system.channels if ch.name in joints]
        measured = [(pid, op, v) for pid, op, v in zip(freq.plates, freq.operators, freq.data)
                    if pid in plates]
        index = np.unique(np.concatenate([ch.kinematic.index for ch in channels]
                                         + [op.index for _, op, _ in measured]))
        norms = dict(zip(freq.plates, freq.norms()))
        return freq, channels, measured, index, norms

    def _channels(self, values):
        """Per frequency, the joint's channel parameters with ``values`` set."""
        trial = with_joint(self.parameters, self.joint, **values)
        for frequency, (omega, kinds, condensation) in self._frequencies.items():
            params = channel_parameters({self.joint: trial[self.joint]}, omega)
            yield frequency, condensation, [params[self.joint, kind] for kind in kinds]

    def cost(self, **values):
        """:math:`E_{mod}^2` with the joint's ``log10_stiffness`` / ``loss_factor`` / ``mass``
        set to ``values`` (the others as in the base parameters)."""
        total = sum(condensation.cost(params) for _, condensation, params in self._channels(values))
        if not math.isfinite(total):
            raise NumericalError(f"E_mod^2 is not finite at joint {self.joint} {values}")
        return total

    def neighbourhood_cost(self, **values):
        """:meth:`ModifiedProblem.neighbourhood_cost` of the joint at ``values``: only the
        interface unknowns that its neighbourhood's channels and measured plates see are
        updated, so the cost does not grow with the structure."""
        joints, plates = self.problem.neighbourhood(self.joint)
        residuals, misfits = dict.fromkeys(joints, 0.0), dict.fromkeys(plates, 0.0)
        trial = with_joint(self.parameters, self.joint, **values)
        for frequency, condensation, params in self._channels(values):
            freq, channels, measured, index, norm = self._neighbourhood[frequency]
            s = condensation.interface(params, index)
            all_params = channel_parameters(trial, freq.system.omega)
            e_ref = freq.reference.total
            for ch in channels:
                residuals[ch.name] += ch.energy(s, all_params[ch.name, ch.kind]) / e_ref
            for pid, op, v in measured:
                misfits[pid] += _norm2([op.residual(s) - v]) / norm[pid]
        return self.problem.neighbourhood_cost(self.joint, residuals, misfits)

    def evaluate(self, **values) -> Evaluation:
        """Every residual and misfit at the joint's ``values``, from the condensed minimisers
        (no factorisation): what a localisation would find there, without its noise floors."""
        interfaces = {f: condensation.interface(params)
                      for f, condensation, params in self._channels(values)}
        return self.problem.evaluation_at(
            with_joint(self.parameters, self.joint, **values), interfaces)


def log_grid(bounds, n):
    """``n`` equally spaced values of log10 k over ``bounds``."""
    lo, hi = bounds
    return np.linspace(lo, hi, n) if n > 1 else np.array([0.5 * (lo + hi)])


def cost_curve(problem, parameters, joint, values, on_point=None):
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

