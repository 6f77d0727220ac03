"""wisp.Hair: numpy views (no copy), validation of arrays from Python, files."""
import re
import sys

import numpy as np
import pytest

import wisp
from conftest import run_cli, small_style


def test_arrays_are_views_of_the_hair(small_hair):
    h = small_hair
    p = h.points
    assert p.dtype == np.float32 and p.shape == (h.point_count, 3)
    assert p.base is h  # the array's base is the Hair: no copy
    assert h.points.__array_interface__["data"][0] == p.__array_interface__["data"][0]
    for name in ("offsets", "colors", "widths", "wisp_ids"):
        a = getattr(h, name)
        assert a is not None and a.base is h, name
    assert h.offsets.dtype == np.uint32 and h.offsets.shape == (len(h) + 1,)
    assert h.colors.shape == (len(h), 3)
    assert h.widths.shape == (h.point_count,)
    assert h.wisp_ids.dtype == np.int32


def test_view_keeps_hair_alive(head):
    hair = wisp.generate(small_style(500, 20), head=head, seed=1)
    p = hair.points
    expected = p.copy()
    del hair
    assert np.array_equal(p, expected)


def test_writes_through_the_view(head):
    hair = wisp.generate(small_style(500, 20), head=head, seed=1)
    hair.points[0] = (1, 2, 3)
    assert tuple(hair.strand(0)[0]) == (1, 2, 3)


def test_offsets_are_read_only(small_hair):
    with pytest.raises(ValueError):
        small_hair.offsets[0] = 5


def test_strand_and_len(small_hair):
    h = small_hair
    o = h.offsets
    assert len(h) == len(o) - 1
    assert np.array_equal(h.strand(2), h.points[o[2]:o[3]])
    assert np.array_equal(h.strand(-1), h.points[o[-2]:o[-1]])
    with pytest.raises(IndexError):
        h.strand(len(h))


def test_resampled(small_hair):
    r = small_hair.resampled(16)
    assert r.shape == (len(small_hair), 16, 3) and r.dtype == np.float32
    # root and tip exact
    assert np.allclose(r[5, 0], small_hair.strand(5)[0])
    assert np.allclose(r[5, -1], small_hair.strand(5)[-1])
    seg = np.linalg.norm(np.diff(r[5], axis=0), axis=1)
    assert seg.std() < 0.05 * seg.mean() + 1e-4  # equal arc length
    with pytest.raises(ValueError, match="resampled"):
        small_hair.resampled(1)


def test_from_arrays_round_trip(small_hair, tmp_path):
    h = small_hair
    copy = wisp.Hair.from_arrays(h.points, h.offsets.astype(np.int64), colors=h.colors,
                                 widths=h.widths, wisp_ids=h.wisp_ids)
    assert np.array_equal(copy.points, h.points)
    assert np.array_equal(copy.offsets, h.offsets)


def pts(n=4):
    return np.zeros((n, 3), np.float32) + np.arange(n, dtype=np.float32)[:, None]


@pytest.mark.parametrize("points, offsets, exc, message", [
    (np.zeros((4, 2), np.float32), [0, 4], ValueError, r"points: expected shape \(P, 3\)"),
    (np.zeros((4, 3), np.int32), [0, 4], TypeError, "points: expected a floating-point"),
    (pts(), [0.0, 4.0], TypeError, "offsets: expected an integer array"),
    (pts(), [1, 4], ValueError, r"offsets\[0\] must be 0"),
    (pts(), [0, 3, 2, 4], ValueError, "not monotone"),
    (pts(), [0, 3], ValueError, "last offset must be the point count 4"),
    (np.full((4, 3), np.nan, np.float32), [0, 4], ValueError, "points: row 0 is not finite"),
    (pts(), [[0, 4]], ValueError, r"offsets: expected shape"),
    (["a", "b"], [0, 2], TypeError, "points: expected a numeric array"),
])
def test_from_arrays_rejects(points, offsets, exc, message):
    with pytest.raises(exc, match=message):
        wisp.Hair.from_arrays(points, offsets)


