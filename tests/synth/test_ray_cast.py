"""Tests of synth/ray_cast.py (through the Renderer): pixel rays are the camera model, and the
surface labels (ground, boards, stands) follow the stadium geometry.
"""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.drawing import SURFACE_BOARD, SURFACE_GOAL, SURFACE_GROUND, SURFACE_STAND
from broadtrack_graph.synth.render import EXACT_SETTINGS, Renderer
from broadtrack_graph.synth.scene import DEFAULT_STADIUM

W, H = 480, 270


def test_renderer_rays_are_the_camera_model():
    camera = Camera.from_degrees(900.0, 0.06, 20.0, 72.0, 0.3, [3.0, 55.0, -12.0], W, H)
    renderer = Renderer(W, H, seed=0, settings=EXACT_SETTINGS)
    dx, dy, dz = renderer.rays(camera)
    rng = np.random.default_rng(0)
    cols, rows = rng.integers(0, W, 200), rng.integers(0, H, 200)
    rays = np.column_stack([dx[rows, cols], dy[rows, cols], dz[rows, cols]]).astype(float)
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    expected = camera.backproject(np.column_stack([cols, rows]).astype(float))
    angle = np.arccos(np.clip(np.sum(rays * expected, axis=1), -1, 1))
    assert angle.max() < 2e-5  # float32 rays, exact distortion inversion


def test_surface_labels_follow_the_geometry():
    # Main camera, wide, looking at the far side: ground, boards and stands in view.
    camera = Camera.from_degrees(500.0, 0.03, 10.0, 82.0, 0.0, [0.0, 55.0, -12.0], W, H)
    frame = Renderer(W, H, seed=0, settings=EXACT_SETTINGS).render(camera)
    labels = frame.labels
    for surface in (SURFACE_GROUND, SURFACE_BOARD, SURFACE_STAND):
        assert np.count_nonzero(labels == surface) > 200
    rng = np.random.default_rng(1)
    st = DEFAULT_STADIUM
    board_rows, board_cols = np.nonzero(labels == SURFACE_BOARD)
    pick = rng.choice(len(board_rows), 100)
    rays = camera.backproject(np.column_stack([board_cols[pick], board_rows[pick]]).astype(float))
    C = camera.position_m
    # Where the ray leaves the board rectangle (slab method), it is between 0 and 0.9 m high.
    with np.errstate(divide="ignore"):
        t_x = (np.sign(rays[:, 0]) * st.board_half_x_m - C[0]) / rays[:, 0]
        t_y = (np.sign(rays[:, 1]) * st.board_half_y_m - C[1]) / rays[:, 1]
    z = C[2] + np.minimum(t_x, t_y) * rays[:, 2]
    assert np.all((z > -st.board_height_m - 0.05) & (z < 0.05))
    ground_rows, ground_cols = np.nonzero(labels == SURFACE_GROUND)
    pick = rng.choice(len(ground_rows), 200)
    points, hits = camera.ground_intersection(np.column_stack([ground_cols[pick], ground_rows[pick]]).astype(float))
    assert hits.all()
    assert np.all(np.abs(points[:, 1]) <= st.stand_half_y_m + 0.05)
    stand_rows, stand_cols = np.nonzero(labels == SURFACE_STAND)
    pick = rng.choice(len(stand_rows), 100)
    points, hits = camera.ground_intersection(np.column_stack([stand_cols[pick], stand_rows[pick]]).astype(float))
    beyond = ~hits | (np.abs(points[:, 1]) > st.stand_half_y_m) | (np.abs(points[:, 0]) > st.stand_half_x_m)
    assert beyond.all()


def _expected_board(camera, uv_px):
    """(N,) bool: the pixel's ray meets a board wall (0..0.9 m high) before the ground, in float64."""
    st = DEFAULT_STADIUM
    rays = camera.backproject(uv_px)
    C = camera.position_m
    with np.errstate(divide="ignore", invalid="ignore"):
        t_ground = np.where(rays[:, 2] > 0, -C[2] / rays[:, 2], np.inf)
        t_board = np.full(len(rays), np.inf)
        for axis, half, other_half in ((0, st.board_half_x_m, st.board_half_y_m), (1, st.board_half_y_m, st.board_half_x_m)):
            for sign in (-1.0, 1.0):
                t = (sign * half - C[axis]) / rays[:, axis]
                hit = C + t[:, None] * rays
                ok = (t > 0) & (np.abs(hit[:, 1 - axis]) <= other_half) & (hit[:, 2] <= 0) & (hit[:, 2] >= -st.board_height_m)
                t_board = np.where(ok & (t < t_board), t, t_board)
    return t_board < t_ground


@pytest.mark.parametrize("pan_deg, tilt_deg, focal_px", [(10.0, 82.0, 500.0), (-35.0, 62.0, 400.0), (60.0, 75.0, 700.0)])
def test_board_pixels_are_exactly_the_rays_meeting_a_board(pan_deg, tilt_deg, focal_px):
    camera = Camera.from_degrees(focal_px, 0.02, pan_deg, tilt_deg, 0.0, [0.0, 55.0, -12.0], W, H)
    labels = Renderer(W, H, seed=0, settings=EXACT_SETTINGS).render(camera).labels
    rng = np.random.default_rng(5)
    uv = np.column_stack([rng.integers(0, W, 4000), rng.integers(0, H, 4000)]).astype(float)
    expected = _expected_board(camera, uv)
    label = labels[uv[:, 1].astype(int), uv[:, 0].astype(int)]
    got = label == SURFACE_BOARD
    background = label != SURFACE_GOAL  # the goals are drawn over whatever is behind them
    assert expected[background].sum() > 30  # the view shows boards
    assert np.sum(expected[background] != got[background]) <= 3  # float32 rays may flip an edge pixel
