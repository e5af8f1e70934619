"""Scenes of docs/cosim.md with their reference answers and error measures, for the master in
master.py. Each scene says which FMU hosts it (the smallest variant that can), how the body is
modelled, the reference answer (closed form or an independent computation) and, next to it, how a
run is measured against it (`measure`, returning the figures and one scalar `error`).

Scenes: belt (§1), puck0 / puck1 (§4, friction.coupling 0 / 1), bounce (§5), bushing_freq and
bushing_energy (§6), oscillator (§7, with the closed-form amplification matrices of the four
methods for the stability map).
"""
from __future__ import annotations

import functools
import math

import numpy as np

from fmpy.fmi1 import FMICallException

from .master import (ALL_METHODS, AxesBody, Connector, CosimFailure, Coupled, RigidBody,
                     connector_args, expm, quat_exp, quat_log)

G = 9.81
IDENTITY = {"w": 1.0, "x": 0.0, "y": 0.0, "z": 0.0}


def node_inputs(node, r=(0.0, 0.0, 0.0), q=(1.0, 0.0, 0.0, 0.0), v=(0.0, 0.0, 0.0),
                w=(0.0, 0.0, 0.0), orientation=True, angular=True):
    d = {f"{node}.r[{i + 1}]": float(r[i]) for i in range(3)}
    d.update({f"{node}.v[{i + 1}]": float(v[i]) for i in range(3)})
    if orientation:
        d.update({f"{node}.q.{c}": float(x) for c, x in zip("wxyz", q)})
    if angular:
        d.update({f"{node}.w[{i + 1}]": float(w[i]) for i in range(3)})
    return d


def crossings(t, x, level, direction=+1):
    """Times where x crosses `level` in `direction` (+1 up, -1 down), linearly interpolated."""
    s = direction * (np.asarray(x) - level)
    i = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    return t[i] + (t[i + 1] - t[i]) * s[i] / (s[i] - s[i + 1])


class Scene:
    name = ""
    title = ""
    variant = ""
    t_end = 1.0
    blowup = 1e6                    # |velocity| beyond this = blown up
    sweep = ()                      # macro steps H of the work-precision chart
    tol = 1e-10                     # rollback tolerance (m, rad)
    max_iter = 50                   # rollback passes
    theta = 1.0                     # linear-implicit θ
    record = ()                     # extra outputs sampled at the body state
    error_label = "error"
    error2_label = None             # a second error measure (e.g. against the FMU's own model)
    error_rigid_label = None        # the error against a rigid closed form, beside `error`

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def method_options(self, method):
        return {"theta": self.theta, "tol": self.tol, "max_iter": self.max_iter}

    def after_init(self, fmu):
        pass

    fine = None                     # (method, H) of the reference task, when the scene has one

    def fine_reference(self, unzipdir=None):
        """The figures of the scene's reference (run by the sweep's reference task): here, a fine
        run of `fine`; a scene with an independent reference overrides this."""
        from .master import simulate
        return self.measure(simulate(self, *self.fine, unzipdir=unzipdir))