def test_from_arrays_rejects_bad_attributes():
    with pytest.raises(ValueError, match=r"colors: expected shape \(N, 3\)"):
        wisp.Hair.from_arrays(pts(), [0, 4], colors=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="widths: value 1 is -1"):
        wisp.Hair.from_arrays(pts(), [0, 4], widths=[0.1, -1, 0.1, 0.1])
    with pytest.raises(ValueError, match="wisp_ids: value 0 is -7"):
        wisp.Hair.from_arrays(pts(), [0, 4], wisp_ids=[-7])
    with pytest.raises(ValueError, match="farther than"):
        wisp.Hair.from_arrays(pts() * 1e6, [0, 4])


def test_missing_file_and_bad_extension(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.hair"):
        wisp.read(tmp_path / "missing.hair" if False else str(tmp_path / "missing.hair"))
    with pytest.raises(ValueError, match=r"\.usda"):
        wisp.read(str(tmp_path / "x.txt"))
    with pytest.raises(ValueError):
        wisp.Hair.from_arrays(pts(), [0, 4]).write(str(tmp_path / "x.unknown"))


def test_corrupt_file_is_error(tmp_path):
    path = tmp_path / "bad.hair"
    path.write_bytes(b"HAIR" + b"\xff" * 40)
    with pytest.raises(wisp.Error, match="bad.hair"):
        wisp.read(str(path))


@pytest.mark.parametrize("ext", ["hair", "usda", "obj", "ply", "npz", "rib", "pbrt", "data"])
def test_files_byte_identical_to_cli(exe, tmp_path, ext, head):
    style = small_style(800, 40)
    toml = tmp_path / "s.toml"
    toml.write_text(style.to_toml())
    # The same file name in two folders: scenes (.rib, .pbrt) name their picture after it.
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli = tmp_path / "cli" / f"hair.{ext}"
    run_cli(exe, "generate", toml, "-o", cli, "--seed", 11, "--threads", 1, "--quiet")
    hair = wisp.generate(wisp.Style.from_toml(toml), seed=11, threads=2)
    mine = tmp_path / "py" / f"hair.{ext}"
    hair.write(str(mine))
    assert mine.read_bytes() == cli.read_bytes()


@pytest.mark.parametrize("ext", ["hair", "usda", "obj", "ply"])
def test_read_gives_cli_arrays(exe, tmp_path, ext):
    style = small_style(800, 40)
    toml = tmp_path / "s.toml"
    toml.write_text(style.to_toml())
    cli = tmp_path / f"cli.{ext}"
    run_cli(exe, "generate", toml, "-o", cli, "--seed", 5, "--quiet")
    read = wisp.read(str(cli))
    hair = wisp.generate(wisp.Style.from_toml(toml), seed=5)
    assert np.array_equal(read.offsets, hair.offsets)
    assert np.allclose(read.points, hair.points, atol=1e-4)
    again = tmp_path / f"again.{ext}"
    read.write(str(again))
    assert wisp.read(str(again)).point_count == read.point_count


@pytest.mark.parametrize("field, value, message", [
    ("points", np.nan, "Hair: point 1 is not finite (strand 0, its point 1)"),
    ("points", 1e9, "Hair: point 1 (strand 0, its point 1) is at"),
    ("widths", np.inf, "Hair: width 1 is negative or not finite"),
])
def test_values_set_through_the_views_are_checked_before_use(field, value, message):
    # The arrays are writable views, so a NaN can reach the hair after from_arrays checked it:
    # everything that reads the hair checks it again (render once crashed the interpreter).
    p = np.zeros((4, 3), np.float32)
    p[:, 1] = np.arange(4)
    hair = wisp.Hair.from_arrays(p, [0, 4], widths=np.full(4, 0.01, np.float32))
    getattr(hair, field)[1] = value
    for use in (lambda: wisp.render(hair, size=64, head=False), lambda: hair.resampled(8),
                lambda: wisp.stages.color(wisp.Style(), hair)):
        with pytest.raises(wisp.Error, match=re.escape(message)):
            use()


def test_paths_may_be_pathlib(small_hair, tmp_path):
    # Every function that takes a file takes a str or an os.PathLike, as Python's own do.
    import pathlib
    path = tmp_path / "h.hair"
    assert isinstance(path, pathlib.Path)
    small_hair.write(path)
    assert len(wisp.read(path)) == len(small_hair)
    head = wisp.Head.builtin()
    head.write_obj(tmp_path / "head.obj")
    assert wisp.Head.from_obj(tmp_path / "head.obj").faces.shape == head.faces.shape


def test_head_from_style_takes_a_style():
    style = wisp.Style()
    assert wisp.Head.from_style(style).faces.shape[0] > 1000
    with pytest.raises(TypeError, match="Head.from_style: expected a wisp.Style, got int"):
        wisp.Head.from_style(3)


def test_compare_scores_known_cases(small_hair):
    same = wisp.compare(small_hair, small_hair, size=64)
    assert [s["f1"] for s in same["strands"]] == [1.0, 1.0, 1.0]
    assert [s["distance_cm"] for s in same["strands"]] == [0.2, 0.3, 0.4]
    assert same["position_error_cm"] == 0.0 and same["occupancy_iou"] == 1.0
    # Shifted 2.5 mm: beyond the 2 mm threshold, within 3 mm and 4 mm.
    moved = wisp.Hair.from_arrays(small_hair.points + np.float32([0.25, 0, 0]),
                                  small_hair.offsets)
    r = wisp.compare(moved, small_hair, head=False, views=["front"], size=64)
    assert r["position_error_cm"] == pytest.approx(0.25, abs=1e-4)
    assert r["strands"][0]["f1"] < r["strands"][1]["f1"] <= 1.0
    with pytest.raises(TypeError, match="compare: a must be a wisp.Hair"):
        wisp.compare(small_hair.points, small_hair)
    with pytest.raises(ValueError, match="unknown view 'sideways'"):
        wisp.compare(small_hair, small_hair, views=["sideways"])
    with pytest.raises(ValueError, match="voxel"):
        wisp.compare(small_hair, small_hair, voxel=0)


def test_render_targets_follow_the_pictures_camera(small_hair):
    r = wisp.render(small_hair, size=96, view="front",
                    targets=["mask", "depth", "strand_id", "matte", "confidence"])
    assert r["image"].shape == (96, 96, 3)
    assert set(r) >= {"mask", "depth", "strand_id", "matte", "confidence", "K",
                      "world_to_camera"}
    assert np.array_equal(r["mask"], r["matte"] >= 0.5)
    assert (r["confidence"][~r["mask"]] == 0).all()
    # The nearest strand at a hair pixel passes through it, at the depth the map gives, when
    # its points are projected with K and world_to_camera.
    K, w2c = r["K"], r["world_to_camera"]
    ys, xs = np.nonzero(r["mask"])
    assert len(ys) > 50
    offsets = small_hair.offsets
    for y, x in list(zip(ys, xs))[:: max(1, len(ys) // 25)]:
        s = r["strand_id"][y, x]
        assert s >= 0
        p = small_hair.points[offsets[s]:offsets[s + 1]].astype(np.float64)
        cam = p @ w2c[:3, :3].T + w2c[:3, 3]
        pix = cam @ K.T
        uv = pix[:, :2] / pix[:, 2:3]
        # The pixel lies on the polyline through the projected points (within a pixel).
        a, b = uv[:-1], uv[1:]
        ab = b - a
        t = np.clip(((np.array([x + 0.5, y + 0.5]) - a) * ab).sum(1) /
                    np.maximum((ab * ab).sum(1), 1e-12), 0, 1)
        near = a + t[:, None] * ab
        d = np.hypot(*(near - [x + 0.5, y + 0.5]).T)
        k = np.argmin(d)
        assert d[k] < 1.0, (x, y, s, d[k])
        z = cam[k, 2] + t[k] * (cam[k + 1, 2] - cam[k, 2])
        assert abs(z - r["depth"][y, x]) < 0.5
    with pytest.raises(ValueError, match="unknown map 'picture'"):
        wisp.render(small_hair, size=32, targets=["picture"])
    with pytest.raises(TypeError, match="targets: expected a list"):
        wisp.render(small_hair, size=32, targets="mask")
