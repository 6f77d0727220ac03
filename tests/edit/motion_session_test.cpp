// The editor's live motion session (issue 17): its own thread, input at frame boundaries,
// the newest frame for the browser, and a recording that `wisp animate` replays exactly.
#include "edit/motion_session.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "core/error.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

struct Small {
    Style style;
    Head head;
    HairstyleResult result;
    HeadFrame frame;
};

const Small& small() {
    static const Small s = [] {
        Small s;
        s.style = load_preset("long-straight");
        s.style.wisps = 60;
        s.style.strands = 600;
        s.style.points_per_strand = 12;
        s.head = load_head(HeadSpec{});
        s.result = generate_hairstyle(s.style, s.head);
        s.frame = head_frame(*s.head.scalp);
        return s;
    }();
    return s;
}

std::unique_ptr<MotionSession> session(size_t shown = 200) {
    const Small& s = small();
    MotionSessionSettings settings;
    settings.shown_strands = shown;
    settings.wisp_held = s.result.solve.held_length;
    return std::make_unique<MotionSession>(s.result.hair, *s.head.mesh, s.frame, s.style.dynamics,
                                           s.style.prototype.kind, settings);
}

std::vector<Vec3f> positions(const MotionFrame& frame) {
    std::vector<Vec3f> out((frame.bytes.size() - 20) / 12);
    for (size_t i = 0; i < out.size(); ++i)
        std::memcpy(out[i].data(), frame.bytes.data() + 20 + 12 * i, 12);
    return out;
}

TEST(MotionSession, StartsPausedAtRestAndStepsOneFrame) {
    auto live = session();
    const auto first = live->frame_after(std::nullopt, 0);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->index, 0u);
    EXPECT_FALSE(live->frame_after(0u, 50));  // paused: nothing new
    live->drag(Vec3f(0, 40, 0), Vec3f::Zero());
    for (int i = 0; i < 6; ++i)
        live->step();
    const auto sixth = live->frame_after(0u, 0);
    ASSERT_TRUE(sixth);
    EXPECT_EQ(sixth->index, 6u);
    // The head turned 40° about the vertical: the roots moved.
    const std::vector<Vec3f> a = positions(*first), b = positions(*sixth);
    EXPECT_GT((a[0] - b[0]).norm(), 0.5f);
    EXPECT_THROW(live->drag(Vec3f(std::nanf(""), 0, 0), Vec3f::Zero()), Error);
    EXPECT_THROW(live->play_preset("moonwalk"), Error);
    EXPECT_THROW(live->set_wind(Vec3f(1e9f, 0, 0)), Error);
}

// Played in real time with input arriving whenever it does, then replayed from the
// recording as `wisp animate --motion` does: the frames the browser saw, byte for byte.
TEST(MotionSession, RecordingReplaysTheFramesTheBrowserSaw) {
    auto live = session();
    live->play();
    std::vector<MotionFrame> seen;
    std::optional<uint32_t> last;
    const auto watch = [&](int ms) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
        while (std::chrono::steady_clock::now() < end)
            if (auto f = live->frame_after(last, 20)) {
                last = f->index;
                seen.push_back(std::move(*f));
            }
    };
    watch(150);
    for (int i = 0; i < 8; ++i) {
        live->drag(Vec3f(10.f * std::sin(0.7f * i), 30.f * std::sin(0.4f * i), 0),
                   Vec3f(0, 0, 2.f * std::sin(0.5f * i)));
        watch(45);
    }
    live->play_preset("shake");
    watch(300);
    live->pause();
    watch(100);
    ASSERT_TRUE(live->error().empty()) << live->error();
    ASSERT_GT(seen.size(), 5u);

    const auto path = std::filesystem::temp_directory_path() / "wisp_session_recording.json";
    live->write_recording(path);
    const Small& s = small();
    const Motion replay = read_motion(path, s.frame);
    std::filesystem::remove(path);
    AnimateSettings settings;
    settings.frames = static_cast<int>(live->frames_published());
    settings.fps = 25;
    settings.wisp_held = s.result.solve.held_length;
    size_t compared = 0;
    animate(s.result.hair, *s.head.mesh, s.frame, replay, s.style.dynamics, s.style.prototype.kind,
            settings, [&](int f, const Hair& moved, const FramePose&) {
                for (const MotionFrame& frame : seen) {
                    if (frame.index != static_cast<uint32_t>(f)) continue;
                    const std::vector<Vec3f> got = positions(frame);
                    size_t at = 0;
                    for (uint32_t strand : live->shown())
                        for (uint32_t i = moved.offsets[strand]; i < moved.offsets[strand + 1];
                             ++i, ++at)
                            ASSERT_EQ(std::memcmp(&got[at], &moved.points[i], 12), 0)
                                << "frame " << f << " strand " << strand;
                    ++compared;
                }
            });
    EXPECT_EQ(compared, seen.size());
    EXPECT_NE(live->replay_arguments().find("--frames " + std::to_string(live->frames_published())),
              std::string::npos);
}

