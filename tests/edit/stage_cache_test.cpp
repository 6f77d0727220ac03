#include "edit/stage_cache.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <string>

#include "edit/wire.hpp"

#include "core/error.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

// A small style, quick to regenerate: a few thousand strands and the solver on. Uncut, so
// that a preview's strands are the full hair's by index (a cut removes strands).
Style small_style() {
    Style s = load_preset("default");
    s.cut.enabled = false;
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

// Stale work is cancelled (issue 16): a newer request bumps the counter while a stage runs
// (here: as it starts, through the progress callback), the run returns null, publishes
// nothing from the stage it stopped in, and the next update gives the hair of a fresh
// generate, byte for byte.
TEST(StageCache, ACancelledUpdateLeavesTheCacheConsistentAndTheNextOneMatchesGenerate) {
    const Stage stops[] = {Stage::kRoots, Stage::kMasters, Stage::kSolve, Stage::kMembers,
                           Stage::kColor};
    for (const Stage stop : stops) {
        SCOPED_TRACE(stage_name(stop));
        StageCache cache(small_style());
        cache.update();
        // A change that re-runs every stage from the roots.
        cache.set("maps.density", "{ procedural = \"crown\", low = 0.5, high = 1 }");
        std::atomic<uint64_t> newest{1};
        const CancelToken token(newest, 1);
        const Runs before = cache.runs();
        const HairstyleResult* r = cache.update(token, [&](Stage s) {
            if (s == stop) ++newest;  // a newer request arrives while `stop` runs
        });
        EXPECT_EQ(r, nullptr);
        // The stages before `stop` finished and stay done; `stop` and those after did not run
        // to the end (a stage is counted when it publishes).
        EXPECT_EQ(cache.stale(), stop);
        const Runs after = cache.runs();
        for (int s = int(Stage::kRoots); s < kStageCount; ++s)
            EXPECT_EQ(after[s] - before[s], s < int(stop) ? 1 : 0) << stage_name(Stage(s));
        const HairstyleResult& next = cache.update();
        EXPECT_EQ(cache.stale(), Stage::kNone);
        const HairstyleResult fresh = generate_hairstyle(cache.style(), cache.head());
        expect_same_hair(next.hair, fresh.hair);
        EXPECT_EQ(next.masters.control, fresh.masters.control);
    }
}

// A map stroke synthesizes the masters' details beside the solve (solve_synthesizing): a solve
// cancelled half way through its layers still leaves whole masters, so the update that
// follows (from the solve) gives the bytes of a fresh generate, masters and hair.
TEST(StageCache, ASolveCancelledWhileTheDetailsAreSynthesizedLeavesWholeMasters) {
    StageCache cache(small_style());
    cache.update();
    cache.set("maps.density", "{ procedural = \"crown\", low = 0.5, high = 1 }");
    std::atomic<uint64_t> newest{1};
    const FractionReport halfway = [&](float f) {
        if (f >= 0.5f) newest = 2;
    };
    const Runs before = cache.runs();
    EXPECT_EQ(cache.update(CancelToken(newest, 1, &halfway)), nullptr);
    EXPECT_EQ(cache.stale(), Stage::kSolve);
    EXPECT_EQ(delta(before, cache.runs()), (Runs{0, 1, 1, 0, 0, 0}));
    const HairstyleResult& next = cache.update();
    const HairstyleResult fresh = generate_hairstyle(cache.style(), cache.head());
    expect_same_hair(next.hair, fresh.hair);
    EXPECT_EQ(next.masters.control, fresh.masters.control);
    EXPECT_EQ(next.masters.frames.size(), fresh.masters.frames.size());
    EXPECT_TRUE(std::equal(
        next.masters.frames.begin(), next.masters.frames.end(), fresh.masters.frames.begin(),
        [](const Frame& a, const Frame& b) { return a.t == b.t && a.n == b.n && a.b == b.b; }));
}

// The solver polls the token between layers of joints: a solve cancelled part way is dropped,
// and the masters the cache hands out are those of a finished solve.
TEST(StageCache, ACancelledSolveLeavesTheLastSolvedMastersAlone) {
    StageCache cache(small_style());
    const std::vector<Vec3f> solved = cache.update_masters().control;
    cache.set("solve.stiffness", "3");
    std::atomic<uint64_t> newest{7};
    EXPECT_EQ(cache.update_masters(CancelToken(newest, 6)), nullptr);  // already overtaken
    EXPECT_EQ(cache.stale(), Stage::kSolve);
    const Masters* m = cache.update_masters(CancelToken(newest, 7));
    ASSERT_NE(m, nullptr);
    EXPECT_NE(m->control, solved);
    EXPECT_EQ(cache.stale(), Stage::kMembers);
}

// While a value moves the editor shows a subset: strand i of the preview is strand
// strand_order[i] of the full hair, exactly (no cut here, so the colours match too), and the
// full update that follows re-runs only the members and the colour.
TEST(StageCache, PreviewIsTheShuffledSubsetOfTheFullHair) {
    StageCache cache(small_style());
    cache.update();
    cache.set("solve.stiffness", "0.3");
    const Hair* preview = cache.update_preview(500);
    ASSERT_NE(preview, nullptr);
    ASSERT_EQ(preview->strand_count(), 500u);
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    const Runs before = cache.runs();
    const Hair& full = cache.update().hair;
    EXPECT_EQ(delta(before, cache.runs()), (Runs{0, 0, 0, 0, 1, 1}));
    expect_same_hair(full, generate_hairstyle(cache.style(), cache.head()).hair);
    const std::vector<uint32_t> order = strand_order(full.strand_count());
    for (size_t i = 0; i < 500; ++i) {
        const auto a = preview->strand(i), b = full.strand(order[i]);
        ASSERT_EQ(a.size(), b.size()) << i;
        EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin())) << i;
        EXPECT_EQ(preview->colors[i], full.colors[order[i]]) << i;
        EXPECT_EQ(preview->wisp[i], full.wisp[order[i]]) << i;
    }
    // Up to date: the preview is the full hair.
    EXPECT_EQ(cache.update_preview(500), &cache.update().hair);
}