# =================================================================================================
# §1 belt stick–slip (Planar)
# =================================================================================================
class Belt(Scene):
    """Mass m on a belt moving along e2a at v_b, spring k to ground (part of the master's body).
    PLANAR: node a = the belt (a.r[2] = v_b t), node b = the mass (y = b.r[2]); the normal load
    m g is the internal contact force friction.Fint (the plane is at b's initial position, so b
    stays in it and loads nothing normal to it; a master that cannot press b after
    initialization, as an SSP system's, sets the same). μ_s = 0.5, μ_k = 0.3 with a sharp
    exponential decay d_c (friction.decay) for the static/kinetic step. The stick spring
    (k_s = 1e6 N/m) is critically damped for the 1 kg mass (friction.stickDamping = 2 sqrt(k_s m)):
    without it, it rings at re-stick and breaks away early (docs/cosim.md, finding 2).

    Truth (`error`): the FMU's model in continuous time, body and friction law integrated together
    (reference.py, the monolithic reference; its figures come to a run as `fine_values`, from the
    sweep's reference task, or are computed here). Beside it (`error_rigid`): the rigid
    Karnopp-type closed form (docs/cosim.md, scene 1): stick 2Δ/v_b, slip (π + 2β)/ω, period,
    x_max = x_k + sqrt(Δ² + (v_b/ω)²), from which the model's own cycle lies 2.6e-5 away (x_max).
    Measured: after the first breakaway, period = mean interval between upward crossings of
    y = x_k (they fall in the stick phase); x_max = mean of the cycle maxima (3-point parabola);
    breakaway = upward crossing of x_s, re-stick = upward crossing of x_k − Δ, so
    slip = re-stick − breakaway and stick = breakaway − previous re-stick.
    error = max(|ΔT|/T, |Δx_max|/x_max) against the reference, error_rigid against the closed
    form."""

    name, title, variant = "belt", "§1 belt stick-slip (Planar)", "Planar"
    m, k, vb, mus, muk = 1.0, 100.0, 0.2, 0.5, 0.3
    decay = 1e5                     # s/m: μ within 1 % of μ_k above 46 µm/s
    k_stick = 1e6                   # N/m (the FMU's default)
    c_stick = 2e3                   # N.s/m: 2 sqrt(k_stick m), the stick critically damped
    t_end = 3.5
    sweep = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5)
    tol = 1e-10
    error_label = ("against the FMU model in continuous time (monolithic reference):\n"
                   "max(|ΔT|/T, |Δx_max|/x_max)")
    error_rigid_label = "against the rigid closed form (Karnopp): max(|ΔT|/T, |Δx_max|/x_max)"

    @property
    def params(self):
        return {"friction.muStatic": self.mus, "friction.muKinetic": self.muk,
                "friction.decay": self.decay, "friction.stickStiffness": self.k_stick,
                "friction.stickDamping": self.c_stick, "friction.Fint": self.m * G}

    def law_parameters(self):
        """(m, k, v_b, μ_s, μ_k, d_c, k_s, c_s, N) of the monolithic reference."""
        return (self.m, self.k, self.vb, self.mus, self.muk, self.decay, self.k_stick,
                self.c_stick, self.m * G)

    def reference(self):
        N = self.m * G
        xs, xk = self.mus * N / self.k, self.muk * N / self.k
        D, w = xs - xk, math.sqrt(self.k / self.m)
        beta = math.atan(self.vb / (w * D))
        stick, slip = 2 * D / self.vb, (math.pi + 2 * beta) / w
        return {"stick": stick, "slip": slip, "period": stick + slip,
                "x_max": xk + math.hypot(D, self.vb / w), "x_s": xs, "x_k": xk, "delta": D}

    def body(self):
        return AxesBody([("r", 2)], [self.m], k_ground=[self.k], node_a=(2, self.vb))

    def init_inputs(self):
        return {**node_inputs("a", v=(0, self.vb, 0)), **node_inputs("b", v=(0, self.vb, 0))}

    def initial_state(self):
        return [0.0], [self.vb]

    fine = ("monolithic", 1e-4)       # the reference task: reference.py (`fine_reference`)
    fine_values = None

    def fine_reference(self, unzipdir=None):
        """The monolithic reference's figures (the truth `error` is measured against)."""
        from .reference import belt_figures
        return belt_figures(self)

    def measure_cycle(self, res):
        """Period, x_max, stick, slip and the number of cycles of a run (see the class)."""
        ref = self.reference()
        t, y = res.t, res.p[:, 0]
        out = {"period": np.nan, "x_max": np.nan, "stick": np.nan, "slip": np.nan, "cycles": 0}
        brk = crossings(t, y, ref["x_s"])
        if res.failed is None and len(brk) >= 3:
            t0 = brk[0]
            up = crossings(t, y, ref["x_k"])
            up = up[up > t0]
            restick = crossings(t, y, ref["x_k"] - ref["delta"])
            restick = restick[restick > t0]
            i = np.nonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (t[1:-1] > t0))[0] + 1
            a, b, c = y[i - 1], y[i], y[i + 1]
            den = a - 2 * b + c
            peaks = b - 0.125 * (a - c) ** 2 / np.where(den == 0, -1e-300, den)
            if len(up) >= 2 and len(peaks) and len(restick):
                out["period"] = float(np.mean(np.diff(up)))
                out["x_max"] = float(np.mean(peaks))
                out["cycles"] = len(up) - 1
                slips = [r - b_ for b_ in brk for r in restick[restick > b_][:1]]
                sticks = [b_ - r for r in restick for b_ in brk[brk > r][:1]]
                out["slip"] = float(np.mean(slips)) if slips else np.nan
                out["stick"] = float(np.mean(sticks)) if sticks else np.nan
        return out

    def measure(self, res):
        out = self.measure_cycle(res)
        if self.fine_values is None:
            self.fine_values = self.fine_reference()
        for name, ref in (("", self.fine_values), ("_rigid", self.reference())):
            for key in ("period", "x_max", "stick", "slip"):
                out[f"err{name}_{key}"] = abs(out[key] - ref[key]) / ref[key]
            out[f"error{name}"] = max(out[f"err{name}_period"], out[f"err{name}_x_max"])
        return out


