"""Synthetic clips in memory: camera track + players -> rendered frames with exact ground truth.

``render_clip`` returns a whole clip (for tests, keep it small: 480x270, ~10 frames);
``iter_clip_frames`` yields frame after frame (the clip writer uses it to write as it
goes). Everything is deterministic for a given seed. No I/O here
(:mod:`broadtrack_graph.synth.writer` writes clip folders).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator, Sequence

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.synth.annotate import Annotator
from broadtrack_graph.synth.motion import FPS, generate_camera_track
from broadtrack_graph.synth.presets import PRESETS, get_preset
from broadtrack_graph.synth.render import Renderer, RenderSettings
from broadtrack_graph.synth.scene import PlayerTrack, simulate_players
from broadtrack_graph.types.observations import FrameObservations, KeypointObservations

IN_MEMORY_SETTINGS = RenderSettings(jpeg_quality=90)
"""Default effects of in-memory clips: like the files, which are JPEG (quality 90)."""


def frame_id(index: int) -> str:
    """SoccerNet game-state image stem of the 0-based frame index: 0 -> "000001"."""
    return f"{index + 1:06d}"


@dataclass
class SyntheticFrame:
    """One rendered frame and its ground truth.

    index: 0-based position in the clip; frame_id: "000001"-style image stem.
    image: (H, W, 3) BGR uint8.
    camera: ground-truth camera at (W, H).
    lines_norm: SoccerNet annotation (class -> (N, 2) normalised points).
    occluded_classes: classes in the image but fully hidden, annotated from geometry.
    folded_classes: classes only folded into the image by a k1 < 0 model, not annotated (annotate.FrameTruth).
    keypoints_px: visible template keypoints, name -> (2,) pixels.
    mask: (H, W) uint8 line-class mask (LINE_CLASSES index + 1, 0 = none), or None.
    player_boxes_px: (M, 5) [player index, x0, y0, x1, y1] pixels.
    labels: (H, W) uint8 surface labels (drawing.SURFACE_*).
    """

    index: int
    frame_id: str
    image: np.ndarray
    camera: Camera
    lines_norm: dict[str, np.ndarray]
    occluded_classes: list[str]
    keypoints_px: dict[str, np.ndarray]
    mask: np.ndarray | None
    player_boxes_px: np.ndarray
    labels: np.ndarray
    folded_classes: list[str] = field(default_factory=list)

    def observations(self) -> FrameObservations:
        """The ground truth as the tracker's FrameObservations (perfect detections, no flow)."""
        W, H = self.camera.width_px, self.camera.height_px
        scale = np.array([W - 1.0, H - 1.0])
        lines_px = {name: points * scale for name, points in self.lines_norm.items()
                    if name not in self.occluded_classes}
        names = list(self.keypoints_px)
        pitch = _PITCH
        keypoints = KeypointObservations(
            uv_px=np.array([self.keypoints_px[n] for n in names], dtype=float).reshape(-1, 2),
            points_w=pitch.keypoint_array(names), confidence=np.ones(len(names)), names=names,
        )
        return FrameObservations(
            frame_index=self.index, width_px=W, height_px=H, lines_px=lines_px, keypoints=keypoints,
            marking_mask=None if self.mask is None else self.mask > 0,
            player_boxes_px=self.player_boxes_px[:, 1:5].copy(),
        )


_PITCH = PitchTemplate()


@dataclass
class SyntheticClip:
    """A rendered clip held in memory.

    frames: the frames in order.
    tripod: the tripod of a generated track (None for a given camera track).
    lambdas_m: (F,) lambda per frame for a generated track, else None.
    players: the player track that was rendered.
    """

    frames: list[SyntheticFrame]
    width_px: int
    height_px: int
    fps: float
    preset: str
    seed: int
    tripod: Tripod | None = None
    lambdas_m: np.ndarray | None = None
    players: PlayerTrack | None = None
    info: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.frames)

    @property
    def images(self) -> list[np.ndarray]:
        return [f.image for f in self.frames]

    @property
    def cameras(self) -> list[Camera]:
        return [f.camera for f in self.frames]

    @property
    def annotations(self) -> dict[str, dict[str, np.ndarray]]:
        """frame id -> normalised SoccerNet annotation (the evaluator's input).

        Frames that show no marking at all (a tight zoom on plain grass) have no annotation,
        as in SoccerNet, and are left out: the metric cannot score them.
        """
        return {f.frame_id: f.lines_norm for f in self.frames if f.lines_norm}


