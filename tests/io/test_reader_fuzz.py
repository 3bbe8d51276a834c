"""Fuzz the file readers: truncations, wrong types and wrong values never escape as anything but InputError.

Readers covered: detections files (:func:`read_detections`, which skips bad records with a warning
and raises InputError only when nothing is usable), camera files (:func:`read_camera_file`) and
annotation files, per image and game-state (:func:`read_annotations`). Seeded; a few thousand cases.
"""

from __future__ import annotations

import json
import logging
import random

import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.cameras import read_camera_file
from broadtrack_graph.io.detections import read_detections

DETECTION = {"frame": 3, "frame_id": "000004", "image_size": [1920, 1080], "units": "px",
             "lines": {"Side line top": [[102.5, 311.0], [388.0, 290.5]], "Middle line": [{"x": 960.2, "y": 300.1}]},
             "keypoints": [{"name": "Centre spot", "xy": [955.0, 610.0], "confidence": 0.92},
                           {"world": [11.0, -20.16, 0.0], "xy": [1210.0, 402.0], "confidence": 0.71}],
             "mask": "masks/000004.png", "players": [[812, 500, 840, 580]]}
CAMERA = {"pan_degrees": 10.0, "tilt_degrees": 75.0, "roll_degrees": 0.5, "position_meters": [0.0, 55.0, -12.0],
          "x_focal_length": 1500.0, "y_focal_length": 1500.0, "principal_point": [960.0, 540.0],
          "radial_distortion": [0.01, 0.0, 0.0, 0.0, 0.0, 0.0], "tangential_distortion": [0.0, 0.0],
          "thin_prism_distortion": [0.0, 0.0, 0.0, 0.0]}
ANNOTATION = {"Side line top": [{"x": 0.1, "y": 0.2}, {"x": 0.5, "y": 0.21}], "Circle central": [{"x": 0.4, "y": 0.6}]}
GAMESTATE = {"info": {"frame_rate": 25}, "images": [{"file_name": "000001.jpg", "image_id": "1"}],
             "annotations": [{"image_id": "1", "supercategory": "pitch", "lines": ANNOTATION}]}

WEIRD = [None, True, -1, 0, 1e308, -1e308, float("nan"), float("inf"), "", "x", "Centre spot", [], [1], [1, 2, 3],
         [[1, 2]], {}, {"x": 1}, {"a": [1, 2]}, [None, None], [[None, "a"]], 10 ** 30, "\u0000", [[1e400, 2]]]


def _mutate(value, rng: random.Random, depth: int = 0):
    """Replace, drop or recurse into one part of a JSON value."""
    if isinstance(value, dict) and value and depth < 4:
        key = rng.choice(list(value))
        out = dict(value)
        action = rng.random()
        if action < 0.2:
            del out[key]
        elif action < 0.5:
            out[key] = rng.choice(WEIRD)
        elif action < 0.55:
            out[rng.choice(["Unknown class", "frame", "xy"])] = rng.choice(WEIRD)
        else:
            out[key] = _mutate(value[key], rng, depth + 1)
        return out
    if isinstance(value, list) and value and depth < 4:
        out = list(value)
        i = rng.randrange(len(out))
        action = rng.random()
        if action < 0.3:
            del out[i]
        elif action < 0.6:
            out[i] = rng.choice(WEIRD)
        else:
            out[i] = _mutate(value[i], rng, depth + 1)
        return out
    return rng.choice(WEIRD)


def _text(value, rng: random.Random) -> str:
    text = json.dumps(value, allow_nan=True)
    if rng.random() < 0.2:
        text = text[: rng.randrange(len(text) + 1)]  # truncated file
    return text


def _cases(seed: int, template, count: int):
    rng = random.Random(seed)
    for _ in range(count):
        value = template
        for _ in range(rng.randint(1, 3)):
            value = _mutate(value, rng)
        yield rng, value


@pytest.fixture(autouse=True)
def quiet(caplog):
    caplog.set_level(logging.CRITICAL)  # the readers warn about every skipped item; not needed here


def test_detections_reader_raises_only_input_error(tmp_path):
    path = tmp_path / "det.jsonl"
    read = 0
    for rng, value in _cases(1, DETECTION, 1500):
        lines = [_text(value, rng)] + ([json.dumps(DETECTION)] if rng.random() < 0.3 else [])
        path.write_text("\n".join(lines) + ("\n" if rng.random() < 0.5 else ""), encoding="utf-8")
        try:
            result = read_detections(path)
        except InputError as exc:
            assert "\n" not in str(exc)
            continue
        read += 1
        assert result.frames and all(index >= 0 for index in result.frames)
    assert read > 300  # most mutations leave a usable record (a skipped item is only a warning)


def test_camera_reader_raises_only_input_error(tmp_path):
    path = tmp_path / "camera_00001.json"
    for rng, value in _cases(2, CAMERA, 1500):
        path.write_text(_text(value, rng), encoding="utf-8")
        try:
            camera = read_camera_file(path, 960 if rng.random() < 0.5 else None, 540)
        except InputError as exc:
            assert "\n" not in str(exc)
            continue
        assert camera.focal_px > 0


@pytest.mark.parametrize("template, name, seed", [(ANNOTATION, "00001.json", 3),
                                                  (GAMESTATE, "Labels-GameState.json", 4)])
def test_annotation_readers_raise_only_input_error(tmp_path, template, name, seed):
    path = tmp_path / name
    for rng, value in _cases(seed, template, 800):
        path.write_text(_text(value, rng), encoding="utf-8")
        try:
            read_annotations(path if name.startswith("Labels") else tmp_path)
        except InputError as exc:
            assert "\n" not in str(exc)
