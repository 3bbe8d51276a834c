"""The demo reuses a rendered clip only when it is complete and made with the same settings."""

from __future__ import annotations

from broadtrack_graph.actions.demo import DemoSettings, folder_size_mb, reusable_clip
from broadtrack_graph.synth.writer import write_synthetic_clip

SMALL = DemoSettings(frames=3, width_px=320, height_px=180, seed=5)


def test_reusable_clip_matches_settings_and_completeness(tmp_path):
    clip = tmp_path / "clip"
    assert not reusable_clip(clip, SMALL)  # nothing there
    write_synthetic_clip(clip, preset=SMALL.preset, frame_count=SMALL.frames, width_px=SMALL.width_px,
                         height_px=SMALL.height_px, seed=SMALL.seed, write_masks=False, progress=False)
    assert reusable_clip(clip, SMALL)
    assert not reusable_clip(clip, DemoSettings(frames=3, width_px=320, height_px=180, seed=6))
    assert not reusable_clip(clip, DemoSettings(frames=4, width_px=320, height_px=180, seed=5))
    assert not reusable_clip(clip, DemoSettings(frames=3, width_px=640, height_px=360, seed=5))
    (clip / "img1" / "000002.jpg").unlink()  # a partial clip is rendered again
    assert not reusable_clip(clip, SMALL)


def test_folder_size_counts_files(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "x.bin").write_bytes(b"0" * 1_500_000)
    (tmp_path / "y.bin").write_bytes(b"0" * 500_000)
    assert folder_size_mb(tmp_path) == 2.0
