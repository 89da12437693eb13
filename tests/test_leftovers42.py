"""Leftovers of issue 42: a saved configuration space keeps its diagonals (.npz, fields, Zarr stores)."""

from __future__ import annotations

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.core.errors import MapFormatError, ParameterError
from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import apply_robot
from gridfield.io import load_field, read, read_npz, save_field, write_npz
from gridfield.planners import plan

# ----------------------------------------------------------------------------------------------
# 1. a saved C-space keeps its diagonals
# ----------------------------------------------------------------------------------------------
# The map of tests/test_cspace_moves.py: two rooms of a wall-bordered 8x8 map that a disc of radius 0.6 joins
# only through corners of its configuration space (rows top first, as in the file).
CORNER_MAP = ["........", "........", "........", "........", "@@@.....", ".....@@@", "........", "........"]
CORNER_START, CORNER_GOAL, CORNER_RADIUS = (2.5, 1.5), (4.5, 5.5), 0.6


def corner_cspace() -> GridMap:
    occ = np.array([[ch == "@" for ch in row] for row in CORNER_MAP[::-1]])
    cspace = apply_robot(GridMap(Grid(occ.shape, 1.0, border="wall"), occ), CORNER_RADIUS)
    assert cspace.diagonals is not None and cspace.diagonals.any()
    return cspace


def assert_same_moves(loaded: GridMap, cspace: GridMap) -> None:
    """Equal diagonals, and the octile wavefront takes the same path on both (through the corners: the map
    without its diagonals has none)."""
    assert loaded.diagonals is not None
    assert loaded.diagonals.dtype == np.uint8 and np.array_equal(loaded.diagonals, cspace.diagonals)
    assert np.array_equal(loaded.occupied, cspace.occupied) and loaded.grid == cspace.grid
    want = plan("wavefront-octile", cspace, CORNER_START, CORNER_GOAL)
    got = plan("wavefront-octile", loaded, CORNER_START, CORNER_GOAL)
    assert want.status == got.status == "reached"
    assert np.array_equal(got.points, want.points)
    plain = cspace.with_occupied(cspace.occupied, diagonals=None)
    assert plan("wavefront-octile", plain, CORNER_START, CORNER_GOAL).status == "no_path"


def test_write_npz_and_read_npz_round_trip_the_diagonals(tmp_path):
    cspace = corner_cspace()
    f = write_npz(tmp_path / "c.npz", {"occupied": cspace.occupied}, cspace.grid, diagonals=cspace.diagonals)
    assert_same_moves(read_npz(f), cspace)
    assert_same_moves(read(f), cspace)
    # a map without diagonals is read back without them
    f = write_npz(tmp_path / "plain.npz", {"occupied": cspace.occupied}, cspace.grid)
    assert read_npz(f).diagonals is None


def test_write_npz_checks_the_diagonals(tmp_path):
    cspace = corner_cspace()
    with pytest.raises(ParameterError, match=r"diagonals has shape \(8, 8\), but the grid's 2x2 blocks have shape"):
        write_npz(tmp_path / "c.npz", {"occupied": cspace.occupied}, cspace.grid, diagonals=np.zeros((8, 8), np.uint8))
    with pytest.raises(ParameterError, match=r"written with write_npz\(\.\.\., diagonals=gridmap\.diagonals\)"):
        write_npz(tmp_path / "c.npz", {"occupied": cspace.occupied, "diagonals": cspace.diagonals}, cspace.grid)


@pytest.mark.parametrize("bad, why", [
    (np.zeros((8, 8), np.uint8), r"got dtype uint8 and shape \(8, 8\)"),
    (np.zeros((7, 7), np.float64), r"got dtype float64 and shape \(7, 7\)"),
    (np.full((7, 7), 4, np.uint8), "found the value 4"),
])
def test_a_file_with_bad_diagonals_is_a_map_format_error_naming_it(tmp_path, bad, why):
    cspace = corner_cspace()
    f = tmp_path / "bad.npz"
    with open(f, "wb") as fh:
        np.savez(fh, occupied=cspace.occupied, diagonals=bad, resolution=1.0, origin=np.zeros(2),
                 border=np.asarray("wall"))
    with pytest.raises(MapFormatError, match=rf"^{f}: array 'diagonals' must .*{why}"):
        read_npz(f)


