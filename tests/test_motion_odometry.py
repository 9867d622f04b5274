"""Odometry motion model: Tables 5.5 and 5.6, and the odometry deltas."""

from functools import partial

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from probrob.angles import angle_diff, wrap_angle
from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
)
from probrob.motion import (
    apply_odometry_deltas,
    motion_model_odometry,
    odometry_deltas,
    sample_motion_model_odometry,
)

EXACT = partial(sample_normal_distribution, method="exact")
ALPHA = np.array([0.05, 0.02, 0.05, 0.02])
X0 = np.array([1.0, -0.5, 2.0])
P_MIN = 0.001  # significance level of the statistical tests, at fixed seeds


def compose(pose, rot1, trans, rot2):
    """Apply (δrot1, δtrans, δrot2) to a pose: Table 5.6, lines 8-10."""
    x, y, th = pose
    return np.array(
        [x + trans * np.cos(th + rot1), y + trans * np.sin(th + rot1), th + rot1 + rot2]
    )


def odometry(rot1, trans, rot2, start=(0.3, 0.7, -0.4)):
    """An odometry reading u_t = (x̄_{t-1}, x̄_t) that moves by (δrot1, δtrans, δrot2)."""
    return np.array([start, compose(np.array(start), rot1, trans, rot2)])


def rotate_scene(pose, phi):
    x, y, th = np.moveaxis(np.asarray(pose, float), -1, 0)
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * x - s * y, s * x + c * y, wrap_angle(th + phi)], axis=-1)


def deck_deltas(prev, new):
    """Deck 000 / Table 5.5 lines 2-4 typed literally: no wrapping."""
    rot1 = np.arctan2(new[1] - prev[1], new[0] - prev[0]) - prev[2]
    return rot1, np.hypot(new[0] - prev[0], new[1] - prev[1]), new[2] - prev[2] - rot1


# ------------------------------------------------------------------ the deltas


@given(
    rot1=st.floats(-np.pi, np.pi, exclude_max=True),
    trans=st.floats(1e-3, 10),
    rot2=st.floats(-np.pi, np.pi, exclude_max=True),
    th=st.floats(-np.pi, np.pi),
)
def test_deltas_invert_the_motion(rot1, trans, rot2, th):
    start = np.array([0.5, -2.0, th])
    r1, t, r2 = odometry_deltas(start, compose(start, rot1, trans, rot2))
    assert angle_diff(r1, rot1) == pytest.approx(0.0, abs=1e-9)
    assert t == pytest.approx(trans, rel=1e-9)
    assert angle_diff(r2, rot2) == pytest.approx(0.0, abs=1e-9)
    assert -np.pi <= r1 < np.pi and -np.pi <= r2 < np.pi


def test_deltas_are_wrapped_near_pi():
    """Erratum O1: θ̄ just below π and a step just past the -π cut give δrot1 ≈ -2π + 0.1."""
    prev = np.array([0.0, 0.0, np.pi - 0.05])
    new = np.array([np.cos(-np.pi + 0.05), np.sin(-np.pi + 0.05), np.pi - 0.05])
    rot1, _, rot2 = odometry_deltas(prev, new)
    assert rot1 == pytest.approx(0.1) and rot2 == pytest.approx(-0.1)
    assert deck_deltas(prev, new)[0] == pytest.approx(-2 * np.pi + 0.1)


def test_deltas_use_atan2_not_arctan_of_the_ratio():
    """Erratum O4 (Turkish deck): tan⁻¹(Δy/Δx) sends a step to the left-rear the wrong way."""
    prev = np.array([0.0, 0.0, 0.0])
    new = np.array([-1.0, 1.0, 0.0])
    rot1 = odometry_deltas(prev, new)[0]
    assert rot1 == pytest.approx(3 * np.pi / 4)
    assert np.arctan((new[1] - prev[1]) / (new[0] - prev[0])) == pytest.approx(-np.pi / 4)


