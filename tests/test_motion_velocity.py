"""Velocity motion model: Tables 5.1 and 5.3, and the noise-free motion g."""

from functools import partial

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from probrob.angles import wrap_angle
from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
)
from probrob.motion import (
    _invert_velocity,
    motion_model_velocity,
    sample_motion_model_velocity,
    velocity_motion,
    velocity_motion_jacobians,
)

EXACT = partial(sample_normal_distribution, method="exact")
ALPHA = np.array([0.05, 0.02, 0.04, 0.05, 0.02, 0.03])
X0 = np.array([0.4, -0.2, 0.3])
P_MIN = 0.001  # significance level of the statistical tests, at fixed seeds


def book_formula_velocity(x_t, u_t, x_prev, dt, alpha):
    """Deck 000 / Table 5.1 typed literally: unsigned r*, no wrapping, μ divides by zero."""
    x, y, th = x_prev
    xp, yp, thp = x_t
    v, w = u_t
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = (
            0.5
            * ((x - xp) * np.cos(th) + (y - yp) * np.sin(th))
            / ((y - yp) * np.cos(th) - (x - xp) * np.sin(th))
        )
        xs = (x + xp) / 2 + mu * (y - yp)
        ys = (y + yp) / 2 + mu * (xp - x)
        rs = np.hypot(x - xs, y - ys)
        dth = np.arctan2(yp - ys, xp - xs) - np.arctan2(y - ys, x - xs)
        v_hat, w_hat = dth / dt * rs, dth / dt
        g_hat = (thp - th) / dt - w_hat
    if not np.all(np.isfinite([v_hat, w_hat, g_hat])):
        return np.nan, v_hat
    a1, a2, a3, a4, a5, a6 = alpha
    prob = prob_normal_distribution
    return (
        prob(v - v_hat, a1 * v**2 + a2 * w**2)
        * prob(w - w_hat, a3 * v**2 + a4 * w**2)
        * prob(g_hat, a5 * v**2 + a6 * w**2)
    ), v_hat


def forward(noise, x_prev=X0, dt=1.0):
    """The map (v̂, ω̂, γ̂) -> x_t of Table 5.3, lines 5-7."""
    v, w, g = noise
    pose = velocity_motion(x_prev, [v, w], dt)
    pose[2] += g * dt
    return pose


def rotate_scene(pose, phi):
    """Rotate a pose about the world origin by phi (headings wrapped)."""
    x, y, th = pose
    c, s = np.cos(phi), np.sin(phi)
    return np.array([c * x - s * y, s * x + c * y, wrap_angle(th + phi)])


# ------------------------------------------------------------------ noise-free motion g


def test_velocity_motion_matches_the_printed_formula():
    x, y, th = X0
    for v, w, dt in [(1.0, 0.5, 1.0), (-0.7, 2.0, 0.3), (2.0, -1.2, 0.5)]:
        r = v / w
        expected = [
            x - r * np.sin(th) + r * np.sin(th + w * dt),
            y + r * np.cos(th) - r * np.cos(th + w * dt),
            th + w * dt,
        ]
        np.testing.assert_allclose(velocity_motion(X0, [v, w], dt), expected, atol=1e-12)


def test_velocity_motion_straight_line_and_rotation_in_place_are_exact():
    x, y, th = X0
    np.testing.assert_array_equal(
        velocity_motion(X0, [2.0, 0.0], 0.5), [x + np.cos(th), y + np.sin(th), th]
    )
    np.testing.assert_array_equal(velocity_motion(X0, [0.0, 1.0], 0.5), [x, y, th + 0.5])


@given(
    v=st.floats(-3, 3),
    w=st.floats(-1e-6, 1e-6),
    th=st.floats(-np.pi, np.pi),
)
def test_velocity_motion_is_continuous_as_omega_goes_to_zero(v, w, th):
    dt = 0.7
    pose = velocity_motion([0.0, 0.0, th], [v, w], dt)
    straight = velocity_motion([0.0, 0.0, th], [v, 0.0], dt)
    # The arc leaves the straight line by v Δt² ω / 2 sideways.
    assert np.all(np.abs(pose - straight) <= abs(v) * dt**2 * abs(w) / 2 + abs(w) * dt + 1e-15)


