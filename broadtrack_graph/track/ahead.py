"""What a frame gets before the tracking loop takes it: its shot, and the steps that need no camera.

Each image frame gets, in order, where it is decoded: its shot and the static graphics mask
(:class:`~broadtrack_graph.track.shot_stream.ShotStream`), whether it repeats the previous frame's image
(:mod:`broadtrack_graph.shots.repeats`), the flow pyramid, the camera-free half of the weight-free detector
(``find_markings``: grass, field, players, the marking map; the players' legs are left to the side that first
reads them, :mod:`~broadtrack_graph.detect.found_markings`), and while this side is far enough ahead of the loop,
the optical flow from the previous frame (:class:`FramesAhead`). The result is the same as doing it all in the
tracking loop.

Two places do it: a background thread of the tracking process (:func:`~broadtrack_graph.io.prefetch.prefetch`), or
a process of its own (:class:`FramesInProcess`), which reopens the input from its path (:class:`FramesRecipe`) and
hands the prepared frames over through shared memory (:class:`~broadtrack_graph.io.process_prefetch.ProcessPrefetch`).
A thread shares the interpreter's lock with the tracking thread; a process does not, but takes about half a second
to start (it imports what finding the markings needs, neither GTSAM nor scipy): :func:`feed_in_process` says which a
run takes.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
import pickle
from dataclasses import dataclass
from typing import Callable, Iterator

import cv2
import numpy as np

from broadtrack_graph.detect.flow import flow_candidates, flow_keep_mask, prepare
from broadtrack_graph.detect.graphics import mask_graphics
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.prefetch import PREFETCH_ENV
from broadtrack_graph.io.process_prefetch import ProcessPrefetch
from broadtrack_graph.shots.repeats import repeat_grey, repeats
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import FrameInput, frames_from_source
from broadtrack_graph.track.shot_stream import ShotStream

FLOW_AHEAD_MIN_LEAD = 2
"""The preparing side tracks a frame's optical flow ahead only while it is at least this many frames ahead of the
loop (it has time to spare: the loop is searching, say); else the loop does (the preparing side is the slower)."""

PROCESS_MIN_FRAMES = 100
"""A process of its own prepares the frames of an input of at least this many frames (:func:`feed_in_process`): it
takes about half a second to start, which a shorter input does not win back."""

PROCESS_DEPTH = 4
"""Frames the preparing process may hold ready (shared-memory slots of
:class:`~broadtrack_graph.io.process_prefetch.ProcessPrefetch`)."""

MAPS_BYTES = 12 * 1024 * 1024
"""Room in a slot beside the frame's image for what is found ahead: the detector's maps at its working width (960 px
whatever the frame's size) with the colour working image its faint look needs, the flow's grey image, the graphics
mask (about 7 MB in all for a 16:9 frame)."""


def slot_bytes(width_px: int, height_px: int) -> int:
    """The size of a shared-memory slot for a frame of this size (bytes): its BGR image and :data:`MAPS_BYTES`."""
    return 3 * int(width_px) * int(height_px) + MAPS_BYTES


class FramesAhead:
    """The camera-free steps of each frame, in order (see the module docstring); call it on every frame.

    Args:
        config: the tracking options (flow, repeats).
        find_markings: the detector's camera-free half (``image, working_bgr -> FoundMarkings``), or None.
        taken: how many frames the loop has taken so far (how far ahead this side is decides the flow ahead).
    """

    def __init__(self, config: TrackingConfig, find_markings: Callable | None, taken: Callable[[], int]) -> None:
        self.config = config
        self.find_markings = find_markings
        self.taken = taken
        self.made = 0  # frames prepared so far
        # the last frame prepared: its flow frame and (its markings found, its graphics mask), or Nones
        self.previous: tuple = (None, None)
        self.last_grey = None  # the last image's grey for the repeat test (None: no image, or no test)

    def __call__(self, frame: FrameInput) -> FrameInput:
        self.made += 1
        if frame.image is None:
            self.previous, self.last_grey = (None, None), None
            return frame
        config = self.config
        grey = None
        if config.repeats.max_changed_share > 0:
            grey = repeat_grey(frame.image, config.repeats, frame.working_bgr)
            frame.repeats_previous = repeats(self.last_grey, grey, config.repeats)
            if frame.repeats_previous:
                # It carries the estimate of the frame it repeats, whose image the next frames are compared with (a
                # slow drift adds up) and whose flow frame the next frame's flow starts from: nothing to prepare.
                return frame
            self.last_grey = grey
        if config.use_flow and frame.flow_frame is None:
            frame.flow_frame = prepare(frame.image, config.flow, grey, frame.working_bgr)  # the repeat test's grey
        found = None
        if self.find_markings is not None and frame.observations is None and frame.markings is None \
                and not frame.shows_other_view:
            # A frame the shot step reads as another view keeps its pixels instead: the loop finds its markings only
            # on the frames the court model looks at (track.reinit_policy).
            try:
                found = frame.markings = self.find_markings(frame.image, frame.working_bgr)  # ShotStream's image
            except ValueError:
                pass  # a bad image: the loop's own detection reports it on this frame
        frame.working_bgr = None  # used: not kept in the queue of frames ready
        lead = self.made - 1 - self.taken()  # frames ready before this one: how far ahead this side is
        if frame.flow_frame is not None and self.previous[0] is not None and found is not None and \
                lead >= FLOW_AHEAD_MIN_LEAD:
            # The flow from the previous frame short of the previous camera's pitch check (the loop's, when it knows
            # that camera): the loop's own matches (detect.flow.flow_candidates), computed here when there is time.
            frame.flow_ahead = flow_candidates(self.previous[0], frame.flow_frame, frame.image.shape[1],
                                               frame.image.shape[0], _keep_mask(*self.previous[1]), config.flow)
        if found is not None and lead + 1 >= FLOW_AHEAD_MIN_LEAD:
            # Far enough ahead to track the next frame's flow here too: its keep mask needs this frame's players'
            # legs, found now (then sent with it). Behind, the tracking side finds them (detect.found_markings).
            found.find_legs()
        # The previous frame's keep mask is made only when a flow ahead needs it.
        self.previous = (frame.flow_frame, (found, frame.graphics_mask)) if found is not None else (None, None)
        return frame


def _keep_mask(found, graphics_mask) -> np.ndarray | None:
    """Where a frame's flow may start (:func:`~broadtrack_graph.detect.flow.flow_keep_mask`) from its markings found
    ahead, off its graphics."""
    return flow_keep_mask(mask_graphics(found.unnamed, graphics_mask))


@dataclass(frozen=True)
class FramesRecipe:
    """An image input as a path and a window: what opens its frames again, in another process.

    path: the video file, image folder or game-state sequence (:func:`~broadtrack_graph.io.frames.open_frames`);
    start, end: the window of frame indices (end exclusive); fps: the source's frame rate.
    """

    path: str
    start: int
    end: int
    fps: float

    @classmethod
    def of(cls, source) -> "FramesRecipe | None":
        """The recipe of an open frame source (None for frames with no path: in memory)."""
        if getattr(source, "path", None) is None:
            return None
        return cls(str(source.path), int(source.start), int(source.end), float(source.fps))


def feed_in_process(recipe: FramesRecipe | None, detector, total: int | None, frame_size: tuple[int, int]) -> bool:
    """Whether a run prepares its frames in a process of its own rather than a thread.

    Yes for an input that can be reopened (``recipe``), with a detector that finds its markings ahead and can be
    sent to another process, of at least :data:`PROCESS_MIN_FRAMES` frames, on a machine of two cores or more, in a
    process that is not itself a worker of a pool (a pool fills the cores already), with room for twice the slots of
    frames of ``frame_size`` (w, h) in the shared memory (a container's is often small), unless the environment variable
    :data:`~broadtrack_graph.io.prefetch.PREFETCH_ENV` says "thread" or "0" (no background work: ``track-many``
    fills every core with workers).
    """
    if os.environ.get(PREFETCH_ENV) in ("0", "thread") or recipe is None or detector is None:
        return False
    if multiprocessing.parent_process() is not None:
        return False
    if getattr(detector, "find_markings", None) is None or (os.cpu_count() or 1) < 2:
        return False
    if total is None or total < PROCESS_MIN_FRAMES:
        return False
    try:
        pickle.dumps(detector)
    except Exception:  # e.g. a detector holding model sessions: a thread prepares its frames
        return False
    return shared_memory_free() >= 2 * PROCESS_DEPTH * slot_bytes(*frame_size)


def shared_memory_free(path: str = "/dev/shm") -> int:
    """Bytes free in the shared memory's file system (0 when it cannot be read: no process then)."""
    try:
        stats = os.statvfs(path)
    except OSError:
        return 0
    return stats.f_bavail * stats.f_frsize


class FramesInProcess:
    """The input's frames, shot and prepared ahead (:class:`FramesAhead`) in a process of its own.

    Iterate it once; :attr:`shots` are the shots found (once the iteration has ended) and :attr:`detects_shots`
    whether shots were looked for at all, as for :class:`~broadtrack_graph.track.shot_stream.ShotStream`.
    ``send_pixels``: every frame comes with its image (the loop reads pixels: a field model, an observer of the
    frames); else only the frames whose pixels the loop reads do (:func:`without_pixels`).
    """

    prepared_ahead = True  # run_loop takes the frames as they come

    def __init__(self, recipe: FramesRecipe, detector, config: TrackingConfig, opencv_threads: int,
                 frame_size: tuple[int, int], send_pixels: bool = True) -> None:
        self.detects_shots = config.detect_shots
        producer = functools.partial(_prepared_frames, recipe, detector, config, opencv_threads, send_pixels)
        self._feed = ProcessPrefetch(producer, depth=PROCESS_DEPTH, slot_bytes=slot_bytes(*frame_size),
                                     name="broadtrack-frames")

    def __iter__(self) -> Iterator[FrameInput]:
        return iter(self._feed)

    @property
    def shots(self) -> list:
        return self._feed.result or []


def without_pixels(frame: FrameInput, use_flow: bool) -> FrameInput:
    """The prepared frame with its image left out (:attr:`FrameInput.image_stayed`) when the loop reads none of its
    pixels: its markings were found (the loop names them) and its flow frame made (or the run has no flow). Else the
    frame as it is (the loop detects on the image itself: a frame the shot step reads as another view, when the court
    model looks at it, track.reinit_policy)."""
    if frame.image is None:
        return frame
    if frame.markings is not None and (frame.flow_frame is not None or not use_flow):
        frame.image, frame.image_stayed = None, True
    return frame


def _prepared_frames(recipe: FramesRecipe, detector, config: TrackingConfig, opencv_threads: int, send_pixels: bool,
                     taken: Callable[[], int]):
    """In the preparing process: the recipe's frames, shot and prepared (sent without the pixels the loop does not
    read unless ``send_pixels``); returns the shots found."""
    cv2.setNumThreads(opencv_threads)
    with open_frames(recipe.path, recipe.start, recipe.end, recipe.fps) as source:
        stream = ShotStream.for_run(frames_from_source(source), config.detect_shots, config.mask_graphics, detector)
        ahead = FramesAhead(config, getattr(detector, "find_markings", None), taken)
        for frame in stream:
            frame = ahead(frame)
            yield frame if send_pixels else without_pixels(frame, config.use_flow)
    return stream.shots