@given(
    rot1=st.floats(-np.pi, np.pi, exclude_max=True),
    trans=st.floats(0, 10),
    rot2=st.floats(-np.pi, np.pi, exclude_max=True),
    th=st.floats(-np.pi, np.pi),
)
def test_apply_deltas_is_table_5_6_lines_8_to_10(rot1, trans, rot2, th):
    start = np.array([0.5, -2.0, th])
    np.testing.assert_allclose(
        apply_odometry_deltas(start, rot1, trans, rot2), compose(start, rot1, trans, rot2)
    )


def test_zero_translation_puts_the_whole_turn_in_rot2():
    rot1, trans, rot2 = odometry_deltas([1.0, 2.0, 3.0], [1.0, 2.0, 3.5])
    assert (rot1, trans, rot2) == (0.0, 0.0, pytest.approx(0.5))


# ------------------------------------------------------------------ the sampler


def test_sampler_moves_from_the_robot_heading_not_the_odometry_heading():
    """Erratum O2 (Turkish deck): x' = x + δ̂trans cos(θ + δ̂rot1), with θ, not θ̄."""
    u = odometry(0.3, 1.0, -0.2)
    x_t = sample_motion_model_odometry(u, X0, np.zeros(4), rng=0)
    np.testing.assert_allclose(x_t, compose(X0, 0.3, 1.0, -0.2), atol=1e-12)
    theta_bar = u[0, 2]
    turkish = X0[0] + 1.0 * np.cos(theta_bar + 0.3)
    assert abs(turkish - x_t[0]) > 0.5


def test_sampler_noise_variables_have_the_table_variances():
    rot1, trans, rot2 = 0.4, 1.5, -0.3
    samples = sample_motion_model_odometry(
        odometry(rot1, trans, rot2), X0, ALPHA, sample=EXACT, size=50_000, rng=1
    )
    r1, t, r2 = odometry_deltas(X0, samples)
    a1, a2, a3, a4 = ALPHA
    for values, mean, var in [
        (r1, rot1, a1 * rot1**2 + a2 * trans**2),
        (t, trans, a3 * trans**2 + a4 * (rot1**2 + rot2**2)),
        (r2, rot2, a1 * rot2**2 + a2 * trans**2),
    ]:
        assert stats.kstest(values, stats.norm(mean, np.sqrt(var)).cdf).pvalue > P_MIN


def test_sampler_variance_is_b2_not_b():
    """Erratum D2 (Turkish deck): sample(α1 δrot1² + ...) with rand(-b, b) reads the variance as b."""
    rot1, trans, rot2 = 0.0, 1.0, 0.0
    alpha = [0.0, 0.0, 0.04, 0.0]  # δtrans has variance 0.04, standard deviation 0.2
    samples = sample_motion_model_odometry(
        odometry(rot1, trans, rot2), X0, alpha, size=40_000, rng=2
    )
    t = odometry_deltas(X0, samples)[1]
    assert t.std() == pytest.approx(0.2, rel=0.02)


def test_robot_at_rest_and_rotation_in_place():
    rest = odometry(0.0, 0.0, 0.0)
    np.testing.assert_array_equal(
        sample_motion_model_odometry(rest, X0, ALPHA, size=4, rng=0), np.broadcast_to(X0, (4, 3))
    )
    assert motion_model_odometry(X0, rest, X0, ALPHA) == np.inf
    moved = X0 + [0.01, 0, 0]
    assert motion_model_odometry(moved, rest, X0, ALPHA, density="pose") == 0.0
    # Table 5.5 takes the variances from the hypothesis, which did move: tiny but positive.
    assert 0.0 < motion_model_odometry(moved, rest, X0, ALPHA) < 1e-6
    spin = odometry(0.0, 0.0, 0.8)
    samples = sample_motion_model_odometry(spin, X0, ALPHA, size=1000, rng=3)
    assert np.all(np.isfinite(samples))
    # A pure rotation: only α4 δrot2² blurs the translation, α1 δrot2² the heading.
    assert np.std(samples[:, 2]) == pytest.approx(np.sqrt(ALPHA[0]) * 0.8, rel=0.1)
    # δrot1 = δtrans = 0 gives δrot1 zero variance: the noisy translation stays on the
    # robot's heading line, and the density is a point mass across it.
    lateral = -(samples[:, 0] - X0[0]) * np.sin(X0[2]) + (samples[:, 1] - X0[1]) * np.cos(X0[2])
    np.testing.assert_allclose(lateral, 0.0, atol=1e-12)
    assert np.std(samples[:, 0]) > 0.01
    assert motion_model_odometry(X0 + [0, 0, 0.8], spin, X0, ALPHA) == np.inf


