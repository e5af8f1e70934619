"""Event-located coupling: the master drives the FMU along the body's own path and stops every step
at the first event the FMU finds in it (a stop engaging or letting go, a damped stop's force
through 0, friction breaking away or sticking again, a normal force through 0), so that each step
integrates a smooth piece of the motion:

  linear_path_ev    the trapezoidal rule on the path r + vτ + ½aτ², linearly implicit: one solve
                    with the load's tangent at the step's start (second order)
  implicit_path_ev  the same rule, implicit: Newton iterations (FMU state restored, FMI 2.0 and
                    3.0 alike) until the body's acceleration is the mean of the loads the FMU gives
                    at the step's two ends (second order, with the FMU's own nonlinearity)
  linear_exact_ev   the body integrated exactly (matrix exponential) under the load's affine model
                    from the step's start, and the FMU driven through the body's end state
                    (position and velocity) along two quadratic pieces of H/2 (exact for a load
                    linear between events, as a stop in contact or a stick spring)

Common to the three (`located`):
- The FMU steps first, with the path given by the acceleration inputs (cosim.extrapolation = 3),
  and returns at the first event: FMI 3.0 by early return, FMI 2.0 by rolling back to the
  `event.time` it reports (`step_fmu`). The step is then taken again to just past the event
  (1e-6 of the step further, `PAST`) with the path computed for that length, so that the step's
  rule holds over a piece without event and the event lies at its end.
- The load's model comes from the step's start only (the load read there, which at an event is
  the load after it, and the FMU's directional derivatives: ∂Q/∂x, ∂Q/∂v, and ∂Q/∂t where node a
  moves), never from a point across an event.
- Prewarping (`AffineLoad`): per coordinate, the trapezoidal rule is applied to a load model
  whose stiffness and damping make its eigenvalues λ' = (2/h) tanh(hλ/2) of the model's own λ, so
  that the rule's amplification is exactly exp(hλ) for the linear part (the body's spring, a stick
  spring, a stop in contact) while the model's steady (polynomial) response is kept. It removes
  the rule's (ωh)²/12 frequency error, keeps an unstable part (the friction decay at breakaway)
  from reaching the rule's pole 2/h, and damps stiff modes as exp(hλ) does.
- After t = 0 and after every event the steps follow `SCHEDULE`: fractions of H, so that the fast
  transients that start at an event (a stick spring catching the body, μ falling from μ_s to μ_k
  within tens of µs) are resolved at every H, and the error keeps its order in H.
- A step whose iterations do not converge is taken again at half its length (at most `HALVINGS`
  times).

Uses connectors (CosimFailure) and numpy; master.py registers the methods.
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from .connectors import CosimFailure

EXTRAPOLATION_EV = 3       # cosim.extrapolation: the path along the acceleration inputs
PAST = 1e-6                # a step taken again to an event ends this fraction of it past the event
SCHEDULE = ((1 / 512, 8), (1 / 64, 16), (1 / 16, 12))   # (fraction of H, steps) after an event
TOL = 1e-10                # Newton / secant: the load residual, relative to the load at the start
MAX_ITER = 25
HALVINGS = 12


def step_fmu(c, t, h):
    """Advance the FMU from t (inputs and path already set) by at most h and stop at the first
    event inside the step; return the time reached.

    FMI 3.0: fmi3DoStep with earlyReturnAllowed; at an event it returns early and the FMU's time,
    state and outputs are at lastSuccessfulTime. FMI 2.0: fmi2GetFMUstate before the step; if
    `event.time` < t + h, fmi2SetFMUstate and step again with h = event.time − t (the same path
    from the same inputs, so the event now lies at the end of the step). Both routes walk the same
    path and stop at the same located event (FMU: to 1e-10 of the step)."""
    f = c.fmu
    if f.version == 3:
        early, last = f.do_step_early(t, h)
        return last if early else t + h
    f.save(1)
    f.do_step(t, h, no_rollback=False)
    te = f.event_time()
    if te < t + h:
        f.restore(1)
        f.do_step(t, te - t)
        return te
    return t + h


def expm(A):
    """exp(A) of a small matrix: scaling and squaring of the Taylor series (degree 18 after
    scaling to norm <= 1/2: truncation < 1e-22 relative)."""
    nrm = float(np.max(np.sum(np.abs(A), axis=1)))
    k = max(0, math.ceil(math.log2(nrm / 0.5))) if nrm > 0.5 else 0
    B = A / (2.0 ** k)
    E, T = np.eye(len(A)), np.eye(len(A))
    for i in range(1, 19):
        T = T @ B / i
        E = E + T
    for _ in range(k):
        E = E @ E
    return E


def stable_part(X):
    """X without the unstable part of its symmetric part (eigenvalues > 0 set to 0): a negative
    stiffness or damping of the tangent (the friction decay's at breakaway: ∂F/∂v = +(μ_s − μ_k)
    N d_c) is left to the load's secant instead of being integrated exponentially."""
    S = 0.5 * (X + X.T)
    w, V = np.linalg.eigh(S)
    if np.all(w <= 0.0):
        return X
    return X - (V * np.maximum(w, 0.0)) @ V.T


