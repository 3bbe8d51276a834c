"""The status of a frame in a run (``track.jsonl``'s ``status`` field)."""

from __future__ import annotations

from enum import StrEnum


class FrameStatus(StrEnum):
    """What became of a frame. A frame has a camera exactly when :attr:`has_camera` is true.

    The values are the strings written to ``track.jsonl``; a member compares equal to its string.
    """

    TRACKED = "tracked"
    """The solver's camera, confident."""
    REINITIALISED = "reinitialised"
    """A camera found again from the frame alone (the chain restarts here)."""
    NO_PITCH = "no-pitch"
    """No grass, or too little of it, to fit a camera."""
    NO_DETECTIONS = "no-detections"
    """The detections file had nothing for the frame."""
    MISSING_FRAME = "missing-frame"
    """The frame could not be decoded or read."""
    FAILED = "failed"
    """A pitch was seen but no camera explained it confidently."""
    MOTION_PRIOR = "motion-prior"
    """No detections: the solver carried the track on its motion prior, but no camera is claimed
    (for at most ``max_motion_prior_frames``; never counts toward completeness)."""
    OTHER_VIEW = "other-view"
    """A close-up, a crowd or another shot that is not a pitch camera's view."""
    UNPLACED = "unplaced"
    """A pitch view no camera was found for (yet): the reason says when the next search runs."""

    @property
    def has_camera(self) -> bool:
        """True for the statuses whose record carries a camera (tracked, reinitialised)."""
        return self in (FrameStatus.TRACKED, FrameStatus.REINITIALISED)
