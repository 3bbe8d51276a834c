"""``bench model``: what the learned field model does alone, on frames it never saw.

* **Held-out synthetic frames** (960x540 by default): field samples of the held-out seed (never
  trained on: every camera kind, close-ups and crowds) and frames of every synthetic preset clip.
  Per frame the model's keypoints are compared with the true camera's projection of the same
  keypoints, and the camera from the model alone (:class:`~broadtrack_graph.reinit.field_model.ModelReinit`,
  accepted by :class:`~broadtrack_graph.reinit.field_model.ModelAcceptance`) is scored with the
  SoccerNet JaC at 5 px against the frame's annotation (a field sample's: every marking of its true
  camera). Figures: keypoints within 5 px (of those the model gives; and the share of the visible
  ones it finds within 5 px), pitch frames with a camera of JaC@5 >= 80 %, negatives with no camera.
* **Real clips** (``--video-dir``, no ground truth): every n-th frame, the camera from the model
  alone and the weight-free global search's camera (its default positions), each judged by the
  independent line-alignment check (:mod:`broadtrack_graph.metrics.line_alignment`), side by side.
* **Speed**, one onnxruntime thread: the model's forward pass and frame -> camera (forward, keypoints,
  camera) per frame, medians, at each real clip's resolution.
"""

from __future__ import annotations

import time
from pathlib import Path

import cv2
import numpy as np

HELP = "the learned field model alone: held-out synthetic keypoints and cameras, real clips against the search, speed"

JAC_TAU_PX = 5.0
GOOD_JAC = 0.8
KEYPOINT_TOLERANCE_PX = 5.0


def add_arguments(parser) -> None:
    from broadtrack_graph.synth.presets import PRESET_STREAMS

    parser.add_argument("--model", type=Path, default=None, help="a field model .onnx (default: the shipped one)")
    parser.add_argument("--samples", type=int, default=300, help="held-out field samples (default 300)")
    parser.add_argument("--presets", nargs="*", default=list(PRESET_STREAMS),
                        help="synthetic presets whose frames are scored too (default: all)")
    parser.add_argument("--preset-frames", type=int, default=12, help="frames per preset clip (default 12)")
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=540)
    parser.add_argument("--video-dir", type=Path, default=None, help="folder of real broadcast videos (*.mp4)")
    parser.add_argument("--every", type=int, default=25, help="real clips: every n-th frame (default 25)")
    parser.add_argument("--no-search", action="store_true", help="real clips: skip the weight-free search")


def run(args) -> dict:
    from broadtrack_graph.detect.field_model import FieldModel
    from broadtrack_graph.reinit.field_model import ModelReinit

    cv2.setNumThreads(1)
    model = FieldModel(args.model, threads=1)
    reinit = ModelReinit(model)
    report = {"model": str(model.path), "synthetic": _synthetic(reinit, args)}
    if args.video_dir is not None:
        report["real"] = _real(reinit, args)
    return report


def _frame_figures(reinit, image, truth, lines_norm, W: int, H: int) -> dict:
    """One frame: the model's keypoints against the truth's, and its camera's JaC@5 (truth None: a negative)."""
    from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W
    from broadtrack_graph.metrics.soccernet import evaluate_frame
    from broadtrack_graph.reinit.field_model import ModelAcceptance

    started = time.perf_counter()
    result = reinit(image)
    ms = 1000 * (time.perf_counter() - started)
    keypoints = reinit.last_keypoints
    accepted = ModelAcceptance().accepts(result)
    out = {"camera": accepted, "ms": ms, "keypoints": len(keypoints)}
    if truth is None:
        return out
    world = np.array([NBJW_KEYPOINTS_W[k] for k in range(1, 58)], float)
    uv_true, front = truth.project(world)
    inside = front & truth.in_image(uv_true)
    if len(keypoints):
        # Each keypoint of the model is matched to the truth's projection of the same pitch point.
        index = np.argmin(np.linalg.norm(keypoints.points_w[:, None] - world[None], axis=2), axis=1)
        error = np.linalg.norm(keypoints.uv_px - uv_true[index], axis=1)
        error[~front[index]] = np.inf
        out["keypoint_errors_px"] = error.tolist()
        found = set(index[error < KEYPOINT_TOLERANCE_PX].tolist())
    else:
        out["keypoint_errors_px"], found = [], set()
    out["visible_keypoints"] = int(inside.sum())
    out["visible_found"] = int(sum(1 for i in np.flatnonzero(inside) if i in found))
    out["jac5"] = float(evaluate_frame(lines_norm, result.camera, W, H, taus=(JAC_TAU_PX,)).jac[JAC_TAU_PX]) \
        if accepted else 0.0
    return out


def _truth_lines(camera, W: int, H: int, sampling) -> dict[str, np.ndarray]:
    """Every marking of the true camera as a SoccerNet annotation (normalised points)."""
    from broadtrack_graph.geometry.template import project_template_polylines

    scale = np.array([W - 1.0, H - 1.0])
    return {name: uv / scale for name, uv in project_template_polylines(camera, W, H, sampling).items() if len(uv)}


