"""Module-level fake global searches for the stage runner's tests: a worker process imports them by name."""

from __future__ import annotations

import multiprocessing
import os
import time

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.search_stages import SEARCH_STAGES

STAGE_SECONDS = 0.15


def numbered_search(observations, detections, pitch, positions, curves, sampling) -> ReinitResult:
    """A camera whose focal length is the stage's number (positions = (number,)), after STAGE_SECONDS, with the
    process that computed it in its reason."""
    time.sleep(STAGE_SECONDS)
    number = float(positions[0])
    camera = Camera(1000.0 + number, 0.0, 0.0, 1.3, 0.0, (0.0, 55.0, -12.0), 1280, 720)
    return ReinitResult(camera, None, f"stage {number:g}", f"pid {os.getpid()}")


def dying_search(observations, detections, pitch, positions, curves, sampling) -> ReinitResult:
    """:func:`numbered_search`, except that a worker process asked for it dies."""
    if multiprocessing.parent_process() is not None:
        os._exit(3)
    return numbered_search(observations, detections, pitch, positions, curves, sampling)


def stage_numbered_search(observations, detections, pitch, positions, curves, sampling) -> ReinitResult:
    """:func:`numbered_search` of the policy's stages: a camera whose focal length is 1000 + the stage's index in
    SEARCH_STAGES."""
    number = next(k for k, (_, stage) in enumerate(SEARCH_STAGES) if stage == positions)
    return numbered_search(observations, detections, pitch, (number,), curves, sampling)


def numbered_call(number, curves=None, offset=0.0):
    """A call of ``StageRunner.mapped``: (number + offset, the process that computed it, whether it was given a
    template), after STAGE_SECONDS."""
    time.sleep(STAGE_SECONDS)
    return number + offset, os.getpid(), curves is not None
