"""One table-driven property suite over the whole public API of probrob (issue 11).

For every public function, hypothesis draws valid inputs (including the degenerate ones:
v = ω = 0, α = 0, zero deltas, θ at ±π, tiny and huge magnitudes) and checks the properties of
its kind; and for every argument, a table of invalid values checks that the function raises
``ValueError`` (``TypeError`` for complex input) whose message names the argument.

How a module joins the suite
----------------------------
Add one :class:`Api` row per public function to ``API`` at the bottom of this file::

    Api(
        probrob.sensors.landmark_model_known_correspondence,  # the function
        "density",  # its kind: "density" | "sampler" | "map" | "plot" | "widget"
        f=LANDMARK_FEATURES,  # every argument the function is called with, by keyword,
        c=CORRESPONDENCE,  # each an ``Arg`` (below): a valid-input strategy, a valid
        x=POSES,  # default, and the invalid values with the exception they raise
        m=LANDMARK_MAP,
        sigmas=SIGMAS3,
    )

Reuse the ``Arg`` objects below (``POSES``, ``ALPHAS6``, ``DT``, ``RNG``, ``SIZE``, ...) or
define new ones next to them. An ``Arg`` is::

    Arg(
        valid=lambda batch: <hypothesis strategy>,  # draws a valid value; ``batch`` is the
        #   example's batch shape (a tuple): batched arguments use ``batched(batch, ...)`` so
        #   that all of them broadcast; scalars ignore it
        default=<a valid value>,  # used for this argument while another one is invalid
        invalid=[(value, ValueError), (1j, TypeError), ...],  # each must raise, naming it
    )

What each kind checks on valid input (always: no warning, the input arrays are not modified,
and a ``ValueError`` is only allowed if it reports a float64 overflow against one of the
function's own arguments, ``"<arg> = ... overflows float64"``):

* ``"density"`` -- the result is >= 0 and never NaN, has the broadcast batch shape, is finite
  where the row's ``finite_when(kwargs)`` says a finite value is defined, and
  ``exp(f(..., log=True)) == f(...)``; ``log`` gets invalid values too.
* ``"sampler"`` -- finite, of shape ``size`` (or the batch shape) + ``trailing``, and the same
  for the same integer seed; ``rng`` and ``size`` must be among the arguments.
* ``"map"`` -- every returned array is finite, and two calls agree.
* ``"plot"`` -- returns a matplotlib ``Axes`` (figures are closed afterwards).
* ``"widget"`` -- returns without error (invalid rows matter most here).

``extra=lambda result, kwargs: ...`` adds row-specific assertions (e.g. angles in [-π, π)).
``examples=`` sets the number of hypothesis examples of a row (default 40; slow rows fewer);
``skip_valid=True`` keeps only the invalid rows (for functions too slow for many examples).
``check_batch_shape=False`` turns off the density shape check for functions whose batch
arguments do not simply broadcast (e.g. landmark maps).
``finite=False`` relaxes a ``"map"`` row's "finite" to "never NaN" where ±inf is a defined
answer (the radius of a straight line, a log density of 0); ``nan_fields=("stderr",)`` names
fields of a result record (a dataclass) where NaN is the documented "not available";
``raises="regex"`` allows a documented ``ValueError`` on valid input (a pose on a landmark, a
filter's S that double precision cannot form) as long as its message names an argument.

Rows with a specific invalid combination (shapes that do not broadcast, ...) go in
``EXTRA_INVALID`` as ``(function, {kwargs}, names that must appear, exception)``.

Run time: the default hypothesis profile (``probrob``, tests/conftest.py) keeps this file well
under a minute. ``PROBROB_HYPOTHESIS_PROFILE=thorough`` runs ten times as many examples.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import probrob.angles as angles
import probrob.datasets as datasets
import probrob.distributions as distributions
import probrob.evaluation as evaluation
import probrob.fitting as fitting
import probrob.kinematics as kinematics
import probrob.live as live
import probrob.localization as localization
import probrob.maps as maps
import probrob.mcl as mcl
import probrob.motion as motion
import probrob.plotting as plotting
import probrob.sensors as sensors
import probrob.simulation as simulation
import probrob.widgets as widgets

# --------------------------------------------------------------------------- the row types


@dataclass(frozen=True, eq=False)  # compared by identity: ``default`` may be an array
class Arg:
    """One argument: how to draw it valid, a valid default, and invalid values to try."""

    valid: Callable[[tuple[int, ...]], st.SearchStrategy]
    default: object
    invalid: list[tuple[object, type[Exception]]] = field(default_factory=list)


class Api:
    """One public function and how to call it (see the module docstring)."""

    def __init__(self, func, kind, *, examples=40, finite_when=None, extra=None, trailing=(),
                 skip_valid=False, check_batch_shape=True, finite=True, raises=None, nan_fields=(),
                 **args):  # fmt: skip
        assert kind in ("density", "sampler", "map", "plot", "widget"), kind
        self.func, self.kind, self.args = func, kind, args
        self.examples, self.finite_when, self.extra = examples, finite_when, extra
        self.trailing, self.skip_valid = trailing, skip_valid
        self.check_batch_shape, self.finite, self.raises = check_batch_shape, finite, raises
        self.nan_fields = nan_fields

    def __repr__(self):
        return f"{self.func.__module__.split('.')[-1]}.{self.func.__name__}"


# --------------------------------------------------------------------------- strategies

PI = np.pi
BATCHES = [(), (1,), (4,), (2, 3)]


def floats(specials, lo, hi):
    """A float strategy that hits the degenerate and extreme ``specials`` often."""
    return st.one_of(
        st.sampled_from(specials), st.floats(lo, hi, allow_nan=False, allow_infinity=False)
    )


def batched(batch, trailing, elements):
    """An array of shape ``batch + trailing`` (or just ``trailing``: a broadcast argument)."""
    return st.sampled_from([batch, ()]).flatmap(
        lambda b: hnp.arrays(float, b + trailing, elements=elements)
    )


def constant(value):
    return lambda batch: st.just(value)


def choices(*values):
    return lambda batch: st.sampled_from(values)


COORD = floats([0.0, -0.0, 5e-324, 1e-300, -1e-300, 1.0, -1.0, 1e6, -1e6], -50.0, 50.0)
HEADING = floats(
    [0.0, PI, -PI, np.nextafter(PI, 0), np.nextafter(-PI, 0), PI / 2, 2 * PI, 1e-300],
    -10.0,
    10.0,
)
ANGLE = floats([0.0, PI, -PI, np.nextafter(PI, 0), 1e-300, 7.05e16, 1e300, -1e308], -1e3, 1e3)
REAL = floats([0.0, -0.0, 5e-324, 1e-300, 1.0, -1.0, 1e300, -1e308], -1e6, 1e6)
SPEED = floats([0.0, -0.0, 1e-300, 1.0, -1.0, 2.0, 1e3], -5.0, 5.0)
NONNEG = floats([0.0, 5e-324, 1e-300, 0.01, 0.1, 1.0, 10.0], 0.0, 1.0)
VARIANCE = floats([0.0, 5e-324, 1e-320, 1e-300, 1.0, 1e300], 0.0, 1e3)
DTS = floats([1e-3, 0.1, 1.0, 10.0], 1e-3, 10.0)


def _pose_elements():
    # (x, y, θ) with each column drawn from its own strategy
    return st.tuples(COORD, COORD, HEADING)


def poses_strategy(batch):
    return st.sampled_from([batch, ()]).flatmap(
        lambda b: st.lists(
            _pose_elements(), min_size=int(np.prod(b)), max_size=int(np.prod(b))
        ).map(lambda rows, b=b: np.array(rows, dtype=float).reshape(b + (3,)))
    )


def odometry_strategy(batch):
    return st.sampled_from([batch, ()]).flatmap(
        lambda b: st.lists(
            st.tuples(_pose_elements(), _pose_elements()),
            min_size=int(np.prod(b)),
            max_size=int(np.prod(b)),
        ).map(lambda rows, b=b: np.array(rows, dtype=float).reshape(b + (2, 3)))
    )


def single_pose_strategy(batch):
    return _pose_elements().map(lambda p: np.array(p, dtype=float))


def size_strategy(batch):
    if batch == ():
        return st.one_of(
            st.none(), st.integers(0, 5), st.tuples(st.integers(0, 3), st.integers(0, 3))
        )
    return st.sampled_from([None, batch, (2, *batch)])


# --------------------------------------------------------------------------- invalid values

NOT_NUMERIC = [(None, ValueError), ("abc", ValueError), ([1.0, "a"], ValueError)]
NOT_REAL = [(1j, TypeError), (np.array([1.0 + 0j]), TypeError)]
NOT_FINITE = [(np.nan, ValueError), (np.inf, ValueError), (-np.inf, ValueError)]
BAD_SCALAR = NOT_NUMERIC + NOT_REAL + NOT_FINITE


def bad_vectors(length):
    ok = [0.0] * length
    return [
        ([np.nan] + ok[1:], ValueError),
        ([np.inf] + ok[1:], ValueError),
        ([1j] + ok[1:], TypeError),
        (ok[:-1], ValueError),  # wrong length
        (np.zeros((4, length + 1)), ValueError),
        (np.float64(1.0), ValueError),  # no last axis
        (None, ValueError),
        ("abc", ValueError),
        ([[0.0] * length, [0.0]], ValueError),  # ragged
    ]


def bad_alphas(count):
    return [
        ([-0.1] + [0.0] * (count - 1), ValueError),
        ([0.1] * (count - 1), ValueError),
        ([0.1] * (count + 1), ValueError),
        ([np.nan] * count, ValueError),
        ([np.inf] * count, ValueError),
        ([1j] * count, TypeError),
        (None, ValueError),
        ("abc", ValueError),
    ]


BAD_POSITIVE = [(0.0, ValueError), (-1.0, ValueError), ([1.0, 2.0], ValueError), *BAD_SCALAR]
BAD_VARIANCE = [(-1.0, ValueError), (-5e-324, ValueError), *BAD_SCALAR]
BAD_RNG = [
    ("abc", ValueError),
    (-1, ValueError),
    (1.5, ValueError),
    (True, ValueError),
    ([1, 2], ValueError),
    (np.random.RandomState(0), ValueError),
]
BAD_SIZE = [(2.7, ValueError), (-1, ValueError), ("3", ValueError), (True, ValueError)]
BAD_SIZE += [((2, 1.5), ValueError), ((2, -1), ValueError), (3 + 0j, ValueError)]
BAD_CALLABLE = [(3, ValueError), ("prob", ValueError), (None, ValueError)]
BAD_CHOICE = [("nonsense", ValueError), (3, ValueError), (None, ValueError)]
BAD_COUNT = [(-1, ValueError), (2.5, ValueError), ("3", ValueError), (True, ValueError)]
BAD_FLAG = [("yes", ValueError), (None, ValueError), (1, ValueError)]

# --------------------------------------------------------------------------- shared Args

POSES = Arg(poses_strategy, np.array([0.1, -0.2, 0.3]), bad_vectors(3))
POSE = Arg(single_pose_strategy, np.array([0.1, -0.2, 0.3]), bad_vectors(3))
VELOCITIES = Arg(lambda batch: batched(batch, (2,), SPEED), np.array([1.0, 0.5]), bad_vectors(2))
ODOMETRY = Arg(
    odometry_strategy,
    np.array([[0.0, 0.0, 0.0], [1.0, 0.2, 0.1]]),
    [
        (np.full((2, 3), np.nan), ValueError),
        (np.zeros(3), ValueError),
        (np.zeros((3, 3)), ValueError),
        (np.zeros((2, 3)) * 1j, TypeError),
        (None, ValueError),
    ],
)
DT = Arg(lambda batch: DTS, 1.0, BAD_POSITIVE)
ALPHAS6 = Arg(lambda batch: st.lists(NONNEG, min_size=6, max_size=6), [0.05] * 6, bad_alphas(6))
ALPHAS4 = Arg(lambda batch: st.lists(NONNEG, min_size=4, max_size=4), [0.05] * 4, bad_alphas(4))
POINTS = Arg(lambda batch: batched(batch, (), REAL), 0.5, BAD_SCALAR)
ANGLES = Arg(lambda batch: batched(batch, (), ANGLE), 0.5, BAD_SCALAR)
VARIANCES = Arg(lambda batch: batched(batch, (), VARIANCE), 1.0, BAD_VARIANCE)
RNG = Arg(
    lambda batch: st.one_of(
        st.integers(0, 2**32),
        st.just(None),
        st.builds(np.random.default_rng, st.integers(0, 100)),
        st.builds(np.random.SeedSequence, st.integers(0, 100)),
    ),
    0,
    BAD_RNG,
)
SIZE = Arg(size_strategy, None, BAD_SIZE)
PROB = Arg(
    choices(distributions.prob_normal_distribution, distributions.prob_triangular_distribution),
    distributions.prob_normal_distribution,
    BAD_CALLABLE,
)
SAMPLE = Arg(
    choices(
        distributions.sample_normal_distribution,
        functools.partial(distributions.sample_normal_distribution, method="exact"),
        distributions.sample_triangular_distribution,
    ),
    distributions.sample_normal_distribution,
    BAD_CALLABLE,
)
NOISE = Arg(choices("variance", "std"), "variance", BAD_CHOICE)
DENSITY = Arg(choices("book", "pose", "xy"), "book", BAD_CHOICE)
METHOD = Arg(choices("sum12", "exact"), "sum12", BAD_CHOICE)
MODEL = Arg(constant("velocity"), "velocity", BAD_CHOICE)
DISTRIBUTION = Arg(choices(*plotting.DISTRIBUTIONS), "normal (12 uniforms)", BAD_CHOICE)
COUNT = Arg(lambda batch: st.integers(0, 30), 10, BAD_COUNT)
COUNT_POSITIVE = Arg(lambda batch: st.integers(1, 30), 10, [(0, ValueError), *BAD_COUNT])
NONNEG_INT = Arg(lambda batch: st.integers(0, 30), 0, BAD_COUNT)


def _seed_only(batch):
    return st.integers(0, 1000)


SEED = Arg(_seed_only, 0, BAD_RNG)  # plotting keeps an int seed (every frame redraws it)

# the live widgets' arguments (probrob.live: the ranges of their sliders)
LIVE_THETA = Arg(constant(0.0), 0.0, [(3.2, ValueError), *BAD_SCALAR])
LIVE_DISTRIBUTION = Arg(choices("normal", "triangular"), "normal", BAD_CHOICE)
LIVE_DENSITY = Arg(choices("xy", "pose", "book"), "xy", BAD_CHOICE)
LIVE_PARTICLES = Arg(lambda batch: st.integers(1, 30), 20, [(0, ValueError), *BAD_COUNT])
LIVE_GRID = Arg(lambda batch: st.integers(2, 12), 8, [(1, ValueError), *BAD_COUNT])


# --------------------------------------------------------------------------- row helpers


def _positive_variances_motion(kw) -> bool:
    """Finite is defined for "book": all α >= 1e-3 and every |v|, |ω| >= 1e-3."""
    if kw.get("density", "book") != "book":
        return False
    return bool(np.min(kw["alpha"]) >= 1e-3 and np.min(np.abs(kw["u_t"])) >= 1e-3)


def _hypothesis_moved_odometry(kw) -> bool:
    """Finite is defined for Table 5.5 as printed when all α >= 1e-3 and x_t moved >= 1 mm."""
    if kw.get("density", "book") != "book" or np.min(kw["alpha"]) < 1e-3:
        return False
    d = np.asarray(kw["x_t"])[..., :2] - np.asarray(kw["x_prev"])[..., :2]
    return bool(np.all(np.hypot(d[..., 0], d[..., 1]) >= 1e-3))


def _angles_in_range(result, kw):
    assert np.all((np.asarray(result) >= -PI) & (np.asarray(result) < PI))


def _deltas_sane(result, kw):
    rot1, trans, rot2 = result
    assert np.all(np.asarray(trans) >= 0)
    _angles_in_range(rot1, kw)
    _angles_in_range(rot2, kw)


# --------------------------------------------------------------------------- the table

API = [
    # probrob.angles
    Api(angles.wrap_angle, "map", theta=ANGLES, extra=_angles_in_range),
    Api(angles.angle_diff, "map", a=ANGLES, b=ANGLES, extra=_angles_in_range),
    Api(
        angles.circular_mean,
        "map",
        theta=Arg(
            lambda batch: hnp.arrays(float, st.integers(1, 6), elements=ANGLE),
            [0.1, 0.2],
            [*BAD_SCALAR, ([], ValueError)],
        ),
        extra=_angles_in_range,
    ),
    # probrob.distributions
    Api(
        distributions.prob_normal_distribution,
        "density",
        a=POINTS,
        b2=VARIANCES,
        finite_when=lambda kw: bool(np.all(np.asarray(kw["b2"]) > 1e-300)),
    ),
    Api(
        distributions.prob_triangular_distribution,
        "density",
        a=POINTS,
        b2=VARIANCES,
        finite_when=lambda kw: bool(np.all(np.asarray(kw["b2"]) > 1e-300)),
    ),
    Api(
        distributions.sample_normal_distribution,
        "sampler",
        b2=VARIANCES,
        size=SIZE,
        rng=RNG,
        method=METHOD,
    ),
    Api(distributions.sample_triangular_distribution, "sampler", b2=VARIANCES, size=SIZE, rng=RNG),
    # probrob.motion
    Api(motion.velocity_motion, "map", x_prev=POSES, u_t=VELOCITIES, dt=DT),
    Api(motion.velocity_motion_jacobians, "map", x_prev=POSES, u_t=VELOCITIES, dt=DT),
    Api(
        motion.motion_model_velocity,
        "density",
        x_t=POSES,
        u_t=VELOCITIES,
        x_prev=POSES,
        dt=DT,
        alpha=ALPHAS6,
        prob=PROB,
        noise=NOISE,
        density=DENSITY,
        finite_when=_positive_variances_motion,
        examples=80,
    ),
    Api(
        motion.sample_motion_model_velocity,
        "sampler",
        u_t=VELOCITIES,
        x_prev=POSES,
        dt=DT,
        alpha=ALPHAS6,
        sample=SAMPLE,
        noise=NOISE,
        size=SIZE,
        rng=RNG,
        trailing=(3,),
        examples=60,
    ),
    Api(
        motion.odometry_deltas,
        "map",
        xbar_prev=POSES,
        xbar_t=POSES,
        extra=_deltas_sane,
    ),
    Api(
        motion.apply_odometry_deltas,
        "map",
        x_prev=POSES,
        rot1=ANGLES,
        trans=POINTS,
        rot2=ANGLES,
    ),
    Api(
        motion.motion_model_odometry,
        "density",
        x_t=POSES,
        u_t=ODOMETRY,
        x_prev=POSES,
        alpha=ALPHAS4,
        prob=PROB,
        noise=NOISE,
        density=DENSITY,
        finite_when=_hypothesis_moved_odometry,
        examples=80,
    ),
    Api(
        motion.sample_motion_model_odometry,
        "sampler",
        u_t=ODOMETRY,
        x_prev=POSES,
        alpha=ALPHAS4,
        sample=SAMPLE,
        noise=NOISE,
        size=SIZE,
        rng=RNG,
        trailing=(3,),
        examples=60,
    ),
    # probrob.plotting (few examples: matplotlib is slow)
    Api(
        plotting.plot_distribution,
        "plot",
        prob=PROB,
        b2=Arg(lambda batch: floats([1e-6, 1.0], 1e-3, 1e3), 1.0, BAD_POSITIVE),
        bins=Arg(lambda batch: st.integers(1, 20), 10, [(0, ValueError), *BAD_COUNT]),
        examples=3,
    ),
    Api(plotting.plot_pose, "plot", pose=POSE, examples=3),
    Api(
        plotting.plot_samples,
        "plot",
        poses=Arg(
            lambda batch: hnp.arrays(float, (5, 3), elements=st.floats(-10, 10)),
            np.zeros((4, 3)),
            [(np.zeros(3), ValueError), (np.zeros((4, 4)), ValueError), *NOT_FINITE],
        ),
        examples=3,
    ),
    Api(
        plotting.motion_extent,
        "map",
        points=Arg(
            lambda batch: hnp.arrays(float, (5, 3), elements=st.floats(-1e3, 1e3)),
            np.zeros((4, 3)),
            [(np.zeros((0, 3)), ValueError), (np.zeros((4, 1)), ValueError), *NOT_FINITE],
        ),
    ),
    Api(
        plotting.motion_samples,
        "map",
        model=MODEL,
        u_t=Arg(lambda batch: VELOCITIES.valid(()), np.array([1.0, 0.5]), bad_vectors(2)),
        x_prev=POSE,
        alpha=ALPHAS6,
        n=COUNT,
        distribution=DISTRIBUTION,
        noise=NOISE,
        rng=SEED,
        examples=10,
    ),
    Api(
        plotting.plot_motion_model,
        "plot",
        model=MODEL,
        u_t=Arg(lambda batch: VELOCITIES.valid(()), np.array([1.0, 0.5]), bad_vectors(2)),
        x_prev=POSE,
        alpha=ALPHAS6,
        dt=DT,
        distribution=DISTRIBUTION,
        noise=NOISE,
        n_samples=COUNT,
        n_headings=NONNEG_INT,
        grid=Arg(constant(8), 8, [(1, ValueError), *BAD_COUNT]),
        rng=SEED,
        examples=3,
    ),
    # probrob.widgets (invalid rows; building the sliders is cheap, the players are not)
    Api(
        widgets.velocity_model_explorer,
        "widget",
        x_prev=POSE,
        v=Arg(constant(1.0), 1.0, [(2.5, ValueError), *BAD_SCALAR]),
        w=Arg(constant(0.5), 0.5, [(-2.5, ValueError), *BAD_SCALAR]),
        dt=Arg(constant(1.0), 1.0, [(0.0, ValueError), (5.0, ValueError), *BAD_SCALAR]),
        alpha=Arg(constant([0.02] * 6), [0.02] * 6, [([0.6] + [0.02] * 5, ValueError)]),
        distribution=DISTRIBUTION,
        noise=NOISE,
        n_samples=COUNT,
        rng=SEED,
        examples=2,
    ),
    Api(
        widgets.odometry_model_explorer,
        "widget",
        x_prev=POSE,
        rot1=Arg(constant(0.4), 0.4, [(3.2, ValueError), *BAD_SCALAR]),
        trans=Arg(constant(1.0), 1.0, [(-0.1, ValueError), *BAD_SCALAR]),
        rot2=Arg(constant(-0.3), -0.3, [(-3.2, ValueError), *BAD_SCALAR]),
        alpha=Arg(constant([0.05] * 4), [0.05] * 4, [([0.05, 0.9, 0.05, 0.05], ValueError)]),
        distribution=DISTRIBUTION,
        noise=NOISE,
        n_samples=COUNT,
        rng=SEED,
        examples=2,
    ),
    # the draws embedded in the live widgets (probrob.live)
    Api(live.standard_draws, "widget", n=COUNT_POSITIVE, rng=RNG, examples=3),
    Api(live.landmark_draws, "widget", n=COUNT_POSITIVE, rng=RNG, examples=3),
    Api(
        widgets.alpha_player,
        "widget",
        model=MODEL,
        index=Arg(constant(1), 1, [(0, ValueError), (7, ValueError), (1.5, ValueError)]),
        values=Arg(
            constant([0.0, 0.1]),
            [0.0, 0.1],
            [([], ValueError), ([-0.1], ValueError), *NOT_FINITE[:1], *NOT_NUMERIC[:2]],
        ),
        alpha=ALPHAS6,
        u_t=Arg(constant([1.0, 0.5]), [1.0, 0.5], bad_vectors(2)),
        skip_valid=True,
    ),
    # the book's figure style, the diagrams of Tables 5.1 / 5.5 and the generic player (i9).
    # use_book_style changes matplotlib's global settings: listed, never called here.
    Api(plotting.book_style, "widget", skip_valid=True),
    Api(plotting.use_book_style, "widget", skip_valid=True),
    Api(plotting.plot_velocity_geometry, "plot", x_prev=POSE, x_t=POSE, dt=DT, examples=5),
    Api(plotting.plot_odometry_deltas, "plot", xbar_prev=POSE, xbar_t=POSE, examples=5),
    Api(
        widgets.parameter_player,
        "widget",
        draw=Arg(constant(lambda ax, value: None), lambda ax, value: None, BAD_CALLABLE),
        values=Arg(constant([0.0, 1.0]), [0.0, 1.0], [([], ValueError)]),
        label=Arg(constant("x"), "x", [("", ValueError), (3, ValueError), (None, ValueError)]),
        skip_valid=True,
    ),
    # the live widgets (i10): every argument checked against its slider's range; a valid call
    # builds the HTML of a small widget (the JavaScript itself is tested in test_live_widgets)
    Api(
        widgets.velocity_model_live,
        "widget",
        v=Arg(constant(1.0), 1.0, [(2.5, ValueError), *BAD_SCALAR]),
        w=Arg(constant(0.8), 0.8, [(-2.5, ValueError), *BAD_SCALAR]),
        dt=Arg(constant(1.0), 1.0, [(0.0, ValueError), (5.0, ValueError), *BAD_SCALAR]),
        theta=LIVE_THETA,
        alpha=Arg(constant([0.02] * 6), [0.02] * 6, [([0.6] + [0.02] * 5, ValueError)]),
        distribution=LIVE_DISTRIBUTION,
        noise=NOISE,
        density=LIVE_DENSITY,
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.odometry_model_live,
        "widget",
        rot1=Arg(constant(0.6), 0.6, [(3.2, ValueError), *BAD_SCALAR]),
        trans=Arg(constant(1.0), 1.0, [(-0.1, ValueError), (3.5, ValueError), *BAD_SCALAR]),
        rot2=Arg(constant(-0.4), -0.4, [(-3.2, ValueError), *BAD_SCALAR]),
        theta=LIVE_THETA,
        alpha=Arg(constant([0.05] * 4), [0.05] * 4, [([0.05, 0.9, 0.05, 0.05], ValueError)]),
        distribution=LIVE_DISTRIBUTION,
        noise=NOISE,
        density=LIVE_DENSITY,
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.landmark_model_live,
        "widget",
        r=Arg(constant(2.0), 2.0, [(-0.1, ValueError), (6.0, ValueError), *BAD_SCALAR]),
        phi=Arg(constant(0.5), 0.5, [(3.2, ValueError), *BAD_SCALAR]),
        s=Arg(constant(1.0), 1.0, [(-1.0, ValueError), *BAD_SCALAR]),
        sigmas=Arg(
            constant([0.1, 0.05, 0.2]),
            [0.1, 0.05, 0.2],
            [
                ([0.1, 0.1], ValueError),
                ([1.5, 0.1, 0.1], ValueError),
                ([-0.1, 0.1, 0.1], ValueError),
                ([np.nan] * 3, ValueError),
                ([1j] * 3, TypeError),
                (None, ValueError),
            ],
        ),
        theta=LIVE_THETA,
        landmark=Arg(constant([0.0, 0.0, 1.0]), [0.0, 0.0, 1.0], bad_vectors(3)),
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.beam_model_live,
        "widget",
        z_star=Arg(constant(5.0), 5.0, [(-0.1, ValueError), (11.0, ValueError), *BAD_SCALAR]),
        weights=Arg(
            constant([0.7, 0.15, 0.05, 0.1]),
            [0.7, 0.15, 0.05, 0.1],
            [
                ([0.5] * 3, ValueError),
                ([1.5, 0.0, 0.0, 0.0], ValueError),
                ([np.nan] * 4, ValueError),
                ([1j] * 4, TypeError),
                (None, ValueError),
            ],
        ),
        sigma_hit=Arg(constant(0.2), 0.2, [(0.0, ValueError), (2.0, ValueError), *BAD_SCALAR]),
        lambda_short=Arg(constant(0.6), 0.6, [(0.0, ValueError), (9.0, ValueError)]),
        max_range=Arg(constant(10.0), 10.0, BAD_POSITIVE),
        grid=LIVE_GRID,
        examples=3,
    ),
    Api(
        widgets.distribution_live,
        "widget",
        b2=Arg(constant(1.0), 1.0, [(0.0, ValueError), (5.0, ValueError), *BAD_SCALAR]),
        distribution=LIVE_DISTRIBUTION,
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.live_widget,
        "widget",
        kernel=Arg(
            constant("velocity"),
            "velocity",
            [("ackermann", ValueError), (3, ValueError), (None, ValueError)],
        ),
        sliders=Arg(constant([]), [], []),
        title=Arg(constant("t"), "t", []),
        caption=Arg(constant("c"), "c", []),
        aria_label=Arg(constant("a"), "a", []),
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=2,
    ),
]


# --------------------------------------------------------------------------- kinematics, sensors,
# maps, filters, simulation, fitting and datasets (the modules of issues 1-8 that landed later)

# a 10 x 8 grid of 0.5 m cells with a wall border and one inner block; poses anywhere inside,
# the borders included (x = 0 and y = 0 exactly, and the last float below the far edge)
_OCC = np.zeros((8, 10), dtype=bool)
_OCC[0, :] = _OCC[-1, :] = _OCC[:, 0] = _OCC[:, -1] = True
_OCC[3:5, 4:6] = True
GRID_MAP = maps.OccupancyGrid(_OCC, 0.5)
BEAMS = np.array([-PI / 2, 0.0, PI / 4, PI])  # K = 4, one straight back (θ + π)
PARAMS = sensors.BeamModelParams(
    0.7, 0.1, 0.1, 0.1, sigma_hit=0.2, lambda_short=0.5, max_range=6.0
)
BEAM_PARAMS_ALL = [
    PARAMS,
    sensors.BeamModelParams(1.0, 0.0, 0.0, 0.0, sigma_hit=0.2, lambda_short=0.5, max_range=6.0),
    sensors.BeamModelParams(0.0, 0.0, 1.0, 0.0, sigma_hit=1e-3, lambda_short=10.0, max_range=6.0),
    sensors.BeamModelParams(0.0, 0.0, 0.0, 1.0, sigma_hit=5.0, lambda_short=1e-3, max_range=6.0),
]
GX = floats([0.0, 2.5, np.nextafter(5.0, 0)], 0.0, 4.999)
GY = floats([0.0, 1.9, np.nextafter(4.0, 0)], 0.0, 3.999)


def grid_poses_strategy(batch):
    return st.sampled_from([batch, ()]).flatmap(
        lambda b: st.lists(
            st.tuples(GX, GY, HEADING), min_size=int(np.prod(b)), max_size=int(np.prod(b))
        ).map(lambda rows, b=b: np.array(rows, dtype=float).reshape(b + (3,)))
    )


RANGE = floats([0.0, 1e-300, 0.2, 5.0, np.nextafter(6.0, 0), 6.0], 0.0, 6.0)
LANDMARKS = np.array([[2.0, 1.0, 0.0], [-1.0, 3.0, 1.0], [0.5, -2.0, 2.0], [4.0, 4.0, 3.0]])
N_LM = len(LANDMARKS)


def n_features(batch):
    """The number of features of a filter step, from the example's batch: 0 (empty), 1, 3, 2."""
    return {(): 0, (1,): 1, (4,): 3, (2, 3): 2}[batch]


