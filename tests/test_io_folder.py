"""A map's folder stands for its one map file (a ROS map ships as map.yaml + map.pgm in a folder of its own,
and a newcomer passes the folder: it was refused with "is a directory, expected a map file")."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from gridfield.cli import main
from gridfield.core.errors import MapFormatError
from gridfield.io import bundled_map, read


def test_a_ros_folder_reads_as_its_yaml(test_maps):
    folder = test_maps / "ros_maps" / "turtlebot3_world"
    a, b = read(folder), read(folder / "map.yaml")
    assert a.grid == b.grid and np.array_equal(a.occupied, b.occupied)


def test_a_moving_ai_folder_reads_as_its_map(tmp_path, capsys):
    shutil.copy(bundled_map("arena/arena.map"), tmp_path / "arena.map")
    shutil.copy(bundled_map("arena/arena.map.scen"), tmp_path / "arena.map.scen")
    assert np.array_equal(read(tmp_path).occupied, read(tmp_path / "arena.map").occupied)
    assert main(["plan", str(tmp_path), "--start", "1.5", "37.5", "--goal", "45.5", "3.5"]) == 0
    assert "potential: reached" in capsys.readouterr().out


def test_a_folder_with_several_or_no_maps_names_them(tmp_path, capsys):
    for name in ("a.yaml", "b.yaml"):
        shutil.copy(bundled_map("seed000.yaml"), tmp_path / name)
    with pytest.raises(MapFormatError, match=r"is a directory with 2 map files \(a\.yaml, b\.yaml\); give one of them"):
        read(tmp_path)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["info", str(empty)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "is a directory with no map file" in err
