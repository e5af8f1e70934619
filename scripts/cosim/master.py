"""A small co-simulation master: the master owns a body, the connector FMU returns the load the
connector exerts on node b, and a coupling method advances both over a macro step H. This file
is the registry of the methods and the master's loop (`simulate`); the parts:

  connectors.py     the connector FMU with every per-step call prepared (FMI 2.0 and 3.0)
  bodies.py         the bodies and their integration under a ramped load
  coupling.py       the coupled system and the methods without event location:
                    zoh, jacobi, extrapolation, linear_implicit, rollback
  event_methods.py  the event-located methods: linear_path_ev, implicit_path_ev,
                    linear_exact_ev (METHOD@fmi3: through the FMI 3.0 FMU with early return)

The names the scenes, the sweep engine and the tests import stay available from here.
"""
from __future__ import annotations

import time

import numpy as np
from fmpy.fmi1 import FMICallException

from . import event_methods
from .bodies import AxesBody, RigidBody, quat_exp, quat_log, quat_matrix, quat_mul  # noqa: F401
from .connectors import (DIST, FMI3, REPO, Connector, Connector3, CosimFailure,  # noqa: F401
                         model_description, unzipped)
from .coupling import Coupled, extrapolation, jacobi, linear_implicit, rollback, zoh
from .event_methods import EV_METHODS, EXTRAPOLATION_EV, expm, step_fmu  # noqa: F401

METHODS = {"zoh": zoh, "jacobi": jacobi, "extrapolation": extrapolation,
           "linear_implicit": linear_implicit, "rollback": rollback}
# cosim.extrapolation per method: 0 hold, 1 linear along the velocities (and, FMI 2.0, the input
# derivatives), 3 along the acceleration inputs the method sets
EXTRAPOLATION = {"zoh": 0, "jacobi": 0, **{m: EXTRAPOLATION_EV for m in EV_METHODS}}
ACC_METHODS = tuple(EV_METHODS)     # methods that set the acceleration inputs


def connector_args(base, body):
    """(cosim.extrapolation, acceleration input names) of method `base` on `body`: the
    acceleration inputs of the body's velocity inputs (b.v[i] → b.dv[i], b.w[i] → b.dw[i]), in
    the order of its coordinates, for the methods that set them."""
    acc = [body.in_names[k].replace(".v[", ".dv[").replace(".w[", ".dw[")
           for k in body.vel_inputs] if base in ACC_METHODS else []
    return EXTRAPOLATION.get(base, 1), acc


ALL_METHODS = {**METHODS, **EV_METHODS}
LABELS = {"zoh": "explicit, zero-order hold", "jacobi": "explicit, zero-order hold, Jacobi",
          "extrapolation": "explicit, input extrapolation",
          "linear_implicit": "linear-implicit (directional derivatives)",
          "rollback": "iterative with rollback", **event_methods.LABELS}
FMI3_SUFFIX = "@fmi3"       # method@fmi3: the same method through the FMI 3.0 FMU (early return)


def split_method(method):
    """'linear_exact_ev@fmi3' -> ('linear_exact_ev', 3); 'zoh' -> ('zoh', 2)."""
    if method.endswith(FMI3_SUFFIX):
        return method[:-len(FMI3_SUFFIX)], 3
    return method, 2


def label(method):
    base, version = split_method(method)
    return LABELS[base] + (", FMI 3.0 early return" if version == 3 else
                           (", FMI 2.0 rollback to event.time" if base in EV_METHODS else ""))


class Result:
    """Samples of a run: t (N+1), p (N+1, np), u (N+1, n), extra (N+1, k) monitored outputs
    (read at the body state at each sample), cpu (s, stepping only), and the call counts."""

    def __init__(self, **kw):
        self.__dict__.update(kw)


def simulate(scene, method, H, t_end=None, unzipdir=None, record=None, fail_ok=True):
    """Run `scene` with `method` at macro step H up to t_end (default scene.t_end). `record`:
    names of extra Real outputs to sample at every communication point (slow path).
    `method` may end in "@fmi3": the FMI 3.0 FMU (dist/fmi3/) instead of the FMI 2.0 one.
    Methods without event location step on the grid (i + 1) H; event-located ones choose their
    steps (at most H, shorter after an event and where a step ends at one), and the samples are
    at the communication points they reach (the last step ends at t_end)."""
    t_end = scene.t_end if t_end is None else t_end
    base, version = split_method(method)
    located = base in EV_METHODS
    N = int(round(t_end / H))
    body = scene.body()
    params = dict(scene.params)
    params["cosim.extrapolation"], acc = connector_args(base, body)
    cls = Connector3 if version == 3 else Connector
    fmu = cls(scene.variant, params, scene.init_inputs(), body.in_names,
              body.load_names + list(record or []), unzipdir=unzipdir, acc_names=acc)
    try:
        scene.after_init(fmu)
        c = Coupled(body, fmu, *scene.initial_state(), **scene.method_options(base))
        step = ALL_METHODS[base]
        nr = len(record or [])
        T, P, U, X = [0.0], [c.p.copy()], [c.u.copy()], []
        failed, t, i = None, 0.0, 0
        if nr:
            c.put_state(0.0, c.p, c.u)
            X.append(fmu.get_outputs()[body.n:].copy())
        cpu, clock = 0.0, time.process_time
        while True:
            if located:
                if t >= t_end * (1 - 1e-12):
                    break
                h, t_next = min(H, t_end - t), None
            else:
                if i >= N:
                    break
                h, t_next = H, (i + 1) * H
            c0 = clock()
            ev0 = c.events
            try:
                r = step(c, t, h)
            except (FMICallException, CosimFailure, np.linalg.LinAlgError) as e:
                failed, r = f"t = {t:.6g}: {e}", None
            cpu += clock() - c0
            if not located:
                t = t_next
            elif r is not None:
                t = r
            c.fresh = c.events > ev0          # the next step starts at an event
            i += 1
            if failed is None and not (np.all(np.isfinite(c.p)) and np.all(np.isfinite(c.u))
                                       and np.max(np.abs(c.u)) < scene.blowup):
                failed = f"t = {t:.6g}: state blew up"
            if failed is not None:
                if not fail_ok:
                    raise CosimFailure(failed)
                break
            T.append(t)
            P.append(c.p.copy())
            U.append(c.u.copy())
            if nr:   # monitored outputs at the body state (direct feedthrough, not committed)
                c.put_state(t, c.p, c.u)
                X.append(fmu.get_outputs()[body.n:].copy())
        X = np.array(X) if nr else np.empty((len(P), 0))
        return Result(t=np.array(T), p=np.array(P), u=np.array(U), extra=X, cpu=cpu,
                      steps=len(P) - 1, calls=fmu.calls, iterations=c.iterations,
                      events=c.events, failed=failed, H=H, method=method)
    finally:
        fmu.close()
