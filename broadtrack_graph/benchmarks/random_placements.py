"""``broadtrack-graph bench placements --random N``: a new shot's first frame from cameras anywhere around the pitch.

N cameras are drawn at random (``--seed``) wherever broadcast cameras stand
(:mod:`broadtrack_graph.benchmarks.random_cameras`: the focal point outside the playing area within 110 m
of the centre spot, 5-60 m up, looking at a random point of the pitch, 8-70 deg wide, roll within 2 deg,
a broadcast lens's k1; a view with under a quarter of the image on the pitch is redrawn), and each frame is
rendered with players under a look drawn from ``--looks`` (:mod:`broadtrack_graph.synth.named_looks`:
clean, lower-league, graphics, shadows, blur), or with ``--renderer plain`` by a renderer written apart from the
project's (:mod:`broadtrack_graph.benchmarks.placement_frames`). A frame **counts** when its visible markings
determine a camera (:mod:`broadtrack_graph.geometry.determinable`: two lines of each of the pitch's directions over
60 px each, or a circle or arc 40 % visible and one line); frames that do not count are reported apart.

Each route (``--routes``) is asked for the frame's camera on one core (OpenCV on one
thread; numpy's BLAS too, as the command line sets it), from the weight-free detector's markings (detection is timed
apart; the faint look the court model's second look takes, ``--no-faint-look``: none, is timed with the route):

* ``tracker``: the re-initialisation policy as the tracker asks at a new shot (``ReinitPolicy.decide``: the court
  model, the field model of ``--reinit-model``, then the global search in stages), the frame given again as a still
  camera's next frames while the policy waits for them (at most ``court_agreement_frames``), as ``bench placements``
  does; on a frame the tracker's shot step reads as another view (a close-up, a crowd: ``view``) the court model
  alone, as in the tracker;
* ``search``: the same policy without the court model (the global search at the default positions); none on a frame
  read as another view;
* ``court``: the single-frame court calibrator (``broadtrack_graph.reinit.court.reinit_from_court``) as the tracker
  takes its camera at a new shot: judged by the tracker's confidence (``frame_confidence``) against its bar, and,
  when under it, looked for again on the markings' faint look (timed with it); skipped with a note when it cannot
  be imported;
* ``clip`` (asked only when named): the whole tracker, online, on a short pan from the frame's camera
  (:mod:`.random_clips`), every camera it writes judged against its own frame's truth.

Per route and frame, its camera (written or not: focal point and focal length, ``camera``), and: **written** = a
camera at least ``confidence_threshold + reinit_switch_margin`` confident (what a new shot's chain needs to be
written; the court route: at least the bar the tracker takes its camera at,
``track.reinit_policy.court_accept_at``); **found** = written and its ground template within ``--success-px``
(median) of the truth's; **wrong-written** = written and over :data:`WRONG_PX` off (``twin``: of those, within
``--success-px`` of the truth's half turn about the centre spot, the view the markings cannot tell apart);
**near-written** = written, between the two off the truth or its twin; **none** = not written. Shares are of the
counted frames, overall, by where the camera stands (main stand, far side, behind a goal, corner), by height
(low: under 12 m) and by look (:func:`~.placement_figures.look_group`: the plain renderer's frames sharp or
smeared); seconds per frame as median and 95th percentile (the figures: :mod:`.placement_figures`).
``markings_detected`` counts the frames whose detected markings, read on the true camera's projection, still
determine it (the same rule on the marking map: what detection leaves a route); ``truth_written`` the frames
whose true camera is itself confident enough to be written by the route (no route can write more; the court route's
bar is the one its camera would be taken at with the markings the true camera explains on the map); both on the
markings as found or, for a route that took its second look, on their faint look (``second_look``,
:mod:`.placement_misses`);
``markings_visible`` the frames whose markings, kept only where the
paint changes the rendered image by ``VISIBLE_PAINT_LEVELS`` grey levels or more
(``placement_frames.visible_paint``), still determine the camera (faint, narrow paint rendered small can vanish into
the grass: no detector can find what is not in the image). ``paint_found_by_width``: per look, the true cameras'
template samples (wide enough by their scale to be expected) by the width of their paint across the image
(:data:`PAINT_WIDTH_BINS_PX`, working pixels) and the share of them the detector found
(``reinit.template_reach.found_by_paint_width``). ``found_by_tophat_contrast``: the same by the contrast of each
sample's paint on the detector's top-hat (:data:`~.placement_found.TOPHAT_CONTRAST_BINS`, grey levels; the ridges
are thresholded at ``tophat_threshold`` or the grass texture's level, :mod:`.placement_found`).
``smear_found_by_contrast``: the same on the frames the detector finds
smeared, pooled, by the share of contrast the smear leaves each marking (:data:`SMEARED_CONTRAST_BINS`,
``reinit.template_reach.found_by_smeared_contrast``). ``smear_estimates`` (the plain renderer's frames): its
smears against the detector's reading of them (:func:`~.placement_found.smear_estimates`). ``misses_by_cause``:
each counted frame a route neither finds nor twins, by the first of :data:`~.placement_misses.MISS_CAUSES` that
applies; with ``found_or_twin_of_reachable_pct``, the share found or twin of the frames the route can reach
(detected markings fix the truth, the truth written).
Frame i of a seed is the same in every run (``--first K`` starts at frame K).
"""

