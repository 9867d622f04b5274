"""The numbers stated by the errata entries of deck T4 ("Trabalho 4"), recomputed.

Each test names its entry (``book/errata.md``, L1–L3 and B1–B7) and asserts every number or
approximation that the entry states, at the precision it states it.
"""

import inspect

import numpy as np
import pytest
from scipy.special import ndtr

from probrob.angles import wrap_angle
from probrob.datasets import load_intel_lab
from probrob.distributions import prob_normal_distribution, sample_normal_distribution
from probrob.maps import OccupancyGrid
from probrob.sensors import (
    BeamModelParams,
    beam_model_components,
    beam_range_finder_model,
    landmark_measurement,
    landmark_model_known_correspondence,
    learn_intrinsic_parameters,
    sample_beam_mixture,
)

MAP = np.array([[2.0, 1.0, 7.0], [-3.0, 4.0, 8.0], [0.5, -2.5, 9.0]])
SIGMAS = np.array([0.1, 0.05, 0.2])
TRUE = BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.1, 0.8, 10.0)  # the chapter's EM data


def deck_prob(a, b):
    """Table 5.2's prob(a, b²) fed what deck T4 feeds it: b in the variance slot."""
    return np.exp(-0.5 * a**2 / b) / np.sqrt(2 * np.pi * b)


@pytest.fixture(scope="module")
def em_data():
    rng = np.random.default_rng(11)
    z_star = rng.uniform(0.5, 9.0, 30_000)
    return sample_beam_mixture(z_star, TRUE, rng=rng), z_star


@pytest.fixture(scope="module")
def intel():
    d = load_intel_lab()
    grid = OccupancyGrid.from_scans(d.poses, d.ranges, d.beam_angles, 0.05, max_range=d.max_range)
    return d, grid


def test_L1_sigma_in_the_variance_slot_widens_the_noise():
    """L1: σ_r = 0.1 m read as a variance is a range noise of 0.32 m; σ_r = 0.04 m, 0.2 m."""
    for sigma, stated in [(0.1, 0.32), (0.04, 0.2)]:
        draws = sample_normal_distribution(sigma, 200_000, rng=1)  # the deck's sample(σ)
        assert draws.std() == pytest.approx(stated, abs=0.005)
        assert np.sqrt(sigma) == pytest.approx(stated, abs=0.005)


def test_L2_a_turned_robot_is_judged_impossible():
    """L2: a robot turned by 0.7 rad: likelihood above 10 with −θ, below 1e-6 without."""
    x = np.array([0.0, 0.0, 0.7])
    f = landmark_measurement(x, MAP[0])
    assert landmark_model_known_correspondence(f, 0, x, MAP, SIGMAS) > 10
    r_hat = np.hypot(*(MAP[0, :2] - x[:2]))
    phi_deck = np.arctan2(MAP[0, 1] - x[1], MAP[0, 0] - x[0])  # no −θ
    deck = (
        deck_prob(f[0] - r_hat, SIGMAS[0] ** 2)
        * deck_prob(f[1] - phi_deck, SIGMAS[1] ** 2)
        * deck_prob(f[2] - MAP[0, 2], SIGMAS[2] ** 2)
    )
    assert deck < 1e-6


def test_L3_unwrapped_bearing_error_is_two_pi_off():
    """L3: raw difference 2π − 0.015 rad, likelihood 0; the true error is 0.015 rad."""
    lm = np.array([-2.0, -0.02, 7.0])
    phi_hat = landmark_measurement([0.0, 0.0, 0.0], lm)[1]
    phi = np.pi - 0.005
    assert phi - phi_hat == pytest.approx(2 * np.pi - 0.015, abs=5e-4)
    assert abs(wrap_angle(phi - phi_hat)) == pytest.approx(0.015, abs=5e-4)
    assert deck_prob(phi - phi_hat, SIGMAS[1] ** 2) == 0.0


def test_B1_deck_e_step_numbers(em_data):
    """B1: z_hit = 0.656 for Table 6.2 as printed, 0.643 with the exact M-step, 0.698 by EM."""
    z, z_star = em_data
    printed = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck", m_step="book")
    deck_e = learn_intrinsic_parameters(z, z_star, 10.0, e_step="deck")
    em = learn_intrinsic_parameters(z, z_star, 10.0)
    assert round(printed.z_hit, 3) == 0.656
    assert round(deck_e.z_hit, 3) == 0.643
    assert round(em.z_hit, 3) == 0.698


def test_B1_the_deck_e_step_lowers_the_likelihood(em_data):
    """B1: on the chapter's data the deck's E-step lowers the likelihood at some of its
    iterations (with either M-step), where EM's never falls."""
    z, z_star = em_data
    for m_step in ("exact", "book"):
        _, deck = learn_intrinsic_parameters(
            z, z_star, 10.0, e_step="deck", m_step=m_step, full_output=True
        )
        assert np.diff(deck.log_likelihood).min() < -1e-4, m_step
    _, em = learn_intrinsic_parameters(z, z_star, 10.0, full_output=True)
    assert np.diff(em.log_likelihood).min() > -1e-12


