"""Issue 42, part 2: one occupancy rule for images, said out loud.

The same picture (black walls on white) saved as PNG, PGM, BMP and TIFF reads the same occupied cells
(grey levels, dark = occupied, with read_bitmap's threshold and negate); TIFF min-is-white and 1-bit images
are honoured; label rasters need the explicit ``occupancy="nonzero"``; floats are refused under the grey
rule; the rule applied is in ``meta["occupancy_rule"]`` and ``gridfield info`` says it. The expected cells
come from the pixel values and the rule's formula, not from gridfield's readers.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from gridfield.cli import main
from gridfield.core.errors import MapFormatError, ParameterError
from gridfield.io import bundled_map, read, read_bitmap, read_npy, read_tiff

tifffile = pytest.importorskip("tifffile")


def picture(depth: int = 8) -> np.ndarray:
    """A 40 x 64 grey picture, top row first: white, two black walls, and every 8-bit grey level
    (rows 30..33: levels 0..255, 64 per row), so the threshold's neighbours 127 and 128 are in it."""
    img = np.full((40, 64), 255, np.uint16)
    img[4:8, 2:60] = 0
    img[12:26, 40:44] = 0
    img[30:34] = np.arange(256).reshape(4, 64)
    if depth == 16:
        img = img * 257  # the same grey levels on 0..65535; 127 -> 32639, 128 -> 32896
        img[35, :2] = (32767, 32768)  # and the 16-bit threshold's neighbours
    return img.astype(np.uint8 if depth == 8 else np.uint16)


def expected(img: np.ndarray, threshold: float = 0.5, negate: bool = False) -> np.ndarray:
    """map_server's rule by hand: occupancy (W - v) / W (v / W with negate) above threshold; flipped."""
    white = float(np.iinfo(img.dtype).max)
    v = img.astype(np.float64)
    occ = v / white if negate else (white - v) / white
    return np.flipud(occ > threshold)


def write_pgm(path, img: np.ndarray) -> None:
    maxval = int(np.iinfo(img.dtype).max)
    data = img.astype(">u2").tobytes() if maxval > 255 else img.tobytes()
    path.write_bytes(b"P5\n%d %d\n%d\n" % (img.shape[1], img.shape[0], maxval) + data)


def save_all(tmp_path, img: np.ndarray) -> dict[str, object]:
    files = {"png": tmp_path / "m.png", "pgm": tmp_path / "m.pgm", "tif": tmp_path / "m.tif"}
    Image.fromarray(img).save(files["png"])
    write_pgm(files["pgm"], img)
    tifffile.imwrite(files["tif"], img, tile=(16, 16))
    if img.dtype == np.uint8:
        files["bmp"] = tmp_path / "m.bmp"
        Image.fromarray(img).save(files["bmp"])
    return files


def occupied(m) -> np.ndarray:
    return np.asarray(m.occupied)


# -- the same image in every format -------------------------------------------------------------
@pytest.mark.parametrize("depth", [8, 16])
@pytest.mark.parametrize(("threshold", "negate"), [(0.5, False), (0.3, False), (0.65, True)])
def test_same_image_same_cells_in_every_format(tmp_path, depth, threshold, negate):
    img = picture(depth)
    want = expected(img, threshold, negate)
    for kind, f in save_all(tmp_path, img).items():
        m = read(f, threshold=threshold, negate=negate)
        np.testing.assert_array_equal(occupied(m), want, err_msg=kind)
        assert m.meta["occupancy_rule"].startswith("light = occupied" if negate else "dark = occupied"), kind


def test_tiff_is_read_like_the_png_by_default(tmp_path):
    """The issue's report: the PNG had 1 000 occupied cells, the TIFF of the same picture 5 144."""
    img = picture()
    files = save_all(tmp_path, img)
    png, tif = read(files["png"]), read(files["tif"])
    assert int(np.count_nonzero(occupied(tif))) == int(np.count_nonzero(occupied(png)))
    np.testing.assert_array_equal(occupied(tif), occupied(png))
    assert occupied(tif)[-6, 10]  # the wall in the image's rows 4..7 is near the top of the map
    assert not occupied(tif)[0, 0]  # white is free
    assert tif.meta["occupancy_rule"] == "dark = occupied (grey level below 50 % of white; values 0..255, 0 = black)"
    assert png.meta["occupancy_rule"] == "dark = occupied (grey level below 50 % of white)"


