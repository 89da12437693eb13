"""The size guard (before any allocation), short error messages, YAML alias bombs, and the error contract's holes."""

from __future__ import annotations

import io
import os
import struct
import subprocess
import sys
import time
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.core.errors import (
    MESSAGE_LIMIT,
    ArgumentTypeError,
    GridfieldError,
    MapFormatError,
    ParameterError,
    SizeLimitError,
)
from gridfield.core.grid import Grid, GridMap
from gridfield.core.limits import check_cells, default_max_cells, max_cells, override
from gridfield.distance.brushfire import brushfire
from gridfield.io import bundled_map, read, read_world
from gridfield.planners import plan

ROOT = Path(__file__).resolve().parent.parent
SEED = str(bundled_map("seed000.yaml"))


@pytest.fixture
def limit(monkeypatch: pytest.MonkeyPatch) -> int:
    monkeypatch.setenv("GRIDFIELD_MAX_CELLS", "1_000_000")
    return 10**6


def _png_header_only(width: int, height: int, colour: int = 6) -> bytes:
    """A PNG whose header claims width x height RGBA pixels, with a tiny (truncated) image stream."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 1000)) + chunk(b"IEND", b"")


def _npz_header_only(path: Path, shape: tuple[int, ...]) -> None:
    """An .npz whose 'occupied' member's header claims ``shape`` (the data itself is missing)."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": "|b1", "fortran_order": False, "shape": shape})
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("occupied.npy", buf.getvalue() + b"\0" * 100)
        z.writestr("resolution.npy", _npy(np.float64(1.0)))
        z.writestr("origin.npy", _npy(np.zeros(2)))


