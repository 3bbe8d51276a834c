"""Benchmark suite "render": time per synthetic frame on one core (ray casting, ground truth, JPEG).

Both wall-clock and process CPU time are reported: on a shared machine the wall time
includes waiting for a core, the CPU time (one OpenCV thread) does not.
"""

from __future__ import annotations

import time

import cv2
import numpy as np

from broadtrack_graph.synth.annotate import Annotator
from broadtrack_graph.synth.clip import clip_scene
from broadtrack_graph.synth.presets import PRESETS
from broadtrack_graph.synth.render import Renderer
from broadtrack_graph.synth.texture import build_textures

HELP = "time the synthetic renderer per frame on one core (default 1920x1080)"


def add_arguments(parser) -> None:
    parser.add_argument("--frames", type=int, default=25, help="frames timed per preset (default 25)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--presets", nargs="+", default=["main", "hard"], choices=sorted(PRESETS))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1: one core)")


def _stats(values) -> dict:
    values = np.asarray(values, dtype=float)
    return {"min_s": round(float(values.min()), 4), "mean_s": round(float(values.mean()), 4),
            "median_s": round(float(np.median(values)), 4),
            "p90_s": round(float(np.percentile(values, 90)), 4), "max_s": round(float(values.max()), 4)}


def run(args) -> dict:
    cv2.setNumThreads(int(args.threads))
    started = time.perf_counter()
    texel = 0.025 if args.width >= 1280 else 0.05
    build_textures.cache_clear()
    build_textures(texel, int(args.seed) % 4)
    texture_s = time.perf_counter() - started
    report = {"width_px": args.width, "height_px": args.height, "opencv_threads": cv2.getNumThreads(),
              "texture_build_s": round(texture_s, 3), "presets": {}}
    annotator = Annotator()
    for preset in args.presets:
        cams, _, _, players = clip_scene(preset, args.frames, args.width, args.height, args.seed)
        renderer = Renderer(args.width, args.height, seed=args.seed)
        render_s, truth_s, jpeg_s, total_s, cpu_render_s, cpu_total_s = [], [], [], [], [], []
        previous = None
        for index, camera in enumerate(cams):
            c0, t0 = time.process_time(), time.perf_counter()
            frame = renderer.render(camera, players, index, previous, want_class_ids=True)
            c1, t1 = time.process_time(), time.perf_counter()
            annotator.annotate(camera, frame.labels, frame.class_ids, want_mask=True)
            t2 = time.perf_counter()
            cv2.imencode(".jpg", frame.image, [cv2.IMWRITE_JPEG_QUALITY, 90])
            c3, t3 = time.process_time(), time.perf_counter()
            render_s.append(t1 - t0)
            truth_s.append(t2 - t1)
            jpeg_s.append(t3 - t2)
            total_s.append(t3 - t0)
            cpu_render_s.append(c1 - c0)
            cpu_total_s.append(c3 - c0)
            previous = camera
        report["presets"][preset] = {
            "frames": len(cams),
            "render_image_cpu": _stats(cpu_render_s), "total_per_frame_cpu": _stats(cpu_total_s),
            "render_image_wall": _stats(render_s), "ground_truth_wall": _stats(truth_s),
            "jpeg_encode_wall": _stats(jpeg_s), "total_per_frame_wall": _stats(total_s),
            "hd_750_frames_estimate_min": round(750 * float(np.mean(total_s)) / 60.0, 2),
        }
    return report
