"""Training the field network on sample shards: targets, losses, the loop with checkpoints and resume.

Targets at stride 4 (the network's output): a Gaussian heatmap per visible keypoint (sigma
``HEATMAP_SIGMA`` output cells), and one line class per output cell (0 background, 1 + the index
of the SoccerNet class), the sample's 1-cell-wide line masks dilated to 3 cells. Losses: the
penalty-reduced focal loss of heatmap keypoint detectors on the keypoints, and cross-entropy on the
line classes with the background down-weighted. Everything is seeded; a checkpoint (model,
optimiser, step, data order) is written every ``checkpoint_minutes`` and at the end, and
``resume`` continues from it.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import cv2
import numpy as np
import torch
from torch.nn import functional as F
from torch.utils.data import DataLoader, Dataset

from field_model.network import KEYPOINTS, FieldNet
from field_model.shards import read_shard

MEAN = np.array([0.485, 0.456, 0.406], np.float32)
STD = np.array([0.229, 0.224, 0.225], np.float32)
STRIDE = 4
HEATMAP_SIGMA = 1.5
BACKGROUND_WEIGHT = 0.1


def image_tensor(image_bgr: np.ndarray) -> np.ndarray:
    """(H, W, 3) BGR uint8 -> (3, H, W) float32 RGB, normalised by the ImageNet mean and std."""
    rgb = image_bgr[:, :, ::-1].astype(np.float32) / 255.0
    return np.ascontiguousarray(((rgb - MEAN) / STD).transpose(2, 0, 1))


def keypoint_targets(keypoints_px: np.ndarray, visible: np.ndarray, out_h: int, out_w: int) -> np.ndarray:
    """(57, out_h, out_w) Gaussian heatmaps (peak 1 at each visible keypoint, in output cells)."""
    ys, xs = np.mgrid[0:out_h, 0:out_w].astype(np.float32)
    target = np.zeros((KEYPOINTS, out_h, out_w), np.float32)
    for k in np.flatnonzero(visible):
        cx, cy = (keypoints_px[k] + 0.5) / STRIDE - 0.5  # pixel centres -> output cell centres
        target[k] = np.exp(-((xs - cx) ** 2 + (ys - cy) ** 2) / (2 * HEATMAP_SIGMA ** 2))
    return target


def line_targets(line_masks: np.ndarray) -> np.ndarray:
    """(26, h, w) bool masks -> (h, w) int64 class map (0 background), each class dilated to 3 cells."""
    out = np.zeros(line_masks.shape[1:], np.int64)
    kernel = np.ones((3, 3), np.uint8)
    for c in range(line_masks.shape[0]):
        if line_masks[c].any():
            out[cv2.dilate(line_masks[c].astype(np.uint8), kernel) > 0] = c + 1
    return out


class ShardDataset(Dataset):
    """Every sample of the shards of a folder, held in memory (JPEG bytes and packed masks: about 80 kB a
    sample at 512x288), so that a shuffled order reads no shard twice."""

    def __init__(self, folder: Path):
        paths = sorted(p for p in Path(folder).glob("*.npz") if not p.name.endswith(".tmp.npz"))
        self.shards = [read_shard(p) for p in paths]
        self.offsets = np.cumsum([0] + [len(shard) for shard in self.shards])

    def __len__(self) -> int:
        return int(self.offsets[-1])

    def __getitem__(self, i: int):
        s = int(np.searchsorted(self.offsets, i, side="right") - 1)
        shard, j = self.shards[s], i - int(self.offsets[s])
        image = shard.image(j)
        h, w = image.shape[0] // STRIDE, image.shape[1] // STRIDE
        return (torch.from_numpy(image_tensor(image)),
                torch.from_numpy(keypoint_targets(shard.keypoints_px[j], shard.visible[j], h, w)),
                torch.from_numpy(line_targets(shard.line_masks(j))))


def focal_heatmap_loss(logits: torch.Tensor, target: torch.Tensor, alpha: float = 2.0, beta: float = 4.0) -> torch.Tensor:
    """Penalty-reduced pixel-wise focal loss, normalised by the number of keypoints (at least 1)."""
    p = torch.sigmoid(logits).clamp(1e-4, 1 - 1e-4)
    positive = target.ge(0.99).float()
    pos_loss = -torch.log(p) * (1 - p) ** alpha * positive
    neg_loss = -torch.log(1 - p) * p ** alpha * (1 - target) ** beta * (1 - positive)
    return (pos_loss.sum() + neg_loss.sum()) / positive.sum().clamp(min=1.0)


def line_loss(logits: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    weight = torch.ones(logits.shape[1])
    weight[0] = BACKGROUND_WEIGHT
    return F.cross_entropy(logits, target, weight=weight)


@dataclass
class TrainConfig:
    shards: str
    out: str
    steps: int = 20000
    batch: int = 12
    lr: float = 2e-3
    weight_decay: float = 1e-4
    hours: float = 2.5
    checkpoint_minutes: float = 10.0
    threads: int = 2
    workers: int = 1
    seed: int = 0


def train(config: TrainConfig, resume: bool = True, progress: bool = True) -> Path:
    """Train (or continue) and return the checkpoint path. Stops at ``steps`` or after ``hours`` of this call."""
    from tqdm import tqdm

    torch.set_num_threads(config.threads)
    out = Path(config.out)
    out.mkdir(parents=True, exist_ok=True)
    checkpoint = out / "checkpoint.pt"
    torch.manual_seed(config.seed)
    model = FieldNet()
    optimiser = torch.optim.AdamW(model.parameters(), lr=config.lr, weight_decay=config.weight_decay)
    step = 0
    if resume and checkpoint.exists():
        state = torch.load(checkpoint, map_location="cpu")
        model.load_state_dict(state["model"])
        optimiser.load_state_dict(state["optimiser"])
        step = int(state["step"])
    (out / "config.json").write_text(json.dumps(asdict(config), indent=1))
    dataset = ShardDataset(Path(config.shards))
    generator = torch.Generator().manual_seed(config.seed + step)  # a resumed run draws a new order
    loader = DataLoader(dataset, batch_size=config.batch, shuffle=True, generator=generator, drop_last=True,
                        num_workers=config.workers, persistent_workers=config.workers > 0)
    started, last_save = time.time(), time.time()
    log = (out / "log.jsonl").open("a", encoding="utf-8")

    def save() -> None:
        temporary = out / "checkpoint.pt.tmp"
        torch.save({"model": model.state_dict(), "optimiser": optimiser.state_dict(), "step": step}, temporary)
        temporary.replace(checkpoint)

    bar = tqdm(total=config.steps, initial=step, desc="train", unit="step", disable=not progress)
    model.train()
    while step < config.steps:
        for images, heatmaps, lines in loader:
            lr = config.lr * 0.5 * (1 + math.cos(math.pi * min(step / config.steps, 1.0)))
            for group in optimiser.param_groups:
                group["lr"] = lr
            keypoint_logits, line_logits = model(images)
            loss_k = focal_heatmap_loss(keypoint_logits, heatmaps)
            loss_l = line_loss(line_logits, lines)
            loss = loss_k + loss_l
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            step += 1
            bar.update(1)
            if step % 10 == 0:
                log.write(json.dumps({"step": step, "loss": loss.item(), "keypoints": loss_k.item(),
                                      "lines": loss_l.item(), "lr": lr, "elapsed_s": round(time.time() - started, 1)}) + "\n")
                log.flush()
                bar.set_postfix(loss=f"{loss.item():.3f}")
            if time.time() - last_save > 60 * config.checkpoint_minutes:
                save()
                last_save = time.time()
            if step >= config.steps or time.time() - started > 3600 * config.hours:
                break
        if time.time() - started > 3600 * config.hours:
            break
    save()
    bar.close()
    log.close()
    return checkpoint
