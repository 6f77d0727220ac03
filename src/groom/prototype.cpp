#include "groom/prototype.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace wisp {

std::vector<Vec3f> prototype_polyline(const PrototypeSpec& spec) {
    using Kind = PrototypeSpec::Kind;
    if (spec.kind == Kind::kPolyline) return spec.polyline;
    const float length = spec.length;
    if (is_straight(spec)) return {Vec3f::Zero(), Vec3f(0.f, length, 0.f)};
    const float period = spec.kind == Kind::kKinky ? 0.5f * spec.period : spec.period;
    // 64 samples a period resolve every preset far below a hair's width.
    const int count = std::clamp(static_cast<int>(64.f * length / period), 64, 1 << 18);
    const float a = spec.amplitude;
    std::vector<Vec3f> out(count + 1);
    for (int i = 0; i <= count; ++i) {
        const float y = length * static_cast<float>(i) / count;
        const float phase = 2.f * kPi * y / period;
        switch (spec.kind) {
            case Kind::kWavy:
                out[i] = {a * std::sin(phase), y, 0.f};
                break;
            case Kind::kCurly:
                out[i] = {a * (std::cos(phase) - 1.f), y, a * std::sin(phase)};
                break;
            case Kind::kKinky: {
                // A zig-zag of a quarter the radius and a third of the pitch rides radially on
                // the coil.
                const float zig = 1.f + 0.25f * std::sin(3.f * phase);
                out[i] = {a * (zig * std::cos(phase) - 1.f), y, a * zig * std::sin(phase)};
                break;
            }
            default:
                out[i] = {0.f, y, 0.f};
        }
    }
    return out;
}

PrototypeCurve make_prototype_curve(const PrototypeSpec& spec) {
    using Kind = PrototypeSpec::Kind;
    if (spec.kind == Kind::kPolyline)
        return prepare_prototype(spec.polyline, spec.period / 41.f, spec.period);
    PrototypeCurve out;
    out.curve = prototype_polyline(spec);
    out.centre.resize(out.curve.size());
    // The axis of every preset: the wave oscillates about x = 0, the coils about x = -a.
    const float axis_x =
        (spec.kind == Kind::kCurly || spec.kind == Kind::kKinky) && spec.amplitude > 0.f
            ? -spec.amplitude
            : 0.f;
    for (size_t k = 0; k < out.curve.size(); ++k)
        out.centre[k] = Vec3f(axis_x, out.curve[k].y(), 0.f);
    if (is_straight(spec)) {
        // Two points are enough for a line, but decompose() walks samples: densify.
        const size_t count = 257;
        out.curve.resize(count);
        out.centre.resize(count);
        for (size_t k = 0; k < count; ++k)
            out.curve[k] = out.centre[k] = Vec3f(0.f, spec.length * k / (count - 1), 0.f);
    }
    out.centre_arc.resize(out.centre.size());
    out.centre_arc[0] = 0.f;
    for (size_t k = 1; k < out.centre.size(); ++k)
        out.centre_arc[k] = out.centre_arc[k - 1] + (out.centre[k] - out.centre[k - 1]).norm();
    return out;
}

PrototypeCurve prepare_prototype(std::span<const Vec3f> polyline, float spacing, float smoothing) {
    if (polyline.size() < 2) fail("prototype: needs at least 2 points, got ", polyline.size());
    if (!(spacing > 0.f)) fail("prototype: sample spacing must be > 0");
    std::vector<float> arc(polyline.size(), 0.f);
    for (size_t i = 1; i < polyline.size(); ++i)
        arc[i] = arc[i - 1] + (polyline[i] - polyline[i - 1]).norm();
    const float total = arc.back();
    if (!(total > 0.f)) fail("prototype: the polyline has zero length");
    const size_t count = std::min<size_t>(static_cast<size_t>(total / spacing) + 1, 1u << 20);
    PrototypeCurve out;
    out.curve.resize(count);
    size_t seg = 0;
    for (size_t k = 0; k < count; ++k) {
        const float a = std::min(static_cast<float>(k) * spacing, total);
        while (seg + 2 < polyline.size() && arc[seg + 1] < a)
            ++seg;
        const float len = arc[seg + 1] - arc[seg];
        const float f = len > 0.f ? std::clamp((a - arc[seg]) / len, 0.f, 1.f) : 0.f;
        out.curve[k] = (1.f - f) * polyline[seg] + f * polyline[seg + 1];
    }
    // Centred moving average with prefix sums (double, so long curves keep precision).
    const int half = std::max(0, static_cast<int>(std::lround(0.5f * smoothing / spacing - 0.5f)));
    std::vector<Vec3d> prefix(count + 1, Vec3d::Zero());
    for (size_t k = 0; k < count; ++k)
        prefix[k + 1] = prefix[k] + out.curve[k].cast<double>();
    out.centre.resize(count);
    for (size_t k = 0; k < count; ++k) {
        const int h = std::min<int>({half, static_cast<int>(k), static_cast<int>(count - 1 - k)});
        const Vec3d sum = prefix[k + h + 1] - prefix[k - h];
        out.centre[k] = (sum / static_cast<double>(2 * h + 1)).cast<float>();
    }
    out.centre_arc.resize(count);
    out.centre_arc[0] = 0.f;
    for (size_t k = 1; k < count; ++k)
        out.centre_arc[k] = out.centre_arc[k - 1] + (out.centre[k] - out.centre[k - 1]).norm();
    return out;
}

std::vector<Vec3f> decompose(const PrototypeCurve& proto, float segment) {
    std::vector<Vec3f> details, work;
    decompose(proto, segment, details, work);
    return details;
}

void decompose(const PrototypeCurve& proto, float segment, std::vector<Vec3f>& details,
               std::vector<Vec3f>& work) {
    details.clear();
    const size_t k_count = proto.centre.size();
    if (k_count < 2 || !(segment > 0.f)) return;
    const float total = proto.centre_arc.back();
    const size_t n = static_cast<size_t>(total / segment) + 1;
    if (n < 3) return;
    work.resize(2 * n);
    Vec3f* const c = work.data();
    Vec3f* const p = work.data() + n;
    size_t j = 0;
    for (size_t i = 0; i < n; ++i) {
        const float a = static_cast<float>(i) * segment;
        while (j + 2 < k_count && proto.centre_arc[j + 1] < a)
            ++j;
        const float len = proto.centre_arc[j + 1] - proto.centre_arc[j];
        const float f = len > 0.f ? std::clamp((a - proto.centre_arc[j]) / len, 0.f, 1.f) : 0.f;
        c[i] = (1.f - f) * proto.centre[j] + f * proto.centre[j + 1];
        p[i] = (1.f - f) * proto.curve[j] + f * proto.curve[j + 1];
    }
    details.resize(n);
    Frame frame;
    for (size_t i = 0; i < n; ++i) {
        const size_t s = std::min(i, n - 2);
        Vec3f t = c[s + 1] - c[s];
        t = t.norm() > 0.f ? Vec3f(t.normalized()) : Vec3f::UnitY();
        // Most centre lines are straight (every preset's): skip the rotation where the
        // tangent does not turn.
        if (i == 0)
            frame = frame_from(t, Vec3f::UnitX());
        else if (t != frame.t)
            frame = transport(frame, t);
        details[i] = frame.to_local(p[i] - c[i]);
    }
}

}  // namespace wisp
