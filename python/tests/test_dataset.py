"""`wisp dataset`'s files as numpy reads them: cameras.npz holds what cameras.json says, and its
matrices project the sample's hair onto its mask."""
import json

import numpy as np
import pytest

from conftest import run_cli


@pytest.fixture(scope="module")
def sample(exe, source_dir, tmp_path_factory):
    d = tmp_path_factory.mktemp("dataset")
    run_cli(exe, "dataset", "plan", source_dir / "tests" / "dataset" / "small.toml", "-o", d)
    run_cli(exe, "dataset", "run", d, "--task-id", 2, "--tasks", 8, "-q")
    return d / "samples" / "000002"


def test_cameras_npz_equals_cameras_json(sample):
    cams = np.load(sample / "cameras.npz")
    assert sorted(cams.files) == ["K", "fov_y_degrees", "image_size", "world_to_camera"]
    js = json.loads((sample / "cameras.json").read_text())["cameras"]
    c = len(js)
    assert c == 2
    assert cams["K"].shape == (c, 3, 3) and cams["K"].dtype == np.float64
    assert cams["world_to_camera"].shape == (c, 4, 4) and cams["world_to_camera"].dtype == np.float64
    assert cams["image_size"].shape == (c, 2) and cams["image_size"].dtype == np.int32
    for i, cam in enumerate(js):
        K = np.array([[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]])
        assert np.array_equal(cams["K"][i], K)
        assert np.array_equal(cams["world_to_camera"][i], np.array(cam["world_to_camera"]))
        assert list(cams["image_size"][i]) == [cam["width"], cam["height"]]
        assert cams["fov_y_degrees"][i] == cam["fov_y_degrees"]
        r = cams["world_to_camera"][i][:3, :3]
        assert np.allclose(r @ r.T, np.eye(3), atol=1e-5)  # a rotation


def test_cameras_project_the_hair_onto_its_depth_map(sample):
    """pixel = K (R p + t), pixel (i, j) covering [i, i+1) × [j, j+1): the sample's control
    points land on pixels of its depth map, at their own depth where nothing is in front."""
    cams = np.load(sample / "cameras.npz")
    points = np.load(sample / "hair.npz")["control_points"].astype(np.float64)
    for i in range(len(cams["K"])):
        w, h = cams["image_size"][i]
        depth = np.load(sample / f"cam{i}_depth.npy")
        assert depth.shape == (h, w) and depth.dtype == np.float32
        cam = (cams["world_to_camera"][i] @ np.c_[points, np.ones(len(points))].T).T[:, :3]
        assert (cam[:, 2] > 0).all()  # in front of the camera
        pix = (cams["K"][i] @ cam.T).T
        x, y = pix[:, 0] / pix[:, 2], pix[:, 1] / pix[:, 2]
        inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        assert inside.mean() > 0.95
        d = depth[y[inside].astype(int), x[inside].astype(int)]
        z = cam[inside, 2]
        # Strand points land on covered pixels, and no surface seen there lies behind them
        # (a flipped or shifted convention fails both: about 0.75 and 0.9 here).
        assert (d > 0).mean() > 0.99
        assert (d <= z + 0.5).mean() > 0.99
        # Most are hidden by strands in front; some are the surface seen.
        assert (np.abs(d - z) < 0.5).mean() > 0.05