# =================================================================================================
# §4 puck sliding and spinning (Planar)
# =================================================================================================
class Puck(Scene):
    """Uniform disc (R, m, J = m R²/2) sliding along e2a at v0 and spinning about e1a at ω0 on
    the plane of node a. PLANAR, 2 dof: y = b.r[2] and α (b.q = rotation about x); normal load
    m g as the internal contact loads friction.Fint = m g and friction.Mint = (2/3) R m g (so
    F_NC = m g and M_NR1 = (2/3) R m g as the seed's formulas give for a disc pressed by its
    weight; b stays in the plane it starts in), μ = 0.3 without decay.

    coupling 0 — truth (`error`): the FMU's model in continuous time, the elastic closed forms
    (docs/cosim.md, scene 4): the puck starts sticking on the stick springs k_s, k_r and breaks
    away at t_b = asin(μ m g ω/(k_s v0))/ω, ω = √(k_s/m), so that sliding stops at
    t_v = t_b + v0 cos(ω t_b)/(μ g); spin likewise with J, k_r and M_R = (2/3) R μ m g. Beside it
    (`error_rigid`): the rigid forms t_v = v0/(μ g), t_ω = 3 R ω0/(4 μ g), their limit as the
    stick stiffnesses grow.
    coupling 1 — reference (physics of a uniform-pressure disc, Farkas et al. 2003, computed
    here independently by quadrature over the disc, `disc_reference`): both stop at the same
    instant t_stop and v/(R ω) → 0.653. Beside it, what the FMU's law (the disc's direction on
    the ellipsoidal limit surface) gives in continuous time (`disc_reference(..., "ellipsoid")`):
    the same ratios, t_stop shorter (the ellipsoid lies up to 7 % outside the disc's surface).
    Measured: t_v, t_ω = first zero crossings of v and ω (linear interpolation);
    t_stop = t_v, stop_gap = |t_v − t_ω|; ratio = v/(R ω) where v = RATIO_AT·v0 (also
    reported where v = 0.3, 0.1, 0.05 v0).
    error (coupling 0) = max(|Δt_v|/t_v, |Δt_ω|/t_ω) against the elastic forms, error_rigid
    against the rigid ones;
    (coupling 1) error = |Δt_stop|/t_stop against the disc, error2 = against the FMU's model;
    err_ratio = |ratio − 0.653|/0.653."""

    variant = "Planar"
    m, R, mu, v0, w0 = 1.0, 0.1, 0.3, 1.0, 5.0
    coupling = 0
    t_end = 0.5
    sweep = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5)
    tol = 1e-10
    k_stick, k_stick_r1 = 1e6, 1e4          # the FMU's defaults

    @property
    def name(self):
        return f"puck{self.coupling}"

    @property
    def title(self):
        return f"§4 puck, friction.coupling = {self.coupling} (Planar)"

    @property
    def error_label(self):
        return ("against the elastic closed forms (the FMU's model): max(|Δt_v|/t_v, |Δt_ω|/t_ω)"
                if self.coupling == 0
                else "stop time against the exact disc (physics): |Δt_stop|/t_stop")

    @property
    def error_rigid_label(self):
        return ("against the rigid closed forms: max(|Δt_v|/t_v, |Δt_ω|/t_ω)"
                if self.coupling == 0 else None)

    @property
    def error2_label(self):
        return (None if self.coupling == 0
                else "stop time against the FMU's law in continuous time: |Δt_stop|/t_stop")

    @property
    def J(self):
        return 0.5 * self.m * self.R ** 2

    @property
    def params(self):
        return {"friction.muStatic": self.mu, "friction.muKinetic": self.mu, "friction.R": self.R,
                "friction.coupling": self.coupling, "friction.stickStiffness": self.k_stick,
                "friction.stickStiffnessR1": self.k_stick_r1, "friction.Fint": self.m * G,
                "friction.Mint": 2.0 / 3.0 * self.R * self.m * G}

    def reference(self):
        if self.coupling == 0:
            return {"t_v": self.v0 / (self.mu * G), "t_w": 3 * self.R * self.w0 / (4 * self.mu * G),
                    **self.elastic_reference()}
        eps0 = self.v0 / (self.R * self.w0)
        rate = self.mu * G / (self.R * self.w0)
        d = disc_reference(eps0, rate, self.RATIO_AT)
        e = disc_reference(eps0, rate, self.RATIO_AT, "ellipsoid")
        return {"t_stop": d["t_stop"], "ratio": d["ratio"], "ratio_limit": 0.653,
                "t_stop_model": e["t_stop"], "ratio_model": e["ratio"]}

    def elastic_reference(self):
        """The elastic closed forms (coupling 0): each effect sticks on its spring from t = 0 (an
        undamped oscillator, ω = √(k/inertia)) until its force reaches the limit L at
        t_b = asin(L ω/(k v0))/ω, then decelerates at L/inertia from v0 cos(ω t_b)."""
        def stop(inertia, k, v0, limit):
            w = math.sqrt(k / inertia)
            tb = math.asin(limit * w / (k * v0)) / w
            return tb + inertia * v0 * math.cos(w * tb) / limit
        return {"t_v_elastic": stop(self.m, self.k_stick, self.v0, self.mu * self.m * G),
                "t_w_elastic": stop(self.J, self.k_stick_r1, self.w0,
                                    2.0 / 3.0 * self.R * self.mu * self.m * G)}

    def model_ratio(self, v_frac):
        """v/(R ω) of the FMU's law (`disc_reference(..., "ellipsoid")`) where v = v_frac·v0."""
        rate = self.mu * G / (self.R * self.w0)
        return disc_reference(self.v0 / (self.R * self.w0), rate, v_frac, "ellipsoid")["ratio"]

    def body(self):
        return AxesBody([("r", 2), ("w", 1)], [self.m, self.J])

    def init_inputs(self):
        return {**node_inputs("a"), **node_inputs("b", v=(0, self.v0, 0), w=(self.w0, 0, 0))}

    def initial_state(self):
        return [0.0, 0.0], [self.v0, self.w0]

    RATIO_AT = 1e-3            # v/(R ω) is read where v has fallen to this fraction of v0
                               # (the exact disc gives 0.661 there, 0.653 in the limit)

    def measure(self, res):
        ref = self.reference()
        t, v, w = res.t, res.u[:, 0], res.u[:, 1]
        tv, tw = crossings(t, v, 0.0, -1), crossings(t, w, 0.0, -1)
        out = {"t_v": tv[0] if len(tv) else np.nan, "t_w": tw[0] if len(tw) else np.nan}
        if res.failed is not None:
            out["t_v"] = out["t_w"] = np.nan
        if self.coupling == 0:
            for name, sfx in (("", "_elastic"), ("_rigid", "")):
                for key in ("t_v", "t_w"):
                    out[f"err{name}_{key}"] = abs(out[key] - ref[key + sfx]) / ref[key + sfx]
                out[f"error{name}"] = max(out[f"err{name}_t_v"], out[f"err{name}_t_w"])
            return out
        for frac in (0.3, 0.1, 0.05, self.RATIO_AT):
            tr = crossings(t, v, frac * self.v0, -1)
            ratio = np.nan
            if len(tr) and res.failed is None:
                wr = np.interp(tr[0], t, w)
                ratio = frac * self.v0 / (self.R * wr) if wr > 0 else np.inf
            out[f"ratio_at_v{frac:g}"] = ratio
        t_stop = out["t_v"]
        out.update({"t_stop": t_stop, "stop_gap": abs(out["t_v"] - out["t_w"]), "ratio": ratio,
                    "err_ratio": abs(ratio - ref["ratio_limit"]) / ref["ratio_limit"],
                    "err_physics": abs(t_stop - ref["t_stop"]) / ref["t_stop"],
                    "err_model": abs(t_stop - ref["t_stop_model"]) / ref["t_stop_model"]})
        out["error"], out["error2"] = out["err_physics"], out["err_model"]
        return out


