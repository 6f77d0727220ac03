#include "core/catmull_rom.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace wisp {
namespace {

// The four control points of segment i (0-based, between points[i] and points[i+1]),
// with phantom end points.
void segment_points(std::span<const Vec3f> p, size_t i, Vec3f& a, Vec3f& b, Vec3f& c, Vec3f& d) {
    const size_t n = p.size();
    b = p[i];
    c = p[i + 1];
    a = i > 0 ? p[i - 1] : Vec3f(2.f * b - c);
    d = i + 2 < n ? p[i + 2] : Vec3f(2.f * c - b);
}

void locate(size_t n, float s, size_t& seg, float& t) {
    const float x = std::clamp(s, 0.f, 1.f) * static_cast<float>(n - 1);
    seg = std::min(static_cast<size_t>(x), n - 2);
    t = x - static_cast<float>(seg);
}

}  // namespace

Vec3f catmull_rom_eval(std::span<const Vec3f> points, float s) {
    if (points.size() == 1) return points[0];
    size_t seg;
    float t;
    locate(points.size(), s, seg, t);
    Vec3f a, b, c, d;
    segment_points(points, seg, a, b, c, d);
    return catmull_rom(a, b, c, d, t);
}

Vec3f catmull_rom_derivative(std::span<const Vec3f> points, float s) {
    if (points.size() == 1) return Vec3f::Zero();
    size_t seg;
    float t;
    locate(points.size(), s, seg, t);
    Vec3f a, b, c, d;
    segment_points(points, seg, a, b, c, d);
    return catmull_rom_tangent(a, b, c, d, t) * static_cast<float>(points.size() - 1);
}

void catmull_rom_sample(std::span<const Vec3f> points, int per_segment, std::span<Vec3f> out) {
    const size_t n = points.size();
    size_t k = 0;
    for (size_t i = 0; i + 1 < n; ++i) {
        Vec3f a, b, c, d;
        segment_points(points, i, a, b, c, d);
        for (int j = 0; j < per_segment; ++j)
            out[k++] = catmull_rom(a, b, c, d, static_cast<float>(j) / per_segment);
    }
    out[k] = points[n - 1];
}

void catmull_rom_resample(std::span<const Vec3f> points, std::span<const float> widths, float width,
                          std::span<Vec3f> out_points, std::span<float> out_widths) {
    const size_t n = points.size(), N = out_points.size();
    const auto width_at = [&](size_t i) { return widths.empty() ? width : widths[i]; };
    if (n == 1 || N == 0) {
        for (size_t k = 0; k < N; ++k) {
            out_points[k] = points[0];
            out_widths[k] = width_at(0);
        }
        return;
    }
    constexpr int kPerSegment = 8;
    const size_t m = (n - 1) * kPerSegment + 1;
    // Rewritten for every strand: a per-thread scratch, not an allocation per strand.
    static thread_local std::vector<Vec3f> dense;
    static thread_local std::vector<float> arc;
    dense.resize(m);
    arc.resize(m);
    // Each segment's cubic in power form, evaluated by Horner: a third of the work of
    // catmull_rom() per sample (most of a resampling writer's time). t = 0 gives the control
    // point exactly; the tip is set exactly.
    for (size_t i = 0; i + 1 < n; ++i) {
        Vec3f a, b, c, d;
        segment_points(points, i, a, b, c, d);
        const Vec3f k1 = 0.5f * (c - a), k2 = 0.5f * (2.f * a - 5.f * b + 4.f * c - d),
                    k3 = 0.5f * (3.f * (b - c) + d - a);
        for (int j = 0; j < kPerSegment; ++j) {
            const float t = static_cast<float>(j) / kPerSegment;
            dense[i * kPerSegment + j] = ((k3 * t + k2) * t + k1) * t + b;
        }
    }
    dense[m - 1] = points[n - 1];
    arc[0] = 0.f;
    for (size_t i = 1; i < m; ++i)
        arc[i] = arc[i - 1] + (dense[i] - dense[i - 1]).norm();
    const float total = arc[m - 1];
    size_t j = 0;  // dense segment [j, j+1] holding the target, moves forward only
    for (size_t k = 0; k < N; ++k) {
        const float f = N > 1 ? static_cast<float>(k) / static_cast<float>(N - 1) : 0.f;
        float u;  // position in dense samples, in [0, m-1]
        if (total > 0.f) {
            const float target = f * total;
            while (j + 2 < m && arc[j + 1] < target)
                ++j;
            const float len = arc[j + 1] - arc[j];
            const float t = len > 0.f ? std::clamp((target - arc[j]) / len, 0.f, 1.f) : 0.f;
            u = static_cast<float>(j) + t;
        } else {
            u = f * static_cast<float>(m - 1);
        }
        if (k + 1 == N) u = static_cast<float>(m - 1);
        const size_t a = std::min(static_cast<size_t>(u), m - 2);
        const float t = u - static_cast<float>(a);
        out_points[k] = dense[a] + t * (dense[a + 1] - dense[a]);
        // Widths are linear in the spline parameter between control points.
        const float s = u / kPerSegment;
        const size_t c = std::min(static_cast<size_t>(s), n - 2);
        const float ct = s - static_cast<float>(c);
        out_widths[k] = width_at(c) + ct * (width_at(c + 1) - width_at(c));
    }
}

}  // namespace wisp
