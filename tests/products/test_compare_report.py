"""The comparison table: one aligned row per figure, one column per run."""

from __future__ import annotations

from broadtrack_graph.products.compare_report import format_table


def test_format_table_columns():
    report = {"runs": {"a": {"frames": 3, "frames_with_camera": 2, "reinitialisations": 0, "mean_confidence": None,
                             "jitter": {k: {"rms_d1": 1.0, "rms_d2": None} for k in ("pan_deg", "tilt_deg", "focal_px")},
                             "focal_point": {"std_m": [1, 2, 3], "extent_m": [4, 5, 6], "rms_to_mean_m": 7.0}}}}
    table = format_table(report)
    lines = table.split("\n")
    assert len({len(line) for line in lines}) == 1  # aligned
    assert "| frames / with camera" in table and "3 / 2" in table and "| C extent z (m)" in table
