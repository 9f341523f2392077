r"""Sizes of an assembly's VTCR problem and the memory and time its solves take, before any work.

Everything is counted from the description, without building a matrix: ray unknowns per
plate (the resolution rule), interface unknowns per joint (:func:`interface_function_count`)
and junction corner, residual samples per joint (its Gauss rule), and from them the entries of
the sparse augmented interface matrix (:mod:`solver.interface`):

.. math:: \mathrm{nnz} = \sum_b \mathrm{rows}_b\,|I_b|\ (\times 2) + 2\,\mathrm{nnz}(G) + n_\rho ,

where :math:`I_b` are the interface unknowns a block's plates see. The factors of that matrix
are the dominant cost, and how they grow depends on the path :func:`solver.interface.
factorise_interface` takes:

- **by groups** (:class:`solver.multifrontal.GroupedLDL`, from
  :data:`solver.interface.GROUPED_MIN_SIZE` variables on): fill / nnz = 2.08, 2.41, 2.70 on
  the :math:`N\times N` grids of plates (:math:`P = N^2`) for N = 6, 8, 10, i.e.
  :math:`0.58\ln P` (the separators are lines of joints; the factors are each front's
  :math:`L`, packed, and :math:`M = D^{-1}L^{-1}F_{12}`); factorisation 0.14, 0.33, 0.67 s
  for 1.3e6, 2.9e6, 5.4e6 entries, :math:`\mathrm{fill}^{1.10}`; peak memory of ``vtcr solve
  --no-estimate`` 0.16, 0.21, 0.29 GB, i.e. 31 bytes per factor entry above a start-up of
  0.12 GB (the front being factorised and the contributions waiting for their parents besides
  the factors; measured on a 2-core AMD EPYC, one BLAS thread);
- **SuperLU** (COLAMD ordering; small systems): fill / nnz = 1.6, 3.8, 5.6, 10.1 for
  N = 2, 4, 6, 10, about :math:`\sqrt P` (pessimistic for chains); about 30 bytes per factor
  entry (complex factors, SuperLU's work space, the matrix and the plate data: 2.0 GB for
  6.8e7 entries at N = 10), and the factorisation time grew like :math:`\mathrm{fill}^{1.22}`
  (0.52 s for 2.8e6 entries, 25.6 s for 6.8e7); both above the same start-up of 0.12 GB
  (the four plates' ``vtcr solve`` peaks at 0.12 GB for 8e4 factor entries).

``vtcr solve`` estimates its discretisation error by an enriched solve, every count times
:data:`solver.estimate.ENRICHMENT`: its memory is that solve's (:func:`solver.estimate.
enriched_size`; 0.43 GB estimated on the 10 x 10 grid, 0.46-0.48 GB measured, 0.49 GB
once a forward solve factorised the square system by SuperLU, 0.32 GB since it factorises it
by groups, :mod:`solver.grouped_lu`, from one copy of its entries).

The memory is the start-up and the larger of those factors and the plates' build
(:data:`BUILD_BYTES_PER_SQUARED_ORDER`), which peaks before the factorisation: the traces of a
moving-line box (orders up to 370) took 112 MB where its factors take 14.

The plates' blocks and transfer operators are counted from the orders of the dense matrices
a build factorises (:data:`CUBED_ORDER_SECONDS`, :data:`MEMBRANE_BLOCK_SECONDS`,
:data:`PLATE_SECONDS`): a solve's estimate is 0.54 to 1.23 times its measured time on the 21
cases of ``bench/bench_sizing.py`` it was fitted to, from one plate to a 12-bay panel with
moving lines (0.41 to 1.03 on folds whose mixed ends move under the rule of
``docs/method.md`` section 10.4: their corner functions cost more than rays).

All on one core of the 2-core reference machine. These are estimates to a factor of about
two, for deciding before a run whether it fits, not measurements.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from assembly.case import Case
from solver.admissibility import factorised_sizes
from solver.in_plane import membrane_bases, membrane_problems
from solver.interface import GROUPED_MIN_SIZE
from solver.layout import interface_layout
from solver.problems import plate_bases, plate_problems

__all__ = ["SizeEstimate", "estimate_size", "available_memory"]

BYTES_PER_FACTOR_ENTRY = 30.0  # SuperLU
START_UP_BYTES = 1.2e8  # the interpreter, the libraries and the description, before any solve
FACTOR_SECONDS = (0.52, 2.8e6, 1.22)  # SuperLU: seconds for a fill, and the exponent of the growth
GROUPED_FILL_PER_LOG_PLATES = 0.58  # factor entries / matrix entries, per ln P
GROUPED_BYTES = 31.0  # per factor entry
GROUPED_FACTOR_SECONDS = (0.14, 1.31e6, 1.10)
CUBED_ORDER_SECONDS = 8.7e-10
"""Seconds per cubed order :math:`n^3` of each dense matrix a build factorises
(:func:`solver.admissibility.factorised_sizes`): its traces, assembly, pivoted QR and transfer
operators, which grow like the rays' count cubed."""
MEMBRANE_BLOCK_SECONDS = 0.014
"""Seconds per distinct in-plane block beyond its cubed order: its edge traces and the corner
functions of its fixed-free corners, costly for small orders."""
PLATE_SECONDS = 0.0015
"""Seconds per plate, shared or not: its loads and the solve of its transfer operator.

The three were fitted (relative least squares) to the plate blocks' time of one solve
(``timings["plates"]``, best of three, one BLAS thread, 2-core Intel Xeon) on 21 cases:
every case of ``cases/`` at its highest frequency, the four plates at 2 kHz, the single plate
at 1 and 3 kHz, the 4 x 4 and 6 x 6 grids and the stiffened panel of
``bench/bench_moving_lines.py`` moving and held at 600 and 2500 Hz and widened to 6 and 12
bays (``bench/bench_sizing.py``). Estimate / time: 0.5 to 1.5 (0.004 s to 0.68 s
measured). One plate per group of identical ones is what makes the 10 x 10 grid's plates
cheap (0.10 s: nine distinct blocks for 100 plates) and a moving-line box dear (0.68 s:
sixteen, of orders up to 370). The constant 0.02 s a plate it replaces (2026-11-27) had them
at 0.23 to 19 times their time: 2.0 s for the grid, 0.22 s for the box."""
BUILD_BYTES_PER_SQUARED_ORDER = 100.0
"""The plates' build's peak per squared order of the matrices it factorises: each block's
edge traces (Gauss points, in number about proportional to the order, times the order) and,
for the in-plane blocks, the traces that identical plates share until the last is built."""
LOCALISATION_SOLVES = 3  # per frequency: modified problem, direct model, the noise draws (one)
PLAN_SECONDS_PER_ENTRY = 1.2e-7
"""``vtcr plan``'s work per joint and frequency per factor entry (its two condensations and its
expected interval), measured with SuperLU on the 6 x 6 and 10 x 10 grids of
``bench/bench_scale.py``."""
GROUPED_PLAN_SECONDS_PER_ENTRY = 6e-8
"""The same through the grouped factorisation: per joint 0.22 s on ``cases/grid_10x10.toml``
(180 joints, 5.4e6 factor entries of :math:`LDL^H` with L packed; the whole plan 44 s) and
0.125 s on ``cases/box_with_wall.toml`` (20 joints, 4.4e5 entries, three frequencies), 2-core
Intel Xeon, 2026-11-27. It was 1.2e-7 while each joint recomputed the injected power of every
plate (the grid's plan 93 s, 135 s on the 2-core AMD EPYC)."""
PLAN_SOLVES = 3  # per frequency: the model response, the modified problem and the model again


