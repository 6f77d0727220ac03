// The multiresolution hierarchy (Bertails et al. 2003 §2.1–§2.2) and the strand binding.
#include "dynamics/hierarchy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "dynamics/animate.hpp"
#include "dynamics/skin.hpp"
#include "dynamics_fixture.hpp"

namespace wisp {
namespace {

const test::Groomed& long_hair() {
    static const test::Groomed g = test::groomed("long-straight");
    return g;
}

// Which strands are short: under a quarter of the median length (baby hairs). They make
// wisps and groups of their own.
std::vector<uint8_t> short_strands(const Hair& hair) {
    std::vector<float> lengths(hair.strand_count());
    for (size_t s = 0; s < lengths.size(); ++s) {
        const auto strand = hair.strand(s);
        for (size_t i = 1; i < strand.size(); ++i)
            lengths[s] += (strand[i] - strand[i - 1]).norm();
    }
    std::vector<float> sorted = lengths;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    std::vector<uint8_t> out(lengths.size());
    for (size_t s = 0; s < lengths.size(); ++s)
        out[s] = lengths[s] < 0.25f * sorted[sorted.size() / 2];
    return out;
}

// The wisp GCs the styled wisps make: one per wisp id, or two where it holds short strands.
size_t styled_wisp_gcs(const Hair& hair) {
    const std::vector<uint8_t> is_short = short_strands(hair);
    std::set<std::pair<int32_t, uint8_t>> keys;
    for (size_t s = 0; s < hair.strand_count(); ++s)
        keys.emplace(hair.wisp[s], is_short[s]);
    return keys.size();
}

void expect_well_formed(const Hierarchy& h, const Hair& hair) {
    ASSERT_EQ(h.level_begin.size(), static_cast<size_t>(h.levels + 1));
    const int n = h.sections;
    std::vector<uint32_t> strands_seen(h.gc_count(), 0);
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const uint32_t g = h.strand_gc[s];
        ASSERT_GE(g, h.finest_begin());
        ASSERT_LT(g, h.gc_count());
        ++strands_seen[g];
    }
    for (uint32_t g = 0; g < h.gc_count(); ++g) {
        if (h.level[g] + 1 == h.levels) {
            EXPECT_EQ(h.child_count[g], 0u);
            EXPECT_EQ(strands_seen[g], h.strand_count[g]) << "finest GC " << g;
            continue;
        }
        ASSERT_GT(h.child_count[g], 0u) << "GC " << g;
        uint32_t carried = 0;
        for (uint32_t c = h.child_begin[g]; c < h.child_begin[g] + h.child_count[g]; ++c) {
            EXPECT_EQ(h.super[c], static_cast<int32_t>(g));
            EXPECT_EQ(h.level[c], h.level[g] + 1);
            carried += h.strand_count[c];
        }
        EXPECT_EQ(carried, h.strand_count[g]);
        for (int k = 0; k < n; ++k) {
            const uint32_t i = h.node(g, k);
            double mass = 0;
            Vec3d centre = Vec3d::Zero();
            for (uint32_t c = h.child_begin[g]; c < h.child_begin[g] + h.child_count[g]; ++c) {
                const uint32_t j = h.node(c, k);
                mass += h.mass[j];
                centre += h.mass[j] * h.rest[j].cast<double>();
                // §2.1: the super-GC encloses its sub-GCs.
                EXPECT_LE((h.rest[j] - h.rest[i]).norm() + h.radius[j], h.radius[i] + 1e-4f);
            }
            EXPECT_NEAR(h.mass[i], mass, 1e-5 * mass);  // mass is additive
            EXPECT_LT((centre / mass - h.rest[i].cast<double>()).norm(), 1e-4);
        }
    }
    for (uint32_t g = 0; g < h.level_begin[1]; ++g)
        EXPECT_EQ(h.super[g], -1);
}

TEST(Hierarchy, ThreeLevelsFromTheStyledWisps) {
    const test::Groomed& g = long_hair();
    HierarchyOptions o;
    o.levels = 3;
    o.wisps_per_group = 6;
    o.sub_wisps = 3;
    o.sections = 8;
    const Hierarchy h = build_hierarchy(g.hair, o);
    expect_well_formed(h, g.hair);
    // Level 1 is the styled wisps, one GC per wisp id, and one more where a wisp holds short
    // strands (a few baby hairs at the nape).
    std::set<int32_t> ids(g.hair.wisp.begin(), g.hair.wisp.end());
    EXPECT_EQ(h.level_size(1), styled_wisp_gcs(g.hair));
    EXPECT_LE(h.level_size(1), ids.size() + ids.size() / 10);
    // No GC mixes short strands with long ones.
    const std::vector<uint8_t> is_short = short_strands(g.hair);
    std::vector<int> kind(h.gc_count(), -1);
    for (size_t s = 0; s < g.hair.strand_count(); ++s)
        for (int32_t gc = static_cast<int32_t>(h.strand_gc[s]); gc >= 0; gc = h.super[gc]) {
            if (kind[gc] < 0) kind[gc] = is_short[s];
            EXPECT_EQ(kind[gc], is_short[s]) << "GC " << gc << ", strand " << s;
        }
    // About six wisps a group; more groups where neighbouring wisps part ways.
    EXPECT_GE(h.level_size(0), (ids.size() + 5) / 6);
    EXPECT_LE(h.level_size(0), (ids.size() + 2) / 3);
    EXPECT_LE(h.level_size(2), 3 * h.level_size(1));
    EXPECT_GT(h.level_size(2), 2 * ids.size());
    // Every strand of a wisp GC carries that wisp's id.
    std::vector<int32_t> id_of(h.gc_count(), -1);
    for (size_t s = 0; s < g.hair.strand_count(); ++s) {
        const int32_t wisp = h.super[h.strand_gc[s]];
        ASSERT_GE(wisp, 0);
        if (id_of[wisp] < 0) id_of[wisp] = g.hair.wisp[s];
        EXPECT_EQ(g.hair.wisp[s], id_of[wisp]) << "strand " << s;
    }
    // Groups hold neighbours: measured against how far the roots spread over the scalp (about
    // 12 cm from their centre on long-straight), a group's roots keep close together. Groups are
    // cut by the strands' whole shapes, so wisps that hang alike can join from a few wisp
    // spacings apart; six wisps picked at random would spread over most of the scalp.
    Vec3f centre = Vec3f::Zero();
    for (size_t s = 0; s < g.hair.strand_count(); ++s)
        centre += g.hair.strand(s)[0];
    centre /= static_cast<float>(g.hair.strand_count());
    float spread = 0.f;
    for (size_t s = 0; s < g.hair.strand_count(); ++s)
        spread = std::max(spread, (g.hair.strand(s)[0] - centre).norm());
    std::vector<float> radius;
    for (uint32_t top = 0; top < h.level_size(0); ++top)
        radius.push_back(h.radius[h.node(top, 0)]);
    std::sort(radius.begin(), radius.end());
    EXPECT_LT(radius[radius.size() / 2], 0.45f * spread);
    EXPECT_LT(radius.back(), 0.75f * spread);
    // No group's wisps part ways: at every section the wisps' mean points stay within 3 times
    // the distance their roots keep from the group's centre (at least 1 cm). Long hair falling
    // on both sides of a shoulder made groups whose tips spread 20 cm from roots 3 cm apart.
    // Short strands (under a quarter of the median length: baby hairs) move with their
    // neighbours, as the hierarchy clusters them; by their own shape they would stay by the
    // root.
    const int n = o.sections;
    std::vector<float> length(g.hair.strand_count());
    for (size_t s = 0; s < g.hair.strand_count(); ++s) {
        const auto strand = g.hair.strand(s);
        for (size_t i = 1; i < strand.size(); ++i)
            length[s] += (strand[i] - strand[i - 1]).norm();
    }
    std::vector<float> sorted = length;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const float short_strand = 0.25f * sorted[sorted.size() / 2];
    std::vector<Vec3f> wisp_mean(h.gc_count() * n, Vec3f::Zero());
    std::vector<float> counted(h.gc_count(), 0.f);
    for (size_t s = 0; s < g.hair.strand_count(); ++s) {
        if (length[s] < short_strand) continue;
        const uint32_t wisp = static_cast<uint32_t>(h.super[h.strand_gc[s]]);
        for (int k = 0; k < n; ++k)
            wisp_mean[wisp * n + k] +=
                point_at_fraction(g.hair.strand(s), static_cast<float>(k) / (n - 1));
        counted[wisp] += 1.f;
    }
    for (size_t w = 0; w < counted.size(); ++w)
        for (int k = 0; k < n; ++k)
            if (counted[w] > 0.f) wisp_mean[w * n + k] /= counted[w];
    for (uint32_t top = 0; top < h.level_size(0); ++top) {
        float root = 0, worst = 0;
        for (int k = 0; k < n; ++k) {
            Vec3f centre = Vec3f::Zero();
            float wisps = 0.f;
            for (uint32_t w = h.child_begin[top]; w < h.child_begin[top] + h.child_count[top]; ++w)
                if (counted[w] > 0.f) centre += wisp_mean[w * n + k], wisps += 1.f;
            centre /= std::max(wisps, 1.f);
            float spread = 0;
            for (uint32_t w = h.child_begin[top]; w < h.child_begin[top] + h.child_count[top]; ++w)
                if (counted[w] > 0.f)
                    spread = std::max(spread, (wisp_mean[w * n + k] - centre).norm());
            (k == 0 ? root : worst) = std::max(k == 0 ? root : worst, spread);
        }
        EXPECT_LE(worst, 3.f * std::max(root, 1.f) + 1e-3f)
            << "group " << top << ": roots " << root << " cm from its centre, wisps " << worst;
    }
}

TEST(Hierarchy, LevelCountsTwoAndFour) {
    const test::Groomed& g = long_hair();
    HierarchyOptions o;
    o.levels = 2;
    const Hierarchy two = build_hierarchy(g.hair, o);
    expect_well_formed(two, g.hair);
    EXPECT_EQ(two.level_size(0), styled_wisp_gcs(g.hair));
    o.levels = 4;
    o.sub_wisps = 2;
    const Hierarchy four = build_hierarchy(g.hair, o);
    expect_well_formed(four, g.hair);
    EXPECT_GT(four.level_size(3), four.level_size(2));
}

TEST(Hierarchy, ImportedHairIsClusteredByRootAndShape) {
    // Unparted: bisection by root and shape still lets a cluster straddle a parting, where
    // strands from neighbouring roots part ways (issue 12 notes it).
    static const test::Groomed unparted = test::groomed("long-straight", 120, 1200, 16, true);
    Hair hair = unparted.hair;
    hair.wisp.clear();
    HierarchyOptions o;
    o.strands_per_wisp = 20;
    const Hierarchy h = build_hierarchy(hair, o);
    expect_well_formed(h, hair);
    EXPECT_GE(h.level_size(1), (hair.strand_count() + 19) / 20);
    EXPECT_LE(h.level_size(1), hair.strand_count() / 10);
    // Bisection keeps clusters balanced, and a cluster's roots close together: measured on its
    // strands' roots themselves. (The GC's root radius encloses its sub-GCs, so it also grows
    // with how the cluster's strands are cut into sub-wisps by shape, which clumps change: a
    // sub-wisp of strands from two neighbouring clumps has its centre between them.)
    std::vector<Vec3f> centre(h.gc_count(), Vec3f::Zero());
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const uint32_t w = static_cast<uint32_t>(h.super[h.strand_gc[s]]);
        centre[w] += hair.strand(s)[0] / static_cast<float>(h.strand_count[w]);
    }
    std::vector<float> farthest(h.gc_count(), 0.f);
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const uint32_t w = static_cast<uint32_t>(h.super[h.strand_gc[s]]);
        farthest[w] = std::max(farthest[w], (hair.strand(s)[0] - centre[w]).norm());
    }
    // Short strands (baby hairs) are clustered apart, in the few wisps they fill.
    const std::vector<uint8_t> is_short = short_strands(hair);
    std::vector<uint8_t> short_gc(h.gc_count(), 0);
    for (size_t s = 0; s < hair.strand_count(); ++s)
        short_gc[static_cast<size_t>(h.super[h.strand_gc[s]])] = is_short[s];
    double mean = 0;
    for (uint32_t w = h.level_begin[1]; w < h.level_begin[2]; ++w) {
        if (!short_gc[w]) EXPECT_GT(h.strand_count[w], 10u);
        EXPECT_LE(h.strand_count[w], 20u);
        EXPECT_LT(farthest[w], 4.5f) << "wisp GC " << w;
        mean += farthest[w];
    }
    EXPECT_LT(mean / h.level_size(1), 3.0);
}