FEATURE = st.tuples(
    floats([0.0, 1e-300, 1.0, 30.0], 0.0, 20.0), HEADING, st.sampled_from([0.0, 1.0, 2.0, 3.0])
)


def features_strategy(batch):
    k = n_features(batch)
    return st.lists(FEATURE, min_size=k, max_size=k).map(
        lambda rows: np.array(rows, dtype=float).reshape(-1, 3)
    )


def _nonnegative_range(f):
    """A feature's range is a distance: |r| (the sign of a drawn coordinate dropped)."""
    f = np.array(f, dtype=float)
    f[..., 0] = np.abs(f[..., 0])
    return f


def correspondences_strategy(batch):
    k = n_features(batch)
    return st.lists(st.integers(0, N_LM - 1), min_size=k, max_size=k).map(
        lambda c: np.array(c, dtype=int)
    )


_SPD = np.array([[0.2, 0.05, 0.01], [0.05, 0.1, 0.0], [0.01, 0.0, 0.05]])
COVARIANCE = Arg(
    choices(np.zeros((3, 3)), 1e-12 * np.eye(3), np.diag([0.1, 0.2, 0.05]), _SPD, 1e4 * np.eye(3)),
    np.diag([0.1, 0.1, 0.05]),
    [
        (-np.eye(3), ValueError),
        (np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), ValueError),
        (np.eye(2), ValueError),
        (np.full((3, 3), np.nan), ValueError),
        (np.eye(3) * 1j, TypeError),
        (None, ValueError),
    ],
)
COVARIANCE_ANY = Arg(  # covariance_ellipse and nees: (2, 2) too; the symmetric part is used
    COVARIANCE.valid, COVARIANCE.default, [COVARIANCE.invalid[0], *COVARIANCE.invalid[3:]]
)
COVARIANCE_PD = Arg(
    choices(1e-12 * np.eye(3), np.diag([0.1, 0.2, 0.05]), _SPD, 1e4 * np.eye(3)),
    COVARIANCE.default,
    [(np.zeros((3, 3)), ValueError), *COVARIANCE_ANY.invalid],
)
BAD_LANDMARK = [*bad_vectors(3)[:3], (np.zeros((4, 4)), ValueError), (None, ValueError)]
MU = Arg(single_pose_strategy, np.array([0.1, -0.2, 0.3]), bad_vectors(3)[:5])
CONTROL = Arg(
    lambda batch: st.tuples(SPEED, floats([0.0, -0.0, 1e-300, 0.5, -0.5], -2.0, 2.0)).map(
        np.array
    ),
    np.array([1.0, 0.2]),
    bad_vectors(2)[:5],
)
LM_MAP = Arg(
    constant(LANDMARKS),
    LANDMARKS,
    [
        (np.zeros((0, 3)), ValueError),
        (np.zeros((4, 4)), ValueError),
        (np.full((4, 3), np.nan), ValueError),
        (LANDMARKS * 1j, TypeError),
        (None, ValueError),
    ],
)
FEATURES = Arg(
    features_strategy,
    np.array([[2.0, 0.3, 0.0]]),
    [
        (np.zeros((1, 4)), ValueError),
        (np.array([[np.nan, 0.0, 0.0]]), ValueError),
        (np.array([[1j, 0.0, 0.0]]), TypeError),
        (None, ValueError),
    ],
)
CORRESPONDENCE = Arg(
    correspondences_strategy,
    np.array([0]),
    [(np.array([N_LM]), ValueError), (np.array([-1]), ValueError), (np.array([0.5]), ValueError)],
)
ALPHAS4_FILTER = Arg(
    lambda batch: st.lists(NONNEG, min_size=4, max_size=4), [0.05] * 4, bad_alphas(4)
)
SIGMAS = Arg(
    choices((0.1, 0.05, 0.2), (1e-3, 1e-3, 1e-3), (1.0, 0.5, 1.0)),
    (0.1, 0.05, 0.2),
    [((-0.1, 0.05, 0.2), ValueError), ((0.1,), ValueError), ((np.nan,) * 3, ValueError)],
)
SIGMAS_SAMPLE = Arg(
    choices((0.1, 0.05, 0.2), (0.0, 0.0, 0.0), (1e-3, 1e-3, 1e-3)),
    (0.1, 0.05, 0.2),
    [((-0.1, 0.05, 0.2), ValueError), ((0.1,), ValueError), ((np.nan,) * 3, ValueError)],
)
WHEELBASE = Arg(lambda batch: floats([1e-3, 0.3, 1.0, 1e3], 1e-3, 10.0), 0.5, BAD_POSITIVE[:2])
WHEEL = Arg(lambda batch: batched(batch, (), SPEED), 0.5, BAD_SCALAR)
STEER = Arg(
    lambda batch: batched(batch, (), floats([0.0, 1.0, -1.0, 1.5], -1.5, 1.5)), 0.2, BAD_SCALAR
)
WHEELS = Arg(lambda batch: batched(batch, (2,), SPEED), np.array([0.5, 0.4]), bad_vectors(2))
GRID_POSES = Arg(grid_poses_strategy, np.array([2.0, 1.0, 0.3]), bad_vectors(3)[:4])
RANGES = Arg(
    lambda batch: batched(batch, (len(BEAMS),), RANGE),
    np.full(len(BEAMS), 2.0),
    [(np.full(len(BEAMS), -1.0), ValueError), (np.full(len(BEAMS), np.nan), ValueError),
     (np.full(3, 2.0), ValueError), (np.full(len(BEAMS), 1j), TypeError), (None, ValueError)],
)  # fmt: skip
Z_SCALAR = Arg(lambda batch: batched(batch, (), RANGE), 2.0, [(-1.0, ValueError), *BAD_SCALAR])
Z_STAR = Arg(
    lambda batch: batched(batch, (), floats([0.0, 1e-300, 3.0, 6.0], 0.0, 6.0)),
    3.0,
    [(-1.0, ValueError), (7.0, ValueError), *BAD_SCALAR],
)
BEAM_PARAMS = Arg(
    choices(*BEAM_PARAMS_ALL), PARAMS, [(None, ValueError), ((0.7, 0.1, 0.1, 0.1), ValueError)]
)
GRID = Arg(constant(GRID_MAP), GRID_MAP, [(None, ValueError), (_OCC, ValueError)])
BEAM_ANGLES = Arg(constant(BEAMS), BEAMS, [(np.full(4, np.nan), ValueError), (None, ValueError)])
MAX_RANGE = Arg(lambda batch: floats([1e-3, 6.0, 100.0], 1e-3, 50.0), 6.0, BAD_POSITIVE)
RAY_METHOD = Arg(choices("hybrid", "dda", "march"), "hybrid", BAD_CHOICE)
TIMES = Arg(
    constant(np.linspace(0.0, 4.0, 9)),
    np.linspace(0.0, 4.0, 9),
    [(np.linspace(4.0, 0.0, 9), ValueError), (np.full(9, np.nan), ValueError), (None, ValueError)],
)
T_OUT = Arg(
    lambda batch: batched(batch, (), floats([0.0, 4.0, 2.0], 0.0, 4.0)),
    np.array([0.5, 1.5]),
    [(np.array([5.0]), ValueError), (np.array([np.nan]), ValueError), (None, ValueError)],
)
TRACK = Arg(
    constant(np.column_stack([np.linspace(0, 2, 9), np.zeros(9), np.linspace(-PI, PI, 9)])),
    np.column_stack([np.linspace(0, 2, 9), np.zeros(9), np.linspace(-PI, PI, 9)]),
    [(np.zeros((8, 3)), ValueError), (np.zeros((9, 2)), ValueError), (np.full((9, 3), np.nan), ValueError)],
)  # fmt: skip
COMMANDS9 = Arg(
    choices(np.zeros((9, 2)), np.column_stack([np.full(9, 0.5), np.zeros(9)]),
            np.column_stack([np.full(9, 0.5), np.full(9, 0.3)])),
    np.column_stack([np.full(9, 0.5), np.full(9, 0.3)]),
    [(np.zeros((8, 2)), ValueError), (np.zeros((9, 3)), ValueError), (np.full((9, 2), np.inf), ValueError)],
)  # fmt: skip
FIT_K = 6
PATH = Arg(
    constant(None),
    None,
    [(__file__, ValueError), ("/no/such/folder", datasets.DatasetNotFoundError), (3, ValueError)],
)


