"""A frame's straight motion blur, found from the frame alone, and undone. No I/O.

A camera turning while the shutter is open smears the image along one direction: every pixel is the mean of the
sharp image over a segment of length ``L`` (pixels) in that direction, a box blur along a line. A marking across
the smear loses most of its contrast (a 3 px line smeared over 15 px keeps a fifth of it) and the marking map
misses it, while the markings along it stay sharp, so the frame reads as sharp to the width of its strongest
edges (:mod:`.sharpness`).

Finding the blur (:func:`estimate_motion_blur`):

* **Direction.** The smear removes the detail along its direction: the gradient's energy is least there. Over the
  whole image the gradient's second moments (the structure tensor) give that direction as the eigenvector of the
  smaller eigenvalue; their ratio (``anisotropy``, smaller over larger) is near 1 for a frame without a preferred
  direction and falls as the smear grows.
* **Length.** The derivative along the direction of an image smeared over ``L`` is ``(I(x + L/2) - I(x - L/2)) / L``:
  each fine detail of the sharp image (the grass's texture, the sensor's noise) appears twice, ``L`` apart and of
  opposite signs, so the derivative's autocorrelation along the direction has a negative lobe at the lag ``L`` of
  half its value at lag 0 (``depth`` -0.5) where such detail dominates (a smeared step edge adds a positive
  triangle instead). Every image's derivative has a negative lobe a few pixels out (an edge's own width, a thin
  line's two sides, the grain of a textured grass, reaching 6-8 px at the detector's working width): lengths under
  ``min_length_px`` are not told apart from it. A scene with a strong direction of its own (lines or stripes all one
  way) pulls the structure tensor's direction off the smear's, by 10-20 deg and more on rendered pans across a
  pitch's markings: the direction is measured again at full size as the one within ``refine_angle_deg`` whose lobe
  is deepest, and when none there is deep enough (``max_depth``), around the direction within ``scan_angle_deg`` of
  the structure tensor's whose lobe is deepest on the reduced image (1 deg apart) instead.
* **Coherence.** A smear averages the frame's fine detail out along its direction, so the derivative along it has
  no negative lobe of its own before the smear's (from :data:`COHERENCE_LAG_PX` to half the length it stays about
  level or above: each edge spread over ``L`` pixels is alike over a few of them); a sharp frame's derivative has
  its own lobe from two pixels out (a line's two sides, an edge's overshoot, the grass's grain), which a short
  smear's lobe is not told from (``min_length_px``).
* A blur is taken when the lobe is at least ``min_length_px`` out, as deep as ``max_depth`` (half the ideal box's),
  no lobe before it (``min_coherence``) and the gradient's energy anisotropic (``max_anisotropy``).
  It is looked for on the image reduced 2x (a quarter of the cost; every frame pays it; a lobe at least
  ``max_depth_reduced`` deep there is enough to look further), then measured again at full size and judged there.

Undoing it (:func:`deblurred`): the Wiener filter of the segment's kernel, ``conj(K) (1 + nsr) / (|K|^2 + nsr)``
(scaled to keep the image's level), the image extended first so that, repeated periodically as the filter takes it,
its opposite borders meet without a step (:func:`periodic_extension`).
``nsr`` (the noise's power over the image's) keeps the frequencies the box removes entirely from being amplified
without bound: a 3 px marking across a 15 px smear comes back at nearly three times the contrast the smear left it
(half its own), with faint echoes ``L`` apart along it, and the grass's noise about doubled. A larger ``nsr`` brings
less back: smeared frames' markings the court model misses; a smaller one raises the noise into ridges that slow it.

Pixels are (x right, y down); angles in degrees from +x towards +y, in [0, 180).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from broadtrack_graph.detect.sharpness import gradients
from broadtrack_graph.detect.smeared_markings import SmearedImage

COHERENCE_LAG_PX = 2.0
"""The first lag of the coherence: the first clear of the derivative filter's own reach (the 3x3 Sobel spreads a step
over two pixels, so any edge's derivative is alike one pixel out)."""


