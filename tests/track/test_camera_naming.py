"""Which camera id a found camera gets (broadtrack_graph.track.camera_naming): the trusted chain's, or where it
stands and whether the frame is still explained from a known camera's position."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.camera_naming import CameraNaming
from broadtrack_graph.track.chain import Chain
from broadtrack_graph.track.config import TrackingConfig

CONFIG = TrackingConfig()
MAIN_W = np.array([0.0, 55.0, -12.0])


def _camera(position_w) -> Camera:
    return Camera(2000.0, 0.0, 0.0, np.radians(70.0), 0.0, np.asarray(position_w, float), 1280, 720)


def _refine_scoring(confidence: float, calls: list):
    """A refiner that returns the guess it is given at ``confidence`` and records where it was asked to stand."""

    def refine(guesses, detections, curves):
        calls.append(np.asarray(guesses[0][1].position_m, float))
        return ReinitResult(guesses[0][1], LabelledScore(confidence, 0, 0, 0, 0.0, 0.0), guesses[0][0])

    return refine


def _naming(refined_confidence: float, calls: list):
    registry = CameraRegistry(known={"main": MAIN_W})
    return CameraNaming(CONFIG, registry, Chain(CONFIG, registry), _refine_scoring(refined_confidence, calls))


MAP_FRAME = (SimpleNamespace(marking_mask=np.ones((4, 4), bool)), None, lambda camera: 0.9)


def test_a_confident_camera_at_a_known_tripod_that_still_explains_the_frame_there_takes_its_id():
    calls: list = []
    naming = _naming(0.85, calls)
    camera = _camera(MAIN_W + [1.0, 2.0, 0.5])
    assert naming.id_of(ReinitResult(camera, None, ""), 0.9, MAP_FRAME) == "main"
    np.testing.assert_allclose(calls[0], MAIN_W)  # refined with its focal point moved to the known tripod


def test_a_confident_camera_the_known_tripod_does_not_explain_gets_a_new_id():
    naming = _naming(0.9 - CONFIG.reinit_switch_margin - 0.01, [])
    camera = _camera(MAIN_W + [1.0, 2.0, 0.5])
    camera_id = naming.id_of(ReinitResult(camera, None, ""), 0.9, MAP_FRAME)
    assert camera_id not in (None, "main") and camera_id in naming.registry.untrusted


def test_a_camera_found_on_a_known_tripod_takes_its_id_without_a_refit():
    # The known camera's search holds its focal point there: the frame is explained from there already (a refit with
    # the focal point free can slide off a narrow view's few markings and score lower).
    calls: list = []
    naming = _naming(0.1, calls)
    on_it = _camera(MAIN_W + [0.3, -0.4, 0.2])
    assert naming.id_of(ReinitResult(on_it, None, ""), 0.9, MAP_FRAME) == "main" and calls == []
    beside = _camera(MAIN_W + [1.0, 2.0, 0.5])  # off the tripod: refitted there (0.1, under the margin)
    assert naming.id_of(ReinitResult(beside, None, ""), 0.9, MAP_FRAME) != "main" and len(calls) == 1


def test_labelled_detections_without_a_map_are_named_by_where_the_camera_stands():
    calls: list = []
    naming = _naming(0.0, calls)
    frame = (SimpleNamespace(marking_mask=None), None, lambda camera: 0.9)
    assert naming.id_of(ReinitResult(_camera(MAIN_W + [1.0, 0.0, 0.0]), None, ""), 0.9, frame) == "main"
    assert calls == []


def test_a_camera_under_the_threshold_takes_the_nearest_known_id_and_adds_none():
    naming = _naming(0.0, [])
    low = CONFIG.confidence_threshold - 0.1
    assert naming.id_of(ReinitResult(_camera(MAIN_W + [2.0, 0.0, 0.0]), None, ""), low, MAP_FRAME) == "main"
    assert naming.id_of(ReinitResult(_camera((-75.0, 0.0, -24.0)), None, ""), low, MAP_FRAME) is None
    assert set(naming.registry.positions) == {"main"}


def test_a_trusted_chain_keeps_its_own_id_wherever_the_camera_stands():
    naming = _naming(0.0, [])
    naming.chain.identify("main")
    naming.chain.trust(0)
    far = _camera((-75.0, 0.0, -24.0))
    assert naming.id_of(ReinitResult(far, None, ""), 0.95, MAP_FRAME) == "main"


def test_a_narrow_view_far_along_its_line_of_sight_is_refined_from_the_known_tripod_with_its_view_kept():
    # A 9 deg view (f 8000 px at 1280) of the centre spot found 20 m nearer than the main camera's tripod, along its
    # line of sight: the refit starts at the tripod aimed at the same ground point, its focal length scaled by the
    # distances (the same image there), and the id is main's.
    aim = np.zeros(3)
    tripod = MAIN_W
    sight = (aim - tripod) / np.linalg.norm(aim - tripod)
    near = tripod + 20.0 * sight
    pan, tilt = aim_angles(near, aim)
    camera = Camera(8000.0, 0.0, pan, tilt, 0.0, near, 1280, 720)
    calls: list = []
    seen: list = []

    def refine(guesses, detections, curves):
        seen.append(guesses[0][1])
        return _refine_scoring(0.85, calls)(guesses, detections, curves)

    registry = CameraRegistry(known={"main": tripod})
    naming = CameraNaming(CONFIG, registry, Chain(CONFIG, registry), refine)
    assert naming.id_of(ReinitResult(camera, None, ""), 0.9, MAP_FRAME) == "main"
    start = seen[0]
    np.testing.assert_allclose(start.position_m, tripod)
    np.testing.assert_allclose(start.project(aim[None])[0][0], [640.0, 360.0], atol=1e-6)  # still aimed at it
    distance_ratio = np.linalg.norm(tripod) / np.linalg.norm(near)
    np.testing.assert_allclose(start.focal_px, 8000.0 * distance_ratio)
    # The same view 37 deg across or wider (f 1500 px) is not narrow: 20 m along its line of sight, another camera;
    # nor is the narrow view tried there without a marking map to tell (labelled detections).
    wide = camera.replace(focal_px=1500.0)
    assert naming.id_of(ReinitResult(wide, None, ""), 0.9, MAP_FRAME) not in (None, "main")
    labelled = (SimpleNamespace(marking_mask=None), None, lambda camera: 0.9)
    assert naming.id_of(ReinitResult(camera, None, ""), 0.9, labelled) not in (None, "main")
