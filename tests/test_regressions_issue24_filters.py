"""Regressions of issue 24, item 3: the filters without overhead, results and errors unchanged.

The EKF and UKF steps lost their per-feature checks, np.errstate and np.linalg calls on 2×2
and 3×3 matrices (one LAPACK Cholesky now gives S^-1 and log det S); these tests pin what
must not change: the results of the code before that change (to 1e-12), filterpy's
``ExtendedKalmanFilter`` on the same step, Python floats for p(z), and the very messages of
bad input, including those the validators' new fast lanes must still produce.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from probrob import _validation as check
from probrob.localization import (
    ekf_localization,
    ekf_localization_known_correspondences,
    ukf_localization,
    ukf_localization_ml,
)

MAP = np.array([[2.0, 1.0, 0.0], [-1.5, 3.0, 1.0], [4.0, -2.0, 2.0], [-3.0, -2.5, 3.0]])
MU = np.array([0.3, -0.2, 0.4])
SIGMA = np.array([[0.04, 0.005, -0.002], [0.005, 0.03, 0.001], [-0.002, 0.001, 0.01]])
U = np.array([0.8, 0.3])
DT = 0.1
ALPHA = (0.05, 0.01, 0.01, 0.05)
SIGMAS = (0.1, 0.02, 0.1)
Z = np.array([[1.62, 0.05, 0.1], [3.8, 1.55, 0.9], [4.3, -1.05, 2.05]])
C = np.array([0, 1, 2])
GOOD = dict(mu=MU, Sigma=SIGMA, u=U, z=Z, c=C, m=MAP, dt=DT, alpha=ALPHA, sigmas=SIGMAS)

# (filter, features, mu, Sigma, log p(z) or the chosen landmarks), computed by the code
# before issue 24 (commit ffd35c0), printed with repr.
BEFORE = [
    (
        "ekf",
        0,
        [0.3732065603214941, -0.16774601512533344, 0.43000000000000005],
        [
            [0.04041494453006964, 0.0049190365385440365, -0.0023243176400092607],
            [0.0049190365385440365, 0.030253629447236443, 0.001736046571409743],
            [-0.0023243176400092607, 0.001736046571409743, 0.010109],
        ],
        0.0,
    ),
    (
        "ukf",
        0,
        [0.3728406785793665, -0.16790723040495692, 0.43000000000000005],
        [
            [0.04041554492545146, 0.004919771848572535, -0.002321717509435506],
            [0.004919771848572535, 0.030252914943280744, 0.0017301450843881963],
            [-0.002321717509435506, 0.0017301450843881963, 0.010109000000000003],
        ],
        0.0,
    ),
    (
        "ekf",
        1,
        [0.555837127183522, 0.1001799121165084, 0.5139187894879006],
        [
            [0.010448670317611217, -0.003117506447918185, 0.004103925103170525],
            [-0.003117506447918185, 0.012084731111661822, -0.005543129627609009],
            [0.004103925103170525, -0.005543129627609009, 0.003668308591857249],
        ],
        0.42062778486017427,
    ),
    (
        "ukf",
        1,
        [0.5599396593342221, 0.1049490754079224, 0.5144462803860508],
        [
            [0.010552901342266979, -0.0029109918215997673, 0.004058410708319606],
            [-0.0029109918215997673, 0.012226534843357659, -0.005478999288458769],
            [0.004058410708319606, -0.005478999288458769, 0.003809907258728174],
        ],
        -0.5701635250995061,
    ),
    (
        "ekf",
        3,
        [0.43872178478258395, -0.0875910714805641, 0.5640355266612677],
        [
            [0.002180315311547277, 0.00010544269618818944, 0.0002636774072159354],
            [0.00010544269618818944, 0.0017134908436275836, -0.0002485036424342991],
            [0.0002636774072159354, -0.0002485036424342991, 0.00020339079291733651],
        ],
        1.0583722449733748,
    ),
    (
        "ukf",
        3,
        [0.4226125625189515, -0.07752308883482706, 0.5620624651475181],
        [
            [0.0025722378822685757, -0.00022607415097225178, 0.00034766605346994326],
            [-0.00022607415097225178, 0.0023514986837776183, -0.0003437405917977414],
            [0.00034766605346994326, -0.0003437405917977414, 0.0002257617794128742],
        ],
        -2.014509685687954,
    ),
    (
        "ekf_ml",
        3,
        [0.43872178478258395, -0.0875910714805641, 0.5640355266612677],
        [
            [0.002180315311547277, 0.00010544269618818944, 0.0002636774072159354],
            [0.00010544269618818944, 0.0017134908436275836, -0.0002485036424342991],
            [0.0002636774072159354, -0.0002485036424342991, 0.00020339079291733651],
        ],
        [0, 1, 2],
    ),
    (
        "ukf_ml",
        3,
        [0.4226125625189515, -0.07752308883482706, 0.5620624651475181],
        [
            [0.0025722378822685757, -0.00022607415097225178, 0.00034766605346994326],
            [-0.00022607415097225178, 0.0023514986837776183, -0.0003437405917977414],
            [0.00034766605346994326, -0.0003437405917977414, 0.0002257617794128742],
        ],
        [0, 1, 2],
    ),
]


@pytest.mark.parametrize(("method", "k", "mu", "Sigma", "last"), BEFORE)
def test_results_equal_those_before_the_change(method, k, mu, Sigma, last):
    if method == "ekf":
        out = ekf_localization_known_correspondences(
            MU, SIGMA, U, Z[:k], C[:k], MAP, DT, ALPHA, SIGMAS, log=True
        )
    elif method == "ukf":
        out = ukf_localization(MU, SIGMA, U, Z[:k], C[:k], MAP, DT, ALPHA, SIGMAS, log=True)
    elif method == "ekf_ml":
        out = ekf_localization(MU, SIGMA, U, Z[:k], MAP, DT, ALPHA, SIGMAS)
    else:
        out = ukf_localization_ml(MU, SIGMA, U, Z[:k], MAP, DT, ALPHA, SIGMAS)
    np.testing.assert_allclose(out[0], mu, rtol=0, atol=1e-12)
    np.testing.assert_allclose(out[1], Sigma, rtol=0, atol=1e-12)
    if method.endswith("_ml"):
        assert out[2].tolist() == last
    else:
        assert type(out[2]) is float  # a Python float, as before (not np.float64)
        assert out[2] == pytest.approx(last, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("log", [False, True])
@pytest.mark.parametrize("step", [ekf_localization_known_correspondences, ukf_localization])
def test_pz_is_a_python_float(step, log):
    for k in (0, 1, 3):
        assert type(step(MU, SIGMA, U, Z[:k], C[:k], MAP, DT, ALPHA, SIGMAS, log=log)[2]) is float


filterpy = pytest.importorskip("filterpy.kalman")


@pytest.mark.parametrize("k", [1, 2, 3])
def test_ekf_step_equals_filterpy_extended_kalman_filter(k):
    """filterpy's EKF: the same prediction, one update per feature (Joseph form there)."""
    v, w = U
    th = MU[2]
    ekf = filterpy.ExtendedKalmanFilter(dim_x=3, dim_z=3)
    ekf.x, ekf.P = MU.copy(), SIGMA.copy()
    # Table 7.2, lines 3-6 (the errata's V), written out for the reference filter.
    s0, s1, c0, c1 = math.sin(th), math.sin(th + w * DT), math.cos(th), math.cos(th + w * DT)
    ekf.F = np.array([[1, 0, v / w * (c1 - c0)], [0, 1, v / w * (s1 - s0)], [0, 0, 1]])
    V = np.array(
        [
            [(s1 - s0) / w, v * (s0 - s1) / w**2 + v * c1 * DT / w],
            [(c0 - c1) / w, -v * (c0 - c1) / w**2 + v * s1 * DT / w],
            [0, DT],
        ]
    )
    M = np.diag([ALPHA[0] * v**2 + ALPHA[1] * w**2, ALPHA[2] * v**2 + ALPHA[3] * w**2])
    ekf.Q = V @ M @ V.T
    g = MU + [v / w * (s1 - s0), v / w * (c0 - c1), w * DT]
    ekf.predict_x = lambda u: None
    ekf.predict()
    ekf.x = g

    def h(x, landmark):
        dx, dy = landmark[0] - x[0], landmark[1] - x[1]
        return np.array([math.hypot(dx, dy), math.atan2(dy, dx) - x[2], landmark[2]])

    def H(x, landmark):
        dx, dy = landmark[0] - x[0], landmark[1] - x[1]
        q = dx * dx + dy * dy
        return np.array([[-dx / q**0.5, -dy / q**0.5, 0], [dy / q, -dx / q, -1], [0, 0, 0]])

    def residual(a, b):
        nu = a - b
        nu[1] = (nu[1] + math.pi) % (2 * math.pi) - math.pi
        return nu

    for z_i, j in zip(Z[:k], C[:k], strict=True):
        R = np.diag(np.square(SIGMAS))
        ekf.update(z_i, H, h, R=R, args=(MAP[j],), hx_args=(MAP[j],), residual=residual)
    mu, Sigma, _ = ekf_localization_known_correspondences(
        MU, SIGMA, U, Z[:k], C[:k], MAP, DT, ALPHA, SIGMAS
    )
    np.testing.assert_allclose(mu[:2], ekf.x[:2], rtol=0, atol=1e-12)
    assert math.remainder(mu[2] - ekf.x[2], 2 * math.pi) == pytest.approx(0, abs=1e-12)
    np.testing.assert_allclose(Sigma, ekf.P, rtol=0, atol=1e-12)


