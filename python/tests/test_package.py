"""`pip install .` into a fresh virtual environment, and `import wisp` from outside the tree."""
import os
import pathlib
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(os.environ.get("WISP_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def test_pip_install_into_a_fresh_venv(tmp_path):
    env_dir = tmp_path / "env"
    # The venv sees the system's packages for numpy and setuptools: nothing is downloaded.
    made = subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)],
                          capture_output=True, text=True)
    if made.returncode != 0:
        pytest.skip("no venv module (Debian's python3-venv): " + made.stderr[-300:])
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    # The build tree ctest runs in is reused: pip's build only checks that the extension is up
    # to date there instead of compiling the libraries again.
    if "WISP_BUILD_TREE" in os.environ:
        env["WISP_BUILD_DIR"] = os.environ["WISP_BUILD_TREE"]
    pip = subprocess.run([str(env_dir / "bin" / "pip"), "install", "--no-build-isolation",
                          "--no-index", "--no-deps", str(SOURCE)],
                         capture_output=True, text=True, env=env, cwd=tmp_path)
    assert pip.returncode == 0, pip.stdout[-2000:] + pip.stderr[-2000:]
    code = ("import wisp, numpy as np\n"
            "s = wisp.Style.preset('short'); s.roots.wisps = 50; s.roots.strands = 300\n"
            "h = wisp.generate(s)\n"
            "print(wisp.__version__, wisp.__file__, len(h), h.points.dtype)\n")
    run = subprocess.run([str(env_dir / "bin" / "python"), "-c", code], capture_output=True,
                         text=True, env=env, cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    version, where, strands, dtype = run.stdout.split()
    cmake = (SOURCE / "CMakeLists.txt").read_text()
    assert f"project(wisp VERSION {version}" in cmake
    assert pathlib.Path(where).is_relative_to(env_dir), where
    assert (strands, dtype) == ("300", "float32")
