#include "dynamics/live_motion.hpp"

#include <cmath>

#include "core/error.hpp"

namespace wisp {

namespace {

bool same_pose(const MotionKey& a, const MotionKey& b) {
    return a.rotate == b.rotate && a.translate == b.translate;
}

}  // namespace

void check_live_key(const MotionKey& k, const char* what) {
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(k.rotate[c]) || std::abs(k.rotate[c]) > kMaxMotionRotate)
            fail("live motion: the ", what, "'s rotation must be finite and within ±",
                 kMaxMotionRotate, " degrees");
        if (!std::isfinite(k.translate[c]) || std::abs(k.translate[c]) > kMaxMotionTranslate)
            fail("live motion: the ", what, "'s translation must be finite and within ±",
                 kMaxMotionTranslate, " cm");
    }
}

void check_wind(const Vec3f& wind, float gust_amplitude, float gust_frequency) {
    if (!wind.allFinite() || wind.norm() > 1e5f || !std::isfinite(gust_amplitude) ||
        std::abs(gust_amplitude) > 1e5f || !std::isfinite(gust_frequency) || gust_frequency < 0 ||
        gust_frequency > 100)
        fail(
            "live motion: wind must be finite and within 1000 m/s, gust frequency in "
            "[0, 100] Hz");
}

LiveMotion::LiveMotion(const HeadFrame& head, double fps) {
    if (!(fps > 0) || !std::isfinite(fps) || fps > 1000)
        fail("live motion: fps must be in (0, 1000], got ", fps);
    interval_ = 1.0 / fps;
    motion_.name = "live";
    motion_.head.pivot = neck_pivot(head);
    motion_.body.pivot = hips_pivot(head);
    append(0, MotionKey{}, MotionKey{});
    append(interval_, MotionKey{}, MotionKey{});
}

void LiveMotion::append(double time, const MotionKey& head, const MotionKey& body) {
    MotionKey h = head, b = body;
    h.time = b.time = time;
    motion_.head.keys.push_back(h);
    motion_.body.keys.push_back(b);
    motion_.duration = time;
}

void LiveMotion::drive(int frame, const MotionKey& head, const MotionKey& body) {
    if (frame != frames_) fail("live motion: frame ", frame, " driven, expected frame ", frames_);
    check_live_key(head, "head");
    check_live_key(body, "body");
    ++frames_;
    const auto& hk = motion_.head.keys;
    const auto& bk = motion_.body.keys;
    const size_t n = hk.size();
    const bool to_last = same_pose(head, hk[n - 1]) && same_pose(body, bk[n - 1]);
    const bool stopped = same_pose(hk[n - 2], hk[n - 1]) && same_pose(bk[n - 2], bk[n - 1]);
    if (to_last && stopped) return;
    // Room for the most one drive appends (three keys); past it the track keeps its last
    // target, a stop, since it was never left moving with room for only a stop.
    if (n + 3 > kMaxMotionKeys || (frame + 3) * interval_ > kMaxMotionTime) {
        full_ = true;
        if (!stopped) append(hk[n - 1].time + interval_, hk[n - 1], bk[n - 1]);
        return;
    }
    // Key times are whole frames from 0, so a recording read back has the same doubles.
    const auto at = [&](double frames) { return frames * interval_; };
    const double now = frame;
    const double last = std::round(hk[n - 1].time / interval_);
    if (stopped) {
        double start = last;
        if (now > last) {
            append(at(now), hk[n - 1], bk[n - 1]);
            start = now;
        }
        append(at(start + 1), hk[n - 1], bk[n - 1]);
        append(at(start + 2), head, body);
        return;
    }
    // Moving: one frame after the last key (two frames ahead of now in the steady state).
    append(at(last + 1), to_last ? hk[n - 1] : head, to_last ? bk[n - 1] : body);
}

void LiveMotion::hold(int frame) {
    const MotionKey h = head_target(), b = body_target();
    drive(frame, h, b);
}

void LiveMotion::set_wind(const Vec3f& wind, float gust_amplitude, float gust_frequency) {
    check_wind(wind, gust_amplitude, gust_frequency);
    motion_.wind = wind;
    motion_.gust_amplitude = gust_amplitude;
    motion_.gust_frequency = gust_frequency;
}

MotionKey key_about(const MotionTrack& track, double t, const Vec3f& pivot) {
    MotionKey k = track.key_at(t);
    const RigidTransform x = track.at(t);
    // world = x.translation + R·p = translate' + pivot + R·(p − pivot)
    k.translate = x.translation - pivot + x.rotation * pivot;
    return k;
}

}  // namespace wisp
