"""The numbers of the book's prose pages (``book/*.md``), recomputed.

No kernel runs on these pages, so a number they state cannot come from a cell: each test
reads the page, finds the sentence, and asserts that the page's number equals the
recomputed one at the precision the page prints it. (``book/performance.md`` holds timings
measured on one machine, which no test can recompute; the load times of ``datasets.md`` are
such timings too.)
"""

import re
from pathlib import Path

import numpy as np
import pytest

from probrob import datasets
from probrob.datasets import DatasetNotFoundError

ROOT = Path(__file__).parent.parent
BOOK = ROOT / "book"


def page(name):
    """The page's text with every run of whitespace one space (line wrapping ignored)."""
    return " ".join((BOOK / name).read_text(encoding="utf-8").split())


def find(name, pattern):
    """The groups of the one match of ``pattern`` on the page (the sentence must be there)."""
    matches = list(re.finditer(pattern, page(name)))
    assert len(matches) == 1, f"{name}: {len(matches)} matches of {pattern!r}"
    return matches[0].groups()


def printed(value, text):
    """``value`` formatted with as many decimals as ``text`` prints (``"66"``, ``"81.83"``,
    ``"2,578"``)."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return f"{value:,.{decimals}f}" if "," in text else f"{value:.{decimals}f}"


def _load(loader, *args):
    try:
        return loader(*args)
    except DatasetNotFoundError as exc:
        pytest.skip(f"dataset absent: {exc.file}")


@pytest.fixture(scope="module")
def mrclam():
    return _load(datasets.load_mrclam)


@pytest.fixture(scope="module")
def intel():
    return _load(datasets.load_intel_lab)


@pytest.fixture(scope="module")
def walls():
    return {mm: _load(datasets.load_lnpr_wall, mm) for mm in (200, 600)}


# --------------------------------------------------------------------------- datasets.md


def test_mrclam_duration_rates_and_subjects(mrclam):
    minutes, cmd_hz, landmarks, robots, gt_hz = find(
        "datasets.md",
        r"robot 1: (\d+) min of velocity commands \(~(\d+) Hz\), camera range–bearing to "
        r"(\d+) barcoded landmarks and (\d+) robots, Vicon ground truth \(~(\d+) Hz\)",
    )
    t = mrclam.odometry_t
    assert printed((t[-1] - t[0]) / 60, minutes) == minutes
    assert printed((t.size - 1) / (t[-1] - t[0]), cmd_hz) == cmd_hz
    g = mrclam.ground_truth_t
    assert printed((g.size - 1) / (g[-1] - g[0]), gt_hz) == gt_hz
    assert len(mrclam.landmarks) == int(landmarks)
    assert np.unique(mrclam.sighted_robot).size == int(robots)


def test_mrclam_counts(mrclam):
    sightings, robot_sightings = find(
        "datasets.md",
        r"The ([\d,]+) landmark sightings go to `measurements`.*?the ([\d,]+) sightings of "
        r"other robots go to `sightings`",
    )
    assert printed(len(mrclam.measurement_t), sightings) == sightings
    assert printed(len(mrclam.sighting_t), robot_sightings) == robot_sightings
    (steps,) = find("datasets.md", r"between consecutive commands, ([\d,]+) in all")
    stream = mrclam.stream()
    assert printed(len(stream), steps) == steps
    (typical,) = find("datasets.md", r"\(typically ([\d.]+) s\)")
    assert printed(np.median([s.dt for s in stream]), typical) == typical
    # "this recording has neither, so every landmark measurement appears exactly once"
    assert "this recording has neither" in page("datasets.md")
    assert mrclam.measurement_t.min() > mrclam.odometry_t[0]
    assert mrclam.measurement_t.max() <= mrclam.odometry_t[-1]
    assert sum(len(s.z) for s in stream) == len(mrclam.measurement_t)


def test_mrclam_shapes_and_barcodes(mrclam):
    lm, std = find(
        "datasets.md", r"robot\.landmarks, robot\.landmark_std # \((\d+), 3\): .*?; \((\d+), 2\)"
    )
    assert mrclam.landmarks.shape == (int(lm), 3) and mrclam.landmark_std.shape == (int(std), 2)
    r_lo, r_hi, l_lo, l_hi = find(
        "datasets.md", r"\(subjects (\d+)–(\d+) are robots, (\d+)–(\d+) landmarks\)"
    )
    subjects = mrclam.barcodes[:, 0]
    assert (subjects.min(), subjects.max()) == (int(r_lo), int(l_hi))
    assert set(mrclam.landmark_subject) == set(range(int(l_lo), int(l_hi) + 1))
    assert int(r_hi) + 1 == int(l_lo)


def test_intel_lab_numbers(intel):
    scans, beams = find("datasets.md", r"CARMEN log: (\d+) laser scans of (\d+) beams")
    assert intel.ranges.shape == (int(scans), int(beams))
    n1, n2, n3, b3 = find(
        "datasets.md", r"scans\.ranges # \((\d+),\), \((\d+), 3\), \((\d+), (\d+)\)"
    )
    assert intel.t.shape == (int(n1),) and intel.poses.shape == (int(n2), 3)
    assert intel.ranges.shape == (int(n3), int(b3))
    first, last, max_range = find(
        "datasets.md", r"# \(180,\) −(\d+)°…\+(\d+)° from the heading; ([\d.]+) m"
    )
    degrees = np.degrees(intel.beam_angles)
    assert printed(degrees[0], first) == f"-{first}" and printed(degrees[-1], last) == last
    assert printed(intel.max_range, max_range) == max_range
    no_return, longest, backward = find(
        "datasets.md",
        r"A reading of ([\d.]+) m means \"no return\".*?the longest genuine reading is "
        r"([\d.]+) m.*?with (\d+) small backward steps",
    )
    assert np.all(intel.ranges[intel.no_return] == intel.max_range)
    assert printed(intel.max_range, no_return) == no_return
    assert printed(intel.ranges[~intel.no_return].max(), longest) == longest
    assert np.sum(np.diff(intel.t) < 0) == int(backward)


def test_lnpr_wall_numbers(walls):
    near, far, every, d_lo, d_hi, n_near, n_far = find(
        "datasets.md",
        r"facing a wall at (\d+) mm or (\d+) mm, a reading every ~(\d+) s for (\d+)–(\d+) "
        r"days \((\d+)k and (\d+)k readings\)",
    )
    assert sorted(walls) == [int(near), int(far)]
    near_wall, far_wall = walls[int(near)], walls[int(far)]
    for wall in (near_wall, far_wall):
        assert printed(np.median(np.diff(wall.t)), every) == every
    assert printed(near_wall.t[-1] / 86400, d_lo) == d_lo
    assert printed(far_wall.t[-1] / 86400, d_hi) == d_hi
    assert printed(near_wall.t.size / 1000, n_near) == n_near
    assert printed(far_wall.t.size / 1000, n_far) == n_far
    (nominal,) = find("datasets.md", r"wall\.true_distance, wall\.hour # ([\d.]+) m nominal")
    assert printed(far_wall.true_distance, nominal) == nominal
    lo, hi = find("datasets.md", r"The measured mean lies (\d+)–(\d+) mm beyond")
    beyond = sorted(1000 * (w.lidar.mean() - w.true_distance) for w in walls.values())
    assert (printed(beyond[0], lo), printed(beyond[1], hi)) == (lo, hi)


# ------------------------------------------------------------------------------ intro.md


def test_intro_lists_every_chapter_and_five_decks():
    text = page("intro.md")
    assert "reproduces five university course decks" in text
    rows = re.findall(r"\| \{doc\}`\.\./notebooks/(\w+)` \| ([^|]+) \|", text)
    notebooks = {p.stem for p in (ROOT / "notebooks").glob("*.ipynb")}
    assert {name for name, _ in rows} == notebooks
    decks = [deck for _, deck in rows if not deck.strip().startswith("beyond the decks")]
    assert len(decks) == 5  # "five decks", and every deck has its chapter
    assert len(set(decks)) == 5
    assert re.search(r"chapters 5–7", text)


def _chapter_rows():
    """(notebook, read minutes, run seconds) of each row of the intro's chapter table."""
    return re.findall(
        r"\| \{doc\}`\.\./notebooks/(\w+)` \|[^|]+\|[^|]+\| about (\d+) min \| (\d+) s \|",
        page("intro.md"),
    )


