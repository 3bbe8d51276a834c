"""Calibrate a set of annotated frames: one camera per frame from its labelled line points.

:func:`calibrate_annotation_set` is the set-level job (every frame, over worker processes with
:func:`~broadtrack_graph.actions.parallel.map_jobs`); :func:`calibrate_folder` is the
``calibrate`` command: annotations in, ``camera_<id>.json`` files (and a preview mosaic) out.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from broadtrack_graph.actions.parallel import map_jobs
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import AnnotationSet, read_annotations
from broadtrack_graph.io.cameras import camera_file_name, write_camera_file
from broadtrack_graph.reinit.calibrate import FrameCalibration, calibrate_item, init_worker
from broadtrack_graph.reinit.lines import ReinitConfig

PREVIEW_FRAMES = 9
"""Frames drawn in the preview mosaic (evenly spaced over the set)."""


def calibrate_annotation_set(
    annotations: AnnotationSet,
    width_px: int,
    height_px: int,
    on_result: Callable[[FrameCalibration], None] | None = None,
    config: ReinitConfig = ReinitConfig(),
    jobs: int = 1,
    progress: bool = True,
) -> dict:
    """Calibrate every annotated frame; ``on_result`` receives each frame as soon as it is done.

    Args:
        annotations: frames to calibrate (normalised coordinates).
        width_px, height_px: resolution of the cameras produced.
        on_result: callback (e.g. writing camera_<id>.json), called in frame order.
        jobs: worker processes (1 = in this process).
        progress: show a tqdm bar.

    Returns:
        Summary: frames, cameras, missing (frame id -> reason), hypotheses (name -> count),
        mean_self_jaccard, mean_inlier_share.
    """
    items = [(frame_id, annotations.frames[frame_id]) for frame_id in sorted(annotations.frames)]
    summary = {"frames": len(items), "cameras": 0, "missing": {}, "hypotheses": {}}
    jaccards, inliers = [], []

    def handle(result: FrameCalibration) -> None:
        if result.camera is None:
            summary["missing"][result.frame_id] = result.reason
        else:
            summary["cameras"] += 1
            kind = result.hypothesis.split(" at ")[0]
            summary["hypotheses"][kind] = summary["hypotheses"].get(kind, 0) + 1
            jaccards.append(result.jaccard)
            inliers.append(result.inlier_share)
        if on_result is not None:
            on_result(result)

    map_jobs(calibrate_item, items, jobs, initializer=init_worker, initargs=(width_px, height_px, config),
             label="calibrate", progress=progress, on_result=handle)
    summary["mean_self_jaccard"] = float(np.mean(jaccards)) if jaccards else 0.0
    summary["mean_inlier_share"] = float(np.mean(inliers)) if inliers else 0.0
    return summary


def calibrate_folder(annotations_path: str | Path, out_dir: str | Path, width_px: int, height_px: int,
                     jobs: int = 1, preview_path: str | Path | None = None, progress: bool = True) -> dict:
    """Calibrate every frame of an annotation set and write ``camera_<id>.json`` into ``out_dir``.

    Args:
        annotations_path: folder of per-image NNNNN.json annotations, or a Labels-GameState.json (or its folder).
        out_dir: folder for the camera files (created).
        width_px, height_px: resolution the cameras are written for.
        jobs: worker processes.
        preview_path: write a PNG mosaic of :data:`PREVIEW_FRAMES` evenly spaced frames here.

    Returns:
        The summary of :func:`calibrate_annotation_set` with "unreadable_annotations"
        (file -> error) added.

    Raises:
        InputError: resolution below 2x2, or no usable annotation.
    """
    if width_px < 2 or height_px < 2:
        raise InputError(None, f"resolution must be at least 2x2, got {width_px}x{height_px}")
    annotations = read_annotations(annotations_path)
    if not annotations.frames:
        raise InputError(annotations_path, annotations.no_frames_reason())
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)

    frame_ids = sorted(annotations.frames)
    preview_ids = set(frame_ids[:: max(1, len(frame_ids) // PREVIEW_FRAMES)][:PREVIEW_FRAMES])
    previews = []

    def write(result: FrameCalibration) -> None:
        if result.camera is not None:
            write_camera_file(out_dir / camera_file_name(result.frame_id), result.camera, width_px, height_px)
        if preview_path is not None and result.frame_id in preview_ids:
            from broadtrack_graph.products.calibration_preview import draw_calibration

            previews.append(draw_calibration(annotations.frames[result.frame_id], result.camera, width_px,
                                             height_px, title=result.frame_id))

    summary = calibrate_annotation_set(annotations, width_px, height_px, on_result=write, jobs=jobs, progress=progress)
    summary["unreadable_annotations"] = annotations.errors
    if preview_path is not None and previews:
        from broadtrack_graph.products.calibration_preview import write_mosaic

        write_mosaic(previews, preview_path)
    return summary


def calibrate_images(images_path: str | Path, out_dir: str | Path, model_path: str | Path | None = None,
                     preview_path: str | Path | None = None, progress: bool = True) -> dict:
    """One camera per image (or video frame) from the learned field model alone; ``camera_<id>.json`` into out_dir.

    Each frame's keypoints give a camera (:class:`~broadtrack_graph.reinit.field_model.ModelReinit`); it is
    written only when :class:`~broadtrack_graph.reinit.field_model.ModelAcceptance` accepts it (enough
    keypoints agree with it), at the frame's own resolution. Files are written as frames are done, so an
    interrupted run keeps them.

    Args:
        images_path: a folder of images, a video file or a game-state sequence folder.
        out_dir: folder for the camera files (created).
        model_path: a field model .onnx (default: the shipped one).
        preview_path: write a PNG mosaic of :data:`PREVIEW_FRAMES` evenly spaced frames with the projected pitch.

    Returns:
        {"frames", "cameras", "missing" (frame id -> reason), "keypoints_median"}.

    Raises:
        InputError: no readable input, or a model that breaks its contract.
    """
    from tqdm import tqdm

    from broadtrack_graph.detect.field_model import FieldModel
    from broadtrack_graph.io.frames import open_frames
    from broadtrack_graph.reinit.field_model import ModelAcceptance, ModelReinit

    reinit, acceptance = ModelReinit(FieldModel(model_path)), ModelAcceptance()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    summary: dict = {"frames": 0, "cameras": 0, "missing": {}}
    keypoint_counts, previews = [], []
    with open_frames(images_path) as source:
        preview_every = max(1, len(source) // PREVIEW_FRAMES)
        for frame in tqdm(source, total=len(source), desc="calibrate", unit="frame", disable=not progress):
            summary["frames"] += 1
            if frame.image_bgr is None:
                summary["missing"][frame.frame_id] = frame.problem or "frame could not be read"
                continue
            result = reinit(frame.image_bgr)
            keypoint_counts.append(len(reinit.last_keypoints) if reinit.last_keypoints is not None else 0)
            H, W = frame.image_bgr.shape[:2]
            camera = result.camera if acceptance.accepts(result) else None
            if camera is not None:
                write_camera_file(out_dir / camera_file_name(frame.frame_id), camera, W, H)
                summary["cameras"] += 1
            else:
                summary["missing"][frame.frame_id] = result.reason or (
                    f"{result.score.tp} of {keypoint_counts[-1]} keypoints agree with the camera: not accepted")
            if preview_path is not None and frame.frame_index % preview_every == 0 and len(previews) < PREVIEW_FRAMES:
                from broadtrack_graph.products.overlay import draw_pitch

                picture = frame.image_bgr.copy()
                previews.append(draw_pitch(picture, camera) if camera is not None else picture)
    summary["keypoints_median"] = float(np.median(keypoint_counts)) if keypoint_counts else 0.0
    if preview_path is not None and previews:
        import cv2

        from broadtrack_graph.products.calibration_preview import write_mosaic

        size = previews[0].shape[1::-1]
        write_mosaic([p if p.shape == previews[0].shape else cv2.resize(p, size) for p in previews], preview_path)
    return summary