# ------------------------------------------------------------------ Table 5.1 inversion


@given(
    v=st.floats(-2, 2),
    w=st.floats(-2.8, 2.8),
    g=st.floats(-1, 1),
    th=st.floats(-np.pi, np.pi),
    x=st.floats(-5, 5),
    y=st.floats(-5, 5),
)
def test_table_5_1_recovers_the_controls_of_any_arc(v, w, g, th, x, y):
    """Right turns, reversing, straight lines and headings near ±π included."""
    dt = 1.0
    x_prev = np.array([x, y, th])
    x_t = forward((v, w, g), x_prev, dt)
    v_hat, w_hat, g_hat, _ = _invert_velocity(x_t, x_prev, dt)
    if abs(v) > 1e-6:
        assert v_hat == pytest.approx(v, abs=1e-9)
        assert w_hat == pytest.approx(w, abs=1e-7)
        assert g_hat == pytest.approx(g, abs=1e-7)
    else:  # (almost) no displacement: only the total turn is determined
        assert abs(v_hat) < 1e-5
        assert wrap_angle(w_hat + g_hat - (w + g)) == pytest.approx(0.0, abs=1e-7)


def test_rotation_in_place_attributes_the_turn_to_omega():
    x_t = X0 + [0.0, 0.0, 0.4]
    v_hat, w_hat, g_hat, _ = _invert_velocity(x_t, X0, 2.0)
    assert (v_hat, w_hat, g_hat) == (0.0, pytest.approx(0.2, rel=1e-15), 0.0)
    # ... so the density of an in-place rotation peaks at the commanded turn.
    p = motion_model_velocity(x_t, [0.0, 0.2], X0, 2.0, ALPHA + 0.01)
    p_other = motion_model_velocity(X0 + [0, 0, 0.3], [0.0, 0.2], X0, 2.0, ALPHA + 0.01)
    assert p > p_other > 0


def test_book_formula_agrees_for_left_turns_forward():
    """Where the printed table is valid (v, ω > 0, no ±π crossing) the two agree."""
    rng = np.random.default_rng(10)
    u = [1.0, 0.5]
    for _ in range(50):
        x_t = forward((1.0, 0.5, 0.0) + rng.normal(0, 0.1, 3))
        book, _ = book_formula_velocity(x_t, u, X0, 1.0, ALPHA)
        assert motion_model_velocity(x_t, u, X0, 1.0, ALPHA) == pytest.approx(book, rel=1e-9)


def test_circle_centre_of_table_5_1_and_the_turkish_sign_error():
    """Erratum V6: y* = (y + y')/2 + μ(x' - x); the Turkish deck subtracts μ(x̄' - x̄)."""
    x, y, th = X0
    for u in ([1.0, 0.5], [1.0, -0.7], [-0.5, 0.9]):
        xp, yp, _ = velocity_motion(X0, u, 1.0)
        mu = 0.5 * ((x - xp) * np.cos(th) + (y - yp) * np.sin(th))
        mu /= (y - yp) * np.cos(th) - (x - xp) * np.sin(th)
        r = u[0] / u[1]
        centre = np.array([x - r * np.sin(th), y + r * np.cos(th)])  # of the arc g(u, x)
        book = np.array([(x + xp) / 2 + mu * (y - yp), (y + yp) / 2 + mu * (xp - x)])
        turkish = np.array([(x + xp) / 2 - mu * (yp - y), (y + yp) / 2 - mu * (xp - x)])
        np.testing.assert_allclose(book, centre, atol=1e-12)
        assert np.hypot(*(turkish - centre)) > 0.1


