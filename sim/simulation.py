"""The simulation: one MjModel/MjData, a fixed physics step, the sim clock and periodic callbacks.

Everything that runs inside the sim (sensors, controllers, behaviour-tree ticks) registers a
periodic callback whose period is an integer multiple of the physics step. Advancing the sim
runs the callbacks that are due and steps the physics in one ``mj_step(nstep=k)`` batch up to
the next due callback, so Python only wakes when something has work to do.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np

from baobab.sim.errors import SimulationError

Callback = Callable[[float], None]
"""A periodic callback, called with the sim time (s) at which it is due."""

_FATAL_WARNINGS = {
    mujoco.mjtWarning.mjWARN_BADQACC: "bad qacc: the accelerations became non-finite",
    mujoco.mjtWarning.mjWARN_BADQVEL: "bad qvel: the velocities became non-finite",
    mujoco.mjtWarning.mjWARN_BADQPOS: "bad qpos: the positions became non-finite",
    mujoco.mjtWarning.mjWARN_BADCTRL: "bad ctrl: a control became non-finite",
    mujoco.mjtWarning.mjWARN_CONTACTFULL: "contact buffer full",
    mujoco.mjtWarning.mjWARN_CNSTRFULL: "constraint buffer full",
}
_FATAL_INDICES = tuple(int(kind) for kind in _FATAL_WARNINGS)


class _Scheduled:
    """One periodic callback: when it is next due (physics step) and how often."""

    __slots__ = ("active", "callback", "name", "next_step", "period_steps")

    def __init__(self, next_step: int, period_steps: int, callback: Callback, name: str) -> None:
        self.next_step = next_step
        self.period_steps = period_steps
        self.callback = callback
        self.name = name
        self.active = True


class PeriodicHandle:
    """Returned by :meth:`Simulation.every`; call :meth:`cancel` to stop the callback."""

    def __init__(self, entry: _Scheduled) -> None:
        self._entry = entry

    @property
    def name(self) -> str:
        """The name the callback was registered under."""
        return self._entry.name

    @property
    def period_steps(self) -> int:
        """The callback period in physics steps."""
        return self._entry.period_steps

    def cancel(self) -> None:
        """Stop calling the callback (idempotent)."""
        self._entry.active = False


def _keep_warning(message: str) -> None:
    """MuJoCo's warning handler here: keep the text, write no file, print nothing.

    MuJoCo's default handler prints and appends to ``MUJOCO_LOG.TXT`` in the working
    directory; the warnings that matter become :class:`SimulationError` through the
    counters :meth:`Simulation.check_state` reads.
    """
    global last_warning
    last_warning = message


last_warning = ""
"""The text of MuJoCo's latest warning in this process."""


