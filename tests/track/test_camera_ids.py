"""Camera ids by tripod position (broadtrack_graph.track.camera_ids) and camera kinds (reinit.positions)."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.reinit.positions import CAMERA_KINDS, camera_kind, mirrored_position
from broadtrack_graph.track.camera_ids import ON_TRIPOD_M, CameraRegistry


@pytest.mark.parametrize("kind", CAMERA_KINDS, ids=[k.name for k in CAMERA_KINDS])
def test_every_kind_s_positions_and_their_mirrors_are_that_kind(kind):
    for position in kind.positions_w:
        for p in (position, mirrored_position(position)):
            name, distance = camera_kind(p)
            assert name == kind.name and distance == pytest.approx(0.0)


def test_a_camera_a_few_metres_off_a_guess_is_of_its_kind():
    assert camera_kind((1.5, 57.0, -13.0))[0] == "main"
    assert camera_kind((53.9, 71.2, -23.1)) == ("high-corner", pytest.approx(np.linalg.norm([1.4, 1.2, 1.1])))
    assert camera_kind((-66.0, 1.0, -16.0))[0] == "high-behind"
    assert camera_kind((37.0, 41.0, -5.5))[0] == "low-16m"


def test_the_first_main_camera_is_main_and_others_get_numbered_ids():
    registry = CameraRegistry(same_camera_m=8.0)
    assert registry.identify((0.5, 56.0, -12.5)) == "main"
    assert registry.identify((1.0, 58.0, -13.0)) == "main"  # the same tripod, 2 m off
    assert registry.identify((53.9, 71.2, -23.1)) == "high-corner-1"
    assert registry.identify((-54.0, 70.0, -22.0)) == "high-corner-2"  # the other corner
    assert registry.identify((0.0, 80.0, -17.0)) == "main-1"  # a second camera on the main camera's line
    assert registry.nearest((53.0, 70.5, -22.5)) == "high-corner-1"
    assert registry.nearest((0.0, -55.0, -12.0)) is None


def test_known_tripods_and_updates_identify_their_cameras():
    registry = CameraRegistry(known={"main": (0.0, 55.0, -12.0), "high-behind-1": (-75.0, 0.0, -24.0)})
    assert registry.identify((-74.0, 0.5, -23.5)) == "high-behind-1"
    registry.update("main", (0.0, 70.0, -15.0))  # the fitted tripod moved it
    assert registry.identify((0.0, 71.0, -15.0)) == "main"
    assert registry.identify((0.0, 55.0, -12.0)) == "main-1"


def test_along_the_line_of_sight_is_one_camera_across_it_another():
    # A main camera 77 m back and 13 m up, looking at the centre spot.
    position = np.array([0.2, 77.0, -13.0])
    sight = -position / np.linalg.norm(position)
    registry = CameraRegistry(known={"main": position})
    # Re-initialised on one shot, the same camera slides metres along its line of sight.
    assert registry.identify(position + 10.0 * sight, sight) == "main"
    assert registry.stands_at("main", position - 9.0 * sight, sight)
    # Another stadium's main camera 5 m lower and 2 m aside (both 75-77 m back) is another camera,
    # though it stands within the 8 m that distance alone would accept.
    other = np.array([-1.6, 75.5, -18.4])
    assert np.linalg.norm(other - position) < 8.0 and registry.nearest(other) == "main"
    assert registry.nearest(other, sight) is None
    assert registry.identify(other, sight) == "main-1"
    assert registry.identify(other + 3.0 * sight, sight) == "main-1"


def test_the_guesses_are_each_id_s_last_trusted_camera_and_that_camera_at_its_tripod():
    from broadtrack_graph.geometry.camera import Camera

    registry = CameraRegistry()
    main = Camera(1500.0, 0.0, 0.2, 1.3, 0.0, (0.0, 55.0, -12.0), 1280, 720)
    corner = Camera(4400.0, 0.0, -0.1, 1.25, 0.0, (53.0, 70.0, -22.0), 1280, 720)
    assert registry.identify(main.position_m) == "main"
    registry.trust("main", 10, main)
    registry.trust("high-corner-1", 20, corner)
    assert registry.untrusted == set()
    # A new shot: every camera's guess.
    assert [g.camera_id for g in registry.guesses(30, None, 750)] == ["main", "high-corner-1"]
    assert [g.camera_id for g in registry.guesses(30, "main", 750)] == ["main"]
    assert [g.camera_id for g in registry.guesses(770, None, 750)] == ["high-corner-1"]  # main's is 760 frames old
    assert registry.guesses(5, None, 750) == []  # a camera trusted later than the frame is no guess of it
    registry.update("main", (0.0, 57.0, -13.0))  # its tripod, 2.2 m from the trusted camera's focal point
    last, at_tripod = registry.guesses(30, "main", 750)
    assert last.camera_id == at_tripod.camera_id == "main"
    assert last.camera is main and last.label == "last confident camera of main (frame 10)"
    moved = at_tripod.camera
    assert at_tripod.label.endswith("at its tripod") and np.allclose(moved.position_m, (0.0, 57.0, -13.0))
    assert moved.pan_rad == main.pan_rad and moved.focal_px == main.focal_px


def test_a_camera_near_a_known_one_whose_view_its_tripod_does_not_explain_gets_a_new_id():
    asked = []

    def fits(camera_id):
        asked.append(camera_id)
        return False  # the frame, refined at the known tripod, is explained much worse: another stadium's camera

    registry = CameraRegistry(known={"main": (0.0, 60.0, -18.0)})
    assert registry.identify((0.5, 61.0, -18.5), fits=fits) == "main-1" and asked == ["main"]
    registry = CameraRegistry(known={"main": (0.0, 60.0, -18.0)})
    assert registry.identify((0.5, 61.0, -18.5), fits=lambda camera_id: camera_id == "main") == "main"
    assert registry.identify((0.0, -60.0, -18.0), fits=fits) != "main" and asked == ["main"]  # nowhere near: not asked


def test_a_narrow_view_far_along_its_line_of_sight_is_tried_as_the_known_camera_when_the_frame_can_tell():
    # The main camera 77 m back and 13 m up looking at the centre spot; a narrow view found 25 m along that line,
    # 0.5 m across it (a zoomed view's distance fixed loosely): 25 m is past the 12 m gate, within 0.6 of the 52 m
    # from there to the ground it looks at.
    position = np.array([0.2, 77.0, -13.0])
    sight = -position / np.linalg.norm(position)
    found = position + 25.0 * sight + np.array([0.5, 0.0, 0.0])
    asked: list = []

    def fits(camera_id):
        asked.append(camera_id)
        return True

    assert CameraRegistry(known={"main": position}).identify(found, sight, fits=fits, along_share=0.6) == "main"
    assert asked == ["main"]
    # Without the share, or with the frame telling it is not (fits False), a new id; 5 m across, another camera.
    assert CameraRegistry(known={"main": position}).identify(found, sight, fits=fits) == "main-1"
    assert CameraRegistry(known={"main": position}).identify(found, sight, fits=lambda _: False,
                                                             along_share=0.6) == "main-1"
    aside = position + 25.0 * sight + np.array([5.0, 0.0, 0.0])
    assert CameraRegistry(known={"main": position}).identify(aside, sight, fits=fits, along_share=0.6) == "main-1"
    # Too far along: 40 m is over 0.6 of the 37 m left to the ground.
    farther = position + 40.0 * sight
    assert CameraRegistry(known={"main": position}).identify(farther, sight, fits=fits, along_share=0.6) == "main-1"


def test_a_focal_point_stands_on_a_known_tripod_only_within_a_metre_of_it():
    registry = CameraRegistry(known={"main": (0.0, 55.0, -12.0)})
    assert registry.on_tripod("main", (0.3, 55.4, -12.5))
    assert not registry.on_tripod("main", (0.0, 55.0 + 1.5 * ON_TRIPOD_M, -12.0))
    assert registry.stands_at("main", (0.0, 55.0 + 1.5 * ON_TRIPOD_M, -12.0))  # its place, not its tripod
    assert not registry.on_tripod("high-behind-1", (0.0, 55.0, -12.0))
