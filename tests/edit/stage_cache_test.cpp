#include "edit/stage_cache.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

// A small style, quick to regenerate: a few thousand strands and the solver on.
Style small_style() {
    Style s = load_preset("default");
    s.wisps = 120;
    s.strands = 3000;
    s.points_per_strand = 16;
    return s;
}

void expect_same_hair(const Hair& a, const Hair& b) {
    ASSERT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_TRUE(std::equal(a.points.begin(), a.points.end(), b.points.begin()));
    EXPECT_EQ(a.widths, b.widths);
    ASSERT_EQ(a.colors.size(), b.colors.size());
    EXPECT_TRUE(std::equal(a.colors.begin(), a.colors.end(), b.colors.begin()));
    EXPECT_EQ(a.wisp, b.wisp);
    EXPECT_EQ(a.group, b.group);
    ASSERT_EQ(a.root_uv.size(), b.root_uv.size());
    EXPECT_TRUE(std::equal(a.root_uv.begin(), a.root_uv.end(), b.root_uv.begin()));
    ASSERT_EQ(a.root_normal.size(), b.root_normal.size());
    EXPECT_TRUE(std::equal(a.root_normal.begin(), a.root_normal.end(), b.root_normal.begin()));
}

// The stages run by a change: runs() after minus before, per stage.
std::array<int, kStageCount> delta(const std::array<int, kStageCount>& before,
                                   const std::array<int, kStageCount>& after) {
    std::array<int, kStageCount> d{};
    for (int s = 0; s < kStageCount; ++s)
        d[s] = after[s] - before[s];
    return d;
}

using Runs = std::array<int, kStageCount>;  // head, roots, masters, solve, members, color

TEST(StageCache, FirstUpdateRunsEveryStageAndMatchesGenerate) {
    StageCache cache(small_style());
    EXPECT_EQ(cache.stale(), Stage::kRoots);
    const HairstyleResult& r = cache.update();
    EXPECT_EQ(cache.runs(), (Runs{1, 1, 1, 1, 1, 1}));
    EXPECT_EQ(cache.stale(), Stage::kNone);
    expect_same_hair(r.hair, generate_hairstyle(cache.style(), cache.head()).hair);
    // Up to date: nothing runs again.
    cache.update();
    EXPECT_EQ(cache.runs(), (Runs{1, 1, 1, 1, 1, 1}));
}

// Each change re-runs exactly the stages from the one its field feeds, and the result is
// the hair a fresh generate gives for the changed style, byte for byte.
TEST(StageCache, EachChangeRerunsExactlyItsStagesAndMatchesAFreshGenerate) {
    struct Change {
        const char* path;
        const char* value;
        Runs runs;
    };
    const Change changes[] = {
        {"color.wisp_hue", "4", {0, 0, 0, 0, 0, 1}},
        {"color.preset", "\"auburn\"", {0, 0, 0, 0, 0, 1}},
        {"solve.stiffness", "0.4", {0, 0, 0, 1, 1, 1}},
        {"solve.threshold", "0.3", {0, 0, 0, 1, 1, 1}},
        {"wisp.fuzziness", "0.8", {0, 0, 0, 0, 1, 1}},
        {"strand.tip_width", "0.004", {0, 0, 0, 0, 1, 1}},
        {"cut.enabled", "true", {0, 0, 0, 0, 1, 1}},
        {"wisp.deviation_radius", "[1, 2]", {0, 0, 0, 1, 1, 1}},
        {"prototype.shape", "\"curly\"", {0, 0, 1, 1, 1, 1}},
        {"maps.length", "{ procedural = \"nape-short\", low = 10, high = 30 }", {0, 0, 1, 1, 1, 1}},
        {"maps.density", "\"crown\"", {0, 1, 1, 1, 1, 1}},
        {"seed", "9", {0, 1, 1, 1, 1, 1}},
        {"dynamics.dt", "0.005", {0, 0, 0, 0, 0, 0}},
        {"name", "\"renamed\"", {0, 0, 0, 0, 0, 0}},
        {"head.scalp.front", "6", {1, 1, 1, 1, 1, 1}},
    };
    StageCache cache(small_style());
    cache.update();
    for (const Change& c : changes) {
        SCOPED_TRACE(std::string(c.path) + " = " + c.value);
        const Runs before = cache.runs();
        cache.set(c.path, c.value);
        const HairstyleResult& r = cache.update();
        EXPECT_EQ(delta(before, cache.runs()), c.runs);
        expect_same_hair(r.hair, generate_hairstyle(cache.style(), cache.head()).hair);
    }
}