@functools.lru_cache(maxsize=None)
def _disc_table():
    """Friction force f(ε) (along v) and moment m(ε) of a uniform-pressure disc of unit radius
    and unit μN, sliding at ε and spinning at 1 (midpoint quadrature, 200 × 400 cells; the
    figures it gives move by < 2e-5 against 400 × 800)."""
    nr, nt = 200, 400
    r = (np.arange(nr) + 0.5) / nr
    th = (np.arange(nt) + 0.5) / nt * 2 * np.pi
    rr, tt = np.meshgrid(r, th, indexing="ij")
    sy, sz = rr * np.cos(tt), rr * np.sin(tt)
    dA = (rr / nr) * (2 * np.pi / nt) / np.pi
    eps = np.concatenate(([0.0], np.geomspace(1e-4, 1e4, 401)))
    f, m = np.empty_like(eps), np.empty_like(eps)
    for i, e in enumerate(eps):
        uy, uz = e - sz, sy                                # velocity of the contact point
        n = np.hypot(uy, uz)
        f[i] = np.sum(dA * uy / n)
        m[i] = np.sum(dA * (sy * uz - sz * uy) / n)
    return eps, f, m


@functools.lru_cache(maxsize=None)
def disc_reference(eps0, rate, v_frac, surface="disc"):
    """Uniform disc (J = m R²/2) sliding and spinning from ε0 = v0/(R ω0), in continuous time.
    surface = "disc": the exact Contensou friction (physics); "ellipsoid": what the FMU's
    friction.coupling = 1 gives in steady slip, the disc's direction (f, m) ∥ (F̂, M̂) scaled onto
    the ellipsoid |(f, m/ρ)| = μN, ρ = 2R/3 (in units of μN, μNR: (F̂, M̂)/|(F̂, 1.5 M̂)|).
    In the scaled time s = rate·t (rate = μ g/(R ω0)) the scaled speeds V = v/(R ω0),
    W = ω/ω0 obey V' = −f(V/W), W' = −2 m(V/W) (RK4, f and m interpolated in `_disc_table`).
    Returns the stop time (s), v/(R ω) where v = v_frac·v0, and the last ratio before the stop."""
    eps_t, f_t, m_t = _disc_table()
    if surface == "ellipsoid":
        n = np.hypot(f_t, 1.5 * m_t)
        f_t, m_t = f_t / n, m_t / n

    def rhs(y):
        e = y[0] / y[1]
        return np.array([-np.interp(e, eps_t, f_t), -2.0 * np.interp(e, eps_t, m_t)])

    y, s, at = np.array([eps0, 1.0]), 0.0, None
    while y[0] > 1e-6 * eps0 and y[1] > 1e-6:
        d = rhs(y)
        h = min(1e-3, 0.05 * min(y[0] / -d[0], y[1] / -d[1]))
        k2 = rhs(y + 0.5 * h * d)
        k3 = rhs(y + 0.5 * h * k2)
        k4 = rhs(y + h * k3)
        y1 = y + h / 6 * (d + 2 * k2 + 2 * k3 + k4)
        if at is None and y1[0] <= v_frac * eps0:
            a = (y[0] - v_frac * eps0) / (y[0] - y1[0])
            at = v_frac * eps0 / (y[1] + a * (y1[1] - y[1]))
        y, s = y1, s + h
    return {"t_stop": s / rate, "ratio": at, "ratio_last": float(y[0] / y[1])}


