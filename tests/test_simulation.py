"""Tests of probrob.simulation: landmark worlds, noisy runs and filter steps."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from probrob.angles import wrap_angle
from probrob.motion import velocity_motion, velocity_motion_jacobians
from probrob.sensors import landmark_measurement
from probrob.simulation import grid_landmarks, loop_controls, random_landmarks, simulate_run

M = grid_landmarks(3, 3, 4.0, origin=(-4.0, -4.0))
ALPHA = np.array([0.02, 0.005, 0.005, 0.02])
SIGMAS = np.array([0.1, 0.03, 0.2])


def _run(rng=0, **kw):
    args = dict(max_range=5.0, fov=1.0, rng=rng)
    args.update(kw)
    return simulate_run(
        [0.0, -3.0, 0.1], loop_controls(60, 0.1, v=1.0, radius=3.0), 0.1, M, ALPHA, SIGMAS, **args
    )


def test_grid_landmarks():
    m = grid_landmarks(2, 3, (1.0, 2.0), origin=(5.0, -1.0))
    assert m.shape == (6, 3)
    np.testing.assert_array_equal(m[:, 2], np.arange(6))
    assert set(m[:, 0]) == {5.0, 6.0}
    assert set(m[:, 1]) == {-1.0, 1.0, 3.0}


def test_random_landmarks_keep_their_distance():
    m = random_landmarks(20, (0, 10, 0, 10), min_distance=1.0, rng=3)
    d = np.hypot(*(m[:, None, :2] - m[None, :, :2]).transpose(2, 0, 1))
    assert np.min(d[~np.eye(20, dtype=bool)]) >= 1.0
    assert np.all((m[:, :2] >= 0) & (m[:, :2] <= 10))
    np.testing.assert_array_equal(
        random_landmarks(5, (0, 1, 0, 1), rng=1), random_landmarks(5, (0, 1, 0, 1), rng=1)
    )
    with pytest.raises(ValueError, match="min_distance"):
        random_landmarks(50, (0, 1, 0, 1), min_distance=0.5, rng=0)


def test_seeded_runs_repeat_and_differ():
    a, b, c = _run(1), _run(1), _run(2)
    np.testing.assert_array_equal(a.poses, b.poses)
    assert not np.allclose(a.poses, c.poses)
    for sa, sb in zip(a.steps, b.steps, strict=True):
        np.testing.assert_array_equal(sa.z, sb.z)
        np.testing.assert_array_equal(sa.c, sb.c)


def test_noise_free_run_is_dead_reckoning_and_exact_measurements():
    run = simulate_run(
        [0.0, -3.0, 0.1],
        loop_controls(60, 0.1, v=1.0, radius=3.0),
        0.1,
        M,
        np.zeros(4),
        np.zeros(3),
        max_range=5.0,
        fov=1.0,
        rng=0,
    )
    np.testing.assert_allclose(run.poses, run.odometry, atol=1e-12)
    x = run.poses[0]
    for k, step in enumerate(run.steps):
        x = velocity_motion(x, step.u, step.dt)
        np.testing.assert_allclose(run.poses[k + 1], x, atol=1e-12)
        truth = landmark_measurement(run.poses[k + 1], M)
        visible = np.flatnonzero((truth[:, 0] <= 5.0) & (np.abs(truth[:, 1]) <= 1.0))
        np.testing.assert_array_equal(step.c, visible)
        np.testing.assert_allclose(step.z, truth[visible], atol=1e-12)
        assert step.t == pytest.approx(0.1 * (k + 1))


def test_measurement_noise_is_normal_with_the_given_sigmas():
    run = _run(5, max_range=np.inf, fov=np.pi)
    res = []
    for k, step in enumerate(run.steps):
        d = step.z - landmark_measurement(run.poses[k + 1], M[step.c])
        d[:, 1] = wrap_angle(d[:, 1])
        res.append(d / SIGMAS)
    res = np.concatenate(res)
    assert len(res) == 60 * 9
    for j in range(3):
        assert stats.kstest(res[:, j], "norm").pvalue > 0.01


def test_one_step_spread_matches_the_linearised_motion_noise():
    """1500 one-step runs: the end poses' covariance is V M Vᵀ (small noise) within 4 s.e."""
    alpha = np.array([0.002, 0.001, 0.001, 0.002])
    u, dt, x0 = np.array([1.0, 0.5]), 0.5, np.array([1.0, 2.0, 0.3])
    rng = np.random.default_rng(9)
    ends = np.array(
        [simulate_run(x0, u[None], dt, M, alpha, SIGMAS, rng=rng).poses[1] for _ in range(1500)]
    )
    _, V = velocity_motion_jacobians(x0, u, dt)
    Mt = np.diag([alpha[0] + alpha[1] * 0.25, alpha[2] + alpha[3] * 0.25])
    expected = V @ Mt @ V.T
    cov = np.cov(ends.T)
    se = np.sqrt((expected**2 + np.outer(np.diag(expected), np.diag(expected))) / len(ends))
    assert np.all(np.abs(cov - expected) < 4 * se + 1e-6)
    tol = 4 * np.sqrt(np.diag(expected) / len(ends)) + 1e-4
    assert np.all(np.abs(ends.mean(axis=0) - velocity_motion(x0, u, dt)) < tol)


def test_loop_controls_straight_line_is_exact():
    c = loop_controls(5, 0.1, v=2.0, radius=np.inf)
    np.testing.assert_array_equal(c, [[2.0, 0.0]] * 5)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(x0=[0, 0]), "x0"),
        (dict(controls=[1.0, 0.0]), "controls"),
        (dict(dt=-1.0), "dt"),
        (dict(m=np.zeros((0, 3))), "m"),
        (dict(alpha=[0.1] * 6), "alpha"),
        (dict(sigmas=[0.1, -0.1, 0.1]), "sigmas"),
        (dict(max_range=0.0), "max_range"),
        (dict(fov=4.0), "fov"),
    ],
)
def test_bad_input(kw, match):
    args = dict(x0=[0, 0, 0], controls=[[1.0, 0.0]], dt=0.1, m=M, alpha=ALPHA, sigmas=SIGMAS)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        simulate_run(**args)