def test_the_cli_npz_of_a_disc_robot_keeps_the_diagonals(tmp_path, capsys):
    m = tmp_path / "corner.map"
    m.write_text("type octile\nheight 8\nwidth 8\nmap\n" + "\n".join(CORNER_MAP) + "\n")
    cspace = corner_cspace()
    out = tmp_path / "b.npz"
    assert main(["brushfire", str(m), "--robot-radius", str(CORNER_RADIUS), "--npz", str(out)]) == 0
    assert_same_moves(read(out), cspace)
    out = tmp_path / "f.npz"
    assert main(["field", str(m), "--robot-radius", str(CORNER_RADIUS), "--goal", *map(str, CORNER_GOAL),
                 "--planner", "wavefront-octile", "--npz", str(out)]) == 0
    assert_same_moves(read(out), cspace)
    out = tmp_path / "i.npz"
    assert main(["info", str(m), "--robot-radius", str(CORNER_RADIUS), "--npz", str(out)]) == 0
    assert_same_moves(read(out), cspace)
    capsys.readouterr()


def test_save_field_and_load_field_keep_the_map_diagonals(tmp_path):
    from gridfield.fields.navtable import navigation_field

    cspace = corner_cspace()
    field = navigation_field(cspace, CORNER_GOAL, "wavefront-octile").to_field()
    assert field.map.diagonals is not None
    save_field(tmp_path / "f.npz", field)
    assert_same_moves(load_field(tmp_path / "f.npz").map, cspace)


def test_write_store_and_read_store_keep_the_diagonals(tmp_path):
    pytest.importorskip("dask")
    zarr = pytest.importorskip("zarr")
    from gridfield.io import read_store, write_store

    cspace = corner_cspace()
    p = write_store(tmp_path / "c.zarr", {"occupied": cspace.occupied}, cspace.grid, kind="map", chunks=3,
                    scheduler="synchronous", diagonals=cspace.diagonals)
    lazy = read_store(p)
    assert lazy.diagonals is not None and np.array_equal(np.asarray(lazy.diagonals), cspace.diagonals)
    assert_same_moves(lazy.to_gridmap(), cspace)
    p = write_store(tmp_path / "plain.zarr", {"occupied": cspace.occupied}, cspace.grid, kind="map", chunks=3,
                    scheduler="synchronous")
    assert read_store(p).diagonals is None and read_store(p).to_gridmap().diagonals is None
    # a store whose diagonals are not one uint8 per 2x2 block is refused, naming it
    group = zarr.open_group(str(p), mode="a")
    group.create_array("diagonals", shape=(8, 8), chunks=(3, 3), dtype="uint8", fill_value=0)
    with pytest.raises(MapFormatError, match=rf"^{p}: array 'diagonals' must be a uint8 array of shape \(7, 7\)"):
        read_store(p)


def test_the_cli_store_of_a_disc_robot_keeps_the_diagonals(tmp_path, capsys):
    pytest.importorskip("dask")
    pytest.importorskip("zarr")
    from gridfield.io import read_store

    m = tmp_path / "corner.map"
    m.write_text("type octile\nheight 8\nwidth 8\nmap\n" + "\n".join(CORNER_MAP) + "\n")
    out = tmp_path / "b.zarr"
    assert main(["brushfire", str(m), "--robot-radius", str(CORNER_RADIUS), "--metric", "euclidean", "--out", str(out),
                 "--chunks", "3"]) == 0
    capsys.readouterr()
    assert_same_moves(read(out).map.to_gridmap(), corner_cspace())
    assert_same_moves(read_store(out).map.to_gridmap(), corner_cspace())
