"""Sweeps on a real Dask cluster (scripts/cosim/sweep.py, ./scripts/sweep): a `dask scheduler`
and two `dask worker` processes started from the venv on 127.0.0.1 (separate processes, not an
in-process cluster). The workers run in their own empty directories with no PYTHONPATH: the
sweep's code and FMU files reach them only through the engine's worker plugin.

What is checked (each against something the engine does not decide itself):
  - 24 runs on the cluster give, row by row, the same figures as the same runs done serially in
    this process: exact equality (same FMU binary, same arithmetic; the row's floats are written
    with repr, which round-trips), status, step and call counts included; only CPU time and
    worker differ.
  - a worker process killed (SIGKILL) while it runs tasks: the sweep still ends with every row,
    each identical to the serial one, and the rows of the tasks the dead worker was running come
    from another worker; a worker started mid-sweep gets the code and FMUs from the plugin.
  - a run given a refused parameter value becomes an error row whose message names the parameter
    (the FMU's own log line), and the other runs of the sweep go on.
  - the sweep command killed mid-sweep and run again: the rows already written stay as they are
    (byte for byte), the second run computes exactly the missing rows, no key appears twice.
"""
from __future__ import annotations

import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
# a hard import: distributed is pinned in requirements.txt, so a broken install fails here
# instead of skipping every sweep test
import distributed  # noqa: E402
from cosim import sweep  # noqa: E402

DASK = Path(sys.executable).parent / "dask"

# 4 methods x 3 steps x 2 stop stiffnesses = 24 runs of the §5 bounce (RadialThrust)
FOUR = ["zoh", "extrapolation", "linear_implicit", "rollback"]
GRID = [("method", FOUR), ("H", ["1e-4", "5e-5", "2e-5"]), ("stop.stiffness", ["1e4", "2e4"])]
SAME = ("status", "steps", "fmi_calls", "rollback_passes")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Cluster:
    def __init__(self, root):
        self.root = Path(root)
        self.port = free_port()
        self.address = f"tcp://127.0.0.1:{self.port}"
        self.env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "COSIM_DIST")}
        self.procs = {}
        self.logs = []
        self.scheduler = self._start("scheduler", [str(DASK), "scheduler", "--host", "127.0.0.1",
                                                   "--port", str(self.port), "--no-dashboard"])

    def _start(self, name, cmd):
        d = self.root / name
        d.mkdir(parents=True, exist_ok=True)
        log = open(d / "log.txt", "w")
        self.logs.append(log)
        return subprocess.Popen(cmd, cwd=d, env=self.env, stdout=log, stderr=subprocess.STDOUT)

    def add_worker(self, name):
        self.procs[name] = self._start(name, [
            str(DASK), "worker", self.address, "--name", name, "--nthreads", "1", "--no-nanny",
            "--no-dashboard", "--host", "127.0.0.1", "--local-directory", str(self.root / name)])
        return self.procs[name]

    def close(self):
        for p in list(self.procs.values()) + [self.scheduler]:
            if p.poll() is None:
                p.terminate()
        for p in list(self.procs.values()) + [self.scheduler]:
            try:
                p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                p.kill()
        for log in self.logs:
            log.close()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(tmp_path_factory.mktemp("dask"))
    try:
        c.add_worker("w1")
        c.add_worker("w2")
        with distributed.Client(c.address, timeout=60) as client:
            client.wait_for_workers(2, timeout=90)
        yield c
    finally:
        c.close()


@pytest.fixture(scope="module")
def tasks():
    t, inputs = sweep.build_sweep("bounce", [(n, sweep.expand(",".join(v))) for n, v in GRID])
    assert len(t) == 24 and inputs == ["stop.stiffness"]
    return t


@pytest.fixture(scope="module")
def serial(tasks):
    rows = sweep.execute(tasks, None, progress=False)
    assert all(r["status"] == "ok" for r in rows), [r["message"] for r in rows]
    return {r["key"]: r for r in rows}


def same_figures(a, b):
    fa, fb = a["figures"], b["figures"]
    assert fa.keys() == fb.keys()
    for k in fa:
        x, y = fa[k], fb[k]
        assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)), (k, x, y)
    for k in SAME:
        assert a[k] == b[k], (k, a[k], b[k])


def test_workers_have_no_checkout(cluster, tasks):
    """Every worker runs the package from the plugin's zip and holds the FMU extracted in its own
    local directory; a worker that ran a task loaded the FMU from there, not from dist/."""
    rows = sweep.execute(tasks[:4], cluster.address, progress=False)
    sha = sweep.fmu_ref("RadialThrust")["sha256"]

    def where(dask_worker):
        m, c = sys.modules["cosim.master"], sys.modules["cosim.connectors"]
        d = Path(dask_worker.local_directory) / "connector-fmus" / sha
        return m.__file__, str(c.DIST), (d / ".installed").exists(), (d / "unzipped").is_dir()

    with distributed.Client(cluster.address) as client:
        info = client.run(where)
    assert len(info) == 2
    for addr, (code, dist, installed, unzipped) in info.items():
        assert ".zip" in code and str(REPO) not in code, code
        assert installed and unzipped
    for r in rows:
        assert r["status"] == "ok", r["message"]
        code, dist, _, _ = info[r["worker"]]
        assert "connector-fmus" in dist and str(REPO) not in dist, dist


