"""Self-check of the prescribed motions of _cosim_helpers.py (no FMU): their velocities,
angular velocities, quaternion derivatives and accelerations are the derivatives of their
positions. Uses _cosim_helpers and _ref only."""

from __future__ import annotations

import numpy as np

import _ref
from _cosim_helpers import PlanarSlide, Smooth, pure_quat


def test_closed_forms_are_consistent():
    """Self-check of the prescribed motions (no FMU): velocities, angular velocities,
    quaternion derivatives and accelerations against central differences of the positions
    (h = 1e-6, error ~1e-9 of O(1) rates); qdot = 1/2 w * q."""
    m = Smooth("Bushing")
    h = 1e-6
    for t in np.linspace(0.0, 1.0, 7):
        assert np.allclose((m.r(t + h) - m.r(t - h)) / (2 * h), m.v(t), atol=1e-8)
        assert np.allclose((m.v(t + h) - m.v(t - h)) / (2 * h), m.a(t), atol=1e-7)
        assert np.allclose((m.w(t + h) - m.w(t - h)) / (2 * h), m.wdot(t), atol=1e-7)
        assert np.allclose((m.q(t + h) - m.q(t - h)) / (2 * h), m.qdot(t), atol=1e-8)
        assert np.allclose(m.qdot(t), 0.5 * _ref.quat_mul(pure_quat(m.w(t)), m.q(t)), atol=1e-14)
    p = PlanarSlide()
    for t in np.linspace(0.0, 1.0, 7):
        P0, P1, Pm = p.pose(t), p.pose(t + h), p.pose(t - h)
        assert np.allclose((P1["b.r"] - Pm["b.r"]) / (2 * h), P0["b.v"], atol=1e-8)
        dq = (P1["b.q"] - Pm["b.q"]) / (2 * h)
        assert np.allclose(dq, 0.5 * _ref.quat_mul(pure_quat(P0["b.w"]), P0["b.q"]), atol=1e-8)