def _diagonal(*mats):
    return all(np.array_equal(A, np.diag(np.diag(A))) for A in mats)


class AffineLoad:
    """The load's affine model over a step from (x0, u0) at τ = 0 (K = ∂Q/∂x, D = ∂Q/∂u, g = ∂Q/∂t
    at the start, the body's own forces included): Q(x, u, τ) = Q0 + K(x − x0) + D(u − u0) + gτ,
    and its prewarped form for the trapezoidal rule over a step of length h (`correction`).

    Prewarping, per coordinate of a body whose M, K, D are diagonal (else none): m λ² − d λ − k = 0
    gives the model's λ1, λ2; the rule is applied with k' = −m λ'1 λ'2, d' = m(λ'1 + λ'2),
    λ' = (2/h) tanh(hλ/2), about the model's steady response (x_p, u_p) (polynomial in τ: the
    equilibrium moving with g), so that Q' = Q_lin there. Skipped where a λ' would be too close to
    tanh's poles (|Im hλ| > 2.5)."""

    def __init__(self, M, Q0, K, D, g, x0, u0, h, prewarp=True):
        self.M, self.Q0, self.K, self.D, self.g, self.x0, self.u0 = M, Q0, K, D, g, x0, u0
        self.Kp, self.Dp = K.copy(), D.copy()
        self.coords = []
        if not (prewarp and _diagonal(M, K, D)):
            return
        for j in range(len(u0)):
            m, k, d = M[j, j], K[j, j], D[j, j]
            if k == 0.0 and d == 0.0:
                continue
            # m λ² − d λ − k = 0 without cancellation: the larger root first, the other from
            # the product λ1 λ2 = −k/m (a small root from the difference would carry the round-off
            # of d² into λ' and make round-off of the FMU's tangent matter)
            q = 0.5 * (d + math.copysign(1.0, d) * cmath.sqrt(d * d + 4.0 * m * k))
            if q == 0:
                continue
            lam = (q / m, -k / q)
            if any(abs((h * x).imag) > 2.5 for x in lam):
                continue
            lp = [(2.0 / h) * cmath.tanh(0.5 * h * x) for x in lam]
            kp, dp = (-m * lp[0] * lp[1]).real, (m * (lp[0] + lp[1])).real
            if math.isfinite(kp) and math.isfinite(dp):
                self.Kp[j, j], self.Dp[j, j] = kp, dp
                self.coords.append((j, m, k, d, kp, dp))

    def correction(self, x, u, tau):
        """Q'(x, u, τ) − Q_lin(x, u, τ): what prewarping adds to the load at (x, u, τ)."""
        C = np.zeros(len(self.u0))
        for j, m, k, d, kp, dp in self.coords:
            Q0, g, x0, u0 = self.Q0[j], self.g[j], self.x0[j], self.u0[j]
            if k != 0.0:      # steady response x_p = α + βτ, u_p = β
                beta = -g / k
                alpha = x0 - (Q0 + d * (beta - u0)) / k
                prewarped = kp * (x[j] - alpha - beta * tau) + dp * (u[j] - beta)
            else:             # no stiffness: steady velocity u_p = a + bτ
                b = -g / d
                a = u0 + (m * b - Q0) / d
                prewarped = m * b + dp * (u[j] - a - b * tau)
            C[j] = prewarped - (Q0 + k * (x[j] - x0) + d * (u[j] - u0) + g * tau)
        return C

    def trapezoid(self, h):
        """The path's acceleration a by the trapezoidal rule on the prewarped model,
        M a = ½(Q'(start) + Q'(end)), and the rule's matrix A = M − ¼h²K' − ½hD'."""
        x0, u0 = self.x0, self.u0
        Qp0 = self.Q0 + self.correction(x0, u0, 0.0)
        # Q' is affine in (x, u, τ): its rate along τ at a fixed state
        Qpt = self.g + (self.correction(x0, u0, h) - self.correction(x0, u0, 0.0)) / h
        A = self.M - 0.25 * h * h * self.Kp - 0.5 * h * self.Dp
        return np.linalg.solve(A, Qp0 + 0.5 * h * (self.Kp @ u0 + Qpt)), A


