"""Bad input to the map readers: every problem is a GridfieldError whose message names the file
and what is wrong; nothing escapes from Pillow, numpy or PyYAML."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from gridfield.core.errors import GridfieldError, MapFormatError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.io import (
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

READERS = [read, read_bitmap, read_movingai_map, read_scen, read_ros_map, ros_occupancy_values, read_npz]


def png(path: Path, img: np.ndarray | None = None) -> Path:
    Image.fromarray(np.zeros((2, 3), np.uint8) if img is None else img).save(path)
    return path


def ros_yaml(tmp_path: Path, name: str = "m.yaml", *, text: str | None = None, **doc) -> Path:
    f = tmp_path / name
    if text is not None:
        f.write_text(text)
        return f
    if not (tmp_path / "img.png").exists():
        png(tmp_path / "img.png")
    base = {"image": "img.png", "resolution": 0.05, "origin": [0.0, 0.0, 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196}
    base.update(doc)
    base = {k: v for k, v in base.items() if v is not None}
    f.write_text(yaml.safe_dump(base, default_flow_style=None))
    return f


# ----------------------------------------------------------------------------------------
# files that are not there or not files
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("reader", READERS, ids=lambda r: r.__name__)
def test_missing_file(tmp_path, reader):
    f = tmp_path / "nope.map"
    with pytest.raises(MapFormatError, match=r"nope\.map: no such file"):
        reader(f)


@pytest.mark.parametrize("reader", READERS, ids=lambda r: r.__name__)
def test_directory(tmp_path, reader):
    d = tmp_path / "maps.png"
    d.mkdir()
    with pytest.raises(MapFormatError, match=r"maps\.png: is a directory"):
        reader(d)


def test_unreadable_file(tmp_path, monkeypatch):
    # chmod 0 does not stop root (CI runs as root), so make the read itself fail as it would for a user
    f = png(tmp_path / "locked.png")
    real = type(f).read_bytes

    def denied(self):
        if self.name == "locked.png":
            raise PermissionError(13, "Permission denied", str(self))
        return real(self)

    monkeypatch.setattr(type(f), "read_bytes", denied)
    with pytest.raises(MapFormatError, match=r"locked\.png: cannot read: Permission denied"):
        read_bitmap(f)


def test_unknown_extension(tmp_path):
    f = tmp_path / "map.txt"
    f.write_text("....")
    with pytest.raises(MapFormatError, match=r"map\.txt: unknown map format '\.txt'; expected .*\.yaml.*\.map"):
        read(f)


# ----------------------------------------------------------------------------------------
# images
# ----------------------------------------------------------------------------------------
def test_garbage_image(tmp_path):
    f = tmp_path / "junk.png"
    f.write_bytes(b"this is not an image at all\n" * 5)
    with pytest.raises(MapFormatError, match=r"junk\.png: not a readable image \(expected a PNG, PGM or BMP"):
        read(f)


def test_empty_image(tmp_path):
    f = tmp_path / "empty.bmp"
    f.write_bytes(b"")
    with pytest.raises(MapFormatError, match=r"empty\.bmp: the file is empty"):
        read_bitmap(f)


def test_truncated_png(tmp_path):
    good = png(tmp_path / "good.png", np.arange(64 * 64, dtype=np.uint8).reshape(64, 64)).read_bytes()
    f = tmp_path / "cut.png"
    f.write_bytes(good[: len(good) // 2])
    with pytest.raises(MapFormatError, match=r"cut\.png: cannot decode image"):
        read_bitmap(f)


def test_text_map_read_as_bitmap(tmp_path):
    f = tmp_path / "arena.map"
    f.write_bytes(bundled_map("arena/arena.map").read_bytes())
    with pytest.raises(MapFormatError, match=r"arena\.map: not a readable image"):
        read_bitmap(f)


def test_image_read_as_movingai_map(tmp_path):
    f = tmp_path / "pic.map"
    f.write_bytes(png(tmp_path / "p.png").read_bytes())
    with pytest.raises(MapFormatError, match=r"pic\.map: line 1: not a text Moving AI map file"):
        read(f)


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"P5\n4 2\n255\n" + bytes(5), r"truncated PGM: 4 x 2 pixels need 8 bytes of pixel data, found 5"),
        (b"P5\n4 2\n65535\n" + bytes(10), r"truncated PGM: 4 x 2 pixels need 16 bytes of pixel data, found 10"),
        (b"P5\n4 # width\n", r"truncated PGM header: the file ends before the height"),
        (b"P5\n4 two\n255\n", r"bad PGM header: expected the height \(a number\), found 'two'"),
        (b"P5\n0 2\n255\n", r"PGM image has zero size \(0 x 2\)"),
        (b"P5\n2 2\n0\n" + bytes(4), r"PGM maxval must be in 1\.\.65535, got 0"),
        (b"P2\n2 2\n255\n1 2 3\n", r"truncated PGM: 2 x 2 pixels need 4 values, found 3"),
        (b"P2\n2 2\n255\n1 2 x 4\n", r"bad PGM pixel value 'x'; expected a number"),
        (b"P2\n2 2\n15\n1 2 3 16\n", r"PGM pixel value 16 exceeds maxval 15"),
        (b"P2\n2 2\n255\n1 2 -3 4\n", r"bad PGM pixel value '-3'"),
    ],
)
def test_bad_pgm(tmp_path, data, message):
    f = tmp_path / "bad.pgm"
    f.write_bytes(data)
    with pytest.raises(MapFormatError, match=r"bad\.pgm: " + message):
        read_bitmap(f)


def test_bitmap_parameters(tmp_path):
    f = png(tmp_path / "p.png")
    with pytest.raises(ParameterError, match=r"threshold must be a number in \[0, 1\], got 1\.5"):
        read_bitmap(f, threshold=1.5)
    with pytest.raises(ParameterError, match=r"threshold must be a number in \[0, 1\], got nan"):
        read_bitmap(f, threshold=float("nan"))
    with pytest.raises(ParameterError, match=r"negate must be 0 or 1 \(or false/true\), got 2"):
        read_bitmap(f, negate=2)
    with pytest.raises(ParameterError, match=r"unknown must be one of 'occupied', 'free', got 'maybe'"):
        read_bitmap(f, unknown="maybe")
    with pytest.raises(ParameterError, match=r"border must be one of 'open', 'wall', got 'none'"):
        read_bitmap(f, border="none")
    with pytest.raises(ParameterError, match=r"resolution must be a positive finite number, got -1"):
        read_bitmap(f, resolution=-1)


# ----------------------------------------------------------------------------------------
# ROS map YAML
# ----------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("doc", "message"),
    [
        ({"resolution": None}, r"missing key 'resolution'; a ROS map YAML needs image, resolution and origin"),
        ({"image": None}, r"missing key 'image'"),
        ({"image": None, "origin": None}, r"missing keys 'image', 'origin'"),
        ({"image": "nope.pgm"}, r"the image file 'nope\.pgm' does not exist \(looked for .*nope\.pgm\)"),
        ({"image": ""}, r"'image' must be the image file name, got ''"),
        ({"image": 5}, r"'image' must be the image file name, got 5"),
        ({"resolution": 0}, r"'resolution' must be a positive finite number, got 0"),
        ({"resolution": -0.05}, r"'resolution' must be a positive finite number, got -0\.05"),
        ({"resolution": float("nan")}, r"'resolution' must be a positive finite number, got nan"),
        ({"resolution": "fine"}, r"'resolution' must be a number, got 'fine'"),
        ({"resolution": True}, r"'resolution' must be a number, got True"),
        ({"negate": 2}, r"'negate' must be 0 or 1, got 2"),
        ({"negate": "yes please"}, r"'negate' must be 0 or 1, got 'yes please'"),
        ({"occupied_thresh": 1.5}, r"'occupied_thresh' must be in \[0, 1\], got 1\.5"),
        ({"free_thresh": -0.1}, r"'free_thresh' must be in \[0, 1\], got -0\.1"),
        ({"free_thresh": 0.7, "occupied_thresh": 0.2}, r"'free_thresh' \(0\.7\) must be smaller than 'occupied_thresh' \(0\.2\)"),
        ({"free_thresh": 0.5, "occupied_thresh": 0.5}, r"'free_thresh' \(0\.5\) must be smaller"),
        ({"mode": "fancy"}, r"'mode' must be one of trinary, scale, raw, got 'fancy'"),
        ({"origin": [0, 0]}, r"'origin' must be \[x, y, yaw\], got \[0, 0\]"),
        ({"origin": [0, "a", 0]}, r"'origin' must be a number, got 'a'"),
        ({"origin": [0, float("inf"), 0]}, r"'origin' must hold finite numbers"),
    ],
)
def test_bad_ros_yaml(tmp_path, doc, message):
    f = ros_yaml(tmp_path, **doc)
    with pytest.raises(MapFormatError, match=r"m\.yaml: " + message):
        read_ros_map(f)
    with pytest.raises(MapFormatError, match=r"m\.yaml: "):
        ros_occupancy_values(f)


def test_ros_yaml_image_is_directory(tmp_path):
    (tmp_path / "imgdir").mkdir()
    f = ros_yaml(tmp_path, image="imgdir")
    with pytest.raises(MapFormatError, match=r"m\.yaml: 'image' names a directory"):
        read(f)


def test_ros_image_is_garbage(tmp_path):
    (tmp_path / "bad.pgm").write_bytes(b"P5\n10 10\n255\n" + bytes(20))
    f = ros_yaml(tmp_path, image="bad.pgm")
    with pytest.raises(MapFormatError, match=r"bad\.pgm: truncated PGM"):
        read(f)


def test_ros_yaml_not_a_mapping(tmp_path):
    f = ros_yaml(tmp_path, text="- image\n- resolution\n")
    with pytest.raises(MapFormatError, match=r"m\.yaml: a ROS map YAML must be a mapping"):
        read_ros_map(f)


def test_non_utf8_yaml(tmp_path):
    f = tmp_path / "m.yaml"
    f.write_bytes(b"image: m\xe9.pgm\nresolution: 0.05\n")
    with pytest.raises(MapFormatError, match=r"m\.yaml: not a text \(UTF-8\) YAML file"):
        read(f)
    with pytest.raises(MapFormatError, match=r"m\.yaml: not a text \(UTF-8\) YAML file"):
        read_ros_map(f)


def test_yaml_syntax_error(tmp_path):
    f = ros_yaml(tmp_path, text="image: m.pgm\nresolution: [0.05\n")
    with pytest.raises(MapFormatError, match=r"m\.yaml: line \d+, column \d+: invalid YAML"):
        read(f)


def test_ros_yaw_rejected(tmp_path):
    f = ros_yaml(tmp_path, origin=[1.0, 2.0, 0.5])
    with pytest.raises(MapFormatError, match=r"m\.yaml: origin yaw 0\.5 rad is not supported.*set the yaw to 0"):
        read_ros_map(f)
    assert ros_occupancy_values(f).shape == (2, 3)  # the values do not depend on the yaw


def test_ros_option_errors(tmp_path):
    f = ros_yaml(tmp_path)
    with pytest.raises(ParameterError, match=r"semantics must be one of 'nav2', 'ros1', got 'ros3'"):
        read_ros_map(f, semantics="ros3")
    with pytest.raises(ParameterError, match=r"unknown must be one of 'occupied', 'free', got 'lethal'"):
        read_ros_map(f, unknown="lethal")
    with pytest.raises(ParameterError, match=r"m\.yaml: option resolution does not apply to a ROS map YAML; "
                                             r"it takes unknown, semantics, border"):
        read(f, resolution=0.1)


def test_read_option_errors():
    with pytest.raises(ParameterError, match=r"arena\.map: options negate, unknown do not apply to a Moving AI map; "
                                             r"it takes border"):
        read(bundled_map("arena/arena.map"), unknown="free", negate=True)
    with pytest.raises(ParameterError, match=r"seed000\.yaml: option resolution does not apply to a world file"):
        read(bundled_map("seed000.yaml"), resolution=0.5)


# ----------------------------------------------------------------------------------------
# Moving AI .map and .scen
# ----------------------------------------------------------------------------------------
def movingai(tmp_path: Path, text: str, name: str = "m.map") -> Path:
    f = tmp_path / name
    f.write_text(text)
    return f


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("type octile\nheight 3\nwidth 4\nmap\n....\n....\n", r"truncated map: the header says height 3, but the file "
                                                               r"ends at line 6 after 2 map rows"),
        ("type octile\nheight 3\nwidth 4\nmap\n", r"truncated map: .* after 0 map rows"),
        ("type octile\nheight 2\nwidth 4\nmap\n....\n...\n", r"line 6: map row has 3 characters, but the header "
                                                             r"says width 4"),
        ("type octile\nheight 2\nwidth 4\nmap\n.....\n....\n", r"line 5: map row has 5 characters"),
        ("type octile\nheight 2\nwidth 4\nmap\n....\n....\n....\n", r"line 7: more map rows than the header's "
                                                                    r"height 2"),
        ("type octile\nheight 2\nwidth 4\nmap\n....\n.x..\n", r"line 6, column 2: invalid map character 'x'; expected "
                                                              r"\. G S \(passable\) or @ O T W \(blocked\)"),
        ("type octile\nheight 2\nwidth 4\nmap\n....\n..\u00e9.\n", r"line 6, column 3: invalid map character 'é'"),
        ("type octile\nheight 2\nwidth 4\nmap\n....\n.. .\n", r"line 6, column 3: invalid map character ' '"),
        ("type octile\nheight 2\nwidth 4\n....\n", r"line 4: expected a header line"),
        ("type octile\nheight 2\nwidth 4\n", r"no 'map' line"),
        ("type octile\nheight 2\nmap\n....\n....\n", r"header has no 'width' line before 'map' \(line 3\)"),
        ("type octile\nheight two\nwidth 4\nmap\n....\n....\n", r"'height' must be a positive integer, got 'two'"),
        ("type octile\nheight 0\nwidth 4\nmap\n", r"'height' must be a positive integer, got '0'"),
        ("", r"no 'map' line"),
    ],
)
def test_bad_movingai_map(tmp_path, text, message):
    f = movingai(tmp_path, text)
    with pytest.raises(MapFormatError, match=r"m\.map: " + message):
        read_movingai_map(f)


def test_crlf_width_mismatch_reports_line(tmp_path):
    f = tmp_path / "m.map"
    f.write_bytes(b"type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n...\r\n....\r\n")
    with pytest.raises(MapFormatError, match=r"m\.map: line 6: map row has 4 characters, but the header says width 3"):
        read(f)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\n", r"line 2: expected 9 fields"),
        ("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\t0\n0\tm.map\t4\t3\ta\t0\t1\t0\t0\n", r"line 3: start_x must be a "
                                                                                    r"number \(in range\), got 'a'"),
        ("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\tlong\n", r"line 2: optimal length must be a number \(in range\), got 'long'"),
        ("version 1\n0\tm.map\t4\t3\t4\t0\t1\t0\t3\n", r"line 2: start \(4, 0\) or goal \(1, 0\) lies outside the "
                                                       r"4 x 3 map"),
        ("version 1\n0\tm.map\t4\t3\t1\t0\t1\t-1\t3\n", r"line 2: .* lies outside"),
        ("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\t-3\n", r"line 2: optimal length must be a finite number >= 0"),
        ("version 1\n0\tm.map\t0\t3\t1\t0\t1\t0\t3\n", r"line 2: map width and height must be positive"),
        ("version 1\n\n", r"no scenarios in the file"),
    ],
)
def test_bad_scen(tmp_path, text, message):
    f = tmp_path / "m.scen"
    f.write_text(text)
    with pytest.raises(MapFormatError, match=r"m\.scen: " + message):
        read_scen(f)


def test_scen_map_height_mismatch(tmp_path):
    f = tmp_path / "m.scen"
    f.write_text("version 1\n0\tm.map\t4\t3\t1\t0\t1\t0\t0\n")
    with pytest.raises(MapFormatError, match=r"m\.scen: line 2: scenario map height 3 differs from map_height=5"):
        read_scen(f, map_height=5)
    with pytest.raises(ParameterError, match=r"map_height must be a positive integer, got 0"):
        read_scen(f, map_height=0)


def test_binary_scen(tmp_path):
    f = tmp_path / "m.scen"
    f.write_bytes(b"version 1\n\xff\xfe\n")
    with pytest.raises(MapFormatError, match=r"m\.scen: line 2: not a text Moving AI scenario file"):
        read_scen(f)


# ----------------------------------------------------------------------------------------
# npz
# ----------------------------------------------------------------------------------------
def test_bad_npz(tmp_path):
    g = Grid((2, 2), 1.0)
    f = tmp_path / "junk.npz"
    f.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(MapFormatError, match=r"junk\.npz: not a gridfield \.npz file"):
        read(f)
    f2 = tmp_path / "nogrid.npz"
    np.savez(f2, occupied=np.zeros((2, 2), bool))
    with pytest.raises(MapFormatError, match=r"nogrid\.npz: no 'resolution' array"):
        read_npz(f2)
    f3 = write_npz(tmp_path / "noocc.npz", {"distance": np.zeros((2, 2))}, g)
    with pytest.raises(MapFormatError, match=r"noocc\.npz: no 'occupied' array \(it holds distance\)"):
        read_npz(f3)
    f4 = tmp_path / "pickled.npz"
    np.savez(f4, occupied=np.array([None, 1], dtype=object), resolution=1.0, origin=[0.0, 0.0])
    with pytest.raises(MapFormatError, match=r"pickled\.npz: not a gridfield \.npz file"):
        read_npz_arrays(f4)
    f5 = tmp_path / "badres.npz"
    np.savez(f5, occupied=np.zeros((2, 2), bool), resolution=-1.0, origin=[0.0, 0.0])
    with pytest.raises(MapFormatError, match=r"badres\.npz: resolution must be a positive finite number"):
        read_npz(f5)
    f6 = tmp_path / "values.npz"
    np.savez(f6, occupied=np.full((2, 2), 7), resolution=1.0, origin=[0.0, 0.0])
    with pytest.raises(MapFormatError, match=r"values\.npz: 'occupied' must hold booleans \(or 0/1\)"):
        read_npz(f6)
    f8 = tmp_path / "single.npz"
    with open(f8, "wb") as fh:
        np.save(fh, np.zeros((2, 2)))
    with pytest.raises(MapFormatError, match=r"single\.npz: holds a single \.npy array"):
        read(f8)
    f7 = tmp_path / "shapes.npz"
    np.savez(f7, occupied=np.zeros((2, 2), bool), distance=np.zeros((3, 2)), resolution=1.0, origin=[0.0, 0.0])
    with pytest.raises(MapFormatError, match=r"shapes\.npz: arrays have different shapes"):
        read_npz(f7)


def test_write_errors(tmp_path):
    m = GridMap(Grid((2, 2), 1.0), np.zeros((2, 2), bool))
    with pytest.raises(ParameterError, match=r"m\.jpg: cannot write a bitmap with suffix '\.jpg'; use \.png, \.pgm or \.bmp"):
        write_bitmap(tmp_path / "m.jpg", m)
    with pytest.raises(GridfieldError, match=r"m\.png: cannot write"):
        write_bitmap(tmp_path / "no" / "such" / "dir" / "m.png", m)
    with pytest.raises(GridfieldError, match=r"m\.pgm: cannot write"):
        write_ros_map(tmp_path / "missing" / "m.yaml", m)
    with pytest.raises(ParameterError, match=r"array 'distance' has shape \(3, 2\), but the grid has shape \(2, 2\)"):
        write_npz(tmp_path / "a.npz", {"distance": np.zeros((3, 2))}, m.grid)
    with pytest.raises(ParameterError, match=r"array name 'origin' is not allowed"):
        write_npz(tmp_path / "a.npz", {"origin": np.zeros((2, 2))}, m.grid)
    with pytest.raises(ParameterError, match=r"image_name must be a file name relative"):
        write_ros_map(tmp_path / "m.yaml", m, image_name="/abs/m.pgm")


# ----------------------------------------------------------------------------------------
# fuzz: random bytes never escape as a library error
# ----------------------------------------------------------------------------------------
PREFIXES = [b"", b"P5\n", b"P2\n", b"P5 3 2 255\n", b"P2 3 2 9\n", b"type octile\nheight 2\nwidth 3\nmap\n",
            b"version 1\n", b"\x89PNG\r\n\x1a\n", b"BM", b"PK\x03\x04"]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(prefix=st.sampled_from(PREFIXES), body=st.binary(max_size=64),
       suffix=st.sampled_from([".png", ".pgm", ".bmp", ".map", ".scen", ".npz"]))
def test_fuzz_readers_raise_only_gridfield_errors(tmp_path, prefix, body, suffix):
    f = tmp_path / f"fuzz{suffix}"
    f.write_bytes(prefix + body)
    reader = read_scen if suffix == ".scen" else read
    try:
        reader(f)
    except GridfieldError as e:
        assert "fuzz" in str(e)  # names the file
