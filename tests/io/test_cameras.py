"""Camera folders: a run folder or a cameras folder is accepted (and named), a folder without camera files is an error."""

from __future__ import annotations

import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.cameras import resolve_camera_folder, write_camera_file


def _camera() -> Camera:
    return Camera(1500.0, 0.0, 0.1, 1.3, 0.0, (0.0, 55.0, -12.0), 960, 540)


def test_run_folder_and_cameras_folder_both_resolve_to_the_cameras(tmp_path):
    write_camera_file(tmp_path / "run" / "cameras" / "camera_00001.json", _camera())
    (tmp_path / "run" / "track.jsonl").write_text("", encoding="utf-8")
    for given in (tmp_path / "run", tmp_path / "run" / "cameras"):
        folder, files = resolve_camera_folder(given)
        assert folder == tmp_path / "run" / "cameras" and list(files) == ["00001"]


@pytest.mark.parametrize("make", ["empty", "empty-cameras", "missing"])
def test_folder_without_camera_files_is_an_error(tmp_path, make):
    folder = tmp_path / "run"
    if make != "missing":
        folder.mkdir()
    if make == "empty-cameras":
        (folder / "cameras").mkdir()
    with pytest.raises(InputError) as error:
        resolve_camera_folder(folder)
    message = str(error.value)
    assert message.startswith(str(folder)) and "\n" not in message
    assert ("camera folder not found" if make == "missing" else "no camera_<id>.json file") in message
