"""OccupancyGrid.free: the cells known to be free (all non-occupied ones, or those scans saw)."""

import numpy as np
import pytest

from probrob.maps import OccupancyGrid


def test_default_free_is_every_cell_not_occupied():
    occ = np.zeros((4, 5), dtype=bool)
    occ[1, 2] = True
    grid = OccupancyGrid(occ, 0.5)
    np.testing.assert_array_equal(grid.free, ~occ)
    assert not grid.free.flags.writeable


def test_from_scans_knows_only_what_its_beams_saw():
    # one scan from the middle of a 4 m corridor, beams along +x and -x hitting walls at 1.5 m
    poses = np.array([[2.0, 0.5, 0.0]])
    angles = np.array([0.0, np.pi])
    ranges = np.array([[1.45, 1.45]])
    grid = OccupancyGrid.from_scans(poses, ranges, angles, 0.1, max_range=10.0, margin=1.0)
    row = grid.world_to_cell([[2.0, 0.5]])[0, 0]
    free_x = grid.cell_to_world(
        np.stack([np.full(grid.shape[1], row), np.arange(grid.shape[1])], 1)
    )[:, 0][grid.free[row]]
    assert free_x.min() > 0.5 and free_x.max() < 3.5  # between the two walls
    assert not grid.free[row + 3].any()  # no beam went there: unexplored, not free
    assert not np.any(grid.free & grid.occupied)


@pytest.mark.parametrize(
    ("free", "message"),
    [
        (np.ones((2, 2), dtype=bool), "free must be a boolean array of the shape"),
        (np.ones((3, 3)), "free must be a boolean array"),
        (np.ones((3, 3), dtype=bool), "overlap"),
    ],
)
def test_free_is_checked(free, message):
    occ = np.zeros((3, 3), dtype=bool)
    occ[0, 0] = True
    with pytest.raises(ValueError, match=message):
        OccupancyGrid(occ, 1.0, free=free)