TEST(Hierarchy, DeterministicAtAnyThreadCount) {
    const test::Groomed& g = long_hair();
    Hair hair = g.hair;
    hair.wisp.clear();
    HierarchyOptions o;
    Hierarchy one, two;
    {
        ThreadLimit limit(1);
        one = build_hierarchy(hair, o);
    }
    {
        ThreadLimit limit(2);
        two = build_hierarchy(hair, o);
    }
    EXPECT_EQ(one.strand_gc, two.strand_gc);
    EXPECT_EQ(one.radius, two.radius);
    ASSERT_EQ(one.rest.size(), two.rest.size());
    for (size_t i = 0; i < one.rest.size(); ++i)
        ASSERT_EQ(one.rest[i], two.rest[i]);
}

TEST(Hierarchy, TiesHoldAPrefixOfEveryTiedGcAndGroupsDoNotMixTiedAndFree) {
    static const test::Groomed g = test::groomed("ponytail");
    ASSERT_FALSE(g.held.empty());
    // Every other wisp keeps its tie, so that groups could mix tied and free wisps.
    HierarchyOptions o = hierarchy_options(g.style.dynamics);
    o.wisp_held = g.held;
    for (size_t w = 1; w < o.wisp_held.size(); w += 2)
        o.wisp_held[w] = 0;
    const Hierarchy h = build_hierarchy(g.hair, o);
    expect_well_formed(h, g.hair);
    ASSERT_EQ(h.held.size(), h.node_count());
    const int n = h.sections;
    // The wisp id of each GC (through any of its strands) and whether it is tied.
    std::vector<int> wisp_of(h.gc_count(), -1);
    for (size_t s = 0; s < g.hair.strand_count(); ++s)
        for (int64_t c = h.strand_gc[s]; c >= 0; c = h.super[c])
            if (h.level[c] >= 1) wisp_of[c] = g.hair.wisp[s];
    size_t held_nodes = 0, tied_gcs = 0;
    for (uint32_t c = 0; c < h.gc_count(); ++c) {
        EXPECT_EQ(h.held[h.node(c, 0)], 1.f) << "the root of GC " << c;
        if (c >= h.finest_begin()) {
            const bool tied = o.wisp_held[wisp_of[c]] > 0;
            tied_gcs += tied;
            for (int k = 1; k < n; ++k) {
                const float held = h.held[h.node(c, k)];
                EXPECT_TRUE(held == 0.f || held == 1.f);
                if (!tied) {
                    EXPECT_EQ(held, 0.f) << "free GC " << c << " section " << k;
                }
                // Held from the root: a held section's parent section is held.
                if (held == 1.f) {
                    EXPECT_EQ(h.held[h.node(c, k - 1)], 1.f);
                }
                held_nodes += held == 1.f;
            }
            continue;
        }
        for (int k = 1; k < n; ++k) {
            double m = 0, held = 0;
            for (uint32_t s = h.child_begin[c]; s < h.child_begin[c] + h.child_count[c]; ++s) {
                m += h.mass[h.node(s, k)];
                held += h.mass[h.node(s, k)] * h.held[h.node(s, k)];
            }
            EXPECT_NEAR(h.held[h.node(c, k)], held / m, 1e-5) << "GC " << c << " section " << k;
        }
    }
    EXPECT_GT(tied_gcs, 0u);
    EXPECT_GT(held_nodes, 0u);
    // A top-level group is tied or free as a whole.
    for (uint32_t top = 0; top < h.level_size(0); ++top) {
        int tied = 0, free = 0;
        for (uint32_t w = h.child_begin[top]; w < h.child_begin[top] + h.child_count[top]; ++w)
            (o.wisp_held[wisp_of[w]] > 0 ? tied : free) += 1;
        EXPECT_TRUE(tied == 0 || free == 0)
            << "group " << top << ": " << tied << " tied, " << free << " free";
    }
    // Without holds, only the roots are held.
    const Hierarchy loose = build_hierarchy(g.hair, hierarchy_options(g.style.dynamics));
    for (uint32_t i = 0; i < loose.node_count(); ++i)
        EXPECT_EQ(loose.held[i], loose.section_of(i) == 0 ? 1.f : 0.f);
}