@dataclass(frozen=True)
class MotionBlurConfig:
    """Settings of :func:`estimate_motion_blur` and :func:`deblurred` (pixels of the image given)."""

    min_length_px: float = 9.0  # shorter smears are not told from the frame's own lobe (0: never looked for)
    max_length_px: int = 32  # lags looked at
    max_depth: float = -0.25  # the autocorrelation's lobe at the length at least this deep (an ideal box: -0.5) ...
    max_anisotropy: float = 0.7  # ... and the gradient's energy across the smear this share of the energy along it
    min_coherence: float = -0.1  # the autocorrelation from COHERENCE_LAG_PX to half the length at least this
    # ... and, on the image reduced 2x, one pixel out at least this (the cheap first look: the reduction's own
    # smoothing adds to the likeness)
    min_coherence_reduced: float = 0.5
    max_depth_reduced: float = -0.2  # ... and its lobe at least this deep (the test at full size decides)
    refine_angle_deg: float = 5.0  # the direction measured again at full size within this of the reduced image's
    # ... and, with no lobe deep enough there, around the deepest on the reduced image within this of it (0: not)
    scan_angle_deg: float = 30.0
    wiener_nsr: float = 0.02  # noise over signal power of the Wiener filter


@dataclass(frozen=True)
class MotionBlur:
    """A straight motion blur: its length (pixels), direction (degrees, [0, 180)), the autocorrelation's depth at the
    length, the gradient's anisotropy and the derivative's coherence along the smear (module docstring); ``image``:
    the frame's marking channel as the smear left it, when the detector keeps it (to ask whether a camera's markings
    across the smear show there: :mod:`.smeared_markings`), or None."""

    length_px: float
    angle_deg: float
    depth: float
    anisotropy: float
    coherence: float = 1.0  # the autocorrelation's least value between COHERENCE_LAG_PX and half the length
    image: SmearedImage | None = field(default=None, compare=False, repr=False)


