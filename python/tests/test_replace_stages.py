"""Replacing a stage with one's own arrays: Roots.from_arrays and Masters.replaced, checked at
the boundary and taken by the next stage."""
import numpy as np
import pytest

import wisp
from conftest import small_style


@pytest.fixture(scope="module")
def pipeline(head):
    style = small_style(2000, 80)
    roots = wisp.stages.roots(style, head)
    masters = wisp.stages.masters(style, head, roots)
    return style, roots, masters


def test_roots_from_a_stages_own_arrays_give_its_masters(head, pipeline):
    style, roots, masters = pipeline
    own = wisp.Roots.from_arrays(head, roots.master_positions, roots.member_positions,
                                 roots.wisp_offsets)
    assert len(own) == len(roots)
    assert np.array_equal(own.master_positions, roots.master_positions)
    assert np.array_equal(own.wisp_offsets, roots.wisp_offsets)
    # Each wisp's radius is its farthest member, as the roots stage measures it.
    assert np.allclose(own.wisp_radius, roots.wisp_radius, atol=1e-4)
    again = wisp.stages.masters(style, head, own)
    # Normals and scalp UVs are taken from the surface at each root: the same up to rounding.
    assert np.allclose(again.control, masters.control, atol=1e-2)


def test_own_roots_flow_through_every_stage(head, pipeline):
    style, roots, _ = pipeline
    # Half the wisps, each with its members: the next stages take them as they are.
    k = len(roots) // 2
    offsets = roots.wisp_offsets[: k + 1].astype(np.int64)
    members = roots.member_positions[: offsets[-1]]
    own = wisp.Roots.from_arrays(head, roots.master_positions[:k].astype(np.float64), members,
                                 offsets)
    masters = wisp.stages.masters(style, head, own)
    solved, _ = wisp.stages.solve(style, head, own, masters)
    hair = wisp.stages.color(style, wisp.stages.members(style, head, own, solved))
    assert len(masters) == k
    assert 0 < len(hair) <= offsets[-1]
    assert set(np.unique(hair.wisp_ids)) <= set(range(k))
    # Every strand starts at one of the given member roots.
    starts = hair.points[hair.offsets[:-1]]
    nearest = np.min(np.linalg.norm(starts[:, None, :] - members[None, :, :], axis=2), axis=1)
    assert nearest.max() < 1e-3


@pytest.mark.parametrize("change, exc, message", [
    (dict(master_positions=np.zeros((0, 3))), ValueError, "at least one wisp"),
    (dict(master_positions=np.zeros((4, 2))), ValueError, r"master_positions: expected shape \(W, 3\)"),
    (dict(member_positions=np.array([[np.nan, 0, 0]])), ValueError, "member_positions: row 0 is not finite"),
    (dict(master_positions=np.ones((2, 3), dtype=np.int32)), TypeError, "master_positions: expected a floating-point"),
    (dict(wisp_offsets=np.array([0, 1])), ValueError, r"wisp_offsets: expected shape \(W \+ 1,\)"),
    (dict(wisp_offsets=np.array([0, 1, 0])), ValueError, "wisp_offsets: not monotone"),
    (dict(wisp_offsets=np.array([0, 1, 1])), ValueError, "the last offset must be the member count 2"),
    (dict(wisp_offsets=np.array([0.0, 1.0, 2.0])), TypeError, "wisp_offsets: expected an integer array"),
])
def test_roots_from_arrays_rejects(head, pipeline, change, exc, message):
    _, roots, _ = pipeline
    args = dict(master_positions=roots.master_positions[:2],
                member_positions=roots.member_positions[:2], wisp_offsets=np.array([0, 1, 2]))
    args.update(change)
    with pytest.raises(exc, match=message):
        wisp.Roots.from_arrays(head, **args)


def test_roots_must_lie_on_the_head(head, pipeline):
    _, roots, _ = pipeline
    far = roots.master_positions[:2].copy()
    far[1] += np.array([0, 10, 0], dtype=np.float32)
    with pytest.raises(ValueError, match=r"master_positions: row 1 .* cm from the head's surface"):
        wisp.Roots.from_arrays(head, far, roots.member_positions[:2], [0, 1, 2])
    with pytest.raises(TypeError):
        wisp.Roots.from_arrays(None, far, roots.member_positions[:2], [0, 1, 2])