# =================================================================================================
# §5 bounce on a stop (RadialThrust, axial component l)
# =================================================================================================
class Bounce(Scene):
    """Mass m moving along e3a (RADIAL-THRUST axial position l = b.r[3], radial offset fixed at
    r0) at v0 towards the lower stop on l (stop.lower3), penalty stiffness k, damping c, no
    other force. The clipped stop (docs/physics.md, Stops: F = max(0, k p + c ṗ)) lets go when k p + c ṗ = 0,
    before the penetration p returns to 0.

    Reference (closed form, linear damped oscillator, ω_d = ω_n sqrt(1 − ζ²), σ = ζ ω_n):
      force-contact time t_c = (π − 2 asin ζ)/ω_d (where k p + c ṗ = 0),
      restitution e = |ṗ(t_c)|/v0 (the clipped stop's; SCENES gives e_lin = exp(−πζ/sqrt(1−ζ²))
      for the stop that would pull until p = 0, and π/ω_d for its duration),
      geometric contact time t_geo = t_c + p(t_c)/|ṗ(t_c)| (l below the stop position).
    Measured: t_geo = time between the downward and the upward crossing of l = stop.lower3
    (both in free flight, so linear interpolation is exact there), e = rebound speed/v0
    (free flight afterwards). error = max(|Δt_geo|/t_geo, |Δe|/e)."""

    title, variant = "§5 bounce on a stop (RadialThrust, axial)", "RadialThrust"
    m, k, zeta, v0 = 1.0, 1e4, 0.1, 1.0
    l0, lower, r0 = 0.1 + math.pi * 1e-3, 0.05, 0.1    # contact at t = 0.0531..., off the grid
    t_end = 0.1
    sweep = (2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5)
    tol = 1e-12
    theta = 0.5                # the contact oscillation is the physics here: no numerical damping
    error_label = "against the clipped-stop closed form: max(|Δt_geo|/t_geo, |Δe|/e)"

    @property
    def name(self):
        return "bounce"

    @property
    def c(self):
        return 2 * self.zeta * math.sqrt(self.k * self.m)

    @property
    def params(self):
        return {"stop.lower3": self.lower, "stop.stiffness": self.k, "stop.damping": self.c}

    def reference(self):
        wn = math.sqrt(self.k / self.m)
        z = self.zeta
        wd, sig = wn * math.sqrt(1 - z * z), z * wn
        tc = (math.pi - 2 * math.asin(z)) / wd
        p = self.v0 / wd * math.exp(-sig * tc) * math.sin(wd * tc)
        pd = self.v0 * math.exp(-sig * tc) * (math.cos(wd * tc) - sig / wd * math.sin(wd * tc))
        return {"t_c": tc, "e": abs(pd) / self.v0, "t_geo": tc + p / abs(pd),
                "t_lin": math.pi / wd, "e_lin": math.exp(-math.pi * z / math.sqrt(1 - z * z))}

    def body(self):
        return AxesBody([("r", 3)], [self.m])

    def init_inputs(self):
        return {**node_inputs("a"),
                **node_inputs("b", r=(self.r0, 0, self.l0), v=(0, 0, -self.v0),
                              orientation=False, angular=False)}

    def initial_state(self):
        return [self.l0], [-self.v0]

    def measure(self, res):
        ref = self.reference()
        t, l, v = res.t, res.p[:, 0], res.u[:, 0]
        down, up = crossings(t, l, self.lower, -1), crossings(t, l, self.lower, +1)
        out = {"t_geo": np.nan, "e": np.nan}
        if res.failed is None and len(down) and len(up) and v[-1] > 0:
            out["t_geo"] = up[0] - down[0]
            out["e"] = v[-1] / self.v0
        out["err_t_geo"] = abs(out["t_geo"] - ref["t_geo"]) / ref["t_geo"]
        out["err_e"] = abs(out["e"] - ref["e"]) / ref["e"]
        out["error"] = max(out["err_t_geo"], out["err_e"])
        return out


