"""``gridfield info``: the description is checked against values computed independently of
gridfield's readers (Pillow decoding, the raw map text, scikit-image labelling)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml
from PIL import Image
from skimage.measure import label

from gridfield.cli import main
from gridfield.io import bundled_map

from mapdata import image

KEYS = {"shape", "resolution", "origin", "border", "occupied_fraction", "obstacles", "source", "format",
        "occupancy_rule", "occupied_cells", "unknown_cells", "unknown_as"}


def run_json(capsys, *argv):
    rc = main(["info", *map(str, argv), "--json"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    assert err == ""
    lines = out.strip().splitlines()
    assert len(lines) == 1  # exactly one JSON object
    return json.loads(lines[0])


def components(occupied: np.ndarray) -> int:
    return int(label(occupied, connectivity=2).max())


def test_info_ros_map_json(capsys):
    path = bundled_map("turtlebot3_world/map.yaml")
    info = run_json(capsys, path)
    assert set(info) == KEYS
    with Image.open(path.parent / "map.pgm") as im:
        img = np.asarray(im)
    occupied = img != 254  # 0 occupied, 205 unknown -> obstacles by default
    assert info["shape"] == [384, 384]
    assert info["resolution"] == 0.05
    assert info["origin"] == [-10.0, -10.0]
    assert info["border"] == "wall"
    assert info["occupied_fraction"] == pytest.approx((795 + 138722) / 384**2)
    assert info["obstacles"] == components(occupied)
    assert info["format"] == "ros" and info["source"] == str(path)

    free = run_json(capsys, path, "--unknown", "free")
    assert free["occupied_fraction"] == pytest.approx(795 / 384**2)
    assert free["obstacles"] == components(img == 0)
    assert free["border"] == "open"


def ros_pixel_classes(yaml_path) -> tuple[int, int, int]:
    """(occupied, unknown, free) pixel counts of a trinary ROS map, from its image and the YAML's own
    thresholds (map_server: occupancy p = (255 - v) / 255, or v / 255 with negate; p above occupied_thresh
    is occupied, below free_thresh free, between unknown). No pixel may sit on a threshold, where the two
    ROS loaders differ."""
    doc = yaml.safe_load(yaml_path.read_text())
    assert doc.get("mode", "trinary") == "trinary"
    with image(yaml_path.parent / doc["image"]) as im:
        v = np.asarray(im.convert("L"), dtype=np.float64)
    p = v / 255.0 if doc.get("negate", 0) else (255.0 - v) / 255.0
    occ, free = float(doc.get("occupied_thresh", 0.65)), float(doc.get("free_thresh", 0.196))
    assert not np.any(np.isclose(p, occ, atol=1e-6)) and not np.any(np.isclose(p, free, atol=1e-6))
    n_occ, n_free = int(np.count_nonzero(p > occ)), int(np.count_nonzero(p < free))
    return n_occ, p.size - n_occ - n_free, n_free


@pytest.mark.parametrize("name", ["turtlebot3_world/map.yaml", "mdr_wrs20-arena/map.yaml",
                                  "nav2_warehouse/warehouse.yaml"])
def test_info_says_how_many_cells_are_unknown_and_that_they_count_as_occupied(test_maps, name, capsys):
    """ROS maps' grey (205) cells are unknown: info counts them as occupied and says so, in text and JSON."""
    path = test_maps / "ros_maps" / name
    n_occ, n_unknown, n_free = ros_pixel_classes(path)
    assert n_unknown > 0
    cells = n_occ + n_unknown + n_free
    info = run_json(capsys, path)
    assert info["occupied_cells"] == n_occ + n_unknown
    assert info["unknown_cells"] == n_unknown and info["unknown_as"] == "occupied"
    assert info["occupied_fraction"] == pytest.approx((n_occ + n_unknown) / cells)
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"occupied cells:    {n_occ + n_unknown} of {cells} (of which unknown {n_unknown}, treated as occupied)\n" in out
    free = run_json(capsys, path, "--unknown", "free")
    assert free["occupied_cells"] == n_occ
    assert free["unknown_cells"] == n_unknown and free["unknown_as"] == "free"
    assert main(["info", str(path), "--unknown", "free"]) == 0
    out = capsys.readouterr().out
    assert f"occupied cells:    {n_occ} of {cells}\n" in out
    assert f"unknown cells:     {n_unknown}, treated as free (--unknown free)\n" in out