def play_from_cameras(cameras: Sequence[Camera]) -> np.ndarray:
    """(F, 3) a play position per frame for a given track: where the image centre meets the ground."""
    out = np.zeros((len(cameras), 3))
    last = np.zeros(3)
    for i, camera in enumerate(cameras):
        centre = np.array([[camera.width_px / 2.0, camera.height_px / 2.0]])
        point, hit = camera.ground_intersection(centre)
        if hit[0] and abs(point[0, 0]) < 60 and abs(point[0, 1]) < 40:
            last = point[0].copy()
        out[i] = last
    return out


def iter_clip_frames(
    cameras: Sequence[Camera],
    width_px: int,
    height_px: int,
    seed: int = 0,
    players: PlayerTrack | None = None,
    settings: RenderSettings = RenderSettings(),
    want_masks: bool = True,
    cut_frames: frozenset[int] = frozenset(),
) -> Iterator[SyntheticFrame]:
    """Render frames along a camera track, one at a time, with their ground truth.

    Args:
        cameras: one camera per frame (rescaled to width_px x height_px; k1-only distortion).
        width_px, height_px: image size.
        seed: seed of textures, lighting and noise.
        players: players to draw (None: no players).
        settings: image formation effects.
        want_masks: also build the per-class masks (costs ~10 ms per HD frame).
        cut_frames: indices of frames that start a shot after a hard cut (no motion blur from the frame before).
    """
    renderer = Renderer(width_px, height_px, seed=seed, settings=settings)
    annotator = Annotator()
    previous = None
    for index, camera in enumerate(cameras):
        if index in cut_frames:
            previous = None
        camera = camera.rescaled(width_px, height_px)
        rendered = renderer.render(camera, players, index, previous, want_class_ids=want_masks)
        truth = annotator.annotate(camera, rendered.labels, rendered.class_ids, want_mask=want_masks)
        yield SyntheticFrame(
            index=index, frame_id=frame_id(index), image=rendered.image, camera=camera, lines_norm=truth.lines_norm,
            occluded_classes=truth.occluded_classes, keypoints_px=truth.keypoints_px, mask=truth.mask,
            player_boxes_px=rendered.player_boxes_px, labels=rendered.labels, folded_classes=truth.folded_classes,
        )
        previous = camera


def clip_scene(preset: str, frame_count: int, width_px: int, height_px: int, seed: int = 0,
               cameras: Sequence[Camera] | None = None):
    """Camera track and players of a clip: (cameras, tripod or None, lambdas or None, players).

    With ``cameras`` given, they are used as they are (rescaled to the size) and the
    players follow the centre of the view; otherwise a track is generated from the preset.
    """
    spec = get_preset(preset)
    if cameras is None:
        track = generate_camera_track(preset, frame_count, width_px, height_px, seed)
        cams, tripod, lambdas, play = track.cameras, track.tripod, track.lambdas_m, track.ball_w
    else:
        cams = [c.rescaled(width_px, height_px)
                for c in list(cameras)[:frame_count]]
        tripod, lambdas, play = None, None, play_from_cameras(cams)
    players = simulate_players(play, spec.player_count, spec.player_spread_m, seed, FPS)
    return cams, tripod, lambdas, players


def render_clip(
    preset: str = "main",
    frame_count: int = 10,
    width_px: int = 480,
    height_px: int = 270,
    seed: int = 0,
    cameras: Sequence[Camera] | None = None,
    settings: RenderSettings = IN_MEMORY_SETTINGS,
    want_masks: bool = True,
) -> SyntheticClip:
    """Render a whole clip in memory.

    Args:
        preset: camera and play preset (motion.PRESETS); with ``cameras`` only its players are used.
        frame_count: number of frames (with ``cameras``: at most that many of them).
        width_px, height_px: image size.
        seed: random seed (same arguments -> identical clip).
        cameras: render along this track instead of a generated one.
        settings: image formation effects (default: all, with a JPEG round trip at quality 90 like the
            clip files; render.EXACT_SETTINGS for none).
        want_masks: build per-class masks.

    Returns:
        SyntheticClip.
    """
    if preset not in PRESETS:
        get_preset(preset)  # raises with the list of names
    cams, tripod, lambdas, players = clip_scene(preset, frame_count, width_px, height_px, seed, cameras)
    frames = list(iter_clip_frames(cams, width_px, height_px, seed, players, settings, want_masks))
    return SyntheticClip(frames=frames, width_px=width_px, height_px=height_px, fps=FPS, preset=preset, seed=seed,
                         tripod=tripod, lambdas_m=lambdas, players=players)