def test_cluster_rows_identical_to_serial(cluster, tasks, serial, tmp_path):
    out = tmp_path / "rows.csv"
    rows = sweep.execute(tasks, cluster.address, out=out, input_columns=["stop.stiffness"],
                         inputs_of=lambda s: s["fmu"], progress=False)
    assert len(rows) == 24
    written = sweep.RowsFile(out, ["stop.stiffness"]).done
    assert written.keys() == serial.keys()
    for key, row in serial.items():
        same_figures(written[key], row)            # the file, parsed back
        same_figures(rows[[t["spec"]["key"] for t in tasks].index(key)], row)
    workers = {r["worker"] for r in written.values()}
    assert len(workers) == 2 and "serial" not in workers, workers


def test_killed_worker_costs_only_its_running_tasks(cluster, tasks, serial, tmp_path):
    """SIGKILL one worker while it runs a task, once the sweep has written a row; a third worker
    joins mid-sweep. Every row arrives, identical to the serial one; the killed worker's running
    tasks were rerun elsewhere."""
    out = tmp_path / "rows.csv"
    state = {}

    def killer():     # watches the scheduler from another thread while the sweep runs
        with distributed.Client(cluster.address) as client:
            info = client.scheduler_info()["workers"]
            victim = next(a for a, w in info.items() if w["name"] == "w1")
            deadline = time.monotonic() + 120
            while time.monotonic() < deadline:
                if out.exists() and out.read_bytes().count(b"\n") >= 2:
                    running = client.processing(workers=[victim]).get(victim, [])
                    if running:
                        break
                time.sleep(0.01)
            cluster.procs["w1"].send_signal(signal.SIGKILL)
            cluster.procs["w1"].wait(timeout=10)
            state["killed"] = (victim, [k.split("-")[1] for k in running])
        cluster.add_worker("w3")

    watcher = threading.Thread(target=killer)
    watcher.start()
    try:
        rows = sweep.execute(tasks, cluster.address, out=out, input_columns=["stop.stiffness"],
                             inputs_of=lambda s: s["fmu"], progress=False)
    finally:
        watcher.join()
    victim, running = state["killed"]
    assert running, "w1 was running no task when killed"
    written = sweep.RowsFile(out, ["stop.stiffness"]).done
    assert len(rows) == 24 and written.keys() == serial.keys()
    assert len(out.read_text().splitlines()) == 25                 # header + one line per run
    for key, row in serial.items():
        same_figures(written[key], row)
    # what w1 had when it died ran again elsewhere (a task finishing in the instant between the
    # poll and the kill may keep its w1 row: at least one must have been rerun)
    assert any(written[key]["worker"] != victim for key in running), running
    assert all(written[key]["worker"] != "" for key in written)


def test_bad_parameter_is_an_error_row(cluster, tmp_path):
    grid = [("method", ["zoh", "rollback"]), ("H", ["1e-3"]), ("stop.stiffness", ["1e4", "-5"])]
    tasks, _ = sweep.build_sweep("bounce", grid)
    rows = sweep.execute(tasks, cluster.address, out=tmp_path / "bad.csv", progress=False)
    by = {(t["spec"]["method"], t["spec"]["fmu"]["stop.stiffness"]): r for t, r in zip(tasks, rows)}
    for method in ("zoh", "rollback"):
        good, bad = by[(method, 1e4)], by[(method, -5.0)]
        assert good["status"] == "ok" and math.isfinite(good["figures"]["error"])
        assert bad["status"] == "error"
        assert "stop.stiffness" in bad["message"], bad["message"]


def run_cli(cluster, out, *extra):
    cmd = [sys.executable, "-c", "import sys; from cosim.sweep import main; sys.exit(main(sys.argv[1:]))",
           "bounce", "method=" + ",".join(FOUR), "H=5e-5,2e-5", "stop.stiffness=1e4,2e4,3e4",
           "--scheduler", cluster.address,
           "--out", str(out), "--quiet", *extra]
    env = {**os.environ, "PYTHONPATH": str(REPO / "scripts")}
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def test_interrupted_sweep_resumes_without_recomputing(cluster, tmp_path):
    """Kill the sweep command (SIGKILL) once it has written 5 rows, run it again: the second run
    computes only the missing rows and leaves the written ones untouched."""
    out = tmp_path / "resume.csv"
    p = run_cli(cluster, out)
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline and p.poll() is None:
        if out.exists() and out.read_bytes().count(b"\n") >= 6:       # header + 5 rows
            break
        time.sleep(0.05)
    p.kill()
    p.wait()
    first = out.read_bytes()
    first = first[:first.rfind(b"\n") + 1]                # a line cut by the kill is dropped
    n_first = first.count(b"\n") - 1
    assert 5 <= n_first < 24, n_first

    p = run_cli(cluster, out)
    text, _ = p.communicate(timeout=180)
    assert p.returncode == 0, text
    assert f"{n_first} of 24 rows already in {out}; computing {24 - n_first}" in text, text
    final = out.read_bytes()
    assert final.startswith(first)                        # written rows untouched
    lines = final.decode().splitlines()
    keys = [line.split(",", 1)[0] for line in lines[1:]]
    assert len(keys) == 24 == len(set(keys))             # nothing computed twice, nothing missing

    p = run_cli(cluster, out)                             # complete: computes nothing
    text, _ = p.communicate(timeout=120)
    assert p.returncode == 0 and "24 of 24 rows already" in text, text
    assert out.read_bytes() == final