def test_info_of_a_map_without_unknown_cells_says_nothing_of_them(test_maps, capsys):
    """A Moving AI map has no unknown cells (null in JSON, no mention in text); a ROS map whose pixels are
    all free or occupied has none either (0, and no mention)."""
    arena = run_json(capsys, test_maps / "movingai" / "arena" / "arena.map.gz")
    assert arena["unknown_cells"] is None and arena["unknown_as"] is None
    path = test_maps / "ros_maps" / "nav2_smoothers_world" / "smoothers_world.yaml"
    n_occ, n_unknown, n_free = ros_pixel_classes(path)
    assert n_unknown == 0
    info = run_json(capsys, path)
    assert info["occupied_cells"] == n_occ and info["unknown_cells"] == 0
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"occupied cells:    {n_occ} of {n_occ + n_free}\n" in out
    cells = [line for line in out.splitlines() if not line.startswith("occupancy rule:")]  # the rule names its
    assert "unknown" not in "\n".join(cells)  # middle band ("between unknown"); no line speaks of unknown cells


def test_info_movingai_json(capsys):
    path = bundled_map("arena/arena.map")
    info = run_json(capsys, path)
    rows = path.read_text().split("\n")[4:53]
    blocked = np.array([[ch != "." for ch in r] for r in rows])
    assert info["shape"] == [49, 49] and info["resolution"] == 1.0 and info["origin"] == [0.0, 0.0]
    assert info["border"] == "wall" and info["format"] == "movingai"
    assert info["occupied_fraction"] == pytest.approx(blocked.mean())
    assert info["obstacles"] == components(blocked)


def test_info_bitmap_resolution_and_npz(capsys, tmp_path):
    img = np.full((4, 6), 254, dtype=np.uint8)
    img[0, 0] = 0  # top-left: one obstacle
    img[2:4, 3:5] = 0  # a 2x2 block
    img[3, 5] = 0  # touches the block diagonally -> same 8-connected component
    Image.fromarray(img).save(tmp_path / "m.png")
    npz = tmp_path / "out.npz"
    info = run_json(capsys, tmp_path / "m.png", "--resolution", "0.5", "--npz", npz)
    assert info["shape"] == [4, 6] and info["resolution"] == 0.5 and info["border"] == "open"
    assert info["obstacles"] == 2 and info["occupied_fraction"] == pytest.approx(6 / 24)
    assert info["format"] == "bitmap"
    with np.load(npz) as z:
        np.testing.assert_array_equal(z["occupied"], (img == 0)[::-1])
        assert float(z["resolution"]) == 0.5 and z["origin"].tolist() == [0.0, 0.0] and str(z["border"]) == "open"
    # the written file is itself a map gridfield reads
    again = run_json(capsys, npz)
    assert again["shape"] == [4, 6] and again["obstacles"] == 2 and again["format"] == "npz"


def test_info_world(capsys):
    path = bundled_map("seed000.yaml")
    info = run_json(capsys, path, "--resolution", "0.5")
    assert info["format"] == "world" and info["obstacles"] == 3  # three polygons in seed 000
    assert info["shape"] == [40, 50]  # bounds 25 x 20 at 0.5
    assert info["resolution"] == 0.5 and info["origin"] == [0.0, 0.0]
    assert 0 < info["occupied_fraction"] < 1


def test_info_text(capsys):
    rc = main(["info", str(bundled_map("nav2_depot/depot.yaml"))])
    out, err = capsys.readouterr()
    assert rc == 0 and err == ""
    assert "shape:             307 rows x 604 cols" in out
    assert "resolution:        0.05" in out
    assert "border:            wall" in out
    assert "occupied fraction: 0.0321" in out  # 5947 / 185428
    assert "format:            ros" in out


