"""The ``clip`` route of ``bench placements --random N``: the whole tracker, online, on a short slow pan from each
random camera, from nothing, as a user tracks a new shot.

Frame 0 of a camera's clip is the single-frame bench's frame (the same camera, look and image); each next frame pans
the camera on by a rate drawn per camera (:data:`PAN_PX_PER_FRAME`, in pixels at the image centre, either way), the
look held: the players stay where frame 0 put them on the pitch, each frame's sensor noise is drawn afresh, the
synthetic renderer's graphics stay where the image has them (an overlay) and the plain renderer's crowd stays where
it stands in the world (its blocks where frame 0 saw them). The frames go to ``track`` (``track_input``, online, as a
folder of images) and every camera it writes is judged against its frame's truth as the single-frame routes' are
(:func:`judged_clip`).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

CLIP_FRAMES = 5
"""Frames of each camera's clip (``--clip-frames``)."""
PAN_PX_PER_FRAME = (1.0, 4.0)
"""Range of the pan's speed, pixels a frame at the image centre (drawn uniformly, either way)."""
CLIP_STREAM = 3
"""The part of a frame's random stream (``placement_frames.RANDOM_STREAM``) that draws its clip's pan."""


def pan_cameras(camera, frames: int, rng: np.random.Generator) -> list:
    """``frames`` cameras: ``camera`` and the same camera panned on by a rate drawn from ``rng`` each frame."""
    speed = rng.uniform(*PAN_PX_PER_FRAME) * rng.choice([-1.0, 1.0])
    step_rad = speed / camera.focal_px
    return [camera.replace(pan_rad=camera.pan_rad + k * step_rad) for k in range(frames)]


def clip_images(frame: dict, cameras: list) -> list[np.ndarray]:
    """The images of a frame's clip (``placement_frames.draw_frame``'s frame; ``cameras`` from :func:`pan_cameras`):
    frame 0's image and each next camera rendered under the same look (module docstring)."""
    images = [frame["image"]]
    if frame["renderer"] == "plain":
        from broadtrack_graph.synth.plain import players_centre_m, render_plain

        around = players_centre_m(cameras[0])
        images += [render_plain(camera, frame["look"], frame=k, players_around_m=around, crowd_camera=cameras[0])
                   for k, camera in enumerate(cameras[1:], start=1)]
        return images
    from broadtrack_graph.synth.field_samples import render_look
    from broadtrack_graph.synth.named_looks import named_look

    settings = named_look(frame["look_name"])
    images += [render_look(camera, frame["players"], frame["look"], settings, frame=k).image
               for k, camera in enumerate(cameras[1:], start=1)]
    return images


def track_clip(images: list[np.ndarray], config) -> tuple[list, float]:
    """(records, seconds): ``track``'s records of the images as a clip (online, from nothing), and its wall time.

    The frames are written losslessly to a temporary folder the run is read from and written to."""
    import cv2

    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.io.run_folder import RunFolder

    with tempfile.TemporaryDirectory(prefix="placement-clip-") as folder:
        frames = Path(folder) / "frames"
        frames.mkdir()
        for k, image in enumerate(images):
            cv2.imwrite(str(frames / f"{k + 1:06d}.png"), image)
        started = time.perf_counter()
        track_input(frames, Path(folder) / "run", config, progress=False)
        seconds = time.perf_counter() - started
        records = RunFolder(Path(folder) / "run").read_track().records
    return records, seconds


def judged_clip(records: list, cameras: list, ground_w: np.ndarray, success_px: float, wrong_px: float) -> dict:
    """A clip's written cameras judged against their frames' truths (``cameras``) and the truths' twins (the half
    turn about the centre spot): {"outcome", "twin", "error_px" (the worst written camera's, against the truth or
    its twin, whichever is nearer), "confidence" (the first written camera's), "first_written" (its frame; None),
    "written", "right", "near", "wrong"}. The outcome: ``wrong`` when a written camera is over ``wrong_px`` off both,
    else ``near`` when one is over ``success_px``, else ``found`` (or ``wrong`` with ``twin`` when every written
    camera is the twin's), else ``none``."""
    from broadtrack_graph.benchmarks.template_error import median_template_error_px
    from broadtrack_graph.reinit.court_fit import twin_camera

    errors, twins, first, confidence = [], [], None, None
    for record in records:
        if record.camera is None or not 0 <= record.frame_index < len(cameras):
            continue
        truth = cameras[record.frame_index]
        median_truth, median_twin = (np.inf if e is None else e for e in (
            median_template_error_px(record.camera, camera, ground_w) for camera in (truth, twin_camera(truth))))
        errors.append(min(median_truth, median_twin))
        twins.append(median_twin < median_truth)
        if first is None:
            first, confidence = record.frame_index, record.confidence
    errors_a = np.asarray(errors, float)
    counts = {"written": len(errors), "right": int(np.sum(errors_a <= success_px)),
              "near": int(np.sum((errors_a > success_px) & (errors_a <= wrong_px))),
              "wrong": int(np.sum(errors_a > wrong_px))}
    twin = False
    if not errors:
        outcome = "none"
    elif counts["wrong"]:
        outcome = "wrong"
    elif counts["near"]:
        outcome = "near"
    else:
        twin = all(twins)
        outcome = "wrong" if twin else "found"
    worst = float(errors_a.max()) if errors else None
    return {"outcome": outcome, "twin": twin, "error_px": worst, "confidence": confidence, "first_written": first,
            **counts}


def clip_result(seed: int, index: int, frame: dict, frames: int, config, ground_w: np.ndarray, success_px: float,
                wrong_px: float) -> dict:
    """The ``clip`` route's result on frame ``index`` of a seed (``frame``: ``placement_frames.draw_frame``'s): its
    pan of ``frames`` frames tracked with ``config`` and judged (:func:`judged_clip`), with ``seconds`` the run's
    wall time a frame, ``frames``, the first ``reason`` a frame went without a camera, and ``right_under_bar`` False
    (the tracker's bar is its own)."""
    from broadtrack_graph.benchmarks.placement_frames import RANDOM_STREAM

    rng = np.random.default_rng([seed, index, RANDOM_STREAM, CLIP_STREAM])
    cameras = pan_cameras(frame["drawn"].camera, frames, rng)
    records, wall_s = track_clip(clip_images(frame, cameras), config)
    judged = judged_clip(records, cameras, ground_w, success_px, wrong_px)
    rounded = {key: None if judged[key] is None or not np.isfinite(judged[key]) else round(float(judged[key]), digits)
               for key, digits in (("error_px", 2), ("confidence", 3))}
    return {**judged, **rounded, "seconds": round(wall_s / frames, 3), "frames": frames,
            "reason": next((r.reason for r in records if r.camera is None and r.reason), ""),
            "right_under_bar": False}
