"""Regression tests for issue 11: each example of its items 1-10, as a new user tried it.

Every test here failed (NaN, a wrong value, a leaked warning, or an unhelpful error) before
the fix. pytest turns warnings into errors (pyproject), so "no warning" is checked too.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from probrob.angles import angle_diff, circular_mean, wrap_angle
from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
    sample_triangular_distribution,
)
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    motion_model_velocity,
    odometry_deltas,
    sample_motion_model_odometry,
    sample_motion_model_velocity,
    velocity_motion,
    velocity_motion_jacobians,
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


# ----------------------------------------------------- item 4: complex input


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: wrap_angle(1 + 2j), "theta"),
        (lambda: angle_diff(0.0, [1j]), "b"),
        (lambda: prob_normal_distribution(1j, 1.0), "a"),
        (lambda: prob_triangular_distribution(0.0, 1 + 0j), "b2"),
        (lambda: sample_normal_distribution(np.array([1 + 0j])), "b2"),
        (lambda: motion_model_velocity([1j, 0, 0], [1, 0], X0, 1.0, [0.1] * 6), "x_t"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1.0 + 0j, [0.1] * 6), "dt"),
        (lambda: sample_motion_model_velocity([1, 0j], X0, 1.0, [0.1] * 6), "u_t"),
        (lambda: motion_model_odometry(X0, np.zeros((2, 3)) * 1j, X0, [0.1] * 4), "u_t"),
        (lambda: odometry_deltas(X0, [0, 0, 1j]), "xbar_t"),
        (lambda: apply_odometry_deltas(X0, 0.1, [1 + 1j], 0.0), "trans"),
        (lambda: velocity_motion([0, 0, 0], [1, 0], [1j]), "dt"),
    ],
)
def test_complex_input_is_a_type_error_naming_the_argument(call, name):
    with pytest.raises(TypeError, match=rf"\b{name}\b.*complex"):
        call()


# ----------------------------------------------------- item 5: batch shapes


def test_batch_shapes_that_do_not_broadcast_name_each_argument():
    with pytest.raises(ValueError, match=r"x_t \(5,\).*u_t \(4,\).*x_prev \(\)"):
        motion_model_velocity(np.zeros((5, 3)), np.zeros((4, 2)), X0, 1.0, [0.1] * 6)
    with pytest.raises(ValueError, match=r"u_t \(4,\).*x_prev \(5,\)"):
        sample_motion_model_velocity(np.zeros((4, 2)), np.zeros((5, 3)), 1.0, [0.1] * 6)
    with pytest.raises(ValueError, match=r"x_t \(5,\).*u_t \(4,\)"):
        motion_model_odometry(np.zeros((5, 3)), np.zeros((4, 2, 3)), X0, [0.1] * 4)
    with pytest.raises(ValueError, match=r"a \(5,\).*b2 \(4,\)"):
        prob_normal_distribution(np.zeros(5), np.ones(4))
    with pytest.raises(ValueError, match=r"a \(5,\).*b \(4,\)"):
        angle_diff(np.zeros(5), np.ones(4))
    with pytest.raises(ValueError, match=r"x_prev \(5,\).*rot1 \(4,\)"):
        apply_odometry_deltas(np.zeros((5, 3)), np.zeros(4), 1.0, 0.0)
    with pytest.raises(ValueError, match=r"xbar_prev \(5,\).*xbar_t \(4,\)"):
        odometry_deltas(np.zeros((5, 3)), np.zeros((4, 3)))
    with pytest.raises(ValueError, match=r"x_prev \(5,\).*u_t \(4,\)"):
        velocity_motion_jacobians(np.zeros((5, 3)), np.zeros((4, 2)), 1.0)


# ----------------------------------------------------- item 6: overflow


@pytest.mark.parametrize(
    ("call", "culprit"),
    [
        # α v² + α ω² = 2e308: overflows; names alpha, the most extreme argument
        (lambda: motion_model_velocity(X0, [1, 1], X0, 1.0, [1e308] * 6), "alpha"),
        (lambda: sample_motion_model_velocity([1, 1], X0, 1.0, [1e308] * 6), "alpha"),
        (lambda: motion_model_velocity(X0, [1e160, 0], X0, 1.0, [0.1] * 6), "u_t"),
        (lambda: motion_model_velocity([1e160, 1e160, 0], [1, 0], X0, 1.0, [0.1] * 6), "x_t"),
        (lambda: motion_model_velocity([1, 0, 0], [1, 0], X0, 1e-320, [0.1] * 6), "dt"),
        (lambda: velocity_motion(X0, [10.0, 0.0], 1e308), "dt"),
        (lambda: velocity_motion_jacobians(X0, [1.0, 0.1], 1e300), "dt"),
        (lambda: sample_motion_model_velocity([10, 0], X0, 1e308, [0.0] * 6, size=2), "dt"),
        (
            lambda: motion_model_odometry(
                X0, [[0, 0, 0], [1e200, 0, 0]], X0, [0.1] * 4, density="pose"
            ),
            "u_t",
        ),
        (lambda: motion_model_odometry([1e200, 0, 0], np.zeros((2, 3)), X0, [0.1] * 4), "x_t"),
        (
            lambda: motion_model_odometry(
                X0, [[0, 0, 0], [1e308, 0, 0]], [-1e308, 0, 0], [0.1] * 4
            ),
            "x_prev",
        ),
        (lambda: odometry_deltas([-1e308, 0, 0], [1e308, 0, 0]), "xbar"),
        (lambda: apply_odometry_deltas([1e308, 0, 0], 0.0, 1.7e308, 0.0), "trans"),
        (lambda: apply_odometry_deltas([1e308, 0, 0], 0.0, 1e308, 0.0), "(x_prev|trans)"),
        (lambda: sample_motion_model_odometry([[0, 0, 0], [1e200, 0, 0]], X0, [0.1] * 4), "u_t"),
    ],
)
def test_overflow_is_reported_against_the_callers_argument(call, culprit):
    with pytest.raises(ValueError, match=rf"(?s)^{culprit}\w* = .* overflows float64") as info:
        call()
    # never an internal name
    assert not re.search(r"\b(b2|a) must", str(info.value))


def test_huge_dt_gives_a_density_not_an_overflow_error():
    # the Jacobian ½|v̂|Δt⁴ sinc² is taken in log space: Δt = 1e300 is fine
    args = ([1, 0, 0], [1, 0], X0, 1e300, [0.1] * 6)  # v̂ = 1e-300, ω̂ = γ̂ = 0
    book = prob_normal_distribution(1.0, 0.1) * prob_normal_distribution(0.0, 0.1) ** 2
    assert motion_model_velocity(*args) == pytest.approx(book, rel=1e-12)
    log_pose = motion_model_velocity(*args, density="pose", log=True)
    expected = np.log(book / 0.5) + 300 * np.log(10) - 1200 * np.log(10)
    assert log_pose == pytest.approx(expected, rel=1e-12)
    assert motion_model_velocity(*args, density="pose") == 0.0  # e^-2070 underflows


# ----------------------------------------------------- item 7: rng and size


@pytest.mark.parametrize("bad", ["abc", -1, 1.5, True, np.random.RandomState(0), [1, 2]])
def test_bad_rng_is_rejected_naming_rng(bad):
    for call in (
        lambda: sample_normal_distribution(1.0, size=2, rng=bad),
        lambda: sample_triangular_distribution(1.0, size=2, rng=bad),
        lambda: sample_motion_model_velocity([1, 0], X0, 1.0, [0.1] * 6, rng=bad),
        lambda: sample_motion_model_odometry(np.zeros((2, 3)), X0, [0.1] * 4, rng=bad),
    ):
        with pytest.raises(ValueError, match=r"\brng\b"):
            call()


def test_rng_accepts_none_seeds_seed_sequences_and_generators():
    seq = np.random.SeedSequence(5)
    a = sample_normal_distribution(1.0, size=3, rng=np.random.SeedSequence(5))
    b = sample_normal_distribution(1.0, size=3, rng=np.random.default_rng(seq))
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(
        sample_normal_distribution(1.0, size=3, rng=np.int64(7)),
        sample_normal_distribution(1.0, size=3, rng=7),
    )
    assert sample_normal_distribution(1.0, size=3, rng=None).shape == (3,)


@pytest.mark.parametrize("bad", [2.7, 2.0, -1, (2, 1.5), "3", True, (2, -1)])
def test_bad_size_is_rejected_not_truncated(bad):
    for call in (
        lambda: sample_normal_distribution(1.0, size=bad, rng=0),
        lambda: sample_motion_model_velocity([1, 0], X0, 1.0, [0.1] * 6, size=bad, rng=0),
        lambda: sample_motion_model_odometry(np.zeros((2, 3)), X0, [0.1] * 4, size=bad, rng=0),
    ):
        with pytest.raises(ValueError, match=r"\bsize\b"):
            call()


def test_size_accepts_numpy_integers_and_tuples():
    assert sample_normal_distribution(1.0, size=np.int32(3), rng=0).shape == (3,)
    assert sample_normal_distribution(1.0, size=(2, np.int64(3)), rng=0).shape == (2, 3)
    assert sample_normal_distribution(1.0, size=[2, 3], rng=0).shape == (2, 3)


# ----------------------------------------------------- item 8: no mutation, any real dtype


def test_a_sample_callables_array_is_not_scaled_in_place():
    returned = []

    def sample(b2, size=None, rng=None):
        out = np.full(size, 0.5)
        returned.append(out)
        return out

    sample_motion_model_velocity([1, 0], X0, 0.1, [0.1] * 6, sample=sample, size=4, rng=0)
    sample_motion_model_odometry(np.zeros((2, 3)), X0, [0.1] * 4, sample=sample, size=4)
    assert all(np.all(out == 0.5) for out in returned)


@pytest.mark.parametrize("dtype", [np.int64, np.int8, np.uint16, np.float32, np.float16, bool])
def test_a_sample_callable_may_return_any_real_dtype(dtype):
    def sample(b2, size=None, rng=None):
        return np.ones(size, dtype=dtype)

    expected_v = sample_motion_model_velocity(
        [1, 0], X0, 1.0, [0.1] * 6, sample=lambda b2, size, rng: np.ones(size), size=3
    )
    got = sample_motion_model_velocity([1, 0], X0, 1.0, [0.1] * 6, sample=sample, size=3)
    assert got.dtype == np.float64
    np.testing.assert_array_equal(got, expected_v)
    got = sample_motion_model_odometry(np.zeros((2, 3)), X0, [0.1] * 4, sample=sample, size=3)
    assert got.dtype == np.float64 and np.all(np.isfinite(got))


@pytest.mark.parametrize(
    "bad", [lambda b2, size, rng: np.ones(size) * 1j, lambda b2, size, rng: np.ones(7)]
)
def test_a_sample_callable_returning_garbage_is_named(bad):
    with pytest.raises((TypeError, ValueError), match=r"\bsample\b"):
        sample_motion_model_velocity([1, 0], X0, 1.0, [0.1] * 6, sample=bad, size=3)


def test_inputs_and_prob_results_are_not_modified():
    x_t = np.array([[1.0, 0.1, 0.2], [0.0, 0.0, 0.0]])
    u_t = np.array([1.0, 0.1])
    x_prev = np.zeros(3)
    alpha = np.full(6, 0.1)
    copies = [a.copy() for a in (x_t, u_t, x_prev, alpha)]
    returned = []

    def prob(a, b2):
        out = prob_normal_distribution(a, b2)
        out = np.array(out, dtype=float, ndmin=1) * np.ones(np.shape(a))
        returned.append((out, out.copy()))
        return out

    for density in DENSITIES:
        motion_model_velocity(x_t, u_t, x_prev, 1.0, alpha, prob=prob, density=density)
    for before, after in zip(copies, (x_t, u_t, x_prev, alpha), strict=True):
        np.testing.assert_array_equal(before, after)
    for out, copy in returned:
        np.testing.assert_array_equal(out, copy)


def test_a_prob_callable_without_log_keyword_still_works_and_agrees():
    def prob(a, b2):  # linear only, as a reader might write
        return np.exp(-0.5 * np.square(a) / b2) / np.sqrt(2 * np.pi * b2)

    args = ([1.0, 0.1, 0.2], [1.0, 0.1], X0, 1.0, [0.1] * 6)
    for density in DENSITIES:
        mine = motion_model_velocity(*args, prob=prob, density=density)
        assert mine == pytest.approx(motion_model_velocity(*args, density=density), rel=1e-12)
        log = motion_model_velocity(*args, prob=prob, density=density, log=True)
        assert log == pytest.approx(np.log(mine), rel=1e-12)


# ----------------------------------------------------- item 9: no leaked warnings


def test_extreme_and_degenerate_calls_do_not_warn():
    # pytest runs with filterwarnings = error: any RuntimeWarning here fails the test.
    poses = np.array([[0, 0, 0], [0, 0, np.pi], [1e-300, 0, -np.pi], [1e6, -1e6, 3.0]])
    for alpha in ([0.0] * 6, [1e-300] * 6, [0.1] * 6, [1e10] * 6):
        for u in ([0, 0], [1e-300, 0], [0, 1e-300], [1e3, -1e3], [1, 0]):
            for dt in (1e-300, 1.0, 1e300):
                for density in DENSITIES:
                    for log in (False, True):
                        try:
                            p = motion_model_velocity(
                                poses, u, poses[::-1], dt, alpha, density=density, log=log
                            )
                        except ValueError as exc:  # an overflow, named: fine
                            assert "overflows float64" in str(exc)
                            continue
                        assert not np.isnan(p).any()
    for alpha in ([0.0] * 4, [1e-300] * 4, [0.1] * 4, [1e10] * 4):
        for u in (np.zeros((2, 3)), [[0, 0, 0], [0, 0, np.pi]], [[0, 0, 0], [1e-300, 0, 0]]):
            for density in DENSITIES:
                p = motion_model_odometry(poses, u, poses[::-1], alpha, density=density)
                assert not np.isnan(p).any()
                s = sample_motion_model_odometry(u, poses, alpha, rng=0)
                assert np.all(np.isfinite(s))


# ----------------------------------------------------- item 10: plotting and widgets


def test_plotting_errors_name_the_argument():
    import matplotlib.pyplot as plt

    from probrob.plotting import motion_extent, motion_samples, plot_pose

    try:
        with pytest.raises(ValueError, match=r"\bpose\b.*\(5, 3\)"):
            plot_pose(np.zeros((5, 3)))
        with pytest.raises(ValueError, match=r"\bpoints\b"):
            motion_extent(np.zeros((0, 3)))
        with pytest.raises(ValueError, match=r"\bn\b"):
            motion_samples("velocity", [1, 0], X0, [0.1] * 6, n=-1)
        with pytest.raises(ValueError, match=r"\bn\b"):
            motion_samples("velocity", [1, 0], X0, [0.1] * 6, n=2.5)
        assert plt.get_fignums() == []  # nothing drawn before the check
    finally:
        plt.close("all")


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(alpha=(0.6, 0.02, 0.02, 0.02, 0.02, 0.02)), r"alpha\[0\]"),
        (dict(v=5.0), r"\bv\b"),
        (dict(dt=0.0), r"\bdt\b"),
        (dict(distribution="cauchy"), "distribution"),
        (dict(n_samples=-3), "n_samples"),
        (dict(rng="abc"), r"\brng\b"),
    ],
)
def test_velocity_explorer_raises_instead_of_clamping(kwargs, name):
    from probrob.widgets import velocity_model_explorer

    with pytest.raises(ValueError, match=name):
        velocity_model_explorer(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        (dict(alpha=(0.05, 0.9, 0.05, 0.005)), r"alpha\[1\]"),
        (dict(trans=-1.0), "trans"),
        (dict(rot1=3.14), "rot1"),
        (dict(noise="gauss"), "noise"),
    ],
)
def test_odometry_explorer_raises_instead_of_clamping(kwargs, name):
    from probrob.widgets import odometry_model_explorer

    with pytest.raises(ValueError, match=name):
        odometry_model_explorer(**kwargs)


def test_out_of_range_python_ints_and_long_messages():
    with pytest.raises(ValueError, match=r"^theta is out of the float64 range"):
        wrap_angle(10**400)
    with pytest.raises(ValueError, match="x_prev") as info:
        motion_model_velocity(X0, [1, 0], [[0.0, 0.0, np.nan]] * 100_000, 1.0, [0.1] * 6)
    assert len(str(info.value)) < 300  # the value is summarised, not printed whole
