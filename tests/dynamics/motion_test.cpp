#include "dynamics/motion.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The built-in head's frame, and an off-centre one so that pivots and head units are tested
// away from the origin.
const HeadFrame kHead{};
const HeadFrame kOffHead{Vec3f(1.f, 2.f, -3.f), 8.f};

const Vec3f kFace = Vec3f::UnitZ();
const Vec3f kCrown = Vec3f::UnitY();

// Points a motion moves: scalp points, the face, and hair tips well below the head.
std::vector<Vec3f> probes(const HeadFrame& head) {
    std::vector<Vec3f> out;
    for (const Vec3f& d : {Vec3f(0, 1, 0), Vec3f(0, 0, 1), Vec3f(1, 0, 0),
                           Vec3f(-0.6f, 0.6f, -0.5f), Vec3f(0, -3, -1), Vec3f(0.5f, -2, 0.8f)})
        out.push_back(head.to_space(d));
    return out;
}

std::vector<Motion> all_presets(const HeadFrame& head) {
    std::vector<Motion> out;
    for (const std::string& name : motion_preset_names())
        out.push_back(motion_preset(name, head));
    return out;
}

// The rotation of motion.hpp built from the formula, to check at() against.
Mat3f euler(float pitch, float yaw, float roll) {
    const Eigen::AngleAxisf x(pitch * float(kDeg), Vec3f::UnitX());
    const Eigen::AngleAxisf y(yaw * float(kDeg), Vec3f::UnitY());
    const Eigen::AngleAxisf z(roll * float(kDeg), Vec3f::UnitZ());
    return (y * x * z).toRotationMatrix();
}

MotionTrack single_key(const Vec3f& rotate, const Vec3f& translate = Vec3f::Zero(),
                       const Vec3f& pivot = Vec3f::Zero()) {
    MotionTrack tr;
    tr.pivot = pivot;
    MotionKey k;
    k.rotate = rotate;
    k.translate = translate;
    tr.keys.push_back(k);
    return tr;
}

// The signed angle (degrees) by which a track pitches the face down at t.
double face_down_degrees(const MotionTrack& tr, double t) {
    const Vec3f f = tr.at(t).apply_vector(kFace);
    return std::atan2(-f.y(), f.z()) / kDeg;
}

// Central finite difference of the motion of p, compared with the analytic velocity. The
// tolerance allows for float rounding of positions far from the origin (the run ends 9 m
// away) and for the spline being C1, not C2: across a key the difference errs by up to
// |Δacceleration|·step/4, bounded here by half the change of velocity over the two steps.
void expect_velocity_matches_differences(const MotionTrack& tr, const Vec3f& p, double t,
                                         const std::string& what) {
    constexpr double kStep = 2e-4;
    const Vec3f after = tr.at(t + kStep).apply(p), before = tr.at(t - kStep).apply(p);
    const Vec3f fd = (after - before) / static_cast<float>(2 * kStep);
    const Vec3f v = tr.velocity(p, t);
    const float rounding = 8 * std::numeric_limits<float>::epsilon() *
                           (after.norm() + before.norm()) / static_cast<float>(2 * kStep);
    const float kink = 0.5f * (tr.velocity(p, t + kStep) - tr.velocity(p, t - kStep)).norm();
    const float tolerance = 0.01f + 1e-4f * v.norm() + rounding + kink;
    EXPECT_LE((fd - v).norm(), tolerance)
        << what << " t=" << t << " p=" << p.transpose() << " analytic " << v.transpose()
        << " differences " << fd.transpose();
}

// ---- interpolation and conventions --------------------------------------------------------

TEST(Motion, EmptyTrackIsIdentityAndStill) {
    const MotionTrack tr;
    for (double t : {-1.0, 0.0, 0.5, 1e3}) {
        const RigidTransform x = tr.at(t);
        EXPECT_TRUE(x.rotation.isIdentity(0));
        EXPECT_TRUE(x.translation.isZero(0));
        EXPECT_TRUE(tr.velocity(Vec3f(1, 2, 3), t).isZero(0));
    }
}