TEST(Hierarchy, ATieHoldsEveryStrandPassingNearItUpToItsNearestApproach) {
    Hair hair;
    // Straight down from y = 0, 30 cm: the tie at y = −10 is 1 cm off the first strand's
    // axis, 5 cm off the second's.
    hair.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, -8, 0}, {0, -16, 0}, {0, -30, 0}});
    hair.add_strand(std::vector<Vec3f>{{6, 0, 0}, {6, -30, 0}});
    const std::vector<Tie> one{{Vec3f(1, -10, 0), 2.f}};
    std::vector<float> held = held_lengths(hair, one);
    ASSERT_EQ(held.size(), 2u);
    EXPECT_NEAR(held[0], 10.f, 1e-4f);
    EXPECT_EQ(held[1], 0.f);
    // Several ties: the longest hold; a wider radius catches the second strand.
    const std::vector<Tie> two{{Vec3f(1, -10, 0), 2.f}, {Vec3f(0, -20, 0), 6.5f}};
    held = held_lengths(hair, two);
    EXPECT_NEAR(held[0], 20.f, 1e-4f);
    EXPECT_NEAR(held[1], 20.f, 1e-4f);
    EXPECT_THROW(held_lengths(hair, std::vector<Tie>{{Vec3f(0, NAN, 0), 2.f}}), Error);
    EXPECT_THROW(held_lengths(hair, std::vector<Tie>{{Vec3f::Zero(), 0.f}}), Error);
}

