"""Beam range finder model, Table 6.1: components, mixture, sampler, scan likelihood."""

import numpy as np
import pytest
from scipy import integrate, stats

from probrob.maps import OccupancyGrid, ray_cast
from probrob.sensors import (
    BeamModelParams,
    beam_mixture,
    beam_model_components,
    beam_range_finder_model,
    sample_beam_mixture,
)

P = BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.2, 0.5, 8.0)
P_MIN = 0.001


def integral(f, zmax, breaks):
    pts = sorted({b for b in breaks if 0 < b < zmax})
    return integrate.quad(f, 0.0, zmax, points=pts or None, limit=400, epsabs=1e-12)[0]


@pytest.mark.parametrize("z_star", [0.0, 0.1, 2.5, 7.9, 8.0])
def test_each_component_integrates_to_one(z_star):
    for c in (0, 1, 3):  # hit, short, rand: densities on [0, z_max]
        if c == 1 and z_star == 0.0:
            continue  # p_short is then the point mass at 0 (tested below)
        total = integral(lambda z, c=c: beam_model_components(z, z_star, P)[c], 8.0, [z_star])
        assert total == pytest.approx(1.0, abs=1e-9)
    # p_max is the point mass at z_max: probability 1 there, 0 anywhere else.
    comps = beam_model_components([0.0, 3.0, 7.999, 8.0, 9.0], z_star, P)
    np.testing.assert_array_equal(comps[:, 2], [0, 0, 0, 1, 1])


def test_mixture_integrates_to_one_with_the_point_mass():
    for z_star in (0.3, 4.0, 8.0):
        density = integral(lambda z, zs=z_star: beam_mixture(z, zs, P), 8.0, [z_star])
        assert density + P.z_max == pytest.approx(1.0, abs=1e-9)


def test_components_match_the_book_formulas():
    z, zs = 1.3, 2.0
    sig, lam, zmax = P.sigma_hit, P.lambda_short, P.max_range
    eta_hit = 1 / (stats.norm.cdf(zmax, zs, sig) - stats.norm.cdf(0, zs, sig))
    expected = [
        eta_hit * stats.norm.pdf(z, zs, sig),
        lam * np.exp(-lam * z) / (1 - np.exp(-lam * zs)),
        0.0,
        1 / zmax,
    ]
    np.testing.assert_allclose(beam_model_components(z, zs, P), expected, rtol=1e-12)
    # p_short is 0 beyond z*, p_rand is 0 at z_max.
    assert beam_model_components(2.1, zs, P)[1] == 0
    assert beam_model_components(8.0, zs, P)[3] == 0
    # Readings beyond z_max count as max-range readings.
    np.testing.assert_array_equal(beam_mixture(81.83, 3.0, P), beam_mixture(8.0, 3.0, P))
    np.testing.assert_allclose(beam_mixture(z, zs, P), np.dot(P.weights, expected), rtol=1e-12)


def test_short_component_at_zero_expected_range_is_a_point_mass():
    c = beam_model_components([0.0, 0.5], 0.0, P)
    assert c[0, 1] == np.inf and c[1, 1] == 0.0


def test_log_agrees_and_does_not_underflow():
    z = np.array([0.0, 1.0, 3.0, 8.0, 9.0])
    zs = np.array([0.5, 1.2, 7.0, 8.0, 2.0])
    np.testing.assert_allclose(beam_mixture(z, zs, P, log=True), np.log(beam_mixture(z, zs, P)))
    # Only the hit component and a reading 100 σ away: p underflows, log p does not.
    q = BeamModelParams(1.0, 0.0, 0.0, 0.0, 0.01, 1.0, 8.0)
    assert beam_mixture(2.0, 1.0, q) == 0.0
    lp = beam_mixture(2.0, 1.0, q, log=True)
    expected = stats.norm.logpdf(2.0, 1.0, 0.01)  # the truncation mass is 1 here
    assert lp == pytest.approx(expected, rel=1e-12)
    # Off every support: -inf, no warning.
    assert (
        beam_mixture(5.0, 1.0, BeamModelParams(0.0, 1.0, 0.0, 0.0, 0.1, 1.0, 8.0), log=True)
        == -np.inf
    )


