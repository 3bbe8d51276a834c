"""Training shards of the field model (scripts/field_model/shards.py): written, read back, resumable. No torch."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))

from field_model.shards import ShardSpec, make_shard, read_shard, shard_specs  # noqa: E402

from broadtrack_graph.synth.field_samples import sample_field  # noqa: E402


def test_a_shard_reads_back_its_samples(tmp_path):
    spec = ShardSpec(seed=3, first_index=5, count=2, width_px=128, height_px=72)
    path = make_shard(spec, tmp_path)
    shard = read_shard(path)
    assert len(shard) == 2 and not list(tmp_path.glob("*.tmp.npz"))
    for j, index in enumerate((5, 6)):
        sample = sample_field(3, index, 128, 72)
        assert np.array_equal(shard.line_masks(j), sample.line_masks.astype(bool))
        np.testing.assert_array_equal(shard.visible[j], sample.keypoint_visible)
        np.testing.assert_allclose(shard.keypoints_px[j], sample.keypoints_px, equal_nan=True, atol=1e-4)
        assert shard.negative[j] == (sample.camera is None) and shard.kinds[j] == sample.kind
        # JPEG at quality 95: close to the rendered frame
        assert np.abs(shard.image(j).astype(int) - sample.image_bgr.astype(int)).mean() < 4.0
    # An existing shard is kept (generation resumes where it stopped).
    stamp = path.stat().st_mtime_ns
    assert make_shard(spec, tmp_path) == path and path.stat().st_mtime_ns == stamp


def test_shard_specs_cover_the_samples_once():
    specs = shard_specs(1, 250, 512, 288)
    assert [(s.first_index, s.count) for s in specs] == [(0, 100), (100, 100), (200, 50)]
    assert len({s.name for s in specs}) == 3
