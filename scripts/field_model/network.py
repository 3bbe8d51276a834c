"""The field network: a small depthwise-separable encoder, a feature-pyramid decoder to stride 4, two heads.

Input (B, 3, H, W) RGB normalised as the contract says (ImageNet mean and std); H and W multiples of
32. Outputs at stride 4, (B, 57, H / 4, W / 4) keypoint heatmap logits (one per NBJW keypoint, sigmoid)
and (B, 27, H / 4, W / 4) line logits (background + the 26 SoccerNet classes, softmax). About 1 M
parameters (4 MB in float32); the 3x3 convolutions at stride 4 are depthwise-separable, so a
512x288 frame costs about 0.6 G multiply-adds.
"""

from __future__ import annotations

import torch
from torch import nn
from torch.nn import functional as F

KEYPOINTS = 57
LINE_CLASSES = 26


def conv_bn(c_in: int, c_out: int, stride: int = 1, kernel: int = 3, groups: int = 1) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(c_in, c_out, kernel, stride, kernel // 2, groups=groups, bias=False),
                         nn.BatchNorm2d(c_out), nn.ReLU6(inplace=True))


class InvertedResidual(nn.Module):
    """MobileNetV2's block: expand 1x1, depthwise 3x3, project 1x1 (linear), residual when shapes agree."""

    def __init__(self, c_in: int, c_out: int, stride: int, expand: int = 4):
        super().__init__()
        hidden = c_in * expand
        self.residual = stride == 1 and c_in == c_out
        self.body = nn.Sequential(
            conv_bn(c_in, hidden, kernel=1),
            conv_bn(hidden, hidden, stride=stride, groups=hidden),
            nn.Conv2d(hidden, c_out, 1, bias=False), nn.BatchNorm2d(c_out))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        y = self.body(x)
        return x + y if self.residual else y


def separable(c_in: int, c_out: int) -> nn.Sequential:
    """3x3 depthwise then 1x1: the cheap 3x3 convolution of the decoder and the heads."""
    return nn.Sequential(conv_bn(c_in, c_in, groups=c_in), conv_bn(c_in, c_out, kernel=1))


def stage(c_in: int, c_out: int, blocks: int, stride: int) -> nn.Sequential:
    return nn.Sequential(*[InvertedResidual(c_in if i == 0 else c_out, c_out, stride if i == 0 else 1)
                           for i in range(blocks)])


class FieldNet(nn.Module):
    """Encoder to stride 32, top-down pyramid back to stride 4 (64 channels), keypoint and line heads."""

    def __init__(self, width: int = 64):
        super().__init__()
        self.stem = conv_bn(3, 24, stride=2)                       # stride 2
        self.s4 = stage(24, 32, 2, 2)                              # stride 4
        self.s8 = stage(32, 48, 3, 2)                              # stride 8
        self.s16 = stage(48, 96, 4, 2)                             # stride 16
        self.s32 = stage(96, 160, 3, 2)                            # stride 32
        self.lateral = nn.ModuleList([nn.Conv2d(c, width, 1) for c in (32, 48, 96, 160)])
        self.smooth = nn.ModuleList([separable(width, width) for _ in range(3)])
        self.keypoint_head = nn.Sequential(separable(width, width), nn.Conv2d(width, KEYPOINTS, 1))
        self.line_head = nn.Sequential(separable(width, width), nn.Conv2d(width, LINE_CLASSES + 1, 1))
        nn.init.constant_(self.keypoint_head[-1].bias, -4.0)  # heatmaps start near 0 (most pixels are empty)

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        c4 = self.s4(self.stem(x))
        c8 = self.s8(c4)
        c16 = self.s16(c8)
        c32 = self.s32(c16)
        p = self.lateral[3](c32)
        for level, (skip, lateral) in enumerate(zip((c16, c8, c4), (self.lateral[2], self.lateral[1], self.lateral[0]))):
            p = F.interpolate(p, size=skip.shape[-2:], mode="bilinear", align_corners=False) + lateral(skip)
            p = self.smooth[level](p)
        return self.keypoint_head(p), self.line_head(p)
