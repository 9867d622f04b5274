"""Tests of probrob.localization: EKF (Tables 7.2, 7.3) and UKF (Table 7.4) localization."""

from __future__ import annotations

import math

import numpy as np
import pytest

from probrob.angles import wrap_angle
from probrob.evaluation import chi2_quantile, covariance_ellipse, nees
from probrob.fitting import fit_measurement_noise, fit_motion_noise
from probrob.localization import (
    ekf_localization,
    ekf_localization_known_correspondences,
    ekf_predict_segment,
    run_filter,
    ukf_localization,
    ukf_localization_ml,
    ukf_weights,
)
from probrob.motion import velocity_motion
from probrob.sensors import (
    landmark_measurement,
    landmark_measurement_jacobian,
    landmark_model_known_correspondence,
)
from probrob.simulation import grid_landmarks, loop_controls, simulate_run

MAP = np.array([[4.0, 1.0, 0.0], [-2.0, 5.0, 1.0], [1.0, -4.0, 2.0], [6.0, 6.0, 3.0]])
MU = np.array([0.3, -0.2, 0.4])
SIGMA = np.array([[0.04, 0.01, 0.002], [0.01, 0.03, -0.003], [0.002, -0.003, 0.01]])
U = np.array([0.8, 0.3])
DT = 0.5
ALPHA = np.array([0.05, 0.01, 0.02, 0.05])
SIGMAS = np.array([0.2, 0.05, 0.3])


def _features(x, c, rng, sigmas=SIGMAS):
    """Noisy features of the landmarks ``c`` seen from pose ``x``."""
    z = landmark_measurement(x, MAP[c]) + rng.standard_normal((len(c), 3)) * sigmas
    z[:, 1] = wrap_angle(z[:, 1])
    return z


def _fd_jacobian(f, x, eps=1e-6):
    x = np.asarray(x, float)
    cols = []
    for k in range(x.size):
        d = np.zeros_like(x)
        d[k] = eps
        diff = np.asarray(f(x + d)) - np.asarray(f(x - d))
        cols.append(diff / (2 * eps))
    return np.stack(cols, axis=-1)


def _fd_measurement(x, landmark):
    def h(p):
        out = landmark_measurement(p, landmark).copy()
        return out

    J = _fd_jacobian(h, x)
    return J


# --------------------------------------------------------------------------- Jacobians


@pytest.mark.parametrize("landmark", MAP)
@pytest.mark.parametrize("theta", [0.4, np.pi - 1e-3, -np.pi + 1e-3])
def test_measurement_jacobian_matches_finite_differences(landmark, theta):
    x = np.array([0.3, -0.2, theta])
    H = landmark_measurement_jacobian(x, landmark)

    # Bearing differences must be wrapped for the finite difference near ±π.
    def h(p):
        z = landmark_measurement(p, landmark)
        return np.array([z[0], z[1], z[2]])

    eps = 1e-6
    J = np.empty((3, 3))
    for k in range(3):
        d = np.zeros(3)
        d[k] = eps
        diff = h(x + d) - h(x - d)
        diff[1] = wrap_angle(diff[1])
        J[:, k] = diff / (2 * eps)
    np.testing.assert_allclose(H, J, atol=1e-8)


def _deck_H(x, landmark):
    """Deck 004, Table 7.2 line 13, as printed: H11 = -dx/q, H22 = -dx/sqrt(q)."""
    dx, dy = landmark[0] - x[0], landmark[1] - x[1]
    q = dx * dx + dy * dy
    return np.array(
        [[-dx / q, -dy / np.sqrt(q), 0], [dy / q, -dx / np.sqrt(q), -1], [0, 0, 0]], float
    )


def test_deck_measurement_jacobian_fails_finite_differences():
    """Errata F2: the deck divides H11 by q instead of √q and H22 by √q instead of q."""
    x, landmark = MU, MAP[0]
    H = landmark_measurement_jacobian(x, landmark)
    J = _fd_measurement(x, landmark)
    np.testing.assert_allclose(H, J, atol=1e-8)
    deck = _deck_H(x, landmark)
    assert abs(deck[0, 0] - J[0, 0]) > 0.5
    assert abs(deck[1, 1] - J[1, 1]) > 0.5
    # The other entries of the deck's H are right.
    mask = np.ones((3, 3), bool)
    mask[0, 0] = mask[1, 1] = False
    np.testing.assert_allclose(deck[mask], J[mask], atol=1e-8)


def test_deck_predicted_signature_is_not_the_landmark_signature():
    """Errata F3: the deck's third component of ẑ is (m_x - μ_x)/√q, not m_s."""
    x, landmark = MU, MAP[3]
    dx, dy = landmark[0] - x[0], landmark[1] - x[1]
    deck_s = dx / math.hypot(dx, dy)
    zhat = landmark_measurement(x, landmark)
    assert zhat[2] == landmark[2] == 3.0
    assert abs(deck_s - landmark[2]) > 2.0  # a cosine is never a signature of 3


def _deck_V(x, u, dt):
    """Deck 004, Table 7.2 line 4, as printed (V11 = -(sin θ + sin(θ + ωΔt))/ω)."""
    th = x[2]
    v, w = u
    s0, s1, c0, c1 = np.sin(th), np.sin(th + w * dt), np.cos(th), np.cos(th + w * dt)
    return np.array(
        [
            [-(s0 + s1) / w, v * (s0 - s1) / w**2 + v * c1 * dt / w],
            [(c0 - c1) / w, -v * (c0 - c1) / w**2 + v * s1 * dt / w],
            [0, dt],
        ]
    )


