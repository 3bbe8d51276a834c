"""TOML option files: fields, the nested [flow] table, one-line errors, command-line overrides."""

from __future__ import annotations

import pytest

from broadtrack_graph.detect.flow import FlowConfig
from broadtrack_graph.errors import InputError
from broadtrack_graph.graph.config import SolverSettings
from broadtrack_graph.io.config_file import read_config_file
from broadtrack_graph.track.config import TrackingConfig


def write(tmp_path, text: str):
    path = tmp_path / "tracking.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_fields_and_nested_table(tmp_path):
    path = write(tmp_path, 'mode = "fixed-lag"\nlag_frames = 40\nconfidence_threshold = 1\nuse_flow = false\n'
                           '[flow]\ngrid_step_px = 20\nfb_max_px = 0.75\n')
    config = read_config_file(path, TrackingConfig)
    assert config == TrackingConfig(mode="fixed-lag", lag_frames=40, confidence_threshold=1.0, use_flow=False,
                                    flow=FlowConfig(grid_step_px=20, fb_max_px=0.75))
    assert isinstance(config.confidence_threshold, float)  # an integer is accepted as a number
    assert read_config_file(write(tmp_path, ""), TrackingConfig) == TrackingConfig()
    assert read_config_file(None, TrackingConfig) == TrackingConfig()
    # Repeated frames switched off: every frame solved.
    off = read_config_file(write(tmp_path, "[repeats]\nmax_changed_share = 0\n"), TrackingConfig)
    assert off.repeats.max_changed_share == 0.0 and off.repeats.work_width_px == 640


def test_unknown_key_names_file_and_key(tmp_path):
    path = write(tmp_path, "lag = 10\n")
    with pytest.raises(InputError, match=r"tracking.toml: unknown key 'lag' \(known: mode, lag_frames") as info:
        read_config_file(path, TrackingConfig)
    assert "\n" not in str(info.value)
    with pytest.raises(InputError, match="unknown key 'flow.step'"):
        read_config_file(write(tmp_path, "[flow]\nstep = 3\n"), TrackingConfig)


@pytest.mark.parametrize("text, message", [
    ("lag_frames = 2.5", "key 'lag_frames': expected an integer, got float 2.5"),
    ("lag_frames = true", "key 'lag_frames': expected an integer, got bool True"),
    ('use_flow = "no"', "key 'use_flow': expected true or false, got str 'no'"),
    ("mode = 1", "key 'mode': expected a string, got int 1"),
    ("flow = 3", r"key 'flow': expected a table \[flow\], got int"),
    ('[flow]\nfb_max_px = "x"', "key 'flow.fb_max_px': expected a number, got str 'x'"),
])
def test_wrong_type_names_file_and_key(tmp_path, text, message):
    with pytest.raises(InputError, match=message) as info:
        read_config_file(write(tmp_path, text), TrackingConfig)
    assert str(info.value).startswith(str(tmp_path / "tracking.toml") + ": ")


def test_value_rejected_by_the_dataclass_and_bad_files(tmp_path):
    with pytest.raises(InputError, match="tracking.toml: mode must be one of"):
        read_config_file(write(tmp_path, 'mode = "fast"'), TrackingConfig)
    with pytest.raises(InputError, match="tracking.toml: not a TOML file"):
        read_config_file(write(tmp_path, "mode = "), TrackingConfig)
    with pytest.raises(InputError, match="missing.toml: config file not found"):
        read_config_file(tmp_path / "missing.toml", TrackingConfig)


def test_optional_and_tuple_fields(tmp_path):
    path = write(tmp_path, "tripod_delta_prior_m = 0.3\nsingle_frame_cauchy_stages_per_width = [0.5, 1]\n")
    settings = read_config_file(path, SolverSettings)
    assert settings.tripod_delta_prior_m == 0.3 and settings.single_frame_cauchy_stages_per_width == (0.5, 1.0)
    with pytest.raises(InputError, match="expected a list of a number, got list"):
        read_config_file(write(tmp_path, 'single_frame_cauchy_stages_per_width = ["a"]'), SolverSettings)


def test_overrides_win_over_the_file(tmp_path):
    path = write(tmp_path, 'mode = "fixed-lag"\nlag_frames = 40\nuse_tripod = false\n[flow]\nwindow_px = 21\n')
    config = read_config_file(path, TrackingConfig, {"lag_frames": 10})
    assert (config.mode, config.lag_frames, config.use_tripod, config.flow.window_px) == ("fixed-lag", 10, False, 21)
    assert read_config_file(None, TrackingConfig, {"mode": "batch"}).mode == "batch"
    with pytest.raises(InputError, match="lag_frames must be >= 1"):
        read_config_file(path, TrackingConfig, {"lag_frames": 0})
