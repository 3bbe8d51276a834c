"""Overlay drawing: lines where the projection says, no fold-back, colours, the overlay writer."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from broadtrack_graph import cli
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.distortion import distort_normalized
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.io.video import VideoSource
from broadtrack_graph.products.overlay import (
    confidence_colour_bgr,
    draw_pitch,
    project_pitch_polylines,
    render_overlay_frame,
    write_overlay,
)
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 640, 360


def main_camera(**changes) -> Camera:
    camera = Camera.from_degrees(620, -0.04, 12, 72, 0.3, (0.0, 55.0, -15.0), W, H)
    return camera.replace(**changes) if changes else camera


def dense_projection(camera: Camera, step_m: float = 0.02):
    """Pixels of densely sampled visible markings, with the camera's own projection."""
    samples = PitchTemplate().sample_uniform(step_m)
    points = np.vstack([samples[name] for name in LINE_CLASSES])
    uv, in_front = camera.project(points)
    points_c = camera.world_to_camera(points)
    r_n = np.hypot(points_c[:, 0], points_c[:, 1]) / np.where(in_front, points_c[:, 2], np.nan)
    return uv, in_front, r_n


def test_lines_are_drawn_where_the_projection_says():
    camera = main_camera()
    image = np.zeros((H, W, 3), np.uint8)
    draw_pitch(image, camera, (0, 255, 0), thickness_px=1, antialias=False)
    drawn = image[:, :, 1] > 0
    uv, in_front, _ = dense_projection(camera)
    inside = in_front & camera.in_image(uv)
    assert inside.sum() > 2000  # the test sees a good part of the pitch
    cols, rows = np.floor(uv[inside]).astype(int).T
    # Every projected marking point has a drawn pixel within 1 px.
    near = cv2.dilate(drawn.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    assert near[rows, cols].mean() > 0.995
    # Every drawn pixel is within 2 px of a projected marking point.
    reference = np.zeros((H, W), np.uint8)
    reference[rows, cols] = 1
    reference = cv2.dilate(reference, np.ones((5, 5), np.uint8)) > 0
    assert drawn.sum() > 1000 and not (drawn & ~reference).any()
    # Only green was used; the rest of the image stays black.
    assert image[:, :, 0].max() == 0 and image[:, :, 2].max() == 0


def test_points_past_the_distortion_fold_are_not_drawn():
    # Strong barrel distortion and a wide view: naive projection folds far points back into the image.
    camera = Camera.from_degrees(300, -0.2, 0, 70, 0, (0.0, 55.0, -15.0), W, H)
    r_turn = 1 / math.sqrt(3 * 0.2)
    uv, in_front, r_n = dense_projection(camera)
    samples = PitchTemplate().sample_uniform(0.02)
    points_c = camera.world_to_camera(np.vstack([samples[name] for name in LINE_CLASSES]))
    ahead = points_c[:, 2] > 1e-3
    with np.errstate(invalid="ignore", divide="ignore"):
        naive = camera.focal_px * distort_normalized(points_c[:, :2] / points_c[:, 2:], camera.k1) + camera.principal_point
        radius = np.hypot(points_c[:, 0], points_c[:, 1]) / points_c[:, 2]
    folded = ahead & camera.in_image(naive) & (radius > r_turn)
    assert folded.sum() > 50  # the setup really has folded points ...
    assert not in_front[folded].any()  # ... which the camera's projection does not report
    valid = in_front & (r_n < r_turn * 0.98)
    reference = np.zeros((H, W), np.uint8)
    good = valid & camera.in_image(uv)
    cols, rows = np.floor(uv[good]).astype(int).T
    reference[rows, cols] = 1
    reference = cv2.dilate(reference, np.ones((5, 5), np.uint8)) > 0
    image = np.zeros((H, W, 3), np.uint8)
    draw_pitch(image, camera, (255, 255, 255), thickness_px=1, antialias=False)
    drawn = image[:, :, 0] > 0
    assert not (drawn & ~reference).any()
    for pieces in project_pitch_polylines(camera).values():
        for piece in pieces:
            assert piece.shape[1] == 2 and len(piece) >= 2 and np.isfinite(piece).all()


def test_camera_behind_or_away_draws_nothing():
    camera = main_camera(tilt_rad=math.radians(175))  # looking up at the sky
    assert project_pitch_polylines(camera) == {}
    image = np.zeros((H, W, 3), np.uint8)
    draw_pitch(image, camera)
    assert image.max() == 0


def test_drawing_rescales_camera_to_image():
    camera = main_camera()
    small = np.zeros((H // 2, W // 2, 3), np.uint8)
    draw_pitch(small, camera, (0, 255, 0), thickness_px=1, antialias=False)
    big = np.zeros((H, W, 3), np.uint8)
    draw_pitch(big, camera, (0, 255, 0), thickness_px=1, antialias=False)
    down = cv2.resize(big, (W // 2, H // 2), interpolation=cv2.INTER_AREA)[:, :, 1] > 0
    overlap = (small[:, :, 1] > 0) & cv2.dilate(down.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    assert overlap.sum() > 0.95 * (small[:, :, 1] > 0).sum()


def test_confidence_colours():
    assert confidence_colour_bgr(0.95) == (0, 255, 0)
    assert confidence_colour_bgr(0.9) == (0, 255, 0)
    assert confidence_colour_bgr(0.6) == (0, 255, 255)
    assert confidence_colour_bgr(0.1) == (0, 0, 255)
    assert confidence_colour_bgr(0.45) == (0, 128, 255)
    assert confidence_colour_bgr(None) == confidence_colour_bgr(float("nan")) == (230, 230, 230)


def test_render_overlay_frame_adds_panel_inset_and_lines():
    frame = np.full((H, W, 3), 50, np.uint8)
    record = TrackRecord(7, "000008", 0.28, main_camera(), confidence=0.95)
    out = render_overlay_frame(frame, record)
    assert out.shape == frame.shape and (frame == 50).all()  # input untouched
    changed = np.any(out != frame, axis=2)
    assert changed[:40, :120].mean() > 0.3  # text panel, top left
    assert changed[10:60, -120:-10].mean() > 0.8  # bird's-eye inset, top right
    green = (out[:, :, 1] > 200) & (out[:, :, 2] < 80) & (out[:, :, 0] < 80)
    assert green[H // 2:].sum() > 200  # pitch lines in the lower half, in the confidence colour
    empty = render_overlay_frame(frame, TrackRecord(8, "000009", 0.32, None, status=FrameStatus.NO_PITCH, reason="no lines"))
    assert not ((empty[:, :, 1] > 200) & (empty[:, :, 2] < 80))[H // 2:].any()
    none = render_overlay_frame(frame, None, inset=False)
    assert (none[:, -100:] == 50).all()


def test_write_overlay_video_and_images(tmp_path):
    frames = tmp_path / "frames"
    frames.mkdir()
    camera = main_camera()
    for k in range(6):
        image = np.full((H, W, 3), (40, 110, 40), np.uint8)
        draw_pitch(image, camera.replace(pan_rad=camera.pan_rad + 0.01 * k), (255, 255, 255), 2)
        cv2.imwrite(str(frames / f"{k + 1:06d}.jpg"), image)
    data = (frames / "000004.jpg").read_bytes()
    (frames / "000004.jpg").write_bytes(data[: len(data) // 3])
    with TrackWriter(tmp_path / "run", W, H) as writer:
        for k in range(5):  # no record for the last frame
            cam = camera.replace(pan_rad=camera.pan_rad + 0.01 * k)
            writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, cam, confidence=0.9))
    result = write_overlay(tmp_path / "run", frames, tmp_path / "out.mp4", progress=False)
    assert result["frames"] == 6 and result["missing_input"] == 1 and result["with_camera"] == 4
    with VideoSource(tmp_path / "out.mp4") as video:
        assert (video.width_px, video.height_px, len(video)) == (W, H, 6)
    result = write_overlay(tmp_path / "run", frames, tmp_path / "pngs", start=1, end=3, progress=False)
    names = sorted(p.name for p in (tmp_path / "pngs").iterdir())
    assert names == ["overlay_000002.png", "overlay_000003.png"]
    image = cv2.imread(str(tmp_path / "pngs" / names[0]))
    assert image.shape == (H, W, 3)
    code = cli.main(["overlay", str(tmp_path / "run"), "--frames", str(frames), "--out", str(tmp_path / "cli"),
                     "--end", "2", "--no-inset", "--no-progress"])
    assert code == 0 and len(list((tmp_path / "cli").glob("overlay_*.png"))) == 2
    assert cli.main(["overlay", str(tmp_path / "run"), "--frames", str(tmp_path / "none"), "--out",
                     str(tmp_path / "x.mp4")]) == 2


def test_an_overlay_says_why_no_frame_has_a_camera(tmp_path, caplog):
    frames = tmp_path / "frames"
    frames.mkdir()
    for k in range(2):
        cv2.imwrite(str(frames / f"{k + 1:06d}.jpg"), np.full((H, W, 3), (40, 110, 40), np.uint8))
    with TrackWriter(tmp_path / "none", W, H) as writer:  # a run that placed no frame
        for k in range(2):
            writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, None, status=FrameStatus.UNPLACED))
    with TrackWriter(tmp_path / "other", W, H) as writer:  # cameras, but of other frames
        writer.write(TrackRecord(0, "other-000001", 0.0, main_camera(), confidence=0.9))
    for run, why in (("none", "the run has no camera"), ("other", "frame ids differ")):
        caplog.clear()
        assert write_overlay(tmp_path / run, frames, tmp_path / f"{run}.mp4", progress=False)["with_camera"] == 0
        assert why in caplog.text


@pytest.mark.parametrize("confidence", [0.2, 0.95])
def test_overlay_colour_follows_confidence(confidence):
    frame = np.zeros((H, W, 3), np.uint8)
    out = render_overlay_frame(frame, TrackRecord(0, "000001", 0.0, main_camera(), confidence=confidence), inset=False)
    lower = out[H // 2:]
    red = ((lower[:, :, 2] > 200) & (lower[:, :, 1] < 60)).sum()
    green = ((lower[:, :, 1] > 200) & (lower[:, :, 2] < 60)).sum()
    assert (red > 200 and green == 0) if confidence < 0.5 else (green > 200 and red == 0)


def test_drawing_matches_real_annotations_where_the_metric_says_so(sn_calibration_dir):
    """Real SoccerNet frames: where a published calibrator's camera scores JaC@5 = 1, the annotated
    points lie on the drawn lines."""
    from broadtrack_graph.io.annotations import annotation_to_pixels, read_annotation_file
    from broadtrack_graph.io.cameras import read_camera_file
    from broadtrack_graph.metrics.soccernet import evaluate_frame

    checked = 0
    for camera_path in sorted((sn_calibration_dir / "nbjw-cameras").glob("camera_*.json"))[:40]:
        frame_id = camera_path.stem.split("_")[1]
        lines = read_annotation_file(sn_calibration_dir / "annotations" / f"{frame_id}.json")
        camera = read_camera_file(camera_path, 960, 540)
        if evaluate_frame(lines, camera, 960, 540, (5.0,)).jac[5.0] < 1.0:
            continue
        image = np.zeros((540, 960, 3), np.uint8)
        draw_pitch(image, camera, (255, 255, 255), thickness_px=1, antialias=False)
        near = cv2.dilate((image[:, :, 0] > 0).astype(np.uint8), np.ones((13, 13), np.uint8)) > 0  # 6 px
        points = np.vstack([p for name, p in annotation_to_pixels(lines, 960, 540).items() if name in LINE_CLASSES])
        cols, rows = np.clip(np.round(points).astype(int), 0, [959, 539]).T
        assert near[rows, cols].mean() > 0.97, camera_path.name
        checked += 1
    assert checked >= 5