class NoConvergence(Exception):
    """A step's iterations did not converge: the caller takes it again at half its length."""


def _start(c, t):
    """The load's affine model at the step's start: (M, Q0, K, D, Q_t), the body's own forces
    included (trial evaluations only: the FMU keeps its inputs at the body's state at t)."""
    b, p, u = c.body, c.p, c.u
    c.put_state(t, p, u)
    Q0 = c.load() + b.ext(t, p, u)
    K, D, Qt = c.jacobian_t(t, p, u)
    return b.mass(p), Q0, K, D, Qt


def _along(b, p, u, pieces, tau):
    """The body's state at τ along a path of quadratic pieces [(acceleration, length)]."""
    for a, length in pieces:
        s = min(tau, length)
        p, u = b.retract(p, s * (u + 0.5 * s * a)), u + s * a
        tau -= s
        if tau <= 0.0:
            break
    return p, u


def _drive(c, t, pieces, first):
    """The FMU stepped from the body's state at t along a path of quadratic pieces
    [(acceleration, length)], each one FMU step; returns the time reached (an event ends the
    path there). `first`: the FMU is at t and its state is saved there (slot 0); else that state
    is restored first."""
    f, b = c.fmu, c.body
    if first:
        f.save(0)
    else:
        f.restore(0)
    c.iterations += 1
    ts, p, u = t, c.p, c.u
    for a, length in pieces:
        c.put_state(ts, p, u)
        f.acc[:] = a
        f.set_accelerations()
        te = step_fmu(c, ts, length)
        if te < ts + length * (1.0 - 1e-12):
            return te
        p, u = _along(b, p, u, [(a, length)], length)
        ts = te
    return ts


def _path_step(c, t, h, iterate):
    """linear_path_ev (iterate = False) and implicit_path_ev (True) over one step of at most h;
    returns (time reached, acceleration of the path, whether it ended at an event)."""
    b, p, u = c.body, c.p, c.u
    M, Q0, K, D, Qt = _start(c, t)
    model = AffineLoad(M, Q0, K, D, Qt, p, u, h)
    a, A = model.trapezoid(h)
    C0 = model.correction(p, u, 0.0)
    restepped, first = False, True
    for _ in range(MAX_ITER):
        t1 = _drive(c, t, [(a, h)], first)
        first = False
        if t1 < t + h * (1.0 - 1e-12):
            if restepped:
                return t1, a, True
            # the event: this step again, to just past it, on the path of that length
            h = (t1 - t) * (1.0 + PAST)
            model = AffineLoad(M, Q0, K, D, Qt, p, u, h)
            a, A = model.trapezoid(h)
            C0, restepped = model.correction(p, u, 0.0), True
            continue
        if not iterate or restepped:
            return t1, a, False
        # Newton on the trapezoidal rule with the FMU's own load at the path's end
        x1, u1 = b.retract(p, h * (u + 0.5 * h * a)), u + h * a
        c.put_state(t1, x1, u1)
        Q1 = c.load() + b.ext(t1, x1, u1) + model.correction(x1, u1, h)
        R = M @ a - 0.5 * (Q0 + C0 + Q1)
        if np.max(np.abs(R)) <= TOL * max(1.0, float(np.max(np.abs(Q0)))):
            return t1, a, False
        a = a - np.linalg.solve(A, R)
    raise NoConvergence


