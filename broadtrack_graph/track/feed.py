"""The frames fed to a tracking run: decoded, and prepared ahead in the decoding thread, while the run tracks.

:func:`run_loop` feeds a :class:`~broadtrack_graph.track.frame_loop.TrackingRun` the frames of an iterable,
prefetched by a background thread (:func:`~broadtrack_graph.io.prefetch.prefetch`). In that thread, each frame gets
what needs no camera, so it overlaps the tracking of the frames before it: whether it repeats the previous frame's
image (:mod:`broadtrack_graph.shots.repeats`), the flow pyramid, the camera-free half of the weight-free detector
(``find_markings``: grass, field, players, the marking map), and while the thread is far enough ahead, the optical
flow from the previous frame. The result is the same as doing it all in the tracking
thread (``BROADTRACK_PREFETCH=0`` does). The progress bar and an interruption (Ctrl-C, SIGTERM) are handled here.
Both threads call OpenCV: a run is given :func:`default_opencv_threads` threads of OpenCV's own (``track
--threads``; ``bench real`` times its runs with the same).
"""

from __future__ import annotations

import os

from tqdm import tqdm

from broadtrack_graph.detect.flow import flow_candidates, flow_keep_mask, prepare
from broadtrack_graph.detect.graphics import mask_graphics
from broadtrack_graph.io.prefetch import prefetch
from broadtrack_graph.shots.repeats import repeat_grey, repeats
from broadtrack_graph.track.frame_loop import TrackingRun
from broadtrack_graph.track.inputs import FrameInput

FLOW_AHEAD_MIN_LEAD = 2
"""The decoding thread tracks a frame's optical flow ahead only while it is at least this many frames ahead of the
loop (it has time to spare: the loop is searching, say); else the loop does (the decoding thread is the slower)."""


def default_opencv_threads() -> int:
    """OpenCV's threads for a run: the cores its tracking and decoding threads leave, at least 1.

    Both threads call OpenCV, and each of the search's workers runs it on one thread: a pool on top of them only
    oversubscribes the cores. On 2 cores, the splice of docs/BENCHMARKS.md tracked with OpenCV's default pool (a
    thread per core) spent twice the time in the kernel for the same cameras.
    """
    return max(1, (os.cpu_count() or 1) - 2)


def run_loop(run: TrackingRun, frames, total: int | None = None, label: str = "") -> None:
    """Feed frames to a run (prefetching them in a background thread), with a progress bar unless the run's context
    hides it (``total``: the frames expected, for the bar; ``label``: the bar's)."""
    flow_config, progress = run.config.flow, run.context.progress
    find_markings = getattr(run.detector, "find_markings", None)  # a detector whose first half needs no camera
    previous: list = [None, None]  # the last frame prepared ahead: its flow frame and keep mask (or Nones)
    last_grey: list = [None]  # the last image's grey for the repeat test (None: no image, or no test)
    count = {"made": 0, "taken": 0}  # frames prepared ahead, and taken by the loop

    def prepare_ahead(frame: FrameInput) -> FrameInput:
        # In the background thread: what needs no camera, so it overlaps the tracking of the previous frames.
        count["made"] += 1
        if frame.image is None:
            previous[:] = [None, None]
            last_grey[0] = None
            return frame
        grey = None
        if run.config.repeats.max_changed_share > 0:
            grey = repeat_grey(frame.image, run.config.repeats, frame.working_bgr)
            frame.repeats_previous = repeats(last_grey[0], grey, run.config.repeats)
            if frame.repeats_previous:
                # It carries the estimate of the frame it repeats, whose image the next frames are compared with (a
                # slow drift adds up) and whose flow frame the next frame's flow starts from: nothing to prepare.
                return frame
            last_grey[0] = grey
        if run.config.use_flow and frame.flow_frame is None:
            frame.flow_frame = prepare(frame.image, flow_config, grey, frame.working_bgr)  # the repeat test's grey
        other_view = frame.shot is not None and frame.shot.is_other_view
        keep = None
        if find_markings is not None and frame.observations is None and frame.markings is None and not other_view:
            try:
                frame.markings = find_markings(frame.image, frame.working_bgr)  # the working image ShotStream made
                keep = flow_keep_mask(mask_graphics(frame.markings.unnamed, frame.graphics_mask))
            except ValueError:
                pass  # a bad image: the loop's own detection reports it on this frame
        frame.working_bgr = None  # used: not kept in the queue of frames ready
        lead = count["made"] - 1 - count["taken"]  # frames ready before this one: how far ahead this thread is
        if frame.flow_frame is not None and previous[0] is not None and keep is not None and \
                lead >= FLOW_AHEAD_MIN_LEAD:
            # The flow from the previous frame short of the previous camera's pitch check (the loop's, when it knows
            # that camera): the loop's own matches (detect.flow.flow_candidates), computed here when there is time.
            frame.flow_ahead = flow_candidates(previous[0], frame.flow_frame, frame.image.shape[1],
                                               frame.image.shape[0], previous[1], flow_config)
        previous[:] = [frame.flow_frame, keep] if keep is not None else [None, None]
        return frame

    bar = tqdm(prefetch(frames, prepare_ahead), total=total, desc=f"track {label}", unit="frame", disable=not progress)
    try:
        for frame in bar:
            count["taken"] += 1
            run.process(frame)
            if progress:
                bar.set_postfix(run.writer.progress_postfix() if hasattr(run.writer, "progress_postfix") else {},
                                refresh=False)
    except KeyboardInterrupt:
        # Ctrl-C or SIGTERM (the command line turns it into KeyboardInterrupt): the summary tells the truth.
        if hasattr(run.writer, "interrupt"):
            run.writer.interrupt()
        raise
    finally:
        bar.close()
