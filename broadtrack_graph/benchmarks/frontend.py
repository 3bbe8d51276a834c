"""``broadtrack-graph bench frontend``: weight-free detection + flow speed, point accuracy, re-initialisation.

On rendered clips (synth presets, 1920x1080 by default), one thread for OpenCV:

* speed: median / p90 milliseconds per frame of weight-free detection (with a
  predicted camera) plus grid optical flow from the previous frame;
* accuracy: share of named points within 2 px of the true marking (point-to-polyline),
  the prediction being the true camera perturbed (about 3 px) with uncertainty 3 px;
* re-initialisation from a lost state (no usable previous camera): for frames showing at
  least 3 marking classes, as the tracker does at a new shot: the learned field model's camera
  (``--reinit-model``, the shipped one by default), refined on the weight-free marking map and taken
  when certain (``TrackingConfig.certain_confidence``, as the tracker takes a new shot's camera without a search), else
  :func:`reinit_from_mask` on the map (the weight-free global search);
  success = median reprojection error of the visible template below ``--success-px``;
  its time per frame (median and 90th percentile, wall clock and CPU time of the process:
  the CPU figure is less inflated by other jobs on the machine). Also reported over the
  frames whose marking map holds at least ``--min-marking-points`` centre-line points
  (strong motion blur erases the markings).
"""

from __future__ import annotations

import time
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.benchmarks.options import add_reinit_model

HELP = "front end: weight-free detection + flow speed, named-point accuracy, re-initialisation success and speed"


def add_arguments(parser) -> None:
    parser.add_argument("--presets", nargs="+", default=["main", "hard"], help="synth presets (default main hard)")
    parser.add_argument("--frames", type=int, default=12, help="frames per preset (default 12)")
    parser.add_argument("--reinit-every", type=int, default=3, help="re-initialise on every n-th frame (default 3)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--images", type=Path, default=None,
                        help="write overlays here: frontend_synthetic_<preset>.jpg (and frontend_real_frame.jpg: keep it out of the repository, it shows a copyrighted frame)")
    parser.add_argument("--real-frame", type=Path, default=None,
                        help="a real broadcast frame to run the weight-free detector on for the overlay")
    add_reinit_model(parser, default="shipped")  # the model is what this suite measures
    parser.add_argument("--success-px", type=float, default=5.0, help="re-init success bound (median template error)")
    parser.add_argument("--min-marking-points", type=int, default=150,
                        help="frames whose marking map has fewer centre-line points (motion blur, close-ups) are "
                             "also reported apart (default 150)")