TEST(Motion, SignConventions) {
    // pitch > 0 tips the face down: Rx(θ)·(0, 0, 1) = (0, −sin θ, cos θ).
    EXPECT_TRUE(single_key({90, 0, 0}).at(0).apply_vector(kFace).isApprox(Vec3f(0, -1, 0), 1e-6f));
    EXPECT_TRUE(
        single_key({30, 0, 0})
            .at(0)
            .apply_vector(kFace)
            .isApprox(Vec3f(0, -std::sin(30 * float(kDeg)), std::cos(30 * float(kDeg))), 1e-6f));
    // yaw > 0 turns the face toward +X.
    EXPECT_TRUE(single_key({0, 90, 0}).at(0).apply_vector(kFace).isApprox(Vec3f(1, 0, 0), 1e-6f));
    // roll > 0 tilts the crown toward −X.
    EXPECT_TRUE(single_key({0, 0, 90}).at(0).apply_vector(kCrown).isApprox(Vec3f(-1, 0, 0), 1e-6f));
    // R = Ry·Rx·Rz: roll first, then pitch, then yaw.
    EXPECT_TRUE(
        single_key({90, 0, 90}).at(0).apply_vector(Vec3f::UnitX()).isApprox(Vec3f(0, 0, 1), 1e-6f));
    EXPECT_TRUE(single_key({90, 90, 0}).at(0).apply_vector(kFace).isApprox(Vec3f(0, -1, 0), 1e-6f));
    // A general key matches the formula, and the pivot stays put up to the translation.
    const Vec3f pivot(3, -12, 1), move(1, 2, 3);
    const MotionTrack tr = single_key({20, -35, 50}, move, pivot);
    const RigidTransform x = tr.at(0);
    EXPECT_TRUE(x.rotation.isApprox(euler(20, -35, 50), 1e-6f));
    EXPECT_TRUE(x.apply(pivot).isApprox(pivot + move, 1e-6f));
    const Vec3f p(4, 5, 6);
    EXPECT_TRUE(x.apply(p).isApprox(move + pivot + euler(20, -35, 50) * (p - pivot), 1e-6f));
}

// Unevenly spaced random keys with large angles on all three axes at once, so every term of
// the product rule is exercised.
MotionTrack random_track(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> angle(-120, 120), move(-30, 30), gap(0.05f, 0.6f);
    MotionTrack tr;
    tr.pivot = Vec3f(move(rng), move(rng), move(rng));
    double t = 0.3;
    for (int i = 0; i < 12; ++i) {
        MotionKey k;
        k.time = t;
        k.rotate = Vec3f(angle(rng), angle(rng), angle(rng));
        k.translate = Vec3f(move(rng), move(rng), move(rng));
        tr.keys.push_back(k);
        t += gap(rng);
    }
    return tr;
}

TEST(Motion, VelocityMatchesFiniteDifferencesOnRandomTracks) {
    for (uint32_t seed = 1; seed <= 8; ++seed) {
        const MotionTrack tr = random_track(seed);
        const double t0 = tr.keys.front().time, t1 = tr.keys.back().time;
        for (int i = 0; i <= 400; ++i) {
            const double t = t0 - 0.1 + (t1 - t0 + 0.2) * i / 400.0;
            for (const Vec3f& p : probes(kOffHead))
                expect_velocity_matches_differences(tr, p, t, "seed " + std::to_string(seed));
        }
    }
}

TEST(Motion, PassesThroughKeysWithContinuousVelocity) {
    for (uint32_t seed = 1; seed <= 4; ++seed) {
        const MotionTrack tr = random_track(seed);
        const Vec3f p = kOffHead.to_space(Vec3f(0.3f, 0.8f, 0.5f));
        for (size_t i = 0; i < tr.keys.size(); ++i) {
            const MotionKey& k = tr.keys[i];
            const RigidTransform x = tr.at(k.time);
            EXPECT_TRUE(
                x.rotation.isApprox(euler(k.rotate.x(), k.rotate.y(), k.rotate.z()), 1e-5f));
            EXPECT_TRUE(x.apply(tr.pivot).isApprox(tr.pivot + k.translate, 1e-5f));
            const double e = 1e-6;
            const Vec3f before = tr.at(k.time - e).apply(p), after = tr.at(k.time + e).apply(p);
            EXPECT_LE((before - after).norm(), 1e-3f) << "key " << i;
            const Vec3f vb = tr.velocity(p, k.time - e), va = tr.velocity(p, k.time + e);
            EXPECT_LE((vb - va).norm(), 1e-2f * (1 + va.norm())) << "key " << i;
        }
        // Zero velocity at the clamped end keys.
        EXPECT_TRUE(tr.velocity(p, tr.keys.front().time).isZero(1e-6f));
        EXPECT_TRUE(tr.velocity(p, tr.keys.back().time).isZero(1e-6f));
    }
}

TEST(Motion, HoldsTheEndPosesOutsideTheKeys) {
    const MotionTrack tr = random_track(3);
    const Vec3f p(1, 2, 3);
    const double t0 = tr.keys.front().time, t1 = tr.keys.back().time;
    for (double t : {-5.0, 0.0, t0 - 1e-3}) {
        EXPECT_TRUE(tr.at(t).apply(p).isApprox(tr.at(t0).apply(p), 1e-6f));
        EXPECT_TRUE(tr.velocity(p, t).isZero(0));
    }
    for (double t : {t1 + 1e-3, t1 + 10, 1e6}) {
        EXPECT_TRUE(tr.at(t).apply(p).isApprox(tr.at(t1).apply(p), 1e-6f));
        EXPECT_TRUE(tr.velocity(p, t).isZero(0));
    }
}

