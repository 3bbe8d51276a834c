"""The ``bench accuracy`` and ``bench speed`` suites on a tiny configuration (code paths, not speed).

One 3-frame 1920x1080 clip (the size the weight-free detector is tuned for) is rendered
once by the accuracy suite and reused by the speed suite through the same --out folder.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from broadtrack_graph.benchmarks.accuracy import tripod_error
from broadtrack_graph.benchmarks.clips import clip_folder_name
from broadtrack_graph.benchmarks.speed import STAGES, stage_figures
from broadtrack_graph.cli import main
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.tripod_file import write_tripod

FRAMES = 3


@pytest.fixture(scope="module")
def bench_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("bench")


@pytest.fixture(scope="module")
def accuracy_report(bench_dir) -> dict:
    out = bench_dir / "report_accuracy.json"
    code = main(["bench", "accuracy", "--presets", "main", "--frames", str(FRAMES), "--modes", "online", "batch",
                 "--ablation", "flow:main", "--ablation-mode", "online",
                 "--out", str(bench_dir), "--json", str(out), "--no-progress"])
    assert code == 0
    return json.loads(out.read_text())


def test_accuracy_suite_scores_every_mode(accuracy_report, bench_dir):
    report = accuracy_report
    assert report["suite"] == "accuracy" and report["width_px"] == 1920 and report["height_px"] == 1080
    clip = Path(report["clips"]["main"]["path"])
    assert clip.name == clip_folder_name("main", FRAMES, 1920, 1080, 0)
    assert report["clips"]["main"]["rendered_now"] is True
    for mode in ("online", "batch"):
        figures = report["presets"]["main"][mode]
        assert figures["frames"] == FRAMES and figures["frames_with_camera"] == FRAMES
        assert figures["completeness"] == 1.0
        # A clean synthetic clip: the tracker must hit the lines (two-sided bands).
        assert 0.9 <= figures["jac_5"] <= figures["jac_10"] <= 1.0
        assert 0.0 < figures["medre_px"] <= figures["mre_px"] < 3.0
        assert 0.0 < figures["gt_pan_rms_deg"] < 1.0
        assert set(STAGES) <= set(figures["timings_s"])
    assert Path(report["presets"]["main"]["compare_md"]).is_file()
    assert (bench_dir / "compare" / "main" / "series.png").stat().st_size > 1000


def test_accuracy_suite_reports_the_batch_tripod_against_the_clip(accuracy_report, bench_dir):
    clip = Path(accuracy_report["clips"]["main"]["path"])
    truth = json.loads((clip / "tripod.json").read_text())
    batch = accuracy_report["presets"]["main"]["batch"]["tripod"]
    assert batch is not None, "batch mode writes tripod.json in its run folder"
    expected = sum((a - b) ** 2 for a, b in zip(batch["T_w"], truth["T_w"])) ** 0.5
    assert batch["T_error_m"] == pytest.approx(expected, abs=1e-3)
    assert batch["delta_error_m"] == pytest.approx(batch["delta_m"] - truth["delta_m"], abs=1e-3)
    # The figures are those of the run's own tripod.json (three frames do not determine a tripod:
    # no accuracy band here, the 200-frame benchmark measures it).
    written = json.loads((bench_dir / "runs" / "main" / "batch" / "tripod.json").read_text())
    assert batch["T_w"] == pytest.approx(written["T_w"], abs=1e-3)
    assert batch["delta_m"] == pytest.approx(written["delta_m"], abs=1e-3)
    assert batch["T_error_xy_m"] <= batch["T_error_m"]
    # Online on 3 frames never reaches the tripod fit: no tripod.json, no figure.
    assert accuracy_report["presets"]["main"]["online"]["tripod"] is None


def test_accuracy_suite_judges_every_written_camera_against_the_true_one(accuracy_report, bench_dir):
    from broadtrack_graph.benchmarks.reliability import run_reliability

    clip = Path(accuracy_report["clips"]["main"]["path"])
    for mode in ("online", "batch"):
        reliability = accuracy_report["presets"]["main"][mode]["reliability"]
        assert reliability["determinable_frames"] == FRAMES and reliability["cameras"] == FRAMES
        assert reliability["written_right_share"] == 1.0 and reliability["written_share"] == 1.0
        confident = [row for row in reliability["rows"] if row["cameras"]]
        assert confident and all(row["right_share"] == 1.0 for row in confident)
    pooled = accuracy_report["reliability"]["online"]
    assert pooled["cameras"] == FRAMES and pooled["written_right_share_of_determinable"] == 1.0
    # A run whose cameras are tilted by half a degree is wrong on every frame, whatever its confidence says.
    tilted = bench_dir / "tilted"
    shutil.copytree(bench_dir / "runs" / "main" / "online", tilted)
    records = [json.loads(line) for line in (tilted / "track.jsonl").read_text().splitlines()]
    for record in records:
        record["tilt_deg"] += 0.5
    (tilted / "track.jsonl").write_text("".join(json.dumps(record) + "\n" for record in records))
    judged = run_reliability(tilted, clip / "cameras")
    assert judged["cameras"] == FRAMES and judged["written_right_share"] == 0.0


def test_accuracy_ablation_reuses_the_full_run_and_switches_flow_off(accuracy_report, bench_dir):
    ablation = accuracy_report["ablation"]
    assert ablation["mode"] == "online" and set(ablation["factors"]) == {"flow"}
    flow = ablation["factors"]["flow"]
    assert flow["preset"] == "main" and flow["seed"] == 0
    # "with" in online mode is the preset's online run, tracked once.
    assert flow["with"]["jac_5"] == accuracy_report["presets"]["main"]["online"]["jac_5"]
    no_flow = json.loads((bench_dir / "runs" / "main" / "online-no-flow" / "summary.json").read_text())
    assert no_flow["run"]["config"]["use_flow"] is False and no_flow["run"]["config"]["use_tripod"] is True
    assert no_flow["timings_s"]["flow_s"] == 0.0
    assert 0.9 <= flow["without"]["jac_5"] <= 1.0
    assert flow["jac_5_gain"] == pytest.approx(flow["with"]["jac_5"] - flow["without"]["jac_5"], abs=1e-4)


def test_accuracy_ablation_names_factor_and_preset():
    from broadtrack_graph.benchmarks.accuracy import parse_ablation
    from broadtrack_graph.errors import InputError

    assert parse_ablation(["flow:hard:3", "k1:wide"], 7) == [("flow", "hard", 3), ("k1", "wide", 7)]
    for bad in ("flow", "focus:main", "tripod:nowhere", "flow:hard:x"):
        with pytest.raises(InputError, match="FACTOR:PRESET"):
            parse_ablation([bad])


def test_speed_suite_reuses_the_clip_and_accounts_for_the_wall_time(accuracy_report, bench_dir):
    out = bench_dir / "report_speed.json"
    assert main(["bench", "speed", "--frames", str(FRAMES), "--out", str(bench_dir), "--json", str(out),
                 "--no-progress"]) == 0
    report = json.loads(out.read_text())
    assert report["clip"]["rendered_now"] is False and report["clip"]["path"] == accuracy_report["clips"]["main"]["path"]
    assert report["opencv_threads"] == 1
    online = report["modes"]["online"]
    assert online["frames"] == FRAMES
    assert online["fps_wall"] == pytest.approx(FRAMES / online["wall_s"], rel=1e-2)
    stages = online["stages"]
    assert set(stages) == {s.removesuffix("_s") for s in STAGES} | {"other"}
    total = sum(s["total_s"] for s in stages.values())
    assert total == pytest.approx(online["wall_s"], abs=0.01)
    assert stages["detect"]["total_s"] > 0 and stages["solve"]["total_s"] > 0


def test_stage_figures_arithmetic():
    figures = stage_figures({"detect_s": 2.0, "flow_s": 0.5, "solve_s": 1.0, "confidence_s": 0.0, "reinit_s": 0.25,
                             "write_s": 0.25}, frames=10, wall_s=5.0)
    assert figures["detect"] == {"total_s": 2.0, "ms_per_frame": 200.0, "share_of_wall": 0.4, "fps": 5.0}
    assert figures["confidence"]["fps"] is None
    assert figures["other"]["total_s"] == pytest.approx(1.0)
    assert figures["other"]["ms_per_frame"] == pytest.approx(100.0)


def test_tripod_error_against_the_clip_tripod(tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    truth = tmp_path / "truth.json"
    write_tripod(truth, Tripod((0.0, 55.0, -12.0), 0.22))
    assert tripod_error(run, truth) is None
    write_tripod(run / "tripod.json", Tripod((3.0, 59.0, -13.0), 0.30))
    error = tripod_error(run, truth)
    assert error["T_error_m"] == pytest.approx((9 + 16 + 1) ** 0.5, abs=1e-4)
    assert error["T_error_xy_m"] == pytest.approx(5.0, abs=1e-4)
    assert error["T_error_z_m"] == pytest.approx(-1.0, abs=1e-4)
    assert error["delta_error_m"] == pytest.approx(0.08, abs=1e-4)


def test_a_crashing_run_is_reported_and_its_written_frames_kept(tmp_path, monkeypatch):
    import broadtrack_graph.actions.track as tracking
    from broadtrack_graph.benchmarks.accuracy import run_figures
    from broadtrack_graph.benchmarks.clips import track_clip
    from broadtrack_graph.track.config import TrackingConfig

    def crashing_track_input(clip, out_dir, config, detector, progress=True):
        out_dir.mkdir(parents=True)
        (out_dir / "track.jsonl").write_text('{"frame": 0}\n{"frame": 1}\n', encoding="utf-8")
        raise RuntimeError("\nIndeterminate linear system detected while working near variable\nmore text")

    monkeypatch.setattr(tracking, "track_input", crashing_track_input)
    tracked = track_clip(tmp_path / "clip", tmp_path / "run", TrackingConfig())
    assert tracked["error"] == "RuntimeError: Indeterminate linear system detected while working near variable"
    assert tracked["frames_written"] == 2 and tracked["summary"] == {} and tracked["reused"] is False
    figures = run_figures(None, tracked, None)
    assert figures["error"] == tracked["error"] and figures["frames_written"] == 2
