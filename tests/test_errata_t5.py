"""The numbers and claims of the errata entries of deck T5 ("Trabalho #5", F1–F7).

Each test names the entry it checks; every number the entry states is asserted here, at the
precision the entry prints it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from probrob.angles import wrap_angle
from probrob.datasets import DatasetNotFoundError, load_mrclam
from probrob.localization import (
    ekf_localization_known_correspondences,
    ukf_localization,
)
from probrob.motion import velocity_motion, velocity_motion_jacobians
from probrob.sensors import landmark_measurement, landmark_measurement_jacobian

MU = np.array([0.3, -0.2, 0.4])
SIGMA = np.array([[0.04, 0.01, 0.002], [0.01, 0.03, -0.003], [0.002, -0.003, 0.01]])
ALPHA = np.array([0.05, 0.01, 0.02, 0.05])
SIGMAS = np.array([0.1, 0.02, 0.1])  # the chapter's (σ_r, σ_φ, σ_s)


def _deck_V(th, v, w, dt):
    """Deck 004, Tables 7.2/7.3 line 4, exactly as printed."""
    s0, s1, c0, c1 = math.sin(th), math.sin(th + w * dt), math.cos(th), math.cos(th + w * dt)
    return np.array(
        [
            [-(s0 + s1) / w, v * (s0 - s1) / w**2 + v * c1 * dt / w],
            [(c0 - c1) / w, -v * (c0 - c1) / w**2 + v * s1 * dt / w],
            [0.0, dt],
        ]
    )


def _deck_H(x, landmark):
    """Deck 004, line 13, exactly as printed (H11 over q, H22 over √q)."""
    dx, dy = landmark[0] - x[0], landmark[1] - x[1]
    q = dx * dx + dy * dy
    r = math.sqrt(q)
    return np.array([[-dx / q, -dy / r, 0.0], [dy / q, -dx / r, -1.0], [0.0, 0.0, 0.0]])


# --------------------------------------------------------------------------- F1


@pytest.mark.parametrize("th", [0.0, 0.4, -2.0])
def test_f1_deck_V11_is_minus_2_sin_over_omega_for_small_turns(th):
    """F1: the deck's V11 is −2 sin θ/ω − Δt cos θ + O(ω); the right one Δt cos θ + O(ω);
    the other five entries of V are right."""
    v, dt = 0.8, 0.5
    for w in (1e-2, 1e-3):
        deck = _deck_V(th, v, w, dt)
        _, V = velocity_motion_jacobians(np.array([0.0, 0.0, th]), np.array([v, w]), dt)
        assert deck[0, 0] == pytest.approx(-2 * math.sin(th) / w - dt * math.cos(th), abs=2 * w)
        assert V[0, 0] == pytest.approx(dt * math.cos(th), abs=2 * w)
        mask = np.ones((3, 2), bool)
        mask[0, 0] = False
        np.testing.assert_allclose(deck[mask], V[mask], atol=1e-6 / w)  # cancellation in 1/ω²
    # At θ = 0 the deck's entry has the wrong sign; elsewhere it is unbounded as ω → 0.
    assert _deck_V(0.0, v, 1e-3, dt)[0, 0] == pytest.approx(-dt, rel=1e-3)
    if th != 0.0:
        assert abs(_deck_V(th, v, 1e-6, dt)[0, 0]) > 1e5


def test_f1_right_V_is_the_derivative_of_g():
    u, dt = np.array([0.8, 0.3]), 0.5
    _, V = velocity_motion_jacobians(MU, u, dt)
    eps = 1e-6
    fd = np.stack(
        [
            (velocity_motion(MU, u + d, dt) - velocity_motion(MU, u - d, dt)) / (2 * eps)
            for d in np.eye(2) * eps
        ],
        axis=-1,
    )
    np.testing.assert_allclose(V, fd, atol=1e-8)
    assert abs(_deck_V(MU[2], *u, dt)[0, 0] - fd[0, 0]) > 0.5


# --------------------------------------------------------------------------- F2


def test_f2_deck_H_is_off_by_the_factor_sqrt_q():
    """F2: the deck's H11 is the right one divided by √q, its H22 the right one times √q."""
    landmark = np.array([4.0, 1.0, 0.0])
    H = landmark_measurement_jacobian(MU, landmark)
    deck = _deck_H(MU, landmark)
    r = math.hypot(landmark[0] - MU[0], landmark[1] - MU[1])
    assert deck[0, 0] == pytest.approx(H[0, 0] / r, rel=1e-12)
    assert deck[1, 1] == pytest.approx(H[1, 1] * r, rel=1e-12)
    mask = np.ones((3, 3), bool)
    mask[0, 0] = mask[1, 1] = False
    np.testing.assert_allclose(deck[mask], H[mask], atol=1e-15)


