"""The filters' unchecked fast paths agree with the public per-call model functions.

The filters of :mod:`probrob.localization` validate their input once and then call the
unchecked cores of :mod:`probrob.motion`, :mod:`probrob.sensors` and :mod:`probrob.angles`
(the EKF of Table 7.2 in scalar arithmetic). Here each step is recomputed the slow way,
line by line from the public functions ``velocity_motion``, ``velocity_motion_jacobians``,
``landmark_measurement``, ``landmark_measurement_jacobian`` and ``wrap_angle`` with numpy
matrices, on a seeded simulation, and the two must agree to 1e-12 relative.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from probrob.angles import _wrap, wrap_angle
from probrob.localization import (
    ekf_localization,
    ekf_localization_known_correspondences,
    run_filter,
    ukf_localization,
    ukf_weights,
)
from probrob.motion import velocity_motion, velocity_motion_jacobians
from probrob.sensors import landmark_measurement, landmark_measurement_jacobian
from probrob.simulation import grid_landmarks, loop_controls, simulate_run

ALPHA = np.array([0.02, 0.005, 0.01, 0.03])
SIGMAS = np.array([0.15, 0.03, 0.2])
RTOL = 1e-12


def _close(a, b, rtol=RTOL):
    """Agreement to ``rtol`` relative to the size of the array (so near-zero entries pass)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = max(1.0, float(np.max(np.abs(b))))
    np.testing.assert_allclose(a, b, rtol=rtol, atol=rtol * scale)


def _ref_predict(mu, Sigma, u, dt, alpha):
    G, V = velocity_motion_jacobians(mu, u, dt)
    mu_bar = velocity_motion(mu, u, dt)
    v, w = u
    M = np.diag([alpha[0] * v**2 + alpha[1] * w**2, alpha[2] * v**2 + alpha[3] * w**2])
    Sb = G @ Sigma @ G.T + V @ M @ V.T
    return mu_bar, 0.5 * (Sb + Sb.T)


def _ref_ekf(mu, Sigma, u, z, c, m, dt, alpha, sigmas):
    """Table 7.2 from the public functions, numpy matrices, ``np.linalg.inv``."""
    mu_bar, Sb = _ref_predict(mu, Sigma, u, dt, alpha)
    d = z.shape[1]
    Q = np.diag(np.asarray(sigmas[:d]) ** 2)
    log_pz = 0.0
    for i in range(z.shape[0]):
        lm = m[c[i], :d]
        zhat = landmark_measurement(mu_bar, lm)
        H = landmark_measurement_jacobian(mu_bar, lm)
        S = H @ Sb @ H.T + Q
        nu = z[i] - zhat
        nu[1] = wrap_angle(nu[1])
        S_inv = np.linalg.inv(S)
        K = Sb @ H.T @ S_inv
        mu_bar = mu_bar + K @ nu
        Sb = Sb - K @ (Sb @ H.T).T
        Sb = 0.5 * (Sb + Sb.T)
        log_pz += -0.5 * (nu @ S_inv @ nu + math.log(np.linalg.det(S)) + d * math.log(2 * math.pi))
    mu_bar[2] = wrap_angle(mu_bar[2])
    return mu_bar, Sb, log_pz