# =================================================================================================
# §6 bushing oscillator (Bushing, rigid body in 3-D)
# =================================================================================================
class BushingFreq(Scene):
    """Rigid body (m, J = diag(J1, J2, J3)) on a Bushing to ground: node a fixed at the origin,
    node b = the body's centre and principal frame (rest: origin, identity; references = the
    initial geometry). Released from a small combined deflection (1e-6 m along, 1e-5 rad about
    each axis), no damping. The master integrates the full 3-D rigid body (RK4).

    Reference (linearised, docs/cosim.md, scene 6): ω_i = sqrt(k_i/m), ω_(3+i) = sqrt(k_(3+i)/J_i).
    Measured: each coordinate (r_i, rotation vector component i) oscillates at its own
    frequency to first order; ω = π·(crossings − 1)/(last − first zero crossing).
    error = max_i |Δω_i|/ω_i."""

    name, title, variant = "bushing_freq", "§6 bushing, small amplitude (Bushing)", "Bushing"
    m, J = 1.0, (0.01, 0.02, 0.03)
    omega = (10.0, 14.0, 18.0, 12.0, 16.0, 20.0)       # target frequencies (rad/s)
    amp_t, amp_r = 1e-6, 1e-5  # m, rad: small, and the lever-arm coupling O(amp_t² k_t/(amp_r k_r))
                               # and the half-rotation of the centred triad O(amp_r) stay < 1e-5
    t_end = 2.0
    blowup = 100.0
    sweep = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4)
    tol = 1e-13
    error_label = "small-amplitude frequencies: max_i |Δω_i|/ω_i"
    theta = 0.5

    @property
    def stiffness(self):
        inert = (self.m, self.m, self.m) + tuple(self.J)
        return [w * w * i for w, i in zip(self.omega, inert)]

    @property
    def params(self):
        return {f"elasticity.k{k + 1}": v for k, v in enumerate(self.stiffness)}

    def reference(self):
        return {f"w{k + 1}": w for k, w in enumerate(self.omega)}

    def body(self):
        return RigidBody(self.m, self.J)

    def init_inputs(self):
        return {**node_inputs("a"), **node_inputs("b")}

    def initial_state(self):
        q = quat_exp(np.full(3, self.amp_r))
        return np.concatenate((np.full(3, self.amp_t), q)), np.zeros(6)

    def measure(self, res):
        t = res.t
        coords = np.column_stack((res.p[:, :3], np.array([quat_log(q) for q in res.p[:, 3:]])))
        out, errs = {}, []
        for k in range(6):
            z = np.concatenate((crossings(t, coords[:, k], 0.0, -1), crossings(t, coords[:, k], 0.0, +1)))
            z.sort()
            w = math.pi * (len(z) - 1) / (z[-1] - z[0]) if len(z) >= 3 and res.failed is None else np.nan
            out[f"w{k + 1}"] = w
            errs.append(abs(w - self.omega[k]) / self.omega[k])
        out["error"] = max(errs)
        return out


class BushingEnergy(BushingFreq):
    """The same body and Bushing released from a large combined flexion–torsion rotation
    (rotation vector (0.6, 0.4, 1.2) rad), no damping. Reference: the energy E = kinetic (master)
    + energy.stored (FMU, read at the body state) is conserved. error = max |E − E0|/E0 over the
    run. (With damping the FMU's energy.damping would be added.)"""

    name, title = "bushing_energy", "§6 bushing, large rotation (Bushing)"
    rotation = (0.6, 0.4, 1.2)
    record = ("energy.stored",)
    error_label = "energy (kinetic + energy.stored): max |E − E0| / E0"
    tol = 1e-10

    def initial_state(self):
        return np.concatenate((np.zeros(3), quat_exp(np.array(self.rotation)))), np.zeros(6)

    def reference(self):
        return {"drift": 0.0}

    def measure(self, res):
        body = self.body()
        E = np.array([body.kinetic(p, u) for p, u in zip(res.p, res.u)]) + res.extra[:, 0]
        drift = float(np.max(np.abs(E - E[0])) / E[0]) if res.failed is None else np.nan
        return {"E0": float(E[0]), "drift": drift, "error": drift}


