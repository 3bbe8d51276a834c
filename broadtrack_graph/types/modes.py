"""The tracking modes: how a run turns frames into cameras."""

from __future__ import annotations

from enum import StrEnum


class TrackingMode(StrEnum):
    """A tracking mode; the values are the names the command line, manifests and reports use."""

    ONLINE = "online"
    """iSAM2, one frame at a time: a frame's camera is final as soon as the frame is done."""
    FIXED_LAG = "fixed-lag"
    """A fixed-lag smoother: a frame's camera is final ``lag`` frames later."""
    BATCH = "batch"
    """An online first pass, a tripod fit, then Levenberg-Marquardt over the whole clip."""


MODES = tuple(mode.value for mode in TrackingMode)
"""The mode names, in the order of :class:`TrackingMode`: ``("online", "fixed-lag", "batch")``."""
