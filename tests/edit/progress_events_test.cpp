#include "edit/progress_events.hpp"

#include <gtest/gtest.h>

#include <thread>

#include <nlohmann/json.hpp>

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

}  // namespace
}  // namespace wisp