TEST(Motion, HoldsBetweenEqualKeysAreExact) {
    // Still, turn to 45°, hold, back: no dip before the turn and no overshoot after it.
    MotionTrack tr;
    for (auto [t, yaw] : {std::pair{0.0, 0.f},
                          {1.0, 0.f},
                          {1.5, 20.f},
                          {2.0, 45.f},
                          {3.0, 45.f},
                          {3.2, 0.f},
                          {4.0, 0.f}}) {
        MotionKey k;
        k.time = t;
        k.rotate = Vec3f(0, yaw, 0);
        tr.keys.push_back(k);
    }
    const Vec3f p(0, 0, 10);
    for (double t = 0; t <= 4.2; t += 0.01) {
        const float x = tr.at(t).apply(p).x();
        if (t <= 1.0 || t >= 3.2) {
            EXPECT_EQ(x, 0) << t;
            EXPECT_TRUE(tr.velocity(p, t).isZero(0)) << t;
        }
        if (t >= 2.0 && t <= 3.0) {
            EXPECT_NEAR(x, 10 * std::sin(45 * kDeg), 1e-5) << t;
        }
        EXPECT_GE(x, 0) << t;
        EXPECT_LE(x, 10 * std::sin(45 * kDeg) + 1e-5) << t;
    }
}

TEST(Motion, UnevenKeysFollowTheTimeNotTheIndex) {
    // Keys on a straight line at uneven times: the time-aware tangents reproduce the line's
    // constant velocity exactly between the interior keys (a uniform spline would not).
    MotionTrack tr;
    for (double t : {0.0, 0.1, 0.5, 0.6, 1.5, 1.6}) {
        MotionKey k;
        k.time = t;
        k.translate = Vec3f(float(40 * t), 0, 0);
        tr.keys.push_back(k);
    }
    for (double t = 0.1; t <= 1.5; t += 0.05)
        EXPECT_NEAR(tr.velocity(Vec3f::Zero(), t).x(), 40.f, 1e-3f) << t;
}

TEST(Motion, WindAndGust) {
    Motion m;
    m.gust_amplitude = 50;
    EXPECT_TRUE(m.wind_at(0.5).isZero(0)) << "no gust without wind";
    m.wind = Vec3f(0, 0, 100);
    m.gust_frequency = 0.5f;
    EXPECT_TRUE(m.wind_at(0).isApprox(Vec3f(0, 0, 100), 1e-5f));
    EXPECT_TRUE(m.wind_at(0.5).isApprox(Vec3f(0, 0, 150), 1e-5f));
    EXPECT_TRUE(m.wind_at(1.5).isApprox(Vec3f(0, 0, 50), 1e-5f));
    m.gust_amplitude = 0;
    EXPECT_TRUE(m.wind_at(0.5).isApprox(m.wind, 0));
}

// ---- presets ------------------------------------------------------------------------------

TEST(MotionPreset, NamesAndUnknownName) {
    EXPECT_EQ(motion_preset_names(),
              (std::vector<std::string>{"lean", "shake", "nod", "jump", "run", "still"}));
    for (const std::string& name : motion_preset_names())
        EXPECT_EQ(motion_preset(name, kHead).name, name);
    try {
        motion_preset("dance", kHead);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("dance"), std::string::npos) << what;
        for (const std::string& name : motion_preset_names())
            EXPECT_NE(what.find(name), std::string::npos) << what;
    }
}

TEST(MotionPreset, VelocityMatchesFiniteDifferences) {
    for (const HeadFrame& head : {kHead, kOffHead}) {
        for (const Motion& m : all_presets(head)) {
            for (const MotionTrack* tr : {&m.head, &m.body}) {
                for (int i = 0; i <= 600; ++i) {
                    const double t = -0.1 + (m.duration + 0.2) * i / 600.0;
                    for (const Vec3f& p : probes(head))
                        expect_velocity_matches_differences(*tr, p, t, m.name);
                }
            }
        }
    }
}

TEST(MotionPreset, StartAndEndAtRest) {
    for (const Motion& m : all_presets(kOffHead)) {
        SCOPED_TRACE(m.name);
        EXPECT_GT(m.duration, 0);
        for (const MotionTrack* tr : {&m.head, &m.body}) {
            const RigidTransform x = tr->at(0);
            EXPECT_TRUE(x.rotation.isIdentity(1e-6f));
            EXPECT_TRUE(x.translation.isZero(1e-4f));
            if (!tr->keys.empty()) {
                EXPECT_EQ(tr->keys.front().time, 0);
                EXPECT_LE(tr->keys.back().time, m.duration);
            }
            for (const Vec3f& p : probes(kOffHead)) {
                EXPECT_TRUE(tr->velocity(p, 0).isZero(1e-6f));
                EXPECT_TRUE(tr->velocity(p, m.duration).isZero(1e-6f));
                EXPECT_LE(tr->velocity(p, m.duration - 0.01).norm(), 1.f);
                EXPECT_TRUE(tr->velocity(p, m.duration + 1).isZero(0));
            }
        }
    }
}

