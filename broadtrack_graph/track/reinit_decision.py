"""What the re-initialisation decision returns, and the candidates its tries return while it decides: the value
types of :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` and
:class:`~broadtrack_graph.track.frame_tries.FrameTries`. No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import ReinitResult


@dataclass(frozen=True)
class ReinitDecision:
    """What the policy found for one frame, and why.

    camera: the camera to restart the solver from, or None (keep the held camera; or nothing found).
    confidence: the tracker's confidence of ``camera`` (None when unknown or no camera).
    camera_id: the camera id ``camera`` belongs to (None with no camera).
    continues_chain: ``camera`` is a confident camera of this camera id moved onto the frame: its
        chain (and the trust it earned) goes on.
    searched: a global search ran for this frame.
    reason: one line.
    new_camera: ``camera`` was searched for a shot whose camera was not known: its chain is trusted only from
        a frame confident by the margin (a shot's first frame can be explained, nearly as well, by a wrong camera).
    faint_look: ``camera`` was found on the frame's markings with their faint look (detect.faint_lines): the frame's
        markings are those from here on.
    """

    camera: Camera | None
    confidence: float | None
    camera_id: str | None
    continues_chain: bool
    searched: bool
    reason: str
    new_camera: bool = False
    faint_look: bool = False


@dataclass(frozen=True)
class Candidate:
    """A try's camera: taken at once when confident enough, else the best camera so far that a later try must beat.

    result: the camera's re-initialisation; camera_id: its id when it continues a chain (a refined guess), else
    None (given by where it stands if taken); confidence: the tracker's confidence of it; continues_chain: a
    confident camera of its id moved onto the frame; label: what found it.
    """

    result: ReinitResult
    camera_id: str | None
    confidence: float
    continues_chain: bool
    label: str


@dataclass(frozen=True)
class CourtCandidate(Candidate):
    """The court model's camera for a frame (:meth:`~broadtrack_graph.track.frame_tries.FrameTries.court_camera`).

    agrees: it is confident by the margin and the court camera of a frame shortly before in the stretch, as
    confident, stood in the same place (``court_agreement_frames``) with a view at least
    ``court_agreement_view_change`` of the width away.
    """

    agrees: bool = False