# --------------------------------------------------------------------------- F3


def test_f3_deck_signature_is_a_cosine_and_the_pose_update_ignores_it():
    """F3: the deck's ẑ_s lies in [−1, 1]; the third row of H is zero, so the pose update is
    the same whatever signature is predicted, while p(z_t) changes."""
    rng = np.random.default_rng(3)
    poses = rng.uniform(-10, 10, (200, 3))
    landmark = np.array([2.0, -1.0, 7.0])
    dx, dy = landmark[0] - poses[:, 0], landmark[1] - poses[:, 1]
    deck_s = dx / np.hypot(dx, dy)
    assert np.all(np.abs(deck_s) <= 1.0)
    assert landmark_measurement(MU, landmark)[2] == 7.0
    z = landmark_measurement(MU, landmark)[None] + [[0.05, 0.01, 0.0]]
    z_other = z.copy()
    z_other[0, 2] = 0.3  # the signature innovation the deck's ẑ_s would give, or any other
    m = landmark[None]
    a = ekf_localization_known_correspondences(
        MU, SIGMA, [0, 0], z, [0], m, 1.0, np.zeros(4), SIGMAS
    )
    b = ekf_localization_known_correspondences(
        MU, SIGMA, [0, 0], z_other, [0], m, 1.0, np.zeros(4), SIGMAS
    )
    np.testing.assert_allclose(a[0], b[0], atol=1e-15)
    np.testing.assert_allclose(a[1], b[1], atol=1e-15)
    assert a[2] > 10 * b[2]


# --------------------------------------------------------------------------- F4


def test_f4_behind_the_robot_wrapped_and_raw_updates():
    """F4: a landmark behind the robot at (−5, 0.1), measured 0.03 rad off across ±π: the raw
    innovation is −6.25 rad; the library's step turns the robot by −0.028 rad, the deck's by
    +5.79 rad (Σ = 0.01 I, the chapter's σ)."""
    x = np.zeros(3)
    landmark = np.array([[-5.0, 0.1, 0.0]])
    z = np.array([[math.hypot(-5.0, 0.1), -math.pi + 0.01, 0.0]])
    zhat = landmark_measurement(x, landmark[0])
    assert zhat[1] == pytest.approx(math.pi - 0.02, abs=1e-4)
    assert wrap_angle(z[0, 1] - zhat[1]) == pytest.approx(0.03, abs=1e-4)
    assert z[0, 1] - zhat[1] == pytest.approx(-6.25, abs=0.005)
    mu, _, _ = ekf_localization_known_correspondences(
        x, 0.01 * np.eye(3), [0, 0], z, [0], landmark, 1.0, np.zeros(4), SIGMAS
    )
    assert wrap_angle(mu[2]) == pytest.approx(-0.028, abs=5e-4)
    H = landmark_measurement_jacobian(x, landmark[0])
    K = 0.01 * H.T @ np.linalg.inv(H @ (0.01 * np.eye(3)) @ H.T + np.diag(SIGMAS**2))
    assert (K @ (z[0] - zhat))[2] == pytest.approx(5.79, abs=0.005)
    # Sigma points whose bearings straddle ±π: the raw weighted mean is ≈ 0, not ≈ π.
    bearings = np.array([math.pi - 0.02, math.pi - 0.01, -math.pi + 0.01, -math.pi + 0.03])
    assert abs(np.mean(bearings)) < 0.01
    assert abs(wrap_angle(np.angle(np.mean(np.exp(1j * bearings))) - math.pi)) < 0.01


# --------------------------------------------------------------------------- F5