_X_PREV_K = np.column_stack([np.arange(FIT_K) * 0.3, np.zeros(FIT_K), np.linspace(-PI, PI, FIT_K)])
_U_K = np.column_stack([np.linspace(0, 1, FIT_K), np.array([0.0, 0.0, 0.3, -0.3, 1.0, 0.0])])
_X_T_K = motion.velocity_motion(_X_PREV_K, _U_K, 1.0) + 0.01 * np.sin(
    np.arange(FIT_K * 3)
).reshape(-1, 3)
_ODO_K = np.stack([_X_PREV_K, _X_T_K], axis=1)
_U_FIT = np.vstack([[0.1, 0.0], _U_K[1:]])  # the fits: no zero command (a point mass)
_X_T_FIT = motion.velocity_motion(_X_PREV_K, _U_FIT, 1.0) + (
    _X_T_K - motion.velocity_motion(_X_PREV_K, _U_K, 1.0)
)
X_T_FIT = Arg(constant(_X_T_FIT), _X_T_FIT, bad_vectors(3)[:4])
U_FIT = Arg(constant(_U_FIT), _U_FIT, bad_vectors(2)[:4])
X_PREV_K = Arg(constant(_X_PREV_K), _X_PREV_K, bad_vectors(3)[:4])
X_T_K = Arg(constant(_X_T_K), _X_T_K, bad_vectors(3)[:4])
U_K = Arg(constant(_U_K), _U_K, bad_vectors(2)[:4])
ODO_K = Arg(constant(_ODO_K), _ODO_K, ODOMETRY.invalid)
FIT_NOISE = Arg(choices("variance", "std"), "variance", BAD_CHOICE)
FIT_DENSITY = Arg(choices("book", "pose"), "book", BAD_CHOICE)


