"""Tests of probrob.datasets: the real files (against the numbers in each SOURCE.md), the
search order, the errors for missing and corrupt files, and bad arguments.

The real-file tests need ``../shared/data`` beside the repository (or ``$PROBROB_DATA``); CI
has it. They are skipped, with the reason, only when no candidate folder exists at all — a
loader bug that raises ``DatasetNotFoundError`` while the folder is there fails the test.
"""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from probrob import datasets
from probrob.datasets import (
    MRCLAM,
    DatasetCorruptError,
    DatasetNotFoundError,
    load_intel_lab,
    load_lnpr_wall,
    load_mrclam,
)

_DEFAULT_DATA = Path(os.path.normpath(Path(datasets.__file__).resolve().parents[2] / ".."))
_DEFAULT_DATA = _DEFAULT_DATA / "shared" / "data"


def _data_folder(folder: str) -> Path | None:
    env = os.environ.get("PROBROB_DATA")
    for base in ([Path(env)] if env else []) + [_DEFAULT_DATA]:
        if (base / folder).is_dir():
            return base / folder
    return None


MRCLAM_DIR = _data_folder("mrclam_dataset7_robot1")
needs_mrclam = pytest.mark.skipif(
    MRCLAM_DIR is None,
    reason=f"MRCLAM data absent: no mrclam_dataset7_robot1 under $PROBROB_DATA or {_DEFAULT_DATA}",
)

INTEL_DIR = _data_folder("intel_lab_corrected")
needs_intel = pytest.mark.skipif(
    INTEL_DIR is None,
    reason=f"Intel lab data absent: no intel_lab_corrected under $PROBROB_DATA or {_DEFAULT_DATA}",
)
LNPR_DIR = _data_folder("lnpr_wall_lidar")
needs_lnpr = pytest.mark.skipif(
    LNPR_DIR is None,
    reason=f"LNPR data absent: no lnpr_wall_lidar under $PROBROB_DATA or {_DEFAULT_DATA}",
)

# From mrclam_dataset7_robot1/SOURCE.md, written out here independently of Barcodes.dat.
ROBOT_BARCODES = {1: 5, 2: 14, 3: 41, 4: 32, 5: 23}
LANDMARK_BARCODES = [63, 81, 7, 70, 45, 27, 18, 54, 61, 90, 36, 16, 9, 72, 25]  # subjects 6..20


@pytest.fixture(scope="module")
def mrclam() -> MRCLAM:
    return load_mrclam()


# --------------------------------------------------------------------------- MRCLAM, real files


@needs_mrclam
def test_mrclam_shapes_and_counts(mrclam):
    assert mrclam.odometry_t.shape == (58598,)
    assert mrclam.odometry.shape == (58598, 2)
    assert mrclam.ground_truth_t.shape == (58389,)
    assert mrclam.ground_truth.shape == (58389, 3)
    assert mrclam.measurement_t.shape == (2578,)
    assert mrclam.measurements.shape == (2578, 3)
    assert mrclam.correspondences.shape == (2578,)
    assert mrclam.sighting_t.shape == (650,)
    assert mrclam.sightings.shape == (650, 2)
    assert mrclam.sighted_robot.shape == (650,)
    assert mrclam.landmarks.shape == (15, 3)
    assert mrclam.landmark_std.shape == (15, 2)
    assert mrclam.barcodes.shape == (20, 2)
    for name in ("odometry_t", "odometry", "ground_truth", "measurements", "landmarks"):
        assert getattr(mrclam, name).dtype == np.float64
    assert np.issubdtype(mrclam.correspondences.dtype, np.integer)
    # 19 distinct barcodes appear (SOURCE.md): 15 landmarks + robots 2..5.
    seen = set(mrclam.measurements[:, 2].astype(int)) | {
        ROBOT_BARCODES[r] for r in mrclam.sighted_robot.tolist()
    }
    assert len(seen) == 19


