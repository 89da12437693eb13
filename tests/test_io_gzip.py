"""Maps read gzip-compressed: ``.map.gz``, ``.scen.gz`` and ``.pgm.gz`` (also as a ROS YAML's image) read
as the same files uncompressed; a file that is not gzip, is cut short or inflates beyond the size guard
is refused with a one-line error naming it, before memory fills."""

from __future__ import annotations

import gzip
import time
from pathlib import Path

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.core.errors import MapFormatError, SizeLimitError
from gridfield.core.limits import override
from gridfield.io import bundled_map, read, read_ros_map, read_scen


def _gz(src: Path, dst: Path) -> Path:
    dst.write_bytes(gzip.compress(src.read_bytes()))
    return dst


def test_a_compressed_moving_ai_map_and_scenario_file_read_as_the_originals(tmp_path):
    m = _gz(bundled_map("arena/arena.map"), tmp_path / "arena.map.gz")
    s = _gz(bundled_map("arena/arena.map.scen"), tmp_path / "arena.map.scen.gz")
    np.testing.assert_array_equal(read(m).occupied, read(bundled_map("arena/arena.map")).occupied)
    a, b = read_scen(s), read_scen(bundled_map("arena/arena.map.scen"))
    np.testing.assert_array_equal(a.optimal, b.optimal)
    np.testing.assert_array_equal(a.start_xy, b.start_xy)
    assert read(tmp_path).meta["format"] == "movingai"  # a folder holding one .map.gz reads as that map


def test_a_ros_yaml_naming_a_compressed_image_reads_as_the_original(tmp_path):
    src = bundled_map("turtlebot3_world/map.yaml")
    _gz(src.parent / "map.pgm", tmp_path / "map.pgm.gz")
    (tmp_path / "map.yaml").write_text(src.read_text().replace("image: map.pgm", "image: map.pgm.gz"))
    assert "map.pgm.gz" in (tmp_path / "map.yaml").read_text()
    np.testing.assert_array_equal(read_ros_map(tmp_path / "map.yaml").occupied, read_ros_map(src).occupied)


def test_plan_runs_on_compressed_scenarios(tmp_path, capsys):
    m = _gz(bundled_map("arena/arena.map"), tmp_path / "arena.map.gz")
    s = _gz(bundled_map("arena/arena.map.scen"), tmp_path / "arena.map.scen.gz")
    assert main(["plan", str(m), "--scenario", str(s), "--index", "20", "--planner", "wavefront-octile"]) == 0
    assert "reached" in capsys.readouterr().out


@pytest.mark.parametrize(("data", "message"), [
    (b"type octile\nheight 1\n", "not a gzip file"),
    (gzip.compress(b"type octile\nheight 2\nwidth 2\nmap\n..\n..\n", mtime=0)[:-12], "truncated gzip file"),
], ids=["not-gzip", "truncated"])  # fixed ids and time stamp: every xdist worker collects the same tests
def test_a_broken_gzip_file_is_named_in_one_line(tmp_path, capsys, data, message):
    f = tmp_path / "m.map.gz"
    f.write_bytes(data)
    with pytest.raises(MapFormatError, match=message):
        read(f)
    assert main(["info", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(f) in err and message in err


def test_a_gzip_bomb_is_refused_by_the_size_guard_before_it_inflates(tmp_path):
    """256 MiB of one character compress to about 250 kB; with a guard of 1000 cells at most 4000 + 1 MiB bytes are
    decompressed before the refusal."""
    f = tmp_path / "bomb.map.gz"
    with gzip.open(f, "wb", compresslevel=1) as out:
        block = b"." * (1 << 20)
        for _ in range(256):
            out.write(block)
    t0 = time.perf_counter()
    with override(1000), pytest.raises(SizeLimitError, match="decompresses to more than"):
        read(f)
    assert time.perf_counter() - t0 < 5  # generous: nothing near 256 MiB was inflated


def test_only_the_formats_decoded_here_are_read_compressed(tmp_path):
    f = tmp_path / "m.npz.gz"
    f.write_bytes(gzip.compress(b"x"))
    with pytest.raises(MapFormatError, match=r"gzip-compressed maps are read for \.map\.gz"):
        read(f)