from __future__ import annotations

import functools
import math
import sys
import time

import numpy as np

from broadtrack_graph.benchmarks.placement_figures import summarise, summary_table
from broadtrack_graph.benchmarks.placement_found import (
    PAINT_WIDTH_BINS_PX,
    SMEARED_CONTRAST_BINS,
    TOPHAT_CONTRAST_BINS,
    marking_contrast,
)
from broadtrack_graph.benchmarks.placement_frames import RENDERERS, draw_frame, visible_paint
from broadtrack_graph.benchmarks.placement_misses import second_look_reach
from broadtrack_graph.benchmarks.random_clips import CLIP_FRAMES, clip_result
from broadtrack_graph.benchmarks.template_error import median_template_error_px

ROUTES = ("tracker", "search", "court")
CLIP_ROUTE = "clip"
"""The route that tracks a short pan from each camera with the whole tracker (:mod:`.random_clips`); asked only when
named."""
WRONG_PX = 10.0
"""Written cameras further off than this (median template error, pixels) are wrong."""


def add_arguments(parser) -> None:
    from broadtrack_graph.arguments import int_at_least
    from broadtrack_graph.synth.named_looks import LOOK_NAMES

    parser.add_argument("--random", type=int_at_least(1), default=None, metavar="N",
                        help="instead of the halfway-line grid: N cameras drawn anywhere around the pitch under random "
                             "looks, each asked of every route (see docs/BENCHMARKS.md)")
    parser.add_argument("--routes", nargs="+", choices=ROUTES + (CLIP_ROUTE,), default=list(ROUTES),
                        help="with --random: the routes asked (default: the single-frame ones, tracker search "
                             "court; clip: the whole tracker online on a short pan from each camera)")
    parser.add_argument("--clip-frames", type=int_at_least(1), default=CLIP_FRAMES, metavar="K",
                        help=f"with --routes clip: frames of each camera's pan (default {CLIP_FRAMES})")
    parser.add_argument("--looks", nargs="+", choices=LOOK_NAMES, default=list(LOOK_NAMES),
                        help="with --random: the looks drawn from (default: all)")
    parser.add_argument("--renderer", choices=RENDERERS, default="synth",
                        help="with --random: the frames' renderer: the project's own (synth, under --looks) or one "
                             "written apart from it (plain; --looks does not apply; see docs/BENCHMARKS.md)")
    parser.add_argument("--no-faint-look", dest="faint_look", action="store_false",
                        help="with --random: no second look of the court model at the markings' faint look, as the "
                             "tracker takes it at a new shot (detect.faint_lines)")
    parser.add_argument("--first", type=int_at_least(0), default=0, metavar="K",
                        help="with --random: start at frame K of the seed's frames (frame i is the same in every run "
                             "of the seed, size and looks: --random 1 --first i runs one frame of a report again); "
                             "with --annotations: at the K-th annotated frame (by name)")