@needs_mrclam
def test_mrclam_time_is_monotonic_and_spans_match_source(mrclam):
    assert np.all(np.diff(mrclam.odometry_t) > 0)
    assert np.all(np.diff(mrclam.ground_truth_t) > 0)
    assert np.all(np.diff(mrclam.measurement_t) >= 0)
    assert np.all(np.diff(mrclam.sighting_t) >= 0)
    np.testing.assert_allclose(mrclam.odometry_t[[0, -1]], [1248446188.323, 1248447082.113])
    np.testing.assert_allclose(mrclam.ground_truth_t[[0, -1]], [1248446182.116, 1248447082.106])
    all_t = np.concatenate([mrclam.measurement_t, mrclam.sighting_t])
    np.testing.assert_allclose([all_t.min(), all_t.max()], [1248446189.249, 1248447082.053])
    dt = np.diff(mrclam.odometry_t)
    assert np.median(dt) == pytest.approx(0.010, abs=5e-4)
    assert dt.max() == pytest.approx(1.00, abs=0.005)
    assert (mrclam.odometry_t.size - 1) / np.ptp(mrclam.odometry_t) == pytest.approx(
        65.6, abs=0.05
    )


@needs_mrclam
def test_mrclam_value_ranges_match_source(mrclam):
    v, w = mrclam.odometry.T
    np.testing.assert_allclose([v.min(), v.max()], [0.0, 0.086], atol=5e-4)
    np.testing.assert_allclose([w.min(), w.max()], [-0.398, 0.432], atol=5e-4)
    x, y, th = mrclam.ground_truth.T
    np.testing.assert_allclose(
        [x.min(), x.max(), y.min(), y.max()], [0.767, 3.915, -3.418, 4.229], atol=5e-4
    )
    np.testing.assert_allclose([th.min(), th.max()], [-3.1414, 3.1411], atol=5e-5)
    r = np.concatenate([mrclam.measurements[:, 0], mrclam.sightings[:, 0]])
    b = np.concatenate([mrclam.measurements[:, 1], mrclam.sightings[:, 1]])
    np.testing.assert_allclose([r.min(), r.max(), b.min(), b.max()], [1.084, 7.479, -0.575, 0.478])
    lx, ly = mrclam.landmarks[:, 0], mrclam.landmarks[:, 1]
    np.testing.assert_allclose(
        [lx.min(), lx.max(), ly.min(), ly.max()], [0.588, 3.472, -4.468, 4.532], atol=5e-4
    )
    assert mrclam.landmark_std.max() <= 0.65e-3


@needs_mrclam
def test_mrclam_barcode_mapping(mrclam):
    # The landmark rows are subjects 6..20, each carrying its barcode as signature.
    np.testing.assert_array_equal(mrclam.landmark_subject, np.arange(6, 21))
    np.testing.assert_array_equal(mrclam.landmarks[:, 2], LANDMARK_BARCODES)
    # Every measurement's signature is its landmark's signature.
    np.testing.assert_array_equal(
        mrclam.measurements[:, 2], mrclam.landmarks[mrclam.correspondences, 2]
    )
    assert mrclam.correspondences.min() >= 0 and mrclam.correspondences.max() <= 14
    assert set(mrclam.sighted_robot.tolist()) == {2, 3, 4, 5}
    # Independently of the loader: re-read the raw file and map with SOURCE.md's table.
    raw = np.loadtxt(MRCLAM_DIR / "Robot1_Measurement.dat")
    robot_of = {b: r for r, b in ROBOT_BARCODES.items()}
    is_robot = np.isin(raw[:, 1], list(robot_of))
    assert is_robot.sum() == 650 and (~is_robot).sum() == 2578
    np.testing.assert_array_equal(raw[~is_robot][:, [2, 3, 1]], mrclam.measurements)
    np.testing.assert_array_equal(raw[~is_robot][:, 0], mrclam.measurement_t)
    expected_c = [LANDMARK_BARCODES.index(int(b)) for b in raw[~is_robot][:, 1]]
    np.testing.assert_array_equal(mrclam.correspondences, expected_c)
    np.testing.assert_array_equal(
        mrclam.sighted_robot, [robot_of[int(b)] for b in raw[is_robot][:, 1]]
    )
    np.testing.assert_array_equal(raw[is_robot][:, 2:4], mrclam.sightings)


