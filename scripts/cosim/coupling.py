"""The coupled system (`Coupled`: a body, its state and one connector FMU) and the coupling methods
without event location, each advancing both over a macro step H:

  zoh               explicit, zero-order hold (the FMU steps first, the body feels its load)
  jacobi            explicit, zero-order hold in parallel: both step from what the other gave at
                    the last communication point (the fixed-step Jacobi of libcosim and Ecos)
  extrapolation     explicit, the FMU driven along the predicted body path (input derivatives)
  linear_implicit   linear-implicit with the FMU's directional derivatives (θ-method)
  rollback          iterative with rollback (fmi2Get/SetFMUstate) to a stated tolerance

The linear-implicit method integrates the body itself (θ-method on M u' = Q + ext, M the mass
matrix) since it must treat body and connector together. Uses connectors (CosimFailure) and
numpy; the event-located methods (event_methods.py) and the master's loop use this.
"""
from __future__ import annotations

import numpy as np

from .connectors import CosimFailure


class Coupled:
    """A body, its state (p, u) and one connector FMU, wired for the methods below."""

    def __init__(self, body, fmu, p0, u0, theta=1.0, tol=1e-10, max_iter=50):
        self.body, self.fmu = body, fmu
        self.p, self.u = np.array(p0, float), np.array(u0, float)
        n = body.n
        self.S = np.zeros((fmu.nin, 2 * n))
        self.K, self.D = np.zeros((n, n)), np.zeros((n, n))
        self.theta, self.tol, self.max_iter = theta, tol, max_iter
        self.iterations = 0          # rollback or Newton iterations in total
        self.events = 0              # steps cut at an event (event-located methods)
        self.fresh = True            # the step starts at t = 0 or at an event
        self.since_event = 0         # steps since t = 0 or the last event (restart schedule)
        self.held = None             # jacobi: the connector's load for the body's next step
        self.s_t = np.zeros(fmu.nin)

    def put_state(self, t, p, u):
        """Inputs = node a at t, node b = the body at (p, u)."""
        self.body.inputs(t, p, u, self.fmu.x)
        self.fmu.set_inputs()

    def put_path(self, t, H, p0, u0, p1, u1):
        """Inputs at (p0, u0) and input derivatives along the chord to (p1, u1) over H."""
        self.put_state(t, p0, u0)
        self.body.rates(t, H, p0, u0, p1, u1, self.fmu.d)
        self.fmu.set_rates()

    def load(self):
        """The connector's generalised load on the body at the inputs just set (a copy)."""
        return self.fmu.get_outputs()[:self.body.n].copy()

    def jacobian(self, t, p, u):
        """K = ∂Q/∂p, D = ∂Q/∂u from the FMU's directional derivatives at the current inputs
        and committed state, plus the body's own (ground spring)."""
        n = self.body.n
        self.body.seeds(p, self.S)
        for j in range(2 * n):
            col = self.fmu.directional(self.S[:, j])[:n]
            (self.K[:, j] if j < n else self.D[:, j - n])[:] = col
        Ke, De = self.body.ext_jac(t, p, u)
        return self.K + Ke, self.D + De

    def jacobian_t(self, t, p, u):
        """K, D as `jacobian` (copies) and Q_t = ∂Q/∂t at a fixed body state (node a moving:
        one more directional derivative; zero when the body's inputs do not move with time)."""
        K, D = self.jacobian(t, p, u)
        seed = self.body.time_seed(t, self.s_t)
        Qt = np.zeros(self.body.n) if seed is None else self.fmu.directional(seed)[:self.body.n].copy()
        return K.copy(), D.copy(), Qt


def zoh(c, t, H):
    """1. Explicit, zero-order hold (cosim.extrapolation = 0): the FMU holds node b at x(t);
    the body feels the load F(x(t), v(t)) constant over [t, t + H]."""
    c.put_state(t, c.p, c.u)
    c.fmu.do_step(t, H)
    Q = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q, Q, H)