TEST(Hierarchy, StrandHoldsMakeWispsOfHeldAndFreeStrandsApart) {
    // Imported hair (no wisp ids) with every other strand held through half its length:
    // no wisp mixes held and free strands, and held GCs hold a prefix of their sections.
    Hair hair = long_hair().hair;
    hair.wisp.clear();
    HierarchyOptions o;
    o.strands_per_wisp = 20;
    o.strand_held.assign(hair.strand_count(), 0.f);
    for (size_t s = 0; s < hair.strand_count(); s += 2)
        o.strand_held[s] = 15.f;
    const Hierarchy h = build_hierarchy(hair, o);
    expect_well_formed(h, hair);
    std::vector<int> kind(h.gc_count(), -1);  // per wisp-level GC: 0 free, 1 held, 2 mixed
    const int wisp_level = h.levels - 2;
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        int64_t c = h.strand_gc[s];
        while (h.level[c] != wisp_level)
            c = h.super[c];
        const int k = o.strand_held[s] > 0;
        kind[c] = kind[c] < 0 || kind[c] == k ? k : 2;
    }
    size_t held_wisps = 0;
    for (uint32_t c = h.level_begin[wisp_level]; c < h.level_begin[wisp_level + 1]; ++c) {
        EXPECT_NE(kind[c], 2) << "wisp GC " << c << " mixes held and free strands";
        held_wisps += kind[c] == 1;
    }
    EXPECT_GT(held_wisps, 0u);
    size_t held_nodes = 0;
    for (uint32_t c = h.finest_begin(); c < h.gc_count(); ++c)
        for (int k = 1; k < h.sections; ++k) {
            if (h.held[h.node(c, k)] == 1.f) {
                EXPECT_EQ(h.held[h.node(c, k - 1)], 1.f);
            }
            held_nodes += h.held[h.node(c, k)] == 1.f;
        }
    EXPECT_GT(held_nodes, 0u);
    o.strand_held.pop_back();
    EXPECT_THROW(build_hierarchy(hair, o), Error);
    o.strand_held.assign(hair.strand_count(), -1.f);
    EXPECT_THROW(build_hierarchy(hair, o), Error);
}