def test_f5_printed_formulas_fail_at_and_near_zero_turn_rate():
    """F5: at ω = 0 the printed G, V and μ̄ are NaN; at ω = 10⁻⁸ rad/s the printed V12 and
    V22 are wrong in the first digit (relative error > 100 %), the chord form is exact."""
    th, v, dt = 0.4, 0.8, 0.5
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.float64(0.0)
        deck_mu_x = -v / w * np.sin(th) + v / w * np.sin(th + w * dt)
        deck_G13 = -v / w * np.cos(th) + v / w * np.cos(th + w * dt)
        deck_V11 = -(np.sin(th) + np.sin(th + w * dt)) / w
    assert np.isnan(deck_mu_x) and np.isnan(deck_G13) and not np.isfinite(deck_V11)
    G, V = velocity_motion_jacobians(np.array([0.0, 0.0, th]), np.array([v, 0.0]), dt)
    assert np.all(np.isfinite(G)) and np.all(np.isfinite(V))
    assert V[0, 0] == pytest.approx(dt * math.cos(th), rel=1e-15)
    _, V8 = velocity_motion_jacobians(np.array([0.0, 0.0, th]), np.array([v, 1e-8]), dt)
    deck = _deck_V(th, v, 1e-8, dt)
    assert abs(deck[0, 1] - V8[0, 1]) > abs(V8[0, 1])
    assert abs(deck[1, 1] - V8[1, 1]) > abs(V8[1, 1])
    np.testing.assert_allclose(V8, V, atol=1e-8)


def test_f5_the_mrclam_robot_stands_still_at_times():
    """F5: 4.8 % of the MRCLAM steps (dataset 7, robot 1) command v = ω = 0."""
    try:
        data = load_mrclam()
    except DatasetNotFoundError as exc:
        pytest.skip(str(exc))
    u = np.array([s.u for s in data.stream()])
    assert np.mean(np.all(u == 0.0, axis=1)) == pytest.approx(0.048, abs=5e-4)


# --------------------------------------------------------------------------- F7


def test_f7_m_is_the_map_not_the_measurement():
    """F7: m holds the landmarks; Table 7.2 reads only the rows m_j, j = c_t^i, of the map."""
    rng = np.random.default_rng(5)
    m = np.array([[4.0, 1.0, 0.0], [-2.0, 5.0, 1.0], [1.0, -4.0, 2.0]])
    z = landmark_measurement(MU, m[[0, 2]]) + rng.normal(0, 0.01, (2, 3))
    a = ekf_localization_known_correspondences(
        MU, SIGMA, [0.8, 0.3], z, [0, 2], m, 0.5, ALPHA, SIGMAS
    )
    m2 = m.copy()
    m2[1] = [100.0, -50.0, 9.0]  # a landmark no feature is of
    b = ekf_localization_known_correspondences(
        MU, SIGMA, [0.8, 0.3], z, [0, 2], m2, 0.5, ALPHA, SIGMAS
    )
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize(("dt", "share"), [(0.5, 0.14), (0.1, 0.0063)])
def test_f7_without_the_augmented_control_noise_the_ukf_loses_VMV(dt, share):
    """F7: the UKF's Σ̄ with the control-noise sigma points minus the one without them is the
    EKF's V M Vᵀ (to 3·10⁻⁴ relative at Δt = 0.5 s, 6·10⁻⁶ at 0.1 s); leaving them out, as
    the deck's note says, drops that share of the trace (14 % and 0.63 % in this case)."""
    u = np.array([0.8, 0.3])
    none = np.zeros((0, 2))
    with_u = ukf_localization(MU, SIGMA, u, none, [], np.zeros((1, 3)), dt, ALPHA, SIGMAS[:2])[1]
    without = ukf_localization(
        MU, SIGMA, u, none, [], np.zeros((1, 3)), dt, np.zeros(4), SIGMAS[:2]
    )[1]
    _, V = velocity_motion_jacobians(MU, u, dt)
    M = np.diag([ALPHA[0] * 0.64 + ALPHA[1] * 0.09, ALPHA[2] * 0.64 + ALPHA[3] * 0.09])
    VMV = V @ M @ V.T
    rel = np.linalg.norm(with_u - without - VMV) / np.linalg.norm(VMV)
    assert rel < (3.1e-4 if dt == 0.5 else 6e-6)
    assert np.trace(with_u - without) / np.trace(with_u) == pytest.approx(share, rel=0.01)