def test_uint16_tiff_rule_names_its_range(tmp_path):
    img = picture(16)
    tifffile.imwrite(tmp_path / "m.tif", img)
    m = read_tiff(tmp_path / "m.tif")
    assert "values 0..65535" in m.meta["occupancy_rule"]
    row = np.flipud(occupied(m))[35]
    assert row[:2].tolist() == [True, False]  # 32767 occupied (0.500008 > 0.5), 32768 free


def test_tiff_stays_lazy_and_applies_the_rule_per_tile(tmp_path):
    img = picture()
    tifffile.imwrite(tmp_path / "m.tif", img, tile=(16, 16))
    m = read_tiff(tmp_path / "m.tif")
    assert type(m).__name__ == "LazyGridMap" and m.occupied.chunks == (16, 16)
    want = expected(img)
    np.testing.assert_array_equal(m.occupied.window(3, 19, 16, 32), want[3:19, 16:32])
    assert m.occupied.count_nonzero() == int(want.sum())
    assert m.to_gridmap().meta["occupancy_rule"] == m.meta["occupancy_rule"]  # kept in memory too


# -- min-is-white, 1-bit and boolean rasters -----------------------------------------------------
def test_miniswhite_tiff(tmp_path):
    img = picture()
    tifffile.imwrite(tmp_path / "w.tif", 255 - img, photometric="miniswhite")  # 0 = white
    m = read_tiff(tmp_path / "w.tif")
    np.testing.assert_array_equal(occupied(m), expected(img))
    assert "min-is-white: 0 = white" in m.meta["occupancy_rule"]
    negated = read_tiff(tmp_path / "w.tif", negate=True)
    np.testing.assert_array_equal(occupied(negated), expected(img, negate=True))


def test_boolean_tiff_reads_true_as_obstacle(tmp_path):
    occ = np.zeros((20, 30), bool)
    occ[2:5, 3:25] = True
    tifffile.imwrite(tmp_path / "b.tif", occ)  # tifffile: 1 bit per sample, min-is-white (1 = black)
    m = read_tiff(tmp_path / "b.tif")
    np.testing.assert_array_equal(occupied(m), np.flipud(occ))
    assert "1-bit, min-is-white: 1 = black" in m.meta["occupancy_rule"]
    labels = read_tiff(tmp_path / "b.tif", occupancy="nonzero")
    np.testing.assert_array_equal(occupied(labels), np.flipud(occ))
    assert labels.meta["occupancy_rule"] == "True = obstacle (boolean raster)"


def test_one_bit_min_is_black_tiff_is_an_image_too(tmp_path):
    """Pillow saves a 1-bit picture min-is-black (1 = white): black walls on white stay the walls."""
    img = np.where(picture() < 128, 0, 255).astype(np.uint8)
    Image.fromarray(img).convert("1").save(tmp_path / "p.tif")
    with tifffile.TiffFile(tmp_path / "p.tif") as tf:
        assert tf.pages[0].dtype == np.bool_ and int(tf.pages[0].photometric) == 1
    m = read_tiff(tmp_path / "p.tif")
    np.testing.assert_array_equal(occupied(m), expected(img))
    assert "1-bit, 0 = black" in m.meta["occupancy_rule"]


# -- label rasters: the explicit option ---------------------------------------------------------
def test_label_tiff_with_occupancy_nonzero(tmp_path):
    labels = np.zeros((30, 40), np.uint16)
    labels[3:9, 4:30] = 1
    labels[15:25, 10:12] = 7
    labels[28, 39] = 300
    f = tmp_path / "labels.tif"
    tifffile.imwrite(f, labels)
    m = read(f, occupancy="nonzero")
    np.testing.assert_array_equal(occupied(m), np.flipud(labels != 0))
    assert m.meta["occupancy_rule"] == "non-zero = obstacle"
    grey = read(f)  # as an image, labels 0..300 of 65535 are all nearly black: the default says so
    assert grey.meta["occupancy_rule"].startswith("dark = occupied") and occupied(grey).all()


