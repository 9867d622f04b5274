"""The live particle filter (probrob.live.mcl.particle_filter_live): its HTML, and its JavaScript
held equal to probrob.mcl.

The page's JavaScript (``probrob/live/assets/mcl.js``, ``beam_model.js``) is a second
implementation of Tables 8.2 (MCL), 8.3 (augmented MCL) and 8.4 (KLD-sampling) with the odometry
sampler (Table 5.6), the likelihood field (Table 6.3, with its exact distance field) or the beam
model (Table 6.1, with the exact ray casting of probrob.maps.ray_cast) and the low-variance
sampler (Table 4.4). The parity tests open the widget in headless Chromium (the driver of
``.ci/cdp.py``, as tests/test_live_widgets.py), set its sliders and choices through the test hook
and compare, at every step of the run, its particles, their log-weights, its pose estimate, and
augmented MCL's averages and KLD-sampling's weights, with :func:`probrob.mcl.run_mcl` fed the
same random numbers (the embedded draws: the motion noise by the ``sample=`` keyword, the rest
by ``Replay``, a numpy Generator that hands out the page's numbers) and the widget's kidnapping
as its ``on_step``: to 1e-9, relative (absolute below 1). A run on a synthetic room needs no
data; the Intel lab's stretch runs when its log is present. Without Chromium the browser tests
are skipped, unless ``PROBROB_REQUIRE_BROWSER=1``.
"""

from __future__ import annotations

import base64
import functools
import json
import os
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import norm

from probrob import mcl as M
from probrob.distributions import sample_normal_distribution
from probrob.live.mcl import (
    PF_HEADING_BINS,
    PF_KLD_BINS,
    PF_KLD_N_MIN,
    PF_RADIUS,
    PF_ROUNDS,
    particle_filter_beams,
    particle_filter_decoded,
    particle_filter_draws,
    particle_filter_kidnap_target,
)
from probrob.maps import OccupancyGrid, ray_cast
from probrob.sensors import BeamModelParams
from probrob.widgets import particle_filter_live

ROOT = Path(__file__).resolve().parent.parent
TOL = 1e-9
SPREAD = np.array([0.1, 0.1, 0.05])


# ------------------------------------------------------------------------------ the worlds


def _room():
    """A 12 m x 8 m room at 10 cm with walls, asymmetric blocks and an unexplored strip; a
    robot loop of 40 steps; odometry in a frame rotated and shifted against the map's (with
    drift); scans of 37 beams by ray casting, with noise and a few max-range readings."""
    res = 0.1
    occ = np.zeros((80, 120), dtype=bool)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
    occ[20:30, 30:34] = True
    occ[50:53, 60:100] = True
    occ[10:40, 85:87] = True
    occ[60:75, 20:22] = True
    free = ~occ
    free[:, 110:119] = False  # seen by no beam: no particle may start there
    grid = OccupancyGrid(occ, res, origin=(-3.0, 1.5), free=free)
    t = np.linspace(0, 2 * np.pi, 41)
    truth = np.column_stack(
        [
            -3.0 + 6.0 + 3.0 * np.cos(t),
            1.5 + 4.0 + 2.0 * np.sin(t),
            t + np.pi / 2 + 0.1 * np.sin(3 * t),
        ]
    )
    rng = np.random.default_rng(3)
    c, s = np.cos(0.7), np.sin(0.7)
    drift = np.cumsum(rng.normal(0, [0.01, 0.01, 0.005], truth.shape), axis=0)
    odo = truth + drift
    odo = np.column_stack(
        [c * odo[:, 0] - s * odo[:, 1] + 5.0, s * odo[:, 0] + c * odo[:, 1] - 2.0, odo[:, 2] + 0.7]
    )
    odometry = np.stack([odo[:-1], odo[1:]], axis=1)
    angles = np.linspace(-np.pi / 2, np.pi / 2, 37)
    max_range = 8.0
    # method="dda": the default "hybrid" traversal hangs on some of these poses (reported)
    scans = ray_cast(grid, truth[1:], angles, max_range, method="dda")
    # at least 2 cm, a scanner's shortest range: a reading of 0 where a particle's z* is 0
    # (inside a wall) is the beam model's point mass, an infinite likelihood
    scans = np.clip(scans + rng.normal(0, 0.03, scans.shape), 0.02, max_range)
    scans[rng.random(scans.shape) < 0.05] = max_range
    params = BeamModelParams(
        0.8, 0.05, 0.05, 0.1, sigma_hit=0.15, lambda_short=0.5, max_range=max_range
    )
    alpha = (0.05, 0.01, 0.02, 0.005)
    return dict(
        odometry=odometry,
        scans=scans,
        grid=grid,
        beam_angles=angles,
        alpha=alpha,
        params=params,
        truth=truth,
    )


def _intel():
    from probrob.datasets import DatasetNotFoundError, load_intel_lab
    from probrob.sensors import learn_intrinsic_parameters

    try:
        data = load_intel_lab()
    except DatasetNotFoundError:
        return None
    grid = OccupancyGrid.from_scans(
        data.poses, data.ranges, data.beam_angles, 0.1, max_range=data.max_range
    )
    z_all = np.where(data.no_return, 26.0, data.ranges)
    fit = np.arange(0, len(z_all), 10)
    z_star = ray_cast(grid, data.poses[fit], data.beam_angles, 26.0)
    params = learn_intrinsic_parameters(z_all[fit].ravel(), z_star.ravel(), 26.0)
    t = 100
    return dict(
        odometry=data.odometry[:t],
        scans=z_all[1 : t + 1],
        grid=grid,
        beam_angles=data.beam_angles,
        alpha=(0.1134, 0.0166, 0.0027, 0.0013),
        params=params,
        truth=data.poses[: t + 1],
    )