# The messages of the code before the change, word for word.
BAD = [
    ("dt", math.nan, "dt must be finite (no NaN or inf), got nan in it"),
    ("dt", math.inf, "dt must be finite (no NaN or inf), got inf in it"),
    ("dt", -1.0, "dt must be a positive scalar, got -1.0"),
    ("dt", 0.0, "dt must be a positive scalar, got 0.0"),
    ("dt", np.float64(-2.0), "dt must be a positive scalar, got -2.0"),
    (
        "Sigma",
        SIGMA + np.diag([0, 0, -0.02]),
        "Sigma is not positive semi-definite (smallest eigenvalue -0.0101)",
    ),
    (
        "Sigma",
        np.diag([0.01, -1e-9, 0.01]),
        "Sigma is not positive semi-definite (smallest eigenvalue -1e-09)",
    ),
    (
        "Sigma",
        SIGMA + np.triu(np.full((3, 3), 1e-6), 1),
        "Sigma must be symmetric, got entry (0, 1) = 0.005001 and (1, 0) = 0.005",
    ),
    (
        "alpha",
        (0.05, -0.01, 0.01, 0.05),
        "alpha must be non-negative, got [0.05, -0.01, 0.01, 0.05]",
    ),
    ("alpha", (0.05, math.nan, 0.01, 0.05), "alpha must be finite (no NaN or inf), got nan in it"),
    (
        "sigmas",
        (0.1, 0.0, 0.1),
        "sigmas are standard deviations and must be > 0, got [0.1, 0.0, 0.1]",
    ),
    ("c", np.array([0, 1, 4]), "c must index the map's 4 landmarks, got [0, 1, 4]"),
    ("c", np.array([0, -1, 2]), "c must index the map's 4 landmarks, got [0, -1, 2]"),
    ("c", [0.0, 1.0, 2.5], "c must hold integer landmark indices, got [0.0, 1.0, 2.5]"),
    ("z", Z * [[1, 1, 1], [-1, 1, 1], [1, 1, 1]], "z: ranges must be >= 0"),
    ("mu", np.array([0.3, math.inf, 0.4]), "mu must be finite (no NaN or inf), got inf in it"),
]


