#include "groom/master.hpp"

#include <algorithm>
#include <cmath>

namespace wisp {

Vec3f protrusion_direction(const SurfacePoint& root, const Vec3f& growth, float protrusion) {
    const Vec3f& n = root.normal;
    Vec3f flow = growth - growth.dot(n) * n;
    if (flow.norm() < 1e-3f) {
        // Growth along the normal: hair falls toward the back.
        flow = -Vec3f::UnitZ() - (-Vec3f::UnitZ()).dot(n) * n;
        if (flow.norm() < 1e-3f) flow = any_perpendicular(n);
    }
    flow.normalize();
    const float angle = std::clamp(protrusion, 0.f, 1.f) * 0.5f * kPi;
    return (std::cos(angle) * flow + std::sin(angle) * n).normalized();
}

void update_master(Masters& m, size_t w, int i0, int i1) {
    const size_t n = static_cast<size_t>(m.points);
    const size_t base = w * n;
    const size_t lo = static_cast<size_t>(std::max(i0, 0));
    const size_t hi = std::min(static_cast<size_t>(std::max(i1, 0)), n);
    if (lo >= hi) return;
    Frame f = lo == 0 ? m.root_frame[w] : m.frames[base + lo - 1];
    for (size_t i = lo; i < hi; ++i) {
        const size_t s = std::min(i, n - 2);
        Vec3f t = m.outline[base + s + 1] - m.outline[base + s];
        const float len = t.norm();
        t = len > 0.f ? Vec3f(t / len) : f.t;
        if (s == i) f = transport(f, t);  // i = 0 turns the root frame onto the first segment
        m.frames[base + i] = f;
        m.control[base + i] = m.outline[base + i] + f.to_world(m.details[base + i]);
    }
}

void update_master(Masters& m, size_t w) {
    update_master(m, w, 0, m.points);
}

}  // namespace wisp
