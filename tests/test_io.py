"""Map readers and writers: expected values come from the upstream fixtures, the MANIFEST tables,
the raw file text, or Pillow decoding the same image independently of gridfield's own parser."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.world import World
from gridfield.io import (
    Scenarios,
    bundled_map,
    read,
    read_bitmap,
    read_movingai_map,
    read_npz,
    read_npz_arrays,
    read_ros_map,
    read_scen,
    ros_occupancy_values,
    write_bitmap,
    write_npz,
    write_ros_map,
)

from mapdata import MOVINGAI, ROS_MAPS, TEST_MAPS, image, raw

FIXTURES = TEST_MAPS / "ros_map_fixtures"
NAV2_TESTMAP = FIXTURES / "nav2_testmap"
ROS1_TEST = FIXTURES / "ros1_map_server_test"


def cpp_arrays(path: Path) -> list[np.ndarray]:
    """The ``g_valid_image_content[] = {...}`` arrays of an upstream test_constants.cpp, in file order."""
    text = path.read_text()
    blocks = re.findall(r"g_valid_image_content\[\]\s*=\s*\{([^}]*)\}", text)
    out = []
    for b in blocks:
        vals = np.array([int(v) for v in re.findall(r"-?\d+", b)], dtype=np.int8)
        n = math.isqrt(vals.size)
        out.append(vals.reshape(n, n))  # row-major from the LOWER-left: already gridfield's row order
    return out


def pil_array(path: Path) -> np.ndarray:
    """Decode an image with Pillow (independently of gridfield's readers), top row first."""
    with image(path) as im:
        return np.asarray(im).copy()


def write_yaml(path: Path, **doc) -> Path:
    path.write_text(yaml.safe_dump(doc, default_flow_style=None))
    return path


def ros_yaml(tmp_path: Path, image: Path | str, name: str = "m.yaml", **over) -> Path:
    doc = {"image": str(image), "resolution": 0.1, "origin": [0.0, 0.0, 0.0], "negate": 0,
           "occupied_thresh": 0.65, "free_thresh": 0.196}
    doc.update(over)
    return write_yaml(tmp_path / name, **doc)


# ----------------------------------------------------------------------------------------
# bitmaps
# ----------------------------------------------------------------------------------------
# An asymmetric 3 x 4 picture, top row first: the top-left pixel is black, the bottom-right too.
PICTURE = np.array([[0, 254, 254, 254],
                    [254, 0, 254, 254],
                    [254, 254, 254, 0]], dtype=np.uint8)


def pgm_p5(img: np.ndarray, maxval: int = 255) -> bytes:
    h, w = img.shape
    head = f"P5\n# CREATOR: test\n# second comment\n{w}  {h}\n\n{maxval}\n".encode()
    data = img.astype(">u2").tobytes() if maxval > 255 else img.astype(np.uint8).tobytes()
    return head + data


def pgm_p2(img: np.ndarray, maxval: int = 255) -> bytes:
    h, w = img.shape
    rows = "\n".join(" ".join(str(int(v)) for v in row) + "  # row comment" for row in img)
    return f"P2 # magic\n{w} # width\n{h}\n{maxval}\n{rows}\n".encode()


@pytest.mark.parametrize("kind", ["png", "bmp", "pgm-p5", "pgm-p2", "pgm-16bit", "pgm-maxval15", "rgb-png"])
def test_bitmap_orientation(tmp_path, kind):
    res, h, w = 0.25, *PICTURE.shape
    if kind == "png":
        f = tmp_path / "m.png"
        Image.fromarray(PICTURE).save(f)
    elif kind == "bmp":
        f = tmp_path / "m.bmp"
        Image.fromarray(PICTURE).save(f)
    elif kind == "rgb-png":
        f = tmp_path / "m.png"
        Image.fromarray(np.repeat(PICTURE[..., None], 3, axis=2)).save(f)
    elif kind == "pgm-p5":
        f = tmp_path / "m.pgm"
        f.write_bytes(pgm_p5(PICTURE))
    elif kind == "pgm-p2":
        f = tmp_path / "m.pgm"
        f.write_bytes(pgm_p2(PICTURE))
    elif kind == "pgm-16bit":
        f = tmp_path / "m.pgm"
        f.write_bytes(pgm_p5(PICTURE.astype(np.int64) * 257, maxval=65535))
    else:
        f = tmp_path / "m.pgm"
        f.write_bytes(pgm_p2(np.where(PICTURE == 0, 0, 15), maxval=15))
    m = read_bitmap(f, resolution=res, origin=(1.0, -2.0))
    assert m.shape == (h, w)
    assert m.grid.resolution == res and m.grid.origin == (1.0, -2.0)
    assert m.source == str(f) and m.meta["format"] == "bitmap"
    # the image's top-left pixel is the world's upper-left cell
    top_left = (1.0 + 0.5 * res, -2.0 + (h - 0.5) * res)
    bottom_left = (1.0 + 0.5 * res, -2.0 + 0.5 * res)
    bottom_right = (1.0 + (w - 0.5) * res, -2.0 + 0.5 * res)
    assert m.is_free([top_left, bottom_left, bottom_right]).tolist() == [False, True, False]
    # the whole array: row 0 is the image's bottom row
    expected = np.array([[0, 0, 0, 1], [0, 1, 0, 0], [1, 0, 0, 0]], dtype=bool)
    np.testing.assert_array_equal(m.occupied, expected)


def test_bitmap_negate_threshold_and_luma(tmp_path):
    # grey levels 0, 100, 200, 255 in one row: occupancy (255 - v)/255 = 1, .61, .22, 0
    f = tmp_path / "g.png"
    Image.fromarray(np.array([[0, 100, 200, 255]], dtype=np.uint8)).save(f)
    assert read_bitmap(f).occupied.tolist() == [[True, True, False, False]]
    assert read_bitmap(f, threshold=0.7).occupied.tolist() == [[True, False, False, False]]
    assert read_bitmap(f, threshold=0.1).occupied.tolist() == [[True, True, True, False]]
    assert read_bitmap(f, negate=True).occupied.tolist() == [[False, False, True, True]]
    # colours by Rec. 601 luma: red 76 (occupancy .70), green 150 (.41), blue 29 (.89), yellow 226 (.11)
    c = tmp_path / "c.png"
    Image.fromarray(np.array([[[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]]], dtype=np.uint8)).save(c)
    assert read_bitmap(c).occupied.tolist() == [[True, False, True, False]]


def test_bitmap_transparency_is_unknown(tmp_path):
    rgba = np.zeros((1, 3, 4), dtype=np.uint8)
    rgba[0, :, :3] = 254  # white everywhere
    rgba[0, :, 3] = [255, 0, 128]  # opaque, transparent, half transparent
    f = tmp_path / "a.png"
    Image.fromarray(rgba).save(f)
    m = read_bitmap(f)
    assert m.occupied.tolist() == [[False, True, True]]
    assert m.meta["unknown_fraction"] == pytest.approx(2 / 3)
    assert read_bitmap(f, unknown="free").occupied.tolist() == [[False, False, False]]
    # grey + alpha, and a palette image with a transparent entry
    la = tmp_path / "la.png"
    Image.fromarray(rgba).convert("LA").save(la)
    assert read_bitmap(la).occupied.tolist() == [[False, True, True]]
    pal = Image.new("P", (2, 1))
    pal.putpalette([0, 0, 0, 255, 255, 255] + [0] * (256 * 3 - 6))
    pal.putdata([0, 1])
    pal.save(tmp_path / "p.png")
    assert read_bitmap(tmp_path / "p.png").occupied.tolist() == [[True, False]]
    pal.save(tmp_path / "pt.png", transparency=1)
    assert read_bitmap(tmp_path / "pt.png").occupied.tolist() == [[True, True]]


def test_bilevel_png(tmp_path):
    img = Image.new("1", (3, 2), 1)
    img.putpixel((0, 0), 0)  # top-left black
    img.save(tmp_path / "b.png")
    assert read_bitmap(tmp_path / "b.png").occupied.tolist() == [[False, False, False], [True, False, False]]


@pytest.mark.parametrize("name", ["testmap.png", "testmap.pgm", "testmap.bmp"])
def test_read_bitmap_of_nav2_testmap(name):
    expected = cpp_arrays(NAV2_TESTMAP / "test_constants.cpp")[0]
    m = read_bitmap(NAV2_TESTMAP / name, resolution=0.1)
    np.testing.assert_array_equal(m.occupied, expected == 100)


# ----------------------------------------------------------------------------------------
# ROS map_server fixtures
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("semantics", ["nav2", "ros1"])
@pytest.mark.parametrize("name", ["testmap.png", "testmap.pgm", "testmap.bmp"])
def test_nav2_testmap_values(tmp_path, name, semantics):
    expected = cpp_arrays(NAV2_TESTMAP / "test_constants.cpp")[0]
    assert expected.shape == (10, 10) and expected[1, 0] == 100 and expected[0].tolist() == [0] * 10
    if name == "testmap.png":
        yml = NAV2_TESTMAP / "testmap.yaml"  # the upstream YAML itself (yaw 1.0 does not change values)
    else:
        yml = ros_yaml(tmp_path, NAV2_TESTMAP / name, origin=[2.0, 3.0, 1.0], mode="trinary")
    values = ros_occupancy_values(yml, semantics=semantics)
    assert values.dtype == np.int8
    np.testing.assert_array_equal(values, expected)


def test_ros1_testmap_with_utest_thresholds(tmp_path):
    expected = cpp_arrays(ROS1_TEST / "test_constants.cpp")[0]
    yml = ros_yaml(tmp_path, ROS1_TEST / "testmap.png", occupied_thresh=0.65, free_thresh=0.1)
    np.testing.assert_array_equal(ros_occupancy_values(yml, semantics="ros1"), expected)


def test_ros1_testmap2_negate():
    expected = cpp_arrays(ROS1_TEST / "test_constants.cpp")[1]
    assert expected.shape == (12, 12)
    values = ros_occupancy_values(ROS1_TEST / "testmap2.yaml", semantics="ros1")
    np.testing.assert_array_equal(values, expected)
    # without negate the picture is inverted: every cell changes
    with pytest.raises(AssertionError):
        np.testing.assert_array_equal(values, 100 - expected)


def test_rotated_fixture_gives_clear_error():
    from gridfield.core.errors import MapFormatError

    with pytest.raises(MapFormatError, match=r"testmap\.yaml: origin yaw 1 rad is not supported"):
        read_ros_map(NAV2_TESTMAP / "testmap.yaml")
    with pytest.raises(MapFormatError, match=r"testmap2\.yaml: origin yaw -1 rad"):
        read_ros_map(ROS1_TEST / "testmap2.yaml")


def test_testmap_with_zero_yaw_reads_as_grid(tmp_path):
    expected = cpp_arrays(NAV2_TESTMAP / "test_constants.cpp")[0]
    m = read_ros_map(ros_yaml(tmp_path, NAV2_TESTMAP / "testmap.png", origin=[2.0, 3.0, 0.0]))
    np.testing.assert_array_equal(m.occupied, expected == 100)
    assert m.grid.resolution == 0.1 and m.grid.origin == (2.0, 3.0)
    # cell (row 1, col 0) is occupied: world point (2.05, 3.15); (row 0, col 0) is free
    assert m.is_free([[2.05, 3.15], [2.05, 3.05]]).tolist() == [False, True]
    assert m.meta["format"] == "ros" and m.meta["unknown_fraction"] == 0.0


@pytest.mark.parametrize("semantics", ["ros1", "nav2"])
def test_spectrum_modes(tmp_path, semantics):
    img = ROS1_TEST / "spectrum.png"

    def counts(mode):
        yml = ros_yaml(tmp_path, img, occupied_thresh=0.65, free_thresh=0.1, mode=mode)
        v = ros_occupancy_values(yml, semantics=semantics)
        assert v.shape == (16, 16)
        return np.bincount(v.view(np.uint8).ravel(), minlength=256)

    tri = counts("trinary")
    assert (tri[100], tri[0], tri[255]) == (90, 26, 140)
    if semantics == "ros1":  # utest.cpp testMapMode
        sc = counts("scale")
        assert (sc[100], sc[0], sc[1:100].sum()) == (90, 26, 140)
        raw = counts("raw")
        assert (raw == 1).all()


# (local dir, yaml name, free, occupied, unknown, other) -- MANIFEST section 2, ros1 columns
ROS_TABLE = [
    ("nav2_depot", "depot.yaml", 179481, 5947, 0, 0),
    ("nav2_depot_speed_mask", "depot_speed.yaml", 0, 0, 0, 185428),
    ("nav2_warehouse", "warehouse.yaml", 1422292, 30951, 230801, 0),
    ("nav2_planner_benchmark_100by100_10", "100by100_10.yaml", 3586940, 413060, 0, 0),
    ("nav2_smoothers_world", "smoothers_world.yaml", 79424, 10576, 0, 0),
    ("turtlebot3_world", "map.yaml", 7939, 795, 138722, 0),
    ("aws_small_warehouse_005", "map.yaml", 93698, 3673, 23607, 0),
    ("mdr_wrs20-arena", "map.yaml", 8470, 714, 70688, 0),
]
NAV2_DIFFERS = {"nav2_depot_speed_mask": 127481}


@pytest.mark.parametrize(("folder", "name", "free", "occ", "unk", "other"), ROS_TABLE, ids=[r[0] for r in ROS_TABLE])
def test_ros_maps_match_manifest_counts(folder, name, free, occ, unk, other):
    yml = ROS_MAPS / folder / name
    v1 = ros_occupancy_values(yml, semantics="ros1")
    counts = ((v1 == 0).sum(), (v1 == 100).sum(), (v1 == -1).sum(), ((v1 != 0) & (v1 != 100) & (v1 != -1)).sum())
    assert counts == (free, occ, unk, other)
    v2 = ros_occupancy_values(yml, semantics="nav2")
    assert int((v1 != v2).sum()) == NAV2_DIFFERS.get(folder, 0)
    if folder == "nav2_planner_benchmark_100by100_10":
        return  # large; read_ros_map of it is covered below
    m = read_ros_map(yml)
    assert m.shape == v1.shape
    if other == 0:  # trinary maps: obstacles = occupied + unknown; with unknown="free" only the occupied
        assert int(m.occupied.sum()) == occ + unk
        assert int(read_ros_map(yml, unknown="free").occupied.sum()) == occ
        assert m.meta["unknown_fraction"] == pytest.approx(unk / v1.size)


def test_planner_benchmark_negate_map():
    yml = ROS_MAPS / "nav2_planner_benchmark_100by100_10" / "100by100_10.yaml"
    m = read_ros_map(yml)
    assert m.shape == (2000, 2000) and m.grid.resolution == 0.05
    assert int(m.occupied.sum()) == 413060  # white (255) pixels are the obstacles: negate 1
    raw = pil_array(ROS_MAPS / "nav2_planner_benchmark_100by100_10" / "100by100_10.pgm.gz")
    np.testing.assert_array_equal(m.occupied, (raw == 255)[::-1])


def test_scale_mode_map_obstacles():
    # speed mask: black pixels (3735) are 100 under nav2 (inclusive threshold 1.0), 99 under ros1
    yml = ROS_MAPS / "nav2_depot_speed_mask" / "depot_speed.yaml"
    assert int(read_ros_map(yml).occupied.sum()) == 3735
    assert int(read_ros_map(yml, semantics="ros1").occupied.sum()) == 0
    assert read_ros_map(yml).meta["mode"] == "scale"


def test_ros_map_orientation_turtlebot3():
    folder = ROS_MAPS / "turtlebot3_world"
    m = read_ros_map(folder / "map.yaml", unknown="free")
    img = pil_array(folder / "map.pgm.gz")  # independent decoder, top row first
    h = img.shape[0]
    flipped = img[::-1]
    # pick pixels whose vertically mirrored pixel has the opposite meaning
    occ_rc = np.argwhere((img == 0) & (flipped == 254))[0]
    free_rc = np.argwhere((img == 254) & (flipped == 0))[0]
    res, (ox, oy) = 0.05, (-10.0, -10.0)

    def world(rc):
        r, c = rc
        return [ox + (c + 0.5) * res, oy + (h - 1 - r + 0.5) * res]

    assert m.is_free([world(occ_rc), world(free_rc)]).tolist() == [False, True]
    assert m.grid.border == "open"
    assert read_ros_map(folder / "map.yaml").grid.border == "wall"
    assert read_ros_map(folder / "map.yaml", border="open").grid.border == "open"


def test_ros_alpha_is_unknown_in_nav2(tmp_path):
    rgba = np.full((1, 3, 4), 254, dtype=np.uint8)
    rgba[0, :, 3] = [255, 0, 200]
    Image.fromarray(rgba).save(tmp_path / "a.png")
    yml = ros_yaml(tmp_path, "a.png")  # relative to the YAML
    assert ros_occupancy_values(yml, semantics="nav2").tolist() == [[0, -1, -1]]
    # ros1 averages alpha into the trinary mean: (254*3 + 0)/4 = 190.5 -> occupancy .25 -> unknown
    assert ros_occupancy_values(yml, semantics="ros1").tolist() == [[0, -1, 0]]
    assert read_ros_map(yml).occupied.tolist() == [[False, True, True]]


def test_ros_threshold_inclusiveness(tmp_path):
    # occupancies 1, .498, 0 against thresholds exactly 1.0 and 0.0: nav2 compares >= / <=, ros1 > / <
    Image.fromarray(np.array([[0, 128, 255]], dtype=np.uint8)).save(tmp_path / "t.png")
    yml = ros_yaml(tmp_path, "t.png", occupied_thresh=1.0, free_thresh=0.0)
    assert ros_occupancy_values(yml, semantics="nav2").tolist() == [[100, -1, 0]]
    assert ros_occupancy_values(yml, semantics="ros1").tolist() == [[-1, -1, -1]]
    # scale mode: nav2 rounds 100 * ratio, ros1 truncates 1 + 98 * ratio
    yml = ros_yaml(tmp_path, "t.png", occupied_thresh=1.0, free_thresh=0.0, mode="scale")
    assert ros_occupancy_values(yml, semantics="nav2").tolist() == [[100, 50, 0]]  # round(49.8)
    assert ros_occupancy_values(yml, semantics="ros1").tolist() == [[99, 49, 1]]  # trunc(1 + 98 * .498) = 49


def test_ros_yaml_defaults_and_relative_image(tmp_path):
    (tmp_path / "sub").mkdir()
    Image.fromarray(PICTURE).save(tmp_path / "sub" / "p.png")
    yml = write_yaml(tmp_path / "sub" / "m.yaml", image="p.png", resolution=0.5, origin=[-1, -1, 0])
    m = read_ros_map(yml)  # negate 0, thresholds 0.65 / 0.196, trinary when absent
    assert m.meta["mode"] == "trinary"
    np.testing.assert_array_equal(m.occupied, (PICTURE == 0)[::-1])
    assert m.grid.origin == (-1.0, -1.0)


# ----------------------------------------------------------------------------------------
# Moving AI
# ----------------------------------------------------------------------------------------
def map_text_rows(path: Path) -> list[str]:
    lines = raw(path).decode().replace("\r", "").split("\n")
    i = lines.index("map")
    h = int(lines[1].split()[1])
    return lines[i + 1 : i + 1 + h]


def test_movingai_orientation_arena():
    path = bundled_map("arena/arena.map")
    rows = map_text_rows(path)
    h = len(rows)
    m = read_movingai_map(path)
    # a '.' whose vertical mirror is blocked, and a blocked cell whose mirror is '.'
    free_yx = next((y, x) for y in range(h) for x, ch in enumerate(rows[y]) if ch == "." and rows[h - 1 - y][x] != ".")
    blocked_yx = next((y, x) for y in range(h) for x, ch in enumerate(rows[y]) if ch != "." and rows[h - 1 - y][x] == ".")

    def world(yx):
        y, x = yx
        return [x + 0.5, h - 1 - y + 0.5]

    assert m.is_free([world(free_yx), world(blocked_yx)]).tolist() == [True, False]
    assert m.grid.border == "wall" and m.grid.origin == (0.0, 0.0) and m.grid.resolution == 1.0


MAI_DIRS = sorted(p for p in MOVINGAI.glob("*") if p.is_dir())


@pytest.mark.parametrize("folder", MAI_DIRS, ids=[p.name for p in MAI_DIRS])
def test_every_movingai_map_loads(folder):
    path = next(folder.glob("*.map.gz"))
    rows = map_text_rows(path)
    m = read_movingai_map(path)
    assert m.shape == (len(rows), len(rows[0]))
    blocked = sum(sum(ch in "@OTW" for ch in r) for r in rows)
    assert int(m.occupied.sum()) == blocked
    # every scenario start and goal lies on a passable cell (a flipped map would break this)
    s = read_scen(next(folder.glob("*.scen.gz")), map_height=m.shape[0])
    assert s.map_name[0] == path.name.removesuffix(".gz")
    assert m.is_free(s.start_xy).all() and m.is_free(s.goal_xy).all()


def test_movingai_chars_and_crlf(tmp_path):
    text = "type octile\nheight 2\nwidth 4\nmap\n.GS@\nOTW.\n"
    (tmp_path / "a.map").write_text(text)
    (tmp_path / "b.map").write_bytes(text.replace("\n", "\r\n").encode())
    a, b = read_movingai_map(tmp_path / "a.map"), read_movingai_map(tmp_path / "b.map", border="open")
    expected = np.array([[True, True, True, False], [False, False, False, True]])  # row 0 = last line
    np.testing.assert_array_equal(a.occupied, expected)
    np.testing.assert_array_equal(b.occupied, expected)
    assert b.grid.border == "open" and a.meta["format"] == "movingai"
    # no final newline is fine too
    (tmp_path / "c.map").write_text(text.rstrip("\n"))
    np.testing.assert_array_equal(read_movingai_map(tmp_path / "c.map").occupied, expected)


def test_berlin_crlf_equals_lf(tmp_path):
    src = MOVINGAI / "Berlin_0_256" / "Berlin_0_256.map.gz"
    assert b"\r\n" in raw(src)
    lf = tmp_path / "lf.map"
    lf.write_bytes(raw(src).replace(b"\r\n", b"\n"))
    np.testing.assert_array_equal(read_movingai_map(src).occupied, read_movingai_map(lf).occupied)


# ----------------------------------------------------------------------------------------
# scenarios
# ----------------------------------------------------------------------------------------
def test_scen_arena_bundled():
    s = read_scen(bundled_map("arena/arena.map.scen"))
    assert isinstance(s, Scenarios) and len(s) == 160
    assert (s.version, s.precision, s.digits) == ("1", "significant", 6)
    # first line: 0 maps/dao/arena.map 49 49 1 11 1 12 1
    assert s.bucket[0] == 0 and s.map_name[0] == "arena.map" and (s.width[0], s.height[0]) == (49, 49)
    np.testing.assert_array_equal(s.start_xy[0], [1.5, 49 - 1 - 11 + 0.5])
    np.testing.assert_array_equal(s.goal_xy[0], [1.5, 49 - 1 - 12 + 0.5])
    np.testing.assert_array_equal(s.start_cell[0], [37, 1])
    np.testing.assert_array_equal(s.goal_cell[0], [36, 1])
    assert s.optimal[0] == 1.0 and not s.no_path.any()
    # cells and world points agree through the grid geometry
    g = Grid((49, 49), 1.0)
    np.testing.assert_array_equal(g.cell_to_world(s.start_cell), s.start_xy)


def test_scen_variants():
    ar = read_scen(MOVINGAI / "AR0011SR" / "AR0011SR.map.scen.gz")
    assert (ar.version, ar.precision, ar.digits, len(ar)) == ("1.0", "decimals", 2, 1280)
    # 61 maps/bgmaps/AR0011SR.map 512 512 210 395 87 201 244.95
    assert ar.bucket[0] == 61 and ar.optimal[0] == 244.95 and ar.map_name[0] == "AR0011SR.map"
    np.testing.assert_array_equal(ar.start_cell[0], [512 - 1 - 395, 210])
    assert ar.tolerance()[0] == pytest.approx(0.005 + 244.95e-5)

    mz = read_scen(MOVINGAI / "maze512-32-9" / "maze512-32-9.map.scen.gz")
    assert (mz.version, mz.precision, mz.digits, len(mz)) == ("1", "decimals", 8, 8010)
    assert mz.optimal[0] == 3.41421356

    be = read_scen(MOVINGAI / "Berlin_0_256" / "Berlin_0_256.map.scen.gz")
    assert (be.precision, be.digits, len(be)) == ("decimals", 8, 930)

    rm = read_scen(MOVINGAI / "rmtst01" / "rmtst01.map.scen.gz")
    assert (rm.precision, rm.digits, len(rm)) == ("significant", 6, 470)
    assert np.flatnonzero(rm.no_path).tolist() == [4, 9]  # GPPC "no path" markers (MANIFEST 5.1)
    assert rm.tolerance()[0] == pytest.approx(0.5e-5 + 2.41421e-5)  # 2.41421: 5 decimals printed


def test_scen_start_equals_goal_is_not_no_path(tmp_path):
    f = tmp_path / "s.scen"
    f.write_text("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\t0\n0\tm.map\t4\t3\t0\t0\t3\t2\t0\n")
    s = read_scen(f)
    assert s.no_path.tolist() == [False, True]
    np.testing.assert_array_equal(s.goal_xy[1], [3.5, 0.5])  # y = 2 is the bottom row of a 3-high map


# ----------------------------------------------------------------------------------------
# npz
# ----------------------------------------------------------------------------------------
def test_npz_round_trip(tmp_path):
    g = Grid((3, 4), 0.25, origin=(-1.0, 2.0), border="wall")
    occ = (PICTURE == 0)[::-1]
    dist = np.arange(12, dtype=np.float64).reshape(3, 4)
    label = np.arange(12, dtype=np.int32).reshape(3, 4)
    f = write_npz(tmp_path / "fields.dat", {"occupied": occ, "distance": dist, "label": label}, g)
    assert f == tmp_path / "fields.dat" and f.exists()  # no ".npz" appended
    raw = np.load(f)
    assert sorted(raw.files) == ["border", "distance", "label", "occupied", "origin", "resolution"]
    assert float(raw["resolution"]) == 0.25 and raw["origin"].tolist() == [-1.0, 2.0] and str(raw["border"]) == "wall"
    arrays, grid = read_npz_arrays(f)
    assert grid == g
    np.testing.assert_array_equal(arrays["distance"], dist)
    assert arrays["label"].dtype == np.int32
    m = read_npz(f)
    np.testing.assert_array_equal(m.occupied, occ)
    assert m.grid == g and m.meta["format"] == "npz"
    f2 = write_npz(tmp_path / "m.npz", {"occupied": occ.astype(np.uint8)}, g)
    assert isinstance(read(f2), GridMap)
    np.testing.assert_array_equal(read(f2).occupied, occ)


# ----------------------------------------------------------------------------------------
# writers
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".png", ".pgm", ".bmp"])
def test_write_bitmap_pixels(tmp_path, suffix):
    occ = np.array([[False, False, True], [True, False, False]])  # row 0 = bottom
    m = GridMap(Grid((2, 3), 0.5, origin=(1.0, 1.0)), occ)
    f = write_bitmap(tmp_path / f"m{suffix}", m)
    img = pil_array(f)  # independent decoder
    assert img.tolist() == [[0, 254, 254], [254, 254, 0]]  # top row first: occupied black, free 254
    back = read_bitmap(f, resolution=0.5, origin=(1.0, 1.0))
    np.testing.assert_array_equal(back.occupied, occ)


