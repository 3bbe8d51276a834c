"""The playing field from colour: mown grass with its lines and players, not a green crowd above the boards."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.playing_field import grass_and_field
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

W, H = 640, 360
BOARDS = 140  # the boards' top row; the crowd above, the pitch below


def _pitch_below_a_green_crowd(seed: int = 0) -> np.ndarray:
    """(H, W, 3) frame: mown, striped grass with two markings and a player below grey boards, and a crowd above
    whose seats are green where nobody sits (55 %) and someone in any colour elsewhere (3x3 px people)."""
    rng = np.random.default_rng(seed)
    image = np.zeros((H, W, 3), np.uint8)
    image[BOARDS + 12:] = (40, 150, 60)
    for x0 in range(0, W, 80):  # mown stripes
        image[BOARDS + 12:, x0:x0 + 40] = (45, 165, 70)
    cv2.line(image, (0, 300), (W, 250), (235, 240, 235), 3)
    cv2.line(image, (320, BOARDS + 12), (250, H), (235, 240, 235), 3)
    cv2.rectangle(image, (400, 200), (412, 240), (30, 30, 200), -1)  # a player
    image[BOARDS:BOARDS + 12] = (90, 90, 90)
    seats = rng.random((BOARDS // 3 + 1, W // 3 + 1)) < 0.55
    people = rng.integers(0, 255, seats.shape + (3,), dtype=np.uint8)
    crowd = np.where(seats[..., None], np.array([50, 140, 70], np.uint8), people)
    image[:BOARDS] = np.repeat(np.repeat(crowd, 3, axis=0), 3, axis=1)[:BOARDS, :W]
    return image


def _field(image: np.ndarray, min_whole_share: float) -> np.ndarray:
    return grass_and_field(image, (30, 95), 40, 30, 0.9, min_whole_share, 0.02)[1] > 0


def test_the_field_is_the_mown_grass_not_a_green_crowd():
    image = _pitch_below_a_green_crowd()
    field = _field(image, 0.5)
    assert field[BOARDS + 20:].mean() > 0.98  # the pitch, its lines and its player filled in
    assert field[:BOARDS - 5].mean() < 0.02
    # By the grass share of its cells alone the crowd is field.
    assert _field(image, 0.0)[:BOARDS - 5].mean() > 0.5


def test_the_detector_finds_no_marking_in_a_green_crowd():
    image = _pitch_below_a_green_crowd()
    found = WeightFreeDetector(config=WeightFreeConfig(work_width_px=W)).detect(image)
    assert not found.marking_mask[:BOARDS].any() and not found.field_mask[:BOARDS - 5].any()
    assert found.marking_mask[BOARDS + 12:].sum() > 300  # the two markings (a 1-px centre line each)
    mixed = WeightFreeDetector(config=WeightFreeConfig(work_width_px=W, field_min_whole_share=0.0)).detect(image)
    assert mixed.field_mask[:BOARDS - 5].mean() > 0.5


def test_an_image_without_grass_has_no_field():
    grass, field = grass_and_field(np.full((H, W, 3), 128, np.uint8), (30, 95), 40, 30, 0.9, 0.5, 0.02)
    assert not grass.any() and not field.any()


def test_grass_behind_a_goals_net_stays_field():
    """A pocket of grass seen through a goal's white mesh, walled off from the pitch by dark posts and open to the
    boards above, is field like the pitch (the goal line at its foot stays a margin inside the field)."""
    image = np.zeros((H, W, 3), np.uint8)
    image[100:] = (40, 150, 60)
    image[36:100, 292:368] = (20, 20, 20)  # posts and the goal's frame
    pocket = (slice(40, 92), slice(300, 360))  # 13 x 15 cells
    image[pocket] = (40, 150, 60)
    image[pocket[0], pocket[1]][::3] = (230, 235, 230)  # the mesh: a white row every third, a white column too
    image[pocket[0], pocket[1]][:, ::3] = (230, 235, 230)
    assert _field(image, 0.5)[pocket].mean() > 0.8  # all but its rim
    # Counted as grass alone, the mesh makes most cells of the pocket part grass: it would be judged a crowd.
    grass = cv2.inRange(cv2.cvtColor(image, cv2.COLOR_BGR2HSV), (30, 40, 30), (95, 255, 255))
    cells = cv2.resize(grass[pocket], (15, 13), interpolation=cv2.INTER_AREA)
    assert (cells < 0.9 * 255).mean() > 0.5