def _ref_ukf(mu, Sigma, u, z, c, m, dt, alpha, sigmas):
    """Table 7.4 (stacked features, as documented) from the public functions."""
    k = z.shape[0]
    n = 5 + 2 * k
    gamma, wm, wc = ukf_weights(n)
    root = np.zeros((n, n))
    root[:3, :3] = np.linalg.cholesky(Sigma)
    v, w = u
    noise = [alpha[0] * v**2 + alpha[1] * w**2, alpha[2] * v**2 + alpha[3] * w**2]
    noise += [sigmas[0] ** 2, sigmas[1] ** 2] * k
    root[3:, 3:] = np.diag(np.sqrt(noise))
    chi = np.tile(np.concatenate([mu, np.zeros(n - 3)]), (2 * n + 1, 1))
    chi[1 : n + 1] += gamma * root.T
    chi[n + 1 :] -= gamma * root.T
    xbar = velocity_motion(chi[:, :3], u + chi[:, 3:5], dt)
    mu_bar = wm @ xbar
    mu_bar[2] = xbar[0, 2] + wm @ wrap_angle(xbar[:, 2] - xbar[0, 2])
    dx = xbar - mu_bar
    dx[:, 2] = wrap_angle(dx[:, 2])
    Sb = (wc[:, None] * dx).T @ dx
    if k == 0:
        mu_bar[2] = wrap_angle(mu_bar[2])
        return mu_bar, Sb, 0.0
    Z = np.stack([landmark_measurement(xbar, m[c[f], :2]) for f in range(k)], axis=1) + chi[
        :, 5:
    ].reshape(2 * n + 1, k, 2)
    zhat = np.einsum("i,ikd->kd", wm, Z)
    for f in range(k):
        zhat[f, 1] = Z[0, f, 1] + wm @ wrap_angle(Z[:, f, 1] - Z[0, f, 1])
    dz = Z - zhat
    dz[..., 1] = wrap_angle(dz[..., 1])
    dz = dz.reshape(2 * n + 1, 2 * k)
    S = (wc[:, None] * dz).T @ dz
    Pxz = (wc[:, None] * dx).T @ dz
    nu = z[:, :2] - zhat
    nu[:, 1] = wrap_angle(nu[:, 1])
    nu = nu.reshape(-1)
    K = Pxz @ np.linalg.inv(S)
    mu_t = mu_bar + K @ nu
    Sigma_t = Sb - K @ S @ K.T
    logp = -0.5 * (
        nu @ np.linalg.solve(S, nu) + math.log(np.linalg.det(S)) + 2 * k * math.log(2 * math.pi)
    )
    mu_t[2] = wrap_angle(mu_t[2])
    return mu_t, Sigma_t, logp


@pytest.fixture(scope="module")
def sim():
    m = grid_landmarks(4, 4, 8.0, origin=(-12, -12))
    run = simulate_run(
        [0.0, -9.0, 0.3],
        loop_controls(120, 0.2, v=1.0, radius=9.0),
        0.2,
        m,
        ALPHA,
        SIGMAS,
        max_range=14,
        fov=2.5,
        rng=7,
    )
    counts = [len(s.z) for s in run.steps]
    assert max(counts) >= 4 and sum(counts) > 300  # several features per step
    return run, m


@pytest.mark.parametrize("signatures", [True, False])
def test_ekf_step_matches_the_public_functions(sim, signatures):
    run, m = sim
    rng = np.random.default_rng(3)
    checked = 0
    for step, x in zip(run.steps, run.poses[1:], strict=True):
        if len(step.z) == 0:
            continue
        z = np.asarray(step.z) if signatures else np.asarray(step.z)[:, :2]
        # A prior around the true pose with a random full covariance, headings near ±π too.
        A = rng.normal(0, 0.1, (3, 3))
        Sigma = A @ A.T + 1e-4 * np.eye(3)
        mu = x + rng.normal(0, 0.1, 3)
        mu[2] = wrap_angle(mu[2] + rng.choice([0.0, np.pi]))
        got = ekf_localization_known_correspondences(
            mu, Sigma, step.u, z, step.c, m, step.dt, ALPHA, SIGMAS, log=True
        )
        ref = _ref_ekf(mu, Sigma, np.asarray(step.u), z, step.c, m, step.dt, ALPHA, SIGMAS)
        _close(got[0], ref[0])
        _close(got[1], ref[1])
        assert got[2] == pytest.approx(ref[2], rel=RTOL, abs=RTOL)
        checked += 1
    assert checked > 50


