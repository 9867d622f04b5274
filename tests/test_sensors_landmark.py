"""Landmark models (Tables 6.4, 6.5): geometry, Jacobian, likelihood, sampler, deck errata L1–L3."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from probrob.angles import wrap_angle
from probrob.distributions import sample_normal_distribution
from probrob.sensors import (
    landmark_measurement,
    landmark_measurement_jacobian,
    landmark_model_known_correspondence,
    sample_landmark_model_known_correspondence,
)

ALPHA = 1e-3  # significance of the statistical tests (fixed seeds: the verdict is repeatable)
MAP = np.array([[2.0, 1.0, 7.0], [-3.0, 4.0, 8.0], [0.5, -2.5, 9.0]])
SIGMAS = np.array([0.1, 0.05, 0.2])
exact = functools.partial(sample_normal_distribution, method="exact")


def normal_pdf(a, sigma):
    return np.exp(-0.5 * (a / sigma) ** 2) / (np.sqrt(2 * np.pi) * sigma)


# ---- the deck as written (deck 001, "Modelo Landmark"), for the errata tests only -----------
def deck_landmark_model(f, c, x, m, sigmas):
    """Table 6.4 as deck 001 prints it: σ in the variance slot, no −θ, no wrap."""

    def prob(a, b2):  # Table 5.2's prob(a, b²), fed what the deck feeds it
        return np.exp(-0.5 * a**2 / b2) / np.sqrt(2 * np.pi * b2)

    mj = m[c]
    r_hat = np.hypot(mj[0] - x[0], mj[1] - x[1])
    phi_hat = np.arctan2(mj[1] - x[1], mj[0] - x[0])
    return (
        prob(f[0] - r_hat, sigmas[0])
        * prob(f[1] - phi_hat, sigmas[1])
        * prob(f[2] - mj[2], sigmas[2])
    )


# ---- landmark_measurement -------------------------------------------------------------------
def test_measurement_geometry():
    z = landmark_measurement([1.0, 1.0, np.pi / 2], [1.0, 3.0, 7.0])
    np.testing.assert_allclose(z, [2.0, 0.0, 7.0], atol=1e-15)
    z = landmark_measurement([0.0, 0.0, 0.0], [-1.0, 1.0])
    np.testing.assert_allclose(z, [np.sqrt(2.0), 3 * np.pi / 4])


def test_measurement_bearing_is_wrapped_and_relative_to_heading():
    # Landmark straight behind: bearing ±π, returned in [-π, π).
    z = landmark_measurement([0.0, 0.0, 0.0], [-2.0, 0.0])
    assert z[1] == -np.pi
    # Heading 3 rad, landmark at world angle -3 rad: φ = -6 rad wraps to 2π - 6.
    lm = [np.cos(-3.0), np.sin(-3.0)]
    z = landmark_measurement([0.0, 0.0, 3.0], lm)
    np.testing.assert_allclose(z[1], 2 * np.pi - 6.0, atol=1e-12)


def test_errata_L2_deck_bearing_ignores_heading():
    """L2: deck φ̂ = atan2(Δy, Δx) has no −θ; a turned robot sees the landmark elsewhere."""
    x = np.array([0.0, 0.0, 0.7])
    f = landmark_measurement(x, MAP[0])  # what the robot actually measures
    assert landmark_model_known_correspondence(f, 0, x, MAP, SIGMAS) > 10.0
    assert deck_landmark_model(f, 0, x, MAP, SIGMAS**2) < 1e-6  # the deck's φ̂ is 0.7 rad off


def test_measurement_batch_equals_one_at_a_time():
    rng = np.random.default_rng(1)
    x = rng.uniform(-5, 5, (4, 5, 3))
    z = landmark_measurement(x, MAP[1])
    assert z.shape == (4, 5, 3)
    for i in range(4):
        for j in range(5):
            np.testing.assert_array_equal(z[i, j], landmark_measurement(x[i, j], MAP[1]))
    # one pose against every landmark
    assert landmark_measurement(x[0, 0], MAP).shape == (3, 3)


# ---- Jacobian -------------------------------------------------------------------------------
def numeric_jacobian(x, m, h=1e-6):
    cols = []
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        zp, zm = landmark_measurement(x + e, m), landmark_measurement(x - e, m)
        d = zp - zm
        d[1] = wrap_angle(d[1])
        cols.append(d / (2 * h))
    return np.stack(cols, axis=-1)


@given(
    st.floats(-5, 5),
    st.floats(-5, 5),
    st.floats(-np.pi, np.pi),
    st.floats(0.2, 6.0),
    st.floats(-np.pi, np.pi),
)
def test_jacobian_matches_finite_differences(x, y, th, r, ang):
    pose = np.array([x, y, th])
    lm = np.array([x + r * np.cos(ang), y + r * np.sin(ang), 3.0])
    H = landmark_measurement_jacobian(pose, lm)
    np.testing.assert_allclose(H, numeric_jacobian(pose, lm), atol=1e-6, rtol=1e-6)


def test_jacobian_bearing_row_divides_by_q_not_sqrt_q():
    """The bearing row is ∂atan2/∂x = Δy/q: with √q (a common slip) finite differences disagree."""
    pose, lm = np.array([0.0, 0.0, 0.2]), np.array([3.0, 4.0])
    H = landmark_measurement_jacobian(pose, lm)
    fd = numeric_jacobian(pose, lm)
    np.testing.assert_allclose(H, fd, atol=1e-8)
    wrong = H.copy()
    wrong[1, :2] *= 5.0  # Δy/√q instead of Δy/q (q = 25)
    assert not np.allclose(wrong, fd, atol=1e-3)


def test_jacobian_shapes_and_singular_pose():
    rng = np.random.default_rng(2)
    assert landmark_measurement_jacobian(rng.normal(size=(7, 3)), MAP[0]).shape == (7, 3, 3)
    assert landmark_measurement_jacobian(rng.normal(size=3), MAP[:, :2]).shape == (3, 2, 3)
    with pytest.raises(ValueError, match="coincides"):
        landmark_measurement_jacobian([2.0, 1.0, 0.3], MAP[0])


# ---- Table 6.4 --------------------------------------------------------------------------------
def test_likelihood_is_the_product_of_three_normals_with_variances():
    x = np.array([0.3, -0.2, 0.4])
    f = landmark_measurement(x, MAP[1]) + np.array([0.05, -0.02, 0.1])
    q = landmark_model_known_correspondence(f, 1, x, MAP, SIGMAS)
    expected = normal_pdf(0.05, 0.1) * normal_pdf(-0.02, 0.05) * normal_pdf(0.1, 0.2)
    np.testing.assert_allclose(q, expected, rtol=1e-12)


def test_errata_L1_deck_passes_sigma_as_variance():
    """L1: prob(a, σ) with σ in the b² slot is N(0, σ) — a std of √σ, here 0.32 m, not 0.1 m."""
    x = np.array([0.3, -0.2, 0.0])
    f = landmark_measurement(x, MAP[1]) + np.array([0.05, -0.02, 0.1])
    ours = landmark_model_known_correspondence(f, 1, x, MAP, SIGMAS)
    deck = deck_landmark_model(f, 1, x, MAP, SIGMAS)  # heading 0: only L1 differs
    assert deck / ours < 0.05  # the deck's density is about 30× too flat here
    np.testing.assert_allclose(deck_landmark_model(f, 1, x, MAP, SIGMAS**2), ours, rtol=1e-12)


def test_errata_L3_bearing_error_is_wrapped():
    """L3: a bearing of π−0.01 and a prediction of −π+0.01 differ by 0.02 rad, not 2π−0.02."""
    x = np.array([0.0, 0.0, 0.0])
    lm_row = np.array([-2.0, -0.02, 7.0])  # just below the negative x axis: φ̂ ≈ −π + 0.01
    m = np.vstack([lm_row, MAP])
    phi_hat = landmark_measurement(x, lm_row)[1]
    assert phi_hat < -np.pi + 0.02
    f = np.array([np.hypot(2.0, 0.02), np.pi - 0.005, 7.0])
    q = landmark_model_known_correspondence(f, 0, x, m, SIGMAS)
    err = wrap_angle(f[1] - phi_hat)
    assert abs(err) < 0.02
    np.testing.assert_allclose(q, normal_pdf(err, 0.05) * normal_pdf(0, 0.1) * normal_pdf(0, 0.2))
    assert deck_landmark_model(f, 0, x, m, SIGMAS**2) == 0.0  # unwrapped: a 2π error


def test_log_likelihood_and_no_underflow():
    rng = np.random.default_rng(3)
    x = rng.uniform(-4, 4, (50, 3))
    f = np.array([2.0, 0.3, 8.0])
    q = landmark_model_known_correspondence(f, 1, x, MAP, SIGMAS)
    logq = landmark_model_known_correspondence(f, 1, x, MAP, SIGMAS, log=True)
    ok = q > 0
    np.testing.assert_allclose(np.log(q[ok]), logq[ok], rtol=1e-12, atol=1e-12)
    # Far away, the linear value underflows to 0 but the log stays finite.
    far = landmark_model_known_correspondence(f, 1, [400.0, 0.0, 0.0], MAP, SIGMAS, log=True)
    assert np.isfinite(far) and far < -1e6
    assert landmark_model_known_correspondence(f, 1, [400.0, 0.0, 0.0], MAP, SIGMAS) == 0.0


def test_zero_sigma_is_a_point_mass_never_nan():
    x = np.array([0.0, 0.0, 0.0])
    f = landmark_measurement(x, MAP[0])
    sig = [0.1, 0.05, 0.0]  # signature known exactly
    assert landmark_model_known_correspondence(f, 0, x, MAP, sig) == np.inf
    f_wrong = f + [0.0, 0.0, 1.0]
    assert landmark_model_known_correspondence(f_wrong, 0, x, MAP, sig) == 0.0
    assert landmark_model_known_correspondence(f_wrong, 0, x, MAP, sig, log=True) == -np.inf
    # inf · 0: the signature matches exactly but the range is off with σ_r = 0 as well
    f_far = f + [1.0, 0.0, 0.0]
    assert landmark_model_known_correspondence(f_far, 0, x, MAP, [0.0, 0.05, 0.0]) == 0.0


def test_likelihood_broadcasts_features_correspondences_and_particles():
    rng = np.random.default_rng(4)
    particles = rng.uniform(-3, 3, (6, 3))
    f = np.array([[2.0, 0.1, 7.0], [4.0, -1.0, 8.0]])
    c = np.array([0, 1])
    q = landmark_model_known_correspondence(f[:, None], c[:, None], particles[None], MAP, SIGMAS)
    assert q.shape == (2, 6)
    for i in range(2):
        for n in range(6):
            assert q[i, n] == landmark_model_known_correspondence(
                f[i], c[i], particles[n], MAP, SIGMAS
            )


# ---- Table 6.5 --------------------------------------------------------------------------------
def test_sampler_reproduces_the_feature_without_noise():
    """With σ = 0 every sampled pose sees landmark j at exactly (r, φ): the deck's θ is right."""
    f = np.array([2.5, -2.9, 8.0])
    poses = sample_landmark_model_known_correspondence(f, 1, MAP, [0.0, 0.0, 0.0], 500, rng=5)
    z = landmark_measurement(poses, MAP[1])
    np.testing.assert_allclose(z[:, 0], 2.5, rtol=1e-12)
    np.testing.assert_allclose(wrap_angle(z[:, 1] - f[1]), 0.0, atol=1e-12)
    assert np.all((poses[:, 2] >= -np.pi) & (poses[:, 2] < np.pi))