ROOM = _room()
ROOM_KW = dict(n_max=1000, n_particles=300, beams=20)


# ------------------------------------------------------------------------------ the HTML


class _Survey(HTMLParser):
    def __init__(self):
        super().__init__()
        self.labels: set[str] = set()
        self.controls: list[dict] = []
        self.canvases: list[dict] = []
        self.buttons = 0
        self.fetching: list[tuple[str, str]] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "label" and a.get("for"):
            self.labels.add(a["for"])
        if tag in ("input", "select"):
            self.controls.append(a)
        if tag == "canvas":
            self.canvases.append(a)
        if tag == "button":
            self.buttons += 1
        for key in ("src", "href", "srcset", "data"):
            if key in a:
                self.fetching.append((tag, key))


def _config(widget) -> dict:
    return json.loads(re.search(r"const config = (\{.*?\});\n", widget.html).group(1))


def test_widget_is_one_self_contained_accessible_block():
    widget = particle_filter_live(**ROOM, **ROOM_KW)
    html = widget._repr_html_()
    assert "http:" not in html and "https:" not in html and "//cdn" not in html
    survey = _Survey()
    survey.feed(html)
    assert survey.fetching == []
    assert survey.controls == [] and survey.buttons == 0  # the runtime's, from the spec
    config = _config(widget)
    names = [s["name"] for s in config["sliders"]]
    assert names == ["t", "a1", "a2", "a3", "a4", "sigma", "zrand", "beams", "kappa", "n"] + [
        "aslow",
        "afast",
        "eps",
        "delta",
        "kidnap",
    ]
    assert all(p["label"] for p in config["sliders"] + config["choices"])
    assert [c["name"] for c in config["choices"]] == ["start", "view", "sensor", "method"]
    assert [a for a, _ in config["buttons"]] == ["step", "play", "start", "kidnap", "reset"]
    assert config["status"] is True  # a status line, aria-live
    snap = [s["name"] for s in config["sliders"] if s.get("snap")]
    assert snap == ["t", "beams", "n", "delta", "kidnap"]
    # α_slow < α_fast anywhere on the sliders (probrob.mcl.augmented_mcl refuses the rest)
    sl = {s["name"]: s for s in config["sliders"]}
    assert sl["aslow"]["max"] < sl["afast"]["min"]
    # z_{1-δ} of every δ on its slider, as probrob computes it
    z = config["constants"]["kldZ"]
    assert len(z) == 200 and z[9] == norm.isf(10 * 0.001) and z[-1] == norm.isf(200 * 0.001)
    assert len(survey.canvases) == 1 and survey.canvases[0].get("aria-label")
    assert re.fullmatch(r"<probrob live widget: mcl model, \d+ kB of HTML>", repr(widget))
    # the budget the browser check holds it to is written on the block
    assert 'data-size-budget="400000"' in html and len(html.encode()) < 400_000


def test_widget_embeds_the_log_the_map_and_the_draws():
    widget = particle_filter_live(**ROOM, **ROOM_KW, rng=4)
    dec = particle_filter_decoded(widget)
    np.testing.assert_array_equal(dec["odometry"], ROOM["odometry"])
    np.testing.assert_array_equal(dec["truth"], ROOM["truth"])
    np.testing.assert_array_equal(dec["beam_angles"], ROOM["beam_angles"])
    # ranges to the millimetre; max-range readings kept as such
    z = ROOM["scans"]
    skip = z >= ROOM["params"].max_range
    np.testing.assert_array_equal(dec["scans"][skip], ROOM["params"].max_range)
    assert np.abs(dec["scans"][~skip] - z[~skip]).max() <= 0.0005 + 1e-12
    assert skip.any() and (~skip).any()
    draws = particle_filter_draws(1000, len(z), 4)
    for name in ("normal", "offsets", "resample", "uniforms", "rounds", "shuffle"):
        np.testing.assert_array_equal(dec[name], draws[name])
    # the map: 2 bits per cell, decoded here as the page decodes it
    cells = np.frombuffer(base64.b64decode(_config(widget)["map"]["cells"]), np.uint8)
    codes = ((cells[:, None] >> (2 * np.arange(4))) & 3).ravel()[: ROOM["grid"].occupied.size]
    np.testing.assert_array_equal(codes.reshape(ROOM["grid"].shape) == 2, ROOM["grid"].occupied)
    np.testing.assert_array_equal(codes.reshape(ROOM["grid"].shape) == 1, ROOM["grid"].free)


def test_draws_are_seeded_and_standardized():
    a, b = particle_filter_draws(2000, 100, 0), particle_filter_draws(2000, 100, 0)
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])
    assert not np.array_equal(particle_filter_draws(2000, 100, 1)["normal"], a["normal"])
    z = a["normal"]
    assert z.shape == (6000,) and abs(z.mean()) < 0.05 and abs(z.var() - 1) < 0.05
    np.testing.assert_array_equal(z, z.astype(np.float32))  # exact in the page's float32
    assert a["offsets"].shape == (100, 3) and a["offsets"].min() >= 0 and a["offsets"].max() < 6000
    u = a["uniforms"]
    assert u.shape == (2000, 4) and u.min() >= 0 and u.max() < 1
    np.testing.assert_array_equal(u, u.astype(np.float32))
    assert a["resample"].min() >= 0 and a["resample"].max() < 1
    r = a["rounds"]
    assert r.shape == (100, PF_ROUNDS) and r.min() >= 0 and r.max() < 1
    np.testing.assert_array_equal(r, r.astype(np.float32))
    sh = a["shuffle"]
    assert sh.shape == (100, 2) and sh[:, 0].max() < 8000 and sh[:, 1].max() < 2000
    assert sh.min() >= 0
    # the draws of the plain filter come first: a seed's MCL draws are as before the others
    older = np.random.default_rng(0)
    np.testing.assert_array_equal(
        sample_normal_distribution(1.0, size=6000, rng=older).astype(np.float32), a["normal"]
    )