// A preview's colours are made beside the solve, from the roots alone (a strand's id and
// wisp): after a change that moves the roots (so the strands change wisps) and after one that
// re-runs the solve only, they are the full hair's colours of the same strands, to the bit,
// with each wisp's own hue offset.
TEST(StageCache, PreviewColoursMadeBesideTheSolveAreTheFullHairs) {
    Style style = small_style();
    style.color.wisp_hue = 6.f;
    StageCache cache(style);
    cache.update();
    for (const auto& [path, value] :
         {std::pair{"maps.density", "\"crown\""}, std::pair{"solve.stiffness", "0.4"},
          std::pair{"seed", "11"}}) {
        cache.set(path, value);
        const Hair* preview = cache.update_preview(700);
        ASSERT_NE(preview, nullptr) << path;
        ASSERT_EQ(preview->colors.size(), 700u) << path;
        const std::vector<Vec3f> colors = preview->colors;
        const std::vector<int32_t> wisps = preview->wisp;
        const Hair& full = cache.update().hair;
        const std::vector<uint32_t> order = strand_order(full.strand_count());
        for (size_t i = 0; i < 700; ++i) {
            ASSERT_EQ(wisps[i], full.wisp[order[i]]) << path << " " << i;
            ASSERT_EQ(colors[i], full.colors[order[i]]) << path << " " << i;
        }
    }
}

