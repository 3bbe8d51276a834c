"""The shipped field model: it loads by default, honours its contract, and finds the keypoints of a rendered frame."""

from __future__ import annotations

import json

import numpy as np
import pytest

from broadtrack_graph.detect.field_model import SHIPPED_FIELD_MODEL, FieldModel, shipped_field_model
from broadtrack_graph.detect.onnx_contract import contract_path, read_contract
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import LINE_CLASSES
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W
from broadtrack_graph.reinit.field_model import ModelAcceptance, ModelReinit, model_reinit_for
from broadtrack_graph.synth.field_samples import HELD_OUT_SEED, sample_field

NBJW_W = np.array([NBJW_KEYPOINTS_W[k] for k in range(1, 58)], float)


@pytest.fixture(scope="module")
def model():
    return FieldModel()


def test_the_package_ships_a_small_field_model_with_its_contract():
    assert shipped_field_model() == SHIPPED_FIELD_MODEL
    assert SHIPPED_FIELD_MODEL.stat().st_size <= 10 * 1024 * 1024
    contract = read_contract(contract_path(SHIPPED_FIELD_MODEL))
    assert contract.kind == "field" and (contract.width_px, contract.height_px) == (512, 288)
    heads = {head.name: head for head in contract.outputs}
    assert heads["keypoints"].classes == tuple(f"nbjw:{k}" for k in range(1, 58))
    assert heads["lines"].classes == ("background", *LINE_CLASSES)


def _sample(kind: str, min_visible: int = 0):
    """The first held-out sample of a kind (with at least min_visible visible keypoints)."""
    for index in range(200):
        sample = sample_field(HELD_OUT_SEED, index, 960, 540)
        if sample.kind == kind and sample.keypoint_visible.sum() >= min_visible:
            return sample
    raise AssertionError(f"no held-out {kind} sample")


def _errors(sample, keypoints) -> np.ndarray:
    """Pixels from each of the model's keypoints to the true camera's image of the same pitch point."""
    index = [int(np.argmin(np.linalg.norm(NBJW_W - p, axis=1))) for p in keypoints.points_w]
    truth, front = sample.camera.project(NBJW_W[index])
    return np.where(front, np.linalg.norm(keypoints.uv_px - truth, axis=1), np.inf)


@pytest.mark.parametrize("kind", ["wide", "tactical"])
def test_the_shipped_model_finds_the_keypoints_of_a_rendered_frame(model, kind):
    # Figures of the shipped model (docs/MODEL.md): many of its keypoints are a few pixels off at 960x540
    # (one output cell is 7.5 px), some 10-15 px; a broken or untrained model finds none or scatters them.
    sample = _sample(kind, min_visible=10)
    errors = _errors(sample, model.keypoints(sample.image_bgr))
    assert len(errors) >= 10
    assert np.mean(errors < 5.0) >= 0.4 and np.mean(errors < 15.0) >= 0.75


def test_the_shipped_model_alone_gives_the_camera_of_a_wide_view(model):
    sample = _sample("wide", min_visible=10)
    result = ModelReinit(model)(sample.image_bgr)
    assert ModelAcceptance().accepts(result)
    seen = sample.keypoint_visible
    estimate, _ = result.camera.project(NBJW_W[seen])
    truth, _ = sample.camera.project(NBJW_W[seen])
    assert np.median(np.linalg.norm(estimate - truth, axis=1)) < 10.0


def test_a_close_up_gives_no_camera(model):
    sample = _sample("close-up")
    assert not ModelAcceptance().accepts(ModelReinit(model)(sample.image_bgr))


def test_the_run_options_choose_the_model():
    assert model_reinit_for("none") is None and model_reinit_for(None) is None
    assert model_reinit_for("shipped").model.path == SHIPPED_FIELD_MODEL
    with pytest.raises(InputError, match="missing.onnx"):
        model_reinit_for("missing.onnx")


def test_a_model_giving_nan_is_an_error_naming_it(tmp_path):
    onnx = pytest.importorskip("onnx")
    from onnx import TensorProto, helper

    net_w, net_h = 64, 48
    nodes = [helper.make_node("Conv", ["image", "kw", "kb"], ["keypoints"], strides=[4, 4]),
             helper.make_node("Conv", ["image", "lw", "lb"], ["lines"], strides=[4, 4])]
    initialisers = [helper.make_tensor("kw", TensorProto.FLOAT, (1, 3, 1, 1), [0.0, 1.0, 0.0]),
                    helper.make_tensor("kb", TensorProto.FLOAT, (1,), [float("nan")]),
                    helper.make_tensor("lw", TensorProto.FLOAT, (2, 3, 1, 1), [0.0] * 6),
                    helper.make_tensor("lb", TensorProto.FLOAT, (2,), [1.0, 0.0])]
    graph = helper.make_graph(
        nodes, "field", [helper.make_tensor_value_info("image", TensorProto.FLOAT, (1, 3, net_h, net_w))],
        [helper.make_tensor_value_info("keypoints", TensorProto.FLOAT, (1, 1, net_h // 4, net_w // 4)),
         helper.make_tensor_value_info("lines", TensorProto.FLOAT, (1, 2, net_h // 4, net_w // 4))],
        initializer=initialisers)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)])
    model.ir_version = 8
    path = tmp_path / "broken.onnx"
    onnx.save(model, str(path))
    path.with_suffix(".json").write_text(json.dumps({
        "kind": "field", "input": {"width": net_w, "height": net_h, "colour_order": "RGB", "scale": 1 / 255,
                                   "mean": [0.0, 0.0, 0.0], "std": [1.0, 1.0, 1.0]},
        "outputs": {"keypoints": {"activation": "sigmoid", "classes": ["nbjw:1"]},
                    "lines": {"activation": "softmax", "classes": ["background", "Middle line"]}},
        "threshold": 0.5}))
    with pytest.raises(InputError, match="broken.onnx.*NaN"):
        FieldModel(path).keypoints(np.zeros((96, 128, 3), np.uint8))