def jacobi(c, t, H):
    """2. Explicit, zero-order hold in parallel (Jacobi), as fixed-step third-party masters
    (libcosim, Ecos) run an SSP system: at t each side takes what the other gave at the last
    communication point. The FMU steps with the body's state at t held (cosim.extrapolation = 0);
    the body advances under the load the FMU gave after its previous step (at t = 0: at the
    initial state), and the FMU's new load waits for the next step."""
    if c.held is None:
        c.put_state(t, c.p, c.u)
        c.held = c.load()
    Q = c.held
    c.put_state(t, c.p, c.u)
    c.fmu.do_step(t, H)
    c.held = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q, Q, H)


def extrapolation(c, t, H):
    """3. Explicit with input extrapolation: predict the body's end state with F(t) held, drive
    the FMU along that path (input derivatives), then integrate the body with the load ramped
    from F(t) to the FMU's F at the predicted end state."""
    c.put_state(t, c.p, c.u)
    Q0 = c.load()                                              # evaluated, not committed
    p1, u1 = c.body.advance(t, c.p, c.u, Q0, Q0, H)            # predictor
    c.put_path(t, H, c.p, c.u, p1, u1)
    c.fmu.do_step(t, H)
    Q1 = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q0, Q1, H)          # corrector


def linear_implicit(c, t, H):
    """4. Linear-implicit: linearise the load about the explicit predictor (x + H v, v) with the
    FMU's directional derivatives K = ∂Q/∂x, D = ∂Q/∂v and take a θ-method step,
        (M − θ H D − θ² H² K) Δv = H ((1 − θ) Q(t) + θ Q_pred),
        v ← v + Δv,  x ← x + H (v + θ Δv);
    then commit the FMU along that chord. θ = 1: linearised implicit Euler; ½: trapezoidal."""
    # (Linearised about the predictor, not at x(t): at the committed state of a slipping friction
    # contact the trial force sits exactly on the friction limit, and the FMU's central-difference
    # tangent there is half the stick stiffness; at the predictor it is the slip or stick tangent.
    # For a linear connector both are the same.)
    th, b = c.theta, c.body
    c.put_state(t, c.p, c.u)
    Q0 = c.load() + b.ext(t, c.p, c.u)
    pp = b.retract(c.p, H * c.u)                                # predictor, a trial evaluation
    c.put_state(t + H, pp, c.u)                                 # (node a at t + H)
    Qp = c.load() + b.ext(t + H, pp, c.u)
    K, D = c.jacobian(t + H, pp, c.u)
    A = b.mass(c.p) - th * H * D - th * th * H * H * K
    du = np.linalg.solve(A, H * ((1.0 - th) * Q0 + th * Qp))
    p1, u1 = b.retract(c.p, H * (c.u + th * du)), c.u + du
    c.put_path(t, H, c.p, c.u, p1, u1)
    c.fmu.do_step(t, H)                                         # commit along the chord
    c.p, c.u = p1, u1


def rollback(c, t, H):
    """5. Iterative with rollback: fixed point on the end state (p1, u1). Each pass restores the
    FMU state saved at t, drives the FMU along the chord to (p1, u1), and integrates the body
    with the load ramped from F(t) to that F(t + H); stop when the end position moves by
    <= c.tol (and H·velocity likewise), at most c.max_iter passes, else CosimFailure."""
    b = c.body
    c.put_state(t, c.p, c.u)
    Q0 = c.load()
    c.fmu.save()
    p1, u1 = b.advance(t, c.p, c.u, Q0, Q0, H)                  # first guess: held load
    for k in range(c.max_iter):
        if k:
            c.fmu.restore()
        c.put_path(t, H, c.p, c.u, p1, u1)
        c.fmu.do_step(t, H, no_rollback=False)
        Q1 = c.load()
        p2, u2 = b.advance(t, c.p, c.u, Q0, Q1, H)
        change = max(b.dist(p1, p2), H * float(np.max(np.abs(u2 - u1))))
        p1, u1 = p2, u2
        if change <= c.tol:
            break
        first = change if k == 0 else first
        if change > 1e8 * first:
            raise CosimFailure(f"rollback: diverging at t = {t:g} (pass {k + 1})")
    else:
        raise CosimFailure(f"rollback: no convergence to {c.tol:g} in {c.max_iter} passes at t = {t:g}")
    c.iterations += k + 1
    c.p, c.u = p1, u1
