"""Regression tests for issue 11: each example of its items 1-10, as a new user tried it.

Every test here failed (NaN, a wrong value, a leaked warning, or an unhelpful error) before
the fix. pytest turns warnings into errors (pyproject), so "no warning" is checked too.
"""

from __future__ import annotations

import numpy as np
import pytest

from probrob.angles import angle_diff, circular_mean, wrap_angle
from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
)
from probrob.motion import (
    motion_model_odometry,
    motion_model_velocity,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
)

X0 = np.zeros(3)
DENSITIES = ("book", "pose", "xy")


def _grid(n=41, half=1.0, heading=0.0):
    xs = np.linspace(-half, half, n)
    xy = np.stack(np.meshgrid(xs, xs), axis=-1)
    return np.concatenate([xy, np.full((n, n, 1), heading)], axis=-1)


# ----------------------------------------------------- item 1: NaN from ordinary motion


@pytest.mark.parametrize("density", DENSITIES)
def test_robot_commanded_to_stand_still_turned_pose_has_density_zero(density):
    # All variances are 0 (v = ω = 0): the only pose with mass is x_prev itself.
    p = motion_model_velocity([0, 0, 0.5], [0, 0], X0, 1.0, [0.1] * 6, density=density)
    assert p == 0.0
    assert motion_model_velocity([0, 0, 0.5], [0, 0], X0, 1.0, [0.1] * 6, log=True) == -np.inf


def test_zero_alphas_straight_motion_with_a_turn_has_density_zero():
    # Noise-free straight motion cannot turn by 0.3 rad: 0, not inf·0 = NaN.
    assert motion_model_velocity([1, 0, 0.3], [1, 0], X0, 1.0, [0] * 6) == 0.0
    # ... and the noise-free end pose itself is the point mass.
    assert motion_model_velocity([1, 0, 0], [1, 0], X0, 1.0, [0] * 6) == np.inf


@pytest.mark.parametrize("density", DENSITIES)
def test_grid_around_a_stationary_robot_has_no_nan(density):
    grid = _grid()
    p = motion_model_velocity(grid, [0, 0], X0, 1.0, [0.1] * 6, density=density)
    assert not np.isnan(p).any()
    # The point mass at the start pose (grid centre, heading 0) and 0 elsewhere.
    expected = np.zeros((41, 41))
    expected[20, 20] = np.inf
    np.testing.assert_array_equal(p, expected)


@pytest.mark.parametrize("density", DENSITIES)
def test_odometry_with_zero_deltas_is_a_point_mass_not_nan(density):
    still = np.zeros((2, 3))
    grid = _grid(heading=0.0)
    p = motion_model_odometry(grid, still, X0, [0.1] * 4, density=density)
    assert not np.isnan(p).any()
    if density != "book":  # the sampler's variances (all 0): a point mass at x_prev
        expected = np.zeros((41, 41))
        expected[20, 20] = np.inf
        np.testing.assert_array_equal(p, expected)
    assert motion_model_odometry(X0, still, X0, [0.1] * 4, density=density) == np.inf


# ----------------------------------------------------- item 2: tiny variances


@pytest.mark.parametrize(
    ("prob", "peak"),
    [
        (prob_normal_distribution, lambda b: 1 / (np.sqrt(2 * np.pi) * b)),
        (prob_triangular_distribution, lambda b: 1 / (np.sqrt(6) * b)),
    ],
)
def test_tiny_variance_does_not_overflow(prob, peak):
    b2 = 1e-320  # subnormal; 1 / b2 overflows
    expected = peak(np.sqrt(b2))  # √(1e-320) = 1e-160: no overflow
    assert prob(0.0, b2) == pytest.approx(expected, rel=1e-12)
    assert prob(0.0, b2) == pytest.approx(4e159, rel=0.03)
    assert prob(0.0, b2, log=True) == pytest.approx(np.log(expected), rel=1e-14)
    assert prob(1.0, b2) == 0.0
    assert prob(1.0, b2, log=True) == -np.inf


def test_tiny_variance_carries_into_the_motion_densities():
    alpha = [1e-320, 0, 1e-320, 0, 1e-320, 0]  # variances 1e-320 at v = 1
    p = motion_model_velocity([1, 0, 0], [1, 0], X0, 1.0, alpha, log=True)
    # three factors of log(1 / (√(2π) b)) at zero noise, b = √1e-320 (2π·1e-320 would be
    # a subnormal with 4 digits: the log is taken of b, which is a normal double)
    log_peak = -np.log(np.sqrt(1e-320)) - 0.5 * np.log(2 * np.pi)
    assert p == pytest.approx(3 * log_peak, rel=1e-14)
    assert motion_model_velocity([1, 0, 0], [1, 0], X0, 1.0, alpha) == np.inf  # e^1100


# ----------------------------------------------------- item 3: angles


