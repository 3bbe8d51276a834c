"""The online tripod policy (broadtrack_graph.track.online_tripod): provisional tripod, fit, rejection,
on synthetic cameras on a known tripod."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from tripod_cameras import cameras_on

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.online_tripod import OnlineTripod

CONFIG = TrackingConfig(tripod_provisional_frames=5, tripod_fit_frames=30, tripod_fit_min_confidence=0.6,
                        tripod_fit_min_inliers=0.6)


def policy(config=CONFIG, known=None) -> OnlineTripod:
    return OnlineTripod(config, GraphConfig(), PitchTemplate(), known)


def test_provisional_tripod_after_n_confident_frames_then_the_fit():
    truth = Tripod((-20.0, 60.0, -18.0), 0.2)  # delta = the solver's delta prior
    cameras = cameras_on(truth, 30)
    solver = SimpleNamespace(tripod=None)
    online = policy()
    online.update(solver, cameras[0], 0.59)  # not confident enough: left out
    online.update(solver, None, 0.9)  # no camera: left out
    online.update(solver, cameras[0], None)
    assert online.cameras == [] and online.info is None
    for camera in cameras[:4]:
        online.update(solver, camera, 0.9)
    assert solver.tripod is None
    online.update(solver, cameras[4], 0.9)
    np.testing.assert_allclose(solver.tripod.T_w, truth.T_w, atol=1e-9)  # exact: lambda and delta as assumed
    assert solver.tripod.delta_m == 0.2
    assert online.provisional
    assert online.info == {"provisional": True, "frames": 5,
                           "reason": "typical delta and lambda; replaced once enough frames are fitted"}
    provisional = solver.tripod
    for camera in cameras[5:29]:
        online.update(solver, camera, 0.9)
    assert solver.tripod is provisional and len(online.cameras) == 29
    online.update(solver, cameras[29], 0.9)
    assert solver.tripod is not provisional and not online.provisional
    np.testing.assert_allclose(solver.tripod.as_vector(), truth.as_vector(), atol=1e-6)
    assert online.info["inlier_ratio"] == 1.0 and "rejected" not in online.info
    assert "inliers" not in online.info  # per-camera arrays are left out
    assert online.cameras == []
    # Fitted: the tripod is held; later frames are not collected.
    online.update(solver, cameras[0], 0.9)
    assert online.cameras == []


def test_a_tripod_on_the_pitch_is_rejected_and_retried_with_the_newer_half():
    above_pitch = Tripod((10.0, 5.0, -12.0), 0.2)  # over the field: not a broadcast tripod
    cameras = cameras_on(above_pitch, 45, seed=2)
    solver = SimpleNamespace(tripod=None)
    online = policy()
    for camera in cameras[:29]:
        online.update(solver, camera, 0.9)
    assert solver.tripod is None and online.info is None  # no provisional tripod on the pitch either
    online.update(solver, cameras[29], 0.9)
    assert solver.tripod is None
    assert online.info["rejected"] == "inlier ratio 1.00, T [10.0, 5.0, -12.0]: not a consistent tripod"
    assert online.cameras == cameras[15:30]
    for camera in cameras[30:44]:
        online.update(solver, camera, 0.9)
    assert online.cameras == cameras[15:44]
    online.update(solver, cameras[44], 0.9)  # 30 again: fitted again, rejected again
    assert solver.tripod is None and online.cameras == cameras[30:45]


def test_inconsistent_cameras_are_rejected():
    rng = np.random.default_rng(3)
    scattered = [c.replace(position_m=c.position_m + rng.normal(0, 3.0, 3))
                 for c in cameras_on(Tripod((-60.0, 0.0, -20.0), 0.2), 30, seed=3)]
    solver = SimpleNamespace(tripod=None)
    online = policy(TrackingConfig(tripod_provisional_frames=0, tripod_fit_frames=30))
    for camera in scattered:
        online.update(solver, camera, 0.9)
    assert solver.tripod is None and online.info["inlier_ratio"] < 0.6
    assert online.info["rejected"].endswith(": not a consistent tripod")
    assert len(online.cameras) == 15


def test_known_tripod_batch_mode_or_no_tripod_term_leave_the_solver_alone():
    camera = cameras_on(Tripod((-20.0, 60.0, -18.0), 0.2), 1)[0]
    known = Tripod((-20.0, 60.0, -18.0), 0.3)
    for online in (policy(known=known), policy(TrackingConfig(mode="batch", tripod_provisional_frames=1)),
                   policy(TrackingConfig(use_tripod=False, tripod_provisional_frames=1))):
        solver = SimpleNamespace(tripod=None)
        for _ in range(40):
            online.update(solver, camera, 1.0)
        assert solver.tripod is None and online.cameras == [] and online.info is None


def test_one_tripod_per_camera_id_is_kept_and_put_back():
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.tripod import Tripod
    from broadtrack_graph.graph.config import GraphConfig
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.track.online_tripod import OnlineTripod

    class Holder:
        tripod = None

    main, other = Tripod((0.0, 60.0, -15.0), 0.2), Tripod((-30.0, 55.0, -10.0), 0.3)
    policy = OnlineTripod(TrackingConfig(mode="online"), GraphConfig(), PitchTemplate(), None, {"main": main})
    solver = Holder()
    policy.switch(solver, "main")
    assert solver.tripod is main
    policy.switch(solver, "cam2")
    assert solver.tripod is None  # a new camera: fitted from its own frames
    solver.tripod = other  # (as a fit would set it)
    policy.switch(solver, "main")
    assert solver.tripod is main
    policy.switch(solver, "cam2")
    assert solver.tripod is other


def test_a_camera_not_identified_yet_is_solved_without_the_tripod_of_the_camera_before_it():
    main, other = Tripod((0.0, 60.0, -15.0), 0.2), Tripod((-30.0, 55.0, -10.0), 0.3)
    online = policy(TrackingConfig(mode="online"))
    solver = SimpleNamespace(tripod=None)
    online.switch(solver, "main")
    solver.tripod = main  # (as a fit would set it)
    online.release(solver)  # a new shot's camera without an id yet: not pulled to where the main camera stands
    assert solver.tripod is None and online.held_id is None
    online.switch(solver, "cam2")  # identified: a new camera, fitted from its own frames
    assert solver.tripod is None
    solver.tripod = other
    online.switch(solver, "main")  # the main camera's tripod was kept
    assert solver.tripod is main
    # A tripod given to the run without camera ids stays for the first camera (nothing identified before it).
    given = policy(known=main)
    solver = SimpleNamespace(tripod=main)
    given.release(solver)
    assert solver.tripod is main
    given.switch(solver, "main")
    assert solver.tripod is main


def test_a_new_chain_standing_elsewhere_drops_the_cameras_collected_for_the_tripod():
    truth = Tripod((0.0, 55.0, -12.0), 0.2)
    cameras = cameras_on(truth, 8)
    solver = SimpleNamespace(tripod=None)
    online = policy()
    for camera in cameras[:5]:
        online.update(solver, camera, 0.9)
    assert online.provisional and solver.tripod is not None
    registry = CameraRegistry()
    # The same camera re-found by a search 6 m back along its line of sight and 1 m across it: kept.
    same = cameras[5]
    moved = same.replace(position_m=np.asarray(same.position_m) - 6.0 * same.R_cw[2] + 1.0 * same.R_cw[0])
    online.new_chain(solver, moved, registry)
    assert online.provisional and solver.tripod is not None and len(online.cameras) == 5
    # A chain of a camera standing 8 m across its line of sight from them (the wrong chain it replaces stood there):
    # their tripod would pull every frame of it off.
    elsewhere = same.replace(position_m=np.asarray(same.position_m) + 8.0 * same.R_cw[0])
    online.new_chain(solver, elsewhere, registry)
    assert solver.tripod is None and not online.provisional and online.cameras == [] and online.info is None
    # Cameras collected before a provisional tripod are dropped too; a fitted or given tripod stays.
    online.update(solver, cameras[6], 0.9)
    online.new_chain(solver, elsewhere, registry)
    assert online.cameras == []
    fitted = SimpleNamespace(tripod=truth)
    online.new_chain(fitted, elsewhere, registry)
    assert fitted.tripod is truth
    given = policy(known=truth)
    solver = SimpleNamespace(tripod=truth)
    given.new_chain(solver, elsewhere, registry)
    assert solver.tripod is truth
