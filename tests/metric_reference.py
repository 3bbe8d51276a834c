"""A deliberately plain, point-by-point implementation of the SoccerNet camera metric rules.

Used only by the tests, to check the vectorised evaluator frame by frame: every
rule is written as a loop over points, the way the official SoccerNet evaluation states it
(the rules are listed in broadtrack_graph/geometry/template.py and broadtrack_graph/metrics/soccernet.py).
"""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.pitch import MIRRORED_CLASS, PitchTemplate


def _project_point(camera, point_w):
    point_c = camera.R_cw @ (np.asarray(point_w) - camera.position_m)
    if point_c[2] <= 1e-3:
        return None
    x, y = point_c[0] / point_c[2], point_c[1] / point_c[2]
    r2 = x * x + y * y
    factor = 1 + camera.k1 * r2
    xd, yd = np.float32(x * factor), np.float32(y * factor)
    cx, cy = camera.principal_point
    return (float(xd) * camera.focal_px + cx, float(yd) * camera.focal_px + cy)


def _border(current, previous, width, height):
    best, best_d = None, math.inf
    (x1, y1), (x0, y0) = current, previous
    for border in ("x0", "x1", "y0", "y1"):
        if border in ("x0", "x1"):
            x = 0.0 if border == "x0" else width - 1.0
            if x1 == x0:
                continue
            y = y0 + (y1 - y0) * (x - x0) / (x1 - x0)
        else:
            y = 0.0 if border == "y0" else height - 1.0
            if y1 == y0:
                continue
            x = x0 + (x1 - x0) * (y - y0) / (y1 - y0)
        if 0 <= x < width and 0 <= y < height:
            d = math.hypot(x - x1, y - y1)
            if d < best_d:
                best, best_d = (x, y), d
    return best


def polylines(camera, width, height):
    out = {}
    for name, points in PitchTemplate().sample_soccernet().items():
        line, inside_before, previous = [], False, None
        for point in points:
            uv = _project_point(camera, point)
            if uv is None:
                continue
            inside = 0 <= uv[0] < width and 0 <= uv[1] < height
            if inside:
                if not inside_before and previous is not None:
                    hit = _border(uv, previous, width, height)
                    if hit:
                        line.append(hit)
                line.append(uv)
            elif inside_before:
                hit = _border(uv, previous, width, height)
                if hit:
                    line.append(hit)
            inside_before, previous = inside, uv
        if line:
            out[name] = line
    return out


def _distance(point, line):
    if len(line) == 1:
        return math.dist(point, line[0])
    best = math.inf
    for a, b in zip(line[:-1], line[1:]):
        ab = (b[0] - a[0], b[1] - a[1])
        denom = ab[0] ** 2 + ab[1] ** 2
        t = 0.0 if denom == 0 else ((point[0] - a[0]) * ab[0] + (point[1] - a[1]) * ab[1]) / denom
        t = min(1.0, max(0.0, t))
        best = min(best, math.dist(point, (a[0] + t * ab[0], a[1] + t * ab[1])))
    return best


def frame_jac(lines_norm, camera, width, height, tau):
    projected = polylines(camera, width, height)

    def score(labels):
        tp = fp = fn = 0
        for name in projected:
            if name not in labels:
                fp += 1
        for name, points in labels.items():
            if name not in projected:
                fn += 1
            elif all(_distance((x * (width - 1), y * (height - 1)), projected[name]) < tau for x, y in points):
                tp += 1
            else:
                fp += 1
        return tp / (tp + fp + fn) if tp + fp + fn else 0.0

    original = score(lines_norm)
    mirrored = score({MIRRORED_CLASS[name]: points for name, points in lines_norm.items()})
    return original if original > mirrored else mirrored
