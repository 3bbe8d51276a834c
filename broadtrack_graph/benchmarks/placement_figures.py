"""The figures of a ``bench placements --random N`` report, counted from its frames' rows: per route, overall, by
where the camera stands, by height and by look, each with its misses by cause; and the few lines printed for a
human. No I/O.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.benchmarks.placement_found import (
    SHARP_SMEAR_PX,
    found_by_tophat_contrast,
    paint_found_by_width,
    smear_estimates,
    smear_found_by_contrast,
)
from broadtrack_graph.benchmarks.placement_misses import MISS_CAUSES, markings_detected, miss_cause, truth_written

OUTCOMES = ("found", "near", "wrong", "none")
"""A route's outcomes on a frame (``random_placements.outcome``)."""


def _seconds(values) -> dict:
    values = np.asarray(values, float)
    if not len(values):
        return {"median": None, "p95": None}
    return {"median": round(float(np.median(values)), 3), "p95": round(float(np.percentile(values, 95)), 3)}


def route_figures(rows: list[dict], route: str) -> dict:
    """Counts and shares (% of the rows) of each outcome of a route, wrong twins (and found or twin, wrong but not a
    twin), frames whose true camera is confident enough to be written (what a route can reach at most), and the
    route's seconds per frame."""
    results = [row["routes"][route] for row in rows]
    n = len(results)
    out: dict = {"frames": n}
    for name in OUTCOMES:
        k = sum(r["outcome"] == name for r in results)
        out[name], out[f"{name}_pct"] = k, round(100.0 * k / n, 1) if n else None
    twins = [r["outcome"] == "wrong" and bool(r.get("twin")) for r in results]
    out["wrong_twin"] = sum(twins)
    # Found or its twin: what SoccerNet's own metric scores as right (it keeps the mirrored labelling of a frame);
    # and the wrong cameras that are not twins (a camera near the twin is near: twin_outcome).
    out["found_or_twin"] = out["found"] + out["wrong_twin"]
    out["wrong_not_twin"] = out["wrong"] - out["wrong_twin"]
    for name in ("wrong_twin", "found_or_twin", "wrong_not_twin"):
        out[f"{name}_pct"] = round(100.0 * out[name] / n, 1) if n else None
    written = [truth_written(row, route) for row in rows]
    out["truth_written"] = sum(written)
    detected = [markings_detected(row, route) for row in rows]
    out["markings_detected"] = sum(detected)
    # The frames whose visible paint fixes the camera (the paint changes the grey level enough where it shows):
    # how many, and found or twin, and wrong but not a twin, as shares of those.
    visible = [bool(row.get("markings_visible")) for row in rows]
    out["markings_visible"] = sum(visible)
    right = [r["outcome"] == "found" or twin for r, twin in zip(results, twins)]
    wrong_not_twin = [r["outcome"] == "wrong" and not twin for r, twin in zip(results, twins)]
    for name, hits in (("found_or_twin", right), ("wrong_not_twin", wrong_not_twin)):
        out[f"{name}_of_visible_pct"] = round(100.0 * sum(
            hit for hit, shown in zip(hits, visible) if shown) / out["markings_visible"], 1) \
            if out["markings_visible"] else None
    # What the route can reach: frames whose detected markings fix the true camera, confident enough to be written
    # (on the markings as found or on the route's second look, placement_misses).
    reachable = [seen and can for seen, can in zip(detected, written)]
    out["reachable"] = sum(reachable)
    out["found_or_twin_of_reachable_pct"] = round(100.0 * sum(
        ok for ok, can in zip(right, reachable) if can) / out["reachable"], 1) if out["reachable"] else None
    out["misses_by_cause"] = dict.fromkeys(MISS_CAUSES, 0)
    for row, ok in zip(rows, right):
        if not ok:
            out["misses_by_cause"][miss_cause(row, route)] += 1
    out["seconds"] = _seconds([r["seconds"] for r in results])
    return out


def look_group(row: dict) -> str:
    """The look a frame is counted under (``by_look``): the synthetic renderer's named look; the plain renderer's
    frames by whether their look smears them (``plain, motion blur``: a motion blur drawn, over a pixel long; else
    ``plain, sharp``; :data:`~.placement_found.SHARP_SMEAR_PX`)."""
    plain = row.get("plain_look")
    if plain is not None:
        return "plain, motion blur" if plain.get("motion_blur_px", 0.0) > SHARP_SMEAR_PX else "plain, sharp"
    return row["look"]