def outcome(confidence: float | None, error_px: float | None, written_at: float, success_px: float) -> str:
    """found / near / wrong / none for a route's camera (module docstring); error None: no camera."""
    if confidence is None or error_px is None or confidence < written_at:
        return "none"
    if error_px <= success_px:
        return "found"
    return "wrong" if error_px > WRONG_PX else "near"


def twin_outcome(camera_outcome: str, twin_error_px: float | None, success_px: float) -> tuple[str, bool]:
    """(outcome, twin) of a written camera far off the truth but near its twin (the truth's half turn about the
    centre spot, the view the markings cannot tell apart): a twin within ``success_px`` stays ``wrong`` with
    ``twin`` True (counted with the found), one within :data:`WRONG_PX` is ``near`` as a camera as far off the
    truth itself is; any other outcome is returned as it is."""
    if camera_outcome != "wrong" or twin_error_px is None or twin_error_px > WRONG_PX:
        return camera_outcome, False
    return ("wrong", True) if twin_error_px <= success_px else ("near", True)


def _camera_info(drawn) -> dict:
    camera = drawn.camera
    return {"position_m": [round(float(v), 2) for v in camera.position_m], "pan_deg": round(camera.pan_deg, 2),
            "tilt_deg": round(camera.tilt_deg, 2), "roll_deg": round(camera.roll_deg, 2),
            "hfov_deg": round(drawn.hfov_deg, 2), "focal_px": round(camera.focal_px, 1), "k1": round(camera.k1, 4),
            "aim_w": [round(float(v), 2) for v in drawn.aim_w[:2]], "pitch_share": round(drawn.pitch_share, 3)}


def new_shot_decision(policy, detections, frame_size, pitch, curves, sampling, image, faint_look=None,
                      other_view: bool = False):
    """The policy's decision for a new shot's first frame (one frame: its time is a frame's); ``faint_look``: the
    frame's detections with their faint look, for the court model's second look (None: none); ``other_view``: the
    shot step reads the frame as another view (the court model alone looks at it). No camera is known: a court camera
    under its bar that waits for the next frames' to agree waits for a view moved on, which a still frame's repeats
    never show, and no search follows the wait."""
    from broadtrack_graph.types.observations import FrameObservations

    W, H = frame_size
    return policy.decide(FrameObservations(0, W, H), detections, pitch, curves, sampling, image=image,
                         faint_look=faint_look, other_view=other_view)


class _FaintLook:
    """``() -> Detections | None``: a frame's detections with their faint look (None: it adds nothing), looked for
    once."""

    def __init__(self, detector, found) -> None:
        self.detector, self.found, self.detections, self.asked = detector, found, None, False

    def __call__(self):
        if not self.asked:
            looked = self.detector.with_faint_lines(self.found)
            self.detections, self.asked = (self.detector.name(looked) if looked.faint_points_added else None), True
        return self.detections


