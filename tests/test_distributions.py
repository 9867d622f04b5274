from functools import partial

import numpy as np
import pytest
from scipy import integrate, stats

from probrob.distributions import (
    prob_normal_distribution,
    prob_triangular_distribution,
    sample_normal_distribution,
    sample_triangular_distribution,
)

DENSITIES = [prob_normal_distribution, prob_triangular_distribution]
SAMPLERS = [
    sample_normal_distribution,
    partial(sample_normal_distribution, method="exact"),
    sample_triangular_distribution,
]
N = 200_000
ALPHA = 0.001  # significance level of every statistical test below, at a fixed seed


@pytest.mark.parametrize("prob", DENSITIES)
@pytest.mark.parametrize("b2", [0.01, 1.0, 7.3])
def test_density_integrates_to_one_with_variance_b2(prob, b2):
    lim = 12 * np.sqrt(b2)
    points = [-np.sqrt(6 * b2), 0.0, np.sqrt(6 * b2)]  # kinks of the triangle
    mass, _ = integrate.quad(lambda a: prob(a, b2), -lim, lim, points=points, limit=200)
    var, _ = integrate.quad(lambda a: a * a * prob(a, b2), -lim, lim, points=points, limit=200)
    assert mass == pytest.approx(1.0, abs=1e-9)
    assert var == pytest.approx(b2, rel=1e-8)


def test_normal_density_matches_scipy():
    a = np.linspace(-5, 5, 41)
    np.testing.assert_allclose(
        prob_normal_distribution(a, 2.5), stats.norm.pdf(a, 0, np.sqrt(2.5))
    )


def test_triangular_density_support_and_peak():
    b2 = 4.0
    half_width = np.sqrt(6 * b2)
    assert prob_triangular_distribution(0.0, b2) == pytest.approx(1 / (np.sqrt(6) * 2))
    assert prob_triangular_distribution(half_width, b2) == pytest.approx(0.0, abs=1e-15)
    assert prob_triangular_distribution(half_width * 1.01, b2) == 0.0


@pytest.mark.parametrize("prob", DENSITIES)
def test_zero_variance_is_a_point_mass(prob):
    assert prob(0.0, 0.0) == np.inf
    assert prob(1e-12, 0.0) == 0.0
    np.testing.assert_array_equal(prob(np.array([0.0, 1.0]), 0.0), [np.inf, 0.0])


@pytest.mark.parametrize("sample", SAMPLERS)
def test_zero_variance_samples_are_zero(sample):
    np.testing.assert_array_equal(sample(0.0, size=5, rng=0), np.zeros(5))


def irwin_hall_12_cdf(z):
    """Exact CDF of ½ Σ of twelve rand(-1, 1), i.e. of (Σ_{12} U(0, 1)) - 6."""
    from math import comb, factorial

    s = np.asarray(z) + 6.0
    total = np.zeros_like(s)
    for k in range(13):
        total += (-1) ** k * comb(12, k) * np.clip(s - k, 0, None) ** 12
    return total / factorial(12)


def test_sum12_sampler_is_exactly_irwin_hall_with_variance_b2():
    b2 = 2.25
    x = sample_normal_distribution(b2, size=N, rng=1)
    z = x / np.sqrt(b2)
    assert stats.kstest(z, irwin_hall_12_cdf).pvalue > ALPHA
    assert np.abs(z).max() <= 6.0
    # Its variance is b² (a 4σ interval of the sample variance of N draws).
    assert abs(x.var() - b2) < 4 * b2 * np.sqrt((2 - 0.1) / N)


def test_irwin_hall_is_close_to_the_normal():
    # The book's approximation: the CDFs differ by less than 0.003 everywhere.
    z = np.linspace(-6, 6, 2001)
    assert np.max(np.abs(irwin_hall_12_cdf(z) - stats.norm.cdf(z))) < 3e-3


def test_exact_sampler_is_normal():
    x = sample_normal_distribution(0.49, size=N, rng=2, method="exact")
    assert stats.kstest(x, stats.norm(0, 0.7).cdf).pvalue > ALPHA


def test_triangular_sampler_matches_its_density():
    b2 = 0.3
    x = sample_triangular_distribution(b2, size=N, rng=3)
    half_width = np.sqrt(6 * b2)
    tri = stats.triang(c=0.5, loc=-half_width, scale=2 * half_width)
    assert stats.kstest(x, tri.cdf).pvalue > ALPHA
    # ... and scipy's triangle is the book's density.
    a = np.linspace(-2, 2, 101)
    np.testing.assert_allclose(tri.pdf(a), prob_triangular_distribution(a, b2), atol=1e-12)


@pytest.mark.parametrize("sample", SAMPLERS)
def test_samplers_broadcast_variance_arrays(sample):
    b2 = np.array([0.0, 1.0, 100.0])
    x = sample(b2, size=(50_000, 3), rng=4)
    assert x.shape == (50_000, 3)
    assert np.all(x[:, 0] == 0)
    np.testing.assert_allclose(x.std(axis=0)[1:], [1.0, 10.0], rtol=0.02)


@pytest.mark.parametrize("sample", SAMPLERS)
def test_sampler_shapes_and_reproducibility(sample):
    assert isinstance(sample(1.0, rng=0), float)
    for shape in [(7,), (4, 5)]:
        assert sample(1.0, size=shape, rng=0).shape == shape
        assert sample(np.ones(shape), rng=0).shape == shape
    np.testing.assert_array_equal(sample(1.0, size=9, rng=5), sample(1.0, size=9, rng=5))
    gen = np.random.default_rng(6)
    assert not np.array_equal(sample(1.0, size=9, rng=gen), sample(1.0, size=9, rng=gen))


@pytest.mark.parametrize("prob", DENSITIES)
def test_density_shapes(prob):
    assert isinstance(prob(0.1, 1.0), float)
    for shape in [(7,), (4, 5)]:
        a = np.linspace(-1, 1, int(np.prod(shape))).reshape(shape)
        p = prob(a, 0.5)
        assert p.shape == shape
        np.testing.assert_allclose(p.ravel(), [prob(ai, 0.5) for ai in a.ravel()])


@pytest.mark.parametrize("prob", DENSITIES)
def test_density_bad_input(prob):
    with pytest.raises(ValueError, match="b2"):
        prob(0.0, -1.0)
    with pytest.raises(ValueError, match="b2"):
        prob(0.0, np.nan)
    with pytest.raises(ValueError, match=r"\ba\b"):
        prob(np.nan, 1.0)
    with pytest.raises(ValueError, match=r"\ba\b"):
        prob("x", 1.0)


@pytest.mark.parametrize("sample", SAMPLERS)
def test_sampler_bad_input(sample):
    with pytest.raises(ValueError, match="b2"):
        sample(-0.1, size=3)
    with pytest.raises(ValueError, match="b2"):
        sample(np.inf)
    with pytest.raises(ValueError, match="size"):
        sample(np.ones(3), size=(4,))
    with pytest.raises(ValueError, match="size"):
        sample(1.0, size=-2)


def test_unknown_method():
    with pytest.raises(ValueError, match="method"):
        sample_normal_distribution(1.0, method="box-muller")