@needs_mrclam
def test_mrclam_measurements_agree_with_ground_truth_as_source_says(mrclam):
    """SOURCE.md: range residual median +0.044 m, robust σ 0.067 m; bearing −0.0009, 0.018 rad."""
    pose = mrclam.ground_truth_at(mrclam.measurement_t)
    lm = mrclam.landmarks[mrclam.correspondences]
    dx, dy = lm[:, 0] - pose[:, 0], lm[:, 1] - pose[:, 1]
    r_hat = np.hypot(dx, dy)
    phi_hat = np.arctan2(dy, dx) - pose[:, 2]
    dr = mrclam.measurements[:, 0] - r_hat
    dphi = np.angle(np.exp(1j * (mrclam.measurements[:, 1] - phi_hat)))

    def robust_sigma(e):
        return 1.4826 * np.median(np.abs(e - np.median(e)))

    assert np.median(dr) == pytest.approx(0.044, abs=0.0015)
    assert robust_sigma(dr) == pytest.approx(0.067, abs=0.0015)
    assert np.mean(np.abs(dr) > 0.5) == pytest.approx(0.0047, abs=0.0005)
    assert np.median(dphi) == pytest.approx(-0.0009, abs=0.0002)
    assert robust_sigma(dphi) == pytest.approx(0.018, abs=0.0015)
    assert np.abs(dphi).max() < 0.2


@needs_mrclam
def test_mrclam_arrays_are_read_only_and_loads_are_cached(mrclam):
    with pytest.raises(ValueError, match="read-only"):
        mrclam.odometry[0, 0] = 1.0
    assert load_mrclam() is mrclam
    assert load_mrclam(MRCLAM_DIR) is load_mrclam(MRCLAM_DIR.parent)  # folder or its parent


@needs_mrclam
def test_mrclam_stream_real(mrclam):
    steps = mrclam.stream()
    t = mrclam.odometry_t
    assert len(steps) == t.size - 1 == 58597
    np.testing.assert_array_equal([s.t for s in steps], t[1:])
    np.testing.assert_array_equal([s.dt for s in steps], np.diff(t))
    np.testing.assert_array_equal(np.stack([s.u for s in steps]), mrclam.odometry[:-1])
    # Every landmark measurement exactly once, in file order, inside its interval (t - dt, t].
    np.testing.assert_array_equal(np.concatenate([s.z for s in steps]), mrclam.measurements)
    np.testing.assert_array_equal(np.concatenate([s.c for s in steps]), mrclam.correspondences)
    np.testing.assert_array_equal(np.concatenate([s.z_t for s in steps]), mrclam.measurement_t)
    for s in steps:
        assert s.z.shape == (s.c.size, 3) == (s.z_t.size, 3)
        if s.c.size:
            assert np.all(s.z_t > s.t - s.dt) and np.all(s.z_t <= s.t)
    # Robot sightings are dropped: no robot barcode among the signatures.
    sig = np.concatenate([s.z[:, 2] for s in steps])
    assert not np.isin(sig, list(ROBOT_BARCODES.values())).any()
    assert sum(s.c.size > 0 for s in steps) > 500
    again = mrclam.stream()  # built once, then a new list of the same steps
    assert again is not steps and again[1234] is steps[1234]
    with pytest.raises(ValueError, match="read-only"):
        steps[0].u[0] = 1.0


# --------------------------------------------------------------------------- stream, synthetic


def _synthetic(odometry_t, measurement_t) -> MRCLAM:
    n, k = len(odometry_t), len(measurement_t)
    z = np.column_stack([np.arange(k) + 1.0, np.zeros(k), np.full(k, 63.0)])
    return MRCLAM(
        odometry_t=np.asarray(odometry_t, float),
        odometry=np.column_stack([np.arange(n) * 0.1, np.zeros(n)]),
        ground_truth_t=np.array([0.0, 10.0]),
        ground_truth=np.array([[0.0, 0.0, 3.0], [10.0, -5.0, -3.0]]),
        measurement_t=np.asarray(measurement_t, float),
        measurements=z,
        correspondences=np.zeros(k, int),
        sighting_t=np.zeros(0),
        sightings=np.zeros((0, 2)),
        sighted_robot=np.zeros(0, int),
        landmarks=np.array([[1.0, 2.0, 63.0]]),
        landmark_std=np.zeros((1, 2)),
        landmark_subject=np.array([6]),
        barcodes=np.array([[6, 63]]),
        folder="synthetic",
    )