# A filter given a huge Σ and tiny σ cannot form S = HΣHᵀ + Q in double precision: it says so
FILTER_LIMIT = "from Sigma and sigmas|scales of Sigma and sigmas"


def _log_never_nan(result, kw):
    assert not np.isnan(np.asarray(result)).any()


def _fit_sane(result, kw):
    assert np.all(np.isfinite(result.alpha)) and np.all(result.alpha >= 0)


STEPS_K = Arg(lambda batch: hnp.arrays(float, n_features(batch), elements=SPEED), [0.5, 0.5], [])
TURNS_K = Arg(
    lambda batch: hnp.arrays(float, n_features(batch), elements=HEADING),
    [0.0, 0.1],
    [([np.nan, 0.0], ValueError), ([1j, 0.0], TypeError), (None, ValueError), ([0.0], ValueError)],
)


def _seeded(batch):
    return st.integers(0, 1000)


SEED_RNG = Arg(_seeded, 0, BAD_RNG)  # an int seed, so that two calls agree


API += [
    # probrob.kinematics (issue 1)
    Api(kinematics.arc_update, "map", x_prev=POSES, ds=WHEEL, dtheta=WHEEL),
    Api(kinematics.cir_pose_matrix, "map", x=POSES),
    # the radius is ±inf on a straight line (documented): "map" rows with finite=False only
    # require "never NaN"
    Api(kinematics.cir_radius_angle, "map", u=WHEELS, wheelbase=WHEELBASE, finite=False),
    Api(kinematics.cir_state_function, "map", x_prev=POSES, u=WHEELS, wheelbase=WHEELBASE),
    Api(kinematics.cir_state_jacobians, "map", x_prev=POSES, u=WHEELS, wheelbase=WHEELBASE),
    Api(kinematics.cir_step_transform, "map", u=WHEELS, wheelbase=WHEELBASE),
    Api(
        kinematics.dead_reckon,
        "map",
        x0=POSE,
        ds=STEPS_K,
        dtheta=TURNS_K,
        method=Arg(choices("arc", "midpoint", "euler"), "arc", BAD_CHOICE),
    ),
    Api(
        kinematics.diff_drive_odometry,
        "map",
        ds_left=WHEEL,
        ds_right=WHEEL,
        wheelbase=WHEELBASE,
        finite=False,
    ),
    Api(
        kinematics.tricycle_odometry,
        "map",
        d_front=WHEEL,
        steering_angle=STEER,
        wheelbase=WHEELBASE,
    ),
    # probrob.sensors: the landmark model (issue 4)
    Api(
        sensors.landmark_measurement,
        "map",
        x=POSES,
        m=Arg(lambda batch: batched(batch, (3,), COORD), LANDMARKS[0], BAD_LANDMARK),
    ),
    Api(
        sensors.landmark_measurement_jacobian,
        "map",
        x=POSES,
        m=Arg(lambda batch: batched(batch, (3,), COORD), LANDMARKS[0], BAD_LANDMARK),
        raises="coincides with a landmark",  # documented: the bearing has no Jacobian there
    ),
    Api(
        sensors.landmark_model_known_correspondence,
        "density",
        f=Arg(  # issue 23, item 29 (class C): no sensor measures a negative range
            lambda batch: batched(batch, (3,), COORD).map(_nonnegative_range),
            np.array([2.0, 0.3, 0.0]),
            [*bad_vectors(3)[:5], (np.array([-1e-300, 0.3, 0.0]), ValueError)],
        ),
        c=Arg(
            lambda batch: st.integers(0, N_LM - 1),
            0,
            [(N_LM, ValueError), (-1, ValueError), (0.5, ValueError), (None, ValueError)],
        ),
        x=POSES,
        m=LM_MAP,
        sigmas=SIGMAS_SAMPLE,
        check_batch_shape=False,
        finite_when=lambda kw: min(kw["sigmas"]) > 0,
    ),
    Api(
        sensors.sample_landmark_model_known_correspondence,
        "sampler",
        f=Arg(
            constant(np.array([2.0, 0.3, 0.0])),
            np.array([2.0, 0.3, 0.0]),
            [*BAD_LANDMARK, (np.array([-2.0, 0.3, 0.0]), ValueError)],  # a negative range
        ),
        c=Arg(
            constant(1),
            1,
            [(N_LM, ValueError), (-1, ValueError), (0.5, ValueError), (1e300, ValueError)],
        ),
        m=LM_MAP,
        sigmas=SIGMAS_SAMPLE,
        size=SIZE,
        rng=RNG,
        trailing=(3,),
    ),
    # probrob.sensors: the range-finder models (issue 6) and probrob.maps
    Api(
        sensors.beam_mixture,
        "density",
        z=Z_SCALAR,
        z_star=Z_STAR,
        params=BEAM_PARAMS,
        check_batch_shape=False,
    ),
    Api(
        sensors.beam_model_components,
        "density",
        z=Z_SCALAR,
        z_star=Z_STAR,
        params=BEAM_PARAMS,
        check_batch_shape=False,
    ),
    Api(
        sensors.beam_range_finder_model,
        "density",
        z=RANGES,
        x=GRID_POSES,
        grid=GRID,
        beam_angles=BEAM_ANGLES,
        params=BEAM_PARAMS,
        method=RAY_METHOD,
        check_batch_shape=False,
        examples=20,
    ),
    Api(
        sensors.likelihood_field_range_finder_model,
        "density",
        z=RANGES,
        x=GRID_POSES,
        grid=GRID,
        beam_angles=BEAM_ANGLES,
        params=BEAM_PARAMS,
        sensor_offset=Arg(
            choices((0.0, 0.0), (0.1, -0.05)),
            (0.0, 0.0),
            [((np.nan, 0.0), ValueError), ((0.0,), ValueError)],
        ),
        check_batch_shape=False,
        examples=20,
    ),
    # the table holds log densities: -inf far from every wall when z_rand = 0
    Api(
        sensors.likelihood_field_table,
        "map",
        grid=GRID,
        params=BEAM_PARAMS,
        examples=5,
        finite=False,
    ),
    Api(
        sensors.sample_beam_mixture,
        "sampler",
        z_star=Arg(constant(3.0), 3.0, Z_STAR.invalid),
        params=BEAM_PARAMS,
        size=SIZE,
        rng=RNG,
    ),
    # EM is slow (up to 500 iterations): few examples, on 200 draws from a known mixture
    Api(
        sensors.learn_intrinsic_parameters,
        "map",
        z=Arg(
            constant(sensors.sample_beam_mixture(3.0, PARAMS, size=200, rng=1)),
            sensors.sample_beam_mixture(3.0, PARAMS, size=200, rng=1),
            [(np.array([np.nan]), ValueError), (np.array([-1.0]), ValueError), (None, ValueError)],
        ),
        z_star=Arg(constant(3.0), 3.0, Z_STAR.invalid[:4]),
        max_range=Arg(constant(6.0), 6.0, BAD_POSITIVE),
        e_step=Arg(choices("weighted", "deck"), "weighted", BAD_CHOICE),
        m_step=Arg(choices("exact", "book"), "exact", BAD_CHOICE),
        examples=4,
    ),
    Api(
        maps.ray_cast,
        "map",
        grid=GRID,
        poses=GRID_POSES,
        beam_angles=BEAM_ANGLES,
        max_range=MAX_RANGE,
        method=RAY_METHOD,
        examples=20,
    ),
    # probrob.localization (issue 7): empty feature sets (K = 0) come with batch ()
    Api(
        evaluation.chi2_quantile,
        "map",
        p=Arg(
            lambda batch: floats([1e-12, 0.5, 0.95, 1 - 1e-12], 1e-6, 0.999999),
            0.95,
            [(0.0, ValueError), (1.0, ValueError), *BAD_SCALAR],
        ),
        dof=Arg(lambda batch: st.integers(1, 6), 2, [(0, ValueError), *BAD_COUNT]),
    ),
    Api(
        evaluation.covariance_ellipse,
        "map",
        mu=Arg(MU.valid, MU.default, BAD_LANDMARK),
        Sigma=COVARIANCE_ANY,
        p=Arg(
            lambda batch: floats([0.5, 0.95], 0.01, 0.99),
            0.95,
            [(1.0, ValueError), (None, ValueError)],
        ),
        n=COUNT_POSITIVE,
    ),
    Api(
        localization.ekf_localization_known_correspondences,
        "map",
        raises=FILTER_LIMIT,
        mu=MU,
        Sigma=COVARIANCE,
        u=CONTROL,
        z=FEATURES,
        c=CORRESPONDENCE,
        m=LM_MAP,
        dt=DT,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS,
        finite=False,
    ),
    Api(
        localization.ekf_localization,
        "map",
        raises=FILTER_LIMIT,
        mu=MU,
        Sigma=COVARIANCE,
        u=CONTROL,
        z=FEATURES,
        m=LM_MAP,
        dt=DT,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS,
        gate=Arg(choices(None, 0.99, 1e-9), None, [(-1.0, ValueError), (np.nan, ValueError)]),
    ),
    Api(
        localization.ukf_localization,
        "map",
        raises=FILTER_LIMIT,
        mu=MU,
        Sigma=COVARIANCE,
        u=CONTROL,
        z=FEATURES,
        c=CORRESPONDENCE,
        m=LM_MAP,
        dt=DT,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS,
        finite=False,
    ),
    Api(
        localization.ukf_localization_ml,
        "map",
        raises=FILTER_LIMIT,
        mu=MU,
        Sigma=COVARIANCE,
        u=CONTROL,
        z=FEATURES,
        m=LM_MAP,
        dt=DT,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS,
    ),
    Api(
        localization.ekf_predict_segment,
        "map",
        mu=MU,
        Sigma=COVARIANCE,
        u=Arg(
            lambda batch: hnp.arrays(float, (max(n_features(batch), 1), 2), elements=SPEED),
            np.array([[1.0, 0.2]]),
            bad_vectors(2)[:4],
        ),
        dt=DT,
        alpha=ALPHAS4_FILTER,
    ),
    # NEES needs Σ⁻¹: positive definite covariances only (a singular one is a ValueError)
    Api(evaluation.nees, "map", x_true=POSE, mu=MU, Sigma=COVARIANCE_PD),
    Api(
        localization.ukf_weights,
        "map",
        n=Arg(lambda batch: st.integers(1, 6), 3, [(0, ValueError), *BAD_COUNT]),
        ukf_alpha=Arg(
            lambda batch: floats([1e-3, 1.0], 1e-3, 1.0), 1.0, [(0.0, ValueError), *BAD_SCALAR]
        ),
        beta=Arg(lambda batch: floats([0.0, 2.0], 0.0, 3.0), 2.0, BAD_SCALAR),
        kappa=Arg(lambda batch: floats([0.0, 1.0], 0.0, 3.0), 0.0, BAD_SCALAR),
    ),
]