TEST(MotionPreset, PivotsScaleWithTheHead) {
    const Vec3f neck = kOffHead.center + Vec3f(0, -1.2f * kOffHead.radius, 0);
    const Vec3f hips = kOffHead.center + Vec3f(0, -6.f * kOffHead.radius, 0);
    EXPECT_TRUE(motion_preset("lean", kOffHead).head.pivot.isApprox(hips));
    EXPECT_TRUE(motion_preset("run", kOffHead).head.pivot.isApprox(hips));
    EXPECT_TRUE(motion_preset("shake", kOffHead).head.pivot.isApprox(neck));
    EXPECT_TRUE(motion_preset("nod", kOffHead).head.pivot.isApprox(neck));
}

TEST(MotionPreset, StillHasNoKeys) {
    const Motion m = motion_preset("still", kHead);
    EXPECT_TRUE(m.head.keys.empty());
    EXPECT_TRUE(m.body.keys.empty());
    EXPECT_EQ(m.duration, 2);
}

TEST(MotionPreset, LeanPitchesForwardToFortyFiveDegreesAndBack) {
    const Motion m = motion_preset("lean", kHead);
    EXPECT_EQ(m.duration, 4);
    double most = 0;
    for (double t = 0; t <= 4; t += 0.01) {
        const double pitch = face_down_degrees(m.head, t);
        most = std::max(most, pitch);
        if (t < 0.3 || t > 3.0) {
            EXPECT_EQ(pitch, 0) << t;
        }
        if (t > 1.3 && t < 2.0) {
            EXPECT_NEAR(pitch, 45, 1e-4) << t;
        }
        EXPECT_NEAR(face_down_degrees(m.body, t), pitch, 1e-4) << t;
    }
    EXPECT_NEAR(most, 45, 2e-3);  // the spline's last ramp segment overshoots slightly
    // About the hips: the top of the head moves forward (+Z) and down.
    const Vec3f top = kHead.to_space(kCrown);
    const Vec3f leaned = m.head.at(1.65).apply(top);
    EXPECT_NEAR(leaned.z(), 7 * kHead.radius * std::sin(45 * kDeg), 0.05f);
    EXPECT_LT(leaned.y(), top.y());
}

TEST(MotionPreset, ShakeTurnsTheFaceToBothSidesAndLeavesTheBodyStill) {
    const Motion m = motion_preset("shake", kHead);
    EXPECT_EQ(m.duration, 4);
    EXPECT_TRUE(m.body.keys.empty());
    float left = 0, right = 0;
    const Vec3f neck = m.head.pivot;
    for (double t = 0; t <= 4; t += 0.005) {
        const Vec3f f = m.head.at(t).apply_vector(kFace);
        left = std::max(left, f.x());
        right = std::min(right, f.x());
        EXPECT_NEAR(f.y(), 0, 1e-5f) << "yaw only";
        EXPECT_TRUE(m.head.at(t).apply(neck).isApprox(neck, 1e-5f)) << "turns about the neck";
        EXPECT_TRUE(m.body.at(t).rotation.isIdentity(0));
        if (t < 0.25 || t > 2.25) {
            EXPECT_EQ(f.x(), 0) << t;
        }
    }
    EXPECT_NEAR(left, std::sin(40 * kDeg), 2e-3);
    EXPECT_NEAR(right, -std::sin(40 * kDeg), 2e-3);
}

TEST(MotionPreset, NodGoesDownThenUpAndLeavesTheBodyStill) {
    const Motion m = motion_preset("nod", kHead);
    EXPECT_EQ(m.duration, 4);
    EXPECT_TRUE(m.body.keys.empty());
    double down = 0, up = 0, first_down_time = -1;
    for (double t = 0; t <= 4; t += 0.005) {
        const double pitch = face_down_degrees(m.head, t);
        if (first_down_time < 0 && pitch > 20) first_down_time = t;
        down = std::max(down, pitch);
        up = std::min(up, pitch);
        EXPECT_NEAR(m.head.at(t).apply_vector(kFace).x(), 0, 1e-5f) << "pitch only";
        if (t > 2.0) {
            EXPECT_EQ(pitch, 0) << t;
        }
    }
    EXPECT_NEAR(down, 25, 0.1);
    EXPECT_NEAR(up, -10, 0.1);
    EXPECT_GT(first_down_time, 0.25);
    EXPECT_LT(first_down_time, 0.6);
}

