"""Dead reckoning of Pluto's localModule: odometry for translation, the DMU for rotation.

Pluto 3: the localization service fuses "the odometer and inertial data".  The rule here:

- Translation always comes from the odometry: each odometry sample's increment (dx, dy) in the
  frame of the previous sample.
- Rotation comes from the DMU's integrated heading (its filtered state's theta, Pluto 8.2) when the
  DMU is fresh, i.e. its samples cover the odometry sample's time; from the odometry's own heading
  change when it is not (no DMU, or its latest sample is older than ``dmu_stale_s``).  Pitch and
  roll come from the DMU when fresh, else 0 (flat floor).
- An increment no robot could make (over ``MAX_SPEED`` / ``MAX_TURN_RATE``) is a reset of the
  odometry: no motion.  A new base process's first sample (the caller says so) is the motion from
  its zero, where the old one left the robot, if the robot could have made it; else no motion.
  Either adds ``RESET_SIGMA`` to the covariance (the robot may have moved unheard).
- An odometry sample waits for the DMU to cover it, so both sources are used at the same instants:
  while the DMU is at most ``dmu_stale_s`` of odometry time behind, or was heard within
  ``DMU_HEARD_S`` of wall time (late, not gone).

The pose starts at ``start`` and never jumps: it is the continuous estimate of stream (0).  A
dead reckoning resumed from a saved state (``resume_odometry``, see :mod:`pluto_nav.resume`)
applies the increment from that reading to its first odometry sample, with the same reset rule.
Its covariance grows by :func:`pluto_nav.odometry_model.increment_covariance` of each step (with
the heading part of a DMU step from ``dmu_sigma``).  A history of a few seconds lets the laser's
scan time be interpolated (stream 1) and a Post_Pose of the recent past be related to the present.
"""

from __future__ import annotations

import bisect
import collections
import dataclasses
import math
import time
from collections.abc import Callable

import numpy as np

from .geometry import compose, compose_jacobians, interpolate, relative, wrap
from .odometry_model import OdometryNoiseModel, increment_covariance

__all__ = ['DMU_HEARD_S', 'RESET_SIGMA', 'DeadReckoning', 'DrSample', 'possible']

#: Seconds of history kept for interpolation at scan times and past Post_Pose stamps.
HISTORY_S = 5.0
#: Wall seconds a sample is kept at least, however much newer odometry came after it: a loaded
#: machine's backlog of odometry, worked through in one step, would otherwise trim the history
#: past the scans whose timing messages arrive a step later (a CI run placed 14 of 24 such scans).
HISTORY_WALL_S = 2.0
#: Most samples kept (a bound on memory only: 400 s of odometry at 50 Hz).
MAX_HISTORY = 20000
#: Wall seconds a resumed dead reckoning's first odometry sample waits at most for the DMU that ran
#: on (its subscription is matched in its own time: 1 s was too short on a loaded machine); after
#: that the gap's turn is the odometry's (:attr:`DeadReckoning.dmu_not_come` counts it).
RESUME_DMU_WAIT_S = 5.0
#: Wall seconds since the DMU was last heard within which an odometry sample it has not covered
#: waits for it however far the odometry's stamps are ahead (``dmu_stale_s``): a DMU heard a moment
#: ago is late, not gone.  A soak caught the DMU process 0.3 s behind the odometry just after the
#: base's restart (the machine loaded by the new process); three steps of a 1 rad/s turn then took
#: the odometry's turn, 2.6 degrees off together.  Only with a wall clock (offline, stamps alone).
DMU_HEARD_S = 1.0
#: An odometry increment faster than this (m/s, rad/s) is a reset of the odometry, not motion.
MAX_SPEED = 5.0
MAX_TURN_RATE = 10.0
#: Standard deviations (m, m, rad) of the motion a reset of the odometry may hide, added to that
#: step's covariance: what the old base process reported last but nobody heard (its last message
#: or so: a tenth of a second at Pluto's base rate of 10 Hz, at up to 1 m/s and 1.5 rad/s).  Taken
#: with the covariance of no motion, a reset made the poseModule sure of a wrong pose (issue 38).
#: The heading part is not added when the DMU covers the step: it measured the turn.
RESET_SIGMA = (0.1, 0.1, 0.15)