# ------------------------------------------------------------------ the density


def test_density_peaks_at_the_odometry_pose_and_is_invariant_to_the_world_frame():
    u = odometry(0.3, 1.0, -0.2)
    x_t = compose(X0, 0.3, 1.0, -0.2)
    p = motion_model_odometry(x_t, u, X0, ALPHA)
    var1 = ALPHA[0] * 0.09 + ALPHA[1]
    var_t = ALPHA[2] + ALPHA[3] * (0.09 + 0.04)
    var2 = ALPHA[0] * 0.04 + ALPHA[1]
    peak = (
        prob_normal_distribution(0, var1)
        * prob_normal_distribution(0, var_t)
        * prob_normal_distribution(0, var2)
    )
    assert p == pytest.approx(peak, rel=1e-12)
    for phi in np.linspace(-np.pi, np.pi, 37):
        rotated = motion_model_odometry(rotate_scene(x_t, phi), u, rotate_scene(X0, phi), ALPHA)
        assert rotated == pytest.approx(p, rel=1e-9)
        # ... and of the odometry frame's, which is unrelated to the robot's.
        assert motion_model_odometry(x_t, rotate_scene(u, phi), X0, ALPHA) == pytest.approx(
            p, rel=1e-9
        )


def test_density_wraps_rotation_differences():
    """Erratum O1: with unwrapped δ, a heading θ' + 2π would be a different pose."""
    u = odometry(0.3, 1.0, -0.2)
    x_t = compose(X0, 0.35, 0.9, -0.25)
    p = motion_model_odometry(x_t, u, X0, ALPHA)
    assert motion_model_odometry(x_t + [0, 0, 2 * np.pi], u, X0, ALPHA) == pytest.approx(
        p, rel=1e-12
    )