def summarise(rows: list[dict], routes: list[str], width_px: int | None = None) -> dict:
    """The report's figures: counted frames per route overall, by stand, by height and by look; uncounted frames
    apart; with the frames' width, the plain renderer's smears against the detector's reading of them
    (:func:`~.placement_found.smear_estimates`)."""
    from broadtrack_graph.benchmarks.random_cameras import LOW_HEIGHT_M, STANDS

    counted = [row for row in rows if row["determinable"]]
    apart = [row for row in rows if not row["determinable"]]
    groups = {"by_stand": {stand: [r for r in counted if r["class"] == stand] for stand in STANDS},
              "by_height": {f"low (< {LOW_HEIGHT_M:g} m)": [r for r in counted if r["low"]],
                            f"{LOW_HEIGHT_M:g} m and up": [r for r in counted if not r["low"]]},
              "by_look": {look: [r for r in counted if look_group(r) == look]
                          for look in sorted({look_group(r) for r in counted})}}
    by_route = {}
    for route in routes:
        by_route[route] = {"determinable": route_figures(counted, route),
                           **{name: {key: route_figures(members, route) for key, members in group.items()}
                              for name, group in groups.items()},
                           "not_determinable": route_figures(apart, route)}
    return {"determinable": len(counted), "not_determinable": len(apart),
            # what the tracker's shot step reads as another view (the court model alone looks at it there)
            "other_view": {"determinable": sum(bool(r.get("view", {}).get("other_view")) for r in counted),
                           **{stand: sum(bool(r.get("view", {}).get("other_view")) for r in counted
                                         if r["class"] == stand) for stand in STANDS}},
            "not_determinable_by_stand": {stand: sum(r["class"] == stand for r in apart) for stand in STANDS},
            "render_s": _seconds([row["render_s"] for row in rows]),
            "detect_s": _seconds([row["detect_s"] for row in rows]), "by_route": by_route,
            "paint_found_by_width": paint_found_by_width(rows),
            "found_by_tophat_contrast": found_by_tophat_contrast(rows),
            "smear_found_by_contrast": smear_found_by_contrast(rows),
            "smear_estimates": smear_estimates(rows, width_px) if width_px else {}}


def summary_table(report: dict) -> str:
    """A few lines for a human (stderr): per route and group, the shares of the counted frames and the seconds."""
    lines = [f"{report['frames']} frames ({report.get('renderer', 'synth')} renderer), {report['determinable']} "
             f"determinable ({report['not_determinable']} apart); render {report['render_s']['median']} s, detect "
             f"{report['detect_s']['median']} s median"]
    lines.append(f"{'route':<7} {'group':<18} {'frames':>6} {'found%':>7} {'wrong%':>7} {'twin%':>6} {'near%':>6} "
                 f"{'none%':>6} {'f+twin%':>7} {'s med':>6} {'s p95':>6} {'visible':>7} {'marks ok':>8} "
                 f"{'truth ok':>8}")
    for route, figures in report["by_route"].items():
        groups = {"all": figures["determinable"], **figures["by_stand"], **figures["by_height"],
                  **figures.get("by_look", {}), "not determinable": figures["not_determinable"]}
        for name, f in groups.items():
            pct = [("-" if f[f"{o}_pct"] is None else f"{f[f'{o}_pct']:.1f}")
                   for o in ("found", "wrong", "wrong_twin", "near", "none", "found_or_twin")]
            seconds = [("-" if f["seconds"][k] is None else f"{f['seconds'][k]:.2f}") for k in ("median", "p95")]
            lines.append(f"{route:<7} {name:<18} {f['frames']:>6} {pct[0]:>7} {pct[1]:>7} {pct[2]:>6} {pct[3]:>6} "
                         f"{pct[4]:>6} {pct[5]:>7} {seconds[0]:>6} {seconds[1]:>6} {f['markings_visible']:>7} "
                         f"{f['markings_detected']:>8} "
                         f"{f['truth_written']:>8}")
        f = figures["determinable"]
        causes = ", ".join(f"{MISS_CAUSES[cause]} {count}" for cause, count in f["misses_by_cause"].items())
        lines.append(f"{route:<7} determinable misses by cause: {causes}; found or twin of the {f['reachable']} "
                     f"reachable (markings fix the truth, truth written): {f['found_or_twin_of_reachable_pct']} %; "
                     f"of the {f['markings_visible']} whose visible paint fixes it: found or twin "
                     f"{f['found_or_twin_of_visible_pct']} %, wrong (not twins) {f['wrong_not_twin_of_visible_pct']} %")
    smears = report.get("smear_estimates")
    if smears:
        long, short, sharp = smears["long"], smears["short"], smears["sharp"]
        lines.append(f"smears drawn long enough to read: {long['frames']}, read as drawn {long['as_drawn']}, otherwise "
                     f"{long['otherwise']}, not read {long['not_read']}; read smeared: {short['read_smeared']} of "
                     f"{short['frames']} shorter, {sharp['read_smeared']} of {sharp['frames']} sharp")
    for note in report["skipped_routes"].values():
        lines.append(note)
    return "\n".join(lines)