def test_unsigned_radius_of_the_decks_flips_v_for_right_turns():
    """Erratum V1: with r* ≥ 0, v̂ = Δθ r*/Δt has the sign of ω, so a right turn gives -v."""
    u = [1.0, -0.5]
    x_t = velocity_motion(X0, u, 1.0)
    book, v_hat_book = book_formula_velocity(x_t, u, X0, 1.0, ALPHA)
    assert v_hat_book == pytest.approx(-1.0)
    ours = motion_model_velocity(x_t, u, X0, 1.0, ALPHA)
    peak = (
        prob_normal_distribution(0, ALPHA[0] + ALPHA[1] * 0.25)
        * prob_normal_distribution(0, ALPHA[2] + ALPHA[3] * 0.25)
        * prob_normal_distribution(0, ALPHA[4] + ALPHA[5] * 0.25)
    )
    assert ours == pytest.approx(peak, rel=1e-9)  # the noise-free pose is the mode
    assert book < 1e-6 * peak


def test_unwrapped_delta_theta_of_the_decks_breaks_near_pi():
    """Erratum V2: Δθ as a difference of atan2 jumps by 2π when the arc crosses ±π."""
    u = [1.0, 0.8]
    x_t = forward((1.05, 0.75, 0.02))
    ours = motion_model_velocity(x_t, u, X0, 1.0, ALPHA)
    books = []
    for phi in np.linspace(-np.pi, np.pi, 73):
        rotated = motion_model_velocity(
            rotate_scene(x_t, phi), u, rotate_scene(X0, phi), 1.0, ALPHA
        )
        assert rotated == pytest.approx(ours, rel=1e-9)
        books.append(
            book_formula_velocity(rotate_scene(x_t, phi), u, rotate_scene(X0, phi), 1.0, ALPHA)[0]
        )
    assert min(books) < 1e-6 * ours  # some rotations of the scene break the printed form


def test_gamma_is_wrapped():
    """Erratum V3: θ' and θ' + 2π are the same heading; the decks' γ̂ differs by 2π/Δt."""
    u = [1.0, 0.5]
    x_t = forward((1.0, 0.5, 0.05))
    turned = x_t + [0.0, 0.0, 2 * np.pi]
    ours = motion_model_velocity(x_t, u, X0, 1.0, ALPHA)
    assert motion_model_velocity(turned, u, X0, 1.0, ALPHA) == pytest.approx(ours, rel=1e-12)
    assert book_formula_velocity(turned, u, X0, 1.0, ALPHA)[0] < 1e-12 * ours


def test_gamma_subtracts_the_recovered_omega_not_the_command():
    """Erratum V4 (Turkish deck): γ̂ = (θ' - θ)/Δt - ω̂, not - ω."""
    u = [1.0, 0.5]
    noise = (1.1, 0.7, 0.0)  # ω̂ ≠ ω and no final turn
    g_hat = _invert_velocity(forward(noise), X0, 1.0)[2]
    assert g_hat == pytest.approx(0.0, abs=1e-12)
    g_turkish = (forward(noise)[2] - X0[2]) / 1.0 - u[1]
    assert g_turkish == pytest.approx(0.2)


def test_straight_line_has_the_finite_limit():
    """Erratum V5: on the heading line μ = x/0; the limit is ω̂ = 0, v̂ = distance/Δt."""
    u = [1.0, 0.0]
    x_t = velocity_motion(X0, u, 2.0)
    ours = motion_model_velocity(x_t, u, X0, 2.0, ALPHA)
    assert np.isfinite(ours) and ours > 0
    assert not np.isfinite(book_formula_velocity(x_t, u, X0, 2.0, ALPHA)[1])
    v_hat, w_hat, _, _ = _invert_velocity(x_t, X0, 2.0)
    assert (v_hat, w_hat) == (pytest.approx(1.0), 0.0)