def _exact_solution(M, Ks, Ds, Q0, g, u, h):
    """(Δx, u) at h of M u' = Q0 + Ks Δx + Ds (u − u0) + g s, exactly (the (2n + 2)-square
    augmented system's exponential, w = (Δx, u, 1, s))."""
    n = len(u)
    Minv = np.linalg.inv(M)
    A = np.zeros((2 * n + 2, 2 * n + 2))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = Minv @ Ks
    A[n:2 * n, n:2 * n] = Minv @ Ds
    A[n:2 * n, 2 * n] = Minv @ (Q0 - Ds @ u)
    A[n:2 * n, 2 * n + 1] = Minv @ g
    A[2 * n + 1, 2 * n] = 1.0
    w = expm(A * h) @ np.concatenate((np.zeros(n), u, [1.0, 0.0]))
    return w[:n], w[n:2 * n]


def _two_pieces(dx, u0, u1, h):
    """The path of two quadratic pieces of h/2 from (0, u0) through (dx, u1) at h, position and
    velocity continuous: [(a1, h/2), (a2, h/2)]."""
    a1 = 4.0 * (dx - u0 * h) / (h * h) - (u1 - u0) / h
    return [(a1, 0.5 * h), (2.0 * (u1 - u0) / h - a1, 0.5 * h)]


def _exact_step(c, t, h):
    """linear_exact_ev over one step of at most h; returns (time reached, end state, event)."""
    b, p, u = c.body, c.p, c.u
    M, Q0, K, D, Qt = _start(c, t)
    Ks, Ds, g = K, D, Qt.copy()
    restepped, first = False, True
    for _ in range(MAX_ITER):
        dx, u1 = _exact_solution(M, Ks, Ds, Q0, g, u, h)
        pieces = _two_pieces(dx, u, u1, h)
        t1 = _drive(c, t, pieces, first)
        first = False
        if t1 < t + h * (1.0 - 1e-12):
            if restepped:
                return t1, _along(b, p, u, pieces, t1 - t), True
            h, restepped = (t1 - t) * (1.0 + PAST), True
            continue
        x1 = b.retract(p, dx)
        if restepped:
            return t1, (x1, u1), False
        # the secant: the model meets the FMU's load at the body's end state
        c.put_state(t1, x1, u1)
        r = c.load() + b.ext(t1, x1, u1) - (Q0 + Ks @ dx + Ds @ (u1 - u) + g * h)
        if np.max(np.abs(r)) <= TOL * max(1.0, float(np.max(np.abs(Q0)))):
            return t1, (x1, u1), False
        g = g + r / h
    raise NoConvergence


def _scheduled(c, H):
    """The step length after t = 0 or an event (`SCHEDULE`), else H."""
    k = c.since_event
    for frac, n in SCHEDULE:
        if k < n:
            return H * frac
        k -= n
    return H


def located(one_step):
    """An event-located method from its one-step rule: the restart schedule, the step taken again
    at half its length while its iterations do not converge, the body moved to where the FMU got,
    the events counted."""
    def method(c, t, H):
        h = min(H, _scheduled(c, H))
        for _ in range(HALVINGS + 1):
            try:
                t1, end, event = one_step(c, t, h)
                break
            except NoConvergence:
                c.fmu.restore()
                h *= 0.5
        else:
            raise CosimFailure(f"no convergence at t = {t:g} down to h = {h:g}")
        c.p, c.u = end
        c.since_event = 0 if event else c.since_event + 1
        c.events += event
        return t1
    method.__doc__ = one_step.__doc__
    return method


def _path(iterate):
    def one_step(c, t, h):
        t1, a, event = _path_step(c, t, h, iterate)
        h1 = t1 - t
        b, p, u = c.body, c.p, c.u
        return t1, (b.retract(p, h1 * (u + 0.5 * h1 * a)), u + h1 * a), event
    return one_step


linear_path_ev = located(_path(False))
implicit_path_ev = located(_path(True))
linear_exact_ev = located(_exact_step)

EV_METHODS = {"linear_path_ev": linear_path_ev, "implicit_path_ev": implicit_path_ev,
              "linear_exact_ev": linear_exact_ev}
LABELS = {"linear_path_ev": "linearly implicit trapezoid on the body's path, event-located",
          "implicit_path_ev": "implicit trapezoid on the body's path (Newton), event-located",
          "linear_exact_ev": "exact under the load's affine model (exponential), event-located"}
