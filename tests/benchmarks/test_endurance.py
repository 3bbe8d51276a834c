"""The ``bench endurance`` suite on a tiny configuration (code paths and sanity of the figures, not speed).

A 12-frame 480x270 segment of the ``long`` preset is rendered once and played back and
forth as a 60-frame clip, tracked in blocks of 20 frames, and a ``track`` subprocess on
the same clip is killed after 30 frames.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from broadtrack_graph.benchmarks.endurance_kill import check_interrupted_run
from broadtrack_graph.cli import main

FRAMES, UNIQUE, BLOCK = 60, 12, 20


@pytest.fixture(scope="module")
def bench(tmp_path_factory) -> tuple[dict, Path]:
    out = tmp_path_factory.mktemp("endurance")
    report_path = out / "report.json"
    code = main(["bench", "endurance", "--frames", str(FRAMES), "--unique-frames", str(UNIQUE), "--width", "480",
                 "--height", "270", "--block", str(BLOCK), "--eval-every", "2", "--out", str(out),
                 "--json", str(report_path), "--no-progress"])
    assert code == 0
    return json.loads(report_path.read_text()), out


def test_blocks_cover_every_frame_with_sane_figures(bench):
    report, out = bench
    assert report["suite"] == "endurance" and report["frames"] == FRAMES and report["unique_frames"] == UNIQUE
    assert report["clip"]["playback"] == "forwards-backwards"
    tracking = report["tracking"]
    assert tracking["frames"] == FRAMES
    blocks = report["blocks"]
    assert [b["first_frame"] for b in blocks] == [0, 20, 40] and all(b["frames"] == BLOCK for b in blocks)
    for b in blocks:
        assert 0.0 < b["ms"]["median"] <= b["ms"]["p90"] <= b["ms"]["max"] < 60_000.0
        assert 0.0 < b["cpu_ms_median"] < 60_000.0
        assert 50.0 < b["rss_mb"] < 20_000.0
        assert 0 <= b["reinitialisations"] <= BLOCK and 0 <= b["failed"] <= BLOCK
        assert b["scored_frames"] <= BLOCK // 2
        if b["jac_5"] is not None:
            assert 0.0 <= b["jac_5"] <= 1.0
    assert sum(b["reinitialisations"] for b in blocks) == tracking["reinitialisations"]
    flat = report["flatness"]
    assert flat["ms_ratio_last_to_first"] == pytest.approx(blocks[-1]["ms"]["median"] / blocks[0]["ms"]["median"], rel=1e-2)
    assert flat["rss_mb_end_of_first_block"] == blocks[0]["rss_mb"]
    assert flat["rss_growth_mb_after_first_block"] == pytest.approx(
        flat["rss_mb_last_block"] - flat["rss_mb_end_of_first_block"], abs=0.2)
    samples = report["rss_samples_mb"]
    assert [c for c, _ in samples] == [0, 20, 40, 60] and all(50.0 < mb < 20_000.0 for _, mb in samples)
    # The last block has no sample while frames flowed (the one at frame 60 comes after the prefetch
    # thread ended): its RSS is the last sample taken while they did.
    assert flat["rss_mb_last_block"] == samples[-2][1] and flat["rss_mb_after_last_frame"] == samples[-1][1]
    rows = (out / "per_frame.csv").read_text().splitlines()
    assert rows[0] == "frame,process_ms,cpu_ms,interval_ms" and len(rows) == FRAMES + 1
    assert Path(report["files"]["plot"]).stat().st_size > 5000


def test_the_killed_run_left_every_written_frame_readable(bench):
    report, out = bench
    killed = report["interrupted"]
    assert killed["killed"] is True and killed["returncode"] == -9
    assert FRAMES // 2 <= killed["lines_when_killed"] < FRAMES
    assert killed["track_records"] >= FRAMES // 2 and killed["track_records"] < FRAMES
    assert killed["summary_readable"] and killed["summary_complete"] is False
    assert killed["camera_files_unreadable"] == 0 and killed["track_error"] is None
    assert killed["all_readable"] and killed["counts_agree"] and killed["ok"]
    assert killed["camera_files"] >= killed["track_records_with_camera"]
    # The subprocess tracks the same frames as the timed run (identically when the code did not change meanwhile).
    assert killed["vs_full_run"]["frames_compared"] == killed["track_records"]
    assert len(killed["source_digest"]) == 12
    if killed["same_code_as_tracked_run"]:
        assert killed["vs_full_run"]["frames_with_other_status"] == 0
        assert killed["vs_full_run"]["max_pan_difference_deg"] == 0.0


def test_the_check_catches_a_broken_camera_file_and_a_missing_one(bench, tmp_path):
    import shutil

    _, out = bench
    run = tmp_path / "run"
    shutil.copytree(out / "runs" / "killed", run)
    files = sorted((run / "cameras").glob("camera_*.json"))
    assert len(files) >= 3
    files[0].write_text('{"pan_degrees": 1.0, ', encoding="utf-8")  # truncated
    os.remove(files[1])
    check = check_interrupted_run(run)
    assert check["camera_files_unreadable"] == 1 and not check["all_readable"]
    assert check["records_missing_camera_file"] == 1 and not check["counts_agree"] and not check["ok"]