TEST(Hierarchy, RejectsBadInput) {
    HierarchyOptions o;
    o.levels = 5;
    EXPECT_THROW(build_hierarchy(long_hair().hair, o), Error);
    o = HierarchyOptions{};
    o.sections = 2;
    EXPECT_THROW(build_hierarchy(long_hair().hair, o), Error);
    EXPECT_THROW(build_hierarchy(Hair{}, HierarchyOptions{}), Error);
    Hair one;
    one.add_strand(std::vector<Vec3f>{{0, 0, 0}});
    EXPECT_THROW(build_hierarchy(one, HierarchyOptions{}), Error);
    o = HierarchyOptions{};
    o.wisp_held = {1.f, -2.f};
    EXPECT_THROW(build_hierarchy(long_hair().hair, o), Error);
    o.wisp_held = {1.f, NAN};
    EXPECT_THROW(build_hierarchy(long_hair().hair, o), Error);
}

TEST(Skin, RestPoseIsReproducedExactly) {
    const test::Groomed& g = long_hair();
    const Hierarchy h = build_hierarchy(g.hair, HierarchyOptions{});
    const StrandBinding b = bind_strands(g.hair, h);
    std::vector<Mat3f> rotations((h.gc_count() - h.finest_begin()) * h.sections, Mat3f::Identity());
    Hair out = g.hair;
    for (Vec3f& p : out.points)
        p.setZero();
    skin_strands(h, b, h.rest, rotations, out);
    float worst = 0;
    for (size_t i = 0; i < out.points.size(); ++i)
        worst = std::max(worst, (out.points[i] - g.hair.points[i]).norm());
    EXPECT_LT(worst, 1e-4f);
}

TEST(Skin, ARigidMotionOfEveryNodeMovesTheStrandsRigidly) {
    const test::Groomed& g = long_hair();
    const Hierarchy h = build_hierarchy(g.hair, HierarchyOptions{});
    const StrandBinding b = bind_strands(g.hair, h);
    const Mat3f r = Eigen::AngleAxisf(0.7f, Vec3f(1, 2, 3).normalized()).toRotationMatrix();
    const Vec3f t(4, -2, 9);
    std::vector<Vec3f> nodes(h.rest.size());
    for (size_t i = 0; i < nodes.size(); ++i)
        nodes[i] = r * h.rest[i] + t;
    std::vector<Mat3f> rotations((h.gc_count() - h.finest_begin()) * h.sections, r);
    Hair out = g.hair;
    skin_strands(h, b, nodes, rotations, out);
    float worst = 0;
    for (size_t i = 0; i < out.points.size(); ++i)
        worst = std::max(worst, (out.points[i] - (r * g.hair.points[i] + t)).norm());
    EXPECT_LT(worst, 1e-3f);
}

}  // namespace
}  // namespace wisp
