"""Where a camera looks on the ground, and a camera moved keeping that view (broadtrack_graph.geometry.aim)."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.aim import aim_angles, ground_aim, moved_keeping_view
from broadtrack_graph.geometry.camera import Camera

POSITION = np.array([-4.0, 70.0, -16.0])
AIM = np.array([-30.0, 5.0, 0.0])


def _aimed(focal_px: float, position=POSITION, aim=AIM) -> Camera:
    return Camera(focal_px, 0.05, *aim_angles(position, aim), 0.4 * np.pi / 180, np.asarray(position, float), 1280, 720)


def test_the_ground_aim_is_where_the_optical_axis_meets_the_ground():
    camera = _aimed(2500.0)
    np.testing.assert_allclose(ground_aim(camera), AIM, atol=1e-9)
    uv, front = camera.project(AIM[None])
    assert front[0] and np.allclose(uv[0], [640.0, 360.0], atol=1e-6)
    assert ground_aim(camera.replace(tilt_rad=np.pi / 2 + 0.1)) is None  # looking above the horizon
    assert ground_aim(camera.replace(position_m=np.array([0.0, 70.0, 2.0]))) is None  # under the ground


def test_a_camera_moved_along_its_line_of_sight_keeps_a_narrow_view_nearly_the_same():
    narrow = _aimed(9000.0)  # about 8 deg across at 1280 px
    sight = (AIM - POSITION) / np.linalg.norm(AIM - POSITION)
    farther = POSITION - 25.0 * sight
    moved = moved_keeping_view(narrow, farther)
    np.testing.assert_allclose(moved.position_m, farther)
    np.testing.assert_allclose(ground_aim(moved), AIM, atol=1e-9)
    ratio = np.linalg.norm(AIM - farther) / np.linalg.norm(AIM - POSITION)
    np.testing.assert_allclose(moved.focal_px, 9000.0 * ratio)
    assert moved.k1 == narrow.k1 and moved.roll_rad == narrow.roll_rad
    # The ground the narrow view shows (within 4 m of the aim) is drawn within a few pixels from there ...
    grid = np.array([[AIM[0] + dx, AIM[1] + dy, 0.0] for dx in (-4, 0, 4) for dy in (-4, 0, 4)])
    uv_before, _ = narrow.project(grid)
    uv_after, _ = moved.project(grid)
    assert np.abs(uv_after - uv_before).max() < 8.0
    # ... a wide view's perspective shows the move (its corners tens of pixels off).
    wide = _aimed(900.0)
    wide_grid = np.array([[AIM[0] + dx, AIM[1] + dy, 0.0] for dx in (-25, 0, 25) for dy in (-15, 0, 15)])
    uv_wide, _ = wide.project(wide_grid)
    uv_wide_moved, _ = moved_keeping_view(wide, farther).project(wide_grid)
    assert np.abs(uv_wide_moved - uv_wide).max() > 20.0


def test_no_move_keeps_a_view_that_does_not_reach_the_ground():
    assert moved_keeping_view(_aimed(2000.0).replace(tilt_rad=np.pi / 2 + 0.1), POSITION + 5.0) is None
    assert moved_keeping_view(_aimed(2000.0), np.array([0.0, 60.0, 1.0])) is None  # the new place under the ground