CASES = {
    "forward": dict(
        u=odometry(0.3, 1.0, -0.2), alpha=ALPHA, prob=prob_normal_distribution, noise="variance"
    ),
    "sharp": dict(
        u=odometry(2.5, 0.8, -2.9),
        alpha=ALPHA / 5,
        prob=prob_normal_distribution,
        noise="variance",
    ),
    "near-pi": dict(
        u=odometry(0.2, 1.0, 0.1, start=(0, 0, np.pi - 0.1)),
        alpha=ALPHA,
        prob=prob_normal_distribution,
        noise="variance",
    ),
    "std": dict(
        u=odometry(0.3, 1.0, -0.2), alpha=ALPHA / 2, prob=prob_normal_distribution, noise="std"
    ),
    "triangular": dict(
        u=odometry(0.3, 1.0, -0.2),
        alpha=ALPHA,
        prob=prob_triangular_distribution,
        noise="variance",
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_pose_density_integrates_to_one_and_matches_the_sampler(
    case, grid3, chi_square, sampler_for
):
    c = CASES[case]
    samples = sample_motion_model_odometry(
        c["u"], X0, c["alpha"], sample=sampler_for(c["prob"]), noise=c["noise"], size=60_000, rng=4
    )
    grid = grid3.around(samples, 96)
    values = motion_model_odometry(
        grid.points, c["u"], X0, c["alpha"], prob=c["prob"], noise=c["noise"], density="pose"
    )
    assert grid.integrate(values) == pytest.approx(1.0, abs=1e-3)
    assert chi_square(samples, values, grid) > P_MIN
    # density="xy" is the pose density integrated over θ' (Fig. 5.3 / 5.7)
    xy = motion_model_odometry(
        grid.points[:, :, 0, :2],
        c["u"],
        X0,
        c["alpha"],
        prob=c["prob"],
        noise=c["noise"],
        density="xy",
    )
    np.testing.assert_allclose(values.sum(axis=2) * grid.step[2], xy, atol=1e-3 * xy.max())


def test_book_density_is_the_pose_density_times_the_jacobian_where_variances_agree():
    u = odometry(0.3, 1.0, -0.2)
    x_t = compose(X0, 0.3, 1.0, -0.2)  # δ̂ = δ: the book's and the sampler's variances agree
    book = motion_model_odometry(x_t, u, X0, ALPHA)
    pose = motion_model_odometry(x_t, u, X0, ALPHA, density="pose")
    assert book == pytest.approx(pose * 1.0, rel=1e-12)  # Jacobian δ̂trans = 1

    # With a variance that does not depend on δ or δ̂ the two differ by δ̂trans alone.
    def fixed(a, b2):
        return prob_normal_distribution(a, 0.01)

    rng = np.random.default_rng(6)
    x_t = compose(X0, 0.3, 1.0, -0.2) + rng.normal(0, 0.2, (50, 3))
    book = motion_model_odometry(x_t, u, X0, ALPHA, prob=fixed)
    pose = motion_model_odometry(x_t, u, X0, ALPHA, prob=fixed, density="pose")
    trans_hat = np.hypot(x_t[:, 0] - X0[0], x_t[:, 1] - X0[1])
    np.testing.assert_allclose(book, pose * trans_hat, rtol=1e-12)


def test_book_density_does_not_integrate_to_one(grid3):
    """Erratum O3: Table 5.5 evaluates the variances at δ̂, so book / δ̂trans is not normalised."""
    u = odometry(0.3, 1.0, -0.2)
    alpha = np.array([0.2, 0.1, 0.2, 0.1])
    samples = sample_motion_model_odometry(u, X0, alpha, sample=EXACT, size=50_000, rng=5)
    grid = grid3.around(samples, 96)
    book = motion_model_odometry(grid.points, u, X0, alpha)
    pose = motion_model_odometry(grid.points, u, X0, alpha, density="pose")
    trans_hat = np.hypot(grid.points[..., 0] - X0[0], grid.points[..., 1] - X0[1])
    assert grid.integrate(pose) == pytest.approx(1.0, abs=2e-2)
    assert abs(grid.integrate(book / trans_hat) - 1.0) > 0.1


@pytest.mark.parametrize("noise", ["variance", "std"])
def test_noise_forms_pass_the_right_variance(noise):
    seen = []

    def prob(a, b2):
        seen.append(np.asarray(b2))
        return prob_normal_distribution(a, b2)

    r1, t, r2 = 0.3, 1.5, -0.2
    x_t = compose(X0, r1, t, r2)
    motion_model_odometry(x_t, odometry(0.1, 1.0, 0.0), X0, ALPHA, prob=prob, noise=noise)
    a = ALPHA
    if noise == "variance":
        expected = [
            a[0] * r1**2 + a[1] * t**2,
            a[2] * t**2 + a[3] * (r1**2 + r2**2),
            a[0] * r2**2 + a[1] * t**2,
        ]
    else:
        expected = [
            (a[0] * abs(r1) + a[1] * t) ** 2,
            (a[2] * t + a[3] * (abs(r1) + abs(r2))) ** 2,
            (a[0] * abs(r2) + a[1] * t) ** 2,
        ]
    np.testing.assert_allclose(seen, expected)


# ------------------------------------------------------------------ shapes and errors


def deterministic_sample(b2, size=None, rng=None):
    return np.broadcast_to(0.7 * np.sqrt(b2), size).copy()


@pytest.mark.parametrize("shape", [(), (7,), (4, 5)])
def test_batch_equals_one_at_a_time(shape):
    rng = np.random.default_rng(30)
    n = int(np.prod(shape))
    x_prev = (X0 + rng.normal(0, 1, (n, 3))).reshape(*shape, 3)
    start = rng.normal(0, 1, (n, 3))
    u = np.stack([start, start + rng.normal(0, 0.5, (n, 3))], axis=1).reshape(*shape, 2, 3)
    x_t = (x_prev.reshape(n, 3) + rng.normal(0, 0.5, (n, 3))).reshape(*shape, 3)
    p = motion_model_odometry(x_t, u, x_prev, ALPHA)
    s = sample_motion_model_odometry(u, x_prev, ALPHA, sample=deterministic_sample)
    assert np.shape(p) == shape and s.shape == (*shape, 3)
    if shape == ():
        assert isinstance(p, float)
    p = np.asarray(p)
    deltas = odometry_deltas(u[..., 0, :], u[..., 1, :])
    for idx in np.ndindex(shape):
        assert p[idx] == pytest.approx(
            motion_model_odometry(x_t[idx], u[idx], x_prev[idx], ALPHA), rel=1e-12
        )
        np.testing.assert_allclose(
            s[idx],
            sample_motion_model_odometry(u[idx], x_prev[idx], ALPHA, sample=deterministic_sample),
        )
        single = odometry_deltas(u[idx][0], u[idx][1])
        np.testing.assert_allclose([np.asarray(d)[idx] for d in deltas], single)


def test_particle_sets():
    u = odometry(0.1, 1.0, 0.0)
    assert sample_motion_model_odometry(u, np.zeros((100, 3)), ALPHA, rng=0).shape == (100, 3)
    assert sample_motion_model_odometry(u, X0, ALPHA, size=(2, 50), rng=0).shape == (2, 50, 3)
    assert motion_model_odometry(np.zeros((6, 3)), u, X0, ALPHA).shape == (6,)


U = odometry(0.1, 1.0, 0.0)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: motion_model_odometry(X0, U[0], X0, ALPHA), "u_t"),
        (lambda: motion_model_odometry(X0, np.zeros((3, 2)), X0, ALPHA), "u_t"),
        (lambda: motion_model_odometry(X0, U * np.nan, X0, ALPHA), "u_t"),
        (lambda: motion_model_odometry(X0[:2], U, X0, ALPHA), "x_t"),
        (lambda: motion_model_odometry(X0, U, [np.nan, 0, 0], ALPHA), "x_prev"),
        (lambda: motion_model_odometry(X0, U, X0, [0.1] * 6), "alpha"),
        (lambda: motion_model_odometry(X0, U, X0, [0.1, -0.1, 0.1, 0.1]), "alpha"),
        (lambda: motion_model_odometry(X0, U, X0, ALPHA, noise="sigma"), "noise"),
        (lambda: motion_model_odometry(X0, U, X0, ALPHA, density="likelihood"), "density"),
        (lambda: motion_model_odometry(X0, U, X0, ALPHA, prob=1.0), "prob"),
        (lambda: sample_motion_model_odometry(U, np.zeros((5, 3)), ALPHA, size=3), "size"),
        (lambda: sample_motion_model_odometry(U, X0, ALPHA, sample="normal"), "sample"),
        (lambda: sample_motion_model_odometry(U, X0, [1, 2]), "alpha"),
        (lambda: odometry_deltas(X0, [1, 2]), "xbar_t"),
        (lambda: odometry_deltas([np.inf, 0, 0], X0), "xbar_prev"),
        (lambda: apply_odometry_deltas(X0, np.nan, 1.0, 0.0), "rot1"),
        (lambda: apply_odometry_deltas(X0[:2], 0.0, 1.0, 0.0), "x_prev"),
    ],
)
def test_bad_input_raises_value_error_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()