// A dynamics field set while the session runs applies from the next frame, without a
// restart: two sessions with the same input agree until the change and differ after it.
TEST(MotionSession, ADynamicsChangeAppliesFromTheNextFrame) {
    auto same = session(), changed = session();
    DynamicsSpec loose = small().style.dynamics;
    loose.stiffness = 5;
    loose.damping = 0.5f;
    loose.split_threshold = 0.02f;
    for (int i = 1; i <= 8; ++i) {
        for (MotionSession* m : {same.get(), changed.get()})
            m->drag(Vec3f(0, 12.f * i, 0), Vec3f::Zero());
        if (i == 4) changed->set_dynamics(loose);
        same->step();
        changed->step();
        const auto a = same->frame_after(std::nullopt, 0),
                   b = changed->frame_after(std::nullopt, 0);
        ASSERT_TRUE(a && b);
        ASSERT_EQ(a->index, uint32_t(i));
        if (i < 4)
            EXPECT_EQ(a->bytes, b->bytes) << "frame " << i;
        else
            EXPECT_NE(a->bytes, b->bytes) << "frame " << i;
    }
    DynamicsSpec bad = loose;
    bad.friction = 500;  // friction · dt ≥ 1 (§4.2)
    EXPECT_THROW(changed->set_dynamics(bad), Error);
    EXPECT_TRUE(changed->error().empty());
}

// A head flung back and forth at 100 m/s: the hair stays finite (or the session stops with
// a message), it never sends NaN.
TEST(MotionSession, AFlungHeadNeverSendsNonFinitePositions) {
    auto live = session();
    for (int i = 0; i < 12; ++i) {
        live->drag(Vec3f::Zero(), Vec3f((i % 2 ? 400.f : -400.f), 0, 0));
        live->step();
    }
    const auto frame = live->frame_after(std::nullopt, 0);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, 12u);
    for (const Vec3f& p : positions(*frame))
        ASSERT_TRUE(p.allFinite());
    EXPECT_TRUE(live->error().empty()) << live->error();
}

// The stream's message carries every step's splits and merges since the last one (frames
// skipped included), and a frame's tree carries all of its steps' events.
TEST(MotionSession, StreamMessagesCarryTheEventsOfEveryStep) {
    auto live = session();
    uint64_t from = live->events_published();
    EXPECT_EQ(from, 0u);
    std::string message;
    ASSERT_TRUE(live->stream_message(std::nullopt, false, 0, from, message));
    live->play_preset("shake");
    for (int i = 0; i < 15; ++i)
        live->step();
    ASSERT_TRUE(live->stream_message(0u, false, 0, from, message));
    uint32_t length = 0, header[5];
    std::memcpy(&length, message.data(), 4);
    ASSERT_EQ(length + size_t(4), message.size());
    ASSERT_EQ(message.substr(4, 8), "WISPMOTN");
    std::memcpy(header, message.data() + 12, sizeof header);
    const uint32_t frame_bytes = header[2], tree_bytes = header[3], events = header[4];
    EXPECT_EQ(header[1], 15u);
    EXPECT_EQ(tree_bytes, 0u);
    EXPECT_EQ(message.size(), 128 + frame_bytes + 16 * size_t(events));
    // Frames 1 to 15, several steps each, read once: every split and merge of every step.
    const AnimationStats stats = live->stats();
    ASSERT_GT(stats.steps, 15u);
    ASSERT_GT(stats.splits + stats.merges, 0u) << "the shake splits nothing: a weak test";
    ASSERT_LT(stats.splits + stats.merges, kMotionEventsKept);
    EXPECT_EQ(events, stats.splits + stats.merges);
    EXPECT_EQ(from, stats.splits + stats.merges);
    for (uint32_t e = 0; e < events; ++e) {
        float event[4];
        std::memcpy(event, message.data() + 128 + frame_bytes + 16 * e, 16);
        EXPECT_TRUE(std::isfinite(event[0]) && std::isfinite(event[1]) && std::isfinite(event[2]));
        EXPECT_TRUE(event[3] == 0.f || event[3] == 1.f);
    }
    EXPECT_FALSE(live->stream_message(15u, false, 0, from, message));  // nothing new

    // The tree of the next frame: that frame's events, all of its steps'.
    live->tree();
    const uint64_t before = live->events_published();
    live->step();
    const MotionFrame tree = live->tree();
    uint32_t tree_header[5];
    std::memcpy(tree_header, tree.bytes.data() + 8, sizeof tree_header);
    EXPECT_EQ(tree_header[1], 16u);
    EXPECT_EQ(tree_header[4], live->events_published() - before);
    ASSERT_TRUE(live->stream_message(15u, true, 0, from, message));
    std::memcpy(header, message.data() + 12, sizeof header);
    EXPECT_EQ(header[3], tree.bytes.size());
    EXPECT_EQ(message.substr(128 + header[2], 8), "WISPTREE");
}

}  // namespace
}  // namespace wisp
