"""Automatic choice between DOP853 and Radau IIA during a run, by a model of the work done.

A planar chain with many modes is stiff in a way that the eigenvalues at the start cannot settle:
its fast modes oscillate (an explicit method must stay inside its stability region, ``h |lambda|
<= 6``), but they carry amplitudes so small that an L-stable implicit method may step over them at
a loose tolerance, damping them, and still meet the tolerance. Whether that pays depends on the
tolerance and on how much each mode is excited, so it is tried:

1. the run starts with the method of :func:`~flexkane.numerics.integrate.choose_method`;
2. while DOP853 runs, its stiffness test (the share of accepted steps limited by stability, see
   :mod:`flexkane.numerics.dop853`) tells whether its steps are held back by the fast modes; if
   ``STIFF_SHARE`` of them are (over at least 50 accepted steps), the next chunks are a *trial*
   of Radau;
3. a trial first *warms up*: it runs chunks of ``WARMUP_STEPS`` accepted steps, whose work is
   not judged, until its step size stops growing (by less than ``SETTLED_GROWTH`` over a chunk)
   or ``WARMUP_CHUNKS_MAX`` chunks. A method taking over from the other starts from a small step
   size, with a fresh Jacobian and LU decompositions (Radau): judged on its first steps it looks
   several times costlier per unit of time than it is (measured: ``falling-beam-exact`` with 40
   modes at rtol 1e-6, Radau dropped while alone it is five times faster than DOP853). Then the
   trial proper (``TRIAL_STEPS`` accepted steps or ``TRIAL_SPAN_FRACTION`` of the span, over one
   or more chunks) compares the simulated time per unit of work (:func:`chunk_work`) of the two
   methods over neighbouring stretches of the run; the cheaper one (by a margin ``SWITCH_GAIN``
   in favour of the current one) continues, except that Radau takes over from DOP853 at its
   stability limit within that margin when its steps are ``STEP_RATIO`` times longer;
4. while Radau runs, DOP853 gets a trial again every ``RECHECK_FRACTION`` of the span if Radau is
   no longer ``RETRY_MARGIN`` times cheaper than DOP853 was and costlier than at its last check
   or trial, since the motion may change (a manoeuvre ends, a mode is excited); while DOP853
   runs, Radau gets another trial only if its last one was less than ``RETRY_MARGIN`` times
   costlier than DOP853 is now.

The work is counted, never timed: right-hand-side evaluations times the operations of one
evaluation (counted in the generated source), plus the linear algebra of Radau's Newton
iterations and LU decompositions (weighted by ``LINEAR_ALGEBRA_WEIGHT``: their loops run faster
per operation than a generated right-hand side), as LSODA weighs the cost of its two methods. So
the same model and options take the same steps and give the same numbers on any machine and under
any load.
Trials advance the solution like any other chunk (nothing is computed twice).
"""

from __future__ import annotations

__all__ = ["LINEAR_ALGEBRA_WEIGHT", "MethodSwitch", "RECHECK_FRACTION", "RETRY_MARGIN",
           "SETTLED_GROWTH", "STEP_RATIO", "STIFF_SHARE", "SWITCH_GAIN", "TRIAL_SPAN_FRACTION",
           "TRIAL_STEPS", "WARMUP_CHUNKS_MAX", "WARMUP_STEPS", "chunk_work", "evaluation_work"]