def test_kidnap_target_is_the_farthest_reference_position():
    truth = ROOM["truth"]
    for k in (1, 10, 40):
        s = particle_filter_kidnap_target(truth, k)
        d = np.hypot(*(truth[:, :2] - truth[k, :2]).T)
        assert d[s] == d.max() and d[s] > 3.0
    for bad in (0, 41):
        with pytest.raises(ValueError, match="step"):
            particle_filter_kidnap_target(truth, bad)


def test_beam_selection():
    np.testing.assert_array_equal(particle_filter_beams(180, 1), [0])
    np.testing.assert_array_equal(particle_filter_beams(180, 2), [0, 179])
    np.testing.assert_array_equal(particle_filter_beams(180, 3), [0, 90, 179])  # 89.5 -> 90
    assert particle_filter_beams(180, 180).tolist() == list(range(180))
    with pytest.raises(ValueError, match="k"):
        particle_filter_beams(10, 11)


def test_widget_bad_input():
    def make(**kw):
        return particle_filter_live(**{**ROOM, **ROOM_KW, **kw})

    cases = [
        (dict(odometry=ROOM["odometry"][:, 0]), "odometry"),
        (dict(scans=ROOM["scans"][:-1]), "scans"),
        (dict(scans=-ROOM["scans"]), "scans"),
        (dict(truth=ROOM["truth"][:-1]), "truth"),
        (dict(alpha=(0.6, 0, 0, 0)), "alpha"),
        (dict(alpha=(0.1, 0.1, 0.1)), "alpha"),
        (dict(params="beam"), "params"),
        (dict(start="somewhere"), "start"),
        (dict(view="3d"), "view"),
        (dict(n_particles=50), "n_particles"),
        (dict(n_particles=1200), "n_particles"),
        (dict(n_max=150), "n_max"),
        (dict(beams=0), "beams"),
        (dict(beams=38), "beams"),
        (dict(step=41), "step"),
        (dict(exponent=0.0), "exponent"),
        (dict(spread=(0.1, -0.1, 0.1)), "spread"),
        (dict(beam_angles=ROOM["beam_angles"][:-1]), "scans"),
        (dict(grid=OccupancyGrid(np.zeros((5, 5), bool), 0.1)), "grid"),
        (dict(sensor="lidar"), "sensor"),
        (dict(method="amcl"), "method"),
        (dict(alpha_slow=0.05), "alpha_slow"),
        (dict(alpha_slow=-0.001), "alpha_slow"),
        (dict(alpha_fast=0.01), "alpha_fast"),
        (dict(alpha_fast=1.5), "alpha_fast"),
        (dict(epsilon=0.0), "epsilon"),
        (dict(epsilon=0.6), "epsilon"),
        (dict(delta=0.5), "delta"),
        (dict(delta=0.3), "delta"),
        (dict(delta=0.0), "delta"),
        (dict(kidnap=-1), "kidnap"),
        (dict(kidnap=41), "kidnap"),
        (dict(kidnap=2.5), "kidnap"),
    ]
    for kw, name in cases:
        with pytest.raises(ValueError, match=name):
            make(**kw)
    p = ROOM["params"]
    far = BeamModelParams(p.z_hit, p.z_short, p.z_max, p.z_rand, p.sigma_hit, p.lambda_short, 80.0)
    with pytest.raises(ValueError, match="scans"):
        make(params=far, scans=np.full_like(ROOM["scans"], 70.0))
    near = BeamModelParams(p.z_hit, p.z_short, p.z_max, p.z_rand, p.sigma_hit, p.lambda_short, 0.5)
    with pytest.raises(ValueError, match=r"params\.max_range"):
        make(params=near, scans=np.minimum(ROOM["scans"], 0.5))


# ------------------------------------------------------------------------------ the browser


