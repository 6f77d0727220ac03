// The live motion (issue 17): input given frame by frame, recorded, and replayed by the
// animation the CLI runs to the same bytes.
#include "dynamics/live_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numeric>

#include "core/error.hpp"
#include "dynamics_fixture.hpp"

namespace wisp {
namespace {

using test::groomed;

// A mouse drag: still, then the head turned and pushed about, released, and dragged again.
MotionKey drag_at(int f) {
    MotionKey k;
    if (f < 3 || (f >= 14 && f < 20)) return k;
    const float s = static_cast<float>(f);
    k.rotate = Vec3f(12.f * std::sin(0.4f * s), 25.f * std::sin(0.23f * s), 0);
    k.translate = Vec3f(1.5f * std::sin(0.3f * s), 0, 0);
    return k;
}

TEST(LiveMotion, InputOnlyReshapesTimeNotYetSimulated) {
    const HeadFrame head = head_frame(*test::builtin_head().scalp);
    LiveMotion live(head, 25);
    const double F = live.frame_interval();
    // What the head did at each step time, as the simulation saw it while playing.
    std::vector<RigidTransform> seen;
    std::vector<double> times;
    for (int f = 0; f < 40; ++f) {
        if (f < 30)
            live.drive(f, drag_at(f), MotionKey{});
        else
            live.hold(f);
        for (int s = 1; s <= 4; ++s) {
            const double t = (f + 0.25 * s) * F;
            seen.push_back(live.motion().head.at(t));
            times.push_back(t);
        }
    }
    // The final recording moves the head the same way at every one of those times.
    for (size_t i = 0; i < times.size(); ++i) {
        const RigidTransform now = live.motion().head.at(times[i]);
        EXPECT_EQ(now.rotation, seen[i].rotation) << "t = " << times[i];
        EXPECT_EQ(now.translation, seen[i].translation) << "t = " << times[i];
    }
    // The head reaches a target two frames after it was given.
    EXPECT_EQ(live.motion().head.key_at(12 * F).rotate, drag_at(10).rotate);
    // Released at frame 30: the motion stops, the head holds where it was left.
    EXPECT_EQ(live.motion().head.at(45 * F).rotation, live.motion().head.at(60 * F).rotation);
}

TEST(LiveMotion, RefusesSkippedFramesAndBadValues) {
    const HeadFrame head = head_frame(*test::builtin_head().scalp);
    LiveMotion live(head, 25);
    live.hold(0);
    EXPECT_THROW(live.hold(2), Error);
    EXPECT_THROW(live.hold(0), Error);
    MotionKey bad;
    bad.rotate.x() = std::nanf("");
    EXPECT_THROW(live.drive(1, bad, MotionKey{}), Error);
    bad = MotionKey{};
    bad.translate.y() = 1e9f;
    EXPECT_THROW(live.drive(1, MotionKey{}, bad), Error);
    EXPECT_THROW(live.set_wind(Vec3f(std::nanf(""), 0, 0), 0, 0), Error);
    EXPECT_THROW(LiveMotion(head, 0), Error);
}

TEST(LiveMotion, KeyAboutAnotherPivotMovesEveryPointTheSame) {
    const HeadFrame head = head_frame(*test::builtin_head().scalp);
    const Motion lean = motion_preset("lean", head);  // turns about the hips
    MotionTrack about_neck;
    about_neck.pivot = neck_pivot(head);
    for (double t : {0.0, 0.7, 1.3, 2.5})
        about_neck.keys.push_back(key_about(lean.head, t, about_neck.pivot));
    about_neck.keys[0].time = 0;
    for (size_t i = 0; i < about_neck.keys.size(); ++i) {
        const double t = about_neck.keys[i].time;
        const Vec3f p = head.center + Vec3f(3, 9, 2);
        EXPECT_LT((about_neck.at(t).apply(p) - lean.head.at(t).apply(p)).norm(), 1e-4f);
    }
}

// The server test, on the library: a session driven live (a drag, a release, a
// drag again, then a preset) and its recording replayed by animate() as `wisp animate
// --motion recording.json` does give the same bytes, for the strands the live view shows.
TEST(LiveMotion, RecordingReplaysToTheSameFrames) {
    const test::Groomed g = groomed("long-straight", 60, 600, 12);
    const Mesh& body = *test::builtin_head().mesh;
    const double fps = 25;
    AnimateSettings settings;
    settings.frames = 36;
    settings.fps = fps;
    settings.wisp_held = g.held;
    settings.frame_stats = false;

    LiveMotion live(g.head, fps);
    const Motion nod = motion_preset("nod", g.head);
    Animator animator(g.hair, body, g.head, live.motion(), g.style.dynamics, g.style.prototype.kind,
                      settings);
    // The live view's strands: every third one.
    std::vector<uint32_t> shown;
    for (uint32_t s = 0; s < g.hair.strand_count(); s += 3)
        shown.push_back(s);
    size_t shown_points = 0;
    for (uint32_t s : shown)
        shown_points += g.hair.offsets[s + 1] - g.hair.offsets[s];
    std::vector<std::vector<Vec3f>> live_frames;
    std::vector<FramePose> poses;
    for (int f = 0; f < settings.frames; ++f) {
        if (f < 24)
            live.drive(f, drag_at(f), MotionKey{});
        else  // a preset started at frame 24, about the live motion's pivots
            live.drive(f, key_about(nod.head, (f - 24) * live.frame_interval(), live.head_pivot()),
                       key_about(nod.body, (f - 24) * live.frame_interval(), live.body_pivot()));
        animator.advance();
        poses.push_back(animator.pose());
        live_frames.emplace_back(shown_points);
        animator.skin(shown, live_frames.back());
        // Skinned straight into a frame's bytes (the live loop's way): the same bits.
        std::vector<char> xyz(12 * shown_points);
        animator.skin(shown, xyz);
        ASSERT_EQ(std::memcmp(xyz.data(), live_frames.back().data(), xyz.size()), 0) << f;
    }
    const auto recording = std::filesystem::temp_directory_path() / "wisp_live_recording.json";
    live.write(recording);
    const Motion replay = read_motion(recording, g.head);
    std::filesystem::remove(recording);
    ASSERT_EQ(replay.head.keys.size(), live.motion().head.keys.size());
    for (size_t i = 0; i < replay.head.keys.size(); ++i) {
        EXPECT_EQ(replay.head.keys[i].time, live.motion().head.keys[i].time) << i;
        EXPECT_EQ(replay.head.keys[i].rotate, live.motion().head.keys[i].rotate) << i;
        EXPECT_EQ(replay.head.keys[i].translate, live.motion().head.keys[i].translate) << i;
        EXPECT_EQ(replay.body.keys[i].translate, live.motion().body.keys[i].translate) << i;
    }
    EXPECT_EQ(replay.head.pivot, live.motion().head.pivot);
    EXPECT_EQ(replay.body.pivot, live.motion().body.pivot);
    EXPECT_EQ(replay.gravity, live.motion().gravity);

    settings.frame_stats = true;
    int compared = 0;
    animate(
        g.hair, body, g.head, replay, g.style.dynamics, g.style.prototype.kind, settings,
        [&](int f, const Hair& moved, const FramePose& pose) {
            EXPECT_EQ(pose.time, poses[f].time) << f;
            EXPECT_EQ(pose.head.rotation, poses[f].head.rotation) << f;
            EXPECT_EQ(pose.head.translation, poses[f].head.translation) << f;
            size_t at = 0;
            for (uint32_t s : shown)
                for (uint32_t i = moved.offsets[s]; i < moved.offsets[s + 1]; ++i, ++at)
                    ASSERT_EQ(std::memcmp(&moved.points[i], &live_frames[f][at], sizeof(Vec3f)), 0)
                        << "frame " << f << ", strand " << s << ", point " << i;
            ++compared;
        });
    EXPECT_EQ(compared, settings.frames);
    // The hair did move: the drag reached the strands.
    float moved_most = 0;
    for (size_t i = 0; i < shown_points; ++i)
        moved_most = std::max(moved_most, (live_frames[20][i] - live_frames[0][i]).norm());
    EXPECT_GT(moved_most, 1.f);
}

}  // namespace
}  // namespace wisp