def test_intro_reading_times_are_the_word_counts_at_150_a_minute():
    import nbformat

    rows = _chapter_rows()
    assert {name for name, _, _ in rows} == {p.stem for p in (ROOT / "notebooks").glob("*.ipynb")}
    assert "at 150 words a minute" in page("intro.md")
    for name, minutes, _ in rows:
        nb = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
        prose = " ".join(c.source for c in nb.cells if c.cell_type == "markdown")
        prose = re.sub(r"```.*?```", "", prose, flags=re.S)  # display equations, directives
        words = len(prose.split())
        # "about N min": the reading time rounded to 5 minutes
        assert int(minutes) == 5 * round(words / 150 / 5), (name, words, minutes)


def test_intro_says_how_run_times_were_measured_and_names_the_ways_to_read():
    # The run times are one measurement on a loaded machine, which no test can recompute;
    # the page must say so.
    text = page("intro.md")
    assert "one execution of every cell of the notebook" in text and "load average" in text
    for way in ("**As a web book**", "**In JupyterLab, with live sliders.**", "**As a library.**"):
        assert way in text
    assert "`make lab`" in text
    decks = re.findall(
        r"^\| \"([^\"]+)\" \| (Portuguese|Turkish|Italian) \|",
        (BOOK / "intro.md").read_text(encoding="utf-8"),
        flags=re.M,
    )
    assert len(decks) == 5, decks


# ------------------------------------------------------------------------ conventions.md


def test_conventions_tiny_variance_and_overflow_examples():
    from probrob.distributions import prob_normal_distribution
    from probrob.motion import motion_model_velocity

    text = page("conventions.md")
    assert "a variance as small as $10^{-320}$" in text
    assert np.isfinite(prob_normal_distribution(0.0, 1e-320, log=True))
    assert "poses $10^{160}$ m apart" in text
    with pytest.raises(ValueError, match="x_t"):
        motion_model_velocity([1e160, 0.0, 0.0], [1.0, 1.0], [0.0, 0.0, 0.0], 1.0, [0.1] * 6)


# ------------------------------------------------------------------ the pages' references


@pytest.mark.parametrize("name", ["intro.md", "conventions.md", "datasets.md", "errata.md"])
def test_no_page_sends_the_reader_to_a_developers_file(name):
    text = page(name)
    if name == "errata.md":  # its header; the entries of other decks are not this test's
        text = text[: text.index("## Noise distributions")]
    assert "DESIGN.md" not in text and "STYLE.md" not in text
    assert "../shared" not in text


def test_errata_header_names_a_test_that_exists():
    (path, keyword) = find("errata.md", r"`\.venv/bin/pytest (tests/\S+\.py) -k (\w+)`")
    source = (ROOT / path).read_text(encoding="utf-8")
    assert re.search(rf"def test_\w*{keyword}\w*\(", source)
