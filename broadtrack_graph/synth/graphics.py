"""Broadcast graphics drawn over a frame: score bug, channel logo, ticker, lower third, watermark, tags.

Simple filled rectangles, circles and ``cv2.putText`` text at random places, colours and
opacities, each element with its own chance. :func:`draw_broadcast_graphics` draws them in place
and returns the pixels they hide (drawn at least half opaque): a keypoint or marking there is not
visible in the image. Sizes scale with the image height. No I/O here.
"""

from __future__ import annotations

import string

import cv2
import numpy as np

FONTS = (cv2.FONT_HERSHEY_SIMPLEX, cv2.FONT_HERSHEY_DUPLEX, cv2.FONT_HERSHEY_TRIPLEX, cv2.FONT_HERSHEY_COMPLEX)
HIDING_OPACITY = 0.5
"""Graphics at least this opaque hide what is under them."""


def _word(rng: np.random.Generator, low: int, high: int) -> str:
    return "".join(rng.choice(list(string.ascii_uppercase), size=int(rng.integers(low, high + 1))))


def _colour(rng: np.random.Generator, dark: bool | None = None) -> tuple[int, int, int]:
    colour = rng.integers(0, 256, 3)
    if dark is True:
        colour = colour // 4
    elif dark is False:
        colour = 160 + colour * 95 // 255
    return tuple(int(v) for v in colour)


class _Canvas:
    """Draws elements into a layer and blends each with its opacity; collects the hidden pixels."""

    def __init__(self, image: np.ndarray) -> None:
        self.image = image
        self.hidden = np.zeros(image.shape[:2], bool)

    def element(self, x0: int, y0: int, x1: int, y1: int, opacity: float, draw) -> None:
        """draw(layer, mask) paints into the ROI copies; the ROI is then blended with opacity where mask is set."""
        H, W = self.image.shape[:2]
        x0, x1, y0, y1 = max(0, x0), min(W, x1), max(0, y0), min(H, y1)
        if x1 - x0 < 2 or y1 - y0 < 2:
            return
        roi = self.image[y0:y1, x0:x1]
        layer = roi.copy()
        mask = np.zeros(roi.shape[:2], np.uint8)
        draw(layer, mask)
        blended = cv2.addWeighted(layer, opacity, roi, 1.0 - opacity, 0.0)
        cv2.copyTo(blended, mask, roi)
        if opacity >= HIDING_OPACITY:
            self.hidden[y0:y1, x0:x1] |= mask > 0


def _text(layer, mask, text: str, x: int, y: int, height_px: float, colour, font, thickness: int | None = None) -> int:
    """Text with its baseline at y, cap height about height_px; returns its width in pixels."""
    scale = max(0.2, height_px / 22.0)
    thickness = thickness or max(1, int(round(scale * 1.6)))
    (width, _), _ = cv2.getTextSize(text, font, scale, thickness)
    cv2.putText(layer, text, (x, y), font, scale, colour, thickness, cv2.LINE_AA)
    cv2.putText(mask, text, (x, y), font, scale, 255, thickness, cv2.LINE_8)
    return width