@given(eps=st.floats(-1e-3, 1e-3), th=st.floats(-np.pi, np.pi), v=st.floats(0.2, 2.0))
def test_density_is_continuous_across_the_straight_line(eps, th, v):
    """ω → 0: a pose just off the heading line has nearly the density of one on it."""
    x_prev = np.array([1.0, 2.0, th])
    on_line = velocity_motion(x_prev, [v, 0.0], 1.0)
    off_line = on_line + [-np.sin(th) * eps, np.cos(th) * eps, 0.0]
    alpha = [0.1, 0.1, 0.1, 0.1, 0.1, 0.1]
    p_on = motion_model_velocity(on_line, [v, 0.0], x_prev, 1.0, alpha)
    p_off = motion_model_velocity(off_line, [v, 0.0], x_prev, 1.0, alpha)
    # Quadratic, not linear, in eps: the offset turns the arc by ω̂ ≈ 2 eps / v (and γ̂ by
    # -ω̂), each with variance 0.1 v², so the relative change is about 40 eps² / v⁴.
    assert p_off == pytest.approx(p_on, rel=100 * eps**2 / v**4 + 1e-9)
    assert np.isfinite(
        motion_model_velocity(off_line, [v, 0.0], x_prev, 1.0, alpha, density="pose")
    )


# ------------------------------------------------------------------ density over poses


def numeric_jacobian(noise, dt=1.0, h=1e-6):
    cols = []
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        cols.append((forward(noise + step, dt=dt) - forward(noise - step, dt=dt)) / (2 * h))
    return np.column_stack(cols)


@pytest.mark.parametrize(
    "noise",
    [(1.0, 0.5, 0.1), (1.0, -0.5, 0.0), (-0.8, 1.3, -0.2), (1.5, 1e-9, 0.0), (0.5, 3.0, 0.3)],
)
@pytest.mark.parametrize("dt", [1.0, 0.4])
def test_book_over_pose_density_is_the_jacobian(noise, dt):
    noise = np.array(noise)
    x_t = forward(noise, dt=dt)
    u = [1.0, 0.4]
    book = motion_model_velocity(x_t, u, X0, dt, ALPHA * 10)
    pose = motion_model_velocity(x_t, u, X0, dt, ALPHA * 10, density="pose")
    jac = abs(np.linalg.det(numeric_jacobian(noise, dt)))
    assert book / pose == pytest.approx(jac, rel=1e-6)