@pytest.mark.parametrize(
    "theta", [121720196640.79475, 7.05e16, 1e300, -1e308, 1.7976931348623157e308]
)
def test_wrap_angle_stays_in_range_for_huge_angles(theta):
    w = wrap_angle(theta)
    assert -np.pi <= w < np.pi
    # the exact remainder by the float 2π: math.fmod is exact
    import math

    r = math.fmod(theta, 2 * math.pi)
    r = r - 2 * math.pi if r >= math.pi else r + 2 * math.pi if r < -math.pi else r
    assert w == r


def test_wrap_angle_issue_examples():
    assert wrap_angle(121720196640.79475) != -3.1416015625
    assert wrap_angle(7.05e16) != -8.0
    assert -np.pi <= angle_diff(0.0, 1.06e18) < np.pi
    # a - b overflows (2e308): each is reduced first
    d = angle_diff(1e308, -1e308)
    assert d == wrap_angle(wrap_angle(1e308) - wrap_angle(-1e308))


@pytest.mark.parametrize("bad", [np.inf, -np.inf, np.nan, None, "x"])
def test_wrap_angle_rejects_non_finite(bad):
    with pytest.raises(ValueError, match="theta"):
        wrap_angle(bad)
    with pytest.raises(ValueError, match=r"\ba\b"):
        angle_diff(bad, 0.0)


def test_circular_mean_of_nothing_is_an_error():
    with pytest.raises(ValueError, match="theta"):
        circular_mean([])
    with pytest.raises(ValueError, match="theta"):
        circular_mean(np.zeros((3, 0)), axis=1)
    with pytest.raises(ValueError, match="weights"):
        circular_mean([0.1, 0.2], weights=[0.0, 0.0])
    with pytest.raises(ValueError, match="weights"):
        circular_mean([[0.1, 0.2], [0.3, 0.4]], weights=[[1.0, 1.0], [0.0, 0.0]], axis=1)


def test_wrap_angle_is_bit_for_bit_in_range_and_rounding_onto_pi_maps_to_minus_pi():
    rng = np.random.default_rng(0)
    inside = rng.uniform(-np.pi, np.pi, 100_000)
    np.testing.assert_array_equal(wrap_angle(inside), inside)
    # θ just below -π: θ + 2π rounds to +π exactly for the largest such doubles... the
    # exact remainder never does, and an exact π maps to -π.
    assert wrap_angle(np.pi) == -np.pi
    assert wrap_angle(np.nextafter(-np.pi, -4)) < np.pi


# ------------------------------- item 1: the densities agree with the samplers' point masses
#
# Each case has some zero variances. The samples must land where the density is nonzero
# (positive or inf), in every density mode. The cases are chosen so that the inversion of the
# motion recovers the degenerate noise variables exactly (heading 0, straight lines, rest,
# rotation in place), since a point mass's support has measure zero and a rounding error of
# 1e-16 would put a sample beside it.

VELOCITY_DEGENERATE = [
    # (u_t, alpha): robot at rest with noise parameters (every variance 0)
    ([0.0, 0.0], [0.1] * 6),
    # noise-free straight motion
    ([1.0, 0.0], [0.0] * 6),
    # rotation in place, no translational noise: v̂ = 0 exactly, x', y' = x, y
    ([0.0, 1.0], [0.0, 0.0, 0.1, 0.1, 0.1, 0.1]),
    # straight, noise only on v: ω̂ = γ̂ = 0 exactly
    ([1.0, 0.0], [0.01, 0.0, 0.0, 0.0, 0.0, 0.0]),
]


@pytest.mark.parametrize(("u", "alpha"), VELOCITY_DEGENERATE)
@pytest.mark.parametrize("density", DENSITIES)
def test_velocity_samples_land_where_the_density_is_nonzero(u, alpha, density):
    samples = sample_motion_model_velocity(u, X0, 1.0, alpha, size=2000, rng=11)
    p = motion_model_velocity(samples, u, X0, 1.0, alpha, density=density)
    assert np.all(p > 0)
    # ... and a point just off the support has density 0.
    off = samples + [0.0, 1e-3, 1e-3]
    assert np.all(motion_model_velocity(off, u, X0, 1.0, alpha, density=density) == 0)


ODOMETRY_DEGENERATE = [
    # odometry reports no motion: every variance 0
    (np.zeros((2, 3)), [0.1] * 4),
    # straight ahead, noise only on δtrans (α1 = α2 ... only α3 > 0)
    (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), [0.0, 0.0, 0.01, 0.0]),
    # noise-free rotation in place
    (np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.8]]), [0.0] * 4),
]


@pytest.mark.parametrize(("u", "alpha"), ODOMETRY_DEGENERATE)
@pytest.mark.parametrize("density", ["pose", "xy"])
def test_odometry_samples_land_where_the_density_is_nonzero(u, alpha, density):
    samples = sample_motion_model_odometry(u, X0, alpha, size=2000, rng=12)
    p = motion_model_odometry(samples, u, X0, alpha, density=density)
    assert np.all(p > 0)
    off = samples + [0.0, 1e-3, 1e-3]
    assert np.all(motion_model_odometry(off, u, X0, alpha, density=density) == 0)