# Steps of a trial chunk, by method (enough to pass a start-up, few enough to be cheap).
TRIAL_STEPS = {"dop853": 200, "radau": 40}
# A trial also ends after this fraction of the span.
TRIAL_SPAN_FRACTION = 0.05
# Warm-up of a trial (not judged): chunks of WARMUP_STEPS accepted steps until the step size grows
# by less than SETTLED_GROWTH over one of them (so at least two), at most WARMUP_CHUNKS_MAX chunks.
WARMUP_STEPS = 10
SETTLED_GROWTH = 1.25
WARMUP_CHUNKS_MAX = 4
# Share of stability-limited accepted DOP853 steps in a window that calls for a trial of Radau
# (at its stability limit the step size of DOP853 oscillates about it: about half of the steps
# are limited by it, a non-stiff run has almost none).
STIFF_SHARE = 0.4
# The other method takes over when its rate exceeds the current one's by this factor. Radau
# takes over from DOP853 at stability limit also when its rate is within this factor of DOP853's
# and its steps are STEP_RATIO times longer: its steps then follow the motion, not the fast modes,
# and this is its one fair chance, since DOP853 at its stability limit leaves the fast modes
# tolerance-sized oscillations that later trials of Radau must resolve (measured on
# falling-beam-exact, 40 modes, rtol 1e-6: Radau's rate in trials after 0.2 s of DOP853 15 times
# lower than in the first one; equal rates in the first trial, steps 5 times longer; Radau over the
# whole run 6 times cheaper by counted work, 5 times by CPU time).
SWITCH_GAIN = 1.3
STEP_RATIO = 3.0
# Fraction of the span between two trials.
RECHECK_FRACTION = 0.2
# Radau gives DOP853 another trial only when it is no longer this many times cheaper: a DOP853
# trial at its stability limit leaves tolerance-sized oscillations of the fast modes, which Radau
# then resolves instead of damping (measured: 80 times slower for the rest of the run). Likewise
# DOP853 gives Radau another trial only when Radau's last one was less than this many times
# costlier than DOP853 is now: every trial perturbs the run (measured: falling-beam-exact, 40
# modes, rtol 1e-8, trials losing by 5 times every 0.2 s cost DOP853 18 % more evaluations).
RETRY_MARGIN = 2.0
_MIN_ACCEPTED = 50  # accepted steps of a window before its stiffness share means anything
# Operations charged for a call of the right-hand side besides its arithmetic (call, loads).
CALL_OVERHEAD = 50
# Weight of an operation of Radau's linear algebra (LU decompositions, back substitutions: loops
# over arrays, which LLVM vectorizes) against one of the generated right-hand side (straight-line
# code, or term tables). Measured CPU time (2026-11-24): LU of the iteration matrices 5.1 and
# 5.6 Gop/s at n = 46 and 86 (counted as in chunk_work), back substitutions 3.8 and 4.5 Gop/s,
# one evaluation of falling-beam-exact 2.6 Gop/s at 20 modes (RHS_OPERATIONS 5,732, 2.19 us).
LINEAR_ALGEBRA_WEIGHT = 0.5


def evaluation_work(rhs_operations: int, n: int) -> float:
    """Work of one right-hand-side evaluation [floating-point operations].

    Parameters
    ----------
    rhs_operations : int
        Operations of the generated right-hand side (``RHS_OPERATIONS`` of a generated module,
        the solution of ``M u' = f`` included).
    n : int
        Number of states.
    """
    return float(rhs_operations + CALL_OVERHEAD + 2 * n)


def chunk_work(method: str, n: int, rhs_operations: int, nfev: int, nsteps: int,
               nlu: int = 0) -> float:
    """Work of a chunk of integration [floating-point operations], from its counts.

    Parameters
    ----------
    method : {"dop853", "radau"}
        Method of the chunk.
    n : int
        Number of states.
    rhs_operations : int
        Operations of one right-hand side (see :func:`evaluation_work`).
    nfev, nsteps, nlu : int
        Evaluations (Jacobians included), attempted steps and LU decompositions of the chunk.

    Returns
    -------
    float
        DOP853: each evaluation plus its stage combination (about ``14 n``). Radau IIA: each
        evaluation plus, per Newton iteration (one per 3 evaluations), a real and a complex
        back substitution (``2 n^2 + 8 n^2``); per LU decomposition ``(2/3) n^3`` real and
        ``4 (2/3) n^3`` complex; per step the error estimate (a real back substitution); the
        linear algebra weighted by ``LINEAR_ALGEBRA_WEIGHT``.
    """
    evaluation = evaluation_work(rhs_operations, n)
    if method == "dop853":
        return nfev * (evaluation + 14.0 * n)
    linear_algebra = (nfev * (10.0 * n * n + 30.0 * n) / 3.0
                      + nlu * (10.0 / 3.0 * n ** 3 + 4.0 * n * n) + nsteps * (2.0 * n * n + 10.0 * n))
    return nfev * evaluation + LINEAR_ALGEBRA_WEIGHT * linear_algebra


