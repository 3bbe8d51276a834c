"""Training samples on disk: shards of :func:`broadtrack_graph.synth.field_samples.sample_field`.

A shard is one ``.npz`` file of ``SHARD_SIZE`` consecutive sample indices of one seed::

    images        (N,) object array of JPEG bytes (quality 95) of (H, W, 3) BGR frames
    keypoints_px  (N, 57, 2) float32 pixels at (W, H); NaN where unknown
    visible       (N, 57) bool
    line_masks    (N, 26, H / 4, W / 4) bool, packed along the last axis (np.packbits)
    negative      (N,) bool: a close-up or crowd view (no camera)
    kinds         (N,) str

Shards are written to a temporary name and renamed, so an interrupted generation leaves only
whole shards and starts again where it stopped. No torch here.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.synth.field_samples import HELD_OUT_SEED, TRAIN_SEED  # noqa: F401  (the seeds live there)

SHARD_SIZE = 100
"""Samples per shard."""


JPEG_QUALITY = 95


@dataclass(frozen=True)
class ShardSpec:
    """Which samples a shard holds and at what size."""

    seed: int
    first_index: int
    count: int
    width_px: int
    height_px: int

    @property
    def name(self) -> str:
        return f"seed{self.seed}-{self.width_px}x{self.height_px}-{self.first_index:07d}.npz"


def make_shard(spec: ShardSpec, folder: Path) -> Path:
    """Render the shard's samples and write it (atomically) into folder; returns its path."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    cv2.setNumThreads(1)
    from broadtrack_graph.synth.field_samples import sample_field

    path = folder / spec.name
    if path.exists():
        return path
    images, keypoints, visible, masks, negative, kinds = [], [], [], [], [], []
    for index in range(spec.first_index, spec.first_index + spec.count):
        sample = sample_field(spec.seed, index, spec.width_px, spec.height_px)
        ok, jpeg = cv2.imencode(".jpg", sample.image_bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        assert ok, "JPEG encoding failed"
        images.append(jpeg.tobytes())
        keypoints.append(sample.keypoints_px.astype(np.float32))
        visible.append(sample.keypoint_visible)
        masks.append(np.packbits(sample.line_masks.astype(bool), axis=-1))
        negative.append(sample.camera is None)
        kinds.append(sample.kind)
    data = {"images": np.array(images, dtype=object), "keypoints_px": np.stack(keypoints),
            "visible": np.stack(visible), "line_masks": np.stack(masks), "negative": np.array(negative),
            "kinds": np.array(kinds), "mask_width": np.array(spec.width_px // 4)}
    temporary = folder / (spec.name + ".tmp.npz")
    np.savez(temporary, **data)
    temporary.replace(path)
    return path


def shard_specs(seed: int, samples: int, width_px: int, height_px: int) -> list[ShardSpec]:
    """The shards holding samples 0 .. samples - 1 of a seed."""
    return [ShardSpec(seed, first, min(SHARD_SIZE, samples - first), width_px, height_px)
            for first in range(0, samples, SHARD_SIZE)]


def generate(folder: Path, seed: int, samples: int, width_px: int, height_px: int, workers: int = 2,
             progress: bool = True) -> list[Path]:
    """Make every missing shard of (seed, samples) in folder, ``workers`` processes; returns the shard paths."""
    from tqdm import tqdm

    folder.mkdir(parents=True, exist_ok=True)
    specs = shard_specs(seed, samples, width_px, height_px)
    missing = [s for s in specs if not (folder / s.name).exists()]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        for _ in tqdm(pool.map(make_shard, missing, [folder] * len(missing)), total=len(missing),
                      desc=f"shards seed {seed}", unit="shard", disable=not progress):
            pass
    return [folder / s.name for s in specs]


@dataclass
class Shard:
    """A shard read back (see the module docstring), images decoded on demand."""

    images: np.ndarray
    keypoints_px: np.ndarray
    visible: np.ndarray
    packed_masks: np.ndarray
    negative: np.ndarray
    kinds: np.ndarray
    mask_width: int

    def __len__(self) -> int:
        return len(self.images)

    def image(self, i: int) -> np.ndarray:
        """(H, W, 3) BGR uint8."""
        return cv2.imdecode(np.frombuffer(self.images[i], np.uint8), cv2.IMREAD_COLOR)

    def line_masks(self, i: int) -> np.ndarray:
        """(26, H / 4, W / 4) bool."""
        return np.unpackbits(self.packed_masks[i], axis=-1, count=self.mask_width).astype(bool)


def read_shard(path: Path) -> Shard:
    with np.load(path, allow_pickle=True) as data:
        return Shard(data["images"], data["keypoints_px"], data["visible"], data["line_masks"], data["negative"],
                     data["kinds"], int(data["mask_width"]))
