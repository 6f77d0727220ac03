#include "edit/progress_events.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "groom/style_toml.hpp"

namespace wisp {
namespace {

using std::chrono::milliseconds;

TEST(ProgressEvents, ATaskPostsItsStagesThenFinishes) {
    ProgressEvents events;
    const uint64_t start = events.last_id();
    {
        ProgressEvents::Task task(events, "export", 3);
        const StageProgress stages = task.stages();
        stages(Stage::kMembers);
        stages(Stage::kColor);
        task.step("write");
    }
    const std::deque<ProgressEvent> got = events.wait(start, milliseconds(0));
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[0].step, "members");
    EXPECT_EQ(got[0].done, 0);
    EXPECT_EQ(got[1].step, "color");
    EXPECT_EQ(got[2].step, "write");
    EXPECT_EQ(got[2].done, 2);
    EXPECT_TRUE(got[3].finished);
    EXPECT_EQ(got[3].done, 3);
    EXPECT_EQ(got[3].total, 3);
    EXPECT_TRUE(got[3].error.empty());
    for (size_t i = 0; i < got.size(); ++i)
        EXPECT_EQ(got[i].id, start + 1 + i);
}

TEST(ProgressEvents, ATaskEndedByAnExceptionSaysItFailed) {
    ProgressEvents events;
    try {
        ProgressEvents::Task task(events, "render", 2);
        task.step("solve");
        throw std::runtime_error("no");
    } catch (const std::runtime_error&) {
    }
    const std::deque<ProgressEvent> got = events.wait(0, milliseconds(0));
    ASSERT_EQ(got.size(), 2u);
    EXPECT_TRUE(got[1].finished);
    EXPECT_EQ(got[1].step, "failed");
    EXPECT_FALSE(got[1].error.empty());
}

TEST(ProgressEvents, AFrameIsOneEventOfOneLineOfJson) {
    ProgressEvent e;
    e.id = 7;
    e.task = "update";
    e.step = "solve";
    e.done = 3;
    e.total = 6;
    e.error = "line one\nline two";
    const std::string frame = ProgressEvents::frame(e);
    EXPECT_EQ(frame.rfind("id: 7\nevent: progress\ndata: ", 0), 0u) << frame;
    EXPECT_EQ(frame.substr(frame.size() - 2), "\n\n");
    // Only the field separators are newlines: the data is one line.
    const size_t data = frame.find("data: ") + 6;
    const std::string json = frame.substr(data, frame.size() - 2 - data);
    EXPECT_EQ(json.find('\n'), std::string::npos);
    const nlohmann::json j = nlohmann::json::parse(json);
    EXPECT_EQ(j["step"], "solve");
    EXPECT_EQ(j["error"], "line one\nline two");
}

TEST(ProgressEvents, AListenerWakesOnAPostAndOnClose) {
    ProgressEvents events;
    std::thread poster([&] {
        std::this_thread::sleep_for(milliseconds(50));
        ProgressEvents::Task(events, "update", 1).step("solve");
    });
    const std::deque<ProgressEvent> got = events.wait(0, milliseconds(10'000));
    poster.join();
    ASSERT_FALSE(got.empty());
    EXPECT_EQ(got.front().step, "solve");
    // Only the newest kKept events are kept for a listener far behind.
    for (size_t i = 0; i < 2 * ProgressEvents::kKept; ++i)
        events.post({});
    EXPECT_EQ(events.wait(0, milliseconds(0)).size(), ProgressEvents::kKept);
    std::thread closer([&] {
        std::this_thread::sleep_for(milliseconds(50));
        events.close();
    });
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_TRUE(events.wait(events.last_id(), milliseconds(10'000)).empty());
    EXPECT_LT(std::chrono::steady_clock::now() - t0, milliseconds(5'000));
    closer.join();
    EXPECT_TRUE(events.closed());
}

// The fractions posted for `step` in `got`, in order.
std::vector<float> fractions_of(const std::deque<ProgressEvent>& got, const std::string& step) {
    std::vector<float> out;
    for (const ProgressEvent& e : got)
        if (!e.finished && e.step == step && e.fraction > 0.f) out.push_back(e.fraction);
    return out;
}

// A solve of many layers reports its fraction done as it goes (issue 16: the bar moves
// inside a long stage), rising to 1, under the step it belongs to; so do the members.
TEST(ProgressEvents, ALongSolveSendsRisingFractionsEndingAtOne) {
    Style style = load_preset("default");
    style.wisps = 300;
    style.strands = 3000;
    style.points_per_strand = 40;
    StageCache cache(style);
    ProgressEvents events;
    {
        // Every report posted (no throttle), to see each one.
        ProgressEvents::Task task(events, "update", kStageCount, milliseconds(0));
        ASSERT_NE(cache.update_masters(CancelToken(task.fractions()), task.stages()), nullptr);
    }
    std::deque<ProgressEvent> got = events.wait(0, milliseconds(0));
    std::vector<float> solve = fractions_of(got, "solve");
    ASSERT_EQ(solve.size(), 39u) << "one per layer of joints";
    for (size_t i = 1; i < solve.size(); ++i)
        EXPECT_GT(solve[i], solve[i - 1]);
    EXPECT_EQ(solve.back(), 1.f);
    // Each under the solve's step: its number as the step started.
    const auto start = std::find_if(got.begin(), got.end(), [](const ProgressEvent& e) {
        return e.step == "solve" && e.fraction == 0.f;
    });
    ASSERT_NE(start, got.end());
    for (const ProgressEvent& e : got) {
        if (e.step == "solve") {
            EXPECT_EQ(e.done, start->done);
        }
    }
    // The members, from the workers of a parallel loop: still rising, ending at 1.
    const uint64_t seen = events.last_id();
    {
        ProgressEvents::Task task(events, "update", 2, milliseconds(0));
        ASSERT_NE(cache.update(CancelToken(task.fractions()), task.stages()), nullptr);
    }
    got = events.wait(seen, milliseconds(0));
    const std::vector<float> members = fractions_of(got, "members");
    ASSERT_GE(members.size(), 2u);
    for (size_t i = 1; i < members.size(); ++i)
        EXPECT_GT(members[i], members[i - 1]);
    EXPECT_EQ(members.back(), 1.f);
}

// Fractions are posted at most every kFractionInterval, except the last (1), and only when
// they rise: reports from several workers come out of order.
TEST(ProgressEvents, FractionsAreThrottledAndOnlyRise) {
    ProgressEvents events;
    {
        ProgressEvents::Task task(events, "update", 1, milliseconds(60'000));
        const FractionReport& report = *task.fractions();
        report(0.5f);  // before any step: nothing to belong to
        task.step("solve");
        for (const float f : {0.1f, 0.2f, 0.3f, 1.f, 0.9f})
            report(f);
    }
    const std::deque<ProgressEvent> got = events.wait(0, milliseconds(0));
    ASSERT_EQ(got.size(), 3u);  // the step, its 1, finished
    EXPECT_EQ(got[1].fraction, 1.f);
    EXPECT_EQ(got[1].step, "solve");
    EXPECT_TRUE(got[2].finished);
    ProgressEvents quick;
    {
        ProgressEvents::Task task(quick, "update", 1, milliseconds(0));
        task.step("members");
        for (const float f : {0.25f, 0.5f, 0.375f, 0.75f})
            (*task.fractions())(f);
    }
    EXPECT_EQ(fractions_of(quick.wait(0, milliseconds(0)), "members"),
              (std::vector<float>{0.25f, 0.5f, 0.75f}));
}

}  // namespace
}  // namespace wisp