_SIM = simulation.simulate_run(
    np.zeros(3),
    simulation.loop_controls(8, 0.5),
    0.5,
    LANDMARKS,
    [0.01] * 4,
    (0.1, 0.05, 0.0),
    max_range=6.0,
    rng=3,
)
API += [
    Api(
        localization.run_filter,
        "map",
        raises=FILTER_LIMIT,
        nan_fields=("log_pz",),  # documented: NaN for the ML filters
        steps=Arg(constant(_SIM.steps), _SIM.steps, [(None, ValueError), (3, ValueError)]),
        mu0=MU,
        Sigma0=COVARIANCE,
        m=LM_MAP,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS,
        method=Arg(choices("ekf", "ekf_ml", "ukf", "ukf_ml"), "ekf", BAD_CHOICE),
        signatures=Arg(choices(True, False), True, BAD_FLAG),
        examples=8,
        finite=False,
    ),
    Api(
        fitting.fit_measurement_noise,
        "map",
        z=Arg(
            constant(np.array([[2.0, 0.3, 0.0], [1.0, -0.2, 1.0], [3.0, 3.0, 2.0]])),
            np.array([[2.0, 0.3, 0.0], [1.0, -0.2, 1.0], [3.0, 3.0, 2.0]]),
            [(np.zeros((3, 4)), ValueError), (np.full((3, 3), np.nan), ValueError)],
        ),
        c=Arg(
            constant(np.array([0, 1, 2])),
            np.array([0, 1, 2]),
            [(np.array([0, 1]), ValueError), (np.array([0, 1, 9]), ValueError)],
        ),
        poses=Arg(
            constant(_X_PREV_K[:3]),
            _X_PREV_K[:3],
            [(np.zeros((2, 3)), ValueError), (np.full((3, 3), np.nan), ValueError)],
        ),
        m=LM_MAP,
        examples=3,
    ),
    Api(
        fitting.fit_motion_noise,
        "map",
        nan_fields=("nees",),  # documented: NaN for windows without motion
        u=Arg(constant(_U_K), _U_K, [(np.zeros((FIT_K, 3)), ValueError)]),
        dt=Arg(
            constant(np.ones(FIT_K)),
            np.ones(FIT_K),
            [(np.zeros(FIT_K), ValueError), (np.ones(2), ValueError)],
        ),
        poses=Arg(
            constant(np.vstack([_X_PREV_K, _X_T_K[-1]])),
            np.vstack([_X_PREV_K, _X_T_K[-1]]),
            [(_X_PREV_K, ValueError)],
        ),
        window=Arg(lambda batch: floats([1.0, 2.0, 3.0], 1.0, 3.0), 2.0, BAD_POSITIVE),
        examples=5,
        finite=False,
    ),
    # probrob.simulation (issue 7)
    Api(
        simulation.grid_landmarks,
        "map",
        nx=COUNT_POSITIVE,
        ny=COUNT_POSITIVE,
        spacing=Arg(lambda batch: floats([1e-3, 1.0], 1e-3, 5.0), 1.0, BAD_POSITIVE[:2]),
        origin=Arg(
            choices((0.0, 0.0), (-1.0, 2.0)),
            (0.0, 0.0),
            [((np.nan, 0.0), ValueError), ((0.0,), ValueError)],
        ),
    ),
    Api(
        simulation.loop_controls,
        "map",
        T=Arg(lambda batch: st.integers(0, 30), 10, [(-1, ValueError), (2.5, ValueError)]),
        dt=DT,
        v=Arg(lambda batch: SPEED, 0.5, BAD_SCALAR),
        radius=Arg(
            lambda batch: floats([np.inf, 1e-3, 4.0, -4.0], 0.1, 10.0),
            4.0,
            [(0.0, ValueError), (np.nan, ValueError), (None, ValueError)],
        ),
        wiggle=Arg(lambda batch: floats([0.0, 0.3], -1.0, 1.0), 0.0, BAD_SCALAR),
        period=Arg(choices(None, 5.0), None, [(0.0, ValueError), (np.nan, ValueError)]),
    ),
    Api(
        simulation.random_landmarks,
        "map",
        n=COUNT_POSITIVE,
        bounds=Arg(
            choices((0.0, 10.0, 0.0, 5.0), (-1.0, 1.0, -1.0, 1.0)),
            (0.0, 10.0, 0.0, 5.0),
            [
                ((1.0, 0.0, 0.0, 1.0), ValueError),
                ((0.0, 1.0), ValueError),
                ((0.0, np.inf, 0.0, 1.0), ValueError),
            ],
        ),
        min_distance=Arg(
            choices(0.0, 0.01), 0.0, [(-1.0, ValueError), (np.nan, ValueError), (1e3, ValueError)]
        ),
        rng=SEED_RNG,
    ),
    Api(
        simulation.simulate_run,
        "map",
        x0=MU,
        controls=Arg(
            choices(
                np.zeros((5, 2)),
                simulation.loop_controls(5, 0.5),
                simulation.loop_controls(5, 0.5, radius=np.inf),
            ),
            simulation.loop_controls(5, 0.5),
            bad_vectors(2)[:4],
        ),
        dt=DT,
        m=LM_MAP,
        alpha=ALPHAS4_FILTER,
        sigmas=SIGMAS_SAMPLE,
        max_range=Arg(choices(np.inf, 3.0), np.inf, [(0.0, ValueError), (np.nan, ValueError)]),
        fov=Arg(choices(PI, 0.5), PI, [(-0.1, ValueError), (np.nan, ValueError)]),
        rng=SEED_RNG,
        examples=10,
    ),
    # probrob.fitting (issue 8); the alpha fits run scipy.optimize: few examples
    Api(fitting.frame_errors, "map", reference=POSES, poses=POSES),
    Api(
        fitting.integrate_commands,
        "map",
        t=TIMES,
        u=COMMANDS9,
        x0=MU,
        t_out=Arg(lambda batch: st.one_of(st.none(), T_OUT.valid(batch)), None, T_OUT.invalid[:2]),
    ),
    Api(fitting.interpolate_poses, "map", t=TIMES, poses=TRACK, t_out=T_OUT),
    Api(
        fitting.motion_windows,
        "map",
        command_t=TIMES,
        commands=COMMANDS9,
        truth_t=TIMES,
        truth=TRACK,
        dt=Arg(choices(0.5, 1.0, 2.0), 1.0, BAD_POSITIVE),
        stride=Arg(choices(None, 0.5, 1.0), None, [(0.0, ValueError), (np.nan, ValueError)]),
        finite=False,
    ),
    Api(
        fitting.velocity_log_likelihood,
        "map",
        x_t=X_T_K,
        u_t=U_K,
        x_prev=X_PREV_K,
        dt=DT,
        alpha=ALPHAS6,
        noise=FIT_NOISE,
        density=FIT_DENSITY,
        finite=False,
        extra=_log_never_nan,
    ),
    Api(
        fitting.odometry_log_likelihood,
        "map",
        x_t=X_T_K,
        u_t=ODO_K,
        x_prev=X_PREV_K,
        alpha=ALPHAS4,
        noise=FIT_NOISE,
        density=FIT_DENSITY,
        finite=False,
        extra=_log_never_nan,
    ),
    Api(
        fitting.fit_velocity_alpha,
        "map",
        nan_fields=("stderr",),  # documented: NaN for an alpha at its bound
        x_t=X_T_FIT,
        u_t=U_FIT,
        x_prev=X_PREV_K,
        dt=DT,
        noise=FIT_NOISE,
        density=FIT_DENSITY,
        extra=_fit_sane,
        examples=2,
        finite=False,
    ),
    Api(
        fitting.fit_odometry_alpha,
        "map",
        nan_fields=("stderr",),  # documented: NaN for an alpha at its bound
        x_t=X_T_K,
        u_t=ODO_K,
        x_prev=X_PREV_K,
        noise=FIT_NOISE,
        density=FIT_DENSITY,
        extra=_fit_sane,
        examples=2,
        finite=False,
    ),
    # probrob.datasets: loading is slow and needs ../shared/data; only the invalid rows here
    # (tests/test_datasets.py loads each dataset)
    Api(datasets.load_mrclam, "map", path=PATH, skip_valid=True),
    Api(datasets.load_intel_lab, "map", path=PATH, skip_valid=True),
    Api(
        datasets.load_lnpr_wall,
        "map",
        distance_mm=Arg(
            constant(200),
            200,
            [
                (300, ValueError),
                (200.5, ValueError),
                ("200", ValueError),
                (None, ValueError),
                (True, ValueError),
            ],
        ),
        path=PATH,
        skip_valid=True,
    ),
]


# probrob.mcl (Monte Carlo localization): particle sets inside GRID_MAP, odometry pairs, scans
def _particle_sets(batch):
    n = max(1, int(np.prod(batch)))
    return st.lists(st.tuples(GX, GY, HEADING), min_size=n, max_size=n).map(
        lambda rows: np.array(rows, dtype=float)
    )


def _weight_vectors(batch):
    n = max(1, int(np.prod(batch)))
    return (
        st.lists(floats([0.0, 1e-300, 1.0, 1e300], 0.0, 1e300), min_size=n, max_size=n)
        .filter(lambda w: sum(w) > 0)
        .map(np.array)
    )