def _court_with_second_look(court, detections, faint_look, frame_size, pitch, curves, sampling, config):
    """(the court model's result, its camera's confidence or None, the bar it is taken at) as the tracker takes it
    at a new shot: on the markings as found, then, when its camera is under its bar, on their faint look
    (``faint_look``: a :class:`_FaintLook`, or None: no second look), kept when over its own bar."""
    from broadtrack_graph.reinit.frame import frame_confidence
    from broadtrack_graph.track.frame_tries import court_accept_at
    from broadtrack_graph.types.observations import FrameObservations

    def tried(on):
        result = court(on.marking_mask, on.marking_points_px, frame_size, pitch=pitch, curves=curves,
                       field_mask=on.field_mask, player_mask=on.player_mask, motion_blur=on.motion_blur)
        confidence = None if result.camera is None else frame_confidence(
            result.camera, FrameObservations(0, *frame_size), on, curves, sampling)
        return result, confidence, court_accept_at(config, result)

    first = tried(detections)
    looked = None if (first[1] or 0.0) >= first[2] or faint_look is None else faint_look()
    if looked is None:
        return first
    again = tried(looked)
    return again if (again[1] or 0.0) >= again[2] else first


def shot_step_view(image, detector):
    """The tracker's shot step on a frame as a new shot's first (:class:`~broadtrack_graph.track.shot_stream.ShotStream`
    with a run's settings): {"kind", "reason"} of its view; on a frame it reads as another view the court model alone
    looks for a camera."""
    from broadtrack_graph.track.inputs import FrameInput
    from broadtrack_graph.track.shot_stream import ShotStream

    shot = next(iter(ShotStream.for_run([FrameInput(0, "000001", 0.0, image=image)], True, False, detector))).shot
    return {"kind": shot.kind, "reason": shot.reason, "other_view": bool(shot.is_other_view)}


def _court_route():
    """(reinit_from_court, None), or (None, a one-line note) when it cannot be imported."""
    try:
        from broadtrack_graph.reinit.court import reinit_from_court
    except ImportError as error:
        return None, f"route court skipped: broadtrack_graph.reinit.court.reinit_from_court not importable ({error})"
    return reinit_from_court, None