@dataclass(frozen=True)
class SizeEstimate:
    """Unknown counts of one frequency and the estimated cost of ``solve`` and ``update``."""

    frequency: float
    plates: int
    joints: int
    ray_unknowns: int
    interface_unknowns: int
    constraints: int
    residual_samples: int
    matrix_entries: int
    frequencies: int
    max_steps: int
    channels: int = 0  # updatable joints (a junction's finite members each)
    factorised: tuple[tuple[int, ...], tuple[int, ...]] = ((), ())
    """The orders of the dense bending and in-plane matrices a build factorises
    (:func:`solver.admissibility.factorised_sizes`; :func:`estimate_size` counts them, and
    without them the plates cost :data:`PLATE_SECONDS` each only)."""

    @property
    def grouped(self) -> bool:
        """Factorised by groups (:data:`solver.interface.GROUPED_MIN_SIZE` variables or more),
        else by SuperLU."""
        return (self.residual_samples + self.interface_unknowns + self.constraints
                >= GROUPED_MIN_SIZE)

    @property
    def factor_entries(self) -> float:
        r"""Entries of the interface problem's factors: the matrix entries times
        :math:`0.58\ln P` by groups, :math:`\sqrt P` by SuperLU (module docstring)."""
        fill = (GROUPED_FILL_PER_LOG_PLATES * math.log(self.plates) if self.grouped
                else math.sqrt(self.plates))
        return self.matrix_entries * fill

    @property
    def build_bytes(self) -> float:
        """The plates' build at its peak: :data:`BUILD_BYTES_PER_SQUARED_ORDER` times the sum
        of the squared orders of the matrices it factorises."""
        bending, in_plane = self.factorised
        return BUILD_BYTES_PER_SQUARED_ORDER * sum(float(n) ** 2 for n in bending + in_plane)

    @property
    def solve_bytes(self) -> float:
        """The start-up and the larger of the plates' build and the interface factors: the
        build's traces are freed before the interface problem is factorised."""
        per_entry = GROUPED_BYTES if self.grouped else BYTES_PER_FACTOR_ENTRY
        return START_UP_BYTES + max(self.build_bytes, per_entry * self.factor_entries)

    @property
    def factorisation_seconds(self) -> float:
        t, fill, power = GROUPED_FACTOR_SECONDS if self.grouped else FACTOR_SECONDS
        return t * (self.factor_entries / fill) ** power

    @property
    def plate_seconds(self) -> float:
        r"""The plates' blocks and transfer operators:
        :math:`c_3\sum n^3 + c_m N_m + c_p P` over the factorised orders :math:`n`, the
        :math:`N_m` distinct in-plane blocks and the :math:`P` plates
        (:data:`CUBED_ORDER_SECONDS`, :data:`MEMBRANE_BLOCK_SECONDS`, :data:`PLATE_SECONDS`)."""
        bending, in_plane = self.factorised
        return (CUBED_ORDER_SECONDS * sum(float(n) ** 3 for n in bending + in_plane)
                + MEMBRANE_BLOCK_SECONDS * len(in_plane) + PLATE_SECONDS * self.plates)

    @property
    def solve_seconds(self) -> float:
        return self.plate_seconds + self.factorisation_seconds

    def update_seconds(self, enriched: SizeEstimate | None = None) -> float:
        """At most ``2 max_steps + 1`` localisations (accepted or undone corrections) after the
        set-up: per frequency a solve and, with ``enriched`` (the estimate of the error
        estimate's enriched solve), two solves of about its size, the error estimate that sets
        the floors and the simulated experiment (``[measurement] resolution``, 1.6 times the
        rule's counts against the enriched 1.5)."""
        localisations = 2 * self.max_steps + 1
        set_up = self.solve_seconds + (0.0 if enriched is None else 2.0 * enriched.solve_seconds)
        return self.frequencies * (set_up + localisations * LOCALISATION_SOLVES
                                   * self.factorisation_seconds)

    @property
    def plan_seconds_per_joint(self) -> float:
        """``vtcr plan``'s work for one joint (:data:`PLAN_SECONDS_PER_ENTRY`,
        :data:`GROUPED_PLAN_SECONDS_PER_ENTRY`)."""
        per_entry = GROUPED_PLAN_SECONDS_PER_ENTRY if self.grouped else PLAN_SECONDS_PER_ENTRY
        return self.frequencies * per_entry * self.factor_entries

    def plan_seconds(self, joints: int | None = None,
                     enriched: SizeEstimate | None = None) -> float:
        """``vtcr plan`` of ``joints`` updatable joints (default every one): per frequency the
        plates' blocks, :data:`PLAN_SOLVES` factorisations and, with ``enriched`` (the estimate
        of the error estimate's enriched solve), that solve; then each joint's work."""
        joints = self.channels if joints is None else joints
        per_frequency = (self.plate_seconds + PLAN_SOLVES * self.factorisation_seconds
                         + (0.0 if enriched is None else enriched.solve_seconds))
        return self.frequencies * per_frequency + joints * self.plan_seconds_per_joint

    def lines(self, enriched: SizeEstimate | None = None) -> list[str]:
        """Human-readable lines for ``vtcr check``; ``enriched``, the estimate of the error
        estimate's enriched solve, adds what ``vtcr solve`` takes with it (its peak memory is
        the enriched solve's, its time the sum of both)."""
        gb = self.solve_bytes / 1e9
        set_up = ", each set up by a solve, its error estimate and a simulated experiment"
        with_estimate = "" if enriched is None else (
            f", with its error estimate about {enriched.solve_bytes / 1e9:.2g} GB and "
            f"{self.solve_seconds + enriched.solve_seconds:.2g} s")
        return [
            f"unknowns at {self.frequency:g} Hz: {self.ray_unknowns} ray unknowns in "
            f"{self.plates} plates, {self.interface_unknowns} interface unknowns, "
            f"{self.constraints} constraints, {self.residual_samples} residual samples",
            f"estimated: solve about {gb:.2g} GB and {self.solve_seconds:.2g} s per frequency"
            f"{with_estimate} (sparse interface matrix {self.matrix_entries:.3g} entries, "
            f"{'LDL^H by groups' if self.grouped else 'LU'} factors about "
            f"{self.factor_entries:.2g}); update at most about "
            f"{self.update_seconds(enriched):.2g} s ({self.frequencies} frequencies"
            f"{'' if enriched is None else set_up}, "
            f"{LOCALISATION_SOLVES} factorisations per localisation, at most "
            f"{2 * self.max_steps + 1} localisations); plan about "
            f"{self.plan_seconds(enriched=enriched):.2g} s, "
            f"{self.plan_seconds_per_joint:.2g} s per joint (plan --joints plans some)",
        ]


