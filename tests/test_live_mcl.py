"""The live particle filter (probrob.live.mcl.particle_filter_live): its HTML, and its JavaScript
held equal to probrob.mcl.

The page's JavaScript (``probrob/live/assets/mcl.js``) is a second implementation of Table 8.2 with
the odometry sampler (Table 5.6), the likelihood field (Table 6.3, with its exact distance
field) and the low-variance sampler (Table 4.4). The parity tests open the widget in headless
Chromium (the driver of ``.ci/cdp.py``, as tests/test_live_widgets.py), set its sliders through
the test hook and compare, at every step of the run, its particles, their log-weights before
resampling and its pose estimate with :func:`probrob.mcl.mcl` and
:func:`probrob.mcl.estimate_pose` fed the same random numbers (the embedded draws, replayed by
the ``sample=`` and ``resample_offset=`` keywords): to 1e-9, relative (absolute below 1). A
run on a synthetic room needs no data; the Intel lab's stretch runs when its log is present.
Without Chromium the browser tests are skipped, unless ``PROBROB_REQUIRE_BROWSER=1``.
"""

from __future__ import annotations

import base64
import json
import os
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from probrob import mcl as M
from probrob.live.mcl import (
    PF_HEADING_BINS,
    PF_RADIUS,
    particle_filter_beams,
    particle_filter_decoded,
    particle_filter_draws,
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
    scans = np.clip(scans + rng.normal(0, 0.03, scans.shape), 0.0, max_range)
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
    assert names == ["t", "a1", "a2", "a3", "a4", "sigma", "zrand", "beams", "kappa", "n"]
    assert all(p["label"] for p in config["sliders"] + config["choices"])
    assert [c["name"] for c in config["choices"]] == ["start", "view"]
    assert [a for a, _ in config["buttons"]] == ["step", "play", "start", "reset"]
    assert config["status"] is True  # a status line, aria-live
    assert [s["name"] for s in config["sliders"] if s.get("snap")] == ["t", "beams", "n"]
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
    for name in ("normal", "offsets", "resample", "uniforms"):
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
    ]
    for kw, name in cases:
        with pytest.raises(ValueError, match=name):
            make(**kw)
    p = ROOM["params"]
    far = BeamModelParams(p.z_hit, p.z_short, p.z_max, p.z_rand, p.sigma_hit, p.lambda_short, 80.0)
    with pytest.raises(ValueError, match="scans"):
        make(params=far, scans=np.full_like(ROOM["scans"], 70.0))


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
    if state["logW"] is not None:
        state["logW"] = _floats(state["logW"])
    return state


class Reference:
    """probrob.mcl run on what the widget embeds, for the widget's slider values ``v``."""

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

    def initial(self):
        n, z, m = self.n, self.dec["normal"], self.n_max
        if self.v["start"] == "global":
            return M.uniform_particles(self.world["grid"], n, uniforms=self.dec["uniforms"][:n])
        return self.dec["truth"][0] + SPREAD * np.stack(
            [z[:n], z[m : m + n], z[2 * m : 2 * m + n]], 1
        )

    def sampler(self, t):
        """The motion sampler of step t (1-based): sqrt(b²) times the pool at three offsets."""
        pool, off, n = self.dec["normal"], self.dec["offsets"][t - 1], self.n
        rows = iter(range(3))

        def sample(b2, size=None, rng=None):
            k = next(rows)
            assert size == (n,)
            return np.sqrt(b2) * pool[(off[k] + np.arange(n)) % pool.size]

        return sample

    def run(self, steps):
        """[(X_t, log-weights of step t before resampling)] for t = 0 .. steps."""
        from probrob.motion import sample_motion_model_odometry

        x = self.initial()
        out = [(x, None)]
        for t in range(1, steps + 1):
            u, z = self.dec["odometry"][t - 1], self.dec["scans"][t - 1, self.sel]
            angles = self.dec["beam_angles"][self.sel]
            x_bar = sample_motion_model_odometry(u, x, self.alpha, sample=self.sampler(t))
            lw = M.measurement_log_weights(
                x_bar, z, self.world["grid"], angles, self.params, exponent=self.v["kappa"]
            )
            x = M.mcl(
                x,
                u,
                z,
                self.world["grid"],
                angles,
                self.alpha,
                self.params,
                exponent=self.v["kappa"],
                sample=self.sampler(t),
                resample_offset=float(self.dec["resample"][t - 1]),
            )
            out.append((x, lw))
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
        x, lw = run[t]
        what = f"{name} {values} step {t}"
        _close(st["particles"], x, f"{what}: particles")
        if t:
            # -inf (off the map) where probrob has -inf, the finite values equal
            assert np.array_equal(np.isfinite(st["logW"]), np.isfinite(lw)), what
            ok = np.isfinite(lw)
            _close(st["logW"][ok], lw[ok], f"{what}: log-weights")
        est = M.estimate_pose(x, radius=PF_RADIUS, heading_bins=PF_HEADING_BINS)
        _close(np.array(st["estimate"]), est.pose, f"{what}: estimate")
        assert st["fraction"] == pytest.approx(est.fraction, rel=TOL), what
        pos = np.hypot(*(est.pose[:2] - truth[t, :2]))
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
    x0, x1 = run[0][0], run[1][0]
    assert not np.allclose(x0, x1)
    if name == "as shipped (known start)":
        assert errors.max() < 0.5  # tracking holds on the room (a sanity check of the log)
    if name == "global start, 1000 particles":
        assert errors[0] > 1.0  # the uniform start is far from the robot


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
    assert np.allclose(Reference(ROOM, widget, v).run(6)[6][0], js, rtol=TOL, atol=TOL)
    for what, change in swaps.items():
        x = Reference(ROOM, widget, {**v, **change}).run(6)[6][0]
        assert np.abs(x - js).max() > 1e3 * TOL, what


def test_intel_widget_runs_what_probrob_runs(page):
    if "intel" not in page.worlds:
        pytest.skip("Intel lab log absent: the room runs the same parity tests")
    state, _, errors = _check_run(page, "intel", {})
    assert state["n"] == 500 and len(state["beams"]) == 60
    assert np.median(errors) < 0.3  # the chapter's tracking, in the page
    _check_run(page, "intel", dict(start="global", n=2000, beams=30, kappa=0.1), steps=30)


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


def test_bench_hook_times_filter_steps(page):
    index, _ = page.widgets["room"]
    w = f"probrobLive.widgets[{index}]"
    page.js(f"{w}.set({{t: 7, n: 400}})")
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
    kernel = [asset(name) for name in ("runtime.js", "draw.js", "maths.js", "mcl.js")]
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