def test_write_ros_map_files(tmp_path):
    m = GridMap(Grid((2, 3), 0.05, origin=(-1.5, 2.25)), np.array([[1, 0, 0], [0, 0, 1]], dtype=bool))
    yml = write_ros_map(tmp_path / "out.yaml", m)
    doc = yaml.safe_load(yml.read_text())
    assert doc == {"image": "out.pgm", "mode": "trinary", "resolution": 0.05, "origin": [-1.5, 2.25, 0.0],
                   "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}
    assert (tmp_path / "out.pgm").read_bytes()[:2] == b"P5"
    write_ros_map(tmp_path / "other.yaml", m, image_name="pic.png")
    assert yaml.safe_load((tmp_path / "other.yaml").read_text())["image"] == "pic.png"
    for sem in ("nav2", "ros1"):
        np.testing.assert_array_equal(read_ros_map(tmp_path / "other.yaml", semantics=sem).occupied, m.occupied)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    occ=st.integers(1, 7).flatmap(
        lambda r: st.integers(1, 7).flatmap(
            lambda c: st.lists(st.booleans(), min_size=r * c, max_size=r * c).map(
                lambda v: np.array(v, dtype=bool).reshape(r, c)))),
    res=st.floats(1e-3, 100.0, allow_nan=False, allow_infinity=False),
    ox=st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False),
    oy=st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False),
    fmt=st.sampled_from([".pgm", ".png"]),
)
def test_ros_round_trip_property(tmp_path, occ, res, ox, oy, fmt):
    m = GridMap(Grid(occ.shape, res, origin=(ox, oy)), occ)
    yml = write_ros_map(tmp_path / "rt.yaml", m, image_name="rt" + fmt)
    back = read_ros_map(yml, border="open")
    assert back.grid == m.grid
    np.testing.assert_array_equal(back.occupied, occ)
    bm = read_bitmap(tmp_path / ("rt" + fmt), resolution=res, origin=(ox, oy))
    np.testing.assert_array_equal(bm.occupied, occ)


# ----------------------------------------------------------------------------------------
# dispatch
# ----------------------------------------------------------------------------------------
def test_read_dispatches_every_format(tmp_path):
    assert isinstance(read(bundled_map("seed000.yaml")), World)
    ros = read(bundled_map("turtlebot3_world/map.yaml"), unknown="free")
    assert ros.meta["format"] == "ros" and ros.grid.border == "open"
    assert read(bundled_map("turtlebot3_world/map.yaml"), unknown=None).grid.border == "wall"  # None = default
    assert read(bundled_map("arena/arena.map")).meta["format"] == "movingai"
    assert read(bundled_map("nav2_depot/depot.pgm"), resolution=0.05).grid.resolution == 0.05
    Image.fromarray(PICTURE).save(tmp_path / "p.PNG")
    assert read(tmp_path / "p.PNG").shape == (3, 4)
    (tmp_path / "w.yml").write_text("bounds: [0, 0, 4, 3]\nborder: wall\n")
    assert isinstance(read(tmp_path / "w.yml"), World)
