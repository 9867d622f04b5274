"""The compiled ray casting (probrob.maps, numba): exact equalities and the bound's error path."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

from probrob import maps
from probrob.maps import OccupancyGrid, ray_cast


def scalar_traversal(occ, x0, y0, dx, dy, t_max):
    """The plain Amanatides–Woo traversal of one ray in cell units, scalar Python, with the
    library's crossing formula ``t = (j + c) / d``'s form ``(j + c) * (1 / d)``: the same
    operations in the same order, so the compiled code must return the same float."""
    h, w = occ.shape
    j, i = math.floor(x0), math.floor(y0)
    inv_x, c_x = (1.0 / dx, float(dx > 0) - x0) if dx != 0 else (1.0, math.inf)
    inv_y, c_y = (1.0 / dy, float(dy > 0) - y0) if dy != 0 else (1.0, math.inf)
    t = 0.0
    while True:
        if occ[i, j]:
            return t
        tx, ty = (j + c_x) * inv_x, (i + c_y) * inv_y
        if tx <= ty:
            t, j = tx, j + (1 if dx > 0 else -1)
        else:
            t, i = ty, i + (1 if dy > 0 else -1)
        if t >= t_max or not (0 <= i < h and 0 <= j < w):
            return t_max


def grid_line_poses(grid, n, rng):
    """Poses on grid lines and corners, a few ulps off them, and anywhere; headings along
    the axes, the diagonals and anywhere: the rays where rounding decides the cell."""
    h, w = grid.shape
    on = (
        grid.origin
        + 0.5 * grid.resolution * np.c_[rng.integers(0, 2 * w, n), rng.integers(0, 2 * h, n)]
    )
    for k in rng.integers(-2, 3, n).nonzero()[0]:
        on[k] = np.nextafter(on[k], np.inf if k % 2 else -np.inf)
    anywhere = grid.origin + grid.resolution * np.c_[rng.random(n) * w, rng.random(n) * h]
    xy = np.r_[on, anywhere]
    axes = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi, -np.pi, np.pi / 4, 1e-17, -1e-307])
    theta = np.where(rng.random(2 * n) < 0.5, rng.choice(axes, 2 * n), rng.uniform(-4, 4, 2 * n))
    poses = np.c_[xy, theta]
    return poses[grid.contains(xy)]


@pytest.fixture(scope="module")
def clutter():
    rng = np.random.default_rng(7)
    occ = rng.random((23, 31)) < 0.2
    occ[5:15, 10] = True  # a wall one cell thick
    return OccupancyGrid(occ, 0.25, (-1.3, 0.6))


def test_the_exact_methods_agree_to_the_last_bit_on_grid_lines_and_corners(clutter):
    rng = np.random.default_rng(0)
    poses = grid_line_poses(clutter, 3000, rng)
    angles = np.r_[0.0, np.pi / 2, np.pi, -np.pi / 2, np.pi / 4, rng.uniform(-np.pi, np.pi, 11)]
    hybrid = ray_cast(clutter, poses, angles, 12.0)
    dda = ray_cast(clutter, poses, angles, 12.0, method="dda")
    assert hybrid.size > 50_000
    np.testing.assert_array_equal(hybrid, dda)
    assert 0.2 < (hybrid < 12.0).mean() < 1.0  # both hits and misses among them


def test_the_compiled_plain_traversal_equals_its_scalar_transcription(clutter):
    rng = np.random.default_rng(1)
    poses = grid_line_poses(clutter, 200, rng)
    angles = rng.uniform(-np.pi, np.pi, 7)
    res, t_max = clutter.resolution, 12.0 / clutter.resolution
    got = ray_cast(clutter, poses, angles, 12.0, method="dda")
    # the directions exactly as the library forms them (numpy's cos and sin of the arrays)
    ct, st, ca, sa = np.cos(poses[:, 2]), np.sin(poses[:, 2]), np.cos(angles), np.sin(angles)
    for p, (x, y, _) in enumerate(poses):
        x0, y0 = (x - clutter.origin[0]) / res, (y - clutter.origin[1]) / res
        for k in range(angles.size):
            dx = ct[p] * ca[k] - st[p] * sa[k]
            dy = st[p] * ca[k] + ct[p] * sa[k]
            t = scalar_traversal(clutter.occupied, x0, y0, dx, dy, t_max)
            assert got[p, k] == min(t * res, 12.0), (p, k)


@pytest.mark.parametrize(
    ("method", "stage"),
    [("hybrid", "sphere"), ("hybrid", "hybrid"), ("dda", "dda"), ("march", "march")],
)
def test_a_ray_past_its_proven_bound_raises_instead_of_returning(monkeypatch, method, stage):
    # The bounds are proofs (tests/test_api_properties.py checks them); a traversal that
    # outran one would be a bug: the compiled loop stops there and ray_cast raises.
    occ = np.zeros((40, 40), bool)
    occ[21, :] = True  # a beam along this wall takes many steps in every stage but sphere's
    grid = OccupancyGrid(occ, 1.0)
    real = maps._step_bounds

    def one_step(shape, t_max):
        bounds = real(shape, t_max)
        bounds[stage] = 1 if stage != "sphere" else 0
        return bounds

    monkeypatch.setattr(maps, "_step_bounds", one_step)
    with pytest.raises(RuntimeError, match=rf"\({stage}\): \d+ ray\(s\) still in flight"):
        ray_cast(grid, [[3.2, 20.5, 0.0]], [0.0, 0.01], 30.0, method=method)


def test_a_second_process_loads_the_compiled_code_from_the_cache(tmp_path):
    # cache=True: the book's build compiles once per machine, and every later kernel loads
    # the machine code (NUMBA_CACHE_DIR here, so that the test starts from an empty cache)
    script = (
        "import numpy as np; from probrob import maps; "
        "maps.ray_cast(maps.OccupancyGrid(np.eye(3, dtype=bool), 1.0), [1.5, 0.5, 0.0], [0.0], "
        "2.0, method='dda'); s = maps._cast_dda.stats; print(sum(s.cache_hits.values()), "
        "sum(s.cache_misses.values()))"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    runs = [
        subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True)
        for _ in range(2)
    ]
    assert [r.returncode for r in runs] == [0, 0], [r.stderr for r in runs]
    assert [r.stdout.split() for r in runs] == [["0", "1"], ["1", "0"]]
