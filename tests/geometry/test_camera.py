import json
import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera, angles_from_rotation, rotation_from_angles
from broadtrack_graph.io.cameras import list_camera_files, read_camera_file, write_camera_file


def main_camera(**changes) -> Camera:
    camera = Camera.from_degrees(2200.0, -0.05, 10.0, 75.0, 0.3, (0.0, 55.0, -12.0), 1920, 1080)
    return camera.replace(**changes) if changes else camera


def test_rotation_conventions_by_hand():
    # tilt 0 looks straight down: the optical axis (row 3 of R_cw) is +z (down).
    R = rotation_from_angles(0.0, 0.0, 0.0)
    np.testing.assert_allclose(R[2], [0, 0, 1], atol=1e-15)
    # tilt 90 deg, pan 0 looks horizontally towards -y (the far touchline).
    R = rotation_from_angles(0.0, math.pi / 2, 0.0)
    np.testing.assert_allclose(R[2], [0, -1, 0], atol=1e-15)
    # positive pan turns the view towards +x.
    R = rotation_from_angles(math.radians(90), math.pi / 2, 0.0)
    np.testing.assert_allclose(R[2], [1, 0, 0], atol=1e-15)
    # camera y axis (image down) points to world +z (down) when looking horizontally.
    np.testing.assert_allclose(R[1], [0, 0, 1], atol=1e-15)


def test_rotation_is_transpose_of_rz_rx_rz():
    pan, tilt, roll = 0.3, 1.2, -0.05
    cp, sp, ct, st, cr, sr = math.cos(pan), math.sin(pan), math.cos(tilt), math.sin(tilt), math.cos(roll), math.sin(roll)
    Rz = lambda c, s: np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])  # noqa: E731
    Rx = np.array([[1, 0, 0], [0, ct, -st], [0, st, ct]])
    np.testing.assert_allclose(rotation_from_angles(pan, tilt, roll), (Rz(cp, sp) @ Rx @ Rz(cr, sr)).T, atol=1e-15)


@pytest.mark.parametrize("angles_deg", [(10, 75, 0.3), (-170, 100, -5), (45, 20, 12), (0, 89.9, 0), (179, 60, -179)])
def test_angles_round_trip_roll_nearest_zero(angles_deg):
    pan, tilt, roll = np.radians(angles_deg)
    R = rotation_from_angles(pan, tilt, roll)
    pan2, tilt2, roll2 = angles_from_rotation(R)
    np.testing.assert_allclose(rotation_from_angles(pan2, tilt2, roll2), R, atol=1e-12)
    # The other branch (tilt -> -tilt, pan + pi, roll + pi) has the larger |roll|.
    other_roll = math.remainder(roll + math.pi, 2 * math.pi)
    assert abs(roll2) <= abs(other_roll) + 1e-12
    if abs(roll) < math.pi / 2:
        np.testing.assert_allclose([pan2, tilt2, roll2], [pan, tilt, roll], atol=1e-12)


def test_projection_by_hand():
    # Camera at (0, 0, -10) looking straight down (tilt 0): world x -> image x, world y -> image y.
    camera = Camera(1000.0, 0.0, 0.0, 0.0, 0.0, (0.0, 0.0, -10.0), 1920, 1080)
    uv, in_front = camera.project(np.array([[1.0, 2.0, 0.0], [0.0, 0.0, 0.0]]))
    np.testing.assert_allclose(uv, [[960 + 100, 540 + 200], [960, 540]])
    assert in_front.all()
    # With k1: x_pix = f (1 + k1 r^2) x_n + p.
    camera = camera.replace(k1=0.1)
    uv, _ = camera.project(np.array([[1.0, 2.0, 0.0]]))
    r2 = 0.1**2 + 0.2**2
    np.testing.assert_allclose(uv, [[960 + 1000 * 0.1 * (1 + 0.1 * r2), 540 + 1000 * 0.2 * (1 + 0.1 * r2)]])


def test_points_behind_camera_are_masked():
    camera = main_camera()
    behind = camera.position_m - 5.0 * camera.optical_axis_w
    uv, in_front = camera.project(np.vstack([behind, [0.0, 0.0, 0.0]]))
    assert not in_front[0] and in_front[1]
    assert np.isnan(uv[0]).all() and np.isfinite(uv[1]).all()


