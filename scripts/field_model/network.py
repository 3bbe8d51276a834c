"""The field network: a small residual encoder, a feature-pyramid decoder to stride 4, two heads.

Input (B, 3, H, W) RGB normalised as the contract says (ImageNet mean and std); H and W multiples of
32. Outputs at stride 4: (B, 57, H / 4, W / 4) keypoint heatmap logits (one per NBJW keypoint,
sigmoid) and (B, 27, H / 4, W / 4) line logits (background + the 26 SoccerNet classes, softmax).

About 1.0 M parameters (4 MB in float32). Plain 3x3 convolutions, not depthwise-separable ones: on
this project's 2-core CPU a training step of the depthwise MobileNetV2-style variant took 3.3 s
(batch 12 at 512x288) against 1.0 s for this one, at the same parameter count, and the forward
pass is as fast (36 ms on one thread in torch).
"""

from __future__ import annotations

import torch
from torch import nn
from torch.nn import functional as F

KEYPOINTS = 57
LINE_CLASSES = 26
ENCODER_CHANNELS = (16, 24, 48, 96, 128)
"""Channels at strides 2, 4, 8, 16 and 32."""
DECODER_WIDTH = 32


def conv_bn_relu(c_in: int, c_out: int, stride: int = 1) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(c_in, c_out, 3, stride, 1, bias=False), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True))


class BasicBlock(nn.Module):
    """ResNet's basic block: two 3x3 convolutions and a shortcut (1x1 when the shape changes)."""

    def __init__(self, c_in: int, c_out: int, stride: int):
        super().__init__()
        self.first = conv_bn_relu(c_in, c_out, stride)
        self.second = nn.Sequential(nn.Conv2d(c_out, c_out, 3, 1, 1, bias=False), nn.BatchNorm2d(c_out))
        self.shortcut = (nn.Identity() if c_in == c_out and stride == 1 else
                         nn.Sequential(nn.Conv2d(c_in, c_out, 1, stride, bias=False), nn.BatchNorm2d(c_out)))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return F.relu(self.second(self.first(x)) + self.shortcut(x))


class FieldNet(nn.Module):
    """Encoder to stride 32, top-down pyramid back to stride 4, keypoint and line heads."""

    def __init__(self, channels: tuple[int, ...] = ENCODER_CHANNELS, width: int = DECODER_WIDTH):
        super().__init__()
        c2, c4, c8, c16, c32 = channels
        self.stem = conv_bn_relu(3, c2, stride=2)
        self.s4 = BasicBlock(c2, c4, 2)
        self.s8 = nn.Sequential(BasicBlock(c4, c8, 2), BasicBlock(c8, c8, 1))
        self.s16 = nn.Sequential(BasicBlock(c8, c16, 2), BasicBlock(c16, c16, 1))
        self.s32 = nn.Sequential(BasicBlock(c16, c32, 2), BasicBlock(c32, c32, 1))
        self.lateral = nn.ModuleList([nn.Conv2d(c, width, 1) for c in (c4, c8, c16, c32)])
        self.smooth = nn.ModuleList([conv_bn_relu(width, width) for _ in range(3)])
        self.keypoint_head = nn.Sequential(conv_bn_relu(width, width), nn.Conv2d(width, KEYPOINTS, 1))
        self.line_head = nn.Sequential(conv_bn_relu(width, width), nn.Conv2d(width, LINE_CLASSES + 1, 1))
        nn.init.constant_(self.keypoint_head[-1].bias, -4.0)  # heatmaps start near 0 (most cells are empty)

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        c4 = self.s4(self.stem(x))
        c8 = self.s8(c4)
        c16 = self.s16(c8)
        c32 = self.s32(c16)
        p = self.lateral[3](c32)
        for level, skip in enumerate((c16, c8, c4)):
            p = F.interpolate(p, size=skip.shape[-2:], mode="bilinear", align_corners=False) + self.lateral[2 - level](skip)
            p = self.smooth[level](p)
        return self.keypoint_head(p), self.line_head(p)