def test_B2_hit_density_at_the_range_and_the_deck_point_mass():
    """B2: p_hit(z_max) = 2/(√(2π) σ_hit) ≈ 8/m for σ_hit = 0.1 m when z* = z_max; the
    printed η then gives the point mass e_max = 1/(1 + p_hit + p_short) = 0.111, with
    p_short = 0.0003/m: about a ninth, where it should be 1."""
    p = BeamModelParams(0.7, 0.1, 0.05, 0.15, 0.1, 0.8, 10.0)
    comps = beam_model_components(10.0, 10.0, p)  # at z = z* = z_max: p_rand is 0 there
    p_hit, p_short = comps[0], comps[1]
    assert p_hit == pytest.approx(2 / (np.sqrt(2 * np.pi) * 0.1), rel=1e-6)
    assert round(p_hit) == 8
    assert f"{p_short:.4f}" == "0.0003" and comps[3] == 0.0
    # The deck's E-step for one reading at z_max = z*, with these parameters.
    _, info = learn_intrinsic_parameters(
        [10.0], [10.0], 10.0, init=p, e_step="deck", full_output=True, max_iter=1
    )
    e_max = info.responsibilities[0, 2]
    assert e_max == pytest.approx(1 / (1 + p_hit + p_short), rel=1e-9)
    assert f"{e_max:.3f}" == "0.111"  # the entry's number
    assert round(1 / e_max) == 9  # "about a ninth"
    _, ours = learn_intrinsic_parameters(
        [10.0], [10.0], 10.0, init=p, full_output=True, max_iter=1
    )
    assert ours.responsibilities[0, 2] == 1.0  # "where it should be 1"


def test_B3_closed_form_lambda_and_the_nine_sigma_rule(em_data):
    """B3: the closed form returns 1.3 for data drawn with λ = 0.8; beyond 9σ_hit the
    truncation of p_hit is below double precision, so the closed form is exact there."""
    z, z_star = em_data
    book = learn_intrinsic_parameters(z, z_star, 10.0, m_step="book")
    assert round(book.lambda_short, 1) == 1.3
    assert ndtr(-9.0) < np.finfo(float).eps * 1e-2


def test_B3_with_the_closed_form_the_likelihood_falls(em_data):
    """B3: with the closed-form M-step EM's likelihood falls at more than half of its
    iterations on the chapter's data."""
    z, z_star = em_data
    _, info = learn_intrinsic_parameters(z, z_star, 10.0, m_step="book", full_output=True)
    steps = np.diff(info.log_likelihood)
    assert np.mean(steps < 0) > 0.5 and steps.min() < -1e-4


def test_B4_default_tolerance_is_stated():
    """B4: the convergence criterion is a change below tol = 1e-8 nats."""
    tol = inspect.signature(learn_intrinsic_parameters).parameters["tol"].default
    assert tol == 1e-8


def test_B5_deck_random_term_integrates_to_five():
    """B5: z_rand z_max / z_hit = 5 for z_rand = 0.2, z_hit = 0.8, z_max = 20 m; the book's
    z_rand / z_max integrates to 0.2."""
    z_rand, z_hit, r_max = 0.2, 0.8, 20.0
    grid = np.linspace(0.0, r_max, 20_001)
    dz = grid[1] - grid[0]
    deck = np.full(grid.size - 1, z_rand / z_hit).sum() * dz
    book = np.full(grid.size - 1, z_rand / r_max).sum() * dz
    assert deck == pytest.approx(5.0, rel=1e-12)
    assert book == pytest.approx(0.2, rel=1e-12)


def test_B6_sigma_read_as_variance_blurs_three_times():
    """B6: σ_hit = 0.1 m in the variance slot is a normal of std 0.32 m, three times wider."""
    d = np.linspace(-3, 3, 60_001)
    dens = prob_normal_distribution(d, 0.1)  # the deck's prob(dist, σ_hit)
    std = np.sqrt(np.sum(dens * d**2) / np.sum(dens))
    assert round(std, 2) == 0.32
    assert round(std / 0.1) == 3


def test_B7_scan_400_products(intel):
    """B7: scan 400 turned by 90° has log q = −1061, so q underflows (below 5e-324); at the
    corrected pose q is about 1e57."""
    d, grid = intel
    p = BeamModelParams(0.85, 0.05, 0.03, 0.07, 0.05, 0.5, d.max_range)
    z, x = d.ranges[400], d.poses[400]
    wrong = beam_range_finder_model(z, x + [0, 0, np.pi / 2], grid, d.beam_angles, p, log=True)
    right = beam_range_finder_model(z, x, grid, d.beam_angles, p, log=True)
    assert round(wrong) == -1061
    assert np.exp(wrong) == 0.0 and np.log(5e-324) > wrong
    assert beam_range_finder_model(z, x + [0, 0, np.pi / 2], grid, d.beam_angles, p) == 0.0
    assert round(right / np.log(10)) == 57
