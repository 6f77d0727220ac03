"""wisp.animate: frames as arrays and the run's stats, as `wisp animate` gives them."""
import json

import numpy as np
import pytest

import wisp
from conftest import run_cli, small_style


def test_frames_and_stats(head):
    # The shake starts a quarter of a second in: by frame 9 the head has turned.
    anim = wisp.animate(small_style(600, 40), motion="shake", frames=10, fps=24, head=head)
    frames = list(anim)
    assert [f.index for f in frames] == list(range(10))
    assert frames[1].time == pytest.approx(1 / 24)
    rest = anim.rest
    assert all(f.points.shape == (rest.point_count, 3) for f in frames)
    assert np.array_equal(frames[0].points, rest.points) or np.allclose(
        frames[0].points, rest.points, atol=1e-3)
    assert not np.allclose(frames[9].points, frames[0].points)  # the hair moved
    assert anim.stats["frames"] == 10 and anim.stats["steps"] > 0
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
    # An unknown motion is refused when animate is called, not when the first frame is taken.
    with pytest.raises(ValueError, match="'no-such-motion' is neither a motion preset"):
        wisp.animate(small_hair, motion="no-such-motion", frames=2)
    with pytest.raises(TypeError, match="motion must be"):
        wisp.animate(small_hair, motion=3, frames=2)


def _tie_at(hair, strand=0, joint=10):
    """A tie through a point of a strand of the rest hair."""
    return tuple(float(v) for v in hair.points[hair.offsets[strand] + joint]) + (1.5,)


def test_ties_as_the_cli(exe, small_hair, tmp_path):
    """wisp.animate(ties=...) holds the strands the CLI's --tie holds: the same frames and
    figures as `wisp animate HAIR --tie x,y,z,r`."""
    tie = _tie_at(small_hair)
    path = tmp_path / "rest.hair"
    small_hair.write(str(path))
    rest = wisp.read(str(path))
    free = wisp.animate(rest, motion="shake", frames=3)
    list(free)
    tied = wisp.animate(rest, motion="shake", frames=3, ties=[tie])
    frames = list(tied)
    assert free.stats["hierarchy"]["held_finest_nodes"] == 0
    assert tied.stats["hierarchy"]["held_finest_nodes"] > 0
    run_cli(exe, "animate", path, "--motion", "shake", "--frames", 3, "-q",
            "--tie", ",".join(repr(v) for v in tie), "--stats", tmp_path / "s.json",
            "-o", tmp_path / "f_####.hair")
    cli = json.loads((tmp_path / "s.json").read_text())
    for key in ("hierarchy", "steps", "splits", "merges", "hair_contacts", "body_contacts",
                "links", "strands", "points", "frames"):
        assert tied.stats[key] == cli[key], key
    last = wisp.read(str(tmp_path / "f_0002.hair"))
    assert np.array_equal(last.points, frames[2].points)


def test_tied_strands_move_with_the_head(small_hair):
    """A tied strand's part from the root to the tie moves rigidly with the head."""
    tie = _tie_at(small_hair, strand=5, joint=8)
    anim = wisp.animate(small_hair, motion="shake", frames=6, ties=np.array([tie]))
    frames = list(anim)
    start = small_hair.offsets[5]
    held = small_hair.points[start:start + 6]
    last = frames[-1]
    rigid = held @ last.head_rotation.T + last.head_translation
    assert np.abs(last.points[start:start + 6] - rigid).max() < 0.05


def test_bad_ties(small_hair):
    with pytest.raises(ValueError, match=r"ties\[0\]: expected x, y, z or x, y, z, radius"):
        wisp.animate(small_hair, ties=[(1, 2)])
    with pytest.raises(ValueError, match=r"ties\[1\]: the radius must be > 0"):
        wisp.animate(small_hair, ties=[(0, 0, 0), (0, 0, 0, -1)])
    with pytest.raises(ValueError, match=r"ties\[0\]: row 1 is not finite"):
        wisp.animate(small_hair, ties=[(0, np.nan, 0)])
    with pytest.raises(TypeError, match="ties"):
        wisp.animate(small_hair, ties="0,0,0")
    # A tie far from every strand: the CLI's message, when the first frame is taken.
    with pytest.raises(ValueError, match="tie 1 .* passes within 2 cm of no strand"):
        list(wisp.animate(small_hair, frames=2, ties=[(0, 500, 0)]))