def test_deck_V_has_a_sign_error():
    """Errata F1: ∂x'/∂v is (-sin θ + sin(θ + ωΔt))/ω; the deck prints -(sin θ + sin(...))/ω."""
    J = _fd_jacobian(lambda uu: velocity_motion(MU, uu, DT), U)
    deck = _deck_V(MU, U, DT)
    assert abs(deck[0, 0] - J[0, 0]) > 0.5
    np.testing.assert_allclose(deck[1:, :], J[1:, :], atol=1e-7)
    np.testing.assert_allclose(deck[0, 1], J[0, 1], atol=1e-7)


@pytest.mark.parametrize("w", [0.0, 1e-9, -1e-9, 0.3, -2.0])
def test_ekf_prediction_is_the_linearised_propagation(w):
    """No features: Σ̄ = G Σ Gᵀ + V M Vᵀ with G, V from finite differences of g (also at ω = 0)."""
    u = np.array([0.8, w])
    mu_bar, Sigma_bar, p_z = ekf_localization_known_correspondences(
        MU, SIGMA, u, np.zeros((0, 3)), [], MAP, DT, ALPHA, SIGMAS
    )
    G = _fd_jacobian(lambda x: velocity_motion(x, u, DT), MU)
    V = _fd_jacobian(lambda uu: velocity_motion(MU, uu, DT), u)
    M = np.diag([ALPHA[0] * 0.64 + ALPHA[1] * w * w, ALPHA[2] * 0.64 + ALPHA[3] * w * w])
    np.testing.assert_allclose(Sigma_bar, G @ SIGMA @ G.T + V @ M @ V.T, atol=1e-9)
    expected = velocity_motion(MU, u, DT)
    np.testing.assert_allclose(mu_bar[:2], expected[:2], atol=1e-15)
    assert mu_bar[2] == pytest.approx(wrap_angle(expected[2]), abs=1e-15)
    assert p_z == 1.0


def test_prediction_is_continuous_at_zero_turn_rate():
    out = [
        ekf_localization_known_correspondences(
            MU, SIGMA, [0.8, w], np.zeros((0, 3)), [], MAP, DT, ALPHA, SIGMAS
        )
        for w in (0.0, 1e-9)
    ]
    np.testing.assert_allclose(out[0][0], out[1][0], atol=1e-9)
    np.testing.assert_allclose(out[0][1], out[1][1], atol=1e-12)
    ukf = [
        ukf_localization(MU, SIGMA, [0.8, w], np.zeros((0, 3)), [], MAP, DT, ALPHA, SIGMAS)
        for w in (0.0, 1e-9)
    ]
    np.testing.assert_allclose(ukf[0][0], ukf[1][0], atol=1e-9)
    np.testing.assert_allclose(ukf[0][1], ukf[1][1], atol=1e-12)


# --------------------------------------------------------------------------- Table 7.2


def test_ekf_update_matches_a_hand_written_kalman_step():
    """One feature: the textbook Kalman equations written out independently."""
    rng = np.random.default_rng(3)
    z = _features(MU, [1], rng)
    mu, Sigma, p_z = ekf_localization_known_correspondences(
        MU, SIGMA, U, z, [1], MAP, DT, ALPHA, SIGMAS
    )
    G = _fd_jacobian(lambda x: velocity_motion(x, U, DT), MU)
    V = _fd_jacobian(lambda uu: velocity_motion(MU, uu, DT), U)
    M = np.diag(
        [ALPHA[0] * U[0] ** 2 + ALPHA[1] * U[1] ** 2, ALPHA[2] * U[0] ** 2 + ALPHA[3] * U[1] ** 2]
    )
    mb = velocity_motion(MU, U, DT)
    Sb = G @ SIGMA @ G.T + V @ M @ V.T
    dx, dy = MAP[1, 0] - mb[0], MAP[1, 1] - mb[1]
    q = dx * dx + dy * dy
    zhat = np.array([np.sqrt(q), np.arctan2(dy, dx) - mb[2], MAP[1, 2]])
    H = np.array([[-dx / np.sqrt(q), -dy / np.sqrt(q), 0], [dy / q, -dx / q, -1], [0, 0, 0]])
    S = H @ Sb @ H.T + np.diag(SIGMAS**2)
    K = Sb @ H.T @ np.linalg.inv(S)
    nu = z[0] - zhat
    nu[1] = wrap_angle(nu[1])
    expected_mu = mb + K @ nu
    expected_Sigma = (np.eye(3) - K @ H) @ Sb
    np.testing.assert_allclose(mu[:2], expected_mu[:2], atol=1e-6)
    assert wrap_angle(mu[2] - expected_mu[2]) == pytest.approx(0, abs=1e-6)
    np.testing.assert_allclose(Sigma, expected_Sigma, atol=1e-7)
    expected_p = np.exp(-0.5 * nu @ np.linalg.solve(S, nu)) / np.sqrt(np.linalg.det(2 * np.pi * S))
    assert p_z == pytest.approx(expected_p, rel=1e-6)


def test_pz_is_the_product_of_landmark_model_values_at_zero_covariance():
    """Σ = 0 and α = 0: S = Q, μ̄ does not move and p_z = Π landmark model (Table 6.4)."""
    rng = np.random.default_rng(5)
    c = np.array([0, 2, 3])
    x_bar = velocity_motion(MU, U, DT)
    z = _features(x_bar, c, rng)
    mu, Sigma, p_z = ekf_localization_known_correspondences(
        MU, np.zeros((3, 3)), U, z, c, MAP, DT, np.zeros(4), SIGMAS
    )
    expected = np.prod(
        [landmark_model_known_correspondence(z[i], c[i], x_bar, MAP, SIGMAS) for i in range(3)]
    )
    assert p_z == pytest.approx(expected, rel=1e-10)
    np.testing.assert_allclose(Sigma, 0, atol=1e-15)
    np.testing.assert_allclose(mu, wrap_angle(x_bar) * [0, 0, 1] + x_bar * [1, 1, 0], atol=1e-12)
    _, _, logp = ekf_localization_known_correspondences(
        MU, np.zeros((3, 3)), U, z, c, MAP, DT, np.zeros(4), SIGMAS, log=True
    )
    assert logp == pytest.approx(np.log(expected), rel=1e-10)


