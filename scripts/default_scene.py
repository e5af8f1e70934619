#!/usr/bin/env python3
"""Default scene: a Bushing connector driven through fmpy; writes out/default_scene.{csv,png}.

Node a stays at the origin with identity orientation. Node b moves along
    r_b(t) = (0.01 sin(2 pi t), 0, 0.1) m
    q_b(t) = rotz(t) * rotx(theta(t)),  theta(t) = 0.2 sin(pi t)   (spin 1 rad/s about world z plus a tilt)
with the consistent velocity and world-frame angular velocity
    v_b = (0.02 pi cos(2 pi t), 0, 0),   w_b = e_z + theta'(t) * rotz(t) e_x.
"""
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from fmpy import simulate_fmu  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "dist" / "Bushing.fmu"
OUT = REPO / "out"
STOP, DT = 2.0, 1e-3

PARAMETERS = {**{f"elasticity.k{k}": 1e4 for k in (1, 2, 3)},    # N/m
              **{f"elasticity.k{k}": 100.0 for k in (4, 5, 6)},  # N.m/rad
              **{f"damping.c{k}": 1.0 for k in range(1, 7)}}     # N.s/m, N.m.s/rad
TRIPLE = [1, 2, 3]
OUTPUTS = ([f"CU{i}" for i in TRIPLE] + [f"CUR{i}" for i in TRIPLE] + [f"CTF{i}" for i in TRIPLE]
           + [f"CTM{i}" for i in TRIPLE] + [f"a.f[{i}]" for i in TRIPLE] + [f"b.m[{i}]" for i in TRIPLE]
           + ["energy.stored", "energy.damping"])


def qmul(p, q):
    """Hamilton product of scalar-first quaternions stored in the last axis."""
    pw, pv, qw, qv = p[..., :1], p[..., 1:], q[..., :1], q[..., 1:]
    w = pw * qw - np.sum(pv * qv, axis=-1, keepdims=True)
    return np.concatenate([w, pw * qv + qw * pv + np.cross(pv, qv)], axis=-1)


def axis_angle(axis, angle):
    half = 0.5 * np.asarray(angle)[:, None]
    return np.concatenate([np.cos(half), np.sin(half) * np.asarray(axis, float)], axis=-1)


def input_table(t):
    theta, dtheta = 0.2 * np.sin(np.pi * t), 0.2 * np.pi * np.cos(np.pi * t)
    zero, one = np.zeros_like(t), np.ones_like(t)
    q = qmul(axis_angle([0, 0, 1], t), axis_angle([1, 0, 0], theta))
    cols = {**{f"a.{n}[{i}]": zero for n in "rvw" for i in TRIPLE},  # node a at rest at the origin
            "a.q.w": one, "a.q.x": zero, "a.q.y": zero, "a.q.z": zero,
            "b.r[1]": 0.01 * np.sin(2 * np.pi * t), "b.r[2]": zero, "b.r[3]": 0.1 * one,
            "b.q.w": q[:, 0], "b.q.x": q[:, 1], "b.q.y": q[:, 2], "b.q.z": q[:, 3],
            "b.v[1]": 0.02 * np.pi * np.cos(2 * np.pi * t), "b.v[2]": zero, "b.v[3]": zero,
            "b.w[1]": dtheta * np.cos(t), "b.w[2]": dtheta * np.sin(t), "b.w[3]": one}
    table = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in cols])
    table["time"] = t
    for name, values in cols.items():
        table[name] = values
    return table


def plot(res, path):
    t = res["time"]
    fig, (ax_u, ax_f, ax_e) = plt.subplots(3, 1, sharex=True, figsize=(9, 10))
    ax_r = ax_u.twinx()
    for i in TRIPLE:
        ax_u.plot(t, res[f"CU{i}"], f"C{i - 1}-", label=f"CU{i}")
        ax_r.plot(t, res[f"CUR{i}"], f"C{i - 1}--", label=f"CUR{i}")
    ax_u.set_ylabel("CU [m]"), ax_r.set_ylabel("CUR [rad] (dashed)")
    ax_u.legend(loc="upper left"), ax_r.legend(loc="upper right")
    ax_m = ax_f.twinx()
    for i in TRIPLE:
        ax_f.plot(t, res[f"CTF{i}"], f"C{i - 1}-", label=f"CTF{i}")
        ax_f.plot(t, res[f"a.f[{i}]"], f"C{i - 1}:", label=f"a.f[{i}]")
        ax_m.plot(t, res[f"CTM{i}"], f"C{i - 1}--", label=f"CTM{i}")
        ax_m.plot(t, res[f"b.m[{i}]"], f"C{i - 1}-.", label=f"b.m[{i}]")
    ax_f.set_ylabel("force [N] (solid, dotted)"), ax_m.set_ylabel("moment [N.m] (dashed, dash-dot)")
    ax_f.legend(loc="upper left", ncol=2, fontsize="small"), ax_m.legend(loc="upper right", ncol=2, fontsize="small")
    ax_e.plot(t, res["energy.stored"], label="energy.stored")
    ax_e.plot(t, res["energy.damping"], label="energy.damping")
    ax_e.set_ylabel("energy [J]"), ax_e.set_xlabel("time [s]"), ax_e.legend()
    for ax in (ax_u, ax_f, ax_e):
        ax.grid(True, alpha=0.3)
    fig.suptitle("Bushing default scene: node b translating, spinning about z and tilting")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    if not FMU.is_file():
        raise SystemExit(f"error: {FMU.relative_to(REPO)} is missing; run ./scripts/run")
    t = np.linspace(0.0, STOP, int(round(STOP / DT)) + 1)
    res = simulate_fmu(str(FMU), fmi_type="CoSimulation", stop_time=STOP, output_interval=DT,
                       start_values=PARAMETERS, input=input_table(t), output=OUTPUTS)
    OUT.mkdir(exist_ok=True)
    csv, png = OUT / "default_scene.csv", OUT / "default_scene.png"
    names = ["time"] + OUTPUTS
    np.savetxt(csv, np.column_stack([res[n] for n in names]), delimiter=",",
               header=",".join(names), comments="", fmt="%.9g")
    plot(res, png)
    print(f"wrote {csv.relative_to(REPO)}")
    print(f"wrote {png.relative_to(REPO)}")


if __name__ == "__main__":
    main()