def _synthetic(reinit, args) -> dict:
    from tqdm import tqdm

    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.synth.field_samples import HELD_OUT_SEED, sample_field

    W, H = args.width, args.height
    sampling = TemplateSampling(PitchTemplate())
    frames: dict[str, list[dict]] = {}
    for index in tqdm(range(args.samples), desc="model: held-out samples", unit="frame"):
        sample = sample_field(HELD_OUT_SEED, index, W, H)
        lines = None if sample.camera is None else _truth_lines(sample.camera, W, H, sampling)
        frames.setdefault(f"sample {sample.kind}", []).append(
            _frame_figures(reinit, sample.image_bgr, sample.camera, lines, W, H))
    for preset in args.presets:
        clip = render_clip(preset, args.preset_frames * 10, W, H, seed=HELD_OUT_SEED)
        for frame in tqdm(clip.frames[::10], desc=f"model: preset {preset}", unit="frame"):
            frames.setdefault(f"preset {preset}", []).append(
                _frame_figures(reinit, frame.image, frame.camera, frame.lines_norm, W, H))
    return {"resolution": f"{W}x{H}", "all": _summary(sum(frames.values(), [])),
            "by_kind": {kind: _summary(items) for kind, items in sorted(frames.items())}}


def _summary(items: list[dict]) -> dict:
    pitch = [f for f in items if "jac5" in f]
    negatives = [f for f in items if "jac5" not in f]
    errors = np.array(sum((f["keypoint_errors_px"] for f in pitch), []), float)
    visible = sum(f["visible_keypoints"] for f in pitch)
    out = {"pitch_frames": len(pitch), "negative_frames": len(negatives)}
    if pitch:
        out.update({
            "keypoints_given": int(len(errors)),
            "keypoints_within_5px": round(float(np.mean(errors < KEYPOINT_TOLERANCE_PX)), 3) if len(errors) else None,
            "keypoint_error_median_px": round(float(np.median(errors)), 2) if len(errors) else None,
            "visible_keypoints_found_within_5px": round(sum(f["visible_found"] for f in pitch) / max(visible, 1), 3),
            "pitch_frames_with_camera": round(float(np.mean([f["camera"] for f in pitch])), 3),
            "pitch_frames_jac5_at_least_80": round(float(np.mean([f["jac5"] >= GOOD_JAC for f in pitch])), 3),
            "jac5_mean_of_cameras": round(float(np.mean([f["jac5"] for f in pitch if f["camera"]])), 3)
            if any(f["camera"] for f in pitch) else None,
        })
    if negatives:
        out["negatives_without_camera"] = round(float(np.mean([not f["camera"] for f in negatives])), 3)
        out["negative_keypoints_median"] = float(np.median([f["keypoints"] for f in negatives]))
    out["frame_to_camera_ms_median"] = round(float(np.median([f["ms"] for f in items])), 1) if items else None
    return out


def _real(reinit, args) -> dict:
    from tqdm import tqdm

    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.metrics.line_alignment import AlignmentConfig, line_alignment, line_pixels
    from broadtrack_graph.reinit.field_model import ModelAcceptance
    from broadtrack_graph.reinit.frame import reinitialise

    pitch = PitchTemplate()
    curves, sampling = fitting_curves(pitch), TemplateSampling(pitch)
    detector, config, acceptance = WeightFreeDetector(pitch), AlignmentConfig(), ModelAcceptance()
    clips = {}
    for video in sorted(Path(args.video_dir).glob("*.mp4")):
        capture = cv2.VideoCapture(str(video))
        figures = {"model": [], "search": [], "model_ms": [], "search_ms": [], "forward_ms": []}
        scored, size = 0, (0, 0)
        total = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        for index in tqdm(range(total), desc=f"model: {video.stem}", unit="frame"):
            if index % max(1, args.every):
                if not capture.grab():  # a frame not scored is not decoded into an image
                    break
                continue
            ok, image = capture.read()
            if not ok:
                break
            scored += 1
            size = image.shape[1::-1]
            pixels = line_pixels(image, config)

            def aligned(camera) -> bool:
                alignment = None if camera is None else line_alignment(image, camera, curves, config, pixels)
                return alignment is not None and alignment.aligned(config)

            before = len(reinit.model.forward_ms)
            started = time.perf_counter()
            result = reinit(image)
            figures["model_ms"].append(1000 * (time.perf_counter() - started))
            figures["forward_ms"].extend(reinit.model.forward_ms[before:])
            figures["model"].append(aligned(result.camera if acceptance.accepts(result) else None))
            if not args.no_search:
                started = time.perf_counter()
                detections = detector.detect(image)
                found = reinitialise(detections.to_observations(index), detections, pitch, curves=curves,
                                     sampling=sampling)
                figures["search_ms"].append(1000 * (time.perf_counter() - started))
                figures["search"].append(aligned(found.camera))
        capture.release()
        clips[video.stem] = {
            "resolution": f"{size[0]}x{size[1]}", "frames_scored": scored,
            "model_alone_aligned": round(float(np.mean(figures["model"])), 3) if scored else None,
            "search_aligned": round(float(np.mean(figures["search"])), 3) if figures["search"] else None,
            "forward_ms_median": round(float(np.median(figures["forward_ms"])), 1) if scored else None,
            "frame_to_camera_ms_median": round(float(np.median(figures["model_ms"])), 1) if scored else None,
            "search_ms_median": round(float(np.median(figures["search_ms"])), 1) if figures["search_ms"] else None,
        }
    return {"every": args.every, "clips": clips}
