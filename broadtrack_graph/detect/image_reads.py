"""An image read between its pixels at many points at once (bilinear, its border repeated). No I/O.

OpenCV's ``remap`` reads an image at a map of points in one call, but takes maps under 32767 points a side: a frame
whose marking map holds more points than that (a smear undone into noise, a crowd or a net full of edges) cannot be
read as one column. :func:`read_at` lays any number of points out in rows of ``columns`` first, so every point is read
as it would be alone (the read at a point does not depend on the others).
"""

from __future__ import annotations

import cv2
import numpy as np


def read_at(image: np.ndarray, x: np.ndarray, y: np.ndarray, columns: int = 1024) -> np.ndarray:
    """The image (h, w) or (h, w, C) read bilinearly, its border repeated, at pixels (x, y) (any same shape S).

    Returns:
        (*S) or (*S, C), the image's dtype.
    """
    shape = np.shape(x)
    m = int(np.prod(shape))
    rows = max(1, -(-m // columns))
    grid_x, grid_y = np.zeros(rows * columns, np.float32), np.zeros(rows * columns, np.float32)
    grid_x[:m], grid_y[:m] = np.ravel(x), np.ravel(y)
    out = cv2.remap(image, grid_x.reshape(rows, columns), grid_y.reshape(rows, columns), cv2.INTER_LINEAR,
                    borderMode=cv2.BORDER_REPLICATE)
    channels = out.shape[2:]
    return out.reshape(rows * columns, *channels)[:m].reshape(*shape, *channels)