def estimate_size(case: Case, frequency: float | None = None,
                  resolution: float | Mapping[str, float] | None = None) -> SizeEstimate:
    """Count the unknowns of ``case`` at ``frequency`` (default its highest) and estimate costs.

    Parameters
    ----------
    case : assembly.Case
    frequency : float, optional
        Hz; the ray counts grow with it, so the highest frequency is the largest problem.
    resolution : float, optional
        Overrides ``[discretisation] resolution``.

    Returns
    -------
    SizeEstimate
    """
    frequency = max(case.frequencies) if frequency is None else float(frequency)
    problems = plate_problems(case, frequency)
    bases = plate_bases(case, problems, resolution)
    arrangement = interface_layout(case, problems, resolution)
    counts, layout, n_s = arrangement.counts, arrangement.slots, arrangement.n_s
    corners, unknowns = arrangement.corner_columns, arrangement.unknowns

    entries = samples = constraints = 0
    moving = set(case.moving_lines())
    in_plane = membrane_problems(case, frequency)
    in_plane_bases = membrane_bases(case, in_plane, problems, resolution)
    n_rays = sum(b.n_dof for b in bases.values()) + sum(b.n_dof for b in in_plane_bases.values())
    for jid, joint in case.joints.items():
        seen = len(np.unique(np.concatenate([unknowns[p] for p in joint.plates])))
        n_f = counts[jid]  # a channel's samples: its residual on the load functions
        if case.is_line(jid):  # a channel per finite member, balance and rigid rows
            channels = len(joint.finite_members())
            rigid_ties = max(1, len(joint.plates) - channels) - 1
            if jid in moving:  # translation as one body, 3 rows per member but the first
                constraints += counts[jid] * (rigid_ties + 3 * (len(joint.plates) - 1))
                entries += 3 * counts[jid] * (len(joint.plates) - 1) * seen
            else:  # and the moment balance
                constraints += counts[jid] * (rigid_ties + 1)
        else:
            channels = 2 if "FA" in layout[jid] else 1
        samples += channels * n_f
        entries += channels * n_f * seen
        if joint.kind == "coplanar":
            constraints += counts[jid]
            entries += counts[jid] * seen
    for pid, points in _measured_points(case).items():
        samples += points
        entries += points * len(unknowns[pid])
    constraints += len(corners)
    matrix_entries = 2 * entries + samples
    return SizeEstimate(frequency, len(case.plates), len(case.joints), n_rays, n_s, constraints,
                        samples,
                        matrix_entries, len(case.frequencies), case.updating.max_steps,
                        len(case.updatable_joints()),
                        tuple(map(tuple, factorised_sizes(problems, bases, in_plane,
                                                          in_plane_bases))))


def _measured_points(case: Case) -> dict[str, int]:
    counts = {}
    for plate, _, _ in case.measurement_points():
        counts[plate] = counts.get(plate, 0) + 1
    return counts


def available_memory() -> float | None:
    """Bytes of memory available to a new computation (``MemAvailable``), or None."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return 1024.0 * float(line.split()[1])
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None
