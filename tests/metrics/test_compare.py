"""Run comparison: jitter and spread by hand, metric wiring, report files, plots, the command."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from broadtrack_graph import cli
from broadtrack_graph.actions.compare import compare_runs
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import project_template_polylines
from broadtrack_graph.io.annotations import annotation_from_pixels, write_annotation_file
from broadtrack_graph.io.cameras import write_camera_file
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.metrics.compare import focal_point_spread, ground_truth_errors, jitter
from broadtrack_graph.products.plots import plot_focal_points, plot_track_series
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 960, 540
N = 21  # frames; 20 first differences, 19 second differences


def true_camera(t: int) -> Camera:
    return Camera.from_degrees(1100 + 5 * t, -0.02, 10 + 0.5 * t, 74.0, 0.0, (0.0, 55.0, -15.0), W, H)


def write_run(folder, jittery: bool, gap: bool = False):
    """Smooth run: the true cameras. Jittery run: pan +-0.1 deg alternating, f +-4 px alternating,
    C x +-0.2 m alternating."""
    with TrackWriter(folder, W, H) as writer:
        for t in range(N):
            frame_id = f"{t + 1:06d}"
            if gap and t == 10:
                writer.write(TrackRecord(t, frame_id, t / 25, None, status=FrameStatus.NO_PITCH, reason="test"))
                continue
            camera = true_camera(t)
            if jittery:
                sign = 1.0 if t % 2 == 0 else -1.0
                camera = camera.replace(
                    pan_rad=camera.pan_rad + math.radians(0.1 * sign), focal_px=camera.focal_px + 4 * sign,
                    position_m=camera.position_m + [0.2 * sign, 0.0, 0.0],
                )
            writer.write(TrackRecord(t, frame_id, t / 25, camera, confidence=0.8 if jittery else 0.9))


def test_jitter_by_hand():
    result = jitter(np.array([0.0, 1.0, 3.0, 6.0]), np.arange(4))
    assert result["rms_d1"] == pytest.approx(math.sqrt((1 + 4 + 9) / 3))
    assert result["rms_d2"] == pytest.approx(1.0)
    assert (result["pairs"], result["triples"]) == (3, 2)
    # A gap in the frame indices and a NaN break the runs.
    result = jitter(np.array([0.0, 1.0, 3.0, 10.0, 11.0, np.nan, 20.0]), np.array([0, 1, 2, 4, 5, 6, 7]))
    assert (result["pairs"], result["triples"]) == (3, 1)
    assert result["rms_d1"] == pytest.approx(math.sqrt((1 + 4 + 1) / 3))
    assert result["rms_d2"] == pytest.approx(1.0)
    # Pan across +-180 deg.
    assert jitter(np.array([179.0, -179.0, -177.0]), np.arange(3), wrap_deg=True)["rms_d1"] == pytest.approx(2.0)
    empty = jitter(np.array([1.0]), np.array([0]))
    assert empty["rms_d1"] is None and empty["rms_d2"] is None


def test_focal_point_spread_by_hand():
    positions = np.array([[0.0, 50.0, -15.0], [2.0, 50.0, -15.0], [1.0, 53.0, -15.0], [np.nan, 0.0, 0.0]])
    spread = focal_point_spread(positions)
    assert spread["frames"] == 3
    assert spread["mean_m"] == pytest.approx([1.0, 51.0, -15.0])
    assert spread["std_m"] == pytest.approx([math.sqrt(2 / 3), math.sqrt(6 / 3), 0.0])
    assert spread["extent_m"] == pytest.approx([2.0, 3.0, 0.0])
    assert spread["rms_to_mean_m"] == pytest.approx(math.sqrt((2 + 2 + 4) / 3))
    assert focal_point_spread(np.full((2, 3), np.nan))["frames"] == 0


def test_compare_smooth_and_jittery_runs(tmp_path):
    write_run(tmp_path / "filter", jittery=True)
    write_run(tmp_path / "smoother", jittery=False)
    report = compare_runs([tmp_path / "filter", tmp_path / "smoother"], out_dir=tmp_path / "cmp")
    smooth, jittery = report["runs"]["smoother"], report["runs"]["filter"]
    # Smooth: pan moves 0.5 deg per frame exactly, f 5 px per frame.
    assert smooth["jitter"]["pan_deg"]["rms_d1"] == pytest.approx(0.5, abs=1e-9)
    assert smooth["jitter"]["pan_deg"]["rms_d2"] == pytest.approx(0.0, abs=1e-9)
    assert smooth["jitter"]["focal_px"]["rms_d1"] == pytest.approx(5.0, abs=1e-9)
    assert smooth["jitter"]["tilt_deg"]["rms_d1"] == pytest.approx(0.0, abs=1e-9)
    # Jittery: first differences alternate 0.5 -+ 0.2 (10 of each), second differences are +-0.4.
    assert jittery["jitter"]["pan_deg"]["rms_d1"] == pytest.approx(math.sqrt((0.3**2 + 0.7**2) / 2), abs=1e-9)
    assert jittery["jitter"]["pan_deg"]["rms_d2"] == pytest.approx(0.4, abs=1e-9)
    assert jittery["jitter"]["focal_px"]["rms_d1"] == pytest.approx(math.sqrt((3**2 + 13**2) / 2), abs=1e-9)
    assert jittery["jitter"]["focal_px"]["rms_d2"] == pytest.approx(16.0, abs=1e-9)
    assert jittery["jitter"]["pan_deg"]["triples"] == N - 2
    # Focal point: x alternates +-0.2 (11 of +, 10 of -).
    mean_x = (11 * 0.2 - 10 * 0.2) / 21
    std_x = math.sqrt((11 * (0.2 - mean_x) ** 2 + 10 * (0.2 + mean_x) ** 2) / 21)
    assert jittery["focal_point"]["std_m"] == pytest.approx([std_x, 0.0, 0.0], abs=1e-9)
    assert jittery["focal_point"]["extent_m"] == pytest.approx([0.4, 0.0, 0.0], abs=1e-9)
    assert smooth["focal_point"]["extent_m"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert jittery["mean_confidence"] == pytest.approx(0.8)
    # Files and table.
    for key in ("json", "markdown", "series_png", "focal_points_png"):
        assert (tmp_path / "cmp").joinpath(report["files"][key].split("/")[-1]).stat().st_size > 0
    saved = json.loads((tmp_path / "cmp" / "compare.json").read_text())
    assert saved["runs"]["filter"]["jitter"]["pan_deg"]["rms_d2"] == pytest.approx(0.4, abs=1e-9)
    table = (tmp_path / "cmp" / "compare.md").read_text()
    assert "| pan jitter RMS d2 (deg/frame^2)" in table and "0.4000" in table and "0.0000" in table


def test_gap_frames_are_left_out_of_jitter(tmp_path):
    write_run(tmp_path / "run", jittery=False, gap=True)
    stats = compare_runs([tmp_path / "run"])["runs"]["run"]
    assert stats["frames_with_camera"] == N - 1
    assert stats["jitter"]["pan_deg"]["pairs"] == N - 1 - 2  # the two pairs touching frame 10 are gone
    assert stats["jitter"]["pan_deg"]["triples"] == N - 2 - 3
    assert stats["jitter"]["pan_deg"]["rms_d2"] == pytest.approx(0.0, abs=1e-9)


def annotate(camera: Camera) -> dict:
    """Annotations that a perfect camera scores 100 % on: every projected class, points on it."""
    polylines = project_template_polylines(camera, W, H)
    return annotation_from_pixels({name: pts[:: max(1, len(pts) // 6)] for name, pts in polylines.items()}, W, H)


def test_metrics_with_annotations_and_ground_truth(tmp_path):
    write_run(tmp_path / "filter", jittery=True)
    write_run(tmp_path / "smoother", jittery=False)
    annotations = tmp_path / "annotations"
    truth = tmp_path / "truth"
    for t in range(0, N, 5):
        write_annotation_file(annotations / f"{t + 1:06d}.json", annotate(true_camera(t)))
    for t in range(N):
        write_camera_file(truth / f"camera_{t + 1:06d}.json", true_camera(t))
    report = compare_runs([tmp_path / "filter", tmp_path / "smoother"], annotations_path=annotations,
                          ground_truth_dir=truth, out_dir=tmp_path / "cmp")
    smooth, jittery = report["runs"]["smoother"]["metrics"], report["runs"]["filter"]["metrics"]
    assert smooth["frames_annotated"] == 5 and smooth["frames_matched"] == 5
    assert smooth["jac"]["5"] == pytest.approx(1.0) and smooth["completeness"] == pytest.approx(1.0)
    assert smooth["mre_px"] < 0.05
    assert jittery["mre_px"] > 0.5 and jittery["jac"]["5"] < smooth["jac"]["5"] + 1e-12
    gt_smooth = report["runs"]["smoother"]["ground_truth_error"]
    gt_jittery = report["runs"]["filter"]["ground_truth_error"]
    assert gt_smooth["frames"] == N and gt_smooth["pan_rms_deg"] == pytest.approx(0.0, abs=1e-9)
    assert gt_jittery["pan_rms_deg"] == pytest.approx(0.1, abs=1e-9)
    assert gt_jittery["position_rms_m"] == pytest.approx(0.2, abs=1e-9)
    assert "JaC@5 (%)" in report["table_markdown"] and "GT pan error RMS (deg)" in report["table_markdown"]


def test_ground_truth_errors_without_overlap(tmp_path):
    write_run(tmp_path / "run", jittery=False)
    write_camera_file(tmp_path / "gt" / "camera_999999.json", true_camera(0))
    errors = ground_truth_errors(read_track(tmp_path / "run"), read_track(tmp_path / "gt"))
    assert errors["frames"] == 0 and errors["pan_rms_deg"] is None


def test_plots_write_pngs(tmp_path):
    write_run(tmp_path / "a", jittery=True, gap=True)
    tracks = {"a": read_track(tmp_path / "a")}
    series = plot_track_series(tracks, tmp_path / "s.png", ground_truth=read_track(tmp_path / "a"))
    points = plot_focal_points(tracks, tmp_path / "p.png", tripod_T_w=[0, 55.2, -15.1])
    import matplotlib.image

    for path in (series, points):
        image = matplotlib.image.imread(path)
        assert image.shape[0] > 300 and image.shape[1] > 600
    with pytest.raises(ValueError, match="unknown series"):
        plot_track_series(tracks, tmp_path / "x.png", series=("zoom",))


def test_compare_command(tmp_path, capsys):
    write_run(tmp_path / "filter", jittery=True)
    write_run(tmp_path / "smoother", jittery=False)
    code = cli.main(["compare", str(tmp_path / "filter"), str(tmp_path / "smoother"), "--names", "online", "smoothed",
                     "--out", str(tmp_path / "cmp"), "--tripod-position", "0", "55", "-15"])
    out = capsys.readouterr().out
    assert code == 0
    assert "| metric" in out and "online" in out and "smoothed" in out and "compare.json" in out
    assert json.loads((tmp_path / "cmp" / "compare.json").read_text())["tripod_T_w"] == [0.0, 55.0, -15.0]
    code = cli.main(["compare", str(tmp_path / "filter"), "--names", "a", "b"])
    assert code == 2 and "2 names for 1 runs" in capsys.readouterr().err
    code = cli.main(["compare", str(tmp_path / "nope")])
    assert code == 2 and "run folder not found" in capsys.readouterr().err


def test_player_statistics_of_a_players_file():
    import numpy as np

    from broadtrack_graph.io.players_file import positions_from_lines
    from broadtrack_graph.metrics.compare import player_statistics

    lines = [{"frame": k, "frame_id": f"{k + 1:06d}", "track_id": 1, "box_px": [0, 0, 1, 1], "x_m": 0.2 * k,
              "y_m": 0.0} for k in range(50)]
    lines.append({"frame": 3, "frame_id": "000004", "track_id": 2, "box_px": [0, 0, 1, 1], "x_m": None, "y_m": None})
    stats = player_statistics(positions_from_lines(lines), fps=25.0)
    assert stats["boxes"] == 51 and stats["located"] == 50 and stats["tracks"] == 1
    assert np.isclose(stats["total_distance_m"], 0.2 * 49, atol=1e-3)
    assert np.isclose(stats["max_top_speed_m_s"], 5.0, atol=1e-3)