TEST(StageCache, SameValueRunsNothingAndSolveCellRebuildsTheHeadField) {
    StageCache cache(small_style());
    cache.update();
    const Runs before = cache.runs();
    cache.set("solve.stiffness", "0.6");  // the default preset's κ: no change
    EXPECT_EQ(cache.stale(), Stage::kNone);
    cache.update();
    EXPECT_EQ(cache.runs(), before);
    EXPECT_EQ(cache.head_field_runs(), 1);
    cache.set("solve.cell", "0.8");  // the head field's cell: 0.6 cm, from 0.75
    cache.update();
    EXPECT_EQ(cache.head_field_runs(), 2);
    cache.set("solve.stiffness", "2");
    cache.update();
    EXPECT_EQ(cache.head_field_runs(), 2);  // the same cell: kept
}

TEST(StageCache, MastersAloneRunOnlyUpToTheSolve) {
    StageCache cache(small_style());
    cache.update();
    cache.set("solve.stiffness", "0.5");
    const Masters& m = cache.update_masters();
    EXPECT_EQ(cache.runs(), (Runs{1, 1, 1, 2, 1, 1}));
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    EXPECT_EQ(m.count(), 120u);
    cache.update();
    EXPECT_EQ(cache.runs(), (Runs{1, 1, 1, 2, 2, 2}));
}

TEST(StageCache, BadValuesLeaveTheStyleAndCacheAsTheyWere) {
    StageCache cache(small_style());
    cache.update();
    const Runs before = cache.runs();
    try {
        cache.set("solve.threshold", "0", "request");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "request: field 'solve.threshold': must be > 0, got 0");
    }
    EXPECT_EQ(cache.style().solve.threshold, small_style().solve.threshold);
    EXPECT_EQ(cache.stale(), Stage::kNone);
    // A value the reader accepts but a stage cannot use (a missing map image) fails in the
    // stage, which stays stale until fixed.
    cache.set("maps.length", "{ image = \"/nonexistent/len.png\" }");
    EXPECT_THROW(cache.update(), Error);
    EXPECT_EQ(cache.stale(), Stage::kMasters);
    cache.set("maps.length", "20");
    cache.update();
    EXPECT_EQ(cache.stale(), Stage::kNone);
    EXPECT_EQ(delta(before, cache.runs()), (Runs{0, 0, 1, 1, 1, 1}));
}

TEST(StageCache, SetStyleRerunsFromTheFirstDifference) {
    StageCache cache(small_style());
    cache.update();
    Style next = cache.style();
    next.color.wisp_value = 0.05f;
    next.solve.stiffness = 0.7f;
    const Runs before = cache.runs();
    cache.set_style(next);
    EXPECT_EQ(cache.stale(), Stage::kSolve);
    cache.update();
    EXPECT_EQ(delta(before, cache.runs()), (Runs{0, 0, 0, 1, 1, 1}));
    // Groups feed the solve, and the strands carry their group.
    next.groups = load_preset("ponytail").groups;
    cache.set_style(next);
    EXPECT_EQ(cache.stale(), Stage::kSolve);
    const HairstyleResult& r = cache.update();
    const HairstyleResult fresh = generate_hairstyle(cache.style(), cache.head());
    expect_same_hair(r.hair, fresh.hair);
    EXPECT_EQ(r.wisp_group, fresh.wisp_group);
    EXPECT_GT(std::count(r.hair.group.begin(), r.hair.group.end(), 1), 0);
}

}  // namespace
}  // namespace wisp