TEST(MotionPreset, JumpIsBallisticWithACrouchBeforeEachTakeOff) {
    const Motion m = motion_preset("jump", kHead);
    EXPECT_EQ(m.duration, 3);
    const float r = kHead.radius;
    float high = 0, previous = 0;
    std::vector<double> take_offs;
    for (double t = 0; t <= m.duration; t += 0.002) {
        const RigidTransform x = m.head.at(t);
        EXPECT_TRUE(x.rotation.isIdentity(0));
        EXPECT_TRUE(m.body.at(t).translation.isApprox(x.translation, 0));
        const float y = x.translation.y();
        high = std::max(high, y);
        if (previous <= 0.05f * r && y > 0.05f * r) take_offs.push_back(t);
        previous = y;
    }
    ASSERT_EQ(take_offs.size(), 2u);
    for (double t_off : take_offs) {
        float crouch = 0;
        for (double t = t_off - 0.35; t < t_off; t += 0.002)
            crouch = std::min(crouch, m.head.at(t).translation.y());
        EXPECT_NEAR(crouch, -0.3f * r, 0.01f * r) << "crouch before the take-off at " << t_off;
    }
    EXPECT_NEAR(high, 1.5f * r, 0.01f * r);
    // Near the apex the spline follows the parabola: acceleration −g.
    double apex = 0;
    for (double t = 0; t < 1.2; t += 1e-3)
        if (m.head.at(t).translation.y() > m.head.at(apex).translation.y()) apex = t;
    for (double dt : {-0.1, -0.05, 0.0, 0.05, 0.1}) {
        const double t = apex + dt, h = 1e-3;
        const Vec3f o = Vec3f::Zero();
        const double a = (m.head.velocity(o, t + h).y() - m.head.velocity(o, t - h).y()) / (2 * h);
        EXPECT_NEAR(a, -981, 0.02 * 981) << "t=" << t;
    }
}

TEST(MotionPreset, RunAcceleratesBobsLeansAndStops) {
    const Motion m = motion_preset("run", kHead);
    EXPECT_EQ(m.duration, 4);
    const float r = kHead.radius, speed = 30 * r;
    const Vec3f centre = kHead.center;
    for (double t = 0.6; t < 2.9; t += 0.1) {
        EXPECT_NEAR(m.head.velocity(centre, t).z(), speed, 1e-3f * speed) << t;
        EXPECT_NEAR(face_down_degrees(m.head, t), 10, 0.01) << t;
    }
    float bob_hi = -1e9f, bob_lo = 1e9f;
    const Vec3f hips = m.head.pivot;  // moves with the translation alone
    for (double t = 1.0; t < 2.5; t += 0.002) {
        const float bob = m.head.at(t).apply(hips).y() - hips.y();
        bob_hi = std::max(bob_hi, bob);
        bob_lo = std::min(bob_lo, bob);
    }
    EXPECT_NEAR(bob_hi, 0.3f * r, 0.02f * r);
    EXPECT_NEAR(bob_lo, -0.3f * r, 0.02f * r);
    // Accelerates over the first 0.5 s, stopped by 3.5 s with the bob and lean gone.
    EXPECT_LT(m.head.velocity(hips, 0.1).z(), 0.1f * speed);
    EXPECT_NEAR(m.head.velocity(hips, 0.25).z(), 0.5f * speed, 0.01f * speed);
    for (double t = 3.5; t <= 4; t += 0.1) {
        EXPECT_TRUE(m.head.velocity(centre, t).isZero(0)) << t;
        EXPECT_NEAR(face_down_degrees(m.head, t), 0, 1e-3) << t;
        EXPECT_NEAR(m.head.at(t).apply(hips).z() - hips.z(), 3 * speed, 1e-3f * speed) << t;
    }
    EXPECT_TRUE(m.body.at(2.0).translation.isApprox(m.head.at(2.0).translation, 0));
}

// ---- files --------------------------------------------------------------------------------

