import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.mot import read_mot, write_mot


def test_reads_boxes_and_reports_bad_lines(tmp_path):
    path = tmp_path / "track.txt"
    path.write_text(
        "# comment\n"
        "1,3,100,200,20,60,0.9,-1,-1,-1\n"
        "1,4,300,210,22,58,-1\n"
        "2,3,102,201,20,60,0.8\n"
        "0,5,10,10,5,5,1\n"            # frame below 1
        "2,6,nan,10,5,5,1\n"           # NaN box
        "2,7,10,10,0,5,1\n"            # empty box
        "3,x,1,2,3,4\n"                # malformed
        "3,1,2\n"                      # too few fields
        "\n")
    boxes = read_mot(path, (1920, 1080))
    assert boxes.kind == "mot" and boxes.image_size == (1920, 1080)
    assert [f.frame_index for f in boxes.frames] == [0, 1]
    first = boxes.frames[0]
    np.testing.assert_array_equal(first.track_ids, [3, 4])
    np.testing.assert_allclose(first.boxes_px[0], [100, 200, 120, 260])
    np.testing.assert_allclose(first.confidences, [0.9, 1.0])
    assert len(boxes.issues) == 5
    assert all(str(path) in issue for issue in boxes.issues)


def test_round_trip(tmp_path):
    path = tmp_path / "a.txt"
    path.write_text("1,3,100,200,20,60,0.9\n2,3,101,200,20,60,0.9\n")
    boxes = read_mot(path)
    write_mot(tmp_path / "b.txt", boxes)
    again = read_mot(tmp_path / "b.txt")
    np.testing.assert_allclose(again.frames[1].boxes_px, boxes.frames[1].boxes_px, atol=0.01)


def test_empty_file_is_an_input_error(tmp_path):
    path = tmp_path / "empty.txt"
    path.write_text("")
    with pytest.raises(InputError):
        read_mot(path)