def run(args) -> dict:
    """The suite's report (module docstring); a short table goes to stderr."""
    import cv2
    from tqdm import tqdm

    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.determinable import MIN_CURVE_SHARE, MIN_LINE_PX, determinability
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.reinit.cheap import refine_guesses
    from broadtrack_graph.reinit.field_model import model_reinit_for
    from broadtrack_graph.reinit.frame import frame_confidence, reinitialise
    from broadtrack_graph.reinit.scoring import ReinitResult
    from broadtrack_graph.reinit.template_reach import (
        found_by_map_value,
        found_by_paint_width,
        found_by_smeared_contrast,
    )
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.track.frame_tries import court_accept_at
    from broadtrack_graph.track.reinit_policy import ReinitPolicy
    from broadtrack_graph.types.observations import FrameObservations

    W, H = args.width, args.height
    pitch = PitchTemplate()
    faint_look = getattr(args, "faint_look", True)
    curves, sampling = fitting_curves(pitch), TemplateSampling(pitch)
    detector = WeightFreeDetector(pitch)
    config = TrackingConfig(reinit_model=args.reinit_model)
    written_at = config.confidence_threshold + config.reinit_switch_margin
    # The court model's camera is taken by the tracker only from its own bar (court_accept_at: by the markings it
    # explains); the report states the bar without a grid of lines.
    written_at_by_route = {"tracker": written_at, "search": written_at, CLIP_ROUTE: written_at,
                           "court": max(written_at, config.court_accept_confidence)}

    def bar_of(route: str, camera, seen) -> float:
        """The confidence ``route`` writes ``camera`` at, the markings it explains counted in ``seen``."""
        return court_accept_at(config, ReinitResult(camera, None, "", explained=seen)) if route == "court" \
            else written_at_by_route[route]

    clip_config = TrackingConfig(mode="online", reinit_model=args.reinit_model)
    ground = np.vstack([p for name, p in pitch.sample_uniform(1.0).items() if pitch.is_on_ground(name)])
    routes, skipped = list(dict.fromkeys(args.routes)), {}
    model = model_reinit_for(config.reinit_model) if {"tracker", "search"} & set(routes) else None
    court = None
    tracker_court = None  # the tracker's court model, imported only when that route is asked
    if "tracker" in routes and config.court_reinit:
        from broadtrack_graph.reinit.court import court_reinit as tracker_court
    if "court" in routes:
        court, note = _court_route()
        if court is None:
            routes.remove("court")
            skipped["court"] = note
            print(note, file=sys.stderr)
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    rows = []
    try:
        frames = range(args.first, args.first + args.random)
        for index in tqdm(frames, desc="placements --random", unit="frame", disable=args.no_progress):
            frame = draw_frame(args.seed, index, W, H, args.looks, args.renderer)
            drawn, image, truth = frame["drawn"], frame["image"], frame["drawn"].camera
            started = time.perf_counter()
            found = detector.find_markings(image)
            detections = detector.name(found)
            detect_s = time.perf_counter() - started
            seen = determinability(truth, pitch)
            view = shot_step_view(image, detector)

            def confidence_of(camera):
                return frame_confidence(camera, FrameObservations(0, W, H), detections, curves, sampling)

            truth_confidence = confidence_of(truth)
            found_markings = determinability(truth, pitch, explained_by=detections.marking_mask)
            paint_samples, paint_found = found_by_paint_width(
                truth, detections.marking_mask, np.array(PAINT_WIDTH_BINS_PX), curves, field_mask=detections.field_mask,
                player_mask=detections.player_mask)
            contrast_samples, contrast_found = found_by_map_value(
                truth, detections.marking_mask, marking_contrast(detector, image), np.array(TOPHAT_CONTRAST_BINS),
                curves, field_mask=detections.field_mask, player_mask=detections.player_mask)
            shown_markings = determinability(truth, pitch, explained_by=visible_paint(frame)) if seen.determinable \
                else seen
            row = {"frame": index, "camera": _camera_info(drawn), "look": frame["look_name"], "class": drawn.stand,
                   "height_m": round(drawn.height_m, 1), "low": drawn.low, "determinable": seen.determinable,
                   "markings": {"x_lines": seen.x_lines, "y_lines": seen.y_lines, "curves": list(seen.curves)},
                   "truth_confidence": _round(truth_confidence, 3),
                   "truth_written": (truth_confidence or 0.0) >= written_at,
                   "markings_detected": found_markings.determinable,
                   "markings_visible": shown_markings.determinable,
                   "paint_found": {"samples": paint_samples.tolist(), "found": paint_found.tolist()},
                   "contrast_found": {"samples": contrast_samples.tolist(), "found": contrast_found.tolist()},
                   "render_s": round(frame["render_s"], 3), "detect_s": round(detect_s, 3), "view": view,
                   "routes": {}}
            if detections.motion_blur is not None:
                smear_samples, smear_found = found_by_smeared_contrast(
                    truth, detections.marking_mask, detections.motion_blur, np.array(SMEARED_CONTRAST_BINS), curves,
                    field_mask=detections.field_mask, player_mask=detections.player_mask)
                row["smear_found"] = {"samples": smear_samples.tolist(), "found": smear_found.tolist()}
                row["smear"] = {"length_px": round(detections.motion_blur.length_px, 2),
                                "angle_deg": round(detections.motion_blur.angle_deg, 1)}
            if args.renderer == "plain":  # its look drawn per frame: blur, noise, compression (synth.plain)
                row["plain_look"] = {k: np.round(v, 3).tolist() for k, v in vars(frame["look"]).items() if k != "seed"}
            for route in routes:
                if route == CLIP_ROUTE:
                    row["routes"][route] = {**clip_result(args.seed, index, frame, args.clip_frames, clip_config,
                                                          ground, args.success_px, WRONG_PX),
                                            "truth_written": (truth_confidence or 0.0) >= written_at}
                    continue
                # The markings' faint look, taken (and timed) within the route that asks for it, as the tracker does.
                looked = _FaintLook(detector, found) if faint_look else None
                if route == "search" and view["other_view"]:
                    # The tracker's shot step reads the frame as another view: the search does not look at it.
                    camera, confidence, seconds, reason = None, None, 0.0, f"other view ({view['reason']})"
                elif route in ("tracker", "search"):
                    # A frame read as another view: the tracker's court model alone looks at it.
                    policy = ReinitPolicy(config, reinitialise, refine_guesses, frame_confidence,
                                          model=model, court=tracker_court if route == "tracker" else None)
                    started = time.perf_counter()
                    decision = new_shot_decision(policy, detections, (W, H), pitch, curves, sampling, image,
                                                 looked, other_view=view["other_view"])
                    seconds = time.perf_counter() - started
                    camera, confidence, reason = decision.camera, decision.confidence, decision.reason
                else:
                    started = time.perf_counter()
                    result, confidence, bar = _court_with_second_look(court, detections, looked, (W, H), pitch,
                                                                      curves, sampling, config)
                    seconds = time.perf_counter() - started
                    camera, reason = result.camera, result.reason
                error = median_template_error_px(camera, truth, ground)
                bar = bar if route == "court" else written_at_by_route[route]
                truth_bar = bar_of(route, truth, found_markings)
                result_row = {"outcome": outcome(confidence, error, bar, args.success_px),
                              "confidence": _round(confidence, 3), "error_px": _round(error, 2),
                              "seconds": round(seconds, 3), "reason": reason,
                              "truth_written": (truth_confidence or 0.0) >= truth_bar,
                              "camera": _camera_summary(camera)}
                if camera is not None and error is not None and error > args.success_px:
                    from broadtrack_graph.reinit.court_fit import twin_camera  # only here: the route may be skipped

                    twin_error = median_template_error_px(camera, twin_camera(truth), ground)
                    result_row["twin_error_px"] = _round(twin_error, 2)  # written or not
                    if result_row["outcome"] == "wrong":
                        result_row["outcome"], result_row["twin"] = twin_outcome("wrong", twin_error, args.success_px)
                # the truth or its twin, not written: the route's bar, not its camera, missed it
                result_row["right_under_bar"] = result_row["outcome"] == "none" and camera is not None and any(
                    e is not None and e <= args.success_px for e in (error, result_row.get("twin_error_px")))
                if looked is not None and looked.detections is not None:  # the second look taken, and it added paint
                    result_row["second_look"] = second_look_reach(truth, looked.detections, (W, H), pitch, curves,
                                                                  sampling, functools.partial(bar_of, route, truth))
                row["routes"][route] = result_row
            rows.append(row)
    finally:
        cv2.setNumThreads(threads)
    looks = ["plain"] if args.renderer == "plain" else list(args.looks)
    report = {"mode": "random", "frames": len(rows), "frame_size": [W, H], "seed": args.seed, "renderer": args.renderer,
              "faint_look": faint_look,
              "looks": looks,
              "routes": routes, "skipped_routes": skipped, "reinit_model": args.reinit_model,
              "written_confidence": {route: round(written_at_by_route[route], 3) for route in routes},
              "success_px": args.success_px, "wrong_px": WRONG_PX,
              "rule": {"min_line_px": MIN_LINE_PX, "min_curve_share": MIN_CURVE_SHARE},
              **summarise(rows, routes, W), "frames_by_index": rows}
    print(summary_table(report), file=sys.stderr)
    return report


def _camera_summary(camera) -> dict | None:
    """A route's camera, written or not, as a row keeps it: its focal point (metres, pitch frame, z down) and focal
    length (pixels of the frame); None without one."""
    if camera is None:
        return None
    return {"position_m": [round(float(v), 2) for v in camera.position_m], "focal_px": round(float(camera.focal_px), 1)}


def _round(value, digits: int):
    """value rounded; None for None and for a non-finite value (JSON has no inf: an error of inf is a camera that
    puts every marking behind it, and its outcome is decided before rounding)."""
    return None if value is None or not math.isfinite(float(value)) else round(float(value), digits)
