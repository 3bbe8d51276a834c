"""The frames of ``bench placements --random N``: a random camera each, rendered by one of two renderers.

``synth``: the project's synthetic renderer under a named look (:mod:`broadtrack_graph.synth.named_looks`) with
simulated players. ``plain``: a renderer written apart from it (:mod:`broadtrack_graph.synth.plain`: the markings
from the Laws of the Game's dimensions, mown stripes, a crowd of coloured blocks, ellipse players, blur, noise and
JPEG drawn per frame), to measure the single-frame calibrator on views it was not tuned on. The camera of frame i of
a seed is the same under both renderers.
"""

from __future__ import annotations

import time

import numpy as np

RENDERERS = ("synth", "plain")
RANDOM_STREAM = 7311
"""Random stream of the frames (numpy SeedSequence entropy [seed, frame, RANDOM_STREAM, part])."""
VISIBLE_PAINT_LEVELS = 8.0
"""Least change of grey level (0-255, at the detector's 960 px working width) the paint must make to be seen."""


def draw_frame(seed: int, index: int, width_px: int, height_px: int, looks, renderer: str = "synth") -> dict:
    """Frame ``index`` of a seed: its random camera, look, players and image (the same for the same arguments).

    Returns {"drawn": RandomCamera, "renderer", "look_name", "look": Look or PlainLook, "players": PlayerTrack (None
    for ``plain``, whose look draws its own), "image": (H, W, 3) BGR, "render_s": seconds}; ``plain`` adds "ground",
    its pixels' ground points (:func:`~broadtrack_graph.synth.plain.ground_of_pixels`), for :func:`visible_paint`.
    """
    from broadtrack_graph.benchmarks.random_cameras import draw_random_camera

    drawn = draw_random_camera(np.random.default_rng([seed, index, RANDOM_STREAM, 0]), width_px, height_px)
    look_rng = np.random.default_rng([seed, index, RANDOM_STREAM, 1])
    if renderer == "plain":
        from broadtrack_graph.synth.plain import draw_plain_look, ground_of_pixels, render_plain

        look = draw_plain_look(look_rng)
        started = time.perf_counter()
        ground = ground_of_pixels(drawn.camera)
        image = render_plain(drawn.camera, look, ground)
        return {"drawn": drawn, "renderer": renderer, "look_name": "plain", "look": look, "players": None,
                "image": image, "render_s": time.perf_counter() - started, "ground": ground}
    if renderer != "synth":
        raise ValueError(f"unknown renderer '{renderer}'; choose from {list(RENDERERS)}")
    from broadtrack_graph.synth.field_samples import render_look
    from broadtrack_graph.synth.named_looks import draw_named_look, named_look
    from broadtrack_graph.synth.scene import simulate_players

    look_name = str(looks[int(look_rng.integers(len(looks)))])
    look = draw_named_look(look_name, look_rng, drawn.aim_w)
    people = np.random.default_rng([seed, index, RANDOM_STREAM, 2])
    count, spread = int(people.integers(12, 23)), float(people.uniform(8.0, 24.0))
    players = simulate_players(drawn.aim_w[None], count, spread, int(people.integers(1 << 31)))
    started = time.perf_counter()
    image = render_look(drawn.camera, players, look, named_look(look_name)).image
    return {"drawn": drawn, "renderer": renderer, "look_name": look_name, "look": look, "players": players,
            "image": image, "render_s": time.perf_counter() - started}


def visible_paint(frame: dict, work_width_px: int | None = None) -> np.ndarray:
    """(h, w) bool map at the working width of where a frame's paint shows: the frame of :func:`draw_frame` rendered
    again with the paint left off (the same camera, players, look, noise and compression) and the grey levels
    compared after both are reduced to the working width (the detector's, by default; at most the frame's own)."""
    import dataclasses

    from broadtrack_graph.detect.weightfree_config import REFERENCE_WIDTH_PX
    from broadtrack_graph.shots.repeats import reduced_grey

    work_width_px = work_width_px or REFERENCE_WIDTH_PX
    if frame.get("renderer", "synth") == "plain":
        from broadtrack_graph.synth.plain import render_plain, unpainted

        bare = render_plain(frame["drawn"].camera, unpainted(frame["look"]), frame.get("ground"))
    else:
        from broadtrack_graph.synth.field_samples import render_look
        from broadtrack_graph.synth.named_looks import named_look

        without_paint = dataclasses.replace(frame["look"], line_half_width_m=1e-4)
        bare = render_look(frame["drawn"].camera, frame["players"], without_paint, named_look(frame["look_name"])).image
    painted, plain = (reduced_grey(image, work_width_px).astype(np.int16) for image in (frame["image"], bare))
    return np.abs(painted - plain) >= VISIBLE_PAINT_LEVELS