def _npy(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def _refused(call, cells: int) -> str:
    t0 = time.perf_counter()
    with pytest.raises(SizeLimitError) as e:
        call()
    elapsed = time.perf_counter() - t0
    msg = str(e.value)
    assert f"{cells} cells" in msg and "GRIDFIELD_MAX_CELLS" in msg and "--max-cells" in msg
    assert "B of memory" in msg  # bytes named too
    assert elapsed < 30  # generous (shared CI machine); the point is that nothing big was allocated
    return msg


def test_images_are_sized_from_their_header_before_decoding(tmp_path: Path, limit: int, monkeypatch) -> None:
    from PIL import Image

    def no_decode(self, *a, **k):  # pragma: no cover - must not run
        raise AssertionError("the image was decoded")

    monkeypatch.setattr(Image.Image, "load", no_decode)
    png = tmp_path / "huge.png"
    png.write_bytes(_png_header_only(13000, 13000))
    assert png.stat().st_size < 2000
    msg = _refused(lambda: read(png), 13000 * 13000)
    assert "13000 x 13000" in msg and str(png) in msg
    pgm = tmp_path / "huge.pgm"
    pgm.write_bytes(b"P5\n50000 40000\n255\n" + b"\0" * 100)
    _refused(lambda: read(pgm), 50000 * 40000)


def test_npz_arrays_are_sized_from_their_header_before_loading(tmp_path: Path, limit: int) -> None:
    f = tmp_path / "huge.npz"
    _npz_header_only(f, (50000, 50000))
    msg = _refused(lambda: read(f), 50000 * 50000)
    assert "'occupied'" in msg
    single = tmp_path / "single.npz"
    single.write_bytes(_npy(np.zeros((3, 3))))
    with pytest.raises(MapFormatError, match=r"single \.npy array"):
        read(single)


def test_movingai_header_and_worlds_are_sized_before_allocating(tmp_path: Path, limit: int) -> None:
    m = tmp_path / "huge.map"
    m.write_text("type octile\nheight 100000\nwidth 100000\nmap\n....\n")
    _refused(lambda: read(m), 10**10)
    # a world at a fine resolution: (25 / 3e-5) x (20 / 3e-5) cells, counted from bounds and resolution
    w = read_world(SEED)
    from gridfield.geometry.rasterize import as_gridmap

    expected = int(np.ceil(20 / 3e-5)) * int(np.ceil(25 / 3e-5))
    msg = _refused(lambda: as_gridmap(w, 3e-5), expected // 10**6)  # the count printed in full
    assert "resolution 3e-05" in msg


def test_api_arrays_are_sized_too(limit: int) -> None:
    huge = np.broadcast_to(np.False_, (30000, 30000))  # no memory behind it
    _refused(lambda: GridMap(Grid(huge.shape, 1.0), huge), 30000 * 30000)
    assert check_cells((1000, 1000), "grid") == 10**6


def test_the_limit_comes_from_override_env_and_memory(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("GRIDFIELD_MAX_CELLS", raising=False)
    mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    assert default_max_cells() == max(10**6, mem // 4 // 64) == max_cells()
    monkeypatch.setenv("GRIDFIELD_MAX_CELLS", "2e6")
    assert max_cells() == 2 * 10**6
    with override(500):
        assert max_cells() == 500
    monkeypatch.setenv("GRIDFIELD_MAX_CELLS", "lots")
    with pytest.raises(ParameterError, match="GRIDFIELD_MAX_CELLS must be a positive number of cells, got 'lots'"):
        max_cells()


def test_cli_size_errors_are_one_line_and_the_option_raises_the_limit(tmp_path: Path, capsys, monkeypatch) -> None:
    monkeypatch.delenv("GRIDFIELD_MAX_CELLS", raising=False)
    assert main(["info", SEED, "--resolution", "0.00003"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cells would need about" in err
    assert main(["info", SEED, "--resolution", "0.5", "--max-cells", "1000"]) == 2  # 40 x 50 = 2000 cells
    assert "40 x 50 = 2000 cells" in capsys.readouterr().err
    assert main(["info", SEED, "--resolution", "0.5", "--max-cells", "2000"]) == 0
    capsys.readouterr()
    assert main(["compare", SEED, "--resolutions", "1", "0.0005"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "resolution 0.0005" in err
    assert main(["info", SEED, "--max-cells", "many"]) == 2
    assert "--max-cells must be a positive number of cells" in capsys.readouterr().err


def _bomb(levels: int) -> str:
    lines = ["a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    lines += [f"a{k}: &a{k} [{', '.join([f'*a{k - 1}'] * 9)}]" for k in range(1, levels)]
    return "\n".join(lines) + f"\nbounds: *a{levels - 1}\n"


def test_yaml_alias_bombs_are_refused_and_long_values_shortened(tmp_path: Path) -> None:
    big = tmp_path / "bomb.yaml"
    big.write_text(_bomb(9))  # 9**9 values after expansion
    with pytest.raises(MapFormatError, match="aliases expand") as e:
        read(big)
    assert len(str(e.value)) <= MESSAGE_LIMIT
    small = tmp_path / "small_bomb.yaml"
    small.write_text(_bomb(5))  # 6e4 values: under the bound, but the message must stay short
    with pytest.raises(MapFormatError, match="bounds") as e:
        read(small)
    assert len(str(e.value)) <= MESSAGE_LIMIT
    long = tmp_path / "long.yaml"
    long.write_text("bounds: [" + ", ".join(["1"] * 5000) + "]\n")
    with pytest.raises(MapFormatError, match="5000 items") as e:
        read(long)
    assert len(str(e.value)) <= MESSAGE_LIMIT


def test_every_error_message_is_capped() -> None:
    assert len(str(GridfieldError("x" * 10**6))) <= MESSAGE_LIMIT
    e = ParameterError("start " + "y" * 5000 + " end")
    assert str(e).startswith("start ") and str(e).endswith(" end") and "characters cut" in str(e)


def test_plan_json_into_a_closed_pipe_exits_quietly(tmp_path: Path) -> None:
    proc = subprocess.Popen([sys.executable, "-m", "gridfield", "plan", SEED, "--planner", "wavefront",
                             "--resolution", "0.5", "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()  # like `| head -c 100` having read its bytes, before the plan is printed
    with proc.stderr:
        err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert err == ""


@pytest.mark.parametrize("command", ["plan", "compare"])
@pytest.mark.parametrize(("name", "message"), [("F", "needs a figure suffix"), ("x.xyz", "suffix '.xyz' is not a figure format")])
def test_figure_files_need_a_figure_suffix(tmp_path: Path, capsys, command: str, name: str, message: str) -> None:
    out = tmp_path / name
    args = [command, SEED, "--resolution", "0.5", "--plot", str(out)]
    if command == "compare":
        args = [command, SEED, "--resolutions", "1", "--plot", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert list(tmp_path.iterdir()) == []  # nothing written (no F.png either)


def test_ros_yaml_without_image_and_absurd_resolution(tmp_path: Path) -> None:
    (tmp_path / "no_image.yaml").write_text("resolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(MapFormatError, match="missing key 'image'"):
        read(tmp_path / "no_image.yaml")
    from PIL import Image

    Image.fromarray(np.full((4, 5), 255, np.uint8)).save(tmp_path / "m.png")
    (tmp_path / "huge.yaml").write_text("image: m.png\nresolution: 1e308\norigin: [0, 0, 0]\n")
    with pytest.raises(MapFormatError, match=r"huge\.yaml: resolution must be between 1e-75 and 1e\+75"):
        read(tmp_path / "huge.yaml")  # the one resolution rule (grid.RESOLUTION_RANGE) comes first


@pytest.mark.parametrize(
    ("occupied", "error", "message"),
    [
        (np.array([[0.5, 0.0]]), ArgumentTypeError, "dtype float64"),
        (np.array([[np.nan, 0.0]]), ArgumentTypeError, "dtype float64"),
        (np.array([["False", "x"]]), ArgumentTypeError, "dtype <U5"),
        (np.array([[None, None]]), ArgumentTypeError, "dtype object"),
        (np.array([[2, 0]]), ParameterError, "found the value 2"),
        (np.array([[-1, 0]]), ParameterError, "found the value -1"),
    ],
)
def test_gridmap_takes_booleans_or_0_1_integers_only(occupied, error, message) -> None:
    with pytest.raises(error, match=message):
        GridMap(Grid((1, 2), 1.0), occupied)


def test_gridmap_accepts_booleans_and_0_1_integers() -> None:
    for occ in (np.array([[True, False]]), np.array([[1, 0]], dtype=np.uint8), [[1, 0]]):
        assert GridMap(Grid((1, 2), 1.0), occ).occupied.tolist() == [[True, False]]


def test_api_errors_name_the_argument_and_what_was_expected() -> None:
    w = read_world(SEED)
    small = GridMap(Grid((2, 2), 1.0), np.eye(2, dtype=bool))
    cases = [
        (lambda: brushfire(np.zeros((3, 3), bool)), TypeError, "gridmap must be a GridMap, got ndarray"),
        (lambda: brushfire(None), TypeError, "gridmap must be a GridMap, got NoneType"),
        (lambda: plan("wavefront", None, (1, 10), (22, 12)), TypeError, "target must be a World .* got NoneType"),
        (lambda: plan("wavefront", w, (1, 10), (22, 12), [1, 2]), TypeError, "params must be a mapping"),
        (lambda: plan("wavefront", w, ("a", "b"), (22, 12)), ValueError, r"start must be two finite numbers \(x, y\)"),
        (lambda: plan("wavefront", w, (1, 10), "xy"), ValueError, "goal must be two finite numbers"),
        (lambda: brushfire(small, far=float("nan")), ValueError, "far must be a number"),
        (lambda: plan("potential", w, (1, 10), (22, 12), {"max_iterations": "10"}, resolution=0.5), ValueError,
         "max_iterations must be an integer >= 0, got '10'"),
    ]
    for call, kind, message in cases:
        with pytest.raises(GridfieldError, match=message) as e:
            call()
        assert isinstance(e.value, kind)


def test_a_huge_command_line_value_gives_a_short_usage_error(capsys) -> None:
    assert main(["info", SEED, "--resolution", "9" * 100000 + "x"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < 2 * MESSAGE_LIMIT and "--resolution" in err