def test_features_are_processed_in_sequence():
    """Two features in one step equal two steps, the second with no motion noise and dt → 0."""
    rng = np.random.default_rng(8)
    z = _features(MU, [0, 1], rng)
    mu2, S2, p2 = ekf_localization_known_correspondences(
        MU, SIGMA, U, z, [0, 1], MAP, DT, ALPHA, SIGMAS
    )
    mu1, S1, p1 = ekf_localization_known_correspondences(
        MU, SIGMA, U, z[:1], [0], MAP, DT, ALPHA, SIGMAS
    )
    # A "step" with v = ω = 0 is the identity motion with zero noise.
    mu1b, S1b, p1b = ekf_localization_known_correspondences(
        mu1, S1, [0, 0], z[1:], [1], MAP, DT, ALPHA, SIGMAS
    )
    np.testing.assert_allclose(mu2, mu1b, atol=1e-12)
    np.testing.assert_allclose(S2, S1b, atol=1e-12)
    assert p2 == pytest.approx(p1 * p1b, rel=1e-10)


# --------------------------------------------------------------------------- ±π


def _rotate(angle, mu, Sigma, z_world_map):
    c, s = np.cos(angle), np.sin(angle)
    R3 = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    mu_r = R3 @ mu
    mu_r[2] = mu[2] + angle
    m = z_world_map.copy()
    m[:, :2] = z_world_map[:, :2] @ R3[:2, :2].T
    return mu_r, R3 @ Sigma @ R3.T, m, R3


@pytest.mark.parametrize("method", ["ekf", "ekf_ml"])
def test_ekf_is_rotation_equivariant_across_pi(method):
    """Rotating the world so that heading and bearings straddle ±π rotates the result."""
    rng = np.random.default_rng(11)
    c = np.array([0, 1, 2])
    x_true = velocity_motion(MU, U, DT)
    z = _features(x_true, c, rng, sigmas=np.array([0.05, 0.02, 0.0]))
    # The rotation that puts the predicted heading at π - 0.005.
    angle = np.pi - 0.005 - x_true[2]
    results = []
    for a in (0.0, angle):
        mu_r, Sigma_r, m_r, R3 = _rotate(a, MU, SIGMA, MAP)
        if method == "ekf":
            out = ekf_localization_known_correspondences(
                mu_r, Sigma_r, U, z, c, m_r, DT, ALPHA, SIGMAS
            )
        else:
            out = ekf_localization(mu_r, Sigma_r, U, z, m_r, DT, ALPHA, SIGMAS)
            np.testing.assert_array_equal(out[2], c)
        results.append((out[0], out[1], R3))
    (mu0, S0, _), (mu1, S1, R3) = results
    back = R3.T @ mu1
    np.testing.assert_allclose(back[:2], mu0[:2], atol=1e-9)
    assert wrap_angle(mu1[2] - angle - mu0[2]) == pytest.approx(0, abs=1e-9)
    np.testing.assert_allclose(R3.T @ S1 @ R3, S0, atol=1e-10)
    assert -np.pi <= mu1[2] < np.pi


def test_ukf_heading_is_invariant_under_a_full_turn():
    """μ_θ and μ_θ - 2π give the same UKF step (the sigma points' headings differ by 2π)."""
    rng = np.random.default_rng(12)
    c = np.array([0, 1, 2])
    z = _features(velocity_motion(MU, U, DT), c, rng)
    mu_a = np.array([MU[0], MU[1], np.pi - 0.01])
    out = [
        ukf_localization(mu_a - [0, 0, turn], SIGMA, U, z, c, MAP, DT, ALPHA, SIGMAS)
        for turn in (0.0, 2 * np.pi)
    ]
    np.testing.assert_allclose(out[0][0], out[1][0], atol=1e-12)
    np.testing.assert_allclose(out[0][1], out[1][1], atol=1e-12)
    assert out[0][2] == pytest.approx(out[1][2], rel=1e-10)


@pytest.mark.parametrize("method", ["ekf", "ukf"])
def test_bearings_straddling_pi_behind_the_robot(method):
    """A landmark straight behind: its sigma-point bearings fall on both sides of ±π.

    The filter must agree with the same geometry turned by 90° (nothing near the cut);
    at small noise EKF and UKF results are compared to 1e-6.
    """
    eps = 1e-2
    results = []
    for a in (0.0, np.pi / 2):
        mu = np.array([0.0, 0.0, a])
        c_, s_ = np.cos(a), np.sin(a)
        landmarks = np.array([[-5.0, 0.01, 0.0], [0.5, 4.0, 1.0]])
        landmarks[:, :2] = landmarks[:, :2] @ np.array([[c_, s_], [-s_, c_]])
        z = landmark_measurement(mu, landmarks)
        z[0, 1] = wrap_angle(z[0, 1] + 0.01)  # measured on the other side of the cut
        args = (mu, np.eye(3) * eps**2, [0.0, 0.0], z, [0, 1], landmarks, DT, ALPHA, SIGMAS * eps)
        if method == "ekf":
            mu_t, S_t, _ = ekf_localization_known_correspondences(*args)
        else:
            mu_t, S_t, _ = ukf_localization(*args)
        R = np.array([[c_, -s_], [s_, c_]])
        results.append((R.T @ mu_t[:2], wrap_angle(mu_t[2] - a), S_t))
    assert abs(results[0][1]) < 0.01  # the heading moved by well under the cut's 2π
    np.testing.assert_allclose(results[0][0], results[1][0], atol=1e-6 * eps)
    assert results[0][1] == pytest.approx(results[1][1], abs=1e-6 * eps)


