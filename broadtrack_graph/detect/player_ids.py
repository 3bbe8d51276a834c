"""Track ids for player boxes that come without them (the detector's blobs): greedy IoU linking frame to frame.

A box takes the id of the previous frame's box it overlaps most (intersection over
union at least ``min_iou``, each previous box used once, best pairs first); a box
with no such partner starts a new id. A gap of more than ``max_gap_frames`` frames
ends every track. This is a minimal linker for analytics on boxes without identities,
not a re-identification tracker: ids switch when players cross.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.types.player_boxes import NO_TRACK_ID, PlayerBoxes, PlayerFrame


def box_iou(a_px: np.ndarray, b_px: np.ndarray) -> np.ndarray:
    """(N, M) intersection over union of boxes a (N, 4) and b (M, 4), [x0, y0, x1, y1] pixels."""
    a = np.asarray(a_px, dtype=float).reshape(-1, 4)[:, None, :]
    b = np.asarray(b_px, dtype=float).reshape(-1, 4)[None, :, :]
    w = np.clip(np.minimum(a[..., 2], b[..., 2]) - np.maximum(a[..., 0], b[..., 0]), 0, None)
    h = np.clip(np.minimum(a[..., 3], b[..., 3]) - np.maximum(a[..., 1], b[..., 1]), 0, None)
    inter = w * h
    area_a = (a[..., 2] - a[..., 0]) * (a[..., 3] - a[..., 1])
    area_b = (b[..., 2] - b[..., 0]) * (b[..., 3] - b[..., 1])
    return inter / np.maximum(area_a + area_b - inter, 1e-9)


class TrackIdLinker:
    """The IoU linking one frame at a time (frames in index order), for boxes that arrive as a run goes.

    Args:
        next_id: the first id given to a new track.
        min_iou, max_gap_frames: see :func:`link_track_ids`.
    """

    def __init__(self, next_id: int = 0, min_iou: float = 0.3, max_gap_frames: int = 1) -> None:
        self.next_id = int(next_id)
        self.min_iou = min_iou
        self.max_gap_frames = max_gap_frames
        self._prev_boxes, self._prev_ids, self._prev_index = np.zeros((0, 4)), np.zeros(0, dtype=int), None

    def link(self, frame: PlayerFrame) -> PlayerFrame:
        """The frame with an id on every box: the previous frame's id it overlaps most, else a new one."""
        ids = frame.track_ids.copy()
        todo = np.flatnonzero(ids == NO_TRACK_ID)
        prev_boxes, prev_ids, prev_index = self._prev_boxes, self._prev_ids, self._prev_index
        gap_ok = (prev_index is not None and frame.frame_index is not None
                  and frame.frame_index - prev_index <= self.max_gap_frames)
        if len(todo) and gap_ok and len(prev_boxes):
            iou = box_iou(frame.boxes_px[todo], prev_boxes)
            used_prev, used_new = set(), set()
            for flat in np.argsort(-iou, axis=None):
                i, j = np.unravel_index(flat, iou.shape)
                if iou[i, j] < self.min_iou:
                    break
                if i in used_new or j in used_prev:
                    continue
                ids[todo[i]] = prev_ids[j]
                used_new.add(i)
                used_prev.add(j)
        for k in np.flatnonzero(ids == NO_TRACK_ID):
            ids[k] = self.next_id
            self.next_id += 1
        self._prev_boxes, self._prev_ids, self._prev_index = frame.boxes_px, ids, frame.frame_index
        return PlayerFrame(frame.frame_index, frame.frame_id, ids, frame.boxes_px, frame.roles, frame.teams,
                           frame.confidences)


def link_track_ids(boxes: PlayerBoxes, min_iou: float = 0.3, max_gap_frames: int = 1) -> PlayerBoxes:
    """A copy of ``boxes`` whose boxes without an id get one by IoU linking (frames in index order).

    Boxes that already have an id keep it; new ids start above the largest given one; frames without an
    index keep their order.
    """
    frames = sorted(boxes.frames, key=lambda f: (f.frame_index is None, f.frame_index or 0))
    out = PlayerBoxes(source=boxes.source, kind=boxes.kind, image_size=boxes.image_size, issues=list(boxes.issues),
                      image_ids=dict(boxes.image_ids))
    linker = TrackIdLinker(1 + max((int(f.track_ids.max()) for f in frames if len(f)), default=0), min_iou,
                           max_gap_frames)
    out.frames = [linker.link(frame) for frame in frames]
    return out
