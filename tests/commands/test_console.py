"""The closing summary line, the exit code of a run without camera, SIGTERM, warnings on stderr."""

from __future__ import annotations

import logging
import os
import signal
from pathlib import Path

import broadtrack_graph.commands.track as track_command
from broadtrack_graph.cli import main
from broadtrack_graph.commands.console import EXIT_NO_CAMERA, run_summary_line
from broadtrack_graph.track.result import RunResult

COUNTS = {"tracked": 0, "reinitialised": 0, "no-pitch": 0, "no-detections": 260, "missing-frame": 0, "failed": 0,
          "motion-prior": 0}


def test_run_without_camera_exits_3_with_the_summary_line(monkeypatch, capsys):
    def fake(frames, out_dir, config, detector, **kwargs):
        logging.getLogger("broadtrack_graph.io.detections").warning("x.jsonl:1: unknown line class 'Foo' skipped")
        return RunResult(Path(out_dir), {"frames_written": 260, "fps": 5.0, "status_counts": COUNTS}, [], None)

    monkeypatch.setattr(track_command, "track_input", fake)
    assert main(["track", "clip", "--out", "run", "--no-progress"]) == EXIT_NO_CAMERA == 3
    captured = capsys.readouterr()
    assert captured.out.splitlines()[-1] == "track: 260 frames, 0 cameras (no-detections 260), 2 warnings"
    assert "WARNING broadtrack_graph.io.detections: x.jsonl:1: unknown line class 'Foo' skipped" in captured.err
    assert "produced no camera in 260 frames" in captured.err  # the error itself is counted as a warning too


def test_summary_line_counts_statuses():
    summary = {"frames_written": 62, "status_counts": {"tracked": 50, "reinitialised": 8, "motion-prior": 4,
                                                       "failed": 0}, "interrupted": True}
    assert run_summary_line("track", summary).startswith(
        "track: INTERRUPTED 62 frames, 58 cameras (tracked 50, reinitialised 8, motion-prior 4), ")


def test_sigterm_ends_like_ctrl_c(monkeypatch, capsys):
    def killed(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        raise AssertionError("SIGTERM did not stop the run")

    monkeypatch.setattr(track_command, "track_input", killed)
    assert main(["track", "clip", "--out", "run", "--no-progress"]) == 130
    assert "interrupted; files written so far are kept" in capsys.readouterr().err
    assert signal.getsignal(signal.SIGTERM) is not None  # the previous handler is back


def test_ffmpeg_log_is_quiet_before_cv2_import():
    import broadtrack_graph.cli  # noqa: F401  (sets the variables at import)

    assert os.environ["OPENCV_FFMPEG_LOGLEVEL"] and os.environ["OPENCV_LOG_LEVEL"]


def test_no_progress_bar_when_stderr_is_not_a_terminal(monkeypatch, capsys):
    seen = []

    def fake(frames, out_dir, config, detector, **kwargs):
        seen.append(kwargs["progress"])
        return RunResult(Path(out_dir), {"frames_written": 1, "status_counts": {"tracked": 1}}, [], None)

    monkeypatch.setattr(track_command, "track_input", fake)
    assert main(["track", "clip", "--out", "run"]) == 0  # capsys: stderr is not a terminal
    assert seen == [False]  # a bar's carriage returns would share lines with the warnings in a log file