def test_sampler_matches_the_mixture():
    rng = np.random.default_rng(0)
    z_star = 3.0
    z = sample_beam_mixture(z_star, P, size=40_000, rng=rng)
    at_max = z == P.max_range
    # The point mass: a binomial count.
    assert stats.binomtest(int(at_max.sum()), z.size, P.z_max).pvalue > P_MIN
    # The continuous part: KS against the CDF of the normalised density part.
    grid = np.linspace(0.0, 8.0, 8001)
    dens = beam_mixture(grid[:-1] + 0.0005, z_star, P) / (1 - P.z_max)
    cdf_grid = np.concatenate([[0.0], np.cumsum(dens) * 0.001])

    def cdf(x):
        return np.interp(x, grid, cdf_grid)

    assert stats.kstest(z[~at_max], cdf).pvalue > P_MIN
    # Each component alone, too (short: truncated exponential; hit: truncated normal).
    short = sample_beam_mixture(
        np.full(20_000, z_star), BeamModelParams(0, 1, 0, 0, 0.2, 0.5, 8.0), rng=1
    )
    assert short.max() <= z_star
    assert stats.kstest(short, stats.truncexpon(b=z_star * 0.5, scale=1 / 0.5).cdf).pvalue > P_MIN
    hit = sample_beam_mixture(0.1, BeamModelParams(1, 0, 0, 0, 0.2, 0.5, 8.0), size=20_000, rng=2)
    assert hit.min() >= 0
    tn = stats.truncnorm(a=(0 - 0.1) / 0.2, b=(8 - 0.1) / 0.2, loc=0.1, scale=0.2)
    assert stats.kstest(hit, tn.cdf).pvalue > P_MIN


def test_sampler_is_reproducible_and_shapes():
    a = sample_beam_mixture([1.0, 2.0], P, size=(5, 2), rng=3)
    b = sample_beam_mixture([1.0, 2.0], P, size=(5, 2), rng=np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)
    assert a.shape == (5, 2)
    with pytest.raises(ValueError, match="size"):
        sample_beam_mixture([1.0, 2.0], P, size=3)
    with pytest.raises(ValueError, match="rng"):
        sample_beam_mixture([1.0, 2.0], P, rng=-1)
    with pytest.raises(TypeError, match="z_star"):
        sample_beam_mixture([1.0 + 1j], P)


# ------------------------------------------------------------------ Table 6.1 on a map
@pytest.fixture(scope="module")
def room():
    occ = np.zeros((60, 80), bool)
    occ[[0, -1], :] = True
    occ[:, [0, -1]] = True
    occ[20:40, 50:53] = True
    return OccupancyGrid(occ, 0.1)


def test_scan_likelihood_is_the_product_over_beams(room):
    angles = np.deg2rad(np.arange(-90, 90, 10))
    pose = np.array([2.0, 3.0, 0.2])
    z_star = ray_cast(room, pose, angles, P.max_range)
    z = sample_beam_mixture(z_star, P, rng=5)
    q = beam_range_finder_model(z, pose, room, angles, P)
    assert q == pytest.approx(np.prod(beam_mixture(z, z_star, P)), rel=1e-12)
    lq = beam_range_finder_model(z, pose, room, angles, P, log=True)
    assert lq == pytest.approx(np.log(q), rel=1e-12)


def test_scan_likelihood_peaks_at_the_true_pose_and_batches(room):
    angles = np.deg2rad(np.arange(-90, 90, 1.0))  # 180 beams: the product underflows
    pose = np.array([2.0, 3.0, 0.2])
    z = ray_cast(room, pose, angles, P.max_range)
    offsets = np.array([[0, 0, 0], [0.3, 0, 0], [0, -0.3, 0], [0, 0, 0.1]])
    lq = beam_range_finder_model(z, pose + offsets, room, angles, P, log=True)
    assert lq.shape == (4,)
    assert np.argmax(lq) == 0
    assert np.all(np.isfinite(lq))
    for k in range(4):
        assert lq[k] == beam_range_finder_model(z, pose + offsets[k], room, angles, P, log=True)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(z_hit=0.8), "sum to 1"),
        (dict(z_rand=-0.05, z_hit=0.9), "z_rand"),
        (dict(sigma_hit=-0.1), "sigma_hit"),
        (dict(sigma_hit=0.0), "sigma_hit"),
        (dict(lambda_short=0.0), "lambda_short"),
        (dict(max_range=np.nan), "max_range"),
    ],
)
def test_bad_parameters_raise(kwargs, match):
    base = dict(
        z_hit=0.7,
        z_short=0.1,
        z_max=0.05,
        z_rand=0.15,
        sigma_hit=0.2,
        lambda_short=0.5,
        max_range=8.0,
    )
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        BeamModelParams(**base)


def test_bad_model_input_raises(room):
    angles = np.zeros(3)
    with pytest.raises(ValueError, match="outside the map"):
        beam_range_finder_model(np.ones(3), [50.0, 1.0, 0.0], room, angles, P)
    with pytest.raises(ValueError, match="z must have shape"):
        beam_range_finder_model(np.ones(4), [2.0, 1.0, 0.0], room, angles, P)
    with pytest.raises(ValueError, match="non-negative"):
        beam_mixture(-1.0, 1.0, P)
    with pytest.raises(ValueError, match="z_star"):
        beam_mixture(1.0, 9.0, P)
    with pytest.raises(ValueError, match="params"):
        beam_mixture(1.0, 1.0, (0.7, 0.1, 0.05, 0.15, 0.2, 0.5, 8.0))