def test_label_bitmaps_with_occupancy_nonzero(tmp_path):
    labels = np.zeros((6, 8), np.uint8)
    labels[1, 2], labels[4, 5] = 3, 200
    Image.fromarray(labels).save(tmp_path / "l.png")
    m = read_bitmap(tmp_path / "l.png", occupancy="nonzero")
    np.testing.assert_array_equal(m.occupied, np.flipud(labels != 0))
    assert m.meta["occupancy_rule"] == "non-zero = obstacle"
    pal = Image.new("P", (8, 6))  # a palette image: its colour indices are the labels
    pal.putdata(labels.ravel().tolist())
    pal.putpalette([255, 255, 255] * 256)  # every colour white: what is read is the index
    pal.save(tmp_path / "p.png")
    with Image.open(tmp_path / "p.png") as im:
        assert im.mode == "P" and np.array_equal(np.asarray(im), labels)
    m = read_bitmap(tmp_path / "p.png", occupancy="nonzero")
    np.testing.assert_array_equal(m.occupied, np.flipud(labels != 0))
    assert m.meta["occupancy_rule"] == "non-zero = obstacle (palette index)"


def test_grey_options_do_not_apply_to_nonzero(tmp_path):
    Image.fromarray(picture()).save(tmp_path / "m.png")
    with pytest.raises(ParameterError, match=r"m\.png: threshold applies to grey levels \(occupancy='dark'\)"):
        read(tmp_path / "m.png", occupancy="nonzero", threshold=0.3)
    with pytest.raises(ParameterError, match=r"occupancy must be one of 'dark', 'nonzero', got 'black'"):
        read(tmp_path / "m.png", occupancy="black")


# -- floats and signed integers: no grey convention ---------------------------------------------
def test_float_tiff_is_refused_under_dark_and_read_with_nonzero(tmp_path):
    a = np.zeros((10, 12), np.float32)
    a[2, 3] = 0.7
    a[5, 5] = -2.5
    f = tmp_path / "f.tif"
    tifffile.imwrite(f, a)
    with pytest.raises(MapFormatError, match=r"f\.tif: a float32 raster has no grey-level convention.*"
                                             r"occupancy='nonzero' \(--occupancy nonzero\)"):
        read(f)
    m = read(f, occupancy="nonzero")
    np.testing.assert_array_equal(occupied(m), np.flipud(a != 0))


def test_signed_integer_tiff_is_refused_under_dark(tmp_path):
    tifffile.imwrite(tmp_path / "s.tif", np.zeros((4, 4), np.int16))
    with pytest.raises(MapFormatError, match=r"s\.tif: int16 values \(signed integers\) have no grey-level"):
        read(tmp_path / "s.tif")
    assert not occupied(read(tmp_path / "s.tif", occupancy="nonzero")).any()


# -- .npy: arrays, not images -------------------------------------------------------------------
def test_npy_keeps_nonzero_and_takes_dark(tmp_path):
    img = picture()
    f = tmp_path / "a.npy"
    np.save(f, img)
    m = read_npy(f)  # an array in gridfield's row order: non-zero = obstacle, no flip
    np.testing.assert_array_equal(occupied(m), img != 0)
    assert m.meta == {"format": "npy", "occupancy_rule": "non-zero = obstacle"}
    grey = read(f, occupancy="dark", threshold=0.3)
    np.testing.assert_array_equal(occupied(grey), np.flipud(expected(img, 0.3)))  # the grey rule, rows kept
    occ = img == 0
    np.save(f, occ)
    for rule in ("nonzero", "dark"):
        b = read_npy(f, occupancy=rule)
        np.testing.assert_array_equal(occupied(b), occ)
        assert b.meta["occupancy_rule"] == "True = obstacle (boolean raster)"
    with pytest.raises(ParameterError, match=r"a\.npy: a boolean array holds occupancy.*negate do not apply"):
        read_npy(f, occupancy="dark", negate=True)
    np.save(f, img.astype(np.float64))
    assert occupied(read_npy(f)).sum() == int((img != 0).sum())
    with pytest.raises(MapFormatError, match=r"a\.npy: a float64 raster has no grey-level convention"):
        read_npy(f, occupancy="dark")