@pytest.mark.parametrize("k1", [-0.5, -0.2, 0.0, 0.2, 0.5])
def test_backprojection_round_trip_whole_image(k1):
    camera = main_camera(k1=k1, focal_px=2500.0)
    u, v = np.meshgrid(np.linspace(0, 1919, 97), np.linspace(0, 1079, 55))
    uv = np.stack([u.ravel(), v.ravel()], axis=1)
    rays = camera.backproject(uv)
    np.testing.assert_allclose(np.linalg.norm(rays, axis=1), 1.0, atol=1e-12)
    uv2, in_front = camera.project(camera.position_m + 30.0 * rays)
    assert in_front.all()
    assert np.max(np.abs(uv2 - uv)) < 1e-6


def test_ground_intersection_round_trip():
    camera = main_camera()
    points = np.array([[0.0, 0.0, 0.0], [20.0, -10.0, 0.0], [-15.0, 5.0, 0.0]])
    uv, _ = camera.project(points)
    ground, hits = camera.ground_intersection(uv)
    assert hits.all()
    np.testing.assert_allclose(ground, points, atol=1e-8)
    # A pixel above the horizon does not hit the ground.
    sky = Camera.from_degrees(2000, 0, 0, 95, 0, (0, 55, -12), 1920, 1080)
    _, hits = sky.ground_intersection(np.array([[960.0, 100.0]]))
    assert not hits[0]


def test_rescaling_keeps_projection_proportional():
    camera = main_camera()
    small = camera.rescaled(960, 540)
    assert small.focal_px == pytest.approx(1100.0) and small.k1 == camera.k1
    points = np.array([[0.0, 0.0, 0.0], [30.0, 20.0, 0.0]])
    np.testing.assert_allclose(small.project(points)[0], camera.project(points)[0] / 2, atol=1e-9)


def test_soccernet_json_round_trip_and_rescale(tmp_path):
    camera = main_camera()
    path = tmp_path / "camera_00001.json"
    write_camera_file(path, camera, 960, 540)
    data = json.loads(path.read_text())
    assert data["principal_point"] == [480.0, 270.0]
    assert data["x_focal_length"] == pytest.approx(1100.0)
    assert len(data["radial_distortion"]) == 6 and data["radial_distortion"][0] == camera.k1
    back = read_camera_file(path, 1920, 1080)
    np.testing.assert_allclose(back.to_vector(), camera.to_vector(), atol=1e-9)
    assert (back.width_px, back.height_px) == (1920, 1080)


def test_reading_rejects_bad_fields(tmp_path):
    from broadtrack_graph.errors import InputError

    good = main_camera().to_soccernet_dict()
    for key, value, message in [
        ("pan_degrees", float("nan"), "not finite"),
        ("position_meters", [1, 2], "expected 3"),
        ("x_focal_length", "abc", "not numeric"),
    ]:
        bad = dict(good, **{key: value})
        path = tmp_path / f"camera_{key}.json"
        path.write_text(json.dumps(bad).replace("NaN", "NaN"))
        with pytest.raises(InputError, match=message) as info:
            read_camera_file(path)
        assert str(path) in str(info.value) and "\n" not in str(info.value)
    (tmp_path / "camera_empty.json").write_text("")
    with pytest.raises(InputError, match="empty"):
        read_camera_file(tmp_path / "camera_empty.json")


def test_reads_every_real_camera_file(sn_calibration_dir):
    files = list_camera_files(sn_calibration_dir / "nbjw-cameras")
    assert len(files) == 1417
    for path in files.values():
        data = json.loads(path.read_text())
        camera = read_camera_file(path)
        assert (camera.width_px, camera.height_px) == (960, 540)
        np.testing.assert_allclose(camera.R_cw, data["rotation_matrix"], atol=1e-9)
        pan, tilt, roll = np.degrees(angles_from_rotation(camera.R_cw))
        np.testing.assert_allclose([pan, tilt, roll], [data["pan_degrees"], data["tilt_degrees"], data["roll_degrees"]], atol=1e-7)


def test_a_camera_rescaled_to_its_own_resolution_is_itself():
    camera = Camera.from_degrees(1500.0, 0.02, 10.0, 70.0, 0.3, (0.0, 55.0, -12.0), 1920, 1080)
    assert camera.rescaled(1920, 1080) is camera
    half = camera.rescaled(960, 540)
    assert half.focal_px == pytest.approx(750.0) and (half.width_px, half.height_px) == (960, 540)
