"""wisp.animate: frames as arrays and the run's stats, as `wisp animate` gives them."""
import numpy as np
import pytest

import wisp
from conftest import small_style


def test_frames_and_stats(head):
    anim = wisp.animate(small_style(600, 40), motion="shake", frames=4, fps=24, head=head)
    frames = list(anim)
    assert [f.index for f in frames] == [0, 1, 2, 3]
    assert frames[1].time == pytest.approx(1 / 24)
    rest = anim.rest
    assert all(f.points.shape == (rest.point_count, 3) for f in frames)
    assert np.array_equal(frames[0].points, rest.points) or np.allclose(
        frames[0].points, rest.points, atol=1e-3)
    assert not np.allclose(frames[3].points, frames[0].points)  # the hair moved
    assert anim.stats["frames"] == 4 and anim.stats["steps"] > 0
    assert anim.stats["hierarchy"]["finest_nodes"] > 0


def test_animate_a_hair_and_stop_early(small_hair):
    anim = wisp.animate(small_hair, motion="lean", frames=50)
    for frame in anim:
        if frame.index == 1:
            break  # the worker stops; nothing hangs


def test_bad_arguments(small_hair):
    with pytest.raises(ValueError, match="frames"):
        wisp.animate(small_hair, frames=0)
    with pytest.raises(ValueError, match="fps"):
        wisp.animate(small_hair, fps=-1)
    with pytest.raises(TypeError):
        wisp.animate("default")
    with pytest.raises(ValueError, match="no-such-motion"):
        list(wisp.animate(small_hair, motion="no-such-motion", frames=2))