@pytest.mark.parametrize("phi", [0.4, np.pi - 0.02, -np.pi + 0.01])
def test_sampler_agrees_with_the_landmark_model(phi):
    """Seen from the sampled poses, range and bearing errors follow Table 6.4's normals."""
    f = np.array([3.0, phi, 9.0])
    sig = np.array([0.2, 0.1, 0.3])
    poses = sample_landmark_model_known_correspondence(f, 2, MAP, sig, 20000, 6, sample=exact)
    z = landmark_measurement(poses, MAP[2])
    assert stats.kstest(z[:, 0] - f[0], stats.norm(0, sig[0]).cdf).pvalue > ALPHA
    assert stats.kstest(wrap_angle(z[:, 1] - f[1]), stats.norm(0, sig[1]).cdf).pvalue > ALPHA
    ring = np.arctan2(poses[:, 1] - MAP[2, 1], poses[:, 0] - MAP[2, 0])
    assert stats.kstest(ring, stats.uniform(-np.pi, 2 * np.pi).cdf).pvalue > ALPHA
    # And the landmark model's likelihood at the samples is that of those normals.
    logq = landmark_model_known_correspondence(
        np.broadcast_to(f, poses.shape), 2, poses, MAP, sig, log=True
    )
    r_err, b_err = z[:, 0] - f[0], wrap_angle(z[:, 1] - f[1])
    expected = np.log(
        normal_pdf(r_err, sig[0]) * normal_pdf(b_err, sig[1]) * normal_pdf(0, sig[2])
    )
    np.testing.assert_allclose(logq, expected, rtol=1e-9)