def estimate_motion_blur(grey: np.ndarray, config: MotionBlurConfig = MotionBlurConfig()) -> MotionBlur | None:
    """The straight motion blur of a grey image (h, w) uint8 or float, or None when it shows none (module docstring).

    Returns:
        MotionBlur at the image's pixels, or None (no blur, or the image too small to tell).
    """
    if config.min_length_px <= 0:
        return None
    h, w = grey.shape
    half = cv2.resize(grey, (max(1, w // 2), max(1, h // 2)), interpolation=cv2.INTER_AREA).astype(np.float32)
    gx, gy = gradients(half)
    angle, anisotropy = _least_energy_direction(gx, gy)
    if anisotropy > config.max_anisotropy:
        return None
    lags = np.arange(1, config.max_length_px // 2 + 1, dtype=float)
    along = _autocorrelation_along(gx, gy, angle, lags)
    if along is None:
        return None
    k = _lobe(along, lags, config.min_length_px / 2.0)
    if k is None or along[k] > config.max_depth_reduced or along[0] < config.min_coherence_reduced:
        return None
    # Measured again at full size around the reduced image's length and direction.
    full = gradients(np.asarray(grey, np.float32))
    near = _lobes_near(full, angle, lags[k], config.refine_angle_deg)
    if near is not None and config.scan_angle_deg > 0 and np.min(near[3]) > config.max_depth:
        # Too shallow along the structure tensor's direction: the deepest lobe near it on the reduced image, its
        # neighbourhood measured at full size in turn (the reduced image's directions are coarse).
        scanned, j = _deepest_lobe_near(gx, gy, angle, lags, k, along[k], config.scan_angle_deg,
                                        config.min_length_px / 2.0)
        if scanned != angle:
            near = _lobes_near(full, scanned, lags[j], config.refine_angle_deg)
    if near is None:
        return None
    maps, fine, angles, lobes = near
    a = int(np.argmin(lobes))  # the direction of the deepest lobe near it
    along = maps.along(angles[a:a + 1], np.arange(1.0, fine[-1] + 2))[0]
    j = _lobe(along, np.arange(1.0, fine[-1] + 2), config.min_length_px)
    if j is None:
        return None
    length, depth = float(j + 1), float(along[j])
    # Along a smear the frame's own fine detail is averaged out: no lobe of its own before the smear's.
    before = along[int(COHERENCE_LAG_PX) - 1:max(int(COHERENCE_LAG_PX), int(length // 2))]
    coherence = float(np.min(before))
    if depth > config.max_depth or coherence < config.min_coherence:
        return None
    return MotionBlur(length, math.degrees(float(angles[a])) % 180.0, depth, anisotropy, coherence)


def _lobe(along: np.ndarray, lags: np.ndarray, min_lag: float) -> int | None:
    """The index of the deepest value of ``along`` (at ``lags``, consecutive integers) from ``min_lag`` on, when it is
    a lobe of its own: lower than the value before it (not the tail of the derivative's own lobe a few pixels out)
    and not at the last lag (a smear longer than looked for, or none); else None."""
    usable = np.flatnonzero(lags >= min_lag)
    if len(usable) < 2:
        return None
    k = int(usable[np.argmin(along[usable])])
    if k == len(lags) - 1 or k == 0 or along[k] >= along[k - 1]:
        return None
    return k


def _lobes_near(gradients_xy: tuple[np.ndarray, np.ndarray], angle: float, lag_px: float, span_deg: float):
    """(correlation maps, lags, directions, the least autocorrelation at those lags along each direction) of full-size
    gradients (gx, gy) for the directions within ``span_deg`` of ``angle`` (radians; 0.5 deg apart) and the lags
    around twice the reduced image's ``lag_px``; None when the image is too small or flat."""
    fine = np.arange(max(1.0, 2 * lag_px - 2), 2 * lag_px + 3)
    maps = _DerivativeCorrelations.of(*gradients_xy, fine[-1])
    if maps is None:
        return None
    angles = angle + np.radians(np.arange(-span_deg, span_deg + 0.01, 0.5))
    return maps, fine, angles, np.min(maps.along(angles, fine), axis=1)


def _deepest_lobe_near(gx: np.ndarray, gy: np.ndarray, angle: float, lags: np.ndarray, k: int, depth: float,
                       span_deg: float, min_lag: float) -> tuple[float, int]:
    """(direction in radians, lag index) of the deepest lobe (:func:`_lobe`) of the derivative's autocorrelation
    along the directions within ``span_deg`` of ``angle`` (1 deg apart), or ``angle`` and ``k`` (its lobe of
    ``depth``) when none is deeper."""
    maps = _DerivativeCorrelations.of(gx, gy, float(lags[-1]))
    if maps is None:
        return angle, k
    angles = angle + np.radians(np.arange(-span_deg, span_deg + 0.01, 1.0))
    along = maps.along(angles, lags)
    rows = np.arange(len(angles))
    j = np.argmin(np.where(lags >= min_lag, along, np.inf), axis=1)
    lobe = along[rows, j]
    real = (j > 0) & (j < len(lags) - 1) & (lobe < along[rows, np.maximum(j - 1, 0)]) & (lobe < depth)
    if not real.any():
        return angle, k
    best = int(np.argmin(np.where(real, lobe, np.inf)))
    return float(angles[best]), int(j[best])


def motion_kernel(length_px: float, angle_deg: float) -> np.ndarray:
    """(k, k) float32 kernel summing to 1: the mean over a segment of ``length_px`` centred on the kernel's centre
    pixel, along ``angle_deg`` (each of many points along it shared among its four nearest pixels)."""
    radius = int(math.ceil(length_px / 2.0)) + 1
    size = 2 * radius + 1
    t = np.linspace(-length_px / 2.0, length_px / 2.0, max(2, int(math.ceil(8 * length_px))))
    x = radius + t * math.cos(math.radians(angle_deg))
    y = radius + t * math.sin(math.radians(angle_deg))
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    kernel = np.zeros((size, size), np.float64)
    for dx, dy, weight in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)), (0, 1, (1 - fx) * fy), (1, 1, fx * fy)):
        np.add.at(kernel, (y0 + dy, x0 + dx), weight)
    return (kernel / kernel.sum()).astype(np.float32)


def deblurred(grey: np.ndarray, blur: MotionBlur, nsr: float = MotionBlurConfig.wiener_nsr) -> np.ndarray:
    """(h, w) uint8: a grey image with its motion blur undone by the Wiener filter (module docstring)."""
    kernel = motion_kernel(blur.length_px, blur.angle_deg)
    h, w = grey.shape
    pad = kernel.shape[0]  # the blend from each border to the opposite one: at least two kernels long
    H, W = cv2.getOptimalDFTSize(h + 2 * pad), cv2.getOptimalDFTSize(w + 2 * pad)
    image = periodic_extension(np.asarray(grey, np.float32), H, W)
    spread = np.zeros((H, W), np.float32)
    k = kernel.shape[0] // 2
    spread[:kernel.shape[0], :kernel.shape[1]] = kernel
    spread = np.roll(spread, (-k, -k), axis=(0, 1))  # the kernel's centre at the origin
    K = cv2.dft(spread, flags=cv2.DFT_COMPLEX_OUTPUT)
    G = cv2.dft(image, flags=cv2.DFT_COMPLEX_OUTPUT)
    power = (K[..., 0] ** 2 + K[..., 1] ** 2 + nsr) / (1.0 + nsr)
    # G * conj(K) (1 + nsr) / (|K|^2 + nsr): the level (where K is 1) kept
    re = (G[..., 0] * K[..., 0] + G[..., 1] * K[..., 1]) / power
    im = (G[..., 1] * K[..., 0] - G[..., 0] * K[..., 1]) / power
    out = cv2.dft(np.dstack([re, im]), flags=cv2.DFT_INVERSE | cv2.DFT_REAL_OUTPUT | cv2.DFT_SCALE)
    return np.clip(out[:h, :w], 0, 255).astype(np.uint8)


def periodic_extension(image: np.ndarray, height: int, width: int) -> np.ndarray:
    """(height, width) float32: an (h, w) image at the top left, the rows and columns after it a smooth blend from
    its last row (column) to its first, so that the image repeated periodically, as the Fourier transform takes it,
    has no step where its opposite borders meet (a step there, deconvolved, rings back into the image along its
    borders as a band the ridge detector reads as a marking).

    The blend of each added row (column) is a raised cosine in its distance from the image's last row (column).
    """
    h, w = image.shape
    out = np.empty((height, width), np.float32)
    out[:h, :w] = image
    for axis, room in ((0, height - h), (1, width - w)):
        if room <= 0:
            continue
        weight = (0.5 - 0.5 * np.cos(np.pi * (np.arange(1, room + 1) / (room + 1)))).astype(np.float32)
        if axis == 0:
            last, first = out[h - 1:h, :w], out[0:1, :w]
            out[h:, :w] = last + weight[:, None] * (first - last)
        else:
            last, first = out[:, w - 1:w], out[:, 0:1]
            out[:, w:] = last + weight[None, :] * (first - last)
    return out


def _least_energy_direction(gx: np.ndarray, gy: np.ndarray) -> tuple[float, float]:
    """(the direction of least gradient energy in radians, the energy along it over the energy across it): the
    structure tensor's eigenvector of the smaller eigenvalue, and its smaller over its larger (1: no preferred
    direction)."""
    jxx, jyy, jxy = float(np.mean(gx * gx)), float(np.mean(gy * gy)), float(np.mean(gx * gy))
    trace, spread = jxx + jyy, math.hypot(jxx - jyy, 2.0 * jxy)
    if trace <= 1e-9:
        return 0.0, 1.0
    return 0.5 * math.atan2(2.0 * jxy, jxx - jyy) + math.pi / 2.0, (trace - spread) / (trace + spread)


def _padded_spectra(images, reach_px: float):
    """The Fourier transforms (OpenCV's packed real form) of same-size images (h, w) padded with zeros by ``reach_px``
    and more (to a fast size): their correlations at lags up to ``reach_px`` do not wrap round. None when the images
    are too small."""
    h, w = images[0].shape
    reach = int(math.ceil(reach_px)) + 2
    if h <= 2 * reach + 8 or w <= 2 * reach + 8:
        return None
    H, W = cv2.getOptimalDFTSize(h + reach), cv2.getOptimalDFTSize(w + reach)
    return [cv2.dft(cv2.copyMakeBorder(g, 0, H - h, 0, W - w, cv2.BORDER_CONSTANT, value=0.0)) for g in images]


def _correlation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``sum_x a(x) b(x + t)`` at t = (column, row) mod the size, from the two padded spectra."""
    return cv2.dft(cv2.mulSpectrums(b, a, 0, conjB=True), flags=cv2.DFT_INVERSE | cv2.DFT_REAL_OUTPUT | cv2.DFT_SCALE)


def _bilinear(R: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """R read at (x, y) (any shape, modulo its size) between its pixels."""
    H, W = R.shape
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    return (R[y0 % H, x0 % W] * (1 - fx) * (1 - fy) + R[y0 % H, (x0 + 1) % W] * fx * (1 - fy)
            + R[(y0 + 1) % H, x0 % W] * (1 - fx) * fy + R[(y0 + 1) % H, (x0 + 1) % W] * fx * fy)


def _autocorrelation_along(gx: np.ndarray, gy: np.ndarray, angle: float, lags: np.ndarray) -> np.ndarray | None:
    """(L,) the autocorrelation of the derivative along ``angle`` (radians) at ``lags`` along it, over its value at lag
    0 (one transform each way); None when the image is too small or flat."""
    c, s = math.cos(angle), math.sin(angle)
    spectra = _padded_spectra([gx * c + gy * s], float(np.max(lags)))
    if spectra is None:
        return None
    R = _correlation(spectra[0], spectra[0])
    if R[0, 0] <= 1e-9:
        return None
    return _bilinear(R, lags * c, lags * s) / R[0, 0]


class _DerivativeCorrelations:
    """The autocorrelation of an image's derivative along any direction, at any lag along it.

    The derivative along (c, s) is ``c gx + s gy``, so its autocorrelation at the lag vector t is
    ``c^2 Rxx(t) + c s (Rxy(t) + Rxy(-t)) + s^2 Ryy(t)`` with ``Rab(t) = sum_x a(x) b(x + t)``: three correlation maps
    (through the Fourier transform, the gradients padded with zeros: no wrap-around) give every direction at once,
    read between pixels bilinearly.
    """

    def __init__(self, maps: tuple[np.ndarray, np.ndarray, np.ndarray]):
        self.Rxx, self.Ryy, self.Rxy = maps

    @classmethod
    def of(cls, gx: np.ndarray, gy: np.ndarray, reach_px: float) -> "_DerivativeCorrelations | None":
        """The maps of the gradients (h, w) for lags up to ``reach_px``; None when the image is too small or flat."""
        spectra = _padded_spectra([gx, gy], reach_px)
        if spectra is None or float(np.mean(gx * gx + gy * gy)) <= 1e-9:
            return None
        fx, fy = spectra
        return cls((_correlation(fx, fx), _correlation(fy, fy), _correlation(fx, fy)))

    def along(self, angles: np.ndarray, lags: np.ndarray) -> np.ndarray:
        """(A, L): the autocorrelation of the derivative along each angle (radians) at each lag along it, over its
        value at lag 0."""
        c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
        x, y = lags[None, :] * c, lags[None, :] * s
        energy = c**2 * self.Rxx[0, 0] + 2 * c * s * self.Rxy[0, 0] + s**2 * self.Ryy[0, 0]
        value = c**2 * _bilinear(self.Rxx, x, y) + c * s * (_bilinear(self.Rxy, x, y) + _bilinear(self.Rxy, -x, -y)) \
            + s**2 * _bilinear(self.Ryy, x, y)
        return value / np.maximum(energy, 1e-12)
