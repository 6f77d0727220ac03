"""wisp.generate: determinism across thread counts, the GIL released, bad arguments."""
import threading
import time

import numpy as np
import pytest

import wisp
from conftest import small_style


def test_same_arrays_at_any_thread_count(head):
    style = small_style(4000, 150)
    a = wisp.generate(style, head=head, seed=9, threads=1)
    b = wisp.generate(style, head=head, seed=9, threads=2)
    c = wisp.generate(style, head=head, seed=9)
    for name in ("points", "offsets", "colors", "widths", "wisp_ids"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert np.array_equal(getattr(a, name), getattr(c, name)), name
    d = wisp.generate(style, head=head, seed=10, threads=1)
    assert not np.array_equal(a.points, d.points)


def test_stats(small_hair):
    s = small_hair.stats
    assert s["strands"] == len(small_hair)
    assert "solve" in s["time_ms"] and s["solver"]["joints"] > 0


def test_bad_arguments(head, style):
    with pytest.raises(ValueError, match="seed"):
        wisp.generate(style, head=head, seed=-1)
    with pytest.raises(TypeError, match="seed"):
        wisp.generate(style, head=head, seed=1.5)
    with pytest.raises(ValueError, match="threads"):
        wisp.generate(style, head=head, threads=-2)
    with pytest.raises(TypeError, match="threads"):
        wisp.generate(style, head=head, threads="2")
    with pytest.raises(TypeError, match="style"):
        wisp.generate("default")


def test_gil_released_two_threads_overlap(head):
    """Two Python threads generating at once overlap in time: each call's wall interval
    intersects the other's, and while they run the main thread keeps ticking."""
    style = small_style(60000, 1000)
    spans = {}
    ticks = []

    def work(k):
        t0 = time.perf_counter()
        wisp.generate(style, head=head, seed=k, threads=1)
        spans[k] = (t0, time.perf_counter())

    threads = [threading.Thread(target=work, args=(k,)) for k in (1, 2)]
    for t in threads:
        t.start()
    while any(t.is_alive() for t in threads):
        ticks.append(time.perf_counter())
        time.sleep(0.005)
    for t in threads:
        t.join()
    (a0, a1), (b0, b1) = spans[1], spans[2]
    overlap = min(a1, b1) - max(a0, b0)
    assert overlap > 0.5 * min(a1 - a0, b1 - b0), (spans, overlap)
    assert len(ticks) > 10  # the GIL was free for this thread too


def test_head_from_obj(tmp_path, head):
    path = tmp_path / "head.obj"
    head.write_obj(str(path))
    mine = wisp.Head.from_obj(str(path), scale=1.0, scalp="scalp")
    assert mine.vertices.shape == head.vertices.shape
    assert mine.faces.base is mine and mine.vertices.base is mine
    assert mine.scalp_area == pytest.approx(head.scalp_area, rel=1e-3)
    uv = head.scalp_uv(head.vertices[head.faces[head.scalp_faces[:10], 0]])
    assert uv.shape == (10, 2) and np.all(np.isfinite(uv))
    with pytest.raises(FileNotFoundError):
        wisp.Head.from_obj(str(tmp_path / "none.obj"))
    with pytest.raises(ValueError, match="head.scale"):
        wisp.Head.from_obj(str(path), scale=-1)
    with pytest.raises(ValueError, match="group"):
        wisp.Head.from_obj(str(path), scalp="no-such-group")


def test_stages_compose_to_generate(head):
    style = small_style(2000, 80)
    roots = wisp.stages.roots(style, head)
    masters = wisp.stages.masters(style, head, roots)
    solved, stats = wisp.stages.solve(style, head, roots, masters)
    assert not np.array_equal(solved.control, masters.control)
    hair = wisp.stages.color(style, wisp.stages.members(style, head, roots, solved))
    whole = wisp.generate(style, head=head)
    assert np.array_equal(hair.points, whole.points)
    assert np.array_equal(hair.colors, whole.colors)
    assert roots.master_positions.shape == (len(roots), 3)
    assert masters.control.shape == (len(masters), masters.points_per_master, 3)


def test_render(small_hair):
    image = wisp.render(small_hair, size=(96, 64), shadows=False)
    assert image.shape == (64, 96, 3) and image.dtype == np.uint8
    assert image.std() > 1  # not a blank picture
    png = small_hair._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="view"):
        wisp.render(small_hair, view="sideways", size=32)
    with pytest.raises(TypeError, match="unknown option"):
        wisp.render(small_hair, size=32, brightness=2)
    with pytest.raises(ValueError, match="size"):
        wisp.render(small_hair, size=0)
    with pytest.raises(ValueError, match="one of hair, fiber, kajiya-kay"):
        wisp.render(small_hair, size=32, shading="phong")


def test_fiber_shading_and_its_melanin(small_hair):
    assert wisp.shading_names() == ["hair", "fiber", "kajiya-kay"]
    image = wisp.render(small_hair, size=64, shading="fiber")
    assert image.std() > 1
    # Darker is more eumelanin; a red colour is pheomelanin; concentrations are >= 0.
    colors = np.array([[0.0075, 0.0056, 0.0048], [0.073, 0.039, 0.016], [0.09, 0.026, 0.012]])
    pigments = wisp.melanin_from_color(colors)
    assert pigments.shape == (3, 2) and pigments.dtype == np.float32
    assert (pigments >= 0).all()
    assert pigments[0, 0] > pigments[1, 0]
    assert pigments[2, 1] > pigments[2, 0]
    with pytest.raises(ValueError, match="shape"):
        wisp.melanin_from_color(np.zeros((3, 4)))
    with pytest.raises(ValueError, match="not finite"):
        wisp.melanin_from_color(np.array([[np.nan, 0.1, 0.1]]))
    with pytest.raises(ValueError, match="beta_n"):
        wisp.melanin_from_color(colors, beta_n=5)
