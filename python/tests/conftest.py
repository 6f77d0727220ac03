"""Shared fixtures: a small style (fast enough for every test) and the CLI's executable."""
import os
import pathlib
import subprocess

import pytest

wisp = pytest.importorskip("wisp")


@pytest.fixture(scope="session")
def exe():
    path = os.environ.get("WISP_EXE")
    if not path:
        pytest.skip("WISP_EXE not set (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def source_dir():
    return pathlib.Path(os.environ.get("WISP_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


@pytest.fixture(scope="session")
def head():
    return wisp.Head.builtin()


def small_style(strands=3000, wisps=120):
    style = wisp.Style.preset("default")
    style.roots.wisps = wisps  # first: a style's strands must be >= its wisps
    style.roots.strands = strands
    return style


@pytest.fixture
def style():
    return small_style()


@pytest.fixture(scope="session")
def small_hair(head):
    return wisp.generate(small_style(), head=head, seed=3)


def run_cli(exe, *args):
    subprocess.run([exe, *map(str, args)], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.PIPE)