def test_unwrapped_bearing_innovation_of_the_deck_throws_the_pose_away():
    """Errata F4: with the heading near π a bearing innovation of ~2π must be wrapped."""
    x = np.array([0.0, 0.0, 0.0])
    landmark = np.array([[-5.0, 0.1, 0.0]])  # behind the robot: bearing π - 0.02
    zhat = landmark_measurement(x, landmark[0])
    z = zhat.copy()
    z[1] = wrap_angle(z[1] + 0.03)  # a small measurement error that crosses the cut
    assert abs(z[1] - zhat[1]) > 6  # the raw difference the deck would use
    mu, _, _ = ekf_localization_known_correspondences(
        x, np.eye(3) * 0.01, [0, 0], z[None], [0], landmark, 1.0, np.zeros(4), SIGMAS
    )
    assert abs(wrap_angle(mu[2] - x[2])) < 0.07
    # The deck's literal innovation moves the heading by more than a radian.
    H = landmark_measurement_jacobian(x, landmark[0])
    S = H @ (np.eye(3) * 0.01) @ H.T + np.diag(SIGMAS**2)
    K = np.eye(3) * 0.01 @ H.T @ np.linalg.inv(S)
    deck_mu = x + K @ (z - zhat)
    assert abs(deck_mu[2] - x[2]) > 1.0


# --------------------------------------------------------------------------- Table 7.3


def test_ml_association_picks_the_true_landmark_on_a_well_separated_map():
    m = grid_landmarks(4, 4, 10.0, origin=(-15, -15))
    alpha = np.array([0.01, 0.001, 0.001, 0.01])
    sigmas = np.array([0.1, 0.02, 0.1])
    run = simulate_run(
        [0, -10, 0],
        loop_controls(150, 0.2, v=1.0, radius=10.0),
        0.2,
        m,
        alpha,
        sigmas,
        max_range=12,
        fov=1.2,
        rng=2,
    )
    for signatures in (True, False):
        res = run_filter(
            run.steps,
            run.poses[0],
            np.eye(3) * 1e-3,
            m,
            alpha,
            sigmas,
            method="ekf_ml",
            signatures=signatures,
        )
        true_c = np.concatenate([s.c for s in run.steps])
        assert len(true_c) > 200
        np.testing.assert_array_equal(np.concatenate(res.c), true_c)


def test_ml_uses_the_signature():
    """Two landmarks at the same place, told apart only by their signatures."""
    m = np.array([[5.0, 0.0, 1.0], [5.0, 0.0, 7.0], [0.0, 6.0, 3.0]])
    x = np.array([0.0, 0.0, 0.0])
    for j in (0, 1):
        z = landmark_measurement(x, m[j])[None]
        _, _, c = ekf_localization(x, np.eye(3) * 1e-3, [0, 0], z, m, 1.0, np.zeros(4), SIGMAS)
        assert c.tolist() == [j]


def test_gate_rejects_a_feature_no_landmark_explains():
    z = np.array([[3.0, 2.5, 0.0], *landmark_measurement(velocity_motion(MU, U, DT), MAP[[1]])])
    mu_g, S_g, c_g = ekf_localization(MU, SIGMA, U, z, MAP, DT, ALPHA, SIGMAS, gate=0.99)
    assert c_g.tolist() == [-1, 1]
    # Gated out = as if the clutter had not been seen.
    mu_1, S_1, _ = ekf_localization(MU, SIGMA, U, z[1:], MAP, DT, ALPHA, SIGMAS)
    np.testing.assert_allclose(mu_g, mu_1, atol=1e-14)
    np.testing.assert_allclose(S_g, S_1, atol=1e-14)
    # The book's algorithm (no gate) associates the clutter with something.
    _, _, c = ekf_localization(MU, SIGMA, U, z, MAP, DT, ALPHA, SIGMAS)
    assert c[0] >= 0


def test_ml_with_known_winner_equals_known_correspondences():
    rng = np.random.default_rng(21)
    c = np.array([3, 0, 1])
    z = _features(velocity_motion(MU, U, DT), c, rng)
    mu_k, S_k, _ = ekf_localization_known_correspondences(
        MU, SIGMA, U, z, c, MAP, DT, ALPHA, SIGMAS
    )
    mu_m, S_m, c_m = ekf_localization(MU, SIGMA, U, z, MAP, DT, ALPHA, SIGMAS)
    np.testing.assert_array_equal(c_m, c)
    np.testing.assert_allclose(mu_m, mu_k, atol=1e-14)
    np.testing.assert_allclose(S_m, S_k, atol=1e-14)


# --------------------------------------------------------------------------- Table 7.4


def test_ukf_weights_are_wan_van_der_merwe():
    gamma, wm, wc = ukf_weights(7, 0.5, 2.0, 1.0)
    lam = 0.25 * 8 - 7
    assert gamma == pytest.approx(math.sqrt(7 + lam))
    assert wm[0] == pytest.approx(lam / (7 + lam))
    assert wc[0] == pytest.approx(lam / (7 + lam) + 1 - 0.25 + 2)
    np.testing.assert_allclose(wm[1:], 1 / (2 * (7 + lam)))
    assert wm.sum() == pytest.approx(1.0)


