"""The tripod file with one tripod per camera (broadtrack_graph.io.tripod_file) and ``--tripod`` reading it."""

from __future__ import annotations

import json
from argparse import Namespace

import pytest

from broadtrack_graph.commands.tracking_options import tripods_from_args
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.tripod_file import read_camera_tripods, read_tripod, write_tripod

MAIN = Tripod((0.0, 55.0, -12.0), 0.2)
CORNER = Tripod((52.7, 69.2, -22.6), 0.25)


def test_per_camera_tripods_round_trip(tmp_path):
    path = tmp_path / "tripod.json"
    write_tripod(path, MAIN, {"inlier_ratio": 0.9}, {"main": MAIN, "high-corner-1": CORNER})
    assert list(read_tripod(path).T_w) == [0.0, 55.0, -12.0]  # the top level: the main camera's
    cameras = read_camera_tripods(path)
    assert sorted(cameras) == ["high-corner-1", "main"]
    assert list(cameras["high-corner-1"].T_w) == [52.7, 69.2, -22.6] and cameras["high-corner-1"].delta_m == 0.25
    write_tripod(path, MAIN)
    assert read_camera_tripods(path) == {}  # a one-camera file


def test_a_bad_camera_entry_is_a_one_line_error(tmp_path):
    path = tmp_path / "tripod.json"
    path.write_text(json.dumps({"T_w": [0, 55, -12], "delta_m": 0.2, "cameras": {"main": {"T_w": [0, 55]}}}))
    with pytest.raises(InputError, match="tripod.json: cameras.main: expected"):
        read_camera_tripods(path)


def test_tripod_option_takes_every_camera_of_a_run_s_file_or_one_by_id(tmp_path):
    run = tmp_path / "tripod.json"
    write_tripod(run, MAIN, None, {"main": MAIN, "high-corner-1": CORNER})
    single = tmp_path / "single.json"
    write_tripod(single, CORNER)
    assert sorted(tripods_from_args(Namespace(tripod=[str(run)]))) == ["high-corner-1", "main"]
    only = tripods_from_args(Namespace(tripod=[f"high-corner-1={run}"]))
    assert list(only) == ["high-corner-1"] and list(only["high-corner-1"].T_w) == [52.7, 69.2, -22.6]
    named = tripods_from_args(Namespace(tripod=[f"high-behind-1={single}"]))
    assert list(named["high-behind-1"].T_w) == [52.7, 69.2, -22.6]  # a file without cameras: its top level
    with pytest.raises(InputError, match="a second tripod for camera 'main'"):
        tripods_from_args(Namespace(tripod=[str(run), f"main={single}"]))


def test_a_provisional_tripod_s_uncertainty_round_trips_and_a_bad_one_is_a_one_line_error(tmp_path):
    path = tmp_path / "tripod.json"
    loose = Tripod((-1.1, 63.6, -18.4), 0.2, 0.19)
    write_tripod(path, loose, None, {"main": loose, "high-corner-1": CORNER})
    assert read_tripod(path) == loose and read_camera_tripods(path) == {"main": loose, "high-corner-1": CORNER}
    assert "sigma_m" not in json.loads(path.read_text())["cameras"]["high-corner-1"]  # a firm tripod: as before
    path.write_text(json.dumps({"T_w": [0, 55, -12], "delta_m": 0.2, "sigma_m": -1}))
    with pytest.raises(InputError, match="tripod.json: sigma_m must be"):
        read_tripod(path)
