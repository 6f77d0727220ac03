#include "core/catmull_rom.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace wisp
