"""CARMEN logs: the Intel lab's real odometry, and read_carmen_log for any log a reader brings."""

import gzip

import numpy as np
import pytest

from probrob.angles import wrap_angle
from probrob.datasets import CarmenLog, IntelLab, load_intel_lab, read_carmen_log

try:
    INTEL = load_intel_lab()
except FileNotFoundError:  # pragma: no cover - the data sit beside the checkout in CI
    INTEL = None

needs_data = pytest.mark.skipif(INTEL is None, reason="the Intel lab log is not available")


@needs_data
def test_intel_odometry_pairs_start_at_the_corrected_pose_and_miss_the_next_by_about_5_cm():
    assert isinstance(INTEL, IntelLab) and isinstance(INTEL, CarmenLog)
    u = INTEL.odometry
    assert u.shape == (909, 2, 3) and not u.flags.writeable
    np.testing.assert_array_equal(u[:, 0], INTEL.poses[:-1])
    miss = np.hypot(*(u[:, 1, :2] - INTEL.poses[1:, :2]).T)
    assert 0.04 < np.median(miss) < 0.06
    assert miss.max() < 0.25
    # the odometry is a real reading, not the corrected pose copied: it never lands exactly
    assert np.all(miss > 0)
    # and it is odometry of the same motion: the step lengths agree to a few centimetres
    step_odo = np.hypot(*(u[:, 1, :2] - u[:, 0, :2]).T)
    step_true = np.hypot(*(INTEL.poses[1:, :2] - INTEL.poses[:-1, :2]).T)
    assert np.median(np.abs(step_odo - step_true)) < 0.05
    turn = wrap_angle(u[:, 1, 2] - u[:, 0, 2]) - wrap_angle(
        INTEL.poses[1:, 2] - INTEL.poses[:-1, 2]
    )
    assert np.median(np.abs(wrap_angle(turn))) < 0.05


@needs_data
def test_read_carmen_log_reads_the_intel_log_as_load_intel_lab_does():
    path = f"{INTEL.folder}/intel-corrected.log.gz"
    log = read_carmen_log(path, max_range=81.83)
    for name in ("t", "poses", "ranges", "beam_angles", "odometry"):
        np.testing.assert_array_equal(getattr(log, name), getattr(INTEL, name))
    assert log.max_range == 81.83 and log.laser_offset == 0.0
    assert read_carmen_log(path).max_range == pytest.approx(81.83)  # the largest reading


def _flaser(n, ranges, pose, odom, t):
    r = " ".join(f"{v:g}" for v in ranges)
    p = " ".join(f"{v:g}" for v in (*pose, *odom))
    return f"FLASER {n} {r} {p} {t} host {t}"


def _write(tmp_path, lines, name="log.txt"):
    path = tmp_path / name
    text = "\n".join(lines) + "\n"
    if name.endswith(".gz"):
        with gzip.open(path, "wt") as fh:
            fh.write(text)
    else:
        path.write_text(text)
    return path


