"""Whether a fitted tripod is one, and the tripod an offline pass holds: the rule online and offline share.

A tripod fit (:func:`~broadtrack_graph.graph.tripod_fit.fit_tripod`) finds the point every optical axis passes at
distance delta from. When the cameras it is given do not share a tripod (a chain of wrong cameras, scattered
metres apart, all looking at the same part of the pitch), the point nearest their axes is where they look: on the
grass or under it. Such a fit is rejected when it explains fewer than ``tripod_fit_min_inliers`` of its cameras or
puts the tripod where no broadcast camera stands (under 3 m, over the pitch, out of the stadium:
:func:`~broadtrack_graph.reinit.frame.plausible_position`). Held in the tripod factor, it would pull every frame of
the camera there. Pure: no I/O.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.tripod_fit import fit_tripod_for_run, provisional_tripod_for_run
from broadtrack_graph.reinit.frame import plausible_position
from broadtrack_graph.track.config import TrackingConfig


def rejected_fit(tripod: Tripod, info: dict, config: TrackingConfig, pitch: PitchTemplate) -> str | None:
    """Why a fitted tripod is not a consistent one, in one line (None: it is).

    Args:
        tripod: the fit's tripod.
        info: the fit's report (its ``inlier_ratio``).
        config: ``tripod_fit_min_inliers``.
        pitch: where a tripod may not stand.
    """
    inliers = float(info.get("inlier_ratio", 0.0))
    if inliers >= config.tripod_fit_min_inliers and plausible_position(tripod.T_w, pitch):
        return None
    return f"inlier ratio {inliers:.2f}, T {np.round(tripod.T_w, 2).tolist()}: not a consistent tripod"


def standing_provisional(cameras: list[Camera], graph: GraphConfig, pitch: PitchTemplate) -> Tripod | None:
    """The cameras' provisional tripod (:func:`~broadtrack_graph.graph.tripod_fit.provisional_tripod_for_run`) where
    a broadcast camera can stand, else None."""
    provisional = provisional_tripod_for_run(cameras, graph)
    return provisional if provisional is not None and plausible_position(provisional.T_w, pitch) else None


def offline_tripod(cameras: list[Camera], config: TrackingConfig, graph: GraphConfig,
                   pitch: PitchTemplate) -> tuple[Tripod | None, dict]:
    """The tripod an offline pass holds for one camera's first-pass cameras, and what chose it.

    The fit when there are ``tripod_provisional_frames`` cameras or more and it is consistent
    (:func:`rejected_fit`); else the provisional tripod (the cameras' median with the typical offsets, held as
    loosely as they scatter: :func:`~broadtrack_graph.graph.tripod_fit.provisional_tripod_for_run`) where a
    broadcast camera can stand; else none (the pass refines without the tripod factor).

    Args:
        cameras: the first pass's cameras of one camera id.
        config: the ``tripod_*`` fields.
        graph: the solver's delta prior, the provisional tripod's lambda.
        pitch: where a tripod may not stand.

    Returns:
        (tripod or None, report: the fit's, or why the provisional tripod or none stands in).
    """
    info: dict = {}
    if len(cameras) >= max(1, config.tripod_provisional_frames):
        fitted, info = fit_tripod_for_run(cameras, graph.solver)
        if fitted is not None:
            rejected = rejected_fit(fitted, info, config, pitch)
            if rejected is None:
                return fitted, info
            info = {**info, "rejected": rejected}
        reason = f"the fit rejected ({info.get('rejected') or info.get('reason')}): typical delta and lambda"
    else:
        reason = f"fewer than {config.tripod_provisional_frames} frames: typical delta and lambda"
    provisional = standing_provisional(cameras, graph, pitch)
    if provisional is None:
        return None, {**info, "provisional": False, "frames": len(cameras),
                      "reason": "no tripod: neither a consistent fit nor the cameras' median stands where a "
                                "broadcast camera can"}
    return provisional, {**info, "provisional": True, "frames": len(cameras), "reason": reason}