def possible(increment: np.ndarray | tuple[float, float, float], dt: float) -> bool:
    """Whether a robot could move by ``increment`` (x, y, theta in its frame) in ``dt`` seconds:
    within ``MAX_SPEED`` and ``MAX_TURN_RATE``, with 5 cm and 0.05 rad to spare."""
    return bool(math.hypot(increment[0], increment[1]) <= MAX_SPEED * dt + 0.05
                and abs(increment[2]) <= MAX_TURN_RATE * dt + 0.05)


@dataclasses.dataclass(frozen=True)
class DrSample:
    """The dead-reckoned robot pose at one odometry time."""

    stamp: float
    pose: np.ndarray          # (x, y, theta)
    phi: float
    psi: float
    covariance: np.ndarray    # 3x3 over (x, y, theta), absolute since start
    dmu_used: bool
    increment: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(3))   # from the sample before
    increment_cov: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((3, 3)))
    received: float = 0.0     # the wall clock (monotonic) when it was reckoned


class DeadReckoning:
    """Fuses odometry and DMU samples into the dead-reckoned pose of the robot centre.

    :param start: the starting pose (x, y, theta) in the map frame.
    :param start_covariance: its 3x3 covariance.
    :param noise: the odometry error model (tunable).
    :param dmu_sigma: rad/sqrt(s), heading random walk of the DMU's integrated heading.
    :param dmu_stale_s: s of odometry time after which a DMU that has not covered a sample is
        considered absent for it, unless it was heard within :data:`DMU_HEARD_S` of wall time.
    :param resume_odometry: ``(stamp, (x, y, theta))``, the odometry reading at which the robot was
        at ``start`` (a restarted module resuming a saved state); None: ``start`` is where the
        first odometry sample finds the robot.
    :param resume_dmu: the DMU's (unwrapped heading, pitch, roll) at ``resume_odometry``'s reading,
        from the same DMU process as the samples to come: the turn since is taken from the DMU
        (a restarted localModule's gap is otherwise reckoned with the odometry's heading, 5 %
        of a turn off: 8 degrees after the robot turned 2.5 rad while no localModule ran).
    :param clock: the wall clock (monotonic seconds) that keeps a sample :data:`HISTORY_WALL_S`;
        None: the history is trimmed by the odometry's time alone (a recording replayed offline,
        where every sample comes at once and no scan is late).
    """

    def __init__(self, start: tuple[float, float, float], *, start_covariance: np.ndarray | None = None,
                 noise: OdometryNoiseModel | None = None, dmu_sigma: float = 0.002,
                 dmu_stale_s: float = 0.25,
                 resume_odometry: tuple[float, tuple[float, float, float]] | None = None,
                 resume_dmu: tuple[float, float, float] | None = None,
                 clock: Callable[[], float] | None = time.monotonic) -> None:
        self.noise = noise or OdometryNoiseModel()
        self._clock = clock
        self.dmu_sigma = dmu_sigma
        self.dmu_stale_s = dmu_stale_s
        self.start = np.asarray(start, dtype=float)
        cov = np.zeros((3, 3)) if start_covariance is None else np.asarray(start_covariance, dtype=float)
        self.history: collections.deque[DrSample] = collections.deque()
        self._initial_cov = cov
        self._last_odometry: tuple[float, np.ndarray] | None = None
        self._resume = None if resume_odometry is None else (
            float(resume_odometry[0]), np.asarray(resume_odometry[1], dtype=float))
        self._pending: collections.deque[tuple[float, np.ndarray]] = collections.deque()
        #: Stamps of odometry samples that are a restarted base's first.
        self._restarts_at: set[float] = set()
        self._dmu: collections.deque[tuple[float, float, float, float]] = collections.deque()
        #: The wall time the last DMU sample came (None: none yet, or no wall clock).
        self._dmu_heard: float | None = None
        self._dmu_unwrapped = 0.0
        self._dmu_theta: float | None = None
        #: Resumed with the DMU's reading and no sample of it yet: -1 until odometry waits for
        #: one, then the wall time it began to wait; None: not waiting.
        self._awaiting_dmu: float | None = None
        if self._resume is not None and resume_dmu is not None:
            heading, phi, psi = (float(v) for v in resume_dmu)
            self._dmu.append((self._resume[0], heading, phi, psi))
            self._dmu_unwrapped = self._dmu_theta = heading
            self._awaiting_dmu = None if clock is None else -1.0
        #: Whether :attr:`history` still holds every step since ``start``.
        self._history_from_start = True
        self.odometry_samples = 0
        self.odometry_resets = 0
        #: Whether a resumed dead reckoning gave up waiting for the DMU (the gap's turn is the
        #: odometry's).
        self.dmu_not_come = False
        self.dmu_steps = 0
        self.odometry_steps = 0

    # -- input -----------------------------------------------------------------------------------
    def add_odometry(self, stamp: float, x: float, y: float, theta: float, *,
                     restarted: bool = False) -> list[DrSample]:
        """Take an odometry sample; returns the dead-reckoned samples it (and the DMU) completed.
        ``restarted``: the first sample of a new base process (its odometry counts from zero
        again), taken as no motion whatever the jump."""
        if self._pending and stamp <= self._pending[-1][0]:
            return []
        if not self._pending and self._last_odometry is not None and stamp <= self._last_odometry[0]:
            return []
        if restarted:
            self._restarts_at.add(stamp)
        self.odometry_samples += 1
        self._pending.append((stamp, np.array([x, y, theta], dtype=float)))
        return self._advance()

    def add_dmu(self, stamp: float, theta: float, phi: float, psi: float, *,
                restarted: bool = False) -> list[DrSample]:
        """Take a DMU sample (filtered state: integrated heading, pitch, roll).  ``restarted``: the
        first sample of a new DMU process, whose heading is integrated from zero again: the
        heading goes on from here, and the samples before it are not used across the gap."""
        if restarted:
            self._dmu.clear()
        elif self._dmu and stamp <= self._dmu[-1][0]:
            return []
        self._awaiting_dmu = None
        self._dmu_heard = None if self._clock is None else self._now()
        last = theta if restarted else self._dmu_theta
        self._dmu_unwrapped = theta if last is None else self._dmu_unwrapped + wrap(theta - last)
        self._dmu_theta = theta
        self._dmu.append((stamp, self._dmu_unwrapped, phi, psi))
        while len(self._dmu) > 2 and self._dmu[1][0] < stamp - HISTORY_S:
            self._dmu.popleft()
        return self._advance()

    # -- fusion ----------------------------------------------------------------------------------
    def _advance(self) -> list[DrSample]:
        done = []
        while self._pending:
            stamp, odo = self._pending[0]
            covered = bool(self._dmu) and self._dmu[-1][0] >= stamp
            newest = self._pending[-1][0]
            stale = (not self._dmu or newest - self._dmu[-1][0] > self.dmu_stale_s) and not self._dmu_late()
            if not covered and stale and self._awaiting_dmu is not None:
                # Resumed with the DMU's reading: its own samples are seconds past it, so wait
                # (RESUME_DMU_WAIT_S of wall time) for the DMU that ran on to cover the gap.
                if self._awaiting_dmu < 0.0:
                    self._awaiting_dmu = self._now()
                if self._now() - self._awaiting_dmu < RESUME_DMU_WAIT_S:
                    break
                self._awaiting_dmu = None
                self.dmu_not_come = True
            if not covered and not stale:
                break
            self._pending.popleft()
            done.append(self._step(stamp, odo, use_dmu=covered))
        return done

    def _step(self, stamp: float, odo: np.ndarray, *, use_dmu: bool) -> DrSample:
        if self._last_odometry is None and self._resume is None:
            self._last_odometry = (stamp, odo)
            phi, psi = self._attitude(stamp) if use_dmu else (0.0, 0.0)
            sample = DrSample(stamp, self.start.copy(), phi, psi, self._initial_cov.copy(), use_dmu,
                              received=self._now())
            self.history.append(sample)
            return sample
        if self._last_odometry is None:       # resumed: ``start`` was the robot at this reading
            last_stamp, last_odo = self._resume  # type: ignore[misc]
            previous_pose, previous_cov = self.start, self._initial_cov
        else:
            last_stamp, last_odo = self._last_odometry
            previous_pose, previous_cov = self.history[-1].pose, self.history[-1].covariance
        self._last_odometry = (stamp, odo)
        increment = relative(last_odo, odo)
        dt = max(stamp - last_stamp, 1e-6)
        new_base = stamp in self._restarts_at
        reset = new_base or not possible(increment, dt)
        if reset:
            self._restarts_at.discard(stamp)
            # The base's odometry jumped (its module restarted and counts from zero again): no
            # robot moves like that.  Dead reckoning never jumps: a new base process's reading is
            # the motion since it started at zero where the old one left the robot, if the robot
            # could have made it since the last reading; anything else is no motion.  Either is
            # as uncertain as RESET_SIGMA says.
            self.odometry_resets += 1
            increment = odo.copy() if new_base and possible(odo, dt) else np.zeros(3)
        q = increment_covariance(increment, self.noise)
        if reset:
            q = q + np.diag(np.square(RESET_SIGMA))
        dmu_turn = self._dmu_turn(last_stamp, stamp) if use_dmu else None
        if dmu_turn is not None:
            # The DMU's heading is known modulo a turn across a long step (a resumed gap): the
            # turn nearest the odometry's.
            dmu_turn += math.tau * round((increment[2] - dmu_turn) / math.tau)
            increment = increment.copy()
            increment[2] = dmu_turn
            q = q.copy()
            q[2, :] = q[:, 2] = 0.0
            q[2, 2] = self.dmu_sigma ** 2 * (stamp - last_stamp) + 1e-12
            self.dmu_steps += 1
        else:
            self.odometry_steps += 1
        pose = compose(previous_pose, increment)
        j_pose, j_increment = compose_jacobians(previous_pose, increment)
        cov = j_pose @ previous_cov @ j_pose.T + j_increment @ q @ j_increment.T
        phi, psi = self._attitude(stamp) if dmu_turn is not None else (0.0, 0.0)
        now = self._now()
        sample = DrSample(stamp, pose, phi, psi, 0.5 * (cov + cov.T), dmu_turn is not None, increment, q, now)
        self.history.append(sample)
        while len(self.history) > 2 and self.history[1].stamp < stamp - HISTORY_S and (
                self._clock is None or self.history[1].received < now - HISTORY_WALL_S
                or len(self.history) > MAX_HISTORY):
            self.history.popleft()
            self._history_from_start = False
        return sample

    def dmu_at(self, stamp: float) -> tuple[float, float, float] | None:
        """The DMU's (heading, pitch, roll) interpolated at ``stamp``, the heading in the DMU's own
        terms (what it reported, unwrapped from there); None when its samples do not cover it.
        What the resume file keeps (:mod:`pluto_nav.resume`): a new process takes the DMU's next
        reports as turns from it.  This process's own unwrapped heading is not that after a
        restart of the DMU, whose new count it continued (a localModule resumed from it once
        turned a robot that stood still by 138 degrees, issue 38)."""
        value = self._dmu_value(stamp)
        if value is None or self._dmu_theta is None:
            return None
        return (value[0] - (self._dmu_unwrapped - self._dmu_theta), value[1], value[2])

    def _dmu_late(self) -> bool:
        """Whether the DMU was heard within :data:`DMU_HEARD_S` of wall time: late, not gone."""
        return self._dmu_heard is not None and self._now() - self._dmu_heard <= DMU_HEARD_S

    def _now(self) -> float:
        return 0.0 if self._clock is None else self._clock()

    def _dmu_value(self, stamp: float) -> tuple[float, float, float] | None:
        """Unwrapped heading, pitch, roll of the DMU interpolated at ``stamp``."""
        samples = self._dmu
        if not samples:
            return None
        i = bisect.bisect_left(samples, stamp, key=_first)
        if i == 0:
            return None if samples[0][0] > stamp else samples[0][1:]
        if i >= len(samples):
            return None
        (t0, *a), (t1, *b) = self._dmu[i - 1], self._dmu[i]
        f = (stamp - t0) / (t1 - t0)
        return tuple(u + f * (v - u) for u, v in zip(a, b))  # type: ignore[return-value]

    def _dmu_turn(self, t0: float, t1: float) -> float | None:
        a, b = self._dmu_value(t0), self._dmu_value(t1)
        if a is None or b is None:
            return None
        return b[0] - a[0]

    def _attitude(self, stamp: float) -> tuple[float, float]:
        value = self._dmu_value(stamp)
        return (0.0, 0.0) if value is None else (value[1], value[2])

    # -- output ----------------------------------------------------------------------------------
    @property
    def latest(self) -> DrSample | None:
        return self.history[-1] if self.history else None

    @property
    def latest_odometry(self) -> tuple[float, np.ndarray] | None:
        """The odometry reading ``(stamp, (x, y, theta))`` that :attr:`latest` was reckoned from
        (None before the first)."""
        if self._last_odometry is None:
            return None
        return self._last_odometry[0], self._last_odometry[1].copy()

    def at(self, stamp: float) -> DrSample | None:
        """The dead-reckoned pose interpolated at ``stamp`` (None when the history does not reach
        it: before the first sample or after the latest).  Within a step whose turn is the DMU's,
        the heading is the DMU's turn up to ``stamp``, not a share of the step's: across a gap in
        the odometry (a base restarted) the robot stood, then turned, and a scan placed in the gap
        on a heading drawn straight across it was 10 degrees off, which the poseModule took in
        and held for 27 s (a soak, issue 38)."""
        history = self.history
        if not history or stamp > history[-1].stamp:
            return None
        i = bisect.bisect_left(history, stamp, key=_stamp)
        if i == 0:
            return history[0] if math.isclose(stamp, history[0].stamp) or stamp >= history[0].stamp \
                else None
        a, b = history[i - 1], history[i]
        f = (stamp - a.stamp) / (b.stamp - a.stamp)
        pose = interpolate(a.pose, b.pose, f)
        turn = self._dmu_turn(a.stamp, stamp) if b.dmu_used else None
        if turn is not None:
            pose[2] = wrap(a.pose[2] + turn)
        cov = a.covariance + f * (b.covariance - a.covariance)
        return DrSample(stamp, pose, a.phi + f * (b.phi - a.phi), a.psi + f * (b.psi - a.psi), cov,
                        b.dmu_used)

    def increment_since_start(self, t1: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The relative pose from ``start`` to the robot at ``t1`` and its covariance, accumulated
        over every step since (for a resumed dead reckoning, the step from the saved reading
        first: the gap while no localModule ran, with the odometry's heading); None when the
        history no longer reaches back to the start, or does not reach ``t1``.

        A restarted localModule's first laser increment: the estimator's last scan was the old
        process's, just before the saved reading, so this is the increment it predicts with, and
        its covariance is what the gap is not known to (taken as zero, a heading a few degrees
        off after a restart was held as sure for seconds, issue 38)."""
        end = self.at(t1)
        if end is None or not self._history_from_start:
            return None
        cov = self._steps_covariance(-math.inf, t1)
        return relative(self.start, end.pose), 0.5 * (cov + cov.T)

    def _steps_covariance(self, t0: float, t1: float) -> np.ndarray:
        """The covariance of the steps stamped in (``t0``, ``t1``], composed in order."""
        cov = np.zeros((3, 3))
        relative_pose = np.zeros(3)
        for sample in self.history:
            if sample.stamp <= t0 or sample.stamp > t1:
                continue
            j_pose, j_increment = compose_jacobians(relative_pose, sample.increment)
            cov = j_pose @ cov @ j_pose.T + j_increment @ sample.increment_cov @ j_increment.T
            relative_pose = compose(relative_pose, sample.increment)
        return cov

    def increment_between(self, t0: float, t1: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The relative pose from the robot at ``t0`` to the robot at ``t1`` (in the frame at ``t0``)
        and its covariance, accumulated over the dead-reckoning steps in between (so a DMU heading
        counts as such); None when the history does not cover both."""
        a, b = self.at(t0), self.at(t1)
        if a is None or b is None:
            return None
        increment = relative(a.pose, b.pose)
        cov = self._steps_covariance(t0, t1)
        if not np.any(cov):     # both times between the same two samples: a share of that step
            cov = self._share_of_step(t0, t1)
            if not np.any(cov):
                cov = increment_covariance(increment, self.noise)
        return increment, 0.5 * (cov + cov.T)

    def _share_of_step(self, t0: float, t1: float) -> np.ndarray:
        """The covariance of the step that holds both ``t0`` and ``t1``, in proportion to the
        time between them: within a long step (a base restarted) a scan is as uncertain as the
        step says (its ``RESET_SIGMA``), not as a short motion drawn across it would be."""
        history = self.history
        i = bisect.bisect_left(history, t1, key=_stamp)
        if i == 0 or i >= len(history) or history[i - 1].stamp > t0:
            return np.zeros((3, 3))
        step = history[i]
        return step.increment_cov * ((t1 - t0) / (step.stamp - history[i - 1].stamp))


def _stamp(sample: DrSample) -> float:
    return sample.stamp


def _first(sample: tuple[float, float, float, float]) -> float:
    return sample[0]
