"""The native master (fmi_master, the Python bindings of master/) in Dask workers, as a sweep uses
them: each task carries its archive as bytes (no shared file system, as scripts/cosim/sweep.py
ships its FMUs), writes it into the worker's own temporary folder and runs it there. Worker
processes of a real cluster (distributed's LocalCluster with processes), no mocks.

What is checked: every run on the cluster gives the same structured array as the same run in
this process, bit for bit (the same FMU binaries, the same arithmetic); a run whose archive is
refused comes back as the master's message, not as a lost task.
"""
from __future__ import annotations

import distributed
import numpy as np
import pytest

import fmi_master
from conftest import REPO

ARCHIVES = ("bounce", "puck0", "bushing_pendulum")
STEPS = (1e-3, 5e-4)


def run_archive(data: bytes, name: str, step: float):
    """The task: archive bytes in, its result array (or the master's refusal) out."""
    import tempfile
    from pathlib import Path

    import fmi_master as fm

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"{name}.ssp"
        path.write_bytes(data)
        try:
            return fm.simulate(str(path), step=step, stop=0.2)
        except fm.MasterError as e:
            return f"refused: {e}"


def archive_bytes(name):
    p = REPO / "dist" / "ssp" / f"{name}.ssp"
    if not p.exists():
        pytest.fail(f"{p.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    return p.read_bytes()


def test_the_master_runs_in_dask_workers_with_archives_shipped_as_bytes(tmp_path):
    cases = [(name, h) for name in ARCHIVES for h in STEPS]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None, local_directory=str(tmp_path)) as cluster, \
            distributed.Client(cluster) as client:
        futures = [client.submit(run_archive, archive_bytes(n), n, h, pure=False) for n, h in cases]
        broken = client.submit(run_archive, b"not a zip file", "broken", 1e-3, pure=False)
        remote = client.gather(futures)
        refused = broken.result()
    for (name, h), got in zip(cases, remote):
        here = fmi_master.simulate(str(REPO / "dist" / "ssp" / f"{name}.ssp"), step=h, stop=0.2)
        assert isinstance(got, np.ndarray), f"{name} at {h}: {got}"
        assert got.dtype.names == here.dtype.names
        assert len(got) == round(0.2 / h) + 1
        for col in here.dtype.names:
            assert np.array_equal(got[col], here[col]), f"{name} at {h}: {col}"
    assert isinstance(refused, str) and refused.startswith("refused: "), refused
    assert "broken.ssp" in refused, refused