fs::path temp_dir() {
    const fs::path dir =
        fs::temp_directory_path() / ("wisp_motion_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

fs::path write_text(const std::string& name, const std::string& text) {
    const fs::path p = temp_dir() / name;
    write_file_atomic(p, text);
    return p;
}

// Expects read_motion(path) to throw a wisp::Error whose message starts with the path and
// contains every one of `parts` (the field, what is wrong).
void expect_error(const fs::path& path, std::initializer_list<std::string> parts) {
    try {
        read_motion(path, kHead);
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << what;
        for (const std::string& part : parts)
            EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
    }
}

// A file with the given head keys (the inside of the "keys" array) and extra top-level text.
std::string with_keys(const std::string& keys, const std::string& extra = "") {
    return R"({"format": "wisp-motion", "version": 1, )" + extra + R"("head": {"keys": [)" + keys +
           "]}}";
}

TEST(MotionFile, ReadsHeadUnits) {
    const fs::path p = write_text("head_units.json", R"({
        "format": "wisp-motion", "version": 1,
        "head": {"pivot": [0, -1.2, 0],
                 "keys": [{"t": 0}, {"t": 0.5, "rotate": [10, 20, 30], "translate": [0, 1, 0]}]},
        "gravity": [0, -500, 0], "wind": [100, 0, 0],
        "gust": {"amplitude": 20, "frequency": 2}})");
    const Motion m = read_motion(p, kOffHead);
    EXPECT_EQ(m.name, p.string());
    EXPECT_TRUE(m.head.pivot.isApprox(kOffHead.center + Vec3f(0, -1.2f * 8, 0)));
    ASSERT_EQ(m.head.keys.size(), 2u);
    EXPECT_EQ(m.head.keys[1].time, 0.5);
    EXPECT_TRUE(m.head.keys[1].rotate.isApprox(Vec3f(10, 20, 30)));
    EXPECT_TRUE(m.head.keys[1].translate.isApprox(Vec3f(0, 8, 0)));
    EXPECT_TRUE(m.head.keys[0].translate.isZero(0));
    // Without "body" the body moves with the head.
    EXPECT_EQ(m.body.keys.size(), 2u);
    EXPECT_TRUE(m.body.pivot.isApprox(m.head.pivot));
    EXPECT_EQ(m.duration, 0.5);
    EXPECT_TRUE(m.gravity.isApprox(Vec3f(0, -500, 0)));
    EXPECT_TRUE(m.wind.isApprox(Vec3f(100, 0, 0)));
    EXPECT_EQ(m.gust_amplitude, 20);
    EXPECT_EQ(m.gust_frequency, 2);
}

TEST(MotionFile, ReadsCentimetresAndDefaults) {
    const fs::path p = write_text("cm.json", R"({"format": "wisp-motion", "version": 1,
        "units": "cm",
        "head": {"pivot": [0, -12, 0], "keys": [{"t": 1, "translate": [0, 1, 0]}]},
        "body": {"keys": [{"t": 0}, {"t": 2.5}]}})");
    const Motion m = read_motion(p, kOffHead);
    EXPECT_TRUE(m.head.pivot.isApprox(Vec3f(0, -12, 0)));
    EXPECT_TRUE(m.head.keys[0].translate.isApprox(Vec3f(0, 1, 0)));
    EXPECT_TRUE(m.body.pivot.isZero(0));
    EXPECT_EQ(m.duration, 2.5) << "the last key of either track";
    EXPECT_TRUE(m.gravity.isApprox(Vec3f(0, -981, 0)));
    EXPECT_TRUE(m.wind.isZero(0));
    EXPECT_EQ(m.gust_amplitude, 0);
    EXPECT_EQ(m.gust_frequency, 0.5f);

    const Motion still =
        read_motion(write_text("still.json", with_keys("", R"("body": {"keys": []}, )")), kHead);
    EXPECT_EQ(still.duration, 0);
    const Motion given = read_motion(
        write_text("duration.json", with_keys(R"({"t": 1})", R"("duration": 4, )")), kHead);
    EXPECT_EQ(given.duration, 4);
}

TEST(MotionFile, ReadsTheDocumentedExample) {
    const std::string doc = read_file(WISP_SOURCE_DIR "/docs/motion.md");
    const size_t begin = doc.find("```json\n");
    ASSERT_NE(begin, std::string::npos);
    const size_t end = doc.find("```", begin + 8);
    const Motion m =
        read_motion(write_text("documented.json", doc.substr(begin + 8, end - begin - 8)), kHead);
    EXPECT_EQ(m.head.keys.size(), 5u);
    EXPECT_TRUE(m.head.pivot.isApprox(Vec3f(0, -12, 0)));
    EXPECT_TRUE(m.body.keys.empty());
    EXPECT_EQ(m.duration, 3);
    EXPECT_TRUE(m.head.keys[3].translate.isApprox(Vec3f(0, 0, 5)));
    EXPECT_GT(m.head.at(0.4).apply_vector(kFace).x(), 0.49f) << "turned toward +X";
    EXPECT_TRUE(m.head.velocity(Vec3f::Zero(), 2.5).isZero(0));
}

TEST(MotionFile, LoadPrefersPresets) {
    EXPECT_EQ(load_motion("nod", kHead).name, "nod");
    const fs::path p = write_text("load.json", with_keys(R"({"t": 0}, {"t": 1})"));
    EXPECT_EQ(load_motion(p.string(), kHead).head.keys.size(), 2u);
    EXPECT_THROW(load_motion((temp_dir() / "missing.json").string(), kHead), Error);
}