PARTICLES = Arg(
    _particle_sets,
    np.array([[2.0, 1.0, 0.3], [3.0, 2.5, -1.0]]),
    [
        (np.zeros((0, 3)), ValueError),
        (np.zeros((2, 2)), ValueError),
        (np.full((2, 3), np.nan), ValueError),
        (np.zeros((2, 3)) * 1j, TypeError),
        (None, ValueError),
    ],
)
MCL_ODOMETRY = Arg(
    constant(np.array([[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]])),
    np.array([[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]]),
    [(np.zeros(3), ValueError), (np.full((2, 3), np.inf), ValueError), (None, ValueError)],
)
SCAN = Arg(
    lambda batch: st.lists(RANGE, min_size=len(BEAMS), max_size=len(BEAMS)).map(np.array),
    np.full(len(BEAMS), 2.0),
    [
        (np.full(len(BEAMS), -1.0), ValueError),
        (np.full(3, 2.0), ValueError),
        (np.full(len(BEAMS), np.nan), ValueError),
        (None, ValueError),
    ],
)
MCL_SENSOR = Arg(choices("likelihood_field", "beam"), "likelihood_field", BAD_CHOICE)
EXPONENT = Arg(
    lambda batch: floats([1e-3, 0.5, 1.0], 1e-3, 1.0),
    1.0,
    [(0.0, ValueError), (1.5, ValueError), *BAD_SCALAR],
)
WEIGHTS = Arg(
    _weight_vectors,
    np.array([0.2, 0.8]),
    [
        (np.array([0.0, 0.0]), ValueError),
        (np.array([0.5, -0.1]), ValueError),
        (np.array([0.5, np.nan]), ValueError),
        (np.zeros((2, 2)), ValueError),
        (None, ValueError),
    ],
)
AVERAGE = Arg(lambda batch: floats([0.0, 1e-30, 1.0, 1e30], 0.0, 1e30), 0.0, BAD_VARIANCE)
_MCL_STEP = dict(
    particles=PARTICLES,
    u=MCL_ODOMETRY,
    z=SCAN,
    grid=GRID,
    beam_angles=BEAM_ANGLES,
    alpha=ALPHAS4,
    params=BEAM_PARAMS,
    sensor=MCL_SENSOR,
    exponent=EXPONENT,
    rng=SEED,
)
API += [
    Api(
        mcl.low_variance_sampler,
        "map",
        weights=WEIGHTS,
        size=Arg(
            lambda batch: st.one_of(st.just(None), st.integers(1, 30)),
            None,
            [(0, ValueError), *BAD_COUNT],
        ),
        rng=SEED,
    ),
    Api(
        mcl.effective_sample_size,
        "map",
        weights=WEIGHTS,
        log=Arg(constant(False), False, BAD_FLAG),
    ),
    Api(mcl.uniform_particles, "map", grid=GRID, n=COUNT_POSITIVE, rng=SEED),
    Api(
        mcl.kld_sample_size,
        "map",
        k=Arg(lambda batch: st.integers(2, 10**6), 10, [(1, ValueError), *BAD_COUNT]),
        epsilon=Arg(lambda batch: floats([1e-3, 0.05, 1.0], 1e-3, 1.0), 0.05, BAD_POSITIVE),
        delta=Arg(
            lambda batch: floats([1e-9, 0.01, 0.16, 0.49], 1e-9, 0.49),
            0.01,
            [(0.0, ValueError), (0.5, ValueError), (0.99, ValueError), *BAD_SCALAR],
        ),
    ),
    Api(
        mcl.measurement_log_weights,
        "map",
        finite=False,  # a particle off the map has log-weight -inf (none is drawn here)
        **{k: v for k, v in _MCL_STEP.items() if k not in ("u", "alpha", "rng")},
        examples=20,
    ),
    Api(mcl.mcl, "map", **_MCL_STEP, examples=20),
    Api(
        mcl.selective_mcl,
        "map",
        **_MCL_STEP,
        weights=Arg(constant(None), None, [(np.array([1.0, -1.0]), ValueError)]),
        threshold=Arg(
            lambda batch: floats([0.0, 0.5, 1.0], 0.0, 1.0),
            0.5,
            [(-0.1, ValueError), (1.5, ValueError), *BAD_SCALAR],
        ),
        examples=20,
    ),
    Api(
        mcl.augmented_mcl,
        "map",
        **_MCL_STEP,
        w_slow=AVERAGE,
        w_fast=AVERAGE,
        examples=20,
    ),
    Api(
        mcl.kld_sampling_mcl,
        "map",
        **_MCL_STEP,
        n_min=COUNT_POSITIVE,
        examples=20,
    ),
    Api(
        mcl.estimate_pose,
        "map",
        particles=PARTICLES,
        radius=Arg(lambda batch: floats([0.01, 0.5, 10.0], 0.01, 10.0), 0.5, BAD_POSITIVE),
        heading_bins=Arg(
            choices(9, 12, 36, 2**20),
            12,
            [(8, ValueError), (2**20 + 1, ValueError), *BAD_COUNT],
        ),
    ),
    Api(  # issue 23, item 29 (class D): bins far from the origin, in int64 without wrapping
        mcl.estimate_pose,
        "map",
        particles=Arg(
            lambda batch: _particle_sets(batch).map(lambda x: x * [1e11, -1e11, 1.0]),
            np.array([[2e11, 1e11, 0.3], [-3e11, 2.5e11, -1.0]]),
            [(np.array([[1e300, 0.0, 0.0]]), ValueError)],  # 2**52 bins or more: refused
        ),
        radius=Arg(lambda batch: floats([1e-3, 0.5, 1e6], 1e-3, 1e6), 0.5, []),
        extra=lambda est, kw: np.testing.assert_array_less(np.abs(np.asarray(est.pose[:2])), 1e12),
    ),
    Api(
        mcl.run_mcl,
        "map",
        particles=PARTICLES,
        odometry=Arg(
            constant(np.array([[[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]]] * 2)),
            np.array([[[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]]] * 2),
            [(np.zeros((2, 3)), ValueError), (None, ValueError)],
        ),
        scans=Arg(
            constant(np.full((2, len(BEAMS)), 2.0)),
            np.full((2, len(BEAMS)), 2.0),
            [(np.full((3, len(BEAMS)), 2.0), ValueError), (None, ValueError)],
        ),
        grid=GRID,
        beam_angles=BEAM_ANGLES,
        alpha=ALPHAS4,
        params=BEAM_PARAMS,
        method=Arg(choices("mcl", "augmented", "kld", "selective"), "mcl", BAD_CHOICE),
        rng=SEED,
        skip_valid=True,  # its record holds wall-clock times; tests/test_mcl.py runs it
    ),
    Api(
        plotting.plot_occupancy_grid,
        "plot",
        grid=GRID,
        unexplored=Arg(choices(True, False), True, BAD_FLAG),
        examples=5,
    ),
    Api(plotting.plot_particles, "plot", particles=PARTICLES, examples=5),
    # the live particle filter (probrob.live.particle_filter_live, issue 16 item 6): every
    # argument checked against its slider's range; a valid call builds the HTML of a two-step
    # widget on the small map (its JavaScript is held to probrob.mcl in tests/test_live_mcl.py)
    Api(live.particle_filter_draws, "widget", n_max=COUNT_POSITIVE, steps=COUNT_POSITIVE, rng=RNG),
    Api(
        widgets.particle_filter_live,
        "widget",
        odometry=Arg(
            constant(np.array([[[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]]] * 2)),
            np.array([[[0.0, 0.0, 0.0], [0.2, 0.05, 0.1]]] * 2),
            [(np.zeros((2, 3)), ValueError), (np.full((2, 2, 3), np.nan), ValueError)],
        ),
        scans=Arg(
            constant(np.full((2, len(BEAMS)), 2.0)),
            np.full((2, len(BEAMS)), 2.0),
            [
                (np.full((3, len(BEAMS)), 2.0), ValueError),
                (np.full((2, len(BEAMS)), -1.0), ValueError),
                (None, ValueError),
            ],
        ),
        grid=GRID,
        beam_angles=BEAM_ANGLES,
        alpha=Arg(
            constant([0.05] * 4),
            [0.05] * 4,
            [([0.05, 0.9, 0.05, 0.05], ValueError), ([0.05] * 3, ValueError)],
        ),
        params=Arg(constant(PARAMS), PARAMS, [(None, ValueError), ((0.7, 0.1, 0.1), ValueError)]),
        truth=Arg(
            constant(np.array([[2.0, 1.0, 0.3]] * 3)),
            np.array([[2.0, 1.0, 0.3]] * 3),
            [(np.zeros((2, 3)), ValueError), (np.full((3, 3), np.nan), ValueError)],
        ),
        start=Arg(choices("known", "global"), "known", BAD_CHOICE),
        n_particles=Arg(choices(100, 200), 100, [(50, ValueError), *BAD_COUNT]),
        n_max=Arg(constant(200), 200, [(150, ValueError), (6000, ValueError), *BAD_COUNT]),
        beams=Arg(
            lambda batch: st.integers(1, len(BEAMS)),
            2,
            [(0, ValueError), (len(BEAMS) + 1, ValueError), *BAD_COUNT],
        ),
        exponent=Arg(constant(1.0), 1.0, [(0.0, ValueError), (1.5, ValueError), *BAD_SCALAR]),
        step=Arg(lambda batch: st.integers(0, 2), 0, [(3, ValueError), *BAD_COUNT]),
        view=Arg(choices("map", "robot"), "map", BAD_CHOICE),
        rng=SEED,
        examples=3,
    ),
    Api(
        mcl.occupied_bins,
        "map",
        particles=PARTICLES,
        bin_size=Arg(
            constant((0.5, 0.5, np.pi / 18)),
            (0.5, 0.5, np.pi / 18),
            [((0.5, 0.0, 0.1), ValueError), ((0.5, 0.5), ValueError), (None, ValueError)],
        ),
    ),
    Api(
        datasets.read_carmen_log,
        "map",
        path=Arg(
            constant(None), None, [(None, ValueError), ("/nonexistent/log", FileNotFoundError)]
        ),
        skip_valid=True,
    ),
]

# the live widgets of issue 17: the Turkish lecture's two noise forms side by side and the CIR
# report's step (probrob.live; their JavaScript is tested in test_live_widgets_tr_cir)
LIVE_PAIRING = Arg(choices("squared", "same"), "squared", BAD_CHOICE)
LIVE_ARC = Arg(
    lambda batch: floats([-1.0, 0.0, 0.3, 0.6, 1.5], -1.0, 1.5),
    0.6,
    [(-1.5, ValueError), (2.0, ValueError), *BAD_SCALAR],
)
API += [
    Api(
        widgets.velocity_noise_forms_live,
        "widget",
        v=Arg(constant(1.0), 1.0, [(2.5, ValueError), *BAD_SCALAR]),
        w=Arg(constant(0.0), 0.0, [(-2.5, ValueError), *BAD_SCALAR]),
        dt=Arg(constant(1.0), 1.0, [(0.0, ValueError), (5.0, ValueError), *BAD_SCALAR]),
        theta=LIVE_THETA,
        alpha=Arg(constant([0.1] * 6), [0.1] * 6, [([0.6] + [0.1] * 5, ValueError)]),
        pairing=LIVE_PAIRING,
        distribution=LIVE_DISTRIBUTION,
        density=LIVE_DENSITY,
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.odometry_noise_forms_live,
        "widget",
        rot1=Arg(constant(0.6), 0.6, [(3.2, ValueError), *BAD_SCALAR]),
        trans=Arg(constant(0.0), 0.0, [(-0.1, ValueError), (3.5, ValueError), *BAD_SCALAR]),
        rot2=Arg(constant(-0.4), -0.4, [(-3.2, ValueError), *BAD_SCALAR]),
        theta=LIVE_THETA,
        alpha=Arg(constant([0.2] * 4), [0.2] * 4, [([0.2, 0.9, 0.2, 0.2], ValueError)]),
        pairing=LIVE_PAIRING,
        distribution=LIVE_DISTRIBUTION,
        density=LIVE_DENSITY,
        n_particles=LIVE_PARTICLES,
        grid=LIVE_GRID,
        rng=SEED,
        examples=3,
    ),
    Api(
        widgets.cir_step_live,
        "widget",
        s_sx=LIVE_ARC,
        s_dx=LIVE_ARC,
        wheelbase=Arg(
            lambda batch: floats([0.1, 0.4, 1.0], 0.1, 1.0),
            0.4,
            [(0.05, ValueError), (1.5, ValueError), *BAD_POSITIVE],
        ),
        theta=Arg(
            lambda batch: floats([0.0, -3.14, 3.14], -3.14, 3.14),
            0.0,
            [(3.2, ValueError), *BAD_SCALAR],
        ),
        examples=5,
    ),
]

# the live EKF step of Trabalho 5 (issue 17; its JavaScript is tested in test_live_widgets_t5)
API += [
    Api(
        widgets.ekf_step_live,
        "widget",
        mu=Arg(
            lambda batch: st.tuples(
                floats([-3.0, 0.0, 3.0], -3.0, 3.0),
                floats([-3.0, 0.0, 3.0], -3.0, 3.0),
                floats([-3.14, 0.0, 3.14], -3.14, 3.14),
            ),
            (0.0, 0.0, 0.0),
            [((4.0, 0.0, 0.0), ValueError), ((0.0, 0.0, 3.2), ValueError), *bad_vectors(3)],
        ),
        prior_std=Arg(
            lambda batch: st.tuples(*[floats([0.01, 0.2, 1.0], 0.01, 1.0)] * 3),
            (0.15, 0.3, 0.1),
            [((0.0, 0.1, 0.1), ValueError), ((0.1, 0.1, 2.0), ValueError), *bad_vectors(3)],
        ),
        u=Arg(
            lambda batch: st.tuples(
                floats([-2.0, 0.0, 2.0], -2.0, 2.0), floats([-2.0, 0.0, 2.0], -2.0, 2.0)
            ),
            (1.0, 0.4),
            [((3.0, 0.0), ValueError), *bad_vectors(2)],
        ),
        dt=Arg(
            lambda batch: floats([0.1, 1.0, 3.0], 0.01, 3.0),
            1.0,
            [(5.0, ValueError), *BAD_POSITIVE],
        ),
        alpha=Arg(
            constant((0.05, 0.01, 0.01, 0.05)),
            (0.05, 0.01, 0.01, 0.05),
            [([0.6, 0.0, 0.0, 0.0], ValueError), *bad_alphas(4)],
        ),
        sigmas=Arg(
            lambda batch: st.tuples(
                floats([0.01, 1.0], 0.01, 1.0), floats([0.005, 0.5], 0.005, 0.5)
            ),
            (0.1, 0.05),
            [((0.0, 0.05), ValueError), ((0.1, 0.6), ValueError), *bad_vectors(2)],
        ),
        landmark=Arg(
            lambda batch: st.tuples(*[floats([-5.0, 0.0, 5.0], -5.0, 5.0)] * 2),
            (2.5, 1.5),
            [((6.0, 0.0), ValueError), *bad_vectors(2)],
        ),
        innovation=Arg(
            lambda batch: st.tuples(
                floats([-1.0, 0.0, 1.0], -1.0, 1.0), floats([-0.5, 0.0, 0.5], -0.5, 0.5)
            ),
            (0.15, -0.04),
            [((0.0, 0.6), ValueError), *bad_vectors(2)],
        ),
        p=Arg(
            lambda batch: floats([0.5, 0.95, 0.99], 0.01, 0.999),
            0.95,
            [(0.0, ValueError), (1.0, ValueError), *BAD_SCALAR],
        ),
        examples=5,
    ),
]

