"""``broadtrack-graph bench placements``: a new shot's first frame from main cameras at other distances and heights.

The main camera's search guesses (:mod:`broadtrack_graph.reinit.positions`) stand at a few places;
real main cameras stand 48-90 m back and 10-25 m up. This suite renders one frame of the ``main``
preset's look from a main camera on the halfway line at each distance and elevation asked
(elevation: the angle below the horizon at which it sees the centre spot) looking at each of three
views (the centre circle, the right and the left penalty area, zoomed as a broadcast does), and asks
the re-initialisation policy for the frame's camera as the tracker does at a new shot (the court model, the
learned field model, then the search in stages, on one process), the frame given again as a still camera's next
frames while the policy waits for them (the court model's camera under its bar waits for the next frames' to
agree; at most ``court_agreement_frames``). Found: a camera at least
``confidence_threshold + reinit_switch_margin`` confident (what a new shot's chain needs to be
trusted) whose projected ground template lies within ``--success-px`` (median) of the truth's.

``--random N`` draws N cameras anywhere around the pitch instead, under random looks (or by the plain renderer,
``--renderer plain``: asked without ``--random``, a one-line error), and asks every single-frame route for each:
:mod:`broadtrack_graph.benchmarks.random_placements`. ``--annotations DIR`` asks the court model for the cameras of
real broadcast frames from their annotated markings instead: :mod:`broadtrack_graph.benchmarks.annotated_views`.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from broadtrack_graph.arguments import float_between, int_at_least
from broadtrack_graph.benchmarks import annotated_views, random_placements
from broadtrack_graph.benchmarks.options import add_reinit_model

HELP = "a new shot's first frame from main cameras at several distances and elevations: is the camera found?"

VIEWS = {  # ground point looked at (metres), horizontal field of view (degrees)
    "centre circle": ((0.0, 0.0, 0.0), 28.0),
    "right penalty area": ((38.0, 0.0, 0.0), 33.0),
    "left penalty area": ((-38.0, 5.0, 0.0), 38.0),
}


def add_arguments(parser) -> None:
    parser.add_argument("--distances", type=float_between(1.0, 500.0), nargs="+", default=[55.0, 68.0, 85.0],
                        help="horizontal distances of the camera from the centre spot, metres (default 55 68 85)")
    parser.add_argument("--elevations", type=float_between(0.0, 80.0), nargs="+",
                        default=[8.0, 10.0, 15.0, 18.0, 22.0, 26.0],
                        help="angles below the horizon at which the camera sees the centre spot, degrees")
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=720)
    parser.add_argument("--seed", type=int, default=3,
                        help="the rendered look (grass, lighting, players); with --random the cameras and looks too")
    parser.add_argument("--success-px", type=float, default=3.0,
                        help="found: median template error below this (with --random: at most this)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_reinit_model(parser)
    random_placements.add_arguments(parser)
    parser.add_argument("--annotations", type=Path, default=None, metavar="DIR",
                        help="instead of rendered frames: the court model on the markings of SoccerNet line "
                             "annotations (NNNNN.json files of real broadcast frames; see docs/BENCHMARKS.md)")
    parser.add_argument("--limit", type=int_at_least(1), default=None, metavar="N",
                        help="with --annotations: at most N frames (from --first K on)")


def run(args) -> dict:
    if args.annotations is not None:
        return annotated_views.run(args)
    if args.random is not None:
        return random_placements.run(args)
    if args.renderer != "synth":
        from broadtrack_graph.errors import InputError

        raise InputError(None, f"--renderer {args.renderer} renders the frames of --random N only")
    from tqdm import tqdm

    from broadtrack_graph.benchmarks.template_error import template_errors_px
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.aim import aim_angles
    from broadtrack_graph.geometry.camera import Camera
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.reinit.cheap import refine_guesses
    from broadtrack_graph.reinit.court import court_reinit
    from broadtrack_graph.reinit.field_model import model_reinit_for
    from broadtrack_graph.reinit.frame import frame_confidence, reinitialise
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.track.reinit_policy import ReinitPolicy

    W, H = args.width, args.height
    pitch = PitchTemplate()
    curves, sampling, detector = fitting_curves(pitch), TemplateSampling(pitch), WeightFreeDetector(pitch)
    config = TrackingConfig(reinit_model=args.reinit_model)
    model = model_reinit_for(config.reinit_model)
    ground = np.vstack([p for name, p in pitch.sample_uniform(1.0).items() if pitch.is_on_ground(name)])
    trusted = config.confidence_threshold + config.reinit_switch_margin
    cells = [(d, e) for d in args.distances for e in args.elevations]
    rows, found = [], 0
    for distance, elevation in tqdm(cells, desc="placements", disable=args.no_progress):
        position = np.array([0.0, distance, -distance * math.tan(math.radians(elevation))])
        for view, (target, fov_deg) in VIEWS.items():
            pan, tilt = aim_angles(position, np.asarray(target))
            truth = Camera(W / 2 / math.tan(math.radians(fov_deg) / 2), 0.0, pan, tilt, 0.0, position, W, H)
            image = render_clip("main", 1, W, H, seed=args.seed, cameras=[truth]).frames[0].image
            policy = ReinitPolicy(config, reinitialise, refine_guesses, frame_confidence, model=model,
                                  court=court_reinit if config.court_reinit else None)
            started = time.perf_counter()
            decision = random_placements.new_shot_decision(policy, detector.detect(image), (W, H), pitch, curves,
                                                           sampling, image)
            seconds = time.perf_counter() - started
            errors = template_errors_px(decision.camera, truth, ground) if decision.camera is not None else []
            error = float(np.median(errors)) if len(errors) else math.inf
            ok = error < args.success_px and (decision.confidence or 0.0) >= trusted
            found += ok
            rows.append({"distance_m": distance, "elevation_deg": elevation, "height_m": round(-position[2], 1),
                         "view": view, "found": bool(ok), "confidence": decision.confidence,
                         "template_error_px": None if math.isinf(error) else round(error, 2),
                         "seconds": round(seconds, 2), "decision": decision.reason})
    return {"frame_size": [W, H], "success_px": args.success_px, "reinit_model": args.reinit_model,
            "found": found, "frames": len(rows), "found_share": round(found / max(len(rows), 1), 3),
            "frames_by_cell": rows}