class BushingPendulum(BushingFreq):
    """A rigid body hanging under gravity on a Bushing from a fixed node a: its centre of mass
    (node b) 0.2 m below node a, the Bushing's springs at their reference (the initial geometry),
    set moving by an initial spin (2, 1, 0.5) rad/s; it sags under its weight and swings and
    turns on the Bushing's translational (400 N/m) and rotational springs, no damping.
    Reference: the energy E = kinetic + gravity's potential −m g·(r − r0) (master) +
    energy.stored (FMU) is conserved: E0 is the spin's kinetic energy. error = max |E − E0|/E0. The scene an SSP system of the
    connector and the Body FMU reproduces in third-party masters (docs/ssp.md)."""

    name, title = "bushing_pendulum", "§6 bushing pendulum under gravity (Bushing)"
    gravity = (0.0, 0.0, -G)
    hang = 0.2                          # m: node b below node a
    spin = (2.0, 1.0, 0.5)              # rad/s, W
    record = ("energy.stored",)
    error_label = "energy (kinetic + potential + energy.stored): max |E − E0| / E0"
    tol = 1e-10
    sweep = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4)

    @property
    def stiffness(self):
        return [400.0, 400.0, 400.0, 1.0, 2.0, 3.0]

    def body(self):
        return RigidBody(self.m, self.J, gravity=self.gravity)

    def init_inputs(self):
        return {**node_inputs("a"), **node_inputs("b", r=(0.0, 0.0, -self.hang), w=self.spin)}

    def initial_state(self):
        p = np.concatenate(([0.0, 0.0, -self.hang], [1.0, 0.0, 0.0, 0.0]))
        return p, np.concatenate((np.zeros(3), self.spin))

    def reference(self):
        return {"drift": 0.0}

    def measure(self, res):
        body = self.body()
        # gravity's potential from the start position: E0 is the energy the spin put in
        p0 = body.potential(res.p[0])
        E = (np.array([body.kinetic(p, u) + body.potential(p) - p0 for p, u in zip(res.p, res.u)])
             + res.extra[:, 0])
        drift = float(np.max(np.abs(E - E[0])) / E[0]) if res.failed is None else np.nan
        return {"E0": float(E[0]), "drift": drift, "error": drift}


# =================================================================================================
# §7 stability: mass on a connector spring-damper (RadialThrust, axial component l)
# =================================================================================================
class Oscillator(Scene):
    """Mass m on the connector's axial spring k and damper c (RADIAL-THRUST l = b.r[3], radial
    offset r0 fixed; elasticity.k3, damping.c3; reference = the initial geometry l0). The map of
    one macro step (x, v) → (x', v') is linear; it is measured through the FMU column by column
    (`one_step_map`) and its spectral radius decides stability."""

    name, title, variant = "oscillator", "§7 oscillator (RadialThrust, axial)", "RadialThrust"
    m, k, zeta = 1.0, 1e4, 0.0
    l0, r0 = 0.1, 0.1
    tol = 1e-12
    max_iter = 2000
    theta = 1.0

    @property
    def omega(self):
        return math.sqrt(self.k / self.m)

    @property
    def params(self):
        return {"elasticity.k3": self.k, "damping.c3": 2 * self.zeta * math.sqrt(self.k * self.m)}

    def body(self):
        return AxesBody([("r", 3)], [self.m])

    def init_inputs(self):
        return {**node_inputs("a"), **node_inputs("b", r=(self.r0, 0, self.l0),
                                                  orientation=False, angular=False)}

    x0 = 1e-3                   # initial stretch (m) for plain runs

    def initial_state(self):
        return [self.l0 + self.x0], [0.0]


class OneStepMap:
    """The map (x, v/ω) → (x', v'/ω) of one macro step of `method` on the §7 oscillator, measured
    through the FMU: one step from each unit state (amplitude `amp`), the FMU state restored to
    the initialised one in between. Call with h = ω H; `rho(h)` = its spectral radius (∞ when the
    method fails: the FMU refuses, rollback does not converge)."""

    amp = 1.0

    def __init__(self, method, zeta, unzipdir=None, **kw):
        self.osc = Oscillator(zeta=zeta, **kw)
        body = self.osc.body()
        params = dict(self.osc.params)
        params["cosim.extrapolation"], acc = connector_args(method, body)
        self.fmu = Connector(self.osc.variant, params, self.osc.init_inputs(), body.in_names,
                             body.load_names, unzipdir=unzipdir, acc_names=acc)
        self.c = Coupled(body, self.fmu, *self.osc.initial_state(), **self.osc.method_options(method))
        self.c.fresh = False          # a step between events: the map the methods iterate
        self.c.since_event = 10 ** 9  # (no restart schedule)
        self.s0 = self.fmu.s.getFMUstate()
        self.step = ALL_METHODS[method]
        self.evaluations = 0

    def __call__(self, h):
        w, l0, a = self.osc.omega, self.osc.l0, self.amp
        A = np.empty((2, 2))
        for j, (x, y) in enumerate(((1.0, 0.0), (0.0, 1.0))):
            self.fmu.s.setFMUstate(self.s0)
            self.c.p[0], self.c.u[0] = l0 + a * x, a * w * y
            self.step(self.c, 0.0, h / w)
            A[:, j] = (self.c.p[0] - l0) / a, self.c.u[0] / (w * a)
        self.evaluations += 1
        return A

    def rho(self, h):
        try:
            return spectral_radius(self(h))
        except (CosimFailure, FMICallException, np.linalg.LinAlgError):
            return math.inf

    def close(self):
        self.fmu.s.freeFMUstate(self.s0)
        self.fmu.close()


