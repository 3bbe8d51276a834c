"""``track`` arguments -> the track action: config from defaults, a TOML file and flags; bad values exit 2."""

from __future__ import annotations

from pathlib import Path

import pytest

import broadtrack_graph.commands.track as track_command
from broadtrack_graph.actions.track import DetectorOptions
from broadtrack_graph.cli import main
from broadtrack_graph.detect.flow import FlowConfig
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.tripod_file import write_tripod
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.result import RunResult


@pytest.fixture
def calls(monkeypatch):
    seen = []

    def fake_track_input(frames, out_dir, config, detector, **kwargs):
        seen.append({"frames": frames, "out": out_dir, "config": config, "detector": detector, **kwargs})
        return RunResult(Path(out_dir), {"frames_written": 3, "fps": 2.0, "status_counts": {"tracked": 3}}, [], None)

    monkeypatch.setattr(track_command, "track_input", fake_track_input)
    return seen


def test_defaults_are_the_config_defaults(calls, capsys):
    assert main(["track", "clip.mp4", "--out", "run", "--no-progress"]) == 0
    call = calls[0]
    assert call["config"] == TrackingConfig() and call["detector"] == DetectorOptions()
    assert (call["frames"], call["out"], call["tripod"], call["reinit_position"]) == (Path("clip.mp4"), Path("run"), None, None)
    assert (call["detections_path"], call["start"], call["end"], call["progress"]) == (None, None, None, False)
    assert "tracked 3 frames into run (2.0 fps)" in capsys.readouterr().out


def test_flags_give_the_config(calls, tmp_path):
    write_tripod(tmp_path / "tripod.json", Tripod((1.0, 55.0, -12.0), 0.25))
    assert main(["track", "--detections", "d.jsonl", "--frames", "clip", "--out", "run", "--mode", "fixed-lag",
                 "--lag", "12", "--no-flow", "--no-k1", "--no-court", "--no-search", "--confidence-threshold", "0.4",
                 "--write-960x540",
                 "--tripod", str(tmp_path / "tripod.json"), "--start", "5", "--end", "9"]) == 0
    call = calls[0]
    assert call["config"] == TrackingConfig(mode="fixed-lag", lag_frames=12, use_flow=False, estimate_k1=False,
                                            court_reinit=False, global_search=False, confidence_threshold=0.4,
                                            write_960x540=True)
    assert call["frames"] == Path("clip") and call["detections_path"] == Path("d.jsonl")
    assert tuple(call["tripod"].T_w) == (1.0, 55.0, -12.0) and call["tripod"].delta_m == 0.25
    assert (call["start"], call["end"]) == (5, 9)
    assert main(["track", "clip", "--out", "run", "--reinit-position", "0", "50", "-10"]) == 0
    assert calls[1]["tripod"] is None and calls[1]["reinit_position"] == (0.0, 50.0, -10.0)


def test_config_file_and_flags_given_override_it(calls, tmp_path):
    config = tmp_path / "tracking.toml"
    config.write_text('mode = "batch"\nlag_frames = 40\nuse_tripod = false\nbatch_tripod = "joint"\n'
                      "[flow]\ngrid_step_px = 20\n", encoding="utf-8")
    assert main(["track", "clip", "--out", "run", "--config", str(config)]) == 0
    assert calls[0]["config"] == TrackingConfig(mode="batch", lag_frames=40, use_tripod=False, batch_tripod="joint",
                                                flow=FlowConfig(grid_step_px=20))
    assert main(["track", "clip", "--out", "run", "--config", str(config), "--lag", "7", "--mode", "online"]) == 0
    assert calls[1]["config"] == TrackingConfig(mode="online", lag_frames=7, use_tripod=False, batch_tripod="joint",
                                                flow=FlowConfig(grid_step_px=20))


