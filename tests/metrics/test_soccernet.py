import json
import math
import subprocess
import sys

import numpy as np
import pytest
from metric_reference import frame_jac

from broadtrack_graph.actions.evaluate import evaluate_folders, load_cameras
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import MIRRORED_CLASS, PitchTemplate
from broadtrack_graph.geometry.template import distances_to_polyline, project_template_polylines
from broadtrack_graph.io.annotations import AnnotationSet, read_annotations
from broadtrack_graph.io.cameras import write_camera_file
from broadtrack_graph.metrics.soccernet import evaluate_cameras, evaluate_frame

W, H = 960, 540


def camera_main(**changes):
    camera = Camera.from_degrees(1100.0, 0.0, -20.0, 72.0, 0.0, (0.0, 55.0, -14.0), W, H)
    return camera.replace(**changes) if changes else camera


def perfect_annotation(camera, step=5):
    """Annotate every projected class with points on its projection (normalised)."""
    lines = {}
    for name, poly in project_template_polylines(camera, W, H).items():
        points = poly[:: max(1, len(poly) // step)]
        lines[name] = points / np.array([W - 1, H - 1])
    return lines


def test_perfect_camera_scores_one_and_mirror_is_used():
    camera = camera_main()
    lines = perfect_annotation(camera)
    assert len(lines) >= 4
    score = evaluate_frame(lines, camera, W, H, taus=(5,))
    assert score.jac[5.0] == 1.0
    # Labels mirrored through the centre: the frame is scored with the symmetric labelling.
    mirrored = {MIRRORED_CLASS[name]: points for name, points in lines.items()}
    score = evaluate_frame(mirrored, camera, W, H, taus=(5,))
    assert score.jac[5.0] == 1.0 and score.mirrored[5.0]


def test_strict_threshold_and_fp_fn_counting():
    camera = camera_main()
    lines = perfect_annotation(camera)
    name = next(n for n in lines if n.startswith("Side line top") or n.startswith("Big rect"))
    # Move one point of one class exactly 5 px off its line: 5 is not < 5, so the class is a FP.
    poly = project_template_polylines(camera, W, H)[name]
    a, b = poly[0], poly[1]
    normal = np.array([-(b - a)[1], (b - a)[0]]) / np.linalg.norm(b - a)
    mid = (a + b) / 2 + 5.0 * normal
    # Check the shifted point's true distance (another segment could be nearer).
    distance = distances_to_polyline(mid[None], poly)[0]
    shifted = dict(lines)
    shifted[name] = np.vstack([lines[name], mid / np.array([W - 1, H - 1])])
    score = evaluate_frame(shifted, camera, W, H, taus=(distance, distance + 1e-6))
    n = len(lines)
    assert score.jac[distance] == pytest.approx((n - 1) / n)
    assert score.jac[distance + 1e-6] == 1.0
    # A class annotated but not projected is a FN; a projected class not annotated a FP.
    invisible = next(c for c in PitchTemplate().elements if c not in lines and MIRRORED_CLASS[c] not in lines)
    extra = dict(lines, **{invisible: np.array([[0.5, 0.5]])})
    missing = dict(list(lines.items())[1:])
    assert evaluate_frame(extra, camera, W, H, (5,)).fn[5.0] >= 1
    s = evaluate_frame(missing, camera, W, H, (5,))
    assert s.fp[5.0] == 1 and s.tp[5.0] == n - 1


def test_empty_projection_counts_false_negatives():
    sky = Camera.from_degrees(1100.0, 0.0, 180.0, 100.0, 0.0, (0.0, 55.0, -14.0), W, H)  # looks away, above horizon
    lines = {"Side line top": np.array([[0.1, 0.2], [0.5, 0.2]]), "Middle line": np.array([[0.5, 0.5]])}
    score = evaluate_frame(lines, sky, W, H, (5,))
    assert score.jac[5.0] == 0.0 and score.fn[5.0] == 2


def test_missing_camera_lowers_completeness_only():
    camera = camera_main()
    annotations = AnnotationSet(frames={"00001": perfect_annotation(camera), "00002": perfect_annotation(camera)})
    report = evaluate_cameras(annotations, {"00001": camera, "00002": None}, W, H, taus=(5, 10))
    assert report["completeness"] == 0.5 and report["accuracy"] == 1.0 and report["final_score"] == 0.5
    assert report["missing_cameras"] == ["00002"]
    assert set(report["taus"]) == {"5", "10"} and report["tau_values"] == [5.0, 10.0]
    assert report["mre_px"] < 1e-6 and report["resolution"] == [W, H]


def test_vectorised_evaluator_matches_plain_reference_on_perturbed_cameras():
    rng = np.random.default_rng(3)
    base = camera_main(k1=-0.08)
    for _ in range(12):
        truth = base.replace(pan_rad=base.pan_rad + rng.normal(0, 0.3), tilt_rad=base.tilt_rad + rng.normal(0, 0.05))
        lines = perfect_annotation(truth)
        guess = truth.replace(pan_rad=truth.pan_rad + rng.normal(0, 0.004), focal_px=truth.focal_px * rng.uniform(0.98, 1.02))
        ours = evaluate_frame(lines, guess, W, H, taus=(5, 10)).jac
        for tau in (5, 10):
            assert ours[float(tau)] == pytest.approx(frame_jac(lines, guess, W, H, tau), abs=1e-12)


def _write_annotation(path, lines):
    path.write_text(json.dumps({n: [{"x": float(x), "y": float(y)} for x, y in p] for n, p in lines.items()}))


def test_folders_trailing_space_and_bad_inputs(tmp_path):
    camera = camera_main(pan_rad=math.radians(-40))
    lines = perfect_annotation(camera)
    ann, cams = tmp_path / "ann", tmp_path / "cams"
    ann.mkdir()
    cams.mkdir()
    # Frame 1: good, with SoccerNet's trailing-space class name.
    data = {(n + " " if n == "Goal left post left" else n): [{"x": float(x), "y": float(y)} for x, y in p]
            for n, p in lines.items()}
    data["Goal left post left "] = data.pop("Goal left post left ", data.get("Goal left post left ", [{"x": 0.5, "y": 0.5}]))
    (ann / "00001.json").write_text(json.dumps(data))
    write_camera_file(cams / "camera_00001.json", camera)
    # Frame 2: malformed annotation JSON -> reported, left out.
    (ann / "00002.json").write_text("{not json")
    # Frame 3: unknown class -> reported, left out.
    (ann / "00003.json").write_text(json.dumps({"Penalty spot": [{"x": 0.5, "y": 0.5}]}))
    # Frame 4: camera with NaN -> counts as a missing camera and is reported.
    _write_annotation(ann / "00004.json", lines)
    (cams / "camera_00004.json").write_text(json.dumps(dict(camera.to_soccernet_dict(), pan_degrees=float("nan"))))
    annotations = read_annotations(ann)
    assert set(annotations.frames) == {"00001", "00004"}
    assert "malformed JSON" in annotations.errors["00002"] and "00002.json" in annotations.errors["00002"]
    assert "unknown line class 'Penalty spot'" in annotations.errors["00003"]
    assert "Goal left post left" in annotations.frames["00001"]
    report = evaluate_folders(ann, cams, W, H, (5,), progress=False)
    assert report["frames"] == 2 and report["completeness"] == 0.5
    assert "camera_00004.json" in report["errors"]["00004"] and "not finite" in report["errors"]["00004"]
    with pytest.raises(InputError, match="not found"):
        evaluate_folders(tmp_path / "nowhere", cams, W, H, (5,))
    with pytest.raises(InputError, match="camera folder not found"):
        load_cameras(tmp_path / "nowhere", ["00001"], W, H)


def test_cli_one_line_error_for_missing_folder(tmp_path):
    result = subprocess.run(
        [sys.executable, "-m", "broadtrack_graph.cli", "evaluate", "--annotations", str(tmp_path / "none"),
         "--cameras", str(tmp_path), "--no-progress"], capture_output=True, text=True)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "none" in lines[0] and "not found" in lines[0]


def test_real_annotations_vs_published_cameras(sn_calibration_dir):
    """The NBJW cameras on the real test set: frame-by-frame agreement with the plain reference."""
    annotations = read_annotations(sn_calibration_dir / "annotations")
    assert len(annotations.frames) == 1454 and not annotations.errors
    cameras, errors = load_cameras(sn_calibration_dir / "nbjw-cameras", annotations.frames, W, H)
    assert not errors
    report = evaluate_cameras(annotations, cameras, W, H, taus=(5, 10, 20))
    assert report["frames_with_camera"] == 1417
    assert report["completeness"] == pytest.approx(1417 / 1454)
    # Per-frame JaC of a spread of frames agrees with the point-by-point reference.
    frame_ids = sorted(report["per_frame"])[::40]
    for frame_id in frame_ids:
        expected = frame_jac(annotations.frames[frame_id], cameras[frame_id], W, H, 5)
        assert report["per_frame"][frame_id]["jac"]["5"] == pytest.approx(expected, abs=1e-12)
    # Scores rise with tau and are proper fractions.
    finals = [report["taus"][t]["final_score"] for t in ("5", "10", "20")]
    assert 0.5 < finals[0] < finals[1] < finals[2] < 1.0


# Figures of the official sn-calibration evaluation on these files (NBJW cameras, 960x540).
OFFICIAL_FINAL_SCORES = {"5": 0.7368, "10": 0.8763, "20": 0.9122}
OFFICIAL_JAC5_GOAL_FRAMES = {  # frames with goal posts, where the mirrored post names decide the score
    "01766": 0.6154, "01904": 0.5556, "02456": 1.0, "02505": 0.6667, "02557": 0.7000, "02602": 0.6364, "02626": 1.0,
}


def test_real_scores_match_the_official_evaluation(sn_calibration_dir):
    """Final scores at tau 5/10/20 and the goal-post frames agree with the official figures (4 decimals)."""
    annotations = read_annotations(sn_calibration_dir / "annotations")
    cameras, _ = load_cameras(sn_calibration_dir / "nbjw-cameras", annotations.frames, W, H)
    report = evaluate_cameras(annotations, cameras, W, H, taus=(5, 10, 20))
    for tau, expected in OFFICIAL_FINAL_SCORES.items():
        assert round(report["taus"][tau]["final_score"], 4) == expected
    accuracy_sum = sum(frame["jac"]["5"] for frame in report["per_frame"].values() if frame["jac"]["5"] is not None)
    assert accuracy_sum == pytest.approx(1071.30, abs=0.005)
    for frame_id, expected in OFFICIAL_JAC5_GOAL_FRAMES.items():
        assert round(report["per_frame"][frame_id]["jac"]["5"], 4) == expected, frame_id
