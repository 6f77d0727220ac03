// The per-strand root data generation leaves in Hair (root UV, root normal, group) and the
// guide strands made from the masters: what the exporters write for Unreal and numpy.
#include <gtest/gtest.h>

#include <set>

#include "groom/generate.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

TEST(RootData, GeneratedHairKnowsItsRootsAndGroups) {
    Style style = load_preset("braid");
    ASSERT_FALSE(style.groups.empty());
    style.strands = 2000;
    style.wisps = 100;
    static const Head head = load_head(HeadSpec{});
    const HairstyleResult r = generate_hairstyle(style, head);
    const Hair& h = r.hair;
    ASSERT_NO_THROW(h.validate("braid"));
    ASSERT_EQ(h.root_uv.size(), h.strand_count());
    ASSERT_EQ(h.root_normal.size(), h.strand_count());
    ASSERT_EQ(h.group.size(), h.strand_count());
    std::set<int32_t> groups;
    for (size_t s = 0; s < h.strand_count(); ++s) {
        // The root stays where it grew: its UV is the scalp UV of the strand's first point.
        EXPECT_LT((head.scalp->uv_of(h.strand(s)[0]) - h.root_uv[s]).norm(), 1e-3f) << s;
        EXPECT_NEAR(h.root_normal[s].norm(), 1.f, 1e-4f);
        EXPECT_GT(h.root_normal[s].dot(h.strand(s)[0] - head.scalp->center()), 0.f) << s;
        EXPECT_EQ(h.group[s], r.wisp_group[size_t(h.wisp[s])]);
        groups.insert(h.group[s]);
        EXPECT_LE(h.group[s], int32_t(style.groups.size()));
    }
    EXPECT_GE(groups.size(), 3u) << "the braid's plaits are groups of their own";
    // The guides: one per master, carrying its wisp's group and root.
    const Hair g = guide_strands(r.masters, r.wisp_group, style.root_width);
    ASSERT_NO_THROW(g.validate("guides"));
    ASSERT_EQ(g.strand_count(), r.masters.count());
    for (size_t w = 0; w < g.strand_count(); ++w) {
        EXPECT_EQ(g.strand_size(w), uint32_t(style.points_per_strand));
        EXPECT_EQ(g.wisp[w], int32_t(w));
        EXPECT_EQ(g.group[w], r.wisp_group[w]);
        EXPECT_LT((g.strand(w)[0] - r.masters.roots[w].position).norm(), 1e-4f);
    }
}

TEST(RootData, NoGroupsMeansGroupZero) {
    Style style = load_preset("default");
    style.strands = 500;
    style.wisps = 40;
    style.groups.clear();
    static const Head head = load_head(HeadSpec{});
    const HairstyleResult r = generate_hairstyle(style, head);
    for (int32_t g : r.hair.group)
        EXPECT_EQ(g, 0);
}

}  // namespace
}  // namespace wisp