// A preview's members grow beside the solve, band by band as its layers make the masters'
// joints final: after a map stroke (whose masters' details are synthesized beside the solve
// too), a κ change and a seed change, the preview is the full hair's strands, to the bit. With
// a cut too (it cuts the whole strands after the last band): turning it on re-runs only the
// members, the κ change after it grows them beside the solve.
TEST(StageCache, PreviewMembersGrownBesideTheSolveAreTheFullHairs) {
    Style style = small_style();
    StageCache cache(style);
    cache.update();
    int beside = cache.members_grown_beside();
    bool cut = false;
    for (const auto& [path, value] :
         {std::pair{"maps.density", "\"crown\""}, std::pair{"solve.stiffness", "0.4"},
          std::pair{"seed", "11"}, std::pair{"cut.enabled", "true"},
          std::pair{"solve.stiffness", "0.45"}}) {
        const bool solves = std::string(path) != "cut.enabled";
        cut = cut || !solves;
        cache.set(path, value);
        const Hair* preview = cache.update_preview(700);
        ASSERT_NE(preview, nullptr) << path;
        EXPECT_EQ(cache.members_grown_beside(), beside += solves) << path;
        const Hair copy = *preview;
        const Hair& full = cache.update().hair;  // its members grown after the solve
        EXPECT_EQ(cache.members_grown_beside(), beside) << path;
        expect_same_hair(full, generate_hairstyle(cache.style(), cache.head()).hair);
        if (cut) continue;  // the cut removes strands, so the preview's are shifted
        const std::vector<uint32_t> order = strand_order(full.strand_count());
        ASSERT_EQ(copy.strand_count(), 700u) << path;
        for (size_t i = 0; i < 700; ++i) {
            const auto a = copy.strand(i), b = full.strand(order[i]);
            ASSERT_EQ(a.size(), b.size()) << path << " " << i;
            ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin())) << path << " " << i;
            ASSERT_EQ(copy.group[i], full.group[order[i]]) << path << " " << i;
        }
    }
}

// An update that goes on to the members grows the whole hair's beside the solve (the release
// after a κ drag, a map stroke's full answer): the same hair as generate gives, to the bit,
// with a cut too (turning it on re-runs only the members, after the solve).
TEST(StageCache, WholeHairGrownBesideTheSolveIsGeneratesHair) {
    StageCache cache(small_style());
    cache.update();
    int beside = cache.members_grown_beside();
    for (const auto& [path, value] :
         {std::pair{"solve.stiffness", "0.4"}, std::pair{"maps.density", "\"crown\""},
          std::pair{"cut.enabled", "true"}, std::pair{"solve.stiffness", "0.45"}}) {
        const bool solves = std::string(path) != "cut.enabled";
        cache.set(path, value);
        const Hair& hair = cache.update().hair;
        EXPECT_EQ(cache.members_grown_beside(), beside += solves) << path;
        expect_same_hair(hair, generate_hairstyle(cache.style(), cache.head()).hair);
    }
    cache.set("cut.enabled", "false");
    cache.set("solve.stiffness", "0.5");
    ASSERT_NE(cache.hair_bytes(SIZE_MAX), nullptr);  // all strands asked for: the whole hair
    EXPECT_EQ(cache.members_grown_beside(), beside + 1);
    expect_same_hair(cache.update().hair, generate_hairstyle(cache.style(), cache.head()).hair);
}

// What GET /api/hair sends is the encoding of the full hair's first strands in strand_order,
// byte for byte, whatever the answer left out: a colour change colours only the strands sent
// (over positions encoded before) and leaves the colour stage to the update; a κ change grows
// only the strands sent. A buffer still held is never written into.
TEST(StageCache, HairBytesAreTheFullHairsEncodingWhateverTheyLeaveOut) {
    StageCache cache(small_style());
    cache.update();
    const auto full = [&](size_t n) { return encode_strands(cache.update().hair, n); };
    std::shared_ptr<const std::string> held = cache.hair_bytes(500);
    EXPECT_EQ(*held, full(500));
    const std::string was = *held;

    cache.set("color.wisp_hue", "4");
    Runs before = cache.runs();
    std::shared_ptr<const std::string> bytes = cache.hair_bytes(500);
    EXPECT_EQ(cache.runs(), before);  // no stage ran: 500 colours only
    EXPECT_EQ(cache.stale(), Stage::kColor);
    EXPECT_NE(bytes, held);
    EXPECT_EQ(*held, was);  // the held buffer is as it was sent
    std::string sent = *bytes;
    EXPECT_NE(sent, was);  // the colours moved
    EXPECT_EQ(sent, full(500));
    held.reset();
    bytes.reset();

    // The positions are kept: the buffer of the last answer is written over in place.
    const std::string* memory = cache.hair_bytes(500).get();
    cache.set("color.wisp_hue", "1");
    bytes = cache.hair_bytes(500);
    EXPECT_EQ(bytes.get(), memory);
    sent = *bytes;
    bytes.reset();
    EXPECT_EQ(sent, full(500));

    cache.set("solve.stiffness", "0.3");
    before = cache.runs();
    sent = *cache.hair_bytes(500);
    EXPECT_EQ(delta(before, cache.runs()), (Runs{0, 0, 0, 1, 0, 0}));  // 500 strands grown
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    EXPECT_EQ(sent, full(500));

    cache.set("color.wisp_hue", "2");
    sent = *cache.hair_bytes(SIZE_MAX);
    EXPECT_EQ(cache.stale(), Stage::kNone);
    EXPECT_EQ(sent, encode_strands(generate_hairstyle(cache.style(), cache.head()).hair, SIZE_MAX));
}