def run(args) -> dict:
    from tqdm import tqdm

    from broadtrack_graph.detect.detector import PredictedCamera
    from broadtrack_graph.detect.flow import grid_flow, prepare
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateCurves, distances_to_polyline
    from broadtrack_graph.reinit.cheap import refine_guesses
    from broadtrack_graph.reinit.confidence import camera_confidence
    from broadtrack_graph.reinit.field_model import model_reinit_for
    from broadtrack_graph.reinit.frame import plausible_position
    from broadtrack_graph.reinit.mask import reinit_from_mask
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.track.config import TrackingConfig

    cv2.setNumThreads(1)
    pitch = PitchTemplate()
    detector = WeightFreeDetector(pitch)
    curves = TemplateCurves(pitch)
    fine = TemplateCurves(pitch, line_step_m=0.1, circle_step_m=0.05)
    ground_samples = np.vstack([p for n, p in pitch.sample_uniform(1.0).items() if pitch.is_on_ground(n)])
    rng = np.random.default_rng(args.seed)
    model = model_reinit_for(args.reinit_model)
    model_accept = TrackingConfig().certain_confidence  # a new shot's camera, as the tracker takes the model's without a search

    def reinitialise(image, det):
        """(result, found by the model): the model's camera when confident, else the weight-free search's."""
        if model is not None:
            found = model(image)
            if found.camera is not None:
                refined = refine_guesses([(found.hypothesis, found.camera)], det, curves)
                if refined.camera is not None and refined.score.jaccard >= model_accept and \
                        plausible_position(refined.camera.position_m, pitch):
                    return refined, True
        return reinit_from_mask(det.marking_mask, det.marking_points_px, (args.width, args.height), pitch,
                                curves=curves, field_mask=det.field_mask), False

    report = {"presets": {}, "resolution": f"{args.width}x{args.height}",
              "reinit_model": None if model is None else str(model.model.path)}
    for preset in args.presets:
        clip = render_clip(preset, args.frames, args.width, args.height, seed=args.seed)
        det_ms, flow_ms, total_ms, within, reinit_ms, outcomes, confidences = [], [], [], [], [], [], []
        reinit_cpu_ms, by_model = [], []
        detectable, marking_counts = [], []
        previous_grey = None
        for frame in tqdm(clip.frames, desc=f"frontend {preset}", unit="frame"):
            truth = frame.camera
            predicted = truth.replace(pan_rad=truth.pan_rad + rng.normal(0, 3.0 / truth.focal_px),
                                      tilt_rad=truth.tilt_rad + rng.normal(0, 3.0 / truth.focal_px))
            t0 = time.perf_counter()
            det = detector.detect(frame.image, PredictedCamera(predicted, 3.0))
            t1 = time.perf_counter()
            grey = prepare(frame.image)
            if previous_grey is not None:
                keep = det.field_mask & ~det.player_mask
                grid_flow(previous_grey, grey, args.width, args.height, prev_camera=predicted, keep_mask=keep)
            t2 = time.perf_counter()
            previous_grey = grey
            det_ms.append(1000 * (t1 - t0))
            flow_ms.append(1000 * (t2 - t1))
            total_ms.append(1000 * (t2 - t0))
            for name, points in det.lines_px.items():
                uv, front = truth.project(fine.samples_w[name])
                within.append(distances_to_polyline(points, uv[front & np.all(np.isfinite(uv), axis=1)]) < 2.0)
            confidences.append(camera_confidence(truth, det.marking_mask, curves, field_mask=det.field_mask))
            if frame.index % args.reinit_every == 0:
                visible = [n for n in frame.lines_norm if n not in frame.occluded_classes and pitch.is_on_ground(n)]
                if len(visible) < 3:
                    continue
                detectable.append(len(det.marking_points_px) >= args.min_marking_points)
                marking_counts.append(int(len(det.marking_points_px)))
                t3, c3 = time.perf_counter(), time.process_time()
                result, from_model = reinitialise(frame.image, det)
                by_model.append(from_model)
                reinit_ms.append(1000 * (time.perf_counter() - t3))
                reinit_cpu_ms.append(1000 * (time.process_time() - c3))
                uv_true, front = truth.project(ground_samples)
                ok = front & truth.in_image(uv_true)
                if result.camera is None:
                    outcomes.append(np.inf)
                    continue
                uv_est, _ = result.camera.project(ground_samples[ok])
                outcomes.append(float(np.nanmedian(np.linalg.norm(uv_est - uv_true[ok], axis=1))))
        if args.images is not None:
            from broadtrack_graph.detect.detector import draw_detections

            args.images.mkdir(parents=True, exist_ok=True)
            picture = draw_detections(clip.frames[-1].image, det, predicted, curves)
            if picture.shape[1] > 1280:  # keep the repository light
                picture = cv2.resize(picture, (picture.shape[1] // 2, picture.shape[0] // 2), interpolation=cv2.INTER_AREA)
            cv2.imwrite(str(args.images / f"frontend_synthetic_{preset}.jpg"), picture)
        within_all = np.concatenate(within) if within else np.zeros(0, bool)
        outcomes = np.asarray(outcomes)
        report["presets"][preset] = {
            "frames": len(clip.frames),
            "detect_ms_median": round(float(np.median(det_ms)), 1),
            "flow_ms_median": round(float(np.median(flow_ms[1:])) if len(flow_ms) > 1 else 0.0, 1),
            "detect_plus_flow_ms_median": round(float(np.median(total_ms[1:])) if len(total_ms) > 1 else 0.0, 1),
            "detect_plus_flow_ms_p90": round(float(np.percentile(total_ms[1:], 90)) if len(total_ms) > 1 else 0.0, 1),
            "named_points": int(len(within_all)),
            "named_within_2px": round(float(within_all.mean()) if len(within_all) else 0.0, 4),
            "true_camera_confidence_median": round(float(np.median(confidences)), 3),
            "reinit_frames": int(len(outcomes)),
            "reinit_success_rate": round(float(np.mean(outcomes < args.success_px)) if len(outcomes) else 0.0, 3),
            "reinit_frames_with_detected_markings": int(np.sum(detectable)),
            "reinit_success_rate_with_detected_markings": round(
                float(np.mean(outcomes[np.asarray(detectable, bool)] < args.success_px)) if any(detectable) else 0.0, 3),
            "reinit_median_error_px": [round(float(v), 2) for v in outcomes],
            "marking_points_at_reinit": marking_counts,
            "reinit_by_model_share": round(float(np.mean(by_model)), 3) if by_model else None,
            "reinit_ms_median": round(float(np.median(reinit_ms)), 1) if reinit_ms else None,
            "reinit_ms_p90": round(float(np.percentile(reinit_ms, 90)), 1) if reinit_ms else None,
            "reinit_cpu_ms_median": round(float(np.median(reinit_cpu_ms)), 1) if reinit_cpu_ms else None,
            "reinit_cpu_ms_p90": round(float(np.percentile(reinit_cpu_ms, 90)), 1) if reinit_cpu_ms else None,
        }
    if args.real_frame is not None:
        from broadtrack_graph.detect.detector import draw_detections

        image = cv2.imread(str(args.real_frame))
        if image is None:
            from broadtrack_graph.errors import InputError

            raise InputError(args.real_frame, "cannot read image")
        t0 = time.perf_counter()
        det = detector.detect(image)
        real = {"size": f"{image.shape[1]}x{image.shape[0]}", "detect_ms": round(1000 * (time.perf_counter() - t0), 1),
                "marking_points": int(len(det.marking_points_px)), "player_boxes": int(len(det.player_boxes_px))}
        t0 = time.perf_counter()
        result = reinit_from_mask(det.marking_mask, det.marking_points_px, (image.shape[1], image.shape[0]), pitch,
                                  curves=curves, field_mask=det.field_mask)
        real["reinit_ms"] = round(1000 * (time.perf_counter() - t0), 1)
        real["reinit_confidence"] = round(float(result.score.jaccard), 3) if result.score else None
        real["reinit_hypothesis"] = result.hypothesis
        if result.camera is not None:
            real["reinit_camera"] = {"focal_px": round(result.camera.focal_px, 1), "pan_deg": round(result.camera.pan_deg, 2),
                                     "tilt_deg": round(result.camera.tilt_deg, 2),
                                     "position_m": [round(float(v), 2) for v in result.camera.position_m]}
        report["real_frame"] = real
        if args.images is not None:
            cv2.imwrite(str(args.images / "frontend_real_frame.jpg"), draw_detections(image, det, result.camera, curves))
    return report
