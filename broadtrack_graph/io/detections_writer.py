"""Writing the detections file (its format: :mod:`broadtrack_graph.io.detections`, which reads it).

Every detections file the project writes goes through :class:`DetectionsWriter`: the project's
detector (``detect``), imported annotations, and the benchmarks' noisy keypoints.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from broadtrack_graph.types.observations import FrameObservations


def observations_to_record(observations: FrameObservations, frame_id: str | None = None,
                           mask_path: str | None = None, keypoint_ids: list[int] | None = None) -> dict:
    """FrameObservations -> one JSON object of the detections format (pixels).

    keypoint_ids: optional number per keypoint in a detector's own numbering (kept as "id").
    """
    record: dict = {"frame": int(observations.frame_index),
                    "image_size": [int(observations.width_px), int(observations.height_px)], "units": "px"}
    if frame_id is not None:
        record["frame_id"] = frame_id
    if observations.lines_px:
        record["lines"] = {name: np.round(points, 2).tolist() for name, points in observations.lines_px.items()}
    if observations.keypoints is not None and len(observations.keypoints):
        kp = observations.keypoints
        record["keypoints"] = []
        for index in range(len(kp)):
            entry = {"xy": np.round(kp.uv_px[index], 2).tolist(), "confidence": round(float(kp.confidence[index]), 4)}
            if keypoint_ids is not None and index < len(keypoint_ids):
                entry["id"] = int(keypoint_ids[index])
            name = kp.names[index] if index < len(kp.names) else ""
            if name:
                entry["name"] = name
            else:
                entry["world"] = [float(v) for v in kp.points_w[index]]
            record["keypoints"].append(entry)
    if mask_path is not None:
        record["mask"] = mask_path
    if observations.player_boxes_px is not None and len(observations.player_boxes_px):
        record["players"] = np.round(observations.player_boxes_px, 1).tolist()
    return record


def normalized_lines_record(frame_index: int, frame_id: str, image_size: tuple[int, int],
                            lines_norm: dict[str, list]) -> dict:
    """One detections-format record of line points in normalised units (x / (W - 1), y / (H - 1))."""
    return {"frame": int(frame_index), "frame_id": frame_id, "image_size": [int(image_size[0]), int(image_size[1])],
            "units": "normalized", "lines": lines_norm}


def named_keypoints_record(frame_index: int, frame_id: str, image_size: tuple[int, int],
                           keypoints: list[tuple[str, float, float, float]]) -> dict:
    """One detections-format record of template keypoints in pixels: ``(name, x_px, y_px, confidence)`` each."""
    return {"frame": int(frame_index), "frame_id": frame_id, "image_size": [int(image_size[0]), int(image_size[1])],
            "units": "px", "keypoints": [{"name": name, "xy": [x, y], "confidence": confidence}
                                         for name, x, y, confidence in keypoints]}


class DetectionsWriter:
    """Append records to a detections file, one flushed line per frame (an interrupted run keeps them).

    :meth:`write` takes a frame's observations; :meth:`write_record` a record already in the
    format (from :func:`observations_to_record`, :func:`normalized_lines_record`,
    :func:`named_keypoints_record`).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._handle = self.path.open("w", encoding="utf-8")

    def write(self, observations: FrameObservations, frame_id: str | None = None, mask_path: str | None = None,
              keypoint_ids: list[int] | None = None) -> None:
        self.write_record(observations_to_record(observations, frame_id, mask_path, keypoint_ids))

    def write_record(self, record: dict) -> None:
        self._handle.write(json.dumps(record) + "\n")
        self._handle.flush()

    def close(self) -> None:
        self._handle.close()

    def __enter__(self) -> "DetectionsWriter":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
