"""``bench real``: the shared real data end to end, each section run when its data is there.

Sections: real broadcast videos (:mod:`broadtrack_graph.benchmarks.real_video`).
"""

from __future__ import annotations

from broadtrack_graph.benchmarks import real_video

HELP = "real data end to end: real broadcast videos (alignment, re-initialisations, other views, cuts, fps)"

SECTIONS = (
    # (name, has_data(args), run(args) -> dict)
    ("video", real_video.has_video_data, real_video.run_video_clips),
)


def add_arguments(parser) -> None:
    real_video.add_video_arguments(parser)


def run(args) -> dict:
    report = {}
    for name, has_data, run_section in SECTIONS:
        report[name] = run_section(args) if has_data(args) else {"skipped": "no data"}
    return report
