// Clumps at two scales (groom/clumps.hpp): guides spaced by the clump size, wisps joining a
// near guide of their own group that grows their way, and members that gather toward their
// clump's guide and their sub-clump's centre by the profile along the strand, each level
// tight at the tips and untouched at the roots.
#include "groom/clumps.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "groom/generate.hpp"

namespace wisp {
namespace {

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

// Straight strands without fuzziness, so that a member's unclumped points are its root
// offset carried along its master exactly, and the pull is all that moves them.
Style plain_style() {
    Style s;
    s.wisps = 400;
    s.strands = 8000;
    s.points_per_strand = 16;
    s.seed = 5;
    s.prototype.kind = PrototypeSpec::Kind::kStraight;
    s.wisp.fuzziness = 0.f;
    s.wisp.length = Distribution{Distribution::Kind::kConstant, 1.f};
    s.clump.variation = 0.f;
    s.clump.sub_variation = 0.f;
    s.hairline.baby = 0.f;
    s.flyaway.fraction = 0.f;
    return s;
}

struct Grown {
    Roots roots;
    Masters masters;
    Hair hair;
};

Grown grow(const Style& style) {
    Grown g;
    g.roots = grow_roots(style, builtin());
    g.masters = synthesize_masters(style, builtin(), g.roots);
    g.hair = grow_members(style, *builtin().scalp, g.masters, g.roots);
    return g;
}

}  // namespace

TEST(Clumps, GuidesAreSpacedByTheClumpSizeAndWispsJoinANearOneGoingTheirWay) {
    Style style = plain_style();
    style.clump.pull = 0.5f;
    style.clump.size = ScalarMap{ScalarMap::Kind::kConstant, 2.f};
    const Grown g = grow(style);
    // Two groups split left and right: no clump spans them.
    std::vector<int32_t> group(g.masters.count());
    for (size_t w = 0; w < group.size(); ++w)
        group[w] = g.masters.roots[w].position.x() > 0.f;
    const ClumpGuides c = clump_guides(style.clump, *builtin().scalp, g.masters, group);
    ASSERT_EQ(c.guide.size(), g.masters.count());
    std::vector<size_t> guides;
    size_t joined = 0;
    for (size_t w = 0; w < c.guide.size(); ++w) {
        const size_t k = static_cast<size_t>(c.guide[w]);
        ASSERT_LT(k, c.guide.size());
        if (k == w) {
            guides.push_back(w);
            continue;
        }
        ++joined;
        EXPECT_EQ(c.guide[k], static_cast<int32_t>(k)) << "a guide guides itself";
        EXPECT_EQ(group[w], group[k]);
        EXPECT_LE((g.masters.roots[w].position - g.masters.roots[k].position).norm(), 3.f + 1e-4f);
        EXPECT_GE(g.masters.direction[w].dot(g.masters.direction[k]), 0.7071f - 1e-4f);
    }
    // Guides that could share a clump are at least a size apart.
    for (size_t a = 0; a < guides.size(); ++a)
        for (size_t b = a + 1; b < guides.size(); ++b) {
            const size_t i = guides[a], j = guides[b];
            if (group[i] != group[j] ||
                g.masters.direction[i].dot(g.masters.direction[j]) < 0.7071f)
                continue;
            EXPECT_GE((g.masters.roots[i].position - g.masters.roots[j].position).norm(), 2.f);
        }
    // A random Poisson-disk set of spacing 2 fills about 55% of the scalp with disks of
    // radius 1 (more where groups and directions split it): clumps of several wisps.
    const float disks = builtin().scalp->area() / kPi;
    EXPECT_GT(static_cast<float>(guides.size()), 0.4f * disks) << guides.size() << " guides";
    EXPECT_LT(static_cast<float>(guides.size()), 1.2f * disks) << guides.size() << " guides";
    EXPECT_GT(joined, g.masters.count() / 2);
}

// Members move `pull`·s^shape of the way to the guide: the roots stay, the tips gather.
TEST(Clumps, MembersGatherTowardTheirGuideByTheProfileAlongTheStrand) {
    // Unsolved masters leave the scalp straight, each its own way: short ones stay near
    // their guide's to the tip, where the pull is unfaded.
    Style loose = plain_style();
    loose.length = ScalarMap{ScalarMap::Kind::kConstant, 8.f};
    Style clumped = loose;
    clumped.clump.pull = 0.8f;
    clumped.clump.shape = 1.f;
    clumped.clump.size = ScalarMap{ScalarMap::Kind::kConstant, 2.5f};
    const Grown a = grow(loose), b = grow(clumped);
    const ClumpGuides c = clump_guides(clumped.clump, *builtin().scalp, b.masters, {});
    const int n = b.masters.points;
    double root_before = 0, root_after = 0, tip_before = 0, tip_after = 0;
    size_t checked = 0, unfaded = 0;
    for (size_t i = 0; i < b.hair.strand_count(); ++i) {
        const size_t w = static_cast<size_t>(b.hair.wisp[i]);
        const auto guide = b.masters.strand(static_cast<size_t>(c.guide[w]));
        const auto before = a.hair.strand(i), after = b.hair.strand(i);
        ASSERT_EQ(before.size(), after.size());
        EXPECT_EQ(before[0], after[0]) << "roots do not move";
        for (size_t k = 0; k < after.size(); ++k) {
            // Far apart masters are pulled less (the fade); elsewhere exactly by the profile.
            if ((guide[k] - b.masters.strand(w)[k]).norm() > 1.5f * 2.5f) continue;
            const float s = static_cast<float>(k) / static_cast<float>(n - 1);
            const Vec3f expected = before[k] + 0.8f * s * (guide[k] - before[k]);
            ASSERT_LT((after[k] - expected).norm(), 1e-3f) << "strand " << i << " point " << k;
            ++checked;
        }
        if ((guide[n - 1] - b.masters.strand(w)[n - 1]).norm() > 1.5f * 2.5f) continue;
        ++unfaded;
        root_before += (before[1] - guide[1]).norm();
        root_after += (after[1] - guide[1]).norm();
        tip_before += (before.back() - guide[n - 1]).norm();
        tip_after += (after.back() - guide[n - 1]).norm();
    }
    EXPECT_GT(checked, b.hair.point_count() * 3 / 4);
    EXPECT_GT(unfaded, b.hair.strand_count() / 2);
    EXPECT_LT(tip_after, 0.3 * tip_before);
    EXPECT_GT(root_after, 0.9 * root_before);
}

// Inside a wisp, members gather toward the path of their sub-clump's centre, which is the
// centre's root offset carried through the wisp's cylinder.
TEST(Clumps, SubClumpsGatherInsideTheWispTowardTheirTips) {
    Style loose = plain_style();
    Style clumped = loose;
    clumped.clump.sub_count = 4;
    clumped.clump.sub_pull = 0.6f;
    clumped.clump.sub_shape = 2.f;
    const Grown a = grow(loose), b = grow(clumped);
    std::vector<uint32_t> ids(b.hair.strand_count()), centre(b.hair.strand_count());
    for (size_t i = 0; i < ids.size(); ++i)
        ids[i] = static_cast<uint32_t>(i);
    sub_clump_centres(clumped.clump, b.roots, ids, b.hair.wisp, centre);
    const int n = b.masters.points;
    double tip_before = 0, tip_after = 0, mid_before = 0, mid_after = 0;
    std::vector<int> per_wisp(b.masters.count(), 0);
    for (size_t i = 0; i < ids.size(); ++i) {
        const size_t w = static_cast<size_t>(b.hair.wisp[i]);
        const uint32_t first = b.roots.wisp_offsets[w];
        ASSERT_GE(centre[i], first);
        ASSERT_LT(centre[i], std::min(first + 4u, b.roots.wisp_offsets[w + 1]));
        // The centre's own strand is the path: it is its own centre and does not move.
        const auto path = a.hair.strand(centre[i]);
        const auto before = a.hair.strand(i), after = b.hair.strand(i);
        for (size_t k = 0; k < after.size(); ++k) {
            const float s = static_cast<float>(k) / static_cast<float>(n - 1);
            const Vec3f expected = before[k] + 0.6f * s * s * (path[k] - before[k]);
            ASSERT_LT((after[k] - expected).norm(), 1e-3f) << "strand " << i << " point " << k;
        }
        const size_t mid = static_cast<size_t>(n / 2);
        mid_before += (before[mid] - path[mid]).norm();
        mid_after += (after[mid] - path[mid]).norm();
        tip_before += (before.back() - path.back()).norm();
        tip_after += (after.back() - path.back()).norm();
    }
    EXPECT_NEAR(tip_after / tip_before, 0.4, 1e-3);
    EXPECT_NEAR(mid_after / mid_before, 1.0 - 0.6 * (8.0 / 15) * (8.0 / 15), 1e-3);
}

TEST(Clumps, EachClumpTakesItsOwnShareOfThePull) {
    std::vector<float> shares;
    for (uint64_t id = 0; id < 2000; ++id) {
        const float s = clump_share(3, id, 0.4f);
        ASSERT_GE(s, 0.6f);
        ASSERT_LE(s, 1.f);
        shares.push_back(s);
    }
    const auto [lo, hi] = std::minmax_element(shares.begin(), shares.end());
    EXPECT_LT(*lo, 0.62f);
    EXPECT_GT(*hi, 0.98f);
    EXPECT_EQ(clump_share(3, 7, 0.f), 1.f);
    EXPECT_EQ(clump_share(3, 7, 0.4f), clump_share(3, 7, 0.4f));
}

TEST(Clumps, NoPullLeavesTheMembersAsEquationOneGrowsThem) {
    Style style = plain_style();
    style.wisp.fuzziness = 0.3f;
    Style off = style;
    off.clump.size = ScalarMap{ScalarMap::Kind::kConstant, 3.f};
    off.clump.sub_count = 5;
    const Grown a = grow(style), b = grow(off);
    EXPECT_TRUE(a.hair.points == b.hair.points);
}

}  // namespace wisp

