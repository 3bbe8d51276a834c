"""The output folder of a synthetic clip: what the clip writer owns in it, and clearing it before a new clip.

A synthetic clip folder (SoccerNet game-state layout) holds ``clip.json`` and the entries of
:data:`CLIP_ENTRIES`. Writing a clip into a folder that already holds one replaces the old
clip entirely (otherwise the old clip's extra frames would stay and a later ``track`` would
run two different clips as one); a folder that holds anything else is refused.
"""

from __future__ import annotations

import logging
import shutil
from pathlib import Path

from broadtrack_graph.errors import InputError

logger = logging.getLogger(__name__)

CLIP_ENTRIES = ("clip.json", "img1", "annotations", "cameras", "keypoints", "masks", "Labels-GameState.json",
                "players.json", "players_pitch.json", "ground_truth.json", "tripod.json", "clip.mp4")
"""Every file and folder the clip writer creates in its output folder."""


def prepare_clip_folder(out: str | Path) -> int:
    """Make ``out`` ready for a new clip; returns how many entries of an earlier clip were removed.

    Raises:
        InputError: ``out`` is a file, or a non-empty folder that is not a synthetic clip
            (no clip.json) or that holds files a clip does not own.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(out, "exists and is not a folder; give a new or clip folder for --out")
    if not out.is_dir():
        return 0
    present = {p.name for p in out.iterdir()}
    if not present:
        return 0
    foreign = sorted(present - set(CLIP_ENTRIES))
    if "clip.json" not in present or foreign:
        what = f"holds {', '.join(foreign[:3])}{' ...' if len(foreign) > 3 else ''}" if foreign else "is not a synthetic clip (no clip.json)"
        raise InputError(out, f"folder {what}; give a new or empty folder, or an earlier synthetic clip to replace")
    removed = 0
    for name in sorted(present):
        path = out / name
        try:
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)
            else:
                path.unlink()
        except OSError as exc:
            raise InputError(path, f"cannot remove the earlier clip's file: {exc.strerror or exc}") from None
        removed += 1
    logger.info("%s: replaced an earlier synthetic clip (%d entries removed)", out, removed)
    return removed