def test_ukf_step_matches_the_public_functions(sim):
    run, m = sim
    rng = np.random.default_rng(4)
    for step, x in list(zip(run.steps, run.poses[1:], strict=True))[:150]:
        A = rng.normal(0, 0.05, (3, 3))
        Sigma = A @ A.T + 1e-4 * np.eye(3)
        mu = x + rng.normal(0, 0.05, 3)
        z = np.asarray(step.z).reshape(-1, 3)
        got = ukf_localization(mu, Sigma, step.u, z, step.c, m, step.dt, ALPHA, SIGMAS, log=True)
        ref = _ref_ukf(mu, Sigma, np.asarray(step.u), z, step.c, m, step.dt, ALPHA, SIGMAS)
        _close(got[0], ref[0])
        _close(got[1], ref[1])
        assert got[2] == pytest.approx(ref[2], rel=RTOL, abs=RTOL)


@pytest.mark.parametrize("method", ["ekf", "ukf"])
def test_run_filter_matches_chained_public_steps(sim, method):
    run, m = sim
    Sigma0 = np.diag([1e-2, 1e-2, 1e-3])
    res = run_filter(run.steps, run.poses[0], Sigma0, m, ALPHA, SIGMAS, method=method)
    ref_step = _ref_ekf if method == "ekf" else _ref_ukf
    mu, Sigma = np.asarray(run.poses[0], float), Sigma0
    for i, step in enumerate(run.steps):
        z = np.asarray(step.z).reshape(-1, 3)
        mu, Sigma, logp = ref_step(
            mu, Sigma, np.asarray(step.u), z, step.c, m, step.dt, ALPHA, SIGMAS
        )
        _close(res.mu[i], mu, rtol=1e-10)
        _close(res.Sigma[i], Sigma, rtol=1e-10)
        assert res.log_pz[i] == pytest.approx(logp, rel=1e-10, abs=1e-10)


def test_ekf_ml_matches_the_public_functions(sim):
    run, m = sim
    rng = np.random.default_rng(5)
    for step, x in list(zip(run.steps, run.poses[1:], strict=True))[:80]:
        Sigma = np.diag([0.01, 0.01, 0.002])
        mu = x + rng.normal(0, 0.05, 3)
        z = np.asarray(step.z).reshape(-1, 3)
        mu_t, Sigma_t, chosen = ekf_localization(mu, Sigma, step.u, z, m, step.dt, ALPHA, SIGMAS)
        # With the chosen landmarks, the update is Table 7.2's.
        ref = _ref_ekf(mu, Sigma, np.asarray(step.u), z, chosen, m, step.dt, ALPHA, SIGMAS)
        _close(mu_t, ref[0])
        _close(Sigma_t, ref[1])


def test_scalar_wrap_is_bit_identical_to_the_array_wrap():
    rng = np.random.default_rng(0)
    a = np.concatenate(
        [
            rng.uniform(-50, 50, 20_000),
            rng.uniform(-1e9, 1e9, 200),
            np.pi * np.arange(-13, 14),
            [np.pi, -np.pi, np.nextafter(np.pi, 0), 40.0, -40.0, 1e300, -1e300, 0.0, -0.0],
        ]
    )
    scalar = np.array([_wrap(float(t)) for t in a])
    np.testing.assert_array_equal(scalar, _wrap(a))
    assert type(_wrap(1.0)) is float


@pytest.mark.parametrize(
    ("name", "bad"),
    [
        ("mu", [0.0, np.nan, 0.0]),
        ("Sigma", np.eye(2)),
        ("u", [1.0]),
        ("z", [[1.0, np.inf, 0.0]]),
        ("c", [7]),
        ("m", np.zeros((3, 2))),
        ("dt", -0.1),
        ("alpha", [0.1, -0.1, 0.1, 0.1]),
        ("sigmas", [0.1, 0.0, 0.1]),
    ],
)
def test_bad_input_still_names_the_argument(name, bad):
    args = {
        "mu": np.zeros(3),
        "Sigma": np.eye(3) * 0.01,
        "u": [1.0, 0.1],
        "z": [[3.0, 0.2, 0.0]],
        "c": [0],
        "m": np.array([[3.0, 1.0, 0.0]]),
        "dt": 0.1,
        "alpha": ALPHA,
        "sigmas": SIGMAS,
    }
    args[name] = bad
    with pytest.raises(ValueError, match=name):
        ekf_localization_known_correspondences(**args)
    with pytest.raises(ValueError, match=name):
        ukf_localization(**args)