class _Window:
    """Work of one method since the last decision."""

    def __init__(self, method: str):
        self.method = method
        self.advanced = self.work = 0.0
        self.naccept = self.nstiff = 0

    def add(self, advanced: float, work: float, naccept: int, nstiff: int) -> None:
        self.advanced += advanced
        self.work += work
        self.naccept += naccept
        self.nstiff += nstiff

    @property
    def rate(self) -> float:
        """Simulated time per unit of work [s/operation]."""
        return self.advanced / self.work if self.work > 0.0 else float("inf")


class MethodSwitch:
    """Chooses the method and the step budget of each chunk of an automatic run.

    Parameters
    ----------
    method : {"dop853", "radau"}
        Method to start with.
    t0, span : float
        Start and length of the time span [s].
    """

    def __init__(self, method: str, t0: float, span: float):
        self.current = method
        self.span = span
        self.trial: str | None = None
        self.rate: dict[str, float] = {}
        self.next_check = t0 + RECHECK_FRACTION * span if method == "radau" else t0
        self.covered: dict[str, float] = {"dop853": 0.0, "radau": 0.0}
        self.switches = 0
        self._window = _Window(method)
        self._warmup: list[float] | None = None  # step sizes after the trial's warm-up chunks
        self._h = {"dop853": 0.0, "radau": 0.0}  # step size proposed after each one's last chunk

    def next_chunk(self) -> tuple[str, int | None]:
        """Method of the next chunk and its step limit (None: the usual budget)."""
        if self.trial is not None:
            if self._warmup is not None:
                return self.trial, WARMUP_STEPS
            return self.trial, max(TRIAL_STEPS[self.trial] - self._window.naccept, 1)
        return self.current, None

    def record(self, method: str, t_before: float, t_after: float, work: float, naccept: int,
               nstiff: int, h: float = 0.0) -> None:
        """Account for a finished chunk and decide on the next one.

        Parameters
        ----------
        method : str
            Method of the chunk.
        t_before, t_after : float
            Time at the start and at the end of the chunk [s].
        work : float
            Work of the chunk (:func:`chunk_work`) [floating-point operations].
        naccept, nstiff : int
            Accepted steps, and those of them limited by stability (DOP853; 0 for Radau).
        h : float
            Step size that the method proposes after the chunk [s] (ends a trial's warm-up when
            it stops growing; 0: unknown, the warm-up takes two chunks).
        """
        self.covered[method] = self.covered.get(method, 0.0) + (t_after - t_before)
        self._h[method] = h
        if self._warmup is not None:
            self._warmup.append(h)
            if len(self._warmup) >= WARMUP_CHUNKS_MAX or (
                    len(self._warmup) >= 2 and h <= SETTLED_GROWTH * self._warmup[-2]):
                self._warmup = None   # settled: the trial proper starts, on a fresh window
                self._window = _Window(method)
            return
        window = self._window
        window.add(t_after - t_before, work, naccept, nstiff)
        if self.trial is not None:
            if window.naccept < TRIAL_STEPS[self.trial] \
                    and window.advanced < TRIAL_SPAN_FRACTION * self.span:
                return
            self.rate[self.trial] = window.rate
            gain = self.rate[self.trial] / self.rate.get(self.current, float("inf"))
            if gain > SWITCH_GAIN or (self.trial == "radau" and gain * SWITCH_GAIN >= 1.0
                                      and h >= STEP_RATIO * self._h[self.current]):
                self.current = self.trial
                self.switches += 1
            self.trial = None
            self.next_check = t_after + RECHECK_FRACTION * self.span
            self._window = _Window(self.current)
            return
        if window.naccept < _MIN_ACCEPTED or t_after < self.next_check:
            return
        if self.current == "dop853":
            self.rate["dop853"] = window.rate
            if window.nstiff >= STIFF_SHARE * window.naccept and (
                    "radau" not in self.rate or RETRY_MARGIN * self.rate["radau"] > window.rate):
                self.trial = "radau"
        elif "dop853" not in self.rate or (window.rate < RETRY_MARGIN * self.rate["dop853"]
                                           and window.rate < self.rate.get("radau", float("inf"))):
            self.rate["radau"] = window.rate   # Radau got costlier since it was last judged
            self.trial = "dop853"
        self._window = _Window(self.trial or self.current)
        if self.trial is not None:
            self._warmup = []

    @property
    def main_method(self) -> str:
        """The method that covered most of the span so far."""
        return max(self.covered, key=self.covered.get) if any(self.covered.values()) \
            else self.current
