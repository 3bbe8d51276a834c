import json

import numpy as np

from broadtrack_graph.actions.players import PlayersOptions, players_from_run
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.players_file import PREDICTIONS_FILE, read_players_file
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord


def _tiny_run(tmp_path, frames=12):
    """A run of a slowly panning camera and the MOT boxes of 3 players walking at 1 m per frame along x."""
    run = tmp_path / "run"
    truth = {}
    lines = []
    with TrackWriter(run, 1920, 1080) as writer:
        for k in range(frames):
            camera = Camera.from_degrees(2400.0, -0.05, 0.1 * k, 74.0, 0.0, [0.0, 55.0, -15.0], 1920, 1080)
            if k == 5:
                writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, None, status=FrameStatus.NO_PITCH, reason="no grass"))
            else:
                std = {"pan_std_deg": 0.01, "tilt_std_deg": 0.01, "roll_std_deg": 0.01, "focal_std_px": 5.0,
                       "k1_std": 0.001, "position_std_m": np.array([0.05, 0.05, 0.05])}
                writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, camera, std))
            for tid, start in ((1, -10.0), (2, 0.0), (3, 8.0)):
                foot = np.array([[start + 0.2 * k, 5.0 + tid, 0.0]])
                uv, _ = camera.project(foot)
                u, v = uv[0]
                lines.append(f"{k + 1},{tid},{u - 10:.4f},{v - 50:.4f},20,50,1")
                truth[(k, tid)] = foot[0, :2]
    lines.append("40,1,100,100,20,50,1")  # a frame the run does not know
    lines.append("2,9,960,-5000,20,50,1")  # foot far above the horizon
    (tmp_path / "boxes.txt").write_text("\n".join(lines) + "\n")
    return run, truth


def test_players_action_on_a_tiny_run(tmp_path):
    run, truth = _tiny_run(tmp_path)
    result = players_from_run(run, tmp_path / "boxes.txt", tmp_path / "out", PlayersOptions(video=True), progress=False)
    assert result.boxes == 12 * 3 + 2 and result.no_camera == 3 and result.located == 11 * 3
    assert len(result.issues) == 2
    positions = read_players_file(tmp_path / "out")
    for i in np.flatnonzero(positions.has_position):
        np.testing.assert_allclose(positions.xy_m[i], truth[(positions.frame[i], positions.track_id[i])], atol=1e-3)
    assert np.all(positions.std_m[positions.has_position] > 0.01)
    no_camera = [i for i, s in enumerate(positions.status) if s == FrameStatus.NO_PITCH]
    assert len(no_camera) == 3 and positions.reasons[no_camera[0]] == "no grass"
    summary = json.loads((tmp_path / "out" / "players_summary.json").read_text())
    # 0.2 m per frame at 25 fps = 5 m/s; 11 frames with a camera, one gap of two frames bridged
    assert abs(summary["tracks"]["1"]["top_speed_m_s"] - 5.0) < 0.1
    assert abs(summary["tracks"]["1"]["distance_m"] - 0.2 * 11) < 0.05
    assert (tmp_path / "out" / "birdseye_players.mp4").stat().st_size > 0


def test_gamestate_predictions_keys(tmp_path):
    run, _ = _tiny_run(tmp_path, frames=3)
    players_from_run(run, tmp_path / "boxes.txt", tmp_path / "out", progress=False)
    data = json.loads((tmp_path / "out" / PREDICTIONS_FILE).read_text())
    prediction = data["predictions"][0]
    assert {"id", "image_id", "track_id", "supercategory", "category_id", "attributes", "bbox_image",
            "bbox_pitch"} <= set(prediction)
    assert set(prediction["bbox_pitch"]) == {"x_bottom_left", "y_bottom_left", "x_bottom_middle", "y_bottom_middle",
                                             "x_bottom_right", "y_bottom_right"}
    assert set(prediction["bbox_image"]) == {"x", "y", "x_center", "y_center", "w", "h"}
    assert prediction["image_id"] == "1" and prediction["supercategory"] == "object"
    bp = prediction["bbox_pitch"]
    assert bp["x_bottom_left"] < bp["x_bottom_middle"] < bp["x_bottom_right"]