def draw_broadcast_graphics(image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Draw a random set of broadcast graphics in place.

    Args:
        image: (H, W, 3) BGR uint8, changed in place.
        rng: the random stream of the graphics.

    Returns:
        (H, W) bool: pixels the graphics hide (drawn with opacity >= HIDING_OPACITY).
    """
    canvas = _Canvas(image)
    H, W = image.shape[:2]
    font = FONTS[int(rng.integers(len(FONTS)))]
    corners = rng.permutation(4)  # top-left, top-right, bottom-left, bottom-right

    def corner_box(index: int, width: int, height: int, margin: int) -> tuple[int, int]:
        right, bottom = corners[index] % 2 == 1, corners[index] >= 2
        return (W - margin - width if right else margin), (H - margin - height if bottom else margin)

    if rng.random() < 0.85:  # score bug: team codes, score, clock
        h = int(H * rng.uniform(0.035, 0.065))
        w = int(h * rng.uniform(5.5, 9.0))
        x, y = corner_box(0, w, h, int(H * rng.uniform(0.02, 0.06)))
        back, panel, ink = _colour(rng, dark=True), _colour(rng), _colour(rng, dark=False)
        label = f"{_word(rng, 3, 3)} {int(rng.integers(6))}-{int(rng.integers(6))} {_word(rng, 3, 3)}"
        clock = f"{int(rng.integers(95)):02d}:{int(rng.integers(60)):02d}"

        def score_bug(layer, mask):
            cv2.rectangle(layer, (0, 0), (w, h), back, -1)
            cv2.rectangle(mask, (0, 0), (w, h), 255, -1)
            split = int(w * 0.72)
            cv2.rectangle(layer, (split, 0), (w, h), panel, -1)
            _text(layer, mask, label, int(h * 0.2), int(h * 0.75), h * 0.5, ink, font)
            _text(layer, mask, clock, split + int(h * 0.15), int(h * 0.75), h * 0.45, (250, 250, 250), font)

        canvas.element(x, y, x + w, y + h, rng.uniform(0.7, 1.0), score_bug)
    if rng.random() < 0.6:  # channel logo: letters and a disc
        h = int(H * rng.uniform(0.04, 0.09))
        word = _word(rng, 2, 4)
        w = int(h * (0.9 + 0.6 * len(word)))
        x, y = corner_box(1, w, h, int(H * rng.uniform(0.02, 0.06)))
        colour, disc = _colour(rng, dark=False), rng.random() < 0.5

        def logo(layer, mask):
            offset = 0
            if disc:
                cv2.circle(layer, (h // 2, h // 2), h // 2 - 1, colour, -1, cv2.LINE_AA)
                cv2.circle(mask, (h // 2, h // 2), h // 2 - 1, 255, -1)
                offset = h
            _text(layer, mask, word, offset + 2, int(h * 0.8), h * 0.6, colour, font)

        canvas.element(x, y, x + w, y + h, rng.uniform(0.35, 0.95), logo)
    if rng.random() < 0.3:  # ticker along the bottom
        h = int(H * rng.uniform(0.04, 0.07))
        y = H - h - int(H * rng.uniform(0.0, 0.04))
        back, ink = _colour(rng, dark=True), _colour(rng, dark=False)
        words = " ".join(_word(rng, 2, 8) for _ in range(12))
        start = -int(rng.uniform(0, W))

        def ticker(layer, mask):
            cv2.rectangle(layer, (0, 0), (W, h), back, -1)
            cv2.rectangle(mask, (0, 0), (W, h), 255, -1)
            _text(layer, mask, words, start, int(h * 0.75), h * 0.55, ink, font)

        canvas.element(0, y, W, y + h, rng.uniform(0.75, 1.0), ticker)
    if rng.random() < 0.2:  # lower third: a name bar
        h = int(H * rng.uniform(0.05, 0.09))
        w = int(W * rng.uniform(0.25, 0.45))
        x, y = int(W * rng.uniform(0.04, 0.2)), int(H * rng.uniform(0.72, 0.86))
        back, strip = _colour(rng, dark=True), _colour(rng)
        name = f"{int(rng.integers(1, 40))} {_word(rng, 4, 10)}"

        def lower_third(layer, mask):
            cv2.rectangle(layer, (0, 0), (w, h), back, -1)
            cv2.rectangle(layer, (0, 0), (max(2, h // 5), h), strip, -1)
            cv2.rectangle(mask, (0, 0), (w, h), 255, -1)
            _text(layer, mask, name, h // 2, int(h * 0.72), h * 0.5, (245, 245, 245), font)

        canvas.element(x, y, x + w, y + h, rng.uniform(0.8, 1.0), lower_third)
    if rng.random() < 0.25:  # LIVE / REPLAY tag
        h = int(H * rng.uniform(0.03, 0.05))
        tag = str(rng.choice(["LIVE", "REPLAY", "HD", "VAR"]))
        w = int(h * (0.8 + 0.75 * len(tag)))
        x, y = corner_box(2, w, h, int(H * rng.uniform(0.02, 0.06)))
        back = _colour(rng)

        def tag_box(layer, mask):
            cv2.rectangle(layer, (0, 0), (w, h), back, -1)
            cv2.rectangle(mask, (0, 0), (w, h), 255, -1)
            _text(layer, mask, tag, h // 3, int(h * 0.78), h * 0.55, (255, 255, 255), font)

        canvas.element(x, y, x + w, y + h, rng.uniform(0.7, 1.0), tag_box)
    if rng.random() < 0.3:  # faint watermark anywhere (hides nothing)
        h = int(H * rng.uniform(0.06, 0.14))
        word = _word(rng, 3, 8)
        w = int(h * 0.9 * len(word))
        x, y = int(rng.uniform(0, max(1, W - w))), int(rng.uniform(0, max(1, H - h)))
        colour = _colour(rng, dark=False)
        canvas.element(x, y, x + w, y + h, rng.uniform(0.1, 0.3),
                       lambda layer, mask: _text(layer, mask, word, 0, int(h * 0.85), h * 0.7, colour, font))
    return canvas.hidden