@pytest.mark.parametrize("argv, message", [
    (["--lag", "0"], "argument --lag: 0 is too small; give an integer >= 1"),
    (["--threads", "0"], "argument --threads: 0 is too small; give an integer >= 1"),
    (["--config", "missing.toml"], "missing.toml: config file not found"),
    (["--detector", "onnx", "--field-model", "f.onnx", "--keypoint-model", "k.onnx"],
     "f.onnx: a field model holds both outputs"),
])
def test_bad_value_exits_2_with_one_line(calls, capsys, argv, message):
    assert main(["track", "clip", "--out", "run", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("broadtrack-graph track: error: ") and message in err
    assert not calls


def test_unknown_key_in_config_file_exits_2(calls, capsys, tmp_path):
    (tmp_path / "bad.toml").write_text("lag = 3\n", encoding="utf-8")
    assert main(["track", "clip", "--out", "run", "--config", str(tmp_path / "bad.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.toml: unknown key 'lag'" in err and not calls
    assert main(["track", "--out", "run"]) == 2 and "give an INPUT" in capsys.readouterr().err


def test_players_option_reaches_the_action(calls, capsys):
    assert main(["track", "clip.mp4", "--out", "run", "--players", "detector", "--pixel-sigma", "3", "--no-progress"]) == 0
    call = calls[0]
    assert call["players"] == "detector" and call["players_options"].pixel_sigma_px == 3.0
    assert main(["track", "clip.mp4", "--out", "run", "--no-progress"]) == 0
    assert calls[1]["players"] is None and calls[1]["players_options"] is None


def test_a_field_model_reaches_the_action(calls):
    assert main(["track", "clip.mp4", "--out", "run", "--detector", "onnx", "--field-model", "field.onnx"]) == 0
    options = calls[0]["detector"]
    assert options.kind == "onnx" and str(options.field_model) == "field.onnx" and options.keypoint_model is None


def test_the_faint_look_is_the_weight_free_detector_s_and_on_by_default(calls, capsys):
    from broadtrack_graph.actions.track import make_detector

    assert make_detector(DetectorOptions()).config.faint_lines is not None  # on by default
    assert main(["track", "clip.mp4", "--out", "run", "--no-faint-look"]) == 0
    options = calls[0]["detector"]
    assert options.kind == "weightfree" and not options.faint_look
    assert make_detector(options).config.faint_lines is None
    assert main(["track", "clip.mp4", "--out", "run", "--detector", "onnx", "--no-faint-look"]) == 2
    assert "--no-faint-look is the weight-free detector's" in capsys.readouterr().err


def test_onnx_without_a_model_runs_the_shipped_one_and_the_reinit_model_is_an_option(calls):
    from broadtrack_graph.detect.field_model import SHIPPED_FIELD_MODEL

    assert main(["track", "clip.mp4", "--out", "run", "--detector", "onnx"]) == 0
    assert calls[0]["detector"].field_model == SHIPPED_FIELD_MODEL
    assert calls[0]["config"].reinit_model == "none"  # the field model is not a re-initialisation route by default
    assert main(["track", "clip.mp4", "--out", "run", "--reinit-model", "shipped"]) == 0
    assert calls[1]["config"].reinit_model == "shipped"


def test_opencv_threads_default_to_the_cores_the_two_threads_leave(calls, monkeypatch):
    import cv2

    from broadtrack_graph.commands.tracking_options import default_opencv_threads

    for cores, expected in ((None, 1), (1, 1), (2, 1), (3, 1), (8, 6)):
        monkeypatch.setattr("os.cpu_count", lambda cores=cores: cores)
        assert default_opencv_threads() == expected
    monkeypatch.setattr("os.cpu_count", lambda: 5)
    assert main(["track", "clip.mp4", "--out", "run", "--no-progress"]) == 0
    assert cv2.getNumThreads() == 3
    assert main(["track", "clip.mp4", "--out", "run", "--no-progress", "--threads", "2"]) == 0
    assert cv2.getNumThreads() == 2
    assert calls[0]["config"] == calls[1]["config"] == TrackingConfig()  # not a tracking setting: the cameras are the same