def amplification(method, h, zeta, theta=1.0):
    """Closed-form one-step map of each method on x'' = −x − 2ζ x' (ω = 1, step h), the body
    integrated exactly for the load the method gives it (as master.py does)."""
    F = lambda x, v: -x - 2 * zeta * v                       # noqa: E731
    cols = []
    for x, v in ((1.0, 0.0), (0.0, 1.0)):
        Q0 = F(x, v)
        if method == "zoh":
            Q1 = Q0
        elif method == "extrapolation":
            Q1 = F(x + h * v + h * h / 2 * Q0, v + h * Q0)
        elif method == "linear_exact_ev":      # exact for the linear connector
            cols.append(tuple(expm(np.array([[0.0, h], [-h, -2 * zeta * h]])) @ [x, v]))
            continue
        elif method in ("linear_path_ev", "implicit_path_ev"):
            # the trapezoidal rule on the path (x += h v + ½ a h², v += a h) with the load's
            # stiffness and damping prewarped: the eigenvalues λ of x'' = −x − 2ζx' become
            # (2/h) tanh(hλ/2) (kept as they are where |Im hλ| > 2.5); exact for this linear load,
            # so the iterated method's map is the same
            lam = np.roots([1.0, 2 * zeta, 1.0]).astype(complex)
            if np.all(np.abs((h * lam).imag) <= 2.5):
                lam = (2.0 / h) * np.tanh(0.5 * h * lam)
            k, d = (lam[0] * lam[1]).real, -(lam[0] + lam[1]).real    # Q' = −k x − d v
            a = (-k * x - d * v - 0.5 * h * k * v) / (1 + 0.5 * h * d + 0.25 * h * h * k)
            cols.append((x + h * v + 0.5 * h * h * a, v + h * a))
            continue
        elif method == "linear_implicit":
            du = h * ((1 - theta) * Q0 + theta * F(x + h * v, v)) / (1 + theta * h * 2 * zeta + theta ** 2 * h * h)
            cols.append((x + h * (v + theta * du), v + du))
            continue
        elif method == "rollback":     # converged: Newmark β = 1/6, γ = 1/2
            # x1 = x + h v + h²/6 (2 Q0 + Q1), v1 = v + h/2 (Q0 + Q1), Q1 = F(x1, v1)
            A = np.array([[1 + h * h / 6, 2 * zeta * h * h / 6], [h / 2, 1 + zeta * h]])
            x1, v1 = np.linalg.solve(A, [x + h * v + h * h / 3 * Q0, v + h / 2 * Q0])
            cols.append((x1, v1))
            continue
        cols.append((x + h * v + h * h / 6 * (2 * Q0 + Q1), v + h / 2 * (Q0 + Q1)))
    return np.array(cols).T


def spectral_radius(A):
    return float(np.max(np.abs(np.linalg.eigvals(A))))


def bound_closed_form(method, zeta):
    """Largest stable ωH from docs/cosim.md, scene 7 (zoh, rollback) or from `amplification` (others)."""
    if method == "zoh":
        return 0.0 if zeta == 0 else min(4 * zeta, 1 / zeta)
    if method == "rollback":                 # iteration contraction h²/6 + ζ h < 1
        return 3 * (-zeta + math.sqrt(zeta * zeta + 4 / 6))
    return largest_stable(lambda h: spectral_radius(amplification(method, h, zeta)) <= 1 + 1e-12)


def largest_stable(stable, h_lo=1e-3, h_hi=1e3, n=61, rel=1e-4):
    """Largest h on a log grid [h_lo, h_hi] before the first unstable point, refined by
    bisection; 0 if h_lo is unstable, h_hi if all are stable."""
    grid = np.geomspace(h_lo, h_hi, n)
    last = 0.0
    for h in grid:
        if not stable(h):
            if last == 0.0:
                return 0.0
            lo, hi = last, h
            while hi / lo - 1 > rel:
                mid = math.sqrt(lo * hi)
                lo, hi = (mid, hi) if stable(mid) else (lo, mid)
            return lo
        last = h
    return h_hi


SCENES = {s.name: s for s in (Belt(), Puck(coupling=0), Puck(coupling=1), Bounce(),
                              BushingFreq(), BushingEnergy(), BushingPendulum())}
