"""A known camera's tripod in re-initialisation (broadtrack_graph.track.known_tripod): the gate on a tripod. The refit
onto a tripod is tested through the policy (tests/track/test_reinit_policy.py)."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import Determinability
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.known_tripod import EXACT_FIT_CONFIDENCE, fixed_on_known_tripod

CONFIG = TrackingConfig()
TRIPOD = np.array([0.0, 55.0, -12.0])
ARC_AND_LINE = Determinability(False, 1, 0, (), curve_shares={"Circle central": 0.2})  # 5 constraints
ONE_OF_EACH = Determinability(False, 1, 1, ())  # 4: exactly a tripod camera's unknowns


def _camera(position_w) -> Camera:
    return Camera(6000.0, 0.0, 0.0, np.radians(80.0), 0.0, np.asarray(position_w, float), 1280, 720)


def test_a_camera_on_its_trusted_tripod_is_fixed_there_at_the_court_model_s_bars():
    registry = CameraRegistry(known={"main": TRIPOD})
    on_it = _camera(TRIPOD + [0.2, -0.3, 0.1])
    bar = CONFIG.court_accept_confidence
    assert fixed_on_known_tripod(registry, CONFIG, "main", on_it, bar, ARC_AND_LINE)
    assert not fixed_on_known_tripod(registry, CONFIG, "main", on_it, bar - 0.01, ARC_AND_LINE)
    assert fixed_on_known_tripod(registry, CONFIG, "main", on_it, EXACT_FIT_CONFIDENCE, ONE_OF_EACH)
    assert not fixed_on_known_tripod(registry, CONFIG, "main", on_it, EXACT_FIT_CONFIDENCE - 0.01, ONE_OF_EACH)
    assert not fixed_on_known_tripod(registry, CONFIG, "main", on_it, 1.0, Determinability(False, 1, 0, ()))


def test_off_its_tripod_or_on_an_untrusted_or_unknown_id_a_camera_is_not():
    registry = CameraRegistry(known={"main": TRIPOD})
    assert not fixed_on_known_tripod(registry, CONFIG, "main", _camera(TRIPOD + [0.0, 2.0, 0.0]), 1.0, ARC_AND_LINE)
    registry.untrusted.add("main")  # a new id, registered where its camera stood: its position is no tripod yet
    assert not fixed_on_known_tripod(registry, CONFIG, "main", _camera(TRIPOD), 1.0, ARC_AND_LINE)
    assert not fixed_on_known_tripod(registry, CONFIG, None, _camera(TRIPOD), 1.0, ARC_AND_LINE)