CASES = {
    "left": dict(u=[1.0, 0.5], alpha=ALPHA, prob=prob_normal_distribution, noise="variance"),
    "right-reverse": dict(
        u=[-0.8, -0.6], alpha=ALPHA, prob=prob_normal_distribution, noise="variance"
    ),
    "straight": dict(u=[1.2, 0.0], alpha=ALPHA, prob=prob_normal_distribution, noise="variance"),
    "std": dict(u=[1.0, 0.5], alpha=ALPHA / 2, prob=prob_normal_distribution, noise="std"),
    "triangular": dict(
        u=[1.0, 0.5], alpha=ALPHA, prob=prob_triangular_distribution, noise="variance"
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_pose_density_integrates_to_one_and_matches_the_sampler(
    case, grid3, chi_square, sampler_for
):
    c = CASES[case]
    kw = dict(noise=c["noise"])
    samples = sample_motion_model_velocity(
        c["u"], X0, 1.0, c["alpha"], sample=sampler_for(c["prob"]), size=60_000, rng=11, **kw
    )
    grid = grid3.around(samples, 96)
    values = motion_model_velocity(
        grid.points, c["u"], X0, 1.0, c["alpha"], prob=c["prob"], density="pose", **kw
    )
    assert grid.integrate(values) == pytest.approx(1.0, abs=1e-3)
    assert chi_square(samples, values, grid) > P_MIN
    # density="xy" is the pose density integrated over θ' (Fig. 5.3 / 5.7)
    xy = motion_model_velocity(
        grid.points[:, :, 0, :2], c["u"], X0, 1.0, c["alpha"], prob=c["prob"], density="xy", **kw
    )
    np.testing.assert_allclose(values.sum(axis=2) * grid.step[2], xy, atol=1e-3 * xy.max())


def test_sampler_noise_variables_have_the_table_variances():
    u = np.array([1.0, 0.5])
    samples = sample_motion_model_velocity(u, X0, 1.0, ALPHA, sample=EXACT, size=50_000, rng=12)
    v_hat, w_hat, g_hat, _ = _invert_velocity(samples, X0, 1.0)
    a1, a2, a3, a4, a5, a6 = ALPHA
    for values, mean, var in [
        (v_hat, 1.0, a1 + a2 * 0.25),
        (w_hat, 0.5, a3 + a4 * 0.25),
        (g_hat, 0.0, a5 + a6 * 0.25),
    ]:
        assert stats.kstest(values, stats.norm(mean, np.sqrt(var)).cdf).pvalue > P_MIN


@pytest.mark.parametrize("noise", ["variance", "std"])
def test_noise_forms_pass_the_right_variance(noise):
    seen = []

    def prob(a, b2):
        seen.append(np.asarray(b2))
        return prob_normal_distribution(a, b2)

    v, w = 2.0, -0.5
    motion_model_velocity(X0, [v, w], X0, 1.0, ALPHA, prob=prob, noise=noise)
    a = ALPHA
    if noise == "variance":
        expected = [
            a[0] * v**2 + a[1] * w**2,
            a[2] * v**2 + a[3] * w**2,
            a[4] * v**2 + a[5] * w**2,
        ]
    else:
        expected = [
            (a[0] * abs(v) + a[1] * abs(w)) ** 2,
            (a[2] * abs(v) + a[3] * abs(w)) ** 2,
            (a[4] * abs(v) + a[5] * abs(w)) ** 2,
        ]
    np.testing.assert_allclose(seen, expected)


# ------------------------------------------------------------------ limits and shapes


def test_robot_at_rest():
    u = [0.0, 0.0]
    samples = sample_motion_model_velocity(u, X0, 1.0, ALPHA, size=10, rng=0)
    np.testing.assert_array_equal(samples, np.broadcast_to(X0, (10, 3)))
    assert motion_model_velocity(X0, u, X0, 1.0, ALPHA) == np.inf
    assert motion_model_velocity(X0 + [0.01, 0, 0], u, X0, 1.0, ALPHA) == 0.0


def test_sampler_with_exactly_zero_omega_noise_is_straight():
    alpha = [0.1, 0.0, 0.0, 0.0, 0.0, 0.0]
    samples = sample_motion_model_velocity([1.0, 0.0], X0, 1.0, alpha, size=1000, rng=1)
    assert np.all(np.isfinite(samples))
    np.testing.assert_allclose(samples[:, 2], X0[2])
    lateral = -(samples[:, 0] - X0[0]) * np.sin(X0[2]) + (samples[:, 1] - X0[1]) * np.cos(X0[2])
    np.testing.assert_allclose(lateral, 0.0, atol=1e-12)


def test_sampler_is_reproducible_and_accepts_generators():
    a = sample_motion_model_velocity([1, 0.5], X0, 1.0, ALPHA, size=5, rng=3)
    b = sample_motion_model_velocity([1, 0.5], X0, 1.0, ALPHA, size=5, rng=3)
    np.testing.assert_array_equal(a, b)
    gen = np.random.default_rng(3)
    c = sample_motion_model_velocity([1, 0.5], X0, 1.0, ALPHA, size=5, rng=gen)
    d = sample_motion_model_velocity([1, 0.5], X0, 1.0, ALPHA, size=5, rng=gen)
    assert not np.array_equal(c, d)


def deterministic_sample(b2, size=None, rng=None):
    """A 'sampler' that returns +0.7 standard deviations, for batch-vs-single checks."""
    return np.broadcast_to(0.7 * np.sqrt(b2), size).copy()


@pytest.mark.parametrize("shape", [(), (7,), (4, 5)])
def test_batch_equals_one_at_a_time(shape):
    rng = np.random.default_rng(20)
    n = int(np.prod(shape))
    x_prev = (X0 + rng.normal(0, 1, (n, 3))).reshape(*shape, 3)
    u = np.column_stack([rng.uniform(-1, 2, n), rng.uniform(-1, 1, n)]).reshape(*shape, 2)
    x_t = (velocity_motion(x_prev, u, 0.5) + rng.normal(0, 0.1, (*shape, 3))).reshape(*shape, 3)
    p = motion_model_velocity(x_t, u, x_prev, 0.5, ALPHA)
    s = sample_motion_model_velocity(u, x_prev, 0.5, ALPHA, sample=deterministic_sample)
    g = velocity_motion(x_prev, u, 0.5)
    assert np.shape(p) == shape and s.shape == (*shape, 3) and g.shape == (*shape, 3)
    if shape == ():
        assert isinstance(p, float)
    p = np.asarray(p)
    for idx in np.ndindex(shape):
        assert p[idx] == pytest.approx(
            motion_model_velocity(x_t[idx], u[idx], x_prev[idx], 0.5, ALPHA), rel=1e-12
        )
        np.testing.assert_allclose(
            s[idx],
            sample_motion_model_velocity(
                u[idx], x_prev[idx], 0.5, ALPHA, sample=deterministic_sample
            ),
        )


def test_particle_set_broadcasting_and_size():
    particles = np.zeros((100, 3))
    assert sample_motion_model_velocity([1.0, 0.1], particles, 1.0, ALPHA, rng=0).shape == (100, 3)
    assert sample_motion_model_velocity([1.0, 0.1], X0, 1.0, ALPHA, size=(2, 3), rng=0).shape == (
        2,
        3,
        3,
    )
    assert sample_motion_model_velocity(
        [1.0, 0.1], particles, 1.0, ALPHA, size=(5, 100), rng=0
    ).shape == (5, 100, 3)
    assert motion_model_velocity(
        np.zeros((6, 1, 3)), [1.0, 0.1], np.zeros((4, 3)), 1.0, ALPHA
    ).shape == (6, 4)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: motion_model_velocity([0, 0], [1, 0], X0, 1, ALPHA), "x_t"),
        (lambda: motion_model_velocity(X0, [1, 0, 0], X0, 1, ALPHA), "u_t"),
        (lambda: motion_model_velocity(X0, [1, np.nan], X0, 1, ALPHA), "u_t"),
        (lambda: motion_model_velocity(X0, [1, 0], [0, 0, np.inf], 1, ALPHA), "x_prev"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 0.0, ALPHA), "dt"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, [1.0, 2.0], ALPHA), "dt"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1, ALPHA[:4]), "alpha"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1, -ALPHA), "alpha"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1, ALPHA, noise="var"), "noise"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1, ALPHA, density="posterior"), "density"),
        (lambda: motion_model_velocity(X0, [1, 0], X0, 1, ALPHA, prob="normal"), "prob"),
        (lambda: sample_motion_model_velocity(np.ones((3, 2)), X0, 1, ALPHA, size=(2, 4)), "size"),
        (lambda: sample_motion_model_velocity([1, 0], np.zeros((5, 3)), 1, ALPHA, size=4), "size"),
        (lambda: sample_motion_model_velocity([1, 0], X0, -1, ALPHA), "dt"),
        (lambda: sample_motion_model_velocity([1, 0], X0, 1, ALPHA, sample=None), "sample"),
        (lambda: sample_motion_model_velocity([1, 0], X0, 1, ALPHA, noise="sd"), "noise"),
        (lambda: velocity_motion(X0, [[1, 0]], 0), "dt"),
        (lambda: velocity_motion("pose", [1, 0], 1), "x_prev"),
    ],
)
def test_bad_input_raises_value_error_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()