# -- every reader says its rule -----------------------------------------------------------------
def test_other_formats_record_their_rule():
    ros = read(bundled_map("turtlebot3_world/map.yaml"))
    assert ros.meta["occupancy_rule"].startswith("ROS map_server trinary (nav2): occupancy (255 - v) / 255 >= "
                                                 "occupied_thresh 0.65 occupied, <= free_thresh 0.196 free")
    ros1 = read(bundled_map("turtlebot3_world/map.yaml"), semantics="ros1")
    assert "> occupied_thresh 0.65" in ros1.meta["occupancy_rule"]


# -- the command line ---------------------------------------------------------------------------
def info_json(capsys, *argv) -> dict:
    code = main(["info", *map(str, argv), "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads(out)


def test_cli_choices_are_the_readers_rules():
    from gridfield.cli._common import OCCUPANCY_CHOICES
    from gridfield.io import OCCUPANCY_RULES

    assert OCCUPANCY_CHOICES == OCCUPANCY_RULES


def test_info_says_the_rule(tmp_path, capsys):
    img = picture()
    files = save_all(tmp_path, img)
    png, tif = info_json(capsys, files["png"]), info_json(capsys, files["tif"])
    assert tif["occupied_cells"] == png["occupied_cells"] == int(expected(img).sum())
    assert tif["format"] == "tiff"
    assert tif["occupancy_rule"] == "dark = occupied (grey level below 50 % of white; values 0..255, 0 = black)"
    assert main(["info", str(files["tif"])]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert f"occupancy rule:    {tif['occupancy_rule']}" in lines
    labels = info_json(capsys, files["tif"], "--occupancy", "nonzero")
    assert labels["occupancy_rule"] == "non-zero = obstacle" and labels["occupied_cells"] == int((img != 0).sum())
    neg = info_json(capsys, files["png"], "--negate", "--threshold", "0.3")
    assert neg["occupied_cells"] == int(expected(img, 0.3, True).sum())
    assert neg["occupancy_rule"] == "light = occupied (negate: grey level above 30 % of white)"


@pytest.mark.parametrize("name", ["arena/arena.map", "seed000.yaml", "turtlebot3_world/map.yaml"])
def test_info_says_a_rule_for_every_format(capsys, name):
    doc = info_json(capsys, bundled_map(name))
    assert isinstance(doc["occupancy_rule"], str) and doc["occupancy_rule"]
    if name.endswith(".map"):
        assert doc["occupancy_rule"] == "'.', 'G', 'S' free; the rest blocked"


@pytest.mark.parametrize(("command", "name", "option"), [
    ("info", "arena/arena.map", ["--occupancy", "nonzero"]),
    ("info", "turtlebot3_world/map.yaml", ["--negate"]),
    ("brushfire", "seed000.yaml", ["--occupancy", "dark"]),
    ("plan", "arena/arena.map", ["--threshold", "0.3", "--start", "3.5", "45.5", "--goal", "40.5", "5.5"]),
])
def test_an_option_the_format_does_not_take_is_one_error_line(capsys, command, name, option):
    code = main([command, str(bundled_map(name)), *option])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert "does not apply" in err[0] and ("occupancy" in err[0] or "negate" in err[0] or "threshold" in err[0])


def test_brushfire_reads_the_tiff_like_the_png(tmp_path, capsys):
    files = save_all(tmp_path, picture())
    summaries = []
    for kind in ("png", "tif"):
        assert main(["brushfire", str(files[kind])]) == 0
        summaries.append(capsys.readouterr().out.rsplit(",", 1)[0])  # without the time
    assert summaries[0] == summaries[1]