TEST(MotionFile, RoundTripsEveryPreset) {
    for (const HeadFrame& head : {kHead, kOffHead}) {
        for (Motion m : all_presets(head)) {
            SCOPED_TRACE(m.name);
            m.wind = Vec3f(30, 0, -12.5f);
            m.gust_amplitude = 7.25f;
            m.gust_frequency = 1.3f;
            const fs::path p = temp_dir() / ("round_trip_" + m.name + ".json");
            write_motion(p, m);
            const Motion r = read_motion(p, kOffHead);  // cm units: the head frame is unused
            EXPECT_NEAR(r.duration, m.duration, 1e-9);
            EXPECT_TRUE(r.gravity.isApprox(m.gravity, 1e-6f));
            EXPECT_TRUE(r.wind.isApprox(m.wind, 1e-6f));
            EXPECT_EQ(r.gust_amplitude, m.gust_amplitude);
            EXPECT_EQ(r.gust_frequency, m.gust_frequency);
            for (auto [a, b] : {std::pair{&m.head, &r.head}, std::pair{&m.body, &r.body}}) {
                EXPECT_LE((a->pivot - b->pivot).cwiseAbs().maxCoeff(), 1e-4f);
                ASSERT_EQ(a->keys.size(), b->keys.size());
                for (size_t i = 0; i < a->keys.size(); ++i) {
                    EXPECT_NEAR(a->keys[i].time, b->keys[i].time, 1e-9);
                    EXPECT_LE((a->keys[i].rotate - b->keys[i].rotate).cwiseAbs().maxCoeff(), 1e-4f);
                    EXPECT_LE((a->keys[i].translate - b->keys[i].translate).cwiseAbs().maxCoeff(),
                              1e-4f);
                }
            }
        }
    }
}

TEST(MotionFile, WriteRefusesNonFiniteNumbers) {
    Motion m = motion_preset("nod", kHead);
    m.head.keys[3].rotate.x() = NAN;
    const fs::path p = temp_dir() / "nan.json";
    try {
        write_motion(p, m);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("head.keys[3].rotate"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(p));
}

TEST(MotionFile, MissingOrUnreadable) {
    expect_error(temp_dir() / "nope.json", {});
    const fs::path folder = temp_dir() / "folder.json";
    fs::create_directories(folder);
    expect_error(folder, {"folder"});
}

TEST(MotionFile, MalformedJson) {
    expect_error(write_text("empty.json", ""), {"invalid JSON"});
    expect_error(write_text("truncated.json", with_keys(R"({"t": 0}, {"t": 1)").substr(0, 70)),
                 {"invalid JSON"});
    // The error names where the text broke off.
    const std::string cut =
        R"({"format": "wisp-motion", "version": 1, "head": {"keys": [{"t": 0}, {"t": 1)";
    expect_error(write_text("cut.json", cut), {"head.keys[1]", "invalid JSON"});
    expect_error(write_text("nan_literal.json", with_keys(R"({"t": NaN})")),
                 {"head.keys[0].t", "invalid JSON"});
    expect_error(write_text("array.json", "[1, 2]"), {"top level"});
}

TEST(MotionFile, HeaderFields) {
    expect_error(write_text("no_format.json", R"({"version": 1, "head": {"keys": []}})"),
                 {"format", "missing"});
    expect_error(write_text("bad_format.json",
                            R"({"format": "wisp-hair", "version": 1, "head": {"keys": []}})"),
                 {"format", "wisp-motion"});
    expect_error(write_text("bad_version.json",
                            R"({"format": "wisp-motion", "version": 2, "head": {"keys": []}})"),
                 {"version", "expected 1"});
    expect_error(
        write_text("no_version.json", R"({"format": "wisp-motion", "head": {"keys": []}})"),
        {"version", "missing"});
    expect_error(write_text("bad_units.json", with_keys("", R"("units": "inch", )")),
                 {"units", "\"inch\""});
    expect_error(write_text("no_head.json", R"({"format": "wisp-motion", "version": 1})"),
                 {"head", "missing"});
    expect_error(
        write_text("no_keys.json", R"({"format": "wisp-motion", "version": 1, "head": {}})"),
        {"head.keys", "missing"});
}

TEST(MotionFile, UnknownAndRepeatedFields) {
    expect_error(write_text("unknown_top.json", with_keys("", R"("speed": 3, )")),
                 {": speed: unknown field"});
    expect_error(
        write_text("unknown_key.json", with_keys(R"({"t": 0}, {"t": 1, "rotation": [0, 0, 0]})")),
        {"head.keys[1].rotation", "unknown field"});
    expect_error(write_text("unknown_gust.json", with_keys("", R"("gust": {"amp": 1}, )")),
                 {"gust.amp", "unknown field"});
    expect_error(write_text("twice.json", with_keys(R"({"t": 0}, {"t": 1, "t": 2})")),
                 {"head.keys[1].t", "twice"});
    expect_error(
        write_text("twice_top.json", with_keys("", R"("wind": [1, 0, 0], "wind": [2, 0, 0], )")),
        {": wind", "twice"});
}

TEST(MotionFile, WrongTypesAndNonFiniteNumbers) {
    expect_error(write_text("nan_string.json", with_keys(R"({"t": 0, "rotate": ["NaN", 0, 0]})")),
                 {"head.keys[0].rotate[0]", "expected a number"});
    expect_error(write_text("t_string.json", with_keys(R"({"t": "0"})")),
                 {"head.keys[0].t", "expected a number"});
    expect_error(write_text("bool.json", with_keys(R"({"t": true})")),
                 {"head.keys[0].t", "expected a number"});
    expect_error(write_text("overflow.json", with_keys(R"({"t": 0}, {"t": 1e400})")),
                 {"head.keys[1].t"});
    expect_error(write_text("short_vec.json", with_keys(R"({"t": 0, "translate": [1, 2]})")),
                 {"head.keys[0].translate", "3 numbers"});
    expect_error(write_text("keys_object.json", R"({"format": "wisp-motion", "version": 1,
        "head": {"keys": {"t": 0}}})"),
                 {"head.keys", "expected an array"});
    expect_error(write_text("key_number.json", with_keys("3")),
                 {"head.keys[0]", "expected an object"});
    expect_error(write_text("body_array.json", with_keys("", R"("body": [], )")),
                 {"body", "expected an object"});
    expect_error(write_text("pivot.json", R"({"format": "wisp-motion", "version": 1,
        "head": {"pivot": [0, 0, "x"], "keys": []}})"),
                 {"head.pivot[2]", "expected a number"});
    expect_error(write_text("duration_string.json", with_keys("", R"("duration": "4", )")),
                 {"duration", "expected a number"});
    expect_error(write_text("gravity.json", with_keys("", R"("gravity": 9.81, )")),
                 {"gravity", "3 numbers"});
}

