"""A real clip as a longer lens shows it, for ``bench real --zoom Z``: views narrower than the clip's own.

A broadcast's main camera zooms into the penalty area after a fast pan, and its other cameras often hold a narrow
view: fewer markings in view, a camera whose depth along its line of sight the markings fix loosely. A clip's frames
cropped about their centre to ``1/Z`` of their width and height, the pixels kept as they are (:func:`zoom_frame`), are
what the same camera shows through a lens ``Z`` times longer: the crop keeps the focal length in pixels, the angles,
the focal point and the principal point at the image's centre (:func:`zoomed_camera`), only the image is smaller. The
copy is written by :mod:`.clip_copy`; its cameras are scored on the zoomed frames themselves (a camera fixed by the
markings inside the crop may draw the pitch outside it differently and still be right in the view it has).

Which zoomed frames could have a camera at all is read from the clip's own cameras, tracked on its whole frames:
each one's :func:`zoomed_camera` sees the crop, and the rule of :mod:`broadtrack_graph.geometry.determinable` says
whether the markings it shows fix a camera (:func:`determinable_figures`). The crop keeps the camera, so the two
runs' cameras of a frame should be one: how far their focal lengths and focal points lie apart
(:func:`camera_agreement`) shows how loosely a narrow view's markings fix its zoom against its distance.

A broadcast cuts back to a camera it has shown wide, zoomed in: the clip's frames followed by its zoomed frames
enlarged back to the clip's size (:func:`write_zoom_cut`: the same camera, its focal length times the enlargement)
are tracked as one video, and the zoomed shot's cameras are compared with the wide shot's of the same frames and
their camera id with its (:func:`cut_figures`): the zoomed shot is the wide shot's camera, on its tripod.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.benchmarks.clip_copy import FrameChange
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import determinability
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.video import VideoSource, open_video_writer

MAX_ZOOM = 8.0
"""The longest zoom asked (a 1080p frame's crop is then 240x134 pixels)."""


def parse_zoom(text: str) -> float:
    """``Z`` (e.g. ``2``) as the zoom, over 1 and at most :data:`MAX_ZOOM`; an ``argparse`` type."""
    try:
        zoom = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number; give the zoom, e.g. 2") from None
    if not 1.0 < zoom <= MAX_ZOOM:
        raise argparse.ArgumentTypeError(f"zoom {zoom:g} is outside (1, {MAX_ZOOM:g}]; give a zoom over 1, e.g. 2")
    return zoom


def zoom_label(zoom: float) -> str:
    """Its part of the copy's name, e.g. ``zoom2`` or ``zoom1.5``."""
    return f"zoom{zoom:g}"


def zoomed_size(width_px: int, height_px: int, zoom: float) -> tuple[int, int]:
    """(w, h) of the crop: ``1/zoom`` of each side rounded to an even number (at least 2), so that the crop's centre
    is the frame's."""
    def side(length: int) -> int:
        return max(2, int(round(length / zoom / 2.0)) * 2)

    return min(side(width_px), width_px - width_px % 2), min(side(height_px), height_px - height_px % 2)


def zoom_frame(image_bgr: np.ndarray, zoom: float) -> np.ndarray:
    """The frame's centre, ``1/zoom`` of its width and height (:func:`zoomed_size`), its pixels unchanged.

    Args:
        image_bgr: (H, W, 3) uint8.

    Returns:
        (h, w, 3) uint8, a copy; its centre is the frame's ((W - w) and (H - h) even for an even W and H).
    """
    H, W = image_bgr.shape[:2]
    w, h = zoomed_size(W, H, zoom)
    left, top = (W - w) // 2, (H - h) // 2
    return np.ascontiguousarray(image_bgr[top:top + h, left:left + w])


def zoomed_camera(camera: Camera, zoom: float) -> Camera:
    """The camera that sees :func:`zoom_frame` of ``camera``'s frame: the same in every parameter, its image the
    crop's size (the focal length in pixels is the crop's too; a principal point given in pixels moves with the
    crop's corner, the image centre stays the centre)."""
    W, H = camera.width_px, camera.height_px
    w, h = zoomed_size(W, H, zoom)
    principal = camera.principal_point_px
    if principal is not None:
        principal = (principal[0] - (W - w) // 2, principal[1] - (H - h) // 2)
    return camera.replace(width_px=w, height_px=h, principal_point_px=principal)


def zoom_change(zoom: float) -> FrameChange:
    """:func:`zoom_frame` as a :data:`~.clip_copy.FrameChange`."""
    return lambda image, index: zoom_frame(image, zoom)


def determinable_figures(whole_cameras: dict[int, Camera | None], zoomed_cameras: dict[int, Camera | None],
                         zoom: float, pitch: PitchTemplate | None = None) -> dict:
    """How many zoomed frames could have a camera, and how many got one (module docstring).

    Args:
        whole_cameras: frame index -> the clip's own camera on its whole frame (None: none written).
        zoomed_cameras: frame index -> the camera written on the zoomed copy's frame (None: none).

    Returns:
        {"reference_frames": frames with a camera of the whole clip, "determinable": those whose crop's markings fix a
        camera, "determinable_with_camera": of them with a camera written on the copy, "share": their share (None
        when none is determinable), "first_determinable", "first_camera": frame indices (None: none)}.
    """
    pitch = pitch or PitchTemplate()
    fixed = sorted(i for i, camera in whole_cameras.items()
                   if camera is not None and determinability(zoomed_camera(camera, zoom), pitch).determinable)
    found = [i for i in fixed if zoomed_cameras.get(i) is not None]
    written = sorted(i for i, camera in zoomed_cameras.items() if camera is not None)
    return {"reference_frames": sum(1 for camera in whole_cameras.values() if camera is not None),
            "determinable": len(fixed), "determinable_with_camera": len(found),
            "share": round(len(found) / len(fixed), 4) if fixed else None,
            "first_determinable": fixed[0] if fixed else None, "first_camera": written[0] if written else None}


def camera_agreement(whole_cameras: dict[int, Camera | None], zoomed_cameras: dict[int, Camera | None]) -> dict:
    """The zoomed copy's cameras against the clip's own on the frames where both runs wrote one (module docstring).

    Returns:
        {"frames": how many, "focal_ratio_error": {"median", "p95"} of ``|f_zoomed / f_whole - 1|``,
        "position_m": {"median", "p95"} of the focal points' distance, metres}; the figures None with no frame.
    """
    both = [i for i, camera in zoomed_cameras.items() if camera is not None and whole_cameras.get(i) is not None]
    focal = np.array([abs(zoomed_cameras[i].focal_px / whole_cameras[i].focal_px - 1.0) for i in both])
    apart = np.array([float(np.linalg.norm(zoomed_cameras[i].position_m - whole_cameras[i].position_m)) for i in both])

    def spread(values: np.ndarray, digits: int) -> dict:
        if not len(values):
            return {"median": None, "p95": None}
        return {"median": round(float(np.median(values)), digits),
                "p95": round(float(np.percentile(values, 95)), digits)}

    return {"frames": len(both), "focal_ratio_error": spread(focal, 4), "position_m": spread(apart, 2)}


def write_zoom_cut(video: Path, out_path: Path, zoom: float, end: int | None = None) -> tuple[int, float]:
    """Write the clip's decodable frames (those before ``end``), then the same frames zoomed (:func:`zoom_frame`) and
    enlarged back to the clip's size by cubic interpolation, as one video (mp4v, the clip's rate).

    Returns:
        (frames of the clip: the zoomed shot starts there, the focal length's factor from the wide shot to the
        zoomed one: the frame's width over the crop's).

    Raises:
        InputError: the video cannot be read or has no decodable frame, or the copy cannot be written.
    """
    writer, frames, factor = None, 0, 1.0
    try:
        for zoomed in (False, True):
            limit = frames if zoomed else end  # the zoomed shot repeats the wide shot's frames
            with VideoSource(video) as source:
                for index, frame in enumerate(source):
                    if frame.image_bgr is None or (limit is not None and index >= limit):
                        break
                    image = frame.image_bgr
                    if writer is None:
                        writer = open_video_writer(out_path, source.fps, (image.shape[1], image.shape[0]))
                    if zoomed:
                        crop = zoom_frame(image, zoom)
                        factor = image.shape[1] / crop.shape[1]
                        image = cv2.resize(crop, (image.shape[1], image.shape[0]), interpolation=cv2.INTER_CUBIC)
                    else:
                        frames += 1
                    writer.write(image)
    finally:
        if writer is not None:
            writer.release()
    if frames == 0:
        raise InputError(video, "no frame could be decoded")
    return frames, factor


def cut_figures(cameras: dict[int, Camera | None], camera_ids: dict[int, str | None], frames: int,
                factor: float) -> dict:
    """The zoomed shot of :func:`write_zoom_cut`'s video (frames ``frames`` on) against its wide shot.

    Args:
        cameras, camera_ids: frame index -> the camera written (None: none) and its camera id.
        frames: the wide shot's length; factor: the focal length's factor from the wide shot to the zoomed one.

    Returns:
        {"zoomed_frames", "with_camera": zoomed frames with a camera, "wide_id": the wide shot's most written id,
        "same_id_share": of the zoomed frames with a camera, the share written under that id (None: none),
        "focal_ratio_error", "position_m": as :func:`camera_agreement`, the wide camera's focal length times
        ``factor``}.
    """
    wide_ids = Counter(camera_ids.get(i) for i in range(frames) if cameras.get(i) is not None)
    wide_id = wide_ids.most_common(1)[0][0] if wide_ids else None
    zoomed = [i for i in range(frames, 2 * frames) if cameras.get(i) is not None]
    same = sum(1 for i in zoomed if wide_id is not None and camera_ids.get(i) == wide_id)
    widened = {i: cameras[i - frames].replace(focal_px=cameras[i - frames].focal_px * factor)
               for i in zoomed if cameras.get(i - frames) is not None}
    agreement = camera_agreement(widened, {i: cameras[i] for i in zoomed})
    return {"zoomed_frames": frames, "with_camera": len(zoomed), "wide_id": wide_id,
            "same_id_share": round(same / len(zoomed), 4) if zoomed else None,
            "focal_ratio_error": agreement["focal_ratio_error"], "position_m": agreement["position_m"],
            "compared_frames": agreement["frames"]}
