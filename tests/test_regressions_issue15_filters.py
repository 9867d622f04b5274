"""Regression tests of issue 15 for the filters and their evaluation (items 2, 4, 5, 6, 8).

Each test failed on the code before its fix (checked once, see the commit message).
"""

from __future__ import annotations

import re
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from probrob.evaluation import chi2_quantile, covariance_ellipse, nees
from probrob.localization import (
    ekf_localization,
    ekf_localization_known_correspondences,
    ekf_predict_segment,
    run_filter,
    ukf_localization,
    ukf_weights,
)

MAP = np.array([[2.0, 1.0, 0.0], [1.0, -2.0, 1.0]])
MU = np.zeros(3)
SIGMA = 0.01 * np.eye(3)
U = np.array([1.0, 0.1])
ALPHA = [0.01, 0.01, 0.01, 0.01]
SIGMAS = [0.1, 0.05, 0.1]
NO_Z = np.zeros((0, 3))
NO_C = np.zeros(0, dtype=int)


def _raises_naming(name, fn, *args, **kwargs):
    """``fn`` raises a ValueError whose message names ``name``, and no warning leaks."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=re.escape(name)):
            fn(*args, **kwargs)


# --------------------------------------------------------------------------- item 2


@pytest.mark.parametrize("dof", [1, 2, 3, 10, 150, 1399, 1400, 3000, 10_000, 100_000])
@pytest.mark.parametrize("p", [1e-12, 0.025, 0.5, 0.95, 0.975, 1 - 1e-6, 1 - 1e-12])
def test_chi2_quantile_equals_scipy_for_large_dof_and_p_near_one(p, dof):
    # Was: 1490.27 for every dof >= ~1400 (e^{-x/2} underflowed), 2e-6 off at p = 1 - 1e-12.
    assert chi2_quantile(p, dof) == pytest.approx(stats.chi2.ppf(p, dof), rel=1e-12)


def test_chi2_quantile_of_the_issue():
    assert chi2_quantile(0.95, 3000) == pytest.approx(3128.54, abs=0.01)


def test_chi2_quantile_two_dof_is_the_closed_form_near_one():
    # χ²₂ is the exponential distribution of mean 2: q = -2 log(1 - p), 1 - p exact here.
    p = 1 - 1e-12
    assert chi2_quantile(p, 2) == pytest.approx(-2.0 * np.log1p(-p), rel=1e-13)


# --------------------------------------------------------------------------- item 4

NON_SYMMETRIC = np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def test_nees_rejects_a_non_symmetric_sigma():
    # Was 0.03: only the lower triangle was read.
    _raises_naming("Sigma", nees, np.zeros(3), 0.1 * np.ones(3), NON_SYMMETRIC)
    stack = np.stack([np.eye(3), NON_SYMMETRIC])
    _raises_naming("Sigma", nees, np.zeros((2, 3)), np.zeros((2, 3)), stack)


def test_covariance_ellipse_rejects_a_non_symmetric_sigma():
    # Was silently symmetrised.
    _raises_naming("Sigma", covariance_ellipse, np.zeros(3), NON_SYMMETRIC)
    _raises_naming("Sigma", covariance_ellipse, np.zeros(2), NON_SYMMETRIC[:2, :2])


# --------------------------------------------------------------------------- item 5


def _steps(dt, features):
    z = np.array([[2.2, 0.45, 0.0]]) if features else NO_Z
    c = np.array([0]) if features else NO_C
    first = SimpleNamespace(t=0.1, dt=0.1, u=U, z=NO_Z, c=NO_C)
    return [first, SimpleNamespace(t=0.2, dt=dt, u=U, z=z, c=c)]


@pytest.mark.parametrize("method", ["ekf", "ekf_ml", "ukf", "ukf_ml"])
@pytest.mark.parametrize("features", [False, True])
@pytest.mark.parametrize("dt", [np.inf, np.nan])
def test_run_filter_rejects_a_non_finite_dt(method, features, dt):
    # Was NaN with warnings (no features), "non-finite estimate" (EKF) or "math domain
    # error" (UKF).
    _raises_naming(
        "dt", run_filter, _steps(dt, features), MU, SIGMA, MAP, ALPHA, SIGMAS, method=method
    )


@pytest.mark.parametrize("method", ["ekf", "ekf_ml"])
def test_run_filter_names_dt_when_a_huge_dt_overflows(method):
    # A finite but absurd step: the EKF's V M V^T (Δt² M) overflows, and the error names
    # the step's dt, not "the inputs' scales". (The UKF's sigma points stay on bounded
    # arcs: a finite dt gives a finite step there.)
    _raises_naming(
        "dt", run_filter, _steps(1e300, True), MU, SIGMA, MAP, ALPHA, SIGMAS, method=method
    )


def test_one_step_names_dt_when_it_overflows():
    _raises_naming(
        "dt",
        ekf_localization_known_correspondences,
        MU,
        SIGMA,
        U,
        NO_Z,
        NO_C,
        MAP,
        1e300,
        ALPHA,
        SIGMAS,
    )
    _raises_naming("dt", ekf_localization, MU, SIGMA, U, NO_Z, MAP, 1e300, ALPHA, SIGMAS)


@pytest.mark.parametrize(
    ("u", "dt", "alpha", "name"),
    [
        ([[1e200, 0.1]] * 3, 0.1, ALPHA, "u"),
        ([[1.0, 0.1]] * 3, 1e300, ALPHA, "dt"),
        ([[10.0, 0.1]] * 3, 1.0, [1e308] * 4, "alpha"),
    ],
)
def test_ekf_predict_segment_reports_overflow_without_warnings(u, dt, alpha, name):
    # Was RuntimeWarning: overflow encountered in square / matmul / multiply.
    _raises_naming(name, ekf_predict_segment, MU, SIGMA, u, dt, alpha)


# --------------------------------------------------------------------------- item 6


@pytest.mark.parametrize("filt", [ekf_localization_known_correspondences, ukf_localization])
@pytest.mark.parametrize("log", ["False", 0, 1, None, np.array([True])])
def test_log_flag_must_be_a_bool(filt, log):
    # Was: log="False" returned the log.
    _raises_naming("log", filt, MU, SIGMA, U, NO_Z, NO_C, MAP, 0.1, ALPHA, SIGMAS, log=log)


# --------------------------------------------------------------------------- item 8


@pytest.mark.parametrize("ukf_alpha", [1e-10, 1e-160, 1e200])
def test_ukf_weights_name_ukf_alpha_when_the_weights_break_down(ukf_alpha):
    # Was ZeroDivisionError (1e-10, 1e-160) or NaN weights (1e200).
    _raises_naming("ukf_alpha", ukf_weights, 3, ukf_alpha=ukf_alpha)


def test_ukf_weights_name_kappa_when_n_plus_lambda_is_not_positive():
    _raises_naming("kappa", ukf_weights, 3, kappa=-3.0)


def test_ukf_weights_name_kappa_when_n_plus_lambda_overflows():
    _raises_naming("kappa", ukf_weights, 3, ukf_alpha=10.0, kappa=1e308)


def test_ukf_localization_names_ukf_alpha():
    # Was ZeroDivisionError inside the step.
    _raises_naming(
        "ukf_alpha",
        ukf_localization,
        MU,
        SIGMA,
        U,
        NO_Z,
        NO_C,
        MAP,
        0.1,
        ALPHA,
        SIGMAS,
        ukf_alpha=1e-10,
    )


def test_ukf_weights_still_sum_to_one_at_small_and_large_alpha():
    for a in (1e-4, 1e-3, 1.0, 1e3):
        gamma, wm, wc = ukf_weights(3, ukf_alpha=a)
        assert np.isfinite(gamma) and np.all(np.isfinite(wm)) and np.all(np.isfinite(wc))
        assert wm.sum() == pytest.approx(1.0, abs=1e-6)
