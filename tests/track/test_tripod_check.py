"""The tripod an offline pass holds (broadtrack_graph.track.tripod_check): a consistent fit is kept; cameras that do
not share a tripod (wrong cameras scattered along the stand, all looking at one spot) give a fit on the grass, which
is rejected for the cameras' own median; a refined camera under the grass is not written."""

from __future__ import annotations

import numpy as np
from tripod_cameras import cameras_on

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.tripod_fit import fit_tripod_for_run
from broadtrack_graph.reinit.frame import plausible_position
from broadtrack_graph.track.chunked import refined_record
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.tripod_check import offline_tripod, rejected_fit
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

CONFIG = TrackingConfig(tripod_provisional_frames=10, tripod_fit_min_inliers=0.6)
PITCH = PitchTemplate()


def cameras_looking_at(spot_w, count: int, seed: int = 2) -> list[Camera]:
    """Focal points scattered over 25 m of the main stand, 14-19 m up, each looking at ``spot_w`` (a chain of wrong
    cameras that all put the same markings in view)."""
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        position = np.array([rng.uniform(0.0, 25.0), rng.uniform(63.0, 83.0), -rng.uniform(14.0, 19.0)])
        pan, tilt = aim_angles(position, np.asarray(spot_w, float))
        cameras.append(Camera(7000.0, 0.0, pan, tilt, 0.0, position, 1920, 1080))
    return cameras


def test_a_consistent_fit_is_kept():
    truth = Tripod((-20.0, 60.0, -18.0), 0.2)
    tripod, info = offline_tripod(cameras_on(truth, 30), CONFIG, GraphConfig(), PITCH)
    assert "rejected" not in info and not info.get("provisional")
    np.testing.assert_allclose(tripod.T_w, truth.T_w, atol=0.05)


def test_cameras_that_share_no_tripod_give_a_fit_on_the_grass_that_is_rejected():
    spot = (-25.0, -13.0, 0.0)
    cameras = cameras_looking_at(spot, 30)
    fitted, info = fit_tripod_for_run(cameras, GraphConfig().solver)
    assert np.linalg.norm(np.subtract(fitted.T_w, spot)) < 1.0  # the point their axes share: where they look
    assert rejected_fit(fitted, info, CONFIG, PITCH) is not None
    tripod, info = offline_tripod(cameras, CONFIG, GraphConfig(), PITCH)
    assert info["provisional"] and info["rejected"].endswith("not a consistent tripod")
    assert plausible_position(tripod.T_w, PITCH)
    centres = np.array([c.position_m for c in cameras])
    assert np.all(tripod.T_w >= centres.min(axis=0) - 1.0) and np.all(tripod.T_w <= centres.max(axis=0) + 1.0)


def test_too_few_cameras_get_the_provisional_tripod_and_none_where_no_camera_stands():
    truth = Tripod((-20.0, 60.0, -18.0), 0.2)
    tripod, info = offline_tripod(cameras_on(truth, 5), CONFIG, GraphConfig(), PITCH)
    assert info["provisional"] and info["reason"].startswith("fewer than 10 frames")
    np.testing.assert_allclose(tripod.T_w, truth.T_w, atol=1e-9)
    tripod, info = offline_tripod(cameras_on(Tripod((0.0, 0.0, -18.0), 0.2), 5), CONFIG, GraphConfig(), PITCH)
    assert tripod is None and not info["provisional"]  # over the centre spot


def test_a_refined_camera_under_the_grass_is_not_written():
    first = cameras_on(Tripod((-20.0, 60.0, -18.0), 0.2), 1)[0]
    record = TrackRecord(7, "000008", 0.28, first, {}, 0.8, False, FrameStatus.TRACKED, None)
    observations = FrameObservations(7, 1920, 1080)
    curves, sampling = fitting_curves(PITCH), TemplateSampling(PITCH)
    under = first.replace(position_m=np.array([-25.0, -13.0, 1.7]))
    assert refined_record(record, FrameEstimate(7, under), observations, curves, sampling) is record
    moved = first.replace(position_m=first.position_m + np.array([0.1, 0.0, 0.0]))
    refined = refined_record(record, FrameEstimate(7, moved), observations, curves, sampling)
    np.testing.assert_allclose(refined.camera.position_m, moved.position_m)