def one_line_error(capsys, argv) -> str:
    rc = main(argv)
    out, err = capsys.readouterr()
    assert rc == 2
    assert out == ""
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert lines[0].startswith("gridfield info: error: ")
    assert "Traceback" not in err
    return lines[0]


def test_info_missing_file(capsys, tmp_path):
    msg = one_line_error(capsys, ["info", str(tmp_path / "nope.yaml")])
    assert "nope.yaml: no such file" in msg


def test_info_malformed_map(capsys, tmp_path):
    f = tmp_path / "bad.map"
    f.write_text("type octile\nheight 3\nwidth 4\nmap\n....\n..x.\n....\n")
    msg = one_line_error(capsys, ["info", str(f), "--json"])
    assert "bad.map: line 6, column 3: invalid map character 'x'" in msg


def test_info_malformed_ros_yaml(capsys, tmp_path):
    f = tmp_path / "m.yaml"
    f.write_text("image: m.pgm\norigin: [0, 0, 0]\n")
    msg = one_line_error(capsys, ["info", str(f)])
    assert "m.yaml: missing key 'resolution'" in msg


def test_info_option_errors(capsys):
    msg = one_line_error(capsys, ["info", str(bundled_map("arena/arena.map")), "--resolution", "2"])
    assert "--resolution applies to world files and bitmaps" in msg
    msg = one_line_error(capsys, ["info", str(bundled_map("arena/arena.map")), "--unknown", "free"])
    assert "option unknown does not apply to a Moving AI map" in msg


WORLD_NO_RESOLUTION = """\
bounds: [-2, 0, 10, 5]
border: wall
obstacles:
  - circle: {center: [5, 2], radius: 1}
  - circle: {center: [8, 3], radius: 0.5}
  - polygon: [[0, 0], [1, 0], [1, 1]]
  - segment: [[2, 4], [3, 4.5]]
start: [-1.5, 0.5]
goal: [9.5, 4.5]
robot: {radius: 0.25}
"""


def test_info_world_without_resolution_is_described_from_its_vectors(capsys, tmp_path, monkeypatch):
    import yaml

    import gridfield.geometry.rasterize

    f = tmp_path / "w.yaml"
    f.write_text(WORLD_NO_RESOLUTION)
    spec = yaml.safe_load(WORLD_NO_RESOLUTION)
    kinds: dict[str, int] = {}
    for entry in spec["obstacles"]:
        (kind,) = entry
        kinds[kind] = kinds.get(kind, 0) + 1

    def no_raster(*a, **k):
        raise AssertionError("info rasterized a world that sets no resolution")


    monkeypatch.setattr(gridfield.geometry.rasterize, "as_gridmap", no_raster)
    info = run_json(capsys, f)
    assert info["format"] == "world" and info["shape"] is None and info["resolution"] is None
    assert info["occupied_fraction"] is None
    assert info["bounds"] == spec["bounds"] and info["border"] == "wall"
    assert info["obstacles"] == len(spec["obstacles"]) and info["obstacle_kinds"] == kinds
    assert info["start"] == spec["start"] and info["goal"] == spec["goal"]
    assert info["robot"] == "disc of radius 0.25"

    rc = main(["info", str(f)])
    out, err = capsys.readouterr()
    assert rc == 0 and err == ""
    assert "pass --resolution" in out and "2 circles" in out and "start:             (-1.5, 0.5)" in out

    msg = one_line_error(capsys, ["info", str(f), "--npz", str(tmp_path / "o.npz")])
    assert "pass --resolution" in msg


def test_info_world_raster_size_at_the_resolution_it_would_use(capsys, tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text(WORLD_NO_RESOLUTION)
    info = run_json(capsys, f, "--resolution", "0.3")
    assert info["shape"] == [math.ceil(5 / 0.3 - 1e-9), math.ceil(12 / 0.3 - 1e-9)]  # 17 x 40
    assert info["resolution"] == 0.3 and 0 < info["occupied_fraction"] < 1
    seed = run_json(capsys, bundled_map("seed000.yaml"))  # the world's own resolution 0.05
    assert seed["shape"] == [400, 500] and seed["obstacle_kinds"] == {"polygon": 3}
