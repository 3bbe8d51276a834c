"""Scores of a tracked broadcast against its truth: cuts, shot kinds, camera ids, tripods per camera.

Pure functions of shot lists (:class:`~broadtrack_graph.types.shot.Shot`, 0-based frame
indices, end exclusive), per-frame lists and tripods; no files. Used by ``bench broadcast``.

* Cuts: a true cut (the start of every true shot after the first) is found when a
  predicted boundary (the start of a predicted shot after the first) lies within
  ``tolerance_frames`` of it.
* Shot kinds: per true shot, the predicted kind most of its frames got; it agrees exactly
  when equal, and by group when both are pitch kinds ("main", "other-camera") or both
  no-pitch kinds ("close-up", "crowd").
* Camera ids: each true camera maps to the predicted id most of its frames got (frames
  without a predicted id left out); the mapping is one-to-one when every true camera maps
  to an id and no two map to the same. A pitch frame has the right camera when its
  predicted id is given and the true camera most frames with that predicted id belong to
  is the frame's own.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence

import numpy as np

from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.types.shot import Shot

PITCH_KINDS = ("main", "other-camera")
NO_PITCH_KINDS = ("close-up", "crowd")
KIND_ORDER = PITCH_KINDS + NO_PITCH_KINDS
"""Kinds in tie-break order (the first of equally frequent kinds wins)."""


def kind_group(kind: str | None) -> str | None:
    """"pitch" for a pitch kind, "no-pitch" for a no-pitch kind, None otherwise."""
    if kind in PITCH_KINDS:
        return "pitch"
    if kind in NO_PITCH_KINDS:
        return "no-pitch"
    return None


def _share(count: int, total: int) -> float | None:
    return None if total == 0 else round(count / total, 4)


def _majority(values) -> object | None:
    """The most frequent non-None value (ties: first in KIND_ORDER, then sorted), or None."""
    counts = Counter(v for v in values if v is not None)
    if not counts:
        return None
    best = max(counts.values())
    tied = [v for v, c in counts.items() if c == best]
    return min(tied, key=lambda v: (KIND_ORDER.index(v) if v in KIND_ORDER else len(KIND_ORDER), str(v)))


def cut_scores(true_shots: Sequence[Shot], predicted_shots: Sequence[Shot], tolerance_frames: int = 2) -> dict:
    """Cuts found (module docstring).

    Returns:
        {"true_cuts", "predicted_cuts", "found", "recall" (None without true cuts), "false_cuts" (predicted
         boundaries within tolerance of no true cut), "missed" (frame indices of the true cuts not found)}.
    """
    true_cuts = sorted(s.start for s in true_shots[1:])
    predicted = np.array(sorted(s.start for s in predicted_shots[1:]), dtype=int)
    near = lambda frame, others: bool(len(others)) and bool(np.min(np.abs(np.asarray(others) - frame)) <= tolerance_frames)
    found = [c for c in true_cuts if near(c, predicted)]
    false = [int(p) for p in predicted if not near(int(p), true_cuts)]
    return {"true_cuts": len(true_cuts), "predicted_cuts": int(len(predicted)), "found": len(found),
            "recall": _share(len(found), len(true_cuts)), "false_cuts": len(false),
            "missed": [c for c in true_cuts if c not in found]}


def frame_kinds(shots: Sequence[Shot], frame_count: int) -> list[str | None]:
    """(frame_count) the kind of the shot holding each frame (None where no shot does)."""
    kinds: list[str | None] = [None] * frame_count
    for shot in shots:
        for i in range(max(0, shot.start), min(frame_count, shot.end)):
            kinds[i] = shot.kind
    return kinds


def kind_scores(true_shots: Sequence[Shot], predicted_kinds: Sequence[str | None]) -> dict:
    """Shot kind agreement per true shot (module docstring).

    Args:
        true_shots: the true shots.
        predicted_kinds: the predicted kind of every frame (None: unknown), e.g. :func:`frame_kinds`.

    Returns:
        {"shots", "group_agreement", "exact_agreement" (shares of the true shots), "per_shot": [{"start", "end",
         "kind", "predicted_kind"}]}.
    """
    per_shot = []
    for shot in true_shots:
        predicted = _majority(predicted_kinds[shot.start:shot.end])
        per_shot.append({"start": shot.start, "end": shot.end, "kind": shot.kind, "predicted_kind": predicted})
    exact = sum(1 for s in per_shot if s["predicted_kind"] == s["kind"])
    group = sum(1 for s in per_shot if kind_group(s["predicted_kind"]) is not None
                and kind_group(s["predicted_kind"]) == kind_group(s["kind"]))
    return {"shots": len(per_shot), "group_agreement": _share(group, len(per_shot)),
            "exact_agreement": _share(exact, len(per_shot)), "per_shot": per_shot}


def camera_id_scores(true_ids: Sequence[str | None], predicted_ids: Sequence[str | None]) -> dict:
    """Mapping of true to predicted camera ids and the share of pitch frames with the right camera.

    Args:
        true_ids: per frame, the true camera id (None on frames with no pitch camera).
        predicted_ids: per frame, the predicted id (None: no camera), same length.

    Returns:
        {"mapping": {true id: predicted id or None}, "one_to_one": bool, "pitch_frames",
         "frames_with_id" (pitch frames with a predicted id), "right_camera_share" (of the pitch frames),
         "per_camera": {true id: {"frames", "with_id", "right"}}}.
    """
    if len(true_ids) != len(predicted_ids):
        raise ValueError(f"expected as many predicted ids as true ones, got {len(predicted_ids)} and {len(true_ids)}")
    pitch = [(t, p) for t, p in zip(true_ids, predicted_ids) if t is not None]
    cameras = sorted({t for t, _ in pitch})
    mapping = {t: _majority(p for tt, p in pitch if tt == t) for t in cameras}
    owner = {p: _majority(t for t, pp in pitch if pp == p) for p in {p for _, p in pitch if p is not None}}
    mapped = list(mapping.values())
    one_to_one = bool(cameras) and None not in mapped and len(set(mapped)) == len(mapped)
    per_camera = {}
    for t in cameras:
        frames = [p for tt, p in pitch if tt == t]
        per_camera[t] = {"frames": len(frames), "with_id": sum(1 for p in frames if p is not None),
                         "right": sum(1 for p in frames if p is not None and owner[p] == t)}
    right = sum(c["right"] for c in per_camera.values())
    return {"mapping": mapping, "one_to_one": one_to_one, "pitch_frames": len(pitch),
            "frames_with_id": sum(1 for _, p in pitch if p is not None),
            "right_camera_share": _share(right, len(pitch)), "per_camera": per_camera}


def frames_by_kind(true_shots: Sequence[Shot], kinds: Sequence[str] = PITCH_KINDS) -> dict[str, list[int]]:
    """kind -> the frame indices of the true shots of that kind, in order (one list per requested kind)."""
    groups: dict[str, list[int]] = {kind: [] for kind in kinds}
    for shot in true_shots:
        if shot.kind in groups:
            groups[shot.kind].extend(range(shot.start, shot.end))
    return groups


def tripod_scores(true_tripods: dict[str, Tripod], run_tripods: dict[str, Tripod], mapping: dict[str, str | None]
                  ) -> dict[str, dict | None]:
    """Per true camera id, the run's tripod of the predicted id it maps to against the true one.

    Returns:
        true id -> {"predicted_id", "T_error_m" |T - T_true|, "T_error_xy_m", "delta_error_m" (signed)}, or None
        when the run has no tripod for that id.
    """
    out: dict[str, dict | None] = {}
    for cid, truth in true_tripods.items():
        predicted = mapping.get(cid)
        fitted = run_tripods.get(predicted) if predicted is not None else None
        if fitted is None:
            out[cid] = None
            continue
        error = np.asarray(fitted.T_w, float) - np.asarray(truth.T_w, float)
        out[cid] = {"predicted_id": predicted, "T_error_m": round(float(np.linalg.norm(error)), 4),
                    "T_error_xy_m": round(float(np.linalg.norm(error[:2])), 4),
                    "delta_error_m": round(float(fitted.delta_m - truth.delta_m), 4)}
    return out
