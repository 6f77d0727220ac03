"""The examples/ scripts, run small."""
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import wisp
from conftest import small_style

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def run(*args, timeout=600):
    env = dict(os.environ)
    result = subprocess.run([sys.executable, *map(str, args)], env=env, capture_output=True,
                            text=True, timeout=timeout)
    assert result.returncode == 0, result.stderr[-3000:]
    return result.stdout


def test_sweep_contact_sheet(tmp_path):
    out = tmp_path / "sheet.png"
    run(EXAMPLES / "sweep_contact_sheet.py", out, "--values", "0.5,3", "--strands", "1500",
        "--size", "64")
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_render_data_file(tmp_path, head):
    data = tmp_path / "hair.data"
    wisp.generate(small_style(600, 30), head=head, seed=2).write(str(data))
    out = tmp_path / "data.png"
    stdout = run(EXAMPLES / "render_data_file.py", data, out, "--size", "64")
    assert "600 strands" in stdout and out.read_bytes()[:4] == b"\x89PNG"


def test_dask_dataset(tmp_path):
    pytest.importorskip("dask.distributed")
    run(EXAMPLES / "dask_dataset.py", tmp_path, "--samples", "3", "--strands", "400",
        "--workers", "2")
    files = sorted(tmp_path.glob("sample_*.npz"))
    assert len(files) == 3
    a = np.load(files[0])
    assert a["positions"].shape[1:] == (32, 3)
    # Sample k is a pure function of k: generating sample 1 again gives the same file.
    sys.path.insert(0, str(EXAMPLES))
    try:
        import dask_dataset
        again = tmp_path / "again"
        again.mkdir()
        dask_dataset.make_sample(1, "wavy-bob", 400, again)
    finally:
        sys.path.pop(0)
    assert (again / "sample_00001.npz").read_bytes() == files[1].read_bytes()