// While κ moves, each preview answer is written into the last one's buffer once the caller
// let it go (sparing 7.5 MB cleared and faulted in on one thread per answer at 20,000
// strands), never into one still held; every answer is the full hair's encoding.
TEST(StageCache, APreviewAnswerReusesTheLastBufferOnlyOnceItIsLetGo) {
    StageCache cache(small_style());
    cache.update();
    const auto full = [&](size_t n) { return encode_strands(cache.update().hair, n); };
    cache.set("solve.stiffness", "0.3");
    std::shared_ptr<const std::string> held = cache.hair_bytes(500);
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    const std::string was = *held;
    EXPECT_EQ(was, full(500));

    cache.set("solve.stiffness", "0.9");
    std::shared_ptr<const std::string> bytes = cache.hair_bytes(500);
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    EXPECT_NE(bytes, held);
    EXPECT_EQ(*held, was);  // the held buffer is as it was sent
    const std::string* memory = bytes.get();
    std::string sent = *bytes;
    EXPECT_NE(sent, was);  // κ moved the strands
    held.reset();
    bytes.reset();
    EXPECT_EQ(sent, full(500));

    cache.set("solve.stiffness", "0.3");
    bytes = cache.hair_bytes(500);
    EXPECT_EQ(cache.stale(), Stage::kMembers);
    EXPECT_EQ(bytes.get(), memory);  // let go: written over
    sent = *bytes;
    bytes.reset();
    EXPECT_EQ(sent, was);
    EXPECT_EQ(sent, full(500));
}

// While κ moves, the masters preview solves every k-th wisp only; it leaves the cache's
// stages alone, so the update after it solves exactly and equals a fresh generate.
TEST(StageCache, CoarseMastersPreviewLeavesTheExactSolveToTheUpdate) {
    Style style = small_style();
    style.wisps = 1500;  // more than kPreviewWisps: every 3rd wisp
    StageCache cache(style);
    cache.update();
    cache.set("solve.stiffness", "1.5");
    const Runs before = cache.runs();
    const Masters* coarse = cache.update_masters_preview();
    ASSERT_NE(coarse, nullptr);
    EXPECT_EQ(coarse->count(), 500u);
    EXPECT_EQ(cache.stale(), Stage::kSolve);
    EXPECT_EQ(cache.runs(), before);
    const HairstyleResult& r = cache.update();
    const HairstyleResult fresh = generate_hairstyle(cache.style(), cache.head());
    expect_same_hair(r.hair, fresh.hair);
    // The coarse masters are the exact ones' neighbours, not a different hairstyle: wisp i
    // of the preview (wisp 3i) ends near where the exact solve puts it.
    double sum = 0;
    for (size_t i = 0; i < coarse->count(); ++i)
        sum += (coarse->strand(i).back() - r.masters.strand(3 * i).back()).norm();
    EXPECT_LT(sum / double(coarse->count()), 3.0);  // cm, over hair 24–30 cm long
    // Up to date: the preview is the solved masters.
    EXPECT_EQ(cache.update_masters_preview(), &cache.update_masters());
}

// κ and τ leave the styling field as it was: it is built once and kept.
TEST(StageCache, StiffnessKeepsTheStylingField) {
    StageCache cache(small_style());
    cache.update();
    EXPECT_EQ(cache.styling_field_runs(), 1);
    cache.set("solve.stiffness", "0.9");
    cache.set("solve.threshold", "0.4");
    cache.update();
    EXPECT_EQ(cache.styling_field_runs(), 1);
    cache.set("growth.part", "\"left\"");
    const HairstyleResult& r = cache.update();
    EXPECT_EQ(cache.styling_field_runs(), 2);
    expect_same_hair(r.hair, generate_hairstyle(cache.style(), cache.head()).hair);
}

}  // namespace
}  // namespace wisp
