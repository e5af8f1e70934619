"""Monolithic references: a scene's body and the connector's law integrated together in continuous
time, with the transitions located, to a relative 1e-10. Where no closed form of the FMU's own
model exists (the belt: a critically damped stick spring and μ decaying with the slip speed),
this is the truth a coupling method converges to; a fine co-simulation run is not.

The belt's model (docs/cosim.md, "The belt's monolithic reference"), the FMU's friction law
(docs/physics.md, "PLANAR friction") in the limit of vanishing substeps:
- body: m ÿ = −k y − f, with the belt (node a) at v_b t; relative slip w = ẏ − v_b, elastic
  slip e = y − v_b t − s (s the plastic slip), normal force N (the SLIDE-PLANE penalty's m g);
- stick: f = k_s e + c_s w, ṡ = 0; it breaks away where |k_s e + c_s w| reaches μ_s N;
- slip: f = μ(|w|) N sign(k_s e + c_s w) with μ = μ_k + (μ_s − μ_k) exp(−d_c |w|), and
  c_s ṡ = k_s e + c_s w − f (the plastic slip takes what the damped spring does not); it sticks
  again where the trial force k_s e + c_s w falls inside μ(|w|) N.
Integrated phase by phase with scipy's DOP853 (explicit Runge–Kutta of order 8; the stick spring's
1000 rad/s and the breakaway's fast fall of μ are resolved by its error control) at rtol 1e-13,
steps of at most 1e-4 s; each transition is located on the dense output and then again on a
stretch integrated in steps of a 64th of the last one, until it moves by less than 1e-15
(`_phase`). `convergence` reruns it at looser settings to show the figures settle.

Uses scipy and numpy; the belt scene (scenes.py) calls `belt_figures`.
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import solve_ivp

RTOL, ATOL, MAX_STEP = 1e-13, 1e-16, 1e-4
SAMPLE = 1e-6              # the solution is measured on this grid (as a run's samples are)


def belt_law(m, k, vb, mus, muk, dc, ks, cs, N):
    """The right-hand sides and transition functions of the belt's two phases: state
    x = (y, ẏ, s); `stick(t, x)`, `slip(t, x)` and their event functions."""
    def mu(w):
        return muk + (mus - muk) * math.exp(-dc * abs(w))

    def trial(t, x):
        return ks * (x[0] - vb * t - x[2]) + cs * (x[1] - vb)

    def stick(t, x):
        return [x[1], (-k * x[0] - trial(t, x)) / m, 0.0]

    def slip(t, x):
        ftr = trial(t, x)
        f = math.copysign(mu(x[1] - vb) * N, ftr)
        return [x[1], (-k * x[0] - f) / m, (ftr - f) / cs]

    def breakaway(t, x):
        return abs(trial(t, x)) - mus * N

    def restick(t, x):
        return abs(trial(t, x)) - mu(x[1] - vb) * N

    breakaway.terminal, breakaway.direction = True, 1
    restick.terminal, restick.direction = True, -1
    return {1: (stick, breakaway), 2: (slip, restick)}


def _phase(rhs, event, t, x, t_end, rtol, max_step):
    """One phase from (t, x) to its transition (or t_end): pieces of dense output, and the
    transition (time, state) or None. The transition found on a step's dense output is found
    again on that step integrated in smaller steps, until it settles."""
    kw = dict(method="DOP853", rtol=rtol, atol=ATOL, events=event, dense_output=True)
    sol = solve_ivp(rhs, (t, t_end), x, max_step=max_step, **kw)
    pieces = []
    if sol.status != 1:
        return pieces + [(sol.t[0], sol.t[-1], sol.sol)], None
    te, xe = sol.t_events[0][0], sol.y_events[0][0]
    while True:
        # the last step again, in steps of a 64th (and no further than one more of it)
        ta, xa = sol.t[-2], sol.y[:, -2]
        hmax = (te - ta) / 64
        pieces.append((sol.t[0], ta, sol.sol))
        sub = solve_ivp(rhs, (ta, min(t_end, te + (te - ta))), xa, max_step=hmax, **kw)
        if sub.status != 1:       # the transition not met again: keep what was found
            break
        sol, moved = sub, abs(sub.t_events[0][0] - te)
        te, xe = sub.t_events[0][0], sub.y_events[0][0]
        if moved <= 1e-15 * max(1.0, te) or hmax <= 1e-12:
            break
    return pieces + [(sol.t[0], min(sol.t[-1], te), sol.sol)], (te, xe)


@functools.lru_cache(maxsize=None)
def belt_solution(m, k, vb, mus, muk, dc, ks, cs, N, t_end, rtol=RTOL, max_step=MAX_STEP):
    """The belt from rest on the belt (y = 0, ẏ = v_b, sticking) to t_end: (pieces of dense
    output [(t0, t1, sol)], transitions [(time, 'breakaway'|'re-stick')])."""
    law = belt_law(m, k, vb, mus, muk, dc, ks, cs, N)
    t, x, phase = 0.0, np.array([0.0, vb, 0.0]), 1
    pieces, events = [], []
    while t < t_end:
        rhs, event = law[phase]
        more, hit = _phase(rhs, event, t, x, t_end, rtol, max_step)
        pieces += more
        if hit is None:
            break
        t, x = hit[0], np.array(hit[1])
        events.append((t, "breakaway" if phase == 1 else "re-stick"))
        phase = 3 - phase
    return pieces, events


def sample(pieces, t):
    """The solution (y, ẏ, s) at times t (each from the piece that covers it)."""
    out = np.full((len(t), 3), np.nan)
    for a, b, f in pieces:
        i = (t >= a) & (t <= b)
        if i.any():
            out[i] = f(t[i]).T
    return out


def belt_figures(scene, rtol=RTOL, max_step=MAX_STEP):
    """The belt's figures (period, x_max, stick, slip, cycles: `Belt.measure_cycle` on the
    monolithic solution sampled every SAMPLE s)."""
    from .master import Result
    args = scene.law_parameters()
    pieces, _ = belt_solution(*args, scene.t_end, rtol, max_step)
    t = np.linspace(0.0, scene.t_end, int(round(scene.t_end / SAMPLE)) + 1)
    x = sample(pieces, t)
    res = Result(t=t, p=x[:, :1], u=x[:, 1:2], failed=None)
    return scene.measure_cycle(res)


def convergence(scene):
    """The reference's figures at the chosen settings and at looser ones (rtol × 10, × 100;
    steps of at most 2e-4 s): the largest relative change of period and x_max against the
    chosen settings, per variant."""
    best = belt_figures(scene)
    rows = []
    for rtol, max_step in ((RTOL * 10, MAX_STEP), (RTOL * 100, MAX_STEP), (RTOL, 2 * MAX_STEP)):
        f = belt_figures(scene, rtol, max_step)
        change = max(abs(f[k] - best[k]) / best[k] for k in ("period", "x_max"))
        rows.append({"rtol": rtol, "max_step": max_step, "period": f["period"],
                     "x_max": f["x_max"], "change": change})
    return best, rows