def test_masters_replaced_by_own_outline(head, pipeline):
    style, roots, masters = pipeline
    same = masters.replaced(outline=masters.outline, details=masters.details)
    assert np.allclose(same.control, masters.control, atol=1e-4)
    assert same.control.base is not masters.control.base  # a copy; the original is kept
    # Hair half as long: every joint pulled halfway to its root.
    root = masters.outline[:, :1, :]
    short = masters.replaced(outline=root + 0.5 * (masters.outline - root))
    assert np.allclose(short.outline, root + 0.5 * (masters.outline - root), atol=1e-5)
    long_hair = wisp.stages.members(style, head, roots, masters)
    short_hair = wisp.stages.members(style, head, roots, short)

    def mean_length(hair):
        seg = np.linalg.norm(np.diff(hair.points, axis=0), axis=1)
        inside = np.ones(len(seg), bool)
        inside[hair.offsets[1:-1] - 1] = False  # no segment joins two strands
        return seg[inside].sum() / len(hair)

    assert 0.35 < mean_length(short_hair) / mean_length(long_hair) < 0.65
    # Straight masters: no details.
    flat = masters.replaced(details=np.zeros_like(masters.details))
    assert np.allclose(flat.control, flat.outline)
    # The solver and the members stage take the replaced masters.
    solved, stats = wisp.stages.solve(style, head, roots, short)
    assert stats["joints"] > 0 and len(solved) == len(masters)


def test_masters_replaced_rejects(pipeline):
    _, _, masters = pipeline
    w, n = len(masters), masters.points_per_master
    with pytest.raises(ValueError, match=rf"outline: expected shape \({w}, {n}, 3\), got \({w}, {n - 1}, 3\)"):
        masters.replaced(outline=masters.outline[:, 1:, :])
    bad = masters.outline.copy()
    bad[3, 5, 1] = np.inf
    with pytest.raises(ValueError, match=r"outline\[3, 5\]: not a finite coordinate"):
        masters.replaced(outline=bad)
    moved = masters.outline.copy()
    moved[2] += 1.0
    with pytest.raises(ValueError, match=r"outline\[2, 0\]: the first joint must be master 2's root"):
        masters.replaced(outline=moved)
    with pytest.raises(TypeError, match="details: expected a floating-point"):
        masters.replaced(details=np.zeros((w, n, 3), dtype=np.int64))
    with pytest.raises(ValueError, match=r"details: expected shape"):
        masters.replaced(details=np.zeros((w, n)))


def test_render_alpha_is_coverage(small_hair, head):
    size = (96, 80)
    plain = wisp.render(small_hair, size=size, shadows=False)
    rgba = wisp.render(small_hair, size=size, shadows=False, alpha=True)
    assert rgba.shape == (80, 96, 4) and rgba.dtype == np.uint8
    assert rgba.base is not None  # the array owns the renderer's memory
    a = rgba[..., 3]
    assert a[0, 0] == 0 and a[-1, -1] == 0  # the corners show the background
    assert (a == 255).mean() > 0.1  # hair and head cover much of the picture
    assert ((a > 0) & (a < 255)).any()  # antialiased edges
    assert not rgba[..., :3][a == 0].any()  # nothing covers: black

    # Straight colours composited over the background give the plain picture back.
    def linear(c):
        c = c / 255.0
        return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)

    background = np.array([0.3, 0.3, 0.31])
    alpha = a[..., None] / 255.0
    over = linear(rgba[..., :3]) * alpha + background * (1 - alpha)
    assert np.abs(over - linear(plain)).max() < 0.02

    # Without the head only the hair covers pixels.
    hair_only = wisp.render(small_hair, head=False, size=size, shadows=False, alpha=True)
    assert 0 < (hair_only[..., 3] > 0).sum() < (a > 0).sum()
    with pytest.raises(TypeError, match="alpha"):
        wisp.render(small_hair, size=32, alpha="yes")


def test_wrong_types_are_named():
    style = wisp.Style()
    head = wisp.Head.builtin()
    with pytest.raises(TypeError, match="stages.roots: style must be a wisp.Style, got int"):
        wisp.stages.roots(3, head)
    with pytest.raises(TypeError, match="stages.color: hair must be a wisp.Hair, got int"):
        wisp.stages.color(style, 3)
    with pytest.raises(TypeError, match="stages.masters: roots must be a wisp.Roots, got str"):
        wisp.stages.masters(style, head, "roots")