# Invalid combinations that no single argument shows: (function, kwargs, names, exception).
EXTRA_INVALID = [
    (
        motion.motion_model_velocity,
        dict(x_t=np.zeros((5, 3)), u_t=np.zeros((4, 2)), x_prev=np.zeros(3), dt=1, alpha=[0] * 6),
        ("x_t", "u_t"),
        ValueError,
    ),
    (
        motion.motion_model_odometry,
        dict(x_t=np.zeros((5, 3)), u_t=np.zeros((4, 2, 3)), x_prev=np.zeros(3), alpha=[0] * 4),
        ("x_t", "u_t"),
        ValueError,
    ),
    (
        motion.sample_motion_model_velocity,
        dict(u_t=[1, 0], x_prev=np.zeros((5, 3)), dt=1, alpha=[0.1] * 6, size=(4,)),
        ("size",),
        ValueError,
    ),
    (
        motion.sample_motion_model_odometry,
        dict(u_t=np.zeros((4, 2, 3)), x_prev=np.zeros((5, 3)), alpha=[0.1] * 4),
        ("u_t", "x_prev"),
        ValueError,
    ),
    (
        distributions.prob_normal_distribution,
        dict(a=np.zeros(3), b2=np.ones(2)),
        ("a", "b2"),
        ValueError,
    ),
    (
        distributions.sample_normal_distribution,
        dict(b2=np.ones(3), size=(4,)),
        ("size",),
        ValueError,
    ),
    (angles.angle_diff, dict(a=np.zeros(3), b=np.zeros(2)), ("a", "b"), ValueError),
    (angles.circular_mean, dict(theta=[0.1, 0.2], weights=[0.0, 0.0]), ("weights",), ValueError),
    (angles.circular_mean, dict(theta=[0.1, 0.2], weights=[1.0, -1.0]), ("weights",), ValueError),
    (angles.circular_mean, dict(theta=[0.1, 0.2], weights=[1.0, 1j]), ("weights",), TypeError),
    (angles.circular_mean, dict(theta=[0.1, 0.2], axis=3), ("axis",), ValueError),
    (
        motion.odometry_deltas,
        dict(xbar_prev=np.zeros((5, 3)), xbar_t=np.zeros((4, 3))),
        ("xbar_prev", "xbar_t"),
        ValueError,
    ),
    (
        motion.apply_odometry_deltas,
        dict(x_prev=np.zeros((5, 3)), rot1=np.zeros(4), trans=1.0, rot2=0.0),
        ("x_prev", "rot1"),
        ValueError,
    ),
    (
        plotting.plot_density_xy,
        dict(xs=np.arange(3.0), ys=np.arange(4.0), p=np.ones((3, 4))),
        ("p",),
        ValueError,
    ),
    (
        plotting.plot_density_xy,
        dict(xs=np.arange(3.0), ys=np.arange(2.0), p=-np.ones((2, 3))),
        ("p",),
        ValueError,
    ),
    (
        plotting.plot_motion_model,
        dict(model="velocity", u_t=[1, 0], x_prev=[0, 0, 0], alpha=[0.1] * 6, extent=(1, 0, 0, 1)),
        ("extent",),
        ValueError,
    ),
]

# the modules that joined later: lengths that must agree, batches that must broadcast
_FILTER = dict(mu=np.zeros(3), Sigma=np.eye(3) * 0.1, u=[1.0, 0.1], m=LANDMARKS, dt=1.0,
               alpha=[0.01] * 4, sigmas=(0.1, 0.05, 0.1))  # fmt: skip
EXTRA_INVALID += [
    (
        localization.ekf_localization_known_correspondences,
        dict(_FILTER, z=np.ones((2, 3)), c=np.array([0, 1, 2])),
        ("c",),
        ValueError,
    ),
    (
        localization.ukf_localization,
        dict(_FILTER, z=np.ones((2, 3)), c=np.array([0])),
        ("c",),
        ValueError,
    ),
    (
        sensors.landmark_model_known_correspondence,
        dict(f=np.ones((5, 3)), c=np.zeros(4, int), x=np.zeros(3), m=LANDMARKS, sigmas=(1, 1, 1)),
        ("f", "c"),
        ValueError,
    ),
    (
        sensors.beam_range_finder_model,
        dict(
            z=np.ones((5, 4)),
            x=np.tile([2.0, 1.0, 0.0], (3, 1)),
            grid=GRID_MAP,
            beam_angles=BEAMS,
            params=PARAMS,
        ),
        ("z", "x"),
        ValueError,
    ),
    (
        sensors.beam_range_finder_model,
        dict(z=np.ones(3), x=[2.0, 1.0, 0.0], grid=GRID_MAP, beam_angles=BEAMS, params=PARAMS),
        ("z", "beam_angles"),
        ValueError,
    ),
    (
        sensors.likelihood_field_range_finder_model,
        dict(
            z=np.ones((5, 4)),
            x=np.tile([2.0, 1.0, 0.0], (3, 1)),
            grid=GRID_MAP,
            beam_angles=BEAMS,
            params=PARAMS,
        ),
        ("z", "x"),
        ValueError,
    ),
    (
        maps.ray_cast,
        dict(grid=GRID_MAP, poses=[6.0, 1.0, 0.0], beam_angles=BEAMS, max_range=6.0),
        ("poses",),
        ValueError,
    ),
    (
        kinematics.dead_reckon,
        dict(x0=np.zeros(3), ds=[1.0, 1.0], dtheta=[0.0]),
        ("ds", "dtheta"),
        ValueError,
    ),
    (
        fitting.interpolate_poses,
        dict(t=np.linspace(0, 1, 5), poses=np.zeros((4, 3)), t_out=[0.5]),
        ("poses",),
        ValueError,
    ),
]

# issue 23, item 29: inputs that no sensor or robot produces (class C) and integer overflow in
# binning and indexing (class D), refused naming the argument instead of accepted or wrapped
_STEP = simulation.Step(t=0.1, dt=0.1, u=np.array([1.0, 0.0]), z=np.zeros((0, 3)), c=np.zeros(0))
_RUN = dict(mu0=np.zeros(3), Sigma0=0.1 * np.eye(3), m=LANDMARKS, alpha=[0.01] * 4,
            sigmas=(0.1, 0.05, 0.1))  # fmt: skip
EXTRA_INVALID += [
    (  # C: a negative range
        localization.ekf_localization_known_correspondences,
        dict(_FILTER, z=np.array([[-1.0, 0.1, 0.0]]), c=np.array([0])),
        ("z",),
        ValueError,
    ),
    (  # C: a time stamp that is not a time
        localization.run_filter,
        dict(_RUN, steps=[_STEP, dataclasses.replace(_STEP, t=np.nan)]),
        ("steps[1].t",),
        ValueError,
    ),
    (  # C: a command that is text
        localization.run_filter,
        dict(_RUN, steps=[dataclasses.replace(_STEP, u=["1", "0"])]),
        ("steps[0].u",),
        ValueError,
    ),
    (  # D: an integral float index beyond int64
        sensors.landmark_model_known_correspondence,
        dict(f=[2.0, 0.3, 0.0], c=1e300, x=np.zeros(3), m=LANDMARKS, sigmas=(1, 1, 1)),
        ("c",),
        ValueError,
    ),
    (  # D: a cell 2**52 cells away (int64 wrapped silently)
        maps.OccupancyGrid.world_to_cell,
        dict(self=GRID_MAP, xy=[1e20, 0.5]),
        ("xy",),
        ValueError,
    ),
    (  # D: bins of radius 1e-13 around particles 1 km out
        mcl.estimate_pose,
        dict(particles=[[1e3, 0.0, 0.0]] * 2, radius=1e-13),
        ("particles", "radius"),
        ValueError,
    ),
    (  # D: more particles than an index can hold in memory
        mcl.uniform_particles,
        dict(grid=GRID_MAP, n=10**20, rng=0),
        ("n",),
        ValueError,
    ),
    (  # D: a dof beyond what 0.5 * dof holds as a float
        evaluation.chi2_quantile,
        dict(p=0.5, dof=10**400),
        ("dof",),
        ValueError,
    ),
]

# --------------------------------------------------------------------------- the machinery


def _scaled(examples: int) -> int:
    """Examples of a row under the active profile (``probrob``: as given; thorough: x10)."""
    return max(1, round(examples * settings().max_examples / 200))


def _snapshot(kwargs):
    """Copies of the array arguments (lists cannot be modified by numpy code)."""
    return {k: v.copy() for k, v in kwargs.items() if isinstance(v, np.ndarray)}


def _assert_unmodified(before, kwargs):
    for name, value in before.items():
        assert kwargs[name].dtype == value.dtype, f"{name} changed dtype"
        assert np.array_equal(kwargs[name], value, equal_nan=True), f"{name} was modified"


