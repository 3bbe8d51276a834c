"""The size of an image-folder clip: the most common size among its first readable images.

Taking the first image's size would make one odd first image (a title card, a thumbnail)
mark every other frame of the clip missing; the most common size among the first few
readable images is the clip's, and images of another size are reported and skipped.
"""

from __future__ import annotations

import logging
from collections import Counter
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

logger = logging.getLogger(__name__)

SIZE_SAMPLE = 9  # readable images looked at to decide the clip size


def clip_size(files: Sequence[Path], start: int, end: int, decode: Callable[[Path], tuple],
              sample: int = SIZE_SAMPLE) -> tuple[int, np.ndarray] | None:
    """The first readable image of the clip's size, and its index.

    Args:
        files: image paths in frame order; start, end: the window of indices (end exclusive).
        decode: ``path -> (image (H, W, 3) uint8 | None, problem)``.
        sample: how many readable images decide the size (the most common size wins; ties: the earliest).

    Returns:
        (index, image) of the first image of the chosen size, or None when no image of the window decodes.
    """
    seen: list[tuple[int, np.ndarray]] = []
    for index in range(start, end):
        image, _ = decode(files[index])
        if image is not None:
            seen.append((index, image))
            if len(seen) >= sample:
                break
    if not seen:
        return None
    counts = Counter(image.shape[:2] for _, image in seen)
    best = max(counts.values())
    size = next(image.shape[:2] for _, image in seen if counts[image.shape[:2]] == best)
    index, image = next((i, im) for i, im in seen if im.shape[:2] == size)
    if index != seen[0][0]:
        logger.warning("%s: first image is %dx%d but most of the first %d are %dx%d: the clip is %dx%d and images "
                       "of another size are skipped", files[seen[0][0]], seen[0][1].shape[1], seen[0][1].shape[0],
                       len(seen), size[1], size[0], size[1], size[0])
    return index, image