namespace wisp {
namespace {

// Two coils about parallel axes 2 cm apart, a quarter turn out of phase: a wisp pulled
// halfway toward its guide lands on the axis halfway between and keeps the coil's size, its
// phase between the two; a plain blend of the points would shrink it to 0.71 of that (and to
// nothing half a turn apart). Pulled all the way, it is the guide's point.
TEST(ClumpPoint, PullingACoilTowardItsGuideKeepsTheCoil) {
    const int n = 24;
    const float radius = 1.f, pitch = 2.5f;
    Masters m;
    m.points = n;
    m.outline.resize(2 * n);
    m.control.resize(2 * n);
    for (int w = 0; w < 2; ++w)
        for (int k = 0; k < n; ++k) {
            const float y = -0.5f * static_cast<float>(k);
            const float phase = 2.f * kPi * y / pitch + (w == 0 ? 0.f : 0.5f * kPi);
            const size_t i = static_cast<size_t>(w * n + k);
            m.outline[i] = Vec3f(2.f * static_cast<float>(w), y, 0.f);
            m.control[i] = m.outline[i] + radius * Vec3f(std::cos(phase), 0.f, std::sin(phase));
        }
    m.roots.resize(2);
    for (size_t k = 0; k < static_cast<size_t>(n); ++k) {
        const Vec3f half = clump_point(m, 0, 1, k, 0.5f);
        const Vec3f axis = 0.5f * (m.outline[k] + m.outline[n + k]);
        EXPECT_NEAR((half - axis).norm(), radius, 1e-3f) << "point " << k;
        EXPECT_NEAR(half.y(), axis.y(), 1e-4f);
        // Its phase halfway: as near its own point as the guide's, once moved to the axis.
        EXPECT_NEAR((half - axis - (m.control[k] - m.outline[k])).norm(),
                    (half - axis - (m.control[n + k] - m.outline[n + k])).norm(), 1e-3f);
        EXPECT_LT((clump_point(m, 0, 1, k, 1.f) - m.control[n + k]).norm(), 1e-4f);
        EXPECT_LT((clump_point(m, 0, 1, k, 0.f) - m.control[k]).norm(), 1e-4f);
        const Vec3f plain = 0.5f * (m.control[k] + m.control[n + k]);
        EXPECT_NEAR((plain - axis).norm(), 0.7071f * radius, 1e-3f) << "the blend this replaces";
    }
}

}  // namespace
}  // namespace wisp