def _call(func, kwargs, raises=None):
    """Call with warnings as errors; an overflow ValueError naming an argument is allowed.

    So is a ValueError matching the row's ``raises`` (a documented singular input, e.g. a
    pose on a landmark), if it names an argument too.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return func(**kwargs), None
        except ValueError as exc:
            message = str(exc)
            names = "|".join(re.escape(k) for k in kwargs)
            if "overflows float64" in message and re.match(rf"({names})\w* = ", message):
                return None, exc
            named = re.search(rf"(?<![\w.])({names})(?!\w)", message)
            if raises and re.search(raises, message) and named:
                return None, exc
            raise


def _arrays(result, skip=()):
    if dataclasses.is_dataclass(result):  # a result record: its numeric fields
        names = [f.name for f in dataclasses.fields(result) if f.name not in skip]
        values = [getattr(result, name) for name in names]
        return [np.asarray(v) for v in values if _numeric(v)]
    if isinstance(result, tuple):
        return [np.asarray(r) for r in result]
    return [np.asarray(result)]


def _numeric(value):
    return isinstance(value, int | float | np.ndarray) and np.asarray(value).dtype.kind in "biuf"


def _check_valid(api: Api, kwargs: dict, batch):
    before = _snapshot(kwargs)
    result, overflow = _call(api.func, kwargs, api.raises)
    _assert_unmodified(before, kwargs)
    if overflow is not None:
        return
    if api.kind == "density":
        p = np.asarray(result, dtype=float)
        assert not np.isnan(p).any()
        assert np.all(p >= 0)
        if api.finite_when is not None and api.finite_when(kwargs):
            assert np.all(np.isfinite(p)), (p, kwargs)
        log_p, _ = _call(api.func, {**kwargs, "log": True})
        with np.errstate(over="ignore"):
            np.testing.assert_allclose(np.exp(log_p), p, rtol=1e-12, atol=0)
        if api.check_batch_shape:
            shapes = [np.shape(v) for k, v in kwargs.items() if api.args[k] in _BATCH_ARGS]
            trims = [_BATCH_ARGS[api.args[k]] for k in kwargs if api.args[k] in _BATCH_ARGS]
            expected = np.broadcast_shapes(
                *(s[: len(s) - t] for s, t in zip(shapes, trims, strict=True))
            )
            assert p.shape == expected
    elif api.kind == "sampler":
        out = np.asarray(result)
        assert np.all(np.isfinite(out))
        size = kwargs["size"]
        if size is not None:
            size = (size,) if isinstance(size, int) else tuple(size)
            assert out.shape == size + api.trailing
        rng = kwargs["rng"]
        if isinstance(rng, int):
            again, _ = _call(api.func, kwargs)
            np.testing.assert_array_equal(out, again)
    elif api.kind == "map":
        for arr in _arrays(result, api.nan_fields):
            if api.finite:
                assert np.all(np.isfinite(arr.astype(float)))
            else:  # ±inf is a defined answer (e.g. the radius of a straight line); NaN is not
                assert not np.isnan(arr.astype(float)).any()
        again, _ = _call(api.func, kwargs)
        for a, b in zip(_arrays(result), _arrays(again), strict=True):
            np.testing.assert_array_equal(a, b)
    elif api.kind == "plot":
        assert isinstance(result, plt.Axes)
    if api.extra is not None:
        api.extra(result, kwargs)


# Batched Args and how many trailing (non-batch) axes they have.
_BATCH_ARGS = {POSES: 1, VELOCITIES: 1, ODOMETRY: 2, POINTS: 0, ANGLES: 0, VARIANCES: 0}


def _valid_ids():
    return [api for api in API if not api.skip_valid]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.mark.parametrize("api", _valid_ids(), ids=repr)
def test_valid_inputs_have_the_properties_of_their_kind(api):
    @settings(
        max_examples=_scaled(api.examples),
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    @given(data=st.data())
    def run(data):
        batch = data.draw(st.sampled_from(BATCHES), label="batch")
        kwargs = {name: data.draw(arg.valid(batch), label=name) for name, arg in api.args.items()}
        _check_valid(api, kwargs, batch)
        plt.close("all")

    run()


def _invalid_rows():
    rows = []
    for api in API:
        base = {name: arg.default for name, arg in api.args.items()}
        args = dict(api.args)
        if api.kind == "density":
            args["log"] = Arg(constant(False), False, BAD_FLAG)
        for name, arg in args.items():
            for k, (value, exc) in enumerate(arg.invalid):
                rows.append(
                    pytest.param(
                        api.func, {**base, name: value}, (name,), exc, id=f"{api!r}-{name}-{k}"
                    )
                )
    for k, (func, kwargs, names, exc) in enumerate(EXTRA_INVALID):
        rows.append(pytest.param(func, kwargs, names, exc, id=f"extra-{func.__name__}-{k}"))
    return rows


INVALID_ROWS = _invalid_rows()


@pytest.mark.parametrize(("func", "kwargs", "names", "exc"), INVALID_ROWS)
def test_invalid_input_raises_an_error_naming_the_argument(func, kwargs, names, exc):
    before = _snapshot(kwargs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(exc) as info:
            func(**kwargs)
    assert type(info.value) is exc  # not a subclass such as numpy's AxisError
    message = str(info.value)
    for name in names:
        assert re.search(rf"(?<![\w.]){re.escape(name)}(?!\w)", message), (name, message)
    _assert_unmodified(before, kwargs)


def test_every_public_function_is_in_the_table():
    """A new public function of these modules must join the table (or the test says so)."""
    listed = {api.func for api in API}
    listed |= {func for func, *_ in EXTRA_INVALID}
    missing = []
    modules = (angles, distributions, motion, plotting, widgets, kinematics, sensors, maps)
    for module in (*modules, localization, evaluation, simulation, fitting, datasets, mcl):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj) and obj not in listed:  # classes may join as rows too
                missing.append(f"{module.__name__}.{name}")
    assert missing == []


def test_the_suite_counts():
    """The numbers the issue asks for (printed with -s; asserted so that rows are not lost)."""
    n_functions = len({api.func for api in API} | {f for f, *_ in EXTRA_INVALID})
    n_valid = sum(_scaled(api.examples) for api in API if not api.skip_valid)
    print(f"\nproperty suite: {n_functions} functions, {n_valid} valid examples per run, "
          f"{len(INVALID_ROWS)} invalid-input rows")  # fmt: skip
    assert n_functions >= 86 and n_valid >= 2200 and len(INVALID_ROWS) >= 2100


# --------------------------------------------------------------------------- termination
# (issue 15) Every loop whose number of steps depends on the data ends, on the valid inputs
# that drive it hardest, within a time limit (the ``time_limit`` fixture of conftest.py:
# SIGALRM, so a loop that never ends fails the test instead of hanging the run): ray
# casting (its three traversals and sphere tracing, also within their proven step bounds,
# ``maps._step_bounds``), the beam model on top of it, EM (its iterations and the bracket
# search of λ_short), the rejection sampling of random_landmarks, the chunks of from_scans
# and the block loop of the twelve-uniform sampler.

_TERMINATION = settings(
    max_examples=_scaled(60),
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
_AXIS = [0.0, PI / 2, -PI / 2, PI, -PI, 1e-17, -1e-17, PI / 4, 1e-307, -1e-307, 5e-324]


@st.composite
def _ray_casting_case(draw):
    h, w = draw(st.integers(1, 16)), draw(st.integers(1, 16))
    pattern = draw(st.sampled_from(["random", "stripes", "rows", "empty", "full"]))
    seed = draw(st.integers(0, 2**32 - 1))
    occ = {
        "random": np.random.default_rng(seed).random((h, w)) < 0.3,
        "stripes": np.arange(h * w).reshape(h, w) % max(w, 1) == 0,
        "rows": (np.arange(h)[:, None] % 2 == 0) & np.ones((h, w), bool),
        "empty": np.zeros((h, w), bool),
        "full": np.ones((h, w), bool),
    }[pattern]
    res = draw(st.sampled_from([1.0, 0.05, 0.3, 2.0**-3]))
    origin = draw(st.sampled_from([0.0, 0.35, -7.3]))
    grid = maps.OccupancyGrid(occ, res, (origin, origin))
    # on grid lines and corners (half cells), a few ulps off them, or anywhere
    on_lines = st.tuples(st.integers(0, 2 * w - 1), st.integers(0, 2 * h - 1)).map(
        lambda ij: origin + 0.5 * res * np.array(ij, dtype=float)
    )
    anywhere = st.tuples(st.floats(0, 0.999999), st.floats(0, 0.999999)).map(
        lambda uv: origin + res * np.array([uv[0] * w, uv[1] * h])
    )
    xy = draw(st.lists(st.one_of(on_lines, anywhere), min_size=1, max_size=6))
    ulps = draw(st.sampled_from([0, 1, -2]))
    xy = np.array(xy)
    for _ in range(abs(ulps)):
        xy = np.nextafter(xy, np.inf if ulps > 0 else -np.inf)
    theta = draw(
        st.lists(st.one_of(st.sampled_from(_AXIS), HEADING), min_size=len(xy), max_size=len(xy))
    )
    beams = draw(st.lists(st.one_of(st.sampled_from(_AXIS), ANGLE), min_size=1, max_size=5))
    max_range = draw(st.sampled_from([1e-3, 1.0, 7.0, 1e6, 1e300]))
    poses = np.c_[xy, theta]
    return grid, poses[grid.contains(xy)], np.array(beams), max_range


@_TERMINATION
@given(case=_ray_casting_case())
def test_ray_casting_terminates_within_its_step_bounds(case, time_limit):
    grid, poses, beams, max_range = case
    if not poses.size:
        return
    bounds = maps._step_bounds(grid.shape, max_range / grid.resolution)
    with time_limit(20):
        for method in maps._METHODS:
            z, steps = maps._cast(grid, poses, beams, max_range, method)
            assert all(n <= bounds[stage] for stage, n in steps.items()), (method, steps)
            assert np.all((z >= 0) & (z <= max_range))
        params = sensors.BeamModelParams(0.7, 0.1, 0.1, 0.1, 0.2, 0.5, min(max_range, 1e6))
        sensors.beam_range_finder_model(np.zeros(beams.size), poses, grid, beams, params, log=True)


_EM_RANGE = floats([0.0, 1e-300, 0.5, 5.0, np.nextafter(10.0, 0), 10.0, 12.0], 0.0, 10.0)


@_TERMINATION
@given(
    z=st.lists(_EM_RANGE, min_size=1, max_size=40),
    z_star=st.sampled_from([0.0, 1e-300, 2.0, 5.0, 9.999, 10.0]),
    e_step=st.sampled_from(["weighted", "deck"]),
    m_step=st.sampled_from(["exact", "book"]),
    max_iter=st.integers(1, 60),
)
def test_em_terminates(z, z_star, e_step, m_step, max_iter, time_limit):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with time_limit(30):
            params, info = sensors.learn_intrinsic_parameters(
                z, z_star, 10.0, e_step=e_step, m_step=m_step, max_iter=max_iter, full_output=True
            )
    assert info.n_iter <= max_iter
    assert np.isfinite([params.sigma_hit, params.lambda_short]).all()


@_TERMINATION
@given(
    n=st.integers(1, 40),
    min_distance=st.sampled_from([0.0, 0.5, 2.0, 20.0, 1e300]),
)
def test_random_landmarks_terminates(n, min_distance, time_limit):
    with time_limit(30):
        try:
            m = simulation.random_landmarks(
                n, (0.0, 10.0, 0.0, 10.0), min_distance=min_distance, rng=0
            )
        except ValueError as exc:  # the documented "cannot place" after its 1000 rounds
            assert "cannot place" in str(exc)
            return
    assert m.shape == (n, 3)


@_TERMINATION
@given(
    n_scans=st.integers(1, 4),
    ranges=st.lists(floats([0.0, 0.01, 8.0, 30.0], 0.0, 30.0), min_size=3, max_size=3),
    resolution=st.sampled_from([0.05, 0.5, 3.0]),
)
def test_from_scans_terminates(n_scans, ranges, resolution, time_limit):
    poses = np.c_[np.arange(n_scans, dtype=float), np.zeros(n_scans), np.linspace(0, 3, n_scans)]
    with time_limit(30):
        grid = maps.OccupancyGrid.from_scans(
            poses, np.tile(ranges, (n_scans, 1)), [-0.5, 0.0, 0.5], resolution, max_range=8.0
        )
    assert grid.contains(poses[:, :2]).all()


@_TERMINATION
@given(size=st.sampled_from([0, 1, (1 << 14) - 1, 1 << 14, (1 << 14) + 1, 100_003]))
def test_the_twelve_uniform_sampler_terminates(size, time_limit):
    with time_limit(30):
        out = distributions.sample_normal_distribution(1.0, size=size, rng=0)
    assert np.shape(out) == (size,)


# --------------------------------------------------------------------------- issue 23, item 29
# The classes, swept over every row of the table instead of case by case:
#  A. an array-valued scalar ([x], array([x])) for any scalar argument is refused with an error
#     that names the argument (float() raised TypeError "only 0-dimensional arrays ...", or
#     numpy's DeprecationWarning, naming nothing);
#  B. extreme but valid magnitudes (5e-324, 1e-300, 1e300, 1.7e308 for every scalar, every
#     array scaled to them, a BeamModelParams with σ_hit or λ_short at them) warn nothing:
#     each gives a result without NaN or an error naming an argument (an overflow reported
#     against it); C and D are rows above (EXTRA_INVALID, the estimate_pose rows).
_EXTREMES = (5e-324, 1e-300, 1e300, 1.7e308)


def _scalar_args(api):
    """``{name: default}`` of the row's scalar numeric arguments that are not batched, and of
    the function's own keyword arguments with a numeric default that the row leaves out."""
    out = {
        name: arg.default
        for name, arg in api.args.items()
        if arg not in _BATCH_ARGS and _is_number(arg.default)
    }
    for name, par in inspect.signature(api.func).parameters.items():
        if name not in api.args and _is_number(par.default):
            out[name] = par.default
    return out


def _is_number(value):
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(
        value, bool | np.bool_
    )


def _names_an_argument(message, kwargs):
    names = "|".join(re.escape(k) for k in kwargs)
    return re.search(rf"(?<![\w.])({names})(?!\w)", message) is not None


def _call_extreme(func, kwargs):
    """The result, or None after a ValueError/TypeError that names an argument; any other
    exception, a warning, or an error naming nothing fails the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return func(**kwargs)
        except (ValueError, TypeError) as exc:
            assert _names_an_argument(str(exc), kwargs), f"{type(exc).__name__}: {exc}"
            return None


def _array_scalar_rows():
    rows = []
    for api in API:
        base = {name: arg.default for name, arg in api.args.items()}
        for name, default in _scalar_args(api).items():
            for label, value in (("[x]", [default]), ("array([x])", np.array([default]))):
                rows.append(pytest.param(api, base, name, value, id=f"{api!r}-{name}-{label}"))
    return rows


@pytest.mark.parametrize(("api", "base", "name", "value"), _array_scalar_rows())
def test_an_array_valued_scalar_is_named_when_refused(api, base, name, value):
    try:
        _call_extreme(api.func, {**base, name: value})
    finally:
        plt.close("all")


def _extreme_rows():
    rows = []
    for api in API:
        if api.kind in ("plot", "widget"):
            continue
        base = {name: arg.default for name, arg in api.args.items()}
        variants = []
        for name, default in _scalar_args(api).items():
            sign = -1.0 if default < 0 else 1.0
            variants += [(name, f"{x:g}", sign * x) for x in _EXTREMES]
        for name, arg in api.args.items():
            d = arg.default
            if isinstance(d, sensors.BeamModelParams):
                for field_name in ("sigma_hit", "lambda_short"):
                    for x in (5e-324, 1e-300, 1e300):
                        value = dataclasses.replace(d, **{field_name: x})
                        variants.append((name, f"{field_name}={x:g}", value))
                continue
            if _is_number(d) or isinstance(d, str | bool) or d is None:
                continue
            try:
                arr = np.asarray(d, dtype=float)
            except (TypeError, ValueError):
                continue
            if arr.ndim == 0 or not arr.size or not np.all(np.isfinite(arr)) or not arr.any():
                continue
            top = np.max(np.abs(arr))
            for x in _EXTREMES:
                with np.errstate(all="ignore"):
                    scaled = arr / top * x
                if np.all(np.isfinite(scaled)):
                    variants.append((name, f"max {x:g}", scaled))
        for name, label, value in variants:
            rows.append(pytest.param(api, base, name, value, id=f"{api!r}-{name}-{label}"))
    return rows


@pytest.mark.parametrize(("api", "base", "name", "value"), _extreme_rows())
def test_extreme_valid_magnitudes_warn_nothing_and_never_give_nan(api, base, name, value):
    result = _call_extreme(api.func, {**base, name: value})
    if result is None or api.nan_fields:
        return
    for arr in _arrays(result):
        assert not np.isnan(arr.astype(float)).any(), (name, value)


def test_the_sweep_has_rows_for_every_class():
    """Issue 23, item 29: the classes are rows of the suite, not single cases."""
    assert len(_array_scalar_rows()) >= 300
    assert len(_extreme_rows()) >= 500
    extra = {f.__name__ for f, *_ in EXTRA_INVALID}
    assert {"run_filter", "world_to_cell", "estimate_pose", "uniform_particles"} <= extra
