"""Tests of the synthetic clip generator: rendering, ground truth, clip folders, CLI."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from broadtrack_graph.cli import main as cli_main
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES
from broadtrack_graph.io.annotations import AnnotationSet, read_annotations
from broadtrack_graph.io.cameras import list_camera_files, read_camera_file, write_camera_file
from broadtrack_graph.metrics.soccernet import evaluate_cameras
from broadtrack_graph.synth.clip import render_clip
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.synth.render import EXACT_SETTINGS

W, H = 480, 270


@pytest.fixture(scope="module")
def main_clip():
    return render_clip("main", 6, W, H, seed=4)


@pytest.fixture(scope="module")
def exact_clip():
    return render_clip("hard", 4, 960, 540, seed=4, settings=EXACT_SETTINGS)


def _score(clip, tau="5"):
    report = evaluate_cameras(AnnotationSet(frames=clip.annotations), {f.frame_id: f.camera for f in clip.frames},
                              clip.width_px, clip.height_px)
    return report["taus"][tau]["final_score"], report


def test_deterministic_for_a_seed_and_a_short_clip_is_the_start_of_a_long_one(main_clip):
    again = render_clip("main", 2, W, H, seed=4)  # main_clip has 6 frames
    other = render_clip("main", 2, W, H, seed=8)
    for a, b in zip(main_clip.frames[:2], again.frames):
        np.testing.assert_array_equal(a.image, b.image)
        np.testing.assert_array_equal(a.mask, b.mask)
        assert a.lines_norm.keys() == b.lines_norm.keys()
        for name in a.lines_norm:
            np.testing.assert_array_equal(a.lines_norm[name], b.lines_norm[name])
    assert np.abs(main_clip.frames[0].image.astype(int) - other.frames[0].image.astype(int)).mean() > 5


@pytest.mark.parametrize("preset", ["main", "high-behind", "16m"])
def test_ground_truth_cameras_score_one_at_tau_5(preset):
    clip = render_clip(preset, 4, W, H, seed=4, want_masks=False)
    score, report = _score(clip)
    assert score == 1.0
    assert report["mre_px"] < 0.5  # annotated points lie on the projected template
    assert np.mean([len(f.lines_norm) for f in clip.frames]) >= 3  # real content, not empty frames


def test_ground_truth_scores_one_with_noise_effects(main_clip, exact_clip):
    for clip in (main_clip, exact_clip):
        assert _score(clip)[0] == 1.0
    # Like real annotations: a handful of points per straight line, more on circles.
    counts = [len(p) for f in main_clip.frames for p in f.lines_norm.values()]
    assert 2 <= np.median(counts) <= 12


def _apparent_width_px(camera, name, uv_px, pitch):
    """Projected width (pixels) of the 12 cm marking at image points of class name."""
    if not pitch.is_on_ground(name):
        depth = camera.world_to_camera(np.asarray(pitch.elements[name].start_w, float)[None])[0, 2]
        return np.full(len(uv_px), 0.12 * camera.focal_px / depth)
    points, _ = camera.ground_intersection(uv_px)
    element = pitch.elements[name]
    if hasattr(element, "radius_m"):
        normal = points[:, :2] - np.asarray(element.centre_w[:2])
    else:
        direction = np.subtract(element.end_w, element.start_w)[:2]
        normal = np.tile([-direction[1], direction[0]], (len(points), 1))
    normal = normal / np.linalg.norm(normal, axis=1, keepdims=True)
    offset = np.column_stack([0.06 * normal, np.zeros(len(points))])
    a, _ = camera.project(points + offset)
    b, _ = camera.project(points - offset)
    return np.linalg.norm(a - b, axis=1)


def test_annotated_points_lie_on_white_line_pixels(exact_clip, main_clip):
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    for clip in (exact_clip, main_clip):  # without and with noise, blur, shadows, sharpening
        contrasts, mask_hits, total = [], 0, 0
        for frame in clip.frames:
            gray = cv2.cvtColor(frame.image, cv2.COLOR_BGR2GRAY).astype(float)
            brightest = cv2.dilate(gray, np.ones((3, 3)))
            background = cv2.cvtColor(cv2.medianBlur(frame.image, 21), cv2.COLOR_BGR2GRAY).astype(float)
            for name, points in frame.lines_norm.items():
                if name in frame.occluded_classes:
                    continue
                index = LINE_CLASSES.index(name) + 1
                near_mask = cv2.dilate((frame.mask == index).astype(np.uint8), np.ones((3, 3))) > 0
                uv = points * [clip.width_px - 1, clip.height_px - 1]
                px = np.rint(uv).astype(int)
                mask_hits += int(near_mask[px[:, 1], px[:, 0]].sum())
                total += len(px)
                # A marking thinner than half a pixel cannot be white; it must still be in the mask.
                wide = _apparent_width_px(frame.camera, name, uv, pitch) >= 0.5
                contrasts.extend(brightest[px[wide, 1], px[wide, 0]] - background[px[wide, 1], px[wide, 0]])
        contrasts = np.asarray(contrasts)
        assert total > 40 and len(contrasts) > 0.5 * total
        assert np.mean(contrasts > 12) > 0.95  # brighter than the grass around
        assert np.median(contrasts) > 40
        assert mask_hits / total > 0.97  # the mask marks the same class there


def test_masks_and_keypoints_agree_with_geometry(main_clip):
    frame = main_clip.frames[0]
    assert frame.mask.shape == (H, W) and frame.mask.dtype == np.uint8
    assert 0 < np.count_nonzero(frame.mask) < 0.2 * W * H
    assert set(np.unique(frame.mask)) - {0} <= set(range(1, len(LINE_CLASSES) + 1))
    assert frame.keypoints_px, "a main-camera frame shows some keypoints"
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    names = list(frame.keypoints_px)
    uv, _ = frame.camera.project(pitch.keypoint_array(names))
    np.testing.assert_allclose(np.array([frame.keypoints_px[n] for n in names]), uv, atol=1e-9)
    near_mask = cv2.dilate((frame.mask > 0).astype(np.uint8), np.ones((5, 5))) > 0
    on_lines = [near_mask[int(round(v)), int(round(u))] for n, (u, v) in frame.keypoints_px.items()
                if "spot" not in n and "mark" not in n]
    assert np.mean(on_lines) > 0.9


def test_cli_writes_a_clip_folder_that_reads_back(tmp_path):
    out = tmp_path / "clip"
    code = cli_main(["synth", "--preset", "main", "--frames", "3", "--width", "320", "--height", "180", "--seed", "2",
                     "--out", str(out), "--no-progress"])
    assert code == 0
    for name in ("Labels-GameState.json", "clip.json", "tripod.json", "players.json", "ground_truth.json"):
        assert (out / name).is_file(), name
    assert sorted(p.name for p in (out / "img1").iterdir()) == ["000001.jpg", "000002.jpg", "000003.jpg"]
    image = cv2.imread(str(out / "img1" / "000002.jpg"))
    assert image.shape == (180, 320, 3)
    mask = cv2.imread(str(out / "masks" / "000002.png"), cv2.IMREAD_UNCHANGED)
    assert mask.shape == (180, 320) and mask.dtype == np.uint8 and mask.max() <= len(LINE_CLASSES)
    annotations = read_annotations(out)  # Labels-GameState.json
    per_frame = read_annotations(out / "annotations")
    assert sorted(annotations.frames) == sorted(per_frame.frames) == ["000001", "000002", "000003"]
    assert annotations.image_sizes["000001"] == (320, 180)
    cameras = {fid: read_camera_file(path, 320, 180) for fid, path in list_camera_files(out / "cameras").items()}
    report = evaluate_cameras(annotations, cameras, 320, 180)
    assert report["taus"]["5"]["final_score"] == 1.0
    labels = json.loads((out / "Labels-GameState.json").read_text())
    assert any(a.get("supercategory") == "object" for a in labels["annotations"])
    truth = json.loads((out / "ground_truth.json").read_text())
    tripod = json.loads((out / "tripod.json").read_text())
    track = generate_camera_track("main", 3, 320, 180, seed=2)
    assert tripod["T_w"] == pytest.approx(list(track.tripod.T_w)) and tripod["delta_m"] == pytest.approx(track.tripod.delta_m)
    assert [f["lambda_m"] for f in truth["frames"]] == pytest.approx(list(track.lambdas_m))
    np.testing.assert_allclose(cameras["000003"].to_vector(), track.cameras[2].to_vector(), atol=1e-9)
    keypoints = json.loads((out / "keypoints" / "000001.json").read_text())
    assert all(len(uv) == 2 for uv in keypoints.values())
    # True player positions per frame and id; the labels' bbox_pitch agrees with them.
    player_truth = json.loads((out / "players_pitch.json").read_text())
    assert sorted(player_truth["frames"]) == ["000001", "000002", "000003"]
    image_frame = {image["image_id"]: image["file_name"][:6] for image in labels["images"]}
    boxes = [a for a in labels["annotations"] if a.get("supercategory") == "object"]
    for box in boxes:
        x, y = player_truth["frames"][image_frame[box["image_id"]]][str(box["track_id"])]
        assert (box["bbox_pitch"]["x_bottom_middle"], box["bbox_pitch"]["y_bottom_middle"]) == pytest.approx((x, y), abs=1e-3)


def test_cli_renders_along_a_given_camera_track(tmp_path):
    track = generate_camera_track("16m", 3, 960, 540, seed=9)
    cams_dir = tmp_path / "cams"
    for i, camera in enumerate(track.cameras):
        write_camera_file(cams_dir / f"camera_{i + 1:05d}.json", camera)
    out = tmp_path / "clip"
    assert cli_main(["synth", "--cameras", str(cams_dir), "--width", "320", "--height", "180", "--out", str(out),
                     "--no-progress", "--no-masks"]) == 0
    written = list_camera_files(out / "cameras")
    assert len(written) == 3
    for (fid, path), original in zip(sorted(written.items()), track.cameras):
        np.testing.assert_allclose(read_camera_file(path).to_vector(), original.rescaled(320, 180).to_vector(), atol=1e-9)
    assert not (out / "tripod.json").exists()  # a given track has no known tripod
    clip_info = json.loads((out / "clip.json").read_text())
    assert clip_info["frames_written"] == 3 and clip_info["camera_source"] == str(cams_dir)


def test_cli_reports_a_bad_camera_folder(tmp_path, capsys):
    code = cli_main(["synth", "--cameras", str(tmp_path / "missing"), "--width", "320", "--height", "180",
                     "--out", str(tmp_path / "out"), "--no-progress"])
    assert code == 2
    assert "camera folder not found" in capsys.readouterr().err


def test_k1_below_zero_never_annotates_folded_points():
    # With k1 < 0 the model folds points far off-axis back into the image; they must not be annotated.
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, _project_like_official

    camera = Camera.from_degrees(450.0, -0.08, -60.0, 70.0, 0.0, [0.0, 55.0, -12.0], W, H)
    sampling = TemplateSampling()
    uv, front = _project_like_official(camera, sampling.points_w)
    points_c = camera.world_to_camera(sampling.points_w)
    folded = front & ((points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / points_c[:, 2] ** 2 >= 1 / (3 * 0.08))
    inside = front & (uv[:, 0] >= 0) & (uv[:, 0] < W) & (uv[:, 1] >= 0) & (uv[:, 1] < H)
    assert (folded & inside).any()  # the case exists in this view
    frame = render_clip("main", 1, W, H, seed=0, cameras=[camera], want_masks=False).frames[0]
    pitch = PitchTemplate()
    dense = pitch.sample_uniform(0.02)
    for name, points in frame.lines_norm.items():
        if not pitch.is_on_ground(name):
            continue
        uv_px = points * [W - 1, H - 1]
        ground, hits = camera.ground_intersection(uv_px)  # the pixel's real ray (first branch)
        assert hits.all()
        gap = np.min(np.linalg.norm(ground[:, None, :2] - dense[name][None, :, :2], axis=2), axis=1)
        assert gap.max() < 0.05, name  # the ray really meets the marking there
    # Classes the metric sees only through the fold are listed, not annotated; they are the only misses.
    from broadtrack_graph.metrics.soccernet import evaluate_frame

    score = evaluate_frame(frame.lines_norm, camera, W, H, taus=(5.0,))
    misses = {name for name, outcome in score.class_outcome[5.0].items() if outcome != "tp"}
    assert frame.folded_classes and misses == set(frame.folded_classes)


def test_frame_observations_carry_the_ground_truth(main_clip):
    frame = main_clip.frames[1]
    obs = frame.observations()
    assert (obs.width_px, obs.height_px, obs.frame_index) == (W, H, 1)
    for name, points_px in obs.lines_px.items():
        np.testing.assert_allclose(points_px, frame.lines_norm[name] * [W - 1, H - 1])
    uv, _ = frame.camera.project(obs.keypoints.points_w)
    np.testing.assert_allclose(obs.keypoints.uv_px, uv, atol=1e-9)
    assert obs.marking_mask.dtype == bool and obs.marking_mask.shape == (H, W)
    assert obs.player_boxes_px.shape[1] == 4
    assert np.all(obs.player_boxes_px[:, 2] >= obs.player_boxes_px[:, 0])


def test_an_interrupted_clip_keeps_its_finished_frames(tmp_path, monkeypatch):
    import broadtrack_graph.synth.writer as clip_writer

    real = clip_writer.iter_clip_frames

    def two_then_interrupt(*args, **kwargs):
        for count, frame in enumerate(real(*args, **kwargs)):
            if count == 2:
                raise KeyboardInterrupt
            yield frame

    monkeypatch.setattr(clip_writer, "iter_clip_frames", two_then_interrupt)
    out = tmp_path / "clip"
    with pytest.raises(KeyboardInterrupt):
        clip_writer.write_synthetic_clip(out, "main", 5, 320, 180, seed=1, progress=False)
    info = json.loads((out / "clip.json").read_text())
    assert info["frame_count"] == 5 and info["frames_written"] == 2
    assert sorted(read_annotations(out).frames) == ["000001", "000002"]
    assert len(json.loads((out / "players.json").read_text())) == 2


def test_a_frame_without_markings_has_no_annotation(tmp_path):
    # Tight zoom on plain grass between the centre circle and the penalty area.
    camera = Camera.from_degrees(6000.0, 0.01, -28.0, 76.0, 0.0, [0.0, 55.0, -12.0], 320, 180)
    points, hits = camera.ground_intersection(np.array([[0.0, 0.0], [319.0, 179.0], [160.0, 90.0]]))
    assert hits.all() and np.all(np.abs(points[:, 0]) > 10) and np.all(np.abs(points[:, 0]) < 35)
    cams_dir = tmp_path / "cams"
    write_camera_file(cams_dir / "camera_00001.json", camera)
    write_camera_file(cams_dir / "camera_00002.json", camera.replace(focal_px=500.0))  # wide: markings
    out = tmp_path / "clip"
    assert cli_main(["synth", "--cameras", str(cams_dir), "--width", "320", "--height", "180", "--out", str(out),
                     "--no-progress"]) == 0
    assert sorted(p.name for p in (out / "annotations").iterdir()) == ["000002.json"]
    labels = json.loads((out / "Labels-GameState.json").read_text())
    assert [image["has_labeled_pitch"] for image in labels["images"]] == [False, True]
    assert sorted(read_annotations(out).frames) == ["000002"]
    mask = cv2.imread(str(out / "masks" / "000001.png"), cv2.IMREAD_UNCHANGED)
    assert mask.max() == 0
    truth = json.loads((out / "ground_truth.json").read_text())
    assert [f["annotated"] for f in truth["frames"]] == [False, True]