# ------------------------------------------------------------------ Jacobians (Table 7.2)


def numeric_motion_jacobians(x_prev, u, dt, h=1e-6):
    G = np.empty((3, 3))
    V = np.empty((3, 2))
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        G[:, k] = (velocity_motion(x_prev + e, u, dt) - velocity_motion(x_prev - e, u, dt)) / (
            2 * h
        )
    for k in range(2):
        e = np.zeros(2)
        e[k] = h
        V[:, k] = (velocity_motion(x_prev, u + e, dt) - velocity_motion(x_prev, u - e, dt)) / (
            2 * h
        )
    return G, V


@given(
    v=st.floats(-2, 2),
    w=st.one_of(st.floats(-3, 3), st.floats(-1e-7, 1e-7), st.sampled_from([0.0, 0.2, -0.2])),
    th=st.floats(-np.pi, np.pi),
    dt=st.floats(0.05, 1.5),
)
def test_jacobians_match_finite_differences(v, w, th, dt):
    """ω = 0, tiny ω and ωΔt/2 = ±0.1 (where the series hands over) included."""
    x_prev = np.array([0.3, -1.2, th])
    u = np.array([v, w])
    G, V = velocity_motion_jacobians(x_prev, u, dt)
    G_num, V_num = numeric_motion_jacobians(x_prev, u, dt)
    np.testing.assert_allclose(G, G_num, atol=1e-8)
    np.testing.assert_allclose(V, V_num, atol=1e-8)