def test_errata_L1_deck_sampler_noise_is_too_wide():
    """The book's sum-of-12 sampler takes a variance: sample(σ²) has std σ, sample(σ) has √σ."""
    f = np.array([3.0, 0.2, 9.0])
    poses = sample_landmark_model_known_correspondence(f, 0, MAP, [0.04, 0.01], 40000, rng=7)
    r_err = landmark_measurement(poses, MAP[0])[:, 0] - 3.0
    np.testing.assert_allclose(r_err.std(), 0.04, rtol=0.02)
    deck_noise = sample_normal_distribution(0.04, 40000, rng=7)  # the deck's sample(σ_r)
    assert deck_noise.std() > 4 * 0.04


def test_sampler_shapes_and_reproducibility():
    f = np.array([[2.0, 0.1, 7.0], [4.0, -1.0, 8.0]])
    a = sample_landmark_model_known_correspondence(f, [0, 1], MAP, SIGMAS, rng=8)
    b = sample_landmark_model_known_correspondence(f, [0, 1], MAP, SIGMAS, rng=8)
    assert a.shape == (2, 3)
    np.testing.assert_array_equal(a, b)
    assert sample_landmark_model_known_correspondence(f, [0, 1], MAP, SIGMAS, (5, 2)).shape == (
        5,
        2,
        3,
    )
    one = sample_landmark_model_known_correspondence(f[0, :2], 0, MAP[:, :2], SIGMAS[:2], 4)
    assert one.shape == (4, 3)


