"""EM for the beam model's intrinsic parameters, Table 6.2 (corrected; errata B1-B3)."""

import numpy as np
import pytest

from probrob.sensors import BeamModelParams, learn_intrinsic_parameters, sample_beam_mixture

TRUE = BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.1, 0.8, 10.0)
N = 30_000


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(11)
    z_star = rng.uniform(0.5, 9.0, N)
    return sample_beam_mixture(z_star, TRUE, rng=rng), z_star


@pytest.fixture(scope="module")
def fit(data):
    z, z_star = data
    return learn_intrinsic_parameters(z, z_star, 10.0, full_output=True)


def test_em_recovers_the_parameters_it_was_sampled_from(fit):
    p, info = fit
    assert info.converged
    # Stated tolerances: weights within 0.01 (a few binomial standard errors at
    # N = 30,000: sqrt(0.7 * 0.3 / N) = 0.0026), σ_hit and λ_short within 5 %.
    np.testing.assert_allclose(p.weights, TRUE.weights, atol=0.01)
    assert p.sigma_hit == pytest.approx(TRUE.sigma_hit, rel=0.05)
    assert p.lambda_short == pytest.approx(TRUE.lambda_short, rel=0.05)
    assert p.max_range == 10.0


def test_em_history_increases_and_stops_by_the_stated_criterion(fit):
    _, info = fit
    ll = info.log_likelihood
    assert ll.shape == (info.n_iter + 1,)
    assert np.all(np.diff(ll) > -1e-10)  # EM never decreases the likelihood
    assert abs(ll[-1] - ll[-2]) < 1e-8 <= abs(ll[-2] - ll[-3])
    e = info.responsibilities
    assert e.shape == (N, 4)
    np.testing.assert_allclose(e.sum(axis=1), 1.0)


def test_readings_at_max_range_are_the_point_mass(data, fit):
    z, _ = data
    p, info = fit
    at_max = z >= 10.0
    # The max weight is exactly the fraction of max-range readings ...
    assert p.z_max == pytest.approx(at_max.mean(), abs=1e-12)
    # ... because each of them is explained by the point mass alone.
    np.testing.assert_array_equal(info.responsibilities[at_max], [[0, 0, 1, 0]] * at_max.sum())


def test_deck_e_step_without_weights_fails_to_recover(data):
    """Errata B1: Table 6.2's η omits the mixing weights: not EM, wrong fixed point."""
    z, z_star = data
    p = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck")
    err = np.abs(p.weights - TRUE.weights)
    assert err.max() > 0.04  # the weights are off by several times the tolerance
    # And literally, p_max = 1 added to the hit density at z_max: e_max < 1 for a max
    # reading whose expected range is z_max.
    _, info = learn_intrinsic_parameters(
        np.r_[z, 10.0], np.r_[z_star, 10.0], 10.0, e_step="deck", full_output=True, max_iter=1
    )
    assert info.responsibilities[-1, 2] < 0.5


def test_book_closed_form_lambda_ignores_the_truncation(data):
    """Errata B3: λ = Σe/Σez is the MLE of an untruncated exponential: biased here."""
    z, z_star = data
    p = learn_intrinsic_parameters(z, z_star, 10.0, m_step="book")
    assert p.lambda_short > 1.25 * TRUE.lambda_short


def test_sigma_near_the_range_limits_needs_the_truncated_step():
    # z* close to 0: the hit normal is truncated at 0 and its variance is smaller than σ².
    truth = BeamModelParams(0.9, 0.0, 0.0, 0.1, 0.2, 1.0, 4.0)
    rng = np.random.default_rng(5)
    z_star = rng.uniform(0.0, 0.2, 40_000)
    z = sample_beam_mixture(z_star, truth, rng=rng)
    init = BeamModelParams(0.8, 0.0, 0.0, 0.2, 0.1, 1.0, 4.0)  # a zero weight stays zero
    exact = learn_intrinsic_parameters(z, z_star, 4.0, init=init)
    book = learn_intrinsic_parameters(z, z_star, 4.0, init=init, m_step="book")
    assert exact.sigma_hit == pytest.approx(0.2, rel=0.03)
    assert abs(book.sigma_hit - 0.2) > 0.1 * 0.2


def test_clean_data_drives_the_other_weights_to_zero():
    # LNPR-like: one beam at a fixed distance, Gaussian noise only.
    rng = np.random.default_rng(6)
    z = 0.2 + 0.005 * rng.standard_normal(20_000)
    p = learn_intrinsic_parameters(z, 0.2, 4.0, max_iter=2000)
    assert p.z_hit > 0.995
    assert p.sigma_hit == pytest.approx(0.005, rel=0.03)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(z=[-1.0]), "non-negative"),
        (dict(z_star=[11.0]), "z_star"),
        (dict(max_range=0.0), "max_range"),
        (dict(e_step="book"), "e_step"),
        (dict(m_step="newton"), "m_step"),
        (dict(max_iter=0), "max_iter"),
        (dict(z=[]), "at least one"),
        (dict(init=BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.1, 0.8, 5.0)), "init.max_range"),
    ],
)
def test_bad_input(kwargs, match):
    args = dict(z=[1.0, 2.0], z_star=[1.0, 2.0], max_range=10.0)
    args.update(kwargs)
    if "z" in kwargs and len(args["z"]) != len(args["z_star"]):
        args["z_star"] = np.zeros(len(args["z"]))
    with pytest.raises(ValueError, match=match):
        learn_intrinsic_parameters(
            args.pop("z"), args.pop("z_star"), args.pop("max_range"), **args
        )