@pytest.mark.parametrize(("field", "value", "message"), BAD)
@pytest.mark.parametrize("step", [ekf_localization_known_correspondences, ukf_localization])
def test_bad_input_raises_the_same_message(step, field, value, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        step(**dict(GOOD, **{field: value}))


@pytest.mark.parametrize(
    ("keyword", "message"),
    [
        (dict(beta=math.inf), "beta must be finite (no NaN or inf), got inf in it"),
        (dict(kappa=math.nan), "kappa must be finite (no NaN or inf), got nan in it"),
        (dict(ukf_alpha=-1.0), "ukf_alpha must be a positive scalar, got -1.0"),
        (dict(beta=[2.0]), "beta must be a number, got shape (1,): [2.0]"),
    ],
)
def test_bad_ukf_parameters_raise_the_same_message(keyword, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        ukf_localization(**GOOD, **keyword)


@pytest.mark.parametrize("n", [1, 3, 64, 65, 1000])
def test_all_finite_small_and_large_paths_agree(n):
    """Up to 64 numbers all_finite sums in Python floats, beyond in numpy: same answers."""
    finite = np.full(n, 1e308)  # the sum overflows, every entry is finite
    assert check.all_finite(finite)
    assert check.all_finite(-finite)
    assert check.all_finite(np.zeros((n, 1)))
    for bad in (math.nan, math.inf, -math.inf):
        x = np.ones(n)
        x[n // 2] = bad
        assert not check.all_finite(x)
    pair = np.ones(n)
    pair[0], pair[-1] = math.inf, -math.inf  # inf - inf: NaN, not finite
    assert not check.all_finite(pair)


def test_pz_of_an_extreme_pose_is_zero_not_nan():
    """Innovations near 1e308: the EKF's Mahalanobis distance overflows to inf and p(z) is 0,
    not NaN (a triangular solve of such an innovation can meet inf - inf); the UKF's S is
    infinite there and refused, as before."""
    mu = np.array([5.66666667e307, -1.13333333e308, 1.7e308])
    args = (np.diag([0.1, 0.1, 0.05]), [1.0, 0.2], [[2.0, 0.3, 0.0]], [0], MAP, 1.0)
    _, _, p = ekf_localization_known_correspondences(mu, *args, [0.05] * 4, (0.1, 0.05, 0.2))
    assert p == 0.0
    with pytest.raises(ValueError, match=r"^S \(the innovation covariance.*not positive definite"):
        ukf_localization(mu, *args, [0.05] * 4, (0.1, 0.05, 0.2))


# --------------------------------------------------------------------------- compiled loops
# Angle wrapping, the motion model's arc and the EKF's per-feature update are compiled
# (numba, no fast-math). These pin them to the algorithms they replaced.

_TWO_PI = 2.0 * np.pi


def _wrap_by_numpy(theta):
    """The numpy wrap before the compiled loop: θ - 2π·round(θ / 2π), moved by one turn where
    needed; the exact remainder ``fmod`` from |θ| >= 40 on."""
    theta = np.asarray(theta, dtype=float)
    r = theta - np.round(theta * (1.0 / _TWO_PI)) * _TWO_PI
    r = np.where(r >= np.pi, r - _TWO_PI, r)
    r = np.where(r < -np.pi, r + _TWO_PI, r)
    big = ~(np.abs(theta) < 40.0)
    f = np.fmod(theta[big], _TWO_PI)
    f = np.where(f >= np.pi, f - _TWO_PI, f)
    r[big] = np.where(f < -np.pi, f + _TWO_PI, f)
    return r


def _angles_hard_to_wrap():
    rng = np.random.default_rng(24)
    k = np.arange(-9, 10)
    edges = (k + 0.5) * _TWO_PI
    return np.concatenate(
        [
            rng.uniform(-50.0, 50.0, 200_000),
            rng.uniform(-1e10, 1e10, 500),
            rng.normal(0.0, 1e300, 500),
            edges,
            np.nextafter(edges, np.inf),
            np.nextafter(edges, -np.inf),
            [np.pi, -np.pi, np.nextafter(np.pi, 0), np.nextafter(-np.pi, -4), 0.0, -0.0],
            [39.999999, 40.0, -40.0, 5e-324, -5e-324, 1e308, -1e308],
        ]
    )


def test_compiled_wrap_is_the_numpy_algorithm_to_the_last_bit():
    from probrob.angles import _wrap

    theta = _angles_hard_to_wrap()
    got, want = _wrap(theta), _wrap_by_numpy(theta)
    assert np.array_equal(got.view(np.int64), want.view(np.int64))
    assert got.min() >= -np.pi and got.max() < np.pi
    # the Python float path: the same bits, one angle at a time
    some = theta[::97]
    floats = np.array([_wrap(float(t)) for t in some])
    assert np.array_equal(floats.view(np.int64), _wrap(some).view(np.int64))
    # any shape and stride, and non-finite input gives NaN (no direction), never a wrong angle
    grid = theta[:24].reshape(4, 6)
    assert np.array_equal(_wrap(grid[:, ::2]), _wrap_by_numpy(grid[:, ::2]))
    assert _wrap(np.array(7.0)).shape == ()
    assert np.isnan(_wrap(np.array([np.inf, -np.inf, np.nan]))).all()


def test_compiled_arc_is_the_chord_formula_for_one_pose_and_for_many():
    from probrob.motion import _arc

    rng = np.random.default_rng(5)
    n = 20_000
    x, y, th = rng.normal(0, 5, (3, n))
    v = rng.normal(0, 2, n)
    w = np.where(rng.random(n) < 0.1, 0.0, rng.normal(0, 3, n))  # ω = 0 exactly, often
    dt = 0.1
    got = np.empty((n, 3))
    _arc(x, y, th, v, w, dt, out=got)
    # the chord form in numpy (the code before the compiled loop)
    half = w * (0.5 * dt)
    with np.errstate(invalid="ignore", divide="ignore"):
        chord = np.where(half != 0, np.sin(half) / half, 1.0) * v * dt
    mid = th + half
    want = np.stack([x + chord * np.cos(mid), y + chord * np.sin(mid), mid + half], axis=-1)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-13)
    # the printed v/ω form where ω is not small, the straight line where ω = 0
    turn = np.abs(w) > 0.1
    r = v[turn] / w[turn]
    printed = np.stack(
        [
            x[turn] - r * np.sin(th[turn]) + r * np.sin(th[turn] + w[turn] * dt),
            y[turn] + r * np.cos(th[turn]) - r * np.cos(th[turn] + w[turn] * dt),
            th[turn] + w[turn] * dt,
        ],
        axis=-1,
    )
    np.testing.assert_allclose(got[turn], printed, rtol=0, atol=1e-9)
    straight = w == 0
    np.testing.assert_allclose(
        got[straight, 0], x[straight] + v[straight] * dt * np.cos(th[straight])
    )
    # one pose as Python floats: the same bits as the array
    for i in range(0, n, 997):
        one = _arc(*(float(a[i]) for a in (x, y, th, v, w)), dt)
        assert one == tuple(got[i].tolist())
    # broadcasting: one pose, many controls
    many = np.stack(_arc(0.5, -1.0, 0.3, v[:7], w[:7], dt), axis=-1)
    ref = np.empty((7, 3))
    _arc(np.full(7, 0.5), np.full(7, -1.0), np.full(7, 0.3), v[:7], w[:7], dt, out=ref)
    assert np.array_equal(many, ref)


def test_compiled_ekf_update_is_the_table_in_numpy():
    """Table 7.2's lines 9-18 in plain numpy (np.linalg.inv, the Cholesky factor for the
    likelihood) against the compiled loop, three features in turn."""
    from probrob.localization import _ekf_predict, _ekf_updates

    alpha = np.array(ALPHA)
    sigmas = np.array(SIGMAS)
    mu_bar, Sigma_bar = _ekf_predict(MU, SIGMA, U, DT, alpha)
    Q = np.diag(sigmas**2)
    got_mu, got_Sigma, got_log_p = _ekf_updates(mu_bar, Sigma_bar, Z, MAP[C], Q)
    mu, S_bar, log_p = mu_bar.copy(), Sigma_bar.copy(), 0.0
    for z_i, (m_x, m_y, m_s) in zip(Z, MAP[C], strict=True):
        dx, dy = m_x - mu[0], m_y - mu[1]
        q = dx * dx + dy * dy
        z_hat = np.array([math.sqrt(q), math.atan2(dy, dx) - mu[2], m_s])
        H = np.array(
            [[-dx / math.sqrt(q), -dy / math.sqrt(q), 0], [dy / q, -dx / q, -1], [0, 0, 0]]
        )
        S = H @ S_bar @ H.T + Q
        K = S_bar @ H.T @ np.linalg.inv(S)
        nu = z_i - z_hat
        nu[1] = (nu[1] + np.pi) % _TWO_PI - np.pi
        mu = mu + K @ nu
        S_bar = (np.eye(3) - K @ H) @ S_bar
        log_p += -0.5 * (nu @ np.linalg.solve(S, nu) + np.log(np.linalg.det(2 * np.pi * S)))
    np.testing.assert_allclose(got_mu, mu, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got_Sigma, S_bar, rtol=0, atol=1e-13)
    assert got_log_p == pytest.approx(log_p, rel=1e-12)
