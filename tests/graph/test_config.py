"""Graph configuration, keys, track containers and the shared builder."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.graph.builder import GraphBuilder
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import EstimateSequence, FrameEstimate
from broadtrack_graph.graph.keys import camera_key, frame_of_key, tripod_key
from broadtrack_graph.types.observations import FlowMatches, FrameObservations, KeypointObservations


def test_config_from_dict_sets_values_and_rejects_unknown_keys():
    config = GraphConfig.from_dict({"measurements": {"line_sigma_px": 2.0}, "use_flow": False})
    assert config.measurements.line_sigma_px == 2.0 and config.measurements.keypoint_sigma_px == 2.0
    assert config.use_flow is False
    with pytest.raises(ValueError, match="unknown graph config keys"):
        GraphConfig.from_dict({"lines": {}})
    with pytest.raises(ValueError, match="line_sigma"):
        GraphConfig.from_dict({"measurements": {"line_sigma": 1.0}})
    assert GraphConfig().measurements.line_loss == "cauchy"
    assert GraphConfig.from_dict({"measurements": {"line_loss": "geman-mcclure"}}).measurements.line_loss == \
        "geman-mcclure"
    with pytest.raises(ValueError, match="line_loss must be one of cauchy, geman-mcclure"):
        GraphConfig.from_dict({"measurements": {"line_loss": "huber"}})


def test_random_walk_vector_order_and_focal_range():
    config = GraphConfig()
    sigmas = config.motion.random_walk_vector()
    assert sigmas.shape == (8,) and sigmas[2] == pytest.approx(math.radians(1.0)) and sigmas[5] == 0.01
    assert config.priors.focal_range_px(960) == (pytest.approx(288.0), pytest.approx(14400.0))


def test_keys_are_distinct_and_invertible():
    assert camera_key(5) != camera_key(6) != tripod_key()
    assert frame_of_key(camera_key(1234)) == 1234


def test_track_states_and_std_dict():
    camera = Camera.from_degrees(1500.0, -0.05, 10.0, 80.0, 0.1, (0.0, 55.0, -12.0), 960, 540)
    std = np.array([2.0, 0.01, math.radians(0.02), math.radians(0.01), math.radians(0.03), 0.05, 0.05, 0.02])
    track = EstimateSequence([FrameEstimate(0, camera, std, {"lines": 10}), FrameEstimate(1, None, None, {}, reason="cut")])
    states = track.states()
    assert states.shape == (2, 8) and np.allclose(states[0], camera.to_vector()) and np.isnan(states[1]).all()
    d = track[0].std_dict()
    assert d["pan_deg"] == pytest.approx(0.02) and d["f_px"] == 2.0 and track[1].std_dict() is None


def test_builder_uses_known_classes_only_and_counts_measurements():
    builder = GraphBuilder(960, 540, PitchTemplate())
    obs = FrameObservations(
        3, 960, 540,
        lines_px={"Middle line": np.array([[480.0, 100.0], [481.0, 200.0]]), "Line unknown": np.array([[1.0, 2.0]]),
                  "Goal left post left ": np.array([[10.0, 20.0]])},
        keypoints=KeypointObservations(np.array([[480.0, 300.0]]), np.zeros((1, 3)), np.ones(1), ["Centre spot"]),
        flow=FlowMatches(np.zeros((5, 2)), np.ones((5, 2))),
    )
    uv, cls, names = builder.line_arrays(obs)
    assert uv.shape == (3, 2)  # "Line unknown" dropped, trailing space stripped
    assert {names[j] for j in cls} == {"Middle line", "Goal left post left"}
    frame = builder.measurement_factors(obs, 3, 2)
    assert frame.active == {"lines": 3, "keypoints": 1, "flow": 5}
    assert len(builder.measurement_factors(obs, 3, None).factors) == 2  # no flow without a predecessor


def test_a_provisional_tripod_holds_the_camera_only_as_firmly_as_its_cameras_agree():
    import gtsam

    from broadtrack_graph.geometry.tripod import Tripod
    from broadtrack_graph.graph.builder import FrameFactors

    builder = GraphBuilder(960, 540, PitchTemplate())
    m = builder.config.measurements
    camera = Camera(1000.0, 0.0, 0.1, 1.3, 0.0, (0.0, 55.0, -12.0), 960, 540)
    values = gtsam.Values()
    values.insert(camera_key(0), camera.to_vector())
    # A tripod 1 m beside the camera's axis point, held firmly (fitted) and loosely (uncertain by 2 m).
    T = np.asarray(camera.position_m) + 0.2 * camera.R_cw[1] - 0.2 * camera.R_cw[2] + [1.0, 0.0, 0.0]
    errors = []
    for spread in (0.0, 2.0):
        frame = builder.tripod_factor(0, FrameFactors(), Tripod(tuple(T), 0.2, spread))
        assert frame.active == {"tripod": 1}
        errors.append(frame.factors[0].error(values))
    firm, loose = errors
    # The axis-point residuals scale by sigma; the lambda prior's weight is sigma / its own sigma.
    sigma = math.hypot(m.tripod_sigma_m, 2.0)
    assert firm > 100.0 and loose < firm * (m.tripod_sigma_m / sigma) ** 2 * 1.5
