"""Circle hypotheses: cameras (roll 0, focal point fixed) that put a pitch circle on an ellipse of the
marking map, fitted to the ellipse's points. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import Arc, PitchTemplate
from broadtrack_graph.geometry.state import BEHIND_CAMERA_Z
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.map_score import Hypothesis, MapScorer
from broadtrack_graph.reinit.mask_config import MaskSearchConfig


@dataclass(frozen=True)
class _Closest:
    """The camera of a focal point whose circle's image lies closest to an ellipse: that median gap (pixels) and
    the camera."""

    gap_px: float
    camera: Camera


def _pointing(direction_w: np.ndarray, ray_c: np.ndarray):
    """Pan and tilt (radians) with roll 0 turning the world direction onto the camera ray (both (3,)); [] if none."""
    w = direction_w / np.linalg.norm(direction_w)
    c = ray_c / np.linalg.norm(ray_c)
    h = math.hypot(w[0], w[1])
    if h < 1e-9 or abs(c[0]) > h:
        return []
    phi, spread = math.atan2(w[1], w[0]), math.acos(c[0] / h)
    out = []
    for pan in (phi + spread, phi - spread):
        m_y = -math.sin(pan) * w[0] + math.cos(pan) * w[1]
        tilt = math.atan2(w[2], m_y) - math.atan2(c[2], c[1])
        out.append((pan, math.remainder(tilt, 2 * math.pi)))
    return out


def ellipse_cameras(ellipses: list[ImageEllipse], position_w, frame_size, pitch: PitchTemplate,
                    config: MaskSearchConfig = MaskSearchConfig()):
    """Cameras (roll 0, focal point at position_w) putting a pitch circle on an image ellipse.

    The circle's angular size from the focal point and the ellipse's major axis give f (to
    within the stretch off the image centre, so a range of f around it is tried); the camera
    is then turned (roll 0) so that the ray through the ellipse centre meets the circle centre.
    These are rough (the ellipse centre is not the image of the circle centre): fit them to
    the ellipse's pixels before use (:func:`reinit_from_mask` does).

    Returns:
        pans_rad, tilts_rad, focals_px: (K,) each; ellipse_index (K,) ints; circle_names: list of K names.
    """
    W, H = frame_size
    C = np.asarray(position_w, float)
    tilt_lo, tilt_hi = np.radians(config.tilt_range_deg)
    circles = [(name, element) for name, element in pitch.elements.items() if isinstance(element, Arc)]
    pans, tilts, focals, which, names = [], [], [], [], []
    for index, ellipse in enumerate(ellipses):
        u, v = ellipse.centre_px - [W / 2.0, H / 2.0]
        for name, circle in circles:
            direction = np.asarray(circle.centre_w, float) - C
            distance = np.linalg.norm(direction)
            if distance < 2 * circle.radius_m or direction[2] <= 0:
                continue
            focal = ellipse.semi_axes_px[0] / math.tan(math.asin(circle.radius_m / distance))
            for f in focal * np.asarray(config.ellipse_focal_factors):
                if not (config.line_focal_range_per_width[0] * W < f < config.line_focal_range_per_width[1] * W):
                    continue
                for pan, tilt in _pointing(direction, np.array([u, v, f])):
                    if tilt_lo < tilt < tilt_hi:
                        pans.append(pan), tilts.append(tilt), focals.append(f), which.append(index), names.append(name)
    return np.array(pans), np.array(tilts), np.array(focals), np.array(which, int), names


def circle_hypotheses(ellipses: list[ImageEllipse], points_px: np.ndarray, positions, frame_size, pitch,
                       curves: TemplateCurves, scorer: MapScorer, config: MaskSearchConfig) -> list[Hypothesis]:
    """Circle cameras: for each focal point, ellipse and circle the rough camera (:func:`ellipse_cameras`)
    whose projected circle lies closest to the ellipse's points; the ``ellipse_fit_top_k`` closest are
    fitted to those points (f, pan, tilt; the focal point, roll and k1 held) and scored."""
    W, H = frame_size
    band = 3.0 * config.structures.ellipse_band_px * W / 960.0
    on_ellipse = []
    for ellipse in ellipses:
        on = points_px[ellipse.distances_px(points_px) < band]
        on_ellipse.append(on[np.linspace(0, len(on) - 1, min(len(on), config.ellipse_fit_points)).astype(int)])
    circle_names = [name for name, element in pitch.elements.items() if isinstance(element, Arc)]
    samples = pitch.sample_uniform(1.0, classes=circle_names)
    closest: dict[tuple, _Closest] = {}  # (focal point, ellipse index, circle name) -> its closest camera
    for C in positions:
        C = np.asarray(C, float)
        pans, tilts, focals, which, names = ellipse_cameras(ellipses, C, frame_size, pitch, config)
        names = np.asarray(names, dtype=object)
        for index, name in dict.fromkeys(zip(which.tolist(), names.tolist())):
            on = on_ellipse[index]
            if len(on) < 8:
                continue
            group = np.flatnonzero((which == index) & (names == name))
            gaps = _circle_gaps(pans[group], tilts[group], focals[group], samples[name] - C, on, W, H)
            if not np.isfinite(gaps).any():
                continue
            k = group[int(np.nanargmin(gaps))]
            key = (tuple(C), index, name)
            gap = float(np.nanmin(gaps))
            if key not in closest or gap < closest[key].gap_px:
                closest[key] = _Closest(gap, Camera(focals[k], 0.0, pans[k], tilts[k], 0.0, C, W, H))
    fit_config = LineFitConfig(polish_power=0.0, iterations=10, cauchy_scale_px=config.structures.ellipse_band_px * W / 960.0)
    out = []
    ranked = sorted(closest.items(), key=lambda item: item[1].gap_px)
    for (C, which, name), nearest in ranked[:config.ellipse_fit_top_k]:
        camera = fit_camera_to_lines(nearest.camera, {name: on_ellipse[which]}, curves, fit_config,
                                     fixed=(1, 4, 5, 6, 7)).camera
        cost = scorer.costs(C, [camera.pan_rad], [camera.tilt_rad], [camera.focal_px], config.score_hit_px,
                            config.score_point_px)[0]
        if np.isfinite(cost):
            out.append(Hypothesis(np.asarray(C, float), camera.pan_rad, camera.tilt_rad, camera.focal_px, cost))
    return out


def _circle_gaps(pans, tilts, focals, relative_w, on_px, width_px, height_px) -> np.ndarray:
    """(K,) median distance (pixels) from each ellipse point to the nearest projected circle sample, per roll-0,
    k1-0 camera; NaN for a camera with fewer than 3 samples in front of it.

    Args:
        pans, tilts, focals: (K,) radians, radians, pixels; relative_w: (S, 3) circle samples minus the focal point
        (metres); on_px: (P, 2) the ellipse's points (pixels).
    """
    cp, sp = np.cos(pans)[:, None], np.sin(pans)[:, None]
    ct, st = np.cos(tilts)[:, None], np.sin(tilts)[:, None]
    rx, ry, rz = relative_w[:, 0], relative_w[:, 1], relative_w[:, 2]
    # Into the camera: Rx(tilt)^T Rz(pan)^T (X - C) (roll 0).
    x_c = cp * rx + sp * ry
    y1 = -sp * rx + cp * ry
    y_c = ct * y1 + st * rz
    z_c = -st * y1 + ct * rz
    front = z_c > BEHIND_CAMERA_Z
    depth = np.where(front, z_c, 1.0)
    u = focals[:, None] * (x_c / depth) + width_px / 2.0
    v = focals[:, None] * (y_c / depth) + height_px / 2.0
    distance2 = (on_px[None, :, 0, None] - u[:, None, :]) ** 2 + (on_px[None, :, 1, None] - v[:, None, :]) ** 2
    distance2 = np.where(front[:, None, :], distance2, np.inf)
    gaps = np.median(np.sqrt(distance2.min(axis=2)), axis=1)
    return np.where(front.sum(axis=1) >= 3, gaps, np.nan)
