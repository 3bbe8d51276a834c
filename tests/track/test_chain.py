"""The chain's trust state (broadtrack_graph.track.chain): camera id, trust and its bar, lost, carried frames;
the online tripod told of a new camera id through the chain alone."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.chain import Chain
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.online_tripod import OnlineTripod
from broadtrack_graph.track.reinit_decision import ReinitDecision

CONFIG = TrackingConfig(confidence_threshold=0.5, reinit_switch_margin=0.1, max_motion_prior_frames=2)
MAIN = Camera(2000.0, 0.0, 0.0, 1.3, 0.0, (0.0, 55.0, -12.0), 1920, 1080)


def decision(camera_id=None, continues=False, new_camera=False) -> ReinitDecision:
    return ReinitDecision(MAIN, 0.7, camera_id, continues, True, "scripted", new_camera)


def test_a_new_chain_is_lost_untrusted_and_unknown():
    chain = Chain(CONFIG, CameraRegistry())
    assert chain.lost and not chain.trusted and chain.trusted_since is None
    assert chain.camera_id is None and chain.trust_at == pytest.approx(0.5) and chain.carried == 0


def test_a_new_shot_s_camera_is_trusted_only_from_a_frame_at_the_raised_bar():
    chain = Chain(CONFIG, CameraRegistry())
    chain.start(decision("main", new_camera=True))
    assert chain.camera_id == "main" and chain.trust_at == pytest.approx(0.6) and not chain.trusted
    chain.goes_on()
    chain.trust(7)
    chain.trust(9)
    assert chain.trusted and chain.trusted_since == 7 and not chain.lost
    # A re-initialisation that continues it keeps its trust; so does one that replaces its camera mid-shot by a
    # better camera of the same id (the held camera's frames were written: the better one's are too).
    chain.start(decision("main", continues=True))
    assert chain.trusted and chain.continued and chain.trusted_since == 7
    chain.start(decision("main"))
    assert chain.trusted and not chain.continued and chain.trusted_since == 7
    # A new shot's camera, or another camera's, starts a new chain at its bar.
    chain.start(decision("main", new_camera=True))
    assert not chain.trusted and chain.trusted_since is None and chain.trust_at == pytest.approx(0.6)
    chain.trust(11)
    chain.start(decision("high"))
    assert not chain.trusted and chain.trust_at == pytest.approx(0.5)
    # After the chain ended (lost), a re-initialisation starts untrusted whatever its id.
    chain.trust(12)
    chain.faint_look = True  # the frame loop's: the chain's camera needed the faint look
    chain.end()
    assert not chain.faint_look  # the next chain's frames take it only if it needs it too
    chain.start(decision("high"))
    assert not chain.trusted


def test_a_raised_bar_stays_raised_while_its_chain_was_never_trusted():
    chain = Chain(CONFIG, CameraRegistry())
    chain.start(decision(new_camera=True))
    chain.start(decision())  # replaced before any frame reached 0.6
    assert chain.trust_at == pytest.approx(0.6)
    chain.end()
    assert chain.lost and chain.trust_at == pytest.approx(0.5) and not chain.continued


def test_frames_carried_on_the_motion_prior_are_bounded_and_start_over():
    chain = Chain(CONFIG, CameraRegistry())
    assert not chain.carry()  # lost: nothing to carry
    chain.goes_on()
    assert chain.carry() and chain.carry() and not chain.carry() and chain.carried == 2
    chain.observed()
    assert chain.carried == 0 and chain.carry()
    chain.end()
    assert chain.carried == 0


def test_a_chain_is_mostly_sure_while_half_its_scored_frames_reach_the_tripods_bar():
    chain = Chain(CONFIG, CameraRegistry())  # the tripod's bar: tripod_fit_min_confidence = 0.6
    chain.start(decision("main", new_camera=True))
    assert chain.mostly_sure(0.55) is False and chain.mostly_sure(0.6) and chain.mostly_sure(None)
    for confidence in (0.65, 0.62, 0.55):
        chain.rated(confidence)
    assert chain.mostly_sure(0.5)  # 2 of 4 with it
    chain.rated(0.5)
    assert not chain.mostly_sure(0.55) and chain.mostly_sure(0.7)  # 2 of 5; 3 of 5
    assert chain.mostly_sure(None)  # a frame not scored is not counted: 2 of 4
    # A refitted guess continues the chain and its count; a new chain, or the end, starts it over.
    chain.start(decision("main", continues=True))
    assert (chain.frames_rated, chain.frames_sure) == (4, 2)
    chain.start(decision("main"))
    assert (chain.frames_rated, chain.frames_sure) == (0, 0) and chain.mostly_sure(0.5) is False
    chain.rated(0.9)
    chain.end()
    assert (chain.frames_rated, chain.frames_sure) == (0, 0)


def test_the_online_tripod_is_told_of_a_new_camera_id_through_the_chain():
    main, other = Tripod((0.0, 60.0, -15.0), 0.2), Tripod((-30.0, 55.0, -10.0), 0.3)
    solver = SimpleNamespace(tripod=None)
    tripod = OnlineTripod(TrackingConfig(), GraphConfig(), PitchTemplate(), None, {"main": main, "cam2": other})
    chain = Chain(TrackingConfig(), CameraRegistry(), tripod, solver)
    chain.identify("main")
    assert solver.tripod is main and tripod.held_id == "main" and chain.settled_tripod() is main
    chain.start(decision("cam2"))
    assert chain.camera_id == "cam2" and solver.tripod is other
    # A cut: the chain's camera is not known, the tripod of the camera left stays held until one is.
    chain.new_stretch()
    assert chain.camera_id is None and solver.tripod is other and chain.settled_tripod() is None
    chain.start(decision(None))  # a camera not identified yet: no other camera's tripod
    assert solver.tripod is None and tripod.held_id is None
    chain.identify_at(MAIN)  # a confident frame names it by where it stands
    assert chain.camera_id is not None


def test_a_camera_s_place_is_known_once_its_id_is_trusted():
    registry = CameraRegistry()
    chain = Chain(CONFIG, registry)
    assert not chain.place_known  # no id yet
    chain.start(decision(registry.identify(MAIN.position_m, MAIN.R_cw[2])))
    assert chain.camera_id == "main" and not chain.place_known  # a new id, provisional
    registry.trust("main", 3, MAIN)
    assert chain.place_known
    chain.new_stretch()
    assert not chain.place_known