def test_jacobians_equal_the_books_table_7_2():
    x_prev = np.array([1.0, 2.0, 0.7])
    for v, w, dt in [(1.0, 0.5, 1.0), (-0.4, 2.0, 0.3), (2.0, -1.2, 0.5)]:
        th, t1 = x_prev[2], x_prev[2] + w * dt
        G_book = np.array(
            [[1, 0, -v / w * np.cos(th) + v / w * np.cos(t1)],
             [0, 1, -v / w * np.sin(th) + v / w * np.sin(t1)],
             [0, 0, 1]]
        )  # fmt: skip
        V_book = np.array(
            [[(-np.sin(th) + np.sin(t1)) / w,
              v * (np.sin(th) - np.sin(t1)) / w**2 + v * np.cos(t1) * dt / w],
             [(np.cos(th) - np.cos(t1)) / w,
              -v * (np.cos(th) - np.cos(t1)) / w**2 + v * np.sin(t1) * dt / w],
             [0, dt]]
        )  # fmt: skip
        G, V = velocity_motion_jacobians(x_prev, [v, w], dt)
        np.testing.assert_allclose(G, G_book, atol=1e-12)
        np.testing.assert_allclose(V, V_book, atol=1e-12)


def test_jacobians_straight_line_limit_is_exact():
    G, V = velocity_motion_jacobians([0.0, 0.0, 0.0], [2.0, 0.0], 0.5)
    np.testing.assert_array_equal(G, [[1, 0, 0], [0, 1, 1.0], [0, 0, 1]])
    # ∂y'/∂ω = v Δt² / 2 on the straight line (the arc bends to the left).
    np.testing.assert_array_equal(V, [[0.5, 0.0], [0.0, 0.25], [0.0, 0.5]])


@pytest.mark.parametrize("shape", [(), (7,), (4, 5)])
def test_jacobians_batch_equals_one_at_a_time(shape):
    rng = np.random.default_rng(40)
    n = int(np.prod(shape))
    x_prev = rng.normal(0, 1, (n, 3)).reshape(*shape, 3)
    u = np.column_stack([rng.uniform(-1, 2, n), rng.uniform(-1, 1, n)]).reshape(*shape, 2)
    G, V = velocity_motion_jacobians(x_prev, u, 0.5)
    assert G.shape == (*shape, 3, 3) and V.shape == (*shape, 3, 2)
    for idx in np.ndindex(shape):
        G1, V1 = velocity_motion_jacobians(x_prev[idx], u[idx], 0.5)
        np.testing.assert_allclose(G[idx], G1, rtol=1e-14)
        np.testing.assert_allclose(V[idx], V1, rtol=1e-14)


def test_jacobians_bad_input():
    with pytest.raises(ValueError, match="u_t"):
        velocity_motion_jacobians(X0, [1.0], 1.0)
    with pytest.raises(ValueError, match="dt"):
        velocity_motion_jacobians(X0, [1.0, 0.0], -1.0)
