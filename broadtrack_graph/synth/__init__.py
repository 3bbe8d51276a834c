"""Synthetic broadcast clips: tripod camera motion, ray-cast rendering and exact ground truth.

Modules: ``presets`` (where each synthetic camera stands, how it moves), ``motion`` (camera tracks on a tripod), ``scene`` (stadium geometry,
players), ``texture`` (precomputed grass / boards / stands textures), ``render``
(per-pixel ray casting), ``annotate`` (SoccerNet annotations, masks, keypoints),
``clip`` (in-memory clips). Writing clip folders: :mod:`broadtrack_graph.synth.writer`.
Training samples of a learned field model, one randomised image with exact labels each:
:func:`broadtrack_graph.synth.field_samples.sample_field`.

``generate_camera_track`` and ``PRESETS`` import without the renderer; ``render_clip``,
``iter_clip_frames`` and ``SyntheticClip`` are loaded on first use.
"""

from broadtrack_graph.synth.motion import CameraTrack, generate_camera_track
from broadtrack_graph.synth.presets import PRESETS, MotionPreset

__all__ = ["PRESETS", "CameraTrack", "MotionPreset", "generate_camera_track", "render_clip", "iter_clip_frames",
           "SyntheticClip", "SyntheticFrame"]


def __getattr__(name: str):
    if name in ("render_clip", "iter_clip_frames", "SyntheticClip", "SyntheticFrame"):
        from broadtrack_graph.synth import clip

        return getattr(clip, name)
    raise AttributeError(f"module 'broadtrack_graph.synth' has no attribute '{name}'")