def _load_cdp():
    import importlib.util

    spec = importlib.util.spec_from_file_location("probrob_ci_cdp", ROOT / ".ci" / "cdp.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def browser():
    cdp = _load_cdp()
    try:
        executable = cdp.find_chromium(None)
    except cdp.CheckError:
        message = (
            "Chromium not found: the live particle filter's JavaScript-vs-probrob parity tests "
            "need it (apt-get install chromium); CI installs it and runs them"
        )
        if os.environ.get("PROBROB_REQUIRE_BROWSER") == "1":
            pytest.fail(message)
        pytest.skip(message)
    b = cdp.Browser(executable, timeout=60)
    try:
        yield cdp, b
    finally:
        b.close()


INTEL = None  # built once, on first use (its map and fit take a few seconds)


def _worlds():
    global INTEL
    if INTEL is None:
        INTEL = _intel() or {}
    return {"room": ROOM} | ({"intel": INTEL} if INTEL else {})


@pytest.fixture(scope="module")
def page(browser, tmp_path_factory):
    """Widget 0: the room (n_max 1000); widget 1: the Intel lab's first 100 steps as the
    chapter shows it (defaults), if its log is present."""
    cdp, b = browser
    worlds = _worlds()
    widgets = {"room": particle_filter_live(**ROOM, **ROOM_KW, rng=0)}
    if "intel" in worlds:
        widgets["intel"] = particle_filter_live(**worlds["intel"])
    path = tmp_path_factory.mktemp("live_mcl") / "mcl.html"
    body = "\n".join(w.html for w in widgets.values())
    path.write_text(f"<!doctype html><meta charset='utf-8'><body>{body}</body>", "utf-8")
    tab = cdp.Tab.open(b, path.as_uri())
    tab.configs = [_config(w) for w in widgets.values()]
    tab.widgets = {name: (k, w) for k, (name, w) in enumerate(widgets.items())}
    tab.worlds = worlds
    yield tab
    assert tab.exceptions() == []
    tab.close()


def _floats(b64):
    return np.frombuffer(base64.b64decode(b64), "<f8")


def _set(page, index, values):
    state = page.js(
        f"(() => {{ const w = probrobLive.widgets[{index}]; w.set(w.defaults());"
        f" return w.set({json.dumps(values)}); }})()",
        timeout=120,
    )
    return _decode(state)


def _decode(state):
    state["particles"] = _floats(state["particles"]).reshape(-1, 3)
    for key in ("logW", "weights"):
        if state[key] is not None:
            state[key] = _floats(state[key])
    return state


class Replay(np.random.Generator):
    """A numpy Generator that hands :mod:`probrob.mcl` the random numbers the page embeds, in
    the order the page uses them (:func:`probrob.live.mcl.particle_filter_draws`): the
    low-variance sampler's offsets (``uniform()``), augmented MCL's binomial count and random
    particles, KLD-sampling's permutations; its ``sample`` is the motion model's sampler. It
    follows the steps through :func:`probrob.mcl.run_mcl`'s ``on_step`` (``next_step``)."""

    def __init__(self, dec, n_max):
        super().__init__(np.random.PCG64(0))
        self.dec, self.n_max = dec, n_max
        self.flat = dec["uniforms"].ravel()  # the pool U of 4 n_max uniforms
        self.t = 0
        self.counts = {}  # step -> the binomial count of random particles drawn
        self.next_step()

    def next_step(self):
        self.t += 1
        self.round = self.calls = self.base = self.cursor = 0
        self.rows = None

    def sample(self, b2, size=None, rng=None):
        """Noise term k of particle base + i of the step: sqrt(b2) times the pool at the
        step's offset k (particle i of MCL is particle i of the step; KLD-sampling's rounds
        go on counting)."""
        pool, off, k = self.dec["normal"], self.dec["offsets"][self.t - 1], self.calls % 3
        (length,) = size
        z = pool[(off[k] + self.base + np.arange(length)) % pool.size]
        self.calls += 1
        if k == 2:
            self.base += length
        return np.sqrt(b2) * z

    def uniform(self, low=0.0, high=1.0, size=None):
        if size is None:  # Table 4.4, line 3: one offset per draw (per round of Table 8.4)
            r, self.round = self.round, self.round + 1
            t = self.t - 1
            return (
                self.dec["resample"][t] if r == 0 else self.dec["rounds"][t, (r - 1) % PF_ROUNDS]
            )
        assert (low, high) == (-np.pi, np.pi) and size == len(self.rows)  # uniform_particles
        return -np.pi + (2.0 * np.pi) * self.rows[:, 3]

    def binomial(self, n, p, size=None):
        start = self.dec["shuffle"][self.t - 1, 0]
        u = self.flat[(start + np.arange(n)) % self.flat.size]
        self.counts[self.t] = int(np.count_nonzero(u < p))
        return self.counts[self.t]

    def integers(self, low, high=None, size=None, **kw):  # uniform_particles' cells
        rows = (self.dec["shuffle"][self.t - 1, 1] + np.arange(size)) % self.n_max
        self.rows = self.dec["uniforms"][rows]
        return np.floor(self.rows[:, 0] * low).astype(np.intp)

    def random(self, size=None, **kw):  # uniform_particles' points inside their cells
        assert size == (len(self.rows), 2)
        return self.rows[:, 1:3]

    def permutation(self, x):  # Fisher-Yates from the last index down, on U from the start s
        a, start = np.array(x), self.dec["shuffle"][self.t - 1, 0]
        for i in range(a.size - 1, 0, -1):
            j = int(np.floor(self.flat[(start + self.cursor) % self.flat.size] * (i + 1)))
            self.cursor += 1
            a[i], a[j] = a[j], a[i]
        return a


class Reference:
    """probrob.mcl run on what the widget embeds, for the widget's values ``v`` (its sliders
    and choices)."""

    def __init__(self, world, widget, v):
        self.world, self.dec, self.v = world, particle_filter_decoded(widget), v
        cfg = _config(widget)
        self.n_max = cfg["nMax"]
        p = world["params"]
        z_sum = p.z_hit + p.z_rand  # the sum the share splits (held at params')
        self.params = BeamModelParams(
            z_sum * (1 - v["zrand"]),
            p.z_short,
            p.z_max,
            z_sum * v["zrand"],
            v["sigma"],
            p.lambda_short,
            p.max_range,
        )
        self.alpha = [v["a1"], v["a2"], v["a3"], v["a4"]]
        self.sel = particle_filter_beams(len(world["beam_angles"]), int(v["beams"]))
        self.n = int(v["n"])
        self.method = v.get("method", "mcl")
        self.sensor = v.get("sensor", "likelihood_field")
        self.kidnap = int(v.get("kidnap", 0))

    def initial(self):
        n, z, m = self.n, self.dec["normal"], self.n_max
        if self.v["start"] == "global":
            return M.uniform_particles(self.world["grid"], n, uniforms=self.dec["uniforms"][:n])
        return self.dec["truth"][0] + SPREAD * np.stack(
            [z[:n], z[m : m + n], z[2 * m : 2 * m + n]], 1
        )

    def options(self, replay):
        out = dict(sensor=self.sensor, exponent=self.v["kappa"], sample=replay.sample)
        if self.method == "augmented":
            out |= dict(alpha_slow=self.v["aslow"], alpha_fast=self.v["afast"])
        if self.method == "kld":
            out |= dict(
                epsilon=self.v["eps"],
                delta=self.v["delta"],
                bin_size=PF_KLD_BINS,
                n_min=PF_KLD_N_MIN,
                n_max=self.n_max,
            )
        return out

    def run(self, steps):
        """Per step t = 0 .. steps: a dict of X_t, its weights (KLD-sampling) and the
        log-weights the page reports (MCL, augmented: of the moved particles before resampling;
        KLD-sampling: of X_t), the estimate and its fraction, w_slow, w_fast and the random
        particles of the step."""
        from probrob.motion import sample_motion_model_odometry

        truth = self.dec["truth"]
        replay = Replay(self.dec, self.n_max)
        angles = self.dec["beam_angles"][self.sel]
        lw = functools.partial(
            M.measurement_log_weights,
            grid=self.world["grid"],
            beam_angles=angles,
            params=self.params,
            sensor=self.sensor,
            exponent=self.v["kappa"],
        )

        before = {}

        def on_step(t, x):
            replay.next_step()
            before[t] = x
            if t == self.kidnap:
                s = particle_filter_kidnap_target(truth, t)
                return x - truth[t] + truth[s]
            return None

        res = M.run_mcl(
            self.initial(),
            self.dec["odometry"][:steps],
            self.dec["scans"][:steps, self.sel],
            self.world["grid"],
            angles,
            self.alpha,
            self.params,
            method=self.method,
            keep=range(steps + 1),
            rng=replay,
            on_step=on_step,
            **self.options(replay),
        )
        out = []
        for t in range(steps + 1):
            x = res.snapshots[t]
            log_w = None
            if t and self.method == "kld":  # of X_t (before a kidnapping moves it)
                log_w = lw(before[t], self.dec["scans"][t - 1, self.sel])
            elif t:  # the moved particles of step t, as the page moves them
                motion = Replay(self.dec, self.n_max)
                motion.t = t
                x_bar = sample_motion_model_odometry(
                    self.dec["odometry"][t - 1], out[t - 1]["x"], self.alpha, sample=motion.sample
                )
                log_w = lw(x_bar, self.dec["scans"][t - 1, self.sel])
            out.append(
                dict(
                    x=x,
                    w=res.snapshot_weights[t],
                    log_w=log_w,
                    estimate=res.estimates[t],
                    fraction=res.fraction[t],
                    w_slow=res.w_slow[t],
                    w_fast=res.w_fast[t],
                    random=replay.counts.get(t, 0),
                )
            )
        return out


def _close(js, py, what):
    assert js.shape == py.shape, what
    np.testing.assert_allclose(js, py, rtol=TOL, atol=TOL, err_msg=what)


def _check_run(page, name, values, steps=None):
    """Set ``values`` on the widget of world ``name``; compare every step with probrob."""
    index, widget = page.widgets[name]
    state = _set(page, index, values)
    world = page.worlds[name]
    ref = Reference(world, widget, state["values"])
    steps = len(world["odometry"]) if steps is None else steps
    run = ref.run(steps)
    truth = world["truth"]
    errors = []
    for t in range(steps + 1):
        st = _decode(page.js(f"probrobLive.widgets[{index}].set({{t: {t}}})"))
        py = run[t]
        what = f"{name} {values} step {t}"
        _close(st["particles"], py["x"], f"{what}: particles")
        assert st["size"] == len(py["x"]), what
        if t:
            # -inf (off the map) where probrob has -inf, the finite values equal
            lw = py["log_w"]
            assert np.array_equal(np.isfinite(st["logW"]), np.isfinite(lw)), what
            ok = np.isfinite(lw)
            _close(st["logW"][ok], lw[ok], f"{what}: log-weights")
        if ref.method == "kld":
            _close(st["weights"] if t else np.full(ref.n, 1 / ref.n), py["w"], f"{what}: weights")
        if ref.method == "augmented":
            _close(np.array([st["wSlow"], st["wFast"]]), np.array([py["w_slow"], py["w_fast"]]),
                   f"{what}: w_slow, w_fast")  # fmt: skip
            if st["random"] < st["size"]:
                assert st["random"] == py["random"], what
        _close(np.array(st["estimate"]), py["estimate"], f"{what}: estimate")
        assert st["fraction"] == pytest.approx(py["fraction"], rel=TOL), what
        pos = np.hypot(*(py["estimate"][:2] - truth[t, :2]))
        _close(np.array(st["error"][:1]), np.array([pos]), f"{what}: error")
        errors.append(pos)
    return state, run, np.array(errors)


ROOM_SETTINGS = {
    "as shipped (known start)": {},
    "distinct α, σ, share, exponent; 37 beams": dict(
        a1=0.031, a2=0.012, a3=0.0234, a4=0.0071, sigma=0.211, zrand=0.27, kappa=0.43, beams=37
    ),
    "global start, 1000 particles": dict(start="global", n=1000, kappa=0.3),
    "no random readings (z_rand = 0: -inf far from walls)": dict(zrand=0.0, sigma=0.3),
    "only random readings (z_hit = 0: equal weights)": dict(zrand=1.0),
    "one beam, no motion noise": dict(beams=1, a1=0, a2=0, a3=0, a4=0),
    "100 particles, wide noise, narrow σ": dict(n=100, a1=0.4, a2=0.2, a3=0.3, a4=0.1, sigma=0.01),
}


@pytest.mark.parametrize("name", list(ROOM_SETTINGS))
def test_room_widget_runs_what_probrob_runs(page, name):
    _, run, errors = _check_run(page, "room", ROOM_SETTINGS[name])
    # not vacuous: the particles move and resampling happens
    x0, x1 = run[0]["x"], run[1]["x"]
    assert not np.allclose(x0, x1)
    if name == "as shipped (known start)":
        assert errors.max() < 0.5  # tracking holds on the room (a sanity check of the log)
    if name == "global start, 1000 particles":
        assert errors[0] > 1.0  # the uniform start is far from the robot


# Each sensor with each method: (likelihood field | beam model) x (MCL | augmented | KLD), and
# the kidnapping. Augmented MCL's rates are set so that it injects random particles within
# the 40 steps of the room (checked below: the settings are not vacuous).
MODE_SETTINGS = {
    "beam model, as shipped": dict(sensor="beam"),
    "beam model, distinct α, σ, share, exponent; 37 beams": dict(
        sensor="beam", a1=0.031, a2=0.012, a3=0.0234, a4=0.0071, sigma=0.211, zrand=0.27,
        kappa=0.43, beams=37,
    ),
    "beam model, global start, 1000 particles": dict(sensor="beam", start="global", n=1000,
                                                      kappa=0.3),
    "beam model, no random readings (z_rand = 0)": dict(sensor="beam", zrand=0.0, sigma=0.05),
    "augmented, kidnapped after step 12": dict(method="augmented", kidnap=12, aslow=0.02,
                                                afast=0.3, kappa=0.2),
    "augmented, beam model, kidnapped after step 20": dict(
        method="augmented", sensor="beam", kidnap=20, aslow=0.03, afast=0.5, kappa=0.15
    ),
    "augmented, global start, kidnapped after step 25": dict(
        method="augmented", start="global", n=600, aslow=0.04, afast=0.9, kappa=0.1, kidnap=25
    ),
    "KLD-sampling, known start": dict(method="kld"),
    "KLD-sampling, global start, ε 0.1, δ 0.05": dict(method="kld", start="global", n=1000,
                                                       eps=0.1, delta=0.05, kappa=0.3),
    "KLD-sampling, beam model, global start": dict(method="kld", sensor="beam", start="global",
                                                    n=1000, kappa=0.3),
    "KLD-sampling, kidnapped after step 15": dict(method="kld", kidnap=15, eps=0.02,
                                                   delta=0.123),
    "MCL, beam model, kidnapped after step 5": dict(sensor="beam", kidnap=5),
}  # fmt: skip


@pytest.mark.parametrize("name", list(MODE_SETTINGS))
def test_room_widget_modes_run_what_probrob_runs(page, name):
    """Every sensor and method, step by step, against probrob.mcl.run_mcl on the same numbers."""
    state, run, errors = _check_run(page, "room", MODE_SETTINGS[name])
    v = state["values"]
    sizes = np.array([len(r["x"]) for r in run])
    random = np.array([r["random"] for r in run])
    if v["method"] == "augmented":
        assert random.sum() > 0, "no random particle: the setting tests nothing of Table 8.3"
        assert np.all(sizes == v["n"])
    if v["method"] == "kld":
        assert len(set(sizes[1:])) > 1, "the set size never changed"
        assert sizes.min() >= PF_KLD_N_MIN and sizes.max() <= 1000
    if v["kidnap"]:
        k = int(v["kidnap"])
        assert (errors[k] > 2.0 and errors[k - 1] < 1.0) or v["start"] == "global"


def test_room_widget_distance_field_is_exact(page):
    index, _ = page.widgets["room"]
    d = _floats(page.js(f"probrobLive.widgets[{index}].field()"))
    np.testing.assert_array_equal(d.reshape(ROOM["grid"].shape), ROOM["grid"].distance_field)


def test_room_widget_anywhere_on_the_sliders(page):
    """8 seeded random settings: every slider uniform on its range (t kept at the end)."""
    index, _ = page.widgets["room"]
    config = page.js(f"probrobLive.widgets[{index}].config()")
    rng = np.random.default_rng(11)
    for _ in range(8):
        values = {}
        for s in config["sliders"]:
            if s["name"] == "t":
                continue
            v = s["min"] + rng.random() * (s["max"] - s["min"])
            if s["name"] in ("beams", "n"):
                step = 100 if s["name"] == "n" else 1
                v = float(round(v / step) * step)
            values[s["name"]] = max(s["min"], v)
        values["start"] = str(rng.choice(["known", "global"]))
        values["sensor"] = str(rng.choice(["likelihood_field", "beam"]))
        values["method"] = str(rng.choice(["mcl", "augmented", "kld"]))
        values["kidnap"] = float(rng.integers(0, 13))
        _check_run(page, "room", values, steps=12)


def test_the_comparison_is_sharp(page):
    """Each parameter, mis-wired in the reference, breaks the parity (so a kernel that swaps
    two α, drops the exponent, uses z_hit for z_rand or skips a draw offset fails the tests)."""
    index, widget = page.widgets["room"]
    values = ROOM_SETTINGS["distinct α, σ, share, exponent; 37 beams"]
    state = _set(page, index, dict(values, t=6))
    js = state["particles"]
    v = state["values"]
    swaps = {
        "α1 <-> α2": dict(a1=v["a2"], a2=v["a1"]),
        "α3 <-> α4": dict(a3=v["a4"], a4=v["a3"]),
        "α1 <-> α3": dict(a1=v["a3"], a3=v["a1"]),
        "σ_hit + 1 %": dict(sigma=v["sigma"] * 1.01),
        "z_hit <-> z_rand": dict(zrand=1 - v["zrand"]),
        "exponent 1": dict(kappa=1.0),
        "one beam less": dict(beams=v["beams"] - 1),
    }
    assert np.allclose(Reference(ROOM, widget, v).run(6)[6]["x"], js, rtol=TOL, atol=TOL)
    for what, change in swaps.items():
        x = Reference(ROOM, widget, {**v, **change}).run(6)[6]["x"]
        assert np.abs(x - js).max() > 1e3 * TOL, what


SHARP_MODES = {
    "augmented MCL": (
        "augmented, kidnapped after step 12",
        20,
        lambda v: {
            "α_fast + 1 %": dict(afast=v["afast"] * 1.01),
            "α_slow + 1 %": dict(aslow=v["aslow"] * 1.01),
            "α_slow <-> α_fast": dict(aslow=v["afast"], afast=v["aslow"] + 0.5),
            "kidnapped a step later": dict(kidnap=v["kidnap"] + 1),
            "plain MCL": dict(method="mcl"),
        },
    ),
    "KLD-sampling": (
        "KLD-sampling, global start, ε 0.1, δ 0.05",
        8,
        lambda v: {
            "ε + 1 %": dict(eps=v["eps"] * 1.01),
            "δ one step more": dict(delta=v["delta"] + 0.001),
            "plain MCL": dict(method="mcl"),
        },
    ),
    "beam model": (
        "beam model, distinct α, σ, share, exponent; 37 beams",
        6,
        lambda v: {
            "likelihood field": dict(sensor="likelihood_field"),
            "σ_hit + 1 %": dict(sigma=v["sigma"] * 1.01),
            "z_hit <-> z_rand": dict(zrand=1 - v["zrand"]),
            "exponent 1": dict(kappa=1.0),
        },
    ),
}


@pytest.mark.parametrize("mode", list(SHARP_MODES))
def test_the_comparison_is_sharp_for_every_mode(page, mode):
    """A mis-set parameter of augmented MCL (α_fast, α_slow, the kidnapping), of KLD-sampling
    (ε, δ) or of the beam model (σ_hit, the mixture, the sensor itself), given to the reference
    instead of the page's, breaks the parity of the particles (and of w_fast)."""
    index, widget = page.widgets["room"]
    setting, t, changes = SHARP_MODES[mode]
    state = _set(page, index, dict(MODE_SETTINGS[setting], t=t))
    js, v = state["particles"], state["values"]
    right = Reference(ROOM, widget, v).run(t)[t]
    _close(js, right["x"], mode)
    for what, change in changes(v).items():
        wrong = Reference(ROOM, widget, {**v, **change}).run(t)[t]
        x = wrong["x"]
        assert x.shape != js.shape or np.abs(x - js).max() > 1e3 * TOL, what
        if what == "α_fast + 1 %":
            assert abs(wrong["w_fast"] / state["wFast"] - 1) > 1e3 * TOL, what


def test_intel_widget_runs_what_probrob_runs(page):
    if "intel" not in page.worlds:
        pytest.skip("Intel lab log absent: the room runs the same parity tests")
    state, _, errors = _check_run(page, "intel", {})
    assert state["n"] == 500 and len(state["beams"]) == 60
    assert np.median(errors) < 0.3  # the chapter's tracking, in the page
    _check_run(page, "intel", dict(start="global", n=2000, beams=30, kappa=0.1), steps=30)
    # the other sensor and methods on the real map and log
    _check_run(page, "intel", dict(sensor="beam"), steps=30)
    _check_run(page, "intel", dict(method="augmented", kidnap=40, kappa=0.05), steps=60)
    kld = dict(method="kld", sensor="beam", start="global", n=2000, kappa=0.1)
    _, run, _ = _check_run(page, "intel", kld, steps=20)
    assert len(run[0]["x"]) == 2000 and len(run[20]["x"]) < 2000  # the set shrinks


def test_intel_widget_size_and_field(page):
    if "intel" not in page.worlds:
        pytest.skip("Intel lab log absent")
    index, widget = page.widgets["intel"]
    assert len(widget.html.encode()) < 400_000
    d = _floats(page.js(f"probrobLive.widgets[{index}].field()"))
    np.testing.assert_array_equal(d.reshape(INTEL["grid"].shape), INTEL["grid"].distance_field)


JS_CANVAS_HASH = """
(() => {
  const s = document.querySelectorAll(".probrob-live canvas")[%d].toDataURL();
  let h = 0;
  for (let i = 0; i < s.length; i++) h = (h * 31 + s.charCodeAt(i)) | 0;
  return h;
})()
"""
JS_FRAMES = "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))"


def test_keyboard_steps_the_filter_and_the_buttons_play_it(page):
    index, _ = page.widgets["room"]
    w = f"probrobLive.widgets[{index}]"
    root = f"document.querySelectorAll('.probrob-live')[{index}]"
    page.js(f"{w}.set({w}.defaults())")
    before = page.js(JS_CANVAS_HASH % index)
    page.js(f"{root}.querySelector('input[type=range][data-param=t]').focus()")
    for _ in range(3):
        page.key("ArrowRight", "ArrowRight", 39)
    page.js(JS_FRAMES)
    assert page.js(f"{w}.values().t") == 3
    assert page.js(f"{root}.querySelector('input[type=number][data-param=t]').value") == "3"
    assert page.js(JS_CANVAS_HASH % index) != before
    status = page.js(f"{root}.querySelector('.pl-status').textContent")
    assert status.startswith("Step 3 of 40: the estimate is")
    # step, play (runs to the end by itself), to start, reset
    page.js(f"{root}.querySelector('[data-action=step]').click()")
    assert page.js(f"{w}.values().t") == 4
    page.js(f"{root}.querySelector('[data-action=play]').click()")
    assert (
        page.js(f"{root}.querySelector('[data-action=play]').getAttribute('aria-pressed')")
        == "true"
    )
    play = f"{root}.querySelector('[data-action=play]')"
    page.js(
        f"new Promise(r => {{ const k = setInterval(() => {{ if ({play}.textContent === 'play')"
        " { clearInterval(k); r(); } }, 50); })",
        timeout=60,
    )  # play stops by itself at the last step
    assert page.js(f"{w}.values().t") == 40
    assert page.js(f"{play}.getAttribute('aria-pressed')") == "false"
    page.js(f"{root}.querySelector('[data-action=start]').click()")
    assert page.js(f"{w}.values().t") == 0
    page.js(f"{w}.set({{a1: 0.2, n: 600}})")
    page.js(f"{root}.querySelector('[data-action=reset]').click()")
    assert page.js(f"JSON.stringify({w}.values()) === JSON.stringify({w}.defaults())")


@pytest.mark.parametrize(
    "sensor, method",
    [(s, m) for s in ("likelihood_field", "beam") for m in ("mcl", "augmented", "kld")],
)
def test_bench_hook_times_filter_steps(page, sensor, method):
    """The bench hook (benchmarks/bench_live_mcl.py) times every sensor and method."""
    index, _ = page.widgets["room"]
    w = f"probrobLive.widgets[{index}]"
    page.js(f"{w}.set({{t: 7, n: 400, sensor: '{sensor}', method: '{method}', kidnap: 3}})")
    before = page.js(f"{w}.state()")
    out = page.js(f"{w}.bench(60)", timeout=120)  # 60 steps: the run of 40 restarts once
    assert out["count"] == 60
    for key in ("compute", "draw", "total"):
        assert 0 <= out[key]["median"] <= out[key]["p90"] <= out[key]["max"]
    # the hook leaves the widget as it found it
    after = page.js(f"{w}.state()")
    for key in ("values", "particles", "estimate"):
        assert after[key] == before[key], key


def _estimate_cases():
    rng = np.random.default_rng(23)
    opposite = np.r_[np.zeros((50, 3)), np.tile([0.05, 0.0, np.pi], (50, 1))]
    across = np.c_[rng.normal(3.0, 0.1, (200, 2)), np.pi + rng.normal(0.0, 0.2, 200)]
    two_headings = np.c_[rng.normal(1.0, 0.05, (300, 2)), rng.choice([0.3, 2.5], 300)]
    spread = np.c_[rng.uniform(-5, 5, (400, 2)), rng.uniform(-10, 10, 400)]  # any θ, unwrapped
    return {
        "50 at θ = 0 and 50 at θ = π, 5 cm apart (issue 23, item 2)": opposite,
        "a cloud across ±π": across,
        "one place, two headings": two_headings,
        "uniform in x, y and θ": spread,
    }


@pytest.mark.parametrize("name", list(_estimate_cases()))
def test_estimate_pose_in_javascript_is_probrobs(browser, tmp_path, name):
    """mcl.js's estimatePose equals probrob.mcl.estimate_pose on hand-made sets: the heading
    sectors, their wrap at ±π and the tie order (issue 23, item 2)."""
    from probrob.live.core import asset

    cdp, b = browser
    x = _estimate_cases()[name]
    page = tmp_path / "estimate.html"
    kernel = [asset(name) for name in ("runtime.js", "draw.js", "maths.js", "mcl_filter.js")]
    script = "\n".join([*kernel, "window.estimatePose = estimatePose;"])
    page.write_text(f"<!doctype html><meta charset='utf-8'><script>{script}</script>", "utf-8")
    tab = cdp.Tab.open(b, page.as_uri())
    try:
        js = tab.js(
            f"estimatePose({json.dumps(x.ravel().tolist())}, {len(x)}, {PF_RADIUS}, "
            f"{PF_HEADING_BINS})"
        )
    finally:
        tab.close()
    est = M.estimate_pose(x, radius=PF_RADIUS, heading_bins=PF_HEADING_BINS)
    _close(np.array(js["pose"]), est.pose, name)
    assert js["fraction"] == pytest.approx(est.fraction, rel=TOL), name


def _base():
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "probrob_test_live_mcl_base", ROOT / "tests" / "test_live_widgets.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_controls_mode_and_width(page):
    """The controls built from the spec (four buttons, a status line read aloud); the map in
    the dark mode's colours; the plot at least 250 CSS px wide on a phone."""
    base = _base()
    base.assert_controls_built_from_the_spec(page, page.configs)
    index, _ = page.widgets["room"]
    try:
        dark = page.js(base.JS_MODE % json.dumps("dark"))[index]
        assert dark["mode"] == "dark" and base._luminance(dark["corner"]) < 60
        assert "White: occupied" in dark["caption"] and "dark: free" in dark["caption"]
    finally:
        page.js(base.JS_MODE % "null")
    try:
        base.phone(page, True)
        base.assert_plots_fit(page.js(base.JS_PLOTS % json.dumps(358)))
    finally:
        base.phone(page, False)
        page.js(base.JS_PLOTS % "null")
