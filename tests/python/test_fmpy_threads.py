"""Several instances driven from different threads through fmpy's FMU2Slave give, bit for bit,
the records of the same runs done alone.

Uses conftest's `conn` fixture and _cosim_helpers (scenario, H_ROLL)."""

from __future__ import annotations

import threading

from _cosim_helpers import H_ROLL, scenario
from conftest import VARIANTS

THREAD_STEPS = 400


def _thread_run(c, params, inputs_at, barrier, out, key):
    try:
        barrier.wait()
        c.start(params, inputs_at(0.0))
        out[key] = c.drive(inputs_at, THREAD_STEPS, H_ROLL)
    except BaseException as e:  # noqa: BLE001 - reported by the main thread
        out[key] = e


def test_instances_in_threads_match_single_runs(conn):
    """Ten instances (two per variant, the stateful scenarios with stops and Planar friction)
    run concurrently from ten threads give, bit for bit, the records of the same runs done
    alone (fmpy's ctypes calls release the GIL, so the FMU calls really overlap)."""
    jobs = [(v, rep) for v in VARIANTS for rep in range(2)]
    alone = {}
    for v in VARIANTS:
        params, inputs_at = scenario(v)
        alone[v] = conn(v).start(params, inputs_at(0.0)).drive(inputs_at, THREAD_STEPS, H_ROLL)
    for attempt in range(2):
        conns = {job: conn(job[0]) for job in jobs}
        barrier = threading.Barrier(len(jobs))
        out = {}
        threads = []
        for job, c in conns.items():
            params, inputs_at = scenario(job[0])
            th = threading.Thread(target=_thread_run, args=(c, params, inputs_at, barrier, out, job))
            threads.append(th)
        for th in threads:
            th.start()
        for th in threads:
            th.join(timeout=300)
            assert not th.is_alive()
        for job in jobs:
            res = out[job]
            if isinstance(res, BaseException):
                raise res
            assert res == alone[job[0]], (attempt, job)