TEST(MotionFile, KeysOutOfOrderOrRange) {
    expect_error(
        write_text("decreasing.json", with_keys(R"({"t": 0}, {"t": 1}, {"t": 2}, {"t": 1.5})")),
        {"head.keys[3].t", "times must increase"});
    expect_error(write_text("equal.json", with_keys(R"({"t": 0}, {"t": 1}, {"t": 1})")),
                 {"head.keys[2].t", "times must increase"});
    expect_error(write_text("negative.json", with_keys(R"({"t": -0.5})")),
                 {"head.keys[0].t", "≥ 0"});
    expect_error(write_text("late.json", with_keys(R"({"t": 0}, {"t": 3600.5})")),
                 {"head.keys[1].t", "3600"});
    expect_error(write_text("spin.json", with_keys(R"({"t": 0, "rotate": [0, 3601, 0]})")),
                 {"head.keys[0].rotate[1]", "3600"});
    // 2·10⁴ head radii is 2·10⁵ cm on a 10 cm head: too far; the same number in cm is fine.
    expect_error(write_text("far.json", with_keys(R"({"t": 0, "translate": [0, 0, 20000]})")),
                 {"head.keys[0].translate[2]", "cm"});
    EXPECT_NO_THROW(read_motion(
        write_text("far_cm.json",
                   with_keys(R"({"t": 0, "translate": [0, 0, 20000]})", R"("units": "cm", )")),
        kHead));
    expect_error(write_text("far_pivot.json", R"({"format": "wisp-motion", "version": 1,
        "head": {"pivot": [1e5, 0, 0], "keys": []}})"),
                 {"head.pivot[0]"});
    expect_error(
        write_text("body_order.json",
                   with_keys(R"({"t": 0})", R"("body": {"keys": [{"t": 2}, {"t": 1}]}, )")),
        {"body.keys[1].t", "times must increase"});
    expect_error(write_text("neg_duration.json", with_keys("", R"("duration": -1, )")),
                 {"duration", "≥ 0"});
    expect_error(write_text("gust_amp.json", with_keys("", R"("gust": {"amplitude": -1}, )")),
                 {"gust.amplitude", "≥ 0"});
    expect_error(write_text("gust_freq.json", with_keys("", R"("gust": {"frequency": 0}, )")),
                 {"gust.frequency", "> 0"});
}

TEST(MotionFile, TooManyKeys) {
    std::string keys;
    keys.reserve(kMaxMotionKeys * 12);
    for (size_t i = 0; i <= kMaxMotionKeys; ++i)
        keys += (i ? ",{\"t\":" : "{\"t\":") + std::to_string(i * 0.01) + "}";
    expect_error(write_text("many.json", with_keys(keys)),
                 {"head.keys", std::to_string(kMaxMotionKeys + 1), "at most"});
}

}  // namespace
}  // namespace wisp