@pytest.mark.parametrize("name", ["raw.log", "raw.log.gz"])
def test_a_raw_log_round_trips(tmp_path, name):
    lines = [
        "# a comment",
        "PARAM robot_frontlaser_offset 0.1",
        "ODOM 0 0 0 0 0 0 0.5 host 0.5",
        _flaser(3, [1.0, 2.0, 30.0], (0, 0, 0), (10, 5, 1), 1.0),
        "ODOM 10.2 5.1 1.05 0 0 0 1.5 host 1.5",
        "ODOM 10.4 5.2 1.1 0 0 0 1.9 host 1.9",
        "TRUEPOS 1 2 3 4 5 6 2.0 host 2.0",
        _flaser(3, [1.5, 2.5, 3.5], (1, 0, 0), (10.5, 5.25, 1.12), 2.0),
        _flaser(3, [1.5, 30.0, 3.5], (2, 0, 0), (11, 5.5, 1.2), 3.0),
    ]
    log = read_carmen_log(_write(tmp_path, lines, name))
    np.testing.assert_array_equal(log.t, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(log.poses[:, 0], [0, 1, 2])
    assert log.ranges.shape == (3, 3) and log.max_range == 30.0 and log.laser_offset == 0.1
    # step 0 ends at the last ODOM before scan 1; step 1 has none, so at scan 2's odometry pose
    np.testing.assert_array_equal(log.odometry[0], [[10, 5, 1], [10.4, 5.2, 1.1]])
    np.testing.assert_array_equal(log.odometry[1], [[10.5, 5.25, 1.12], [11, 5.5, 1.2]])
    assert log.no_return.sum() == 2  # the code 30 m, twice


@pytest.mark.parametrize(
    ("n", "step_deg", "last_deg"),
    [(180, 1.0, 89.0), (181, 1.0, 90.0), (360, 0.5, 89.5), (361, 0.5, 90.0)],
)
def test_beam_angles_follow_carmen_flaser_convention(tmp_path, n, step_deg, last_deg):
    log = read_carmen_log(_write(tmp_path, [_flaser(n, [1.0] * n, (0, 0, 0), (0, 0, 0), 1.0)]))
    a = np.rad2deg(log.beam_angles)
    assert a[0] == pytest.approx(-90.0) and a[-1] == pytest.approx(last_deg)
    np.testing.assert_allclose(np.diff(a), step_deg)


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ("FLASER x 1 2", r"line 2: FLASER must be followed by its number of beams"),
        ("FLASER 3 1 2 3 0 0 0 0 0 0 1.0 host", r"line 2: FLASER with 3 beams needs 14 fields"),
        ("FLASER 3 1 2 a 0 0 0 0 0 0 1.0 host 1.0", r"line 2: FLASER ranges must be numbers"),
        ("FLASER 3 1 2 -3 0 0 0 0 0 0 1.0 host 1.0", r"line 2: FLASER ranges must be >= 0"),
        ("FLASER 3 1 2 3 0 nan 0 0 0 0 1.0 host 1.0", r"line 2: FLASER x y θ .* must be finite"),
        ("FLASER 2 1 2 0 0 0 0 0 0 1.0 host 1.0", r"line 2: FLASER has 2 beams where earlier"),
        ("ODOM 1 2", r"line 2: ODOM needs at least x y θ"),
        ("ODOM 1 b 3 0 0 0 1 host 1", r"line 2: ODOM x y θ must be numbers"),
        ("NEFF", r"line 2: NEFF needs one value"),
    ],
)
def test_a_malformed_line_is_named_with_what_was_expected(tmp_path, bad, message):
    lines = [_flaser(3, [1, 2, 3], (0, 0, 0), (0, 0, 0), 0.5), bad]
    with pytest.raises(ValueError, match=message):
        read_carmen_log(_write(tmp_path, lines))


def test_read_carmen_log_errors(tmp_path):
    with pytest.raises(ValueError, match=r"no FLASER line .*ROBOTLASER1"):
        read_carmen_log(_write(tmp_path, ["ODOM 0 0 0 0 0 0 1 host 1"]))
    with pytest.raises(FileNotFoundError, match="no such file"):
        read_carmen_log(tmp_path / "missing.log")
    with pytest.raises(ValueError, match="path"):
        read_carmen_log(3.5)
    binary = tmp_path / "binary.log"
    binary.write_bytes(b"\xff\xfe\x00FLASER")
    with pytest.raises(ValueError, match="not a readable text CARMEN log"):
        read_carmen_log(binary)
    good = _write(tmp_path, [_flaser(3, [1, 2, 3], (0, 0, 0), (0, 0, 0), 0.5)])
    with pytest.raises(ValueError, match="max_range"):
        read_carmen_log(good, max_range=-1.0)
    # the largest reading occurs once: it is a reading, not a no-return code
    with pytest.raises(ValueError, match="max_range: pass the scanner's no-return code"):
        read_carmen_log(good)
    assert read_carmen_log(good, max_range=80.0).no_return.sum() == 0
