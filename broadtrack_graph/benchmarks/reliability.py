"""The reliability of a run's written cameras: its records' confidence against right or wrong.

Synthetic runs are judged against their clip's true cameras
(:func:`~broadtrack_graph.metrics.reliability.line_disagreement_px`); real runs by the
line-alignment check, in :mod:`broadtrack_graph.benchmarks.real_video`. The table itself:
:mod:`broadtrack_graph.metrics.reliability`.
"""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.geometry.template import TemplateSampling
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.metrics.reliability import line_disagreement_px, merged_summaries, reliability_summary

RIGHT_TAU_PX = 5.0
"""A synthetic camera is right when it lays every marking the true camera shows within this many pixels (at
960 x 540) of the true camera's projection of it (the SoccerNet metric's tightest threshold)."""


def run_reliability(run_dir: Path, truth_dir: Path, tau_px: float = RIGHT_TAU_PX) -> dict:
    """The reliability of one synthetic run against the true cameras of its clip.

    Returns:
        :func:`~broadtrack_graph.metrics.reliability.reliability_summary` of the written cameras on the frames whose
        true camera shows the pitch (``determinable_frames``), with ``written_share`` (share of those frames with a
        camera written) and ``written_right_share_of_determinable`` (share of those frames with a right camera
        written).
    """
    run, truth = read_track(run_dir), read_track(truth_dir)
    true_by_frame = {r.frame_id: r.camera for r in truth.records if r.camera is not None}
    sampling = TemplateSampling()
    confidence, right = [], []
    determinable = 0
    for record in run.records:
        true_camera = true_by_frame.get(record.frame_id)
        if true_camera is None:
            continue
        # The camera judged against the truth, or the truth against itself for a frame without a camera (None: the
        # true camera shows (almost) no marking, nothing to judge).
        error = line_disagreement_px(record.camera or true_camera, true_camera, sampling)
        if error is None:
            continue
        determinable += 1
        if record.camera is None:
            continue
        confidence.append(float("nan") if record.confidence is None else record.confidence)
        right.append(error < tau_px)
    summary = reliability_summary(confidence, right)
    summary["determinable_frames"] = determinable
    summary["written_share"] = round(len(right) / determinable, 4) if determinable else None
    summary["written_right_share_of_determinable"] = round(sum(right) / determinable, 4) if determinable else None
    summary["right_tau_px"] = tau_px
    return summary


def add_reliability(figures: dict, runs: dict[str, Path], truth_dir: Path) -> None:
    """Each run's reliability (:func:`run_reliability`) into its figures (``figures[name]["reliability"]``; None for a
    run that wrote nothing)."""
    for name, path in runs.items():
        entry = figures[name]
        entry["reliability"] = None if entry.get("frames") is None else run_reliability(path, truth_dir)


def pooled(summaries: list[dict]) -> dict | None:
    """Several runs' reliability added up (the rows; the shares of the determinable frames recomputed)."""
    merged = merged_summaries(summaries)
    if merged is None:
        return None
    determinable = sum(s.get("determinable_frames") or 0 for s in summaries if s)
    if determinable:
        merged["determinable_frames"] = determinable
        merged["written_share"] = round(merged["cameras"] / determinable, 4)
        right = sum(row["right"] for row in merged["rows"])
        merged["written_right_share_of_determinable"] = round(right / determinable, 4)
    return merged
