"""ONNX detectors: a tiny model built here, the JSON contract, line thinning and keypoint peaks."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

onnx = pytest.importorskip("onnx")
from onnx import TensorProto, helper  # noqa: E402

from broadtrack_graph.detect.onnx_detector import ModelContract, OnnxDetector, read_contract  # noqa: E402
from broadtrack_graph.errors import InputError  # noqa: E402

NET_W, NET_H = 64, 48


def _conv_model(path, weights: np.ndarray, bias: np.ndarray) -> None:
    """(1, 3, H, W) -> 1x1 convolution -> (1, C, H, W)."""
    channels = weights.shape[0]
    w = helper.make_tensor("w", TensorProto.FLOAT, (channels, 3, 1, 1), weights.astype(np.float32).ravel().tolist())
    b = helper.make_tensor("b", TensorProto.FLOAT, (channels,), bias.astype(np.float32).tolist())
    node = helper.make_node("Conv", ["image", "w", "b"], ["scores"])
    graph = helper.make_graph(
        [node], "tiny", [helper.make_tensor_value_info("image", TensorProto.FLOAT, (1, 3, NET_H, NET_W))],
        [helper.make_tensor_value_info("scores", TensorProto.FLOAT, (1, channels, NET_H, NET_W))], initializer=[w, b])
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)])
    model.ir_version = 8
    onnx.save(model, str(path))


def _write_contract(path, kind, classes, activation="softmax", colour="RGB", threshold=0.5, **extra):
    contract = ModelContract(kind, NET_W, NET_H, colour, 1 / 255, (0.0, 0.0, 0.0), (1.0, 1.0, 1.0), activation,
                             tuple(classes), threshold).to_json()
    contract.update(extra)
    path.with_suffix(".json").write_text(json.dumps(contract))


@pytest.fixture()
def line_model(tmp_path):
    # channel 0 background (constant 4), channel 1 "Middle line" = 10 * red, channel 2 "Side line top" = 10 * blue.
    weights = np.zeros((3, 3))
    weights[1, 0] = 10.0  # R (input is RGB)
    weights[2, 2] = 10.0  # B
    path = tmp_path / "lines.onnx"
    _conv_model(path, weights, np.array([4.0, 0.0, 0.0]))
    _write_contract(path, "lines", ["background", "Middle line", "Side line top"])
    return path


def test_line_model_points_lie_on_the_drawn_line(line_model):
    W, H = 256, 192  # 4x the network size
    image = np.zeros((H, W, 3), np.uint8)
    cv2.line(image, (40, 20), (200, 170), (0, 0, 255), 9)  # red in BGR
    detector = OnnxDetector(line_model=line_model)
    det = detector.detect(image)
    assert set(det.lines_px) == {"Middle line"}
    points = det.lines_px["Middle line"]
    assert len(points) >= 10
    a, b = np.array([40.0, 20.0]), np.array([200.0, 170.0])
    d = b - a
    distance = np.abs((points[:, 0] - a[0]) * d[1] - (points[:, 1] - a[1]) * d[0]) / np.linalg.norm(d)
    assert np.median(distance) < 1.0 and distance.max() < 3.0
    # Spread along the whole line, not collapsed to a few points.
    along = (points - a) @ d / (d @ d)
    assert along.min() < 0.1 and along.max() > 0.9
    assert det.marking_mask.shape == (H, W) and det.marking_mask[95, 120] and not det.marking_mask[170, 40]
    obs = det.to_observations(3)
    assert obs.frame_index == 3 and obs.lines_px["Middle line"].shape == points.shape


def test_keypoint_model_peak_subpixel(tmp_path):
    weights = np.zeros((2, 3))
    weights[1, 1] = 8.0  # "Centre spot" heatmap = 8 * green
    path = tmp_path / "kp.onnx"
    _conv_model(path, weights, np.array([0.0, -4.0]))
    _write_contract(path, "keypoints", ["background", "Centre spot"], activation="sigmoid")
    image = np.zeros((NET_H * 2, NET_W * 2, 3), np.uint8)
    cv2.circle(image, (50, 30), 3, (0, 255, 0), -1)
    det = OnnxDetector(keypoint_model=path).detect(image)
    assert det.keypoints.names == ["Centre spot"]
    np.testing.assert_allclose(det.keypoints.uv_px[0], [50, 30], atol=1.0)
    np.testing.assert_allclose(det.keypoints.points_w[0], [0, 0, 0])
    assert 0.5 < det.keypoints.confidence[0] <= 1.0


def test_contract_errors_name_the_file(tmp_path, line_model):
    bad = tmp_path / "bad.onnx"
    bad.write_bytes(line_model.read_bytes())
    with pytest.raises(InputError, match="bad.json"):
        OnnxDetector(line_model=bad)  # no contract next to it
    _write_contract(bad, "lines", ["background", "No such line", "Side line top"])
    with pytest.raises(InputError, match="unknown line class"):
        OnnxDetector(line_model=bad)
    _write_contract(bad, "lines", ["background", "Middle line"])
    with pytest.raises(InputError, match="channels"):
        OnnxDetector(line_model=bad)
    _write_contract(bad, "lines", ["background", "Middle line", "Side line top"], extra_key=1)
    with pytest.raises(InputError, match="unknown key"):
        read_contract(bad.with_suffix(".json"))
    with pytest.raises(InputError, match="expected a 'keypoints' model"):
        OnnxDetector(keypoint_model=line_model)


def _field_model(path) -> None:
    """(1, 3, H, W) -> two 1x1 convolutions at stride 2: "keypoints" (1, 1, H/2, W/2) and "lines" (1, 3, H/2, W/2)."""
    kw = helper.make_tensor("kw", TensorProto.FLOAT, (1, 3, 1, 1), [0.0, 8.0, 0.0])  # nbjw:1 heatmap = 8 * green
    kb = helper.make_tensor("kb", TensorProto.FLOAT, (1,), [-4.0])
    lw = np.zeros((3, 3))
    lw[1, 0] = 10.0  # "Middle line" = 10 * red
    lw[2, 2] = 10.0  # "Side line top" = 10 * blue
    lwt = helper.make_tensor("lw", TensorProto.FLOAT, (3, 3, 1, 1), lw.ravel().tolist())
    lb = helper.make_tensor("lb", TensorProto.FLOAT, (3,), [4.0, 0.0, 0.0])
    nodes = [helper.make_node("Conv", ["image", "kw", "kb"], ["keypoints"], strides=[2, 2]),
             helper.make_node("Conv", ["image", "lw", "lb"], ["lines"], strides=[2, 2])]
    graph = helper.make_graph(
        nodes, "field", [helper.make_tensor_value_info("image", TensorProto.FLOAT, (1, 3, NET_H, NET_W))],
        [helper.make_tensor_value_info("keypoints", TensorProto.FLOAT, (1, 1, NET_H // 2, NET_W // 2)),
         helper.make_tensor_value_info("lines", TensorProto.FLOAT, (1, 3, NET_H // 2, NET_W // 2))],
        initializer=[kw, kb, lwt, lb])
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)])
    model.ir_version = 8
    onnx.save(model, str(path))
    contract = {"kind": "field",
                "input": {"width": NET_W, "height": NET_H, "colour_order": "RGB", "scale": 1 / 255,
                          "mean": [0.0, 0.0, 0.0], "std": [1.0, 1.0, 1.0]},
                "outputs": {"keypoints": {"activation": "sigmoid", "classes": ["nbjw:1"]},
                            "lines": {"activation": "softmax", "classes": ["background", "Middle line", "Side line top"]}},
                "threshold": 0.5}
    path.with_suffix(".json").write_text(json.dumps(contract))


def test_field_model_gives_lines_and_nbjw_keypoints_from_a_coarser_grid(tmp_path):
    from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W

    path = tmp_path / "field.onnx"
    _field_model(path)
    assert read_contract(path.with_suffix(".json")).outputs[1].classes[1] == "Middle line"
    W, H = 256, 192  # 4x the network input, 8x its output grid
    image = np.zeros((H, W, 3), np.uint8)
    cv2.line(image, (40, 20), (200, 170), (0, 0, 255), 13)  # red in BGR
    cv2.circle(image, (120, 40), 9, (0, 255, 0), -1)
    det = OnnxDetector(field_model=path).detect(image)
    assert set(det.lines_px) == {"Middle line"} and len(det.lines_px["Middle line"]) >= 5
    a, d = np.array([40.0, 20.0]), np.array([160.0, 150.0])
    points = det.lines_px["Middle line"]
    distance = np.abs((points[:, 0] - a[0]) * d[1] - (points[:, 1] - a[1]) * d[0]) / np.linalg.norm(d)
    assert np.median(distance) < 4.0  # one output cell is 8 frame pixels
    assert det.keypoints.names == [""]  # an nbjw keypoint is known by its world point
    np.testing.assert_allclose(det.keypoints.points_w[0], NBJW_KEYPOINTS_W[1])
    np.testing.assert_allclose(det.keypoints.uv_px[0], [120, 40], atol=4.0)
    obs = det.to_observations(0)
    assert obs.keypoints.points_w.shape == (1, 3)


def test_field_contract_errors_name_the_file(tmp_path):
    path = tmp_path / "field.onnx"
    _field_model(path)
    contract = json.loads(path.with_suffix(".json").read_text())
    contract["outputs"]["keypoints"]["classes"] = ["nbjw:99"]
    path.with_suffix(".json").write_text(json.dumps(contract))
    with pytest.raises(InputError, match="field.json.*unknown keypoint"):
        OnnxDetector(field_model=path)
    del contract["outputs"]["lines"]
    contract["outputs"]["keypoints"]["classes"] = ["nbjw:1"]
    path.with_suffix(".json").write_text(json.dumps(contract))
    with pytest.raises(InputError, match="outputs must be"):
        OnnxDetector(field_model=path)
    _field_model(path)
    contract = json.loads(path.with_suffix(".json").read_text())
    contract["outputs"]["lines"]["classes"] = ["background", "Middle line"]  # the model has 3 channels
    path.with_suffix(".json").write_text(json.dumps(contract))
    with pytest.raises(InputError, match="output lines has 3 channels"):
        OnnxDetector(field_model=path)
    with pytest.raises(InputError, match="expected a 'field' model"):
        _write_contract(tmp_path / "lines.onnx", "lines", ["background", "Middle line", "Side line top"])
        _conv_model(tmp_path / "lines.onnx", np.zeros((3, 3)), np.zeros(3))
        OnnxDetector(field_model=tmp_path / "lines.onnx")