# ---- bad input ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(f=[1.0, 0.0]), "f"),
        (dict(f=[np.nan, 0.0, 7.0]), "f"),
        (dict(c=3), "c"),
        (dict(c=-1), "c"),
        (dict(c=0.5), "c"),
        (dict(x=[0.0, 0.0]), "x"),
        (dict(m=np.zeros((0, 3))), "m"),
        (dict(m=MAP[:, :2]), "m"),
        (dict(sigmas=[0.1, -0.1, 0.1]), "sigmas"),
        (dict(sigmas=[0.1, 0.1]), "sigmas"),
        (dict(x=np.zeros((4, 3)), f=np.zeros((5, 3))), "f"),
    ],
)
def test_landmark_model_bad_input(kwargs, name):
    args = dict(f=[2.0, 0.1, 7.0], c=0, x=[0.0, 0.0, 0.0], m=MAP, sigmas=SIGMAS) | kwargs
    with pytest.raises(ValueError, match=name):
        landmark_model_known_correspondence(**args)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(f=[1.0]), "f"),
        (dict(c=7), "c"),
        (dict(sigmas=[0.1]), "sigmas"),
        (dict(sigmas=[-0.1, 0.1]), "sigmas"),
        (dict(size=-2), "size"),
        (dict(sample="normal"), "sample"),
    ],
)
def test_sampler_bad_input(kwargs, name):
    args = dict(f=[2.0, 0.1, 7.0], c=0, m=MAP, sigmas=SIGMAS) | kwargs
    with pytest.raises(ValueError, match=name):
        sample_landmark_model_known_correspondence(**args)