class Simulation:
    """Owns MjModel/MjData, the sim clock and the periodic callbacks.

    Args:
        model: the compiled model; its ``opt.timestep`` is the physics step (s).
        seed: seed of the one random generator handed to everything that needs noise.
    """

    def __init__(self, model: mujoco.MjModel, *, seed: int = 0) -> None:
        if mujoco.get_mju_user_warning() is None:
            mujoco.set_mju_user_warning(_keep_warning)
        self.model = model
        self.data = mujoco.MjData(model)
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.physics_dt = float(model.opt.timestep)
        self._warning_counts = self.data.warning.number  # a live view of MuJoCo's counters
        self.native_gate = np.zeros(1, dtype=np.int64)
        """1 while :meth:`step_to` steps the physics, else 0: compiled control inside
        ``mj_step`` (:mod:`baobab.sim.native_control`) acts only then, not in a
        :meth:`forward`."""
        self._step = 0
        self._revision = 0
        # In registration order, which is also the order of callbacks due at the same step.
        # A handful of entries: a scan beats a heap, and the next due step is cached.
        self._schedule: list[_Scheduled] = []
        self._next_due: float = math.inf
        mujoco.mj_forward(self.model, self.data)

    @property
    def time(self) -> float:
        """Sim time in seconds, as an exact multiple of the physics step."""
        return self._step * self.physics_dt

    @property
    def state_revision(self) -> int:
        """A number that changes whenever the physics state may have: each stepping batch and
        each :meth:`forward`. Readers cache what they derive from the state under it."""
        return self._revision

    @property
    def step_count(self) -> int:
        """Physics steps taken since construction."""
        return self._step

    @property
    def next_callback_step(self) -> float:
        """The physics step at which the next callback is due (``math.inf`` with none). The
        callbacks due at the current step have not run yet: they run when stepping from it."""
        return self._next_due

    def steps_for(self, duration: float, *, what: str = "duration") -> int:
        """Convert ``duration`` (s) to a whole number of physics steps, or raise.

        Raises:
            SimulationError: if ``duration`` is not a non-negative integer multiple of the step.
        """
        if not math.isfinite(duration) or duration < 0:
            raise SimulationError(f"{what} must be a finite, non-negative time, got {duration}")
        steps = round(duration / self.physics_dt)
        if abs(steps * self.physics_dt - duration) > 1e-9 * max(1.0, duration):
            raise SimulationError(
                f"{what} {duration} s is not an integer multiple of the physics step "
                f"{self.physics_dt} s"
            )
        return steps

    def every(
        self, period: float, callback: Callback, *, name: str, first_call: float | None = None
    ) -> PeriodicHandle:
        """Call ``callback(t)`` every ``period`` seconds of sim time.

        The first call happens at ``first_call`` (s, default: now). Callbacks due at the same
        step run in registration order, before the physics step taken from that time.

        Raises:
            SimulationError: if ``period`` is not a positive multiple of the physics step.
        """
        period_steps = self.steps_for(period, what=f"period of '{name}'")
        if period_steps <= 0:
            raise SimulationError(f"period of '{name}' must be positive, got {period} s")
        start = self._step if first_call is None else self.steps_for(first_call, what="first call")
        entry = _Scheduled(max(start, self._step), period_steps, callback, name)
        self._schedule.append(entry)
        self._next_due = min(self._next_due, entry.next_step)
        return PeriodicHandle(entry)

    def step_for(self, duration: float) -> None:
        """Advance the sim by ``duration`` seconds, running due callbacks on the way.

        Raises:
            SimulationError: on a MuJoCo warning that means divergence, or a non-finite state.
        """
        self.step_to(self._step + self.steps_for(duration))

    def step_to(self, target_step: int) -> None:
        """Advance the sim to physics step ``target_step`` (no-op if already there).

        Callbacks due at a step run just before the physics step taken from it, so advancing
        from t0 to t1 runs exactly the callbacks due in [t0, t1).
        """
        model, data = self.model, self.data
        while self._step < target_step:
            if self._next_due <= self._step:
                self._run_due_callbacks()
            batch = int(min(self._next_due, target_step)) - self._step
            if batch > 0:
                self.native_gate[0] = 1
                try:
                    mujoco.mj_step(model, data, batch)
                finally:
                    self.native_gate[0] = 0
                self._step += batch
                self._revision += 1
                self.check_state()

    def _run_due_callbacks(self) -> None:
        """Run every callback due now, in registration order.

        A callback may register or cancel callbacks: one registered due now runs in this same
        pass, after those registered before it (it is appended to the list being walked).
        """
        now, step = self.time, self._step
        schedule = self._schedule
        next_due = math.inf
        canceled = False
        index = 0
        while index < len(schedule):
            entry = schedule[index]
            index += 1
            if entry.active and entry.next_step <= step:
                try:
                    entry.callback(now)
                except (ValueError, ArithmeticError) as error:
                    self._raise_if_not_finite(error)
                    raise
                entry.next_step += entry.period_steps
            if entry.active:
                next_due = min(next_due, entry.next_step)
            else:
                canceled = True
        if canceled:
            schedule[:] = [entry for entry in schedule if entry.active]
        self._next_due = next_due

    def _raise_if_not_finite(self, error: Exception) -> None:
        """Raise ``SimulationError`` (from ``error``) if the state holds a non-finite number.

        A state edited between steps reaches the callbacks before MuJoCo's own check in the
        next step: a controller fed NaN fails with a ValueError, whose real cause is this.
        """
        data = self.data
        for name in ("qpos", "qvel", "ctrl", "qfrc_applied", "mocap_pos"):
            if not np.isfinite(getattr(data, name)).all():
                raise SimulationError(
                    f"physics diverged at t={self.time:.3f} s: non-finite {name} ({error})"
                ) from error

    def check_state(self) -> None:
        """Raise ``SimulationError`` if MuJoCo warned of divergence since the last check.

        MuJoCo checks qpos, qvel and qacc for non-finite values inside every step, resets the
        data and counts a warning; reading the counters (one array) is all that is needed.
        """
        counts = self._warning_counts
        if not any(counts[index] for index in _FATAL_INDICES):
            return
        reasons = [reason for kind, reason in _FATAL_WARNINGS.items() if counts[int(kind)] > 0]
        for kind in _FATAL_WARNINGS:
            self.data.warning[int(kind)].number = 0
        raise SimulationError(f"physics diverged at t={self.time:.3f} s: {'; '.join(reasons)}")

    def forward(self) -> None:
        """Recompute derived quantities (positions, contacts) after editing the state by hand."""
        mujoco.mj_forward(self.model, self.data)
        self._revision += 1