filterpy = pytest.importorskip("filterpy.kalman")


def _book_g(x, u, dt):
    """Table 7.2 line 6 (ω ≠ 0), written out for the reference filter."""
    v, w = u
    th = x[2]
    return np.array(
        [
            x[0] - v / w * np.sin(th) + v / w * np.sin(th + w * dt),
            x[1] + v / w * np.cos(th) - v / w * np.cos(th + w * dt),
            th + w * dt,
        ]
    )


def _book_h(x, landmark):
    dx, dy = landmark[0] - x[0], landmark[1] - x[1]
    return np.array([np.hypot(dx, dy), np.arctan2(dy, dx) - x[2]])


@pytest.mark.parametrize(
    ("k", "ukf_alpha", "beta", "kappa"),
    [(1, 1.0, 2.0, 0.0), (1, 0.5, 2.0, 1.0), (3, 1.0, 2.0, 0.0), (2, 0.8, 0.0, 2.0)],
)
def test_ukf_matches_filterpy_on_the_augmented_state(k, ukf_alpha, beta, kappa):
    """filterpy's UnscentedKalmanFilter with MerweScaledSigmaPoints on x^a = (x, ε_u, ε_z)."""
    rng = np.random.default_rng(100 + k)
    c = np.array([0, 1, 3][:k], dtype=int)
    z = _features(velocity_motion(MU, U, DT), c, rng)[:, :2]
    n = 5 + 2 * k
    M = np.diag(
        [ALPHA[0] * U[0] ** 2 + ALPHA[1] * U[1] ** 2, ALPHA[2] * U[0] ** 2 + ALPHA[3] * U[1] ** 2]
    )

    def fx(xa, dt):
        out = xa.copy()
        out[:3] = _book_g(xa[:3], U + xa[3:5], dt)
        return out

    def hx(xa):
        return np.concatenate(
            [_book_h(xa[:3], MAP[j]) + xa[5 + 2 * i : 7 + 2 * i] for i, j in enumerate(c)]
        )

    points = filterpy.MerweScaledSigmaPoints(n, alpha=ukf_alpha, beta=beta, kappa=kappa)
    ref = filterpy.UnscentedKalmanFilter(dim_x=n, dim_z=2 * k, dt=DT, hx=hx, fx=fx, points=points)
    ref.x = np.concatenate([MU, np.zeros(n - 3)])
    P = np.zeros((n, n))
    P[:3, :3] = SIGMA
    P[3:5, 3:5] = M
    P[5:, 5:] = np.kron(np.eye(k), np.diag(SIGMAS[:2] ** 2))
    ref.P = P
    ref.Q = np.zeros((n, n))
    ref.R = np.zeros((2 * k, 2 * k))
    ref.predict()
    ref.update(z.ravel())

    mu, Sigma, logp = ukf_localization(
        MU,
        SIGMA,
        U,
        z,
        c,
        MAP,
        DT,
        ALPHA,
        SIGMAS,
        ukf_alpha=ukf_alpha,
        beta=beta,
        kappa=kappa,
        log=True,
    )
    np.testing.assert_allclose(mu, ref.x[:3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(Sigma, ref.P[:3, :3], rtol=0, atol=1e-13)
    assert logp == pytest.approx(ref.log_likelihood, rel=1e-10)


def test_ukf_ignores_signatures():
    rng = np.random.default_rng(4)
    c = np.array([0, 2])
    z = _features(MU, c, rng)
    a = ukf_localization(MU, SIGMA, U, z, c, MAP, DT, ALPHA, SIGMAS)
    b = ukf_localization(MU, SIGMA, U, z[:, :2], c, MAP, DT, ALPHA, SIGMAS[:2])
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("k", [0, 1, 3])
def test_ekf_and_ukf_agree_as_the_noise_vanishes(k):
    """Scale every covariance by ε²: the filters differ by O(ε²), the corrections are O(ε)."""
    eps = 1e-4
    rng = np.random.default_rng(7)
    c = np.array([0, 1, 3][:k], dtype=int)
    x_true = velocity_motion(MU, U, DT)
    sig = SIGMAS * eps
    z = landmark_measurement(x_true, MAP[c]) + rng.standard_normal((k, 3)) * sig
    Sigma0 = SIGMA * eps**2
    e_mu, e_S, e_p = ekf_localization_known_correspondences(
        MU, Sigma0, U, z[:, :2], c, MAP, DT, ALPHA * eps**2, sig
    )
    u_mu, u_S, u_p = ukf_localization(MU, Sigma0, U, z[:, :2], c, MAP, DT, ALPHA * eps**2, sig)
    scale = eps  # size of the correction and of the posterior standard deviations
    assert np.max(np.abs(e_mu - u_mu)) < 1e-3 * scale
    np.testing.assert_allclose(u_S, e_S, rtol=1e-3, atol=1e-3 * scale**2)
    if k:
        assert math.log(u_p) == pytest.approx(math.log(e_p), rel=1e-3)


# --------------------------------------------------------------------------- consistency


def _monte_carlo_nees(method, runs=25, steps=80, seed=0):
    m = grid_landmarks(3, 3, 5.0, origin=(-5, -5))
    alpha = np.array([0.01, 0.002, 0.002, 0.01])
    sigmas = np.array([0.1, 0.02, 0.1])
    rng = np.random.default_rng(seed)
    Sigma0 = np.diag([0.01, 0.01, 0.0025])
    out = np.empty((runs, steps))
    for r in range(runs):
        x0 = np.array([0.0, -3.0, 0.0])
        run = simulate_run(
            x0,
            loop_controls(steps, 0.2, v=1.0, radius=3.0),
            0.2,
            m,
            alpha,
            sigmas,
            max_range=6.0,
            fov=0.8,
            rng=rng,
        )
        mu0 = x0 + rng.multivariate_normal(np.zeros(3), Sigma0)
        res = run_filter(run.steps, mu0, Sigma0, m, alpha, sigmas, method=method)
        out[r] = nees(run.poses[1:], res.mu, res.Sigma)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("method", ["ekf", "ukf"])
def test_nees_lies_within_its_chi2_bounds_on_a_seeded_simulation(method):
    """Average NEES over 25 runs inside the two-sided 95 % χ²₇₅/25 bounds at ≥ 90 % of steps."""
    runs = 25
    values = _monte_carlo_nees(method, runs=runs)
    avg = values.mean(axis=0)
    lo = chi2_quantile(0.025, 3 * runs) / runs
    hi = chi2_quantile(0.975, 3 * runs) / runs
    inside = np.mean((avg >= lo) & (avg <= hi))
    assert inside >= 0.9, (inside, avg.mean())
    assert 2.6 < values.mean() < 3.4


def test_nees_of_an_overconfident_filter_is_detected():
    """The same check fails when the filter's noise is understated tenfold in σ."""
    m = grid_landmarks(3, 3, 5.0, origin=(-5, -5))
    alpha = np.array([0.01, 0.002, 0.002, 0.01])
    sigmas = np.array([0.1, 0.02, 0.1])
    run = simulate_run(
        [0, -3, 0],
        loop_controls(80, 0.2, v=1.0, radius=3.0),
        0.2,
        m,
        alpha,
        sigmas,
        max_range=6.0,
        fov=0.8,
        rng=1,
    )
    res = run_filter(run.steps, run.poses[0], np.eye(3) * 1e-4, m, alpha / 100, sigmas / 10)
    assert nees(run.poses[1:], res.mu, res.Sigma).mean() > 30


def test_nees_wraps_the_heading_error():
    Sigma = np.diag([1.0, 1.0, 0.01])
    assert nees([0, 0, np.pi - 0.05], [0, 0, -np.pi + 0.05], Sigma) == pytest.approx(1.0)
    batch = nees(np.zeros((4, 3)), np.ones((4, 3)), np.broadcast_to(np.eye(3), (4, 3, 3)))
    np.testing.assert_allclose(batch, 3.0)


def test_chi2_quantile_against_scipy():
    stats = pytest.importorskip("scipy.stats")
    for dof in (1, 2, 3, 4, 7, 75, 150):
        for p in (0.025, 0.5, 0.95, 0.99):
            assert chi2_quantile(p, dof) == pytest.approx(stats.chi2.ppf(p, dof), rel=1e-10)


# --------------------------------------------------------------------------- edge cases


@pytest.mark.parametrize("method", ["ekf", "ekf_ml", "ukf"])
def test_step_without_features_and_robot_at_rest(method):
    empty = np.zeros((0, 3))
    for u in ([0.0, 0.0], [0.5, 0.0], U):
        if method == "ekf":
            mu, S, p = ekf_localization_known_correspondences(
                MU, SIGMA, u, empty, [], MAP, DT, ALPHA, SIGMAS
            )
            assert p == 1.0
        elif method == "ekf_ml":
            mu, S, c = ekf_localization(MU, SIGMA, u, empty, MAP, DT, ALPHA, SIGMAS)
            assert c.shape == (0,)
        else:
            mu, S, p = ukf_localization(MU, SIGMA, u, empty, [], MAP, DT, ALPHA, SIGMAS)
            assert p == 1.0
        assert np.all(np.isfinite(mu)) and np.all(np.isfinite(S))
        if not np.any(u):
            np.testing.assert_allclose(mu, MU, atol=1e-15)
            np.testing.assert_allclose(S, SIGMA, atol=1e-15)


def test_ukf_accepts_a_known_pose_and_rest():
    """Σ = 0 and M = 0 (robot at rest): a singular augmented covariance, still finite."""
    z = landmark_measurement(MU, MAP[[0]])
    mu, S, p = ukf_localization(MU, np.zeros((3, 3)), [0, 0], z, [0], MAP, DT, ALPHA, SIGMAS)
    np.testing.assert_allclose(mu, MU, atol=1e-12)
    np.testing.assert_allclose(S, 0, atol=1e-15)
    assert np.isfinite(p) and p > 0


GOOD = dict(
    mu=MU,
    Sigma=SIGMA,
    u=U,
    z=np.array([[4.0, 0.1, 0.0]]),
    c=[0],
    m=MAP,
    dt=DT,
    alpha=ALPHA,
    sigmas=SIGMAS,
)


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("mu", [0, 0], "mu"),
        ("mu", [0, np.nan, 0], "mu"),
        ("Sigma", np.diag([1.0, -1.0, 1.0]), "Sigma"),
        ("Sigma", np.array([[1.0, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "Sigma"),
        ("Sigma", np.eye(2), "Sigma"),
        ("u", [1.0], "u"),
        ("z", np.ones((2, 4)), "z"),
        ("z", [[-1.0, 0.0, 0.0]], "z"),
        ("c", [7], "c"),
        ("c", [0, 1], "c"),
        ("c", [0.5], "c"),
        ("m", np.zeros((0, 3)), "m"),
        ("m", np.zeros((3, 2)), "m"),
        ("dt", 0.0, "dt"),
        ("alpha", [0.1, 0.1], "alpha"),
        ("alpha", [0.1, -0.1, 0.1, 0.1], "alpha"),
        ("sigmas", [0.1, 0.0, 0.1], "sigmas"),
        ("sigmas", [0.1], "sigmas"),
    ],
)
def test_bad_input_names_the_argument(field, value, match):
    args = dict(GOOD, **{field: value})
    with pytest.raises(ValueError, match=match):
        ekf_localization_known_correspondences(**args)
    if field != "c":
        ml = {k: v for k, v in args.items() if k != "c"}
        with pytest.raises(ValueError, match=match):
            ekf_localization(**ml)
    if field != "sigmas" or len(value) != 3 or value[1] == 0:
        with pytest.raises(ValueError, match=match):
            ukf_localization(**args)


@pytest.mark.parametrize("gate", [0.0, 1.0, -0.5, np.nan, "yes"])
def test_bad_gate(gate):
    with pytest.raises(ValueError, match="gate"):
        ekf_localization(MU, SIGMA, U, GOOD["z"], MAP, DT, ALPHA, SIGMAS, gate=gate)


def test_ukf_parameters_that_break_the_covariance_raise():
    with pytest.raises(ValueError, match="kappa"):
        ukf_localization(**GOOD, kappa=-10.0)
    with pytest.raises(ValueError, match="ukf_alpha"):
        ukf_localization(**GOOD, ukf_alpha=0.0)


def test_run_filter_rejects_unknown_method():
    with pytest.raises(ValueError, match="method"):
        run_filter([], MU, SIGMA, MAP, ALPHA, SIGMAS, method="pf")


# --------------------------------------------------------------------------- runs


def test_segment_prediction_equals_step_by_step():
    """The vectorised composition of feature-free EKF steps is the book's loop, to rounding."""
    rng = np.random.default_rng(17)
    n = 400
    u = np.column_stack([rng.uniform(0, 1.0, n), rng.normal(0, 0.5, n)])
    u[::7, 1] = 0.0  # straight stretches
    u[::11] = 0.0  # standing still
    dt = rng.uniform(0.005, 0.05, n)
    mus, Sigmas = ekf_predict_segment(MU, SIGMA, u, dt, ALPHA)
    mu, Sigma = MU, SIGMA
    for k in range(n):
        mu, Sigma, _ = ekf_localization_known_correspondences(
            mu, Sigma, u[k], np.zeros((0, 3)), [], MAP, dt[k], ALPHA, SIGMAS
        )
        assert wrap_angle(mus[k, 2] - mu[2]) == pytest.approx(0.0, abs=1e-12)
        np.testing.assert_allclose(mus[k, :2], mu[:2], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(Sigmas[k], Sigma, rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize("method", ["ekf", "ekf_ml", "ukf"])
def test_run_filter_equals_the_step_functions(method):
    m = grid_landmarks(3, 3, 4.0, origin=(-4, -4))
    alpha = np.array([0.01, 0.002, 0.002, 0.01])
    sigmas = np.array([0.1, 0.02, 0.1])
    run = simulate_run(
        [0, -3, 0],
        loop_controls(60, 0.1, v=1.0, radius=3.0),
        0.1,
        m,
        alpha,
        sigmas,
        max_range=7.0,
        fov=0.4,
        rng=4,
    )
    assert any(len(s.c) == 0 for s in run.steps) and any(len(s.c) > 1 for s in run.steps)
    res = run_filter(run.steps, run.poses[0], np.eye(3) * 1e-3, m, alpha, sigmas, method=method)
    mu, Sigma = run.poses[0], np.eye(3) * 1e-3
    for k, s in enumerate(run.steps):
        if method == "ekf":
            mu, Sigma, lp = ekf_localization_known_correspondences(
                mu, Sigma, s.u, s.z, s.c, m, s.dt, alpha, sigmas, log=True
            )
            assert res.log_pz[k] == pytest.approx(lp, rel=1e-9, abs=1e-12)
        elif method == "ekf_ml":
            mu, Sigma, c = ekf_localization(mu, Sigma, s.u, s.z, m, s.dt, alpha, sigmas)
            np.testing.assert_array_equal(res.c[k], c)
        else:
            mu, Sigma, lp = ukf_localization(
                mu, Sigma, s.u, s.z, s.c, m, s.dt, alpha, sigmas, log=True
            )
            assert res.log_pz[k] == pytest.approx(lp, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(res.mu[k], mu, atol=1e-10)
        np.testing.assert_allclose(res.Sigma[k], Sigma, rtol=1e-9, atol=1e-14)


# --------------------------------------------------------------------------- noise fits


@pytest.mark.slow
def test_fit_motion_noise_recovers_alpha_on_a_simulation():
    """1600 windows of 0.5 s, alternately straight (v varies, ω = 0) and turning slowly
    (v = 0.1, ω varies), so that the four terms are told apart: every α comes back within
    25 % (about 3.5 standard errors; seeds 0-7 stay within 20 %)."""
    rng = np.random.default_rng(1)
    alpha = np.array([0.02, 0.004, 0.003, 0.03])
    T, dt, per = 16000, 0.05, 10  # commands change every 0.5 s
    nw = T // per
    straight = np.arange(nw) % 2 == 0
    v = np.where(straight, rng.uniform(0.5, 1.5, nw), 0.1)
    w = np.where(straight, 0.0, rng.choice([-1, 1], nw) * rng.uniform(0.5, 1.5, nw))
    controls = np.column_stack([np.repeat(v, per), np.repeat(w, per)])
    run = simulate_run([0, 0, 0], controls, dt, MAP[:2], alpha, SIGMAS, rng=rng)
    fit = fit_motion_noise(controls, np.full(T, dt), run.poses, window=0.5)
    assert fit.windows == nw
    np.testing.assert_allclose(fit.alpha, alpha, rtol=0.25)
    # Under the fitted noise the window errors are consistent (χ²₃: mean 3).
    assert 2.7 < np.nanmean(fit.nees) < 3.3


def test_fit_measurement_noise_recovers_bias_and_sigma():
    rng = np.random.default_rng(32)
    poses = np.column_stack([rng.uniform(-2, 2, (4000, 2)), rng.uniform(-np.pi, np.pi, 4000)])
    c = rng.integers(0, len(MAP), 4000)
    z = landmark_measurement(poses, MAP[c])
    z[:, 0] += 0.05 + 0.1 * rng.standard_normal(4000)
    z[:, 1] = wrap_angle(z[:, 1] - 0.01 + 0.03 * rng.standard_normal(4000))
    bias, sigma, robust = fit_measurement_noise(z, c, poses, MAP)
    assert np.all(np.abs(bias - [0.05, -0.01]) < 4 * np.array([0.1, 0.03]) / np.sqrt(4000))
    np.testing.assert_allclose(sigma, [0.1, 0.03], rtol=0.05)
    np.testing.assert_allclose(robust, [0.1, 0.03], rtol=0.08)


def test_ukf_ml_association_on_a_well_separated_map_equals_known():
    m = grid_landmarks(4, 4, 10.0, origin=(-15, -15))
    alpha = np.array([0.01, 0.001, 0.001, 0.01])
    sigmas = np.array([0.1, 0.02, 0.1])
    run = simulate_run(
        [0, -10, 0],
        loop_controls(100, 0.2, v=1.0, radius=10.0),
        0.2,
        m,
        alpha,
        sigmas,
        max_range=12,
        fov=1.2,
        rng=2,
    )
    ml = run_filter(run.steps, run.poses[0], np.eye(3) * 1e-3, m, alpha, sigmas, method="ukf_ml")
    known = run_filter(run.steps, run.poses[0], np.eye(3) * 1e-3, m, alpha, sigmas, method="ukf")
    np.testing.assert_array_equal(np.concatenate(ml.c), np.concatenate([s.c for s in run.steps]))
    np.testing.assert_allclose(ml.mu, known.mu, atol=1e-12)
    np.testing.assert_allclose(ml.Sigma, known.Sigma, atol=1e-14)


def test_ukf_ml_scores_each_landmark_with_the_one_feature_table():
    """The association statistics are the one-feature UKF's: its p_z picks the same landmark."""
    rng = np.random.default_rng(41)
    z = _features(velocity_motion(MU, U, DT), [2], rng)
    logps = [
        ukf_localization(MU, SIGMA, U, z, [k], MAP, DT, ALPHA, SIGMAS, log=True)[2]
        for k in range(len(MAP))
    ]
    _, _, c = ukf_localization_ml(MU, SIGMA, U, z, MAP, DT, ALPHA, SIGMAS)
    assert c.tolist() == [int(np.argmax(logps))] == [2]
    clutter = np.array([[3.0, 2.5, 0.0]])
    mu_g, S_g, c_g = ukf_localization_ml(MU, SIGMA, U, clutter, MAP, DT, ALPHA, SIGMAS, gate=0.99)
    assert c_g.tolist() == [-1]
    mu_0, S_0, _ = ukf_localization(MU, SIGMA, U, np.zeros((0, 2)), [], MAP, DT, ALPHA, SIGMAS)
    np.testing.assert_allclose(mu_g, mu_0, atol=1e-14)
    np.testing.assert_allclose(S_g, S_0, atol=1e-14)


def test_covariance_ellipse_is_the_chi2_contour():
    Sigma = np.array([[0.5, 0.2, 0.01], [0.2, 0.3, 0.0], [0.01, 0.0, 0.1]])
    xy = covariance_ellipse([1.0, 2.0, 0.3], Sigma, p=0.95)
    d = xy - [1.0, 2.0]
    d2 = np.einsum("ni,ij,nj->n", d, np.linalg.inv(Sigma[:2, :2]), d)
    np.testing.assert_allclose(d2, chi2_quantile(0.95, 2), rtol=1e-10)
    # 95 % of Gaussian draws fall inside (2000 draws: within 4 standard errors).
    rng = np.random.default_rng(0)
    draws = rng.multivariate_normal([0, 0], Sigma[:2, :2], size=2000)
    inside = np.einsum("ni,ij,nj->n", draws, np.linalg.inv(Sigma[:2, :2]), draws) <= chi2_quantile(
        0.95, 2
    )
    assert abs(inside.mean() - 0.95) < 4 * np.sqrt(0.95 * 0.05 / 2000)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(m=np.zeros((0, 3))), "m"),
        (dict(Sigma=np.diag([1.0, -1.0, 1.0])), "Sigma"),
        (dict(sigmas=[0.1, 0.0]), "sigmas"),
        (dict(gate=1.5), "gate"),
        (dict(z=np.ones((2, 4))), "z"),
    ],
)
def test_ukf_ml_bad_input(kw, match):
    args = dict(mu=MU, Sigma=SIGMA, u=U, z=GOOD["z"], m=MAP, dt=DT, alpha=ALPHA, sigmas=SIGMAS)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        ukf_localization_ml(**args)


def test_run_filter_rejects_a_gate_for_known_correspondences():
    with pytest.raises(ValueError, match="gate"):
        run_filter([], MU, SIGMA, MAP, ALPHA, SIGMAS, method="ekf", gate=0.99)


def test_covariance_ellipse_bad_input():
    with pytest.raises(ValueError, match="Sigma"):
        covariance_ellipse(MU, np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="Sigma"):
        covariance_ellipse(MU, np.eye(4))
