"""Bird's-eye view: footprint geometry, the metre -> pixel mapping, drawing and insets."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.products.birdseye import (
    CAMERA_BGR,
    BirdseyeView,
    camera_footprint_w,
    draw_birdseye,
    place_inset,
)


def test_footprint_of_a_camera_looking_straight_down():
    # tilt 0 looks straight down; with pan = roll = 0 the camera x axis is world x, camera y is world y.
    camera = Camera.from_degrees(1000, 0.0, 0, 0, 0, (3.0, -2.0, -20.0), 1000, 500)
    footprint = camera_footprint_w(camera, samples_per_edge=4)
    assert footprint.shape == (16, 2)
    # Image corner (0, 0): x_n = (-0.5, -0.25) -> ground offset 20 m * (-0.5, -0.25).
    assert footprint[0] == pytest.approx([3.0 - 10.0, -2.0 - 5.0])
    assert footprint[:, 0].min() == pytest.approx(-7.0) and footprint[:, 0].max() == pytest.approx(13.0)
    assert footprint[:, 1].min() == pytest.approx(-7.0) and footprint[:, 1].max() == pytest.approx(3.0)
    # Right edge starts at the top-right corner.
    assert footprint[4] == pytest.approx([13.0, -7.0])


def test_footprint_rotates_with_pan():
    base = Camera.from_degrees(1000, 0.0, 0, 0, 0, (0.0, 0.0, -20.0), 1000, 500)
    turned = base.replace(pan_rad=math.radians(90))
    a = camera_footprint_w(base, samples_per_edge=3)
    b = camera_footprint_w(turned, samples_per_edge=3)
    # Looking down, panning by 90 deg turns the footprint by 90 deg about the camera.
    rotation = np.array([[0.0, -1.0], [1.0, 0.0]])
    assert np.allclose(b, a @ rotation.T, atol=1e-9) or np.allclose(b, a @ rotation, atol=1e-9)


def test_footprint_above_horizon_is_cut_at_far_distance():
    camera = Camera.from_degrees(800, 0.0, 0, 90, 0, (0.0, 50.0, -15.0), 800, 450)  # horizontal view
    footprint = camera_footprint_w(camera, far_m=100.0)
    distance = np.hypot(*(footprint - camera.position_m[:2]).T)
    assert distance.max() == pytest.approx(100.0)
    assert (distance <= 100.0 + 1e-9).all()
    # Pan 0 looks towards -y: the far cut is on the far side of the camera.
    assert footprint[:, 1].min() == pytest.approx(50.0 - 100.0, abs=1.0)
    # The bottom edge, looking down 29 deg at most, reaches the ground in front of the camera.
    bottom = footprint[len(footprint) // 2: 3 * len(footprint) // 4]
    bottom_distance = np.hypot(*(bottom - camera.position_m[:2]).T)
    half_vfov = math.atan(225 / 800)
    assert bottom_distance.min() == pytest.approx(15.0 / math.tan(half_vfov), rel=0.05)


def test_view_mapping_and_fitting():
    view = BirdseyeView((-60.0, 60.0), (-40.0, 40.0), 5.0)
    assert view.size_px == (600, 400)
    assert view.to_px(np.array([[-60.0, -40.0], [0.0, 0.0], [52.5, 34.0]])) == pytest.approx(
        np.array([[0.0, 0.0], [300.0, 200.0], [562.5, 370.0]]))
    fitted = BirdseyeView.fitting(500, camera_positions_w=np.array([[0.0, 55.0, -15.0]]), margin_m=5.0)
    assert fitted.y_range_m == pytest.approx((-39.0, 60.0))
    assert fitted.x_range_m == pytest.approx((-57.5, 57.5))
    assert fitted.pixels_per_m == pytest.approx(500 / 115.0)
    far = BirdseyeView.fitting(500, camera_positions_w=np.array([[0.0, 500.0, -15.0]]))
    assert far.y_range_m == pytest.approx((-39.0, 39.0))  # implausible position: not stretched for it


def test_draw_birdseye_marks_camera_and_footprint():
    camera = Camera.from_degrees(1500, 0.0, 20, 75, 0, (0.0, 55.0, -15.0), 1920, 1080)
    view = BirdseyeView.fitting(460, camera_positions_w=camera.position_m[None])
    image = draw_birdseye(camera, view, footprint_bgr=(255, 0, 255))
    assert image.shape == (view.size_px[1], view.size_px[0], 3)
    col, row = np.round(view.to_px(camera.position_m[:2])[0]).astype(int)
    assert tuple(image[row, col]) == CAMERA_BGR
    # The footprint centre (ground point of the image centre) is tinted magenta.
    centre_w, hit = camera.ground_intersection(np.array([[960.0, 540.0]]))
    assert hit[0]
    c_col, c_row = np.round(view.to_px(centre_w[:, :2])[0]).astype(int)
    empty = draw_birdseye(None, view)
    assert tuple(empty[row, col]) != CAMERA_BGR
    tint = image[c_row, c_col].astype(int) - empty[c_row, c_col].astype(int)
    assert tint[0] > 40 and tint[2] > 40 and tint[1] < -20  # towards magenta
    # Far behind the camera (outside the footprint) nothing changes.
    assert (image[2, 2] == empty[2, 2]).all()


def test_place_inset_corners():
    frame = np.zeros((200, 400, 3), np.uint8)
    inset = np.full((50, 100, 3), 255, np.uint8)
    place_inset(frame, inset, "bottom-left", width_fraction=0.25, margin_px=10, alpha=1.0)
    assert (frame[150:185, 15:105] == 255).all()
    assert (frame[:140] == 0).all() and (frame[:, 120:] == 0).all()
    with pytest.raises(ValueError, match="corner"):
        place_inset(frame, inset, "middle")