def test_stream_attaches_measurements_to_half_open_intervals():
    # Commands at 1, 2, 4; measurements before, at t0, inside, at the boundaries, after.
    ds = _synthetic([1.0, 2.0, 4.0], [0.5, 1.0, 1.5, 2.0, 2.0, 3.0, 4.0, 4.5])
    steps = ds.stream()
    assert [s.t for s in steps] == [2.0, 4.0]
    assert [s.dt for s in steps] == [1.0, 2.0]
    np.testing.assert_array_equal(steps[1].u, [0.1, 0.0])
    # (t0 - inf, 2] -> step 0 (earlier ones included); (2, 4] -> step 1; 4.5 dropped.
    np.testing.assert_array_equal(steps[0].z_t, [0.5, 1.0, 1.5, 2.0, 2.0])
    np.testing.assert_array_equal(steps[1].z_t, [3.0, 4.0])
    np.testing.assert_array_equal(steps[0].z[:, 0], [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(steps[1].z[:, 0], [6, 7])


def test_stream_without_measurements():
    steps = _synthetic([0.0, 0.5, 1.5], []).stream()
    assert len(steps) == 2
    assert all(s.z.shape == (0, 3) and s.c.shape == (0,) for s in steps)


def test_ground_truth_at_interpolates_heading_across_pi():
    ds = _synthetic([0.0, 1.0], [])
    pose = ds.ground_truth_at([0.0, 5.0, 10.0])
    np.testing.assert_allclose(pose[:, :2], [[0, 0], [5, -2.5], [10, -5]])
    # 3 -> -3 the short way (through π), midpoint at π (wrapped to -π).
    assert abs(np.angle(np.exp(1j * (pose[1, 2] - np.pi)))) < 1e-12
    np.testing.assert_allclose(pose[[0, 2], 2], [3.0, -3.0])
    assert ds.ground_truth_at(2.5).shape == (3,)
    with pytest.raises(ValueError, match="t must lie within"):
        ds.ground_truth_at(10.5)
    with pytest.raises(ValueError, match="t must be finite"):
        ds.ground_truth_at(np.nan)


# --------------------------------------------------------------------------- search and errors


@pytest.fixture
def no_defaults(monkeypatch, tmp_path):
    """No $PROBROB_DATA, a repository whose ../shared/data does not exist, an empty download
    cache and no download (tests/test_datasets_download.py tests downloading)."""
    monkeypatch.delenv("PROBROB_DATA", raising=False)
    monkeypatch.setattr(datasets, "_REPOSITORY", tmp_path / "nowhere" / "repo")
    monkeypatch.setenv("PROBROB_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("PROBROB_DOWNLOAD", "0")
    return tmp_path


def _link_folder(src: Path, dst: Path, skip=()) -> Path:
    dst.mkdir(parents=True)
    for f in src.iterdir():
        if f.name not in skip:
            (dst / f.name).symlink_to(f)
    return dst


def test_missing_everywhere_names_file_places_and_url(no_defaults, monkeypatch):
    env = no_defaults / "env"
    monkeypatch.setenv("PROBROB_DATA", str(env))
    with pytest.raises(DatasetNotFoundError) as info:
        load_mrclam()
    msg = str(info.value)
    assert isinstance(info.value, FileNotFoundError)
    assert "'Barcodes.dat' not found" in msg
    assert str(env / "mrclam_dataset7_robot1") in msg
    assert str(no_defaults / "nowhere" / "shared" / "data" / "mrclam_dataset7_robot1") in msg
    assert "http://asrl.utias.utoronto.ca/datasets/mrclam/" in msg
    assert "raw.githubusercontent.com/ericguerrero/MUSI-lab-session-1" in msg
    assert info.value.file == "Barcodes.dat"
    # the two folders, then the (empty) download cache; downloading is switched off
    assert info.value.places[-1] == str(no_defaults / "cache" / "mrclam_dataset7_robot1")
    assert len(info.value.places) == 3
    assert "Not downloaded: $PROBROB_DOWNLOAD is '0'." in msg


def test_missing_with_explicit_empty_folder(no_defaults):
    empty = no_defaults / "empty"
    empty.mkdir()
    with pytest.raises(DatasetNotFoundError, match="PROBROB_DATA is not set") as info:
        load_mrclam(empty)
    assert str(empty) in str(info.value)
    assert "asrl.utias.utoronto.ca" in str(info.value)
    assert "Nothing is downloaded when path= is given" in str(info.value)
    assert len(info.value.places) == 2  # the path and its sub-folder: no download cache


@needs_mrclam
def test_one_missing_file_is_named(no_defaults):
    folder = _link_folder(MRCLAM_DIR, no_defaults / "partial", skip={"Robot1_Odometry.dat"})
    with pytest.raises(
        DatasetNotFoundError, match=re.escape("'Robot1_Odometry.dat' not found")
    ) as info:
        load_mrclam(folder)
    assert f"{folder}  (the path argument; exists but has no Robot1_Odometry.dat)" in str(
        info.value
    )


@needs_mrclam
@pytest.mark.parametrize("name", ["Barcodes.dat", "Robot1_Measurement.dat"])
def test_corrupt_file_raises(no_defaults, name):
    folder = _link_folder(MRCLAM_DIR, no_defaults / "corrupt", skip={name})
    shutil.copyfile(MRCLAM_DIR / name, folder / name)
    data = bytearray((folder / name).read_bytes())
    data[len(data) // 2] ^= 0x01  # one flipped bit, same size
    (folder / name).write_bytes(bytes(data))
    with pytest.raises(DatasetCorruptError, match=re.escape(name)) as info:
        load_mrclam(folder)
    assert isinstance(info.value, ValueError)
    assert "sha256" in str(info.value) and "raw.githubusercontent.com" in str(info.value)
    assert info.value.file == str(folder / name)


@needs_mrclam
def test_truncated_file_raises(no_defaults):
    name = "Robot1_Measurement.dat"
    folder = _link_folder(MRCLAM_DIR, no_defaults / "short", skip={name})
    (folder / name).write_bytes((MRCLAM_DIR / name).read_bytes()[:-10])
    with pytest.raises(DatasetCorruptError, match="126099 bytes instead of 126109"):
        load_mrclam(folder)


@needs_mrclam
def test_probrob_data_is_honoured(no_defaults, monkeypatch):
    env = no_defaults / "env"
    _link_folder(MRCLAM_DIR, env / "mrclam_dataset7_robot1")
    monkeypatch.setenv("PROBROB_DATA", str(env))
    ds = load_mrclam()
    assert ds.folder == str(env / "mrclam_dataset7_robot1")
    assert ds.odometry.shape == (58598, 2)


@pytest.mark.skipif(
    not (_DEFAULT_DATA / "mrclam_dataset7_robot1").is_dir(),
    reason=f"MRCLAM data absent from {_DEFAULT_DATA}",
)
def test_probrob_data_without_the_dataset_falls_back_to_shared(monkeypatch, tmp_path):
    monkeypatch.setenv("PROBROB_DATA", str(tmp_path))
    assert Path(load_mrclam().folder) == _DEFAULT_DATA / "mrclam_dataset7_robot1"


def test_sha256_is_verified_once_per_file_state(tmp_path, monkeypatch):
    calls = []
    real = datasets.hashlib.file_digest

    def counting(fh, name):
        calls.append(name)
        return real(fh, name)

    monkeypatch.setattr(datasets.hashlib, "file_digest", counting)
    spec = datasets._LNPR.files[0]
    f = tmp_path / spec.name
    f.write_bytes(b"x" * spec.size)
    for _ in range(2):
        with pytest.raises(DatasetCorruptError):
            datasets._verify(datasets._LNPR, f)
    assert len(calls) == 2  # a failed check is not remembered
    monkeypatch.setattr(datasets, "_VERIFIED", {datasets._stamp(f): spec.sha256})
    datasets._verify(datasets._LNPR, f)  # remembered as verified: no hashing
    assert len(calls) == 2


@pytest.mark.parametrize("bad", [3, 1.5, ["a"]])
def test_path_of_wrong_type(bad):
    with pytest.raises(ValueError, match="path must be a folder"):
        load_mrclam(bad)


def test_path_that_is_a_file(tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("not a folder")
    with pytest.raises(ValueError, match="path must be a folder, got the file"):
        load_mrclam(f)


# --------------------------------------------------------------------------- Intel lab


@pytest.fixture(scope="module")
def intel():
    return load_intel_lab()


@needs_intel
def test_intel_shapes_and_first_scan(intel):
    assert intel.t.shape == (910,)
    assert intel.poses.shape == (910, 3)
    assert intel.ranges.shape == (910, 180)
    assert intel.neff.shape == (910,)
    assert intel.max_range == 81.83
    assert intel.laser_offset == 0.0
    np.testing.assert_allclose(np.rad2deg(intel.beam_angles), np.arange(-90.0, 90.0), atol=1e-12)
    # The first FLASER line of the log, read by eye.
    np.testing.assert_array_equal(intel.ranges[0, :4], [1.09, 1.08, 1.08, 1.07])
    np.testing.assert_array_equal(intel.ranges[0, -2:], [1.22, 1.23])
    np.testing.assert_array_equal(intel.poses[0], [0.600266, -0.0320327, -0.354665])
    assert intel.t[0] == 32.9068
    assert intel.t[-1] == 2683.77
    assert intel.neff.min() == pytest.approx(2.1, abs=0.01) and intel.neff.max() == 15


@needs_intel
def test_intel_statistics_match_source(intel):
    r = intel.ranges
    assert r.min() == 0.23
    assert intel.no_return.sum() == 4172
    assert intel.no_return.mean() == pytest.approx(0.0255, abs=5e-5)
    hits = r[~intel.no_return]
    assert hits.max() == 25.38
    np.testing.assert_allclose(
        np.percentile(hits, [1, 5, 50, 95, 99]), [0.45, 0.63, 2.00, 7.71, 13.53], atol=0.005
    )
    lo, hi = intel.poses.min(axis=0), intel.poses.max(axis=0)
    np.testing.assert_allclose(lo, [-9.23, -22.13, -3.14], atol=0.005)
    np.testing.assert_allclose(hi, [16.55, 3.90, 3.25], atol=0.005)
    step = np.hypot(*np.diff(intel.poses[:, :2], axis=0).T)
    assert np.median(step) == pytest.approx(0.67, abs=0.005)
    assert step.max() == pytest.approx(1.16, abs=0.01)
    dt = np.diff(intel.t)
    assert np.sum(dt < 0) == 4 and dt.min() == pytest.approx(-0.86)  # kept as recorded
    assert np.median(dt) == pytest.approx(3.35, abs=0.005)


def _endpoints(pose, ranges, angles, valid):
    a = pose[2] + angles[valid]
    return np.column_stack(
        [pose[0] + ranges[valid] * np.cos(a), pose[1] + ranges[valid] * np.sin(a)]
    )


@needs_intel
def test_intel_beam_convention_aligns_consecutive_scans(intel):
    """With the returned poses and beam angles, consecutive scans overlap; with the mirrored
    beam order they do not. Our measure: for every third pair of consecutive scans, each
    endpoint's distance to the nearest endpoint of the next scan, no-return beams left out;
    its median is 0.043 m here (1° between beams is 0.035 m at the median range of 2 m) and
    0.55 m mirrored. (SOURCE.md reports 0.030 m against 0.45 m with a measure it does not
    spell out.)"""

    def median_nn(angles):
        d = []
        for k in range(0, 909, 3):
            ok = [~intel.no_return[k], ~intel.no_return[k + 1]]
            p = _endpoints(intel.poses[k], intel.ranges[k], angles, ok[0])
            q = _endpoints(intel.poses[k + 1], intel.ranges[k + 1], angles, ok[1])
            d.append(np.min(np.hypot(*(p[:, None, :] - q[None, :, :]).transpose(2, 0, 1)), axis=1))
        return np.median(np.concatenate(d))

    assert median_nn(intel.beam_angles) < 0.05
    assert median_nn(intel.beam_angles[::-1]) > 0.3


# --------------------------------------------------------------------------- LNPR


@needs_lnpr
@pytest.mark.parametrize(
    ("mm", "n", "mean", "sd", "lo", "hi", "mode", "ir", "span"),
    [
        (
            200,
            58988,
            209.74,
            4.84,
            193,
            229,
            211,
            (308.7, 10.5, 283, 338),
            ("2018-01-22T09:58:19", "2018-01-24T12:00:36"),
        ),
        (
            600,
            82301,
            626.97,
            5.92,
            607,
            645,
            631,
            (23.0, 5.7, 0, 48),
            ("2018-02-02T11:00:01", "2018-02-05T08:42:28"),
        ),
    ],
)
def test_lnpr_statistics_match_source(mm, n, mean, sd, lo, hi, mode, ir, span):
    w = load_lnpr_wall(mm)
    assert w.distance_mm == mm and w.true_distance == mm / 1000
    for name in ("t", "lidar", "ir", "hour", "local_time"):
        assert getattr(w, name).shape == (n,)
    mm_values = w.lidar * 1000  # metres in the dataclass
    assert mm_values.mean() == pytest.approx(mean, abs=0.005)
    assert mm_values.std() == pytest.approx(sd, abs=0.005)
    assert (mm_values.min(), mm_values.max()) == pytest.approx((lo, hi))
    assert np.bincount(np.round(mm_values).astype(int)).argmax() == mode
    assert w.ir.mean() == pytest.approx(ir[0], abs=0.05)
    assert w.ir.std() == pytest.approx(ir[1], abs=0.05)
    assert (w.ir.min(), w.ir.max()) == (ir[2], ir[3])
    assert [str(x) for x in w.local_time[[0, -1]]] == list(span)
    assert w.t[0] == 0.0 and np.all(np.diff(w.t) > 0)
    assert w.t[-1] == (np.datetime64(span[1]) - np.datetime64(span[0])).astype(int)
    assert np.median(np.diff(w.t)) == pytest.approx(3.0, abs=0.5)
    assert np.all((w.hour >= 0) & (w.hour < 24))


@needs_lnpr
def test_lnpr_time_of_day_table_matches_source():
    table = {200: [213.6, 210.4, 206.5, 208.4], 600: [631.1, 630.5, 622.3, 624.4]}
    for mm, means in table.items():
        w = load_lnpr_wall(mm)
        got = [1000 * w.lidar[(w.hour >= h) & (w.hour < h + 6)].mean() for h in (0, 6, 12, 18)]
        np.testing.assert_allclose(got, means, atol=0.05)


@pytest.mark.parametrize("bad", [300, 0, 200.0, "200", True, None])
def test_lnpr_bad_distance(bad):
    with pytest.raises(ValueError, match="distance_mm must be one of"):
        load_lnpr_wall(bad)


@needs_lnpr
def test_lnpr_needs_only_the_file_asked_for(no_defaults):
    folder = _link_folder(LNPR_DIR, no_defaults / "lnpr", skip={"sensor_data_600.txt"})
    assert load_lnpr_wall(200, path=folder).lidar.size == 58988
    with pytest.raises(
        DatasetNotFoundError, match=re.escape("'sensor_data_600.txt' not found")
    ) as info:
        load_lnpr_wall(600, path=folder)
    assert "LNPR_BOOK_CODES" in str(info.value)


@needs_lnpr
def test_lnpr_corrupt(no_defaults):
    folder = no_defaults / "lnpr"
    folder.mkdir()
    data = bytearray((LNPR_DIR / "sensor_data_600.txt").read_bytes())
    data[-3] = ord("9") if data[-3] != ord("9") else ord("8")  # one digit changed
    (folder / "sensor_data_600.txt").write_bytes(bytes(data))
    with pytest.raises(DatasetCorruptError, match=re.escape("sensor_data_600.txt")):
        load_lnpr_wall(600, path=folder)


@needs_intel
def test_intel_corrupt(no_defaults):
    folder = no_defaults / "intel"
    folder.mkdir()
    data = bytearray((INTEL_DIR / "intel-corrected.log.gz").read_bytes())
    data[1000] ^= 0x80
    (folder / "intel-corrected.log.gz").write_bytes(bytes(data))
    with pytest.raises(DatasetCorruptError, match=re.escape("intel-corrected.log.gz")):
        load_intel_lab(folder)


def test_intel_and_lnpr_missing_name_publishers(no_defaults):
    with pytest.raises(DatasetNotFoundError, match=re.escape("radish.sourceforge.net")) as info:
        load_intel_lab()
    assert "'intel-corrected.log.gz' not found" in str(info.value)
    assert "acschaefer/ple" in str(info.value)
    with pytest.raises(DatasetNotFoundError, match="ryuichiueda/LNPR_BOOK_CODES") as info:
        load_lnpr_wall(600)
    assert "'sensor_data_600.txt' not found" in str(info.value)
    assert str(no_defaults / "nowhere" / "shared" / "data" / "lnpr_wall_lidar") in str(info.value)
