#include "geometry/ear_envelope.hpp"

#include <algorithm>
#include <cmath>

namespace wisp {

float EarEnvelope::distance(const Vec3f& p) const {
    const Vec3f d = p - center;
    const Vec3f up = forward.cross(out);
    const float q = d.dot(out) / radii.x(), w = d.dot(up) / radii.y(),
                v = d.dot(forward) / radii.z();
    const float q2 = q * q, r2 = w * w + v * v;
    const float g = q2 * q2 + r2 * r2;
    // f = g^¼ − 1 is zero on the surface and grows about linearly with distance; its gradient
    // is ∇g / (4 g^¾).
    const float f = std::sqrt(std::sqrt(g)) - 1.f;
    const Vec3f grad_g(4.f * q2 * q / radii.x(), 4.f * r2 * w / radii.y(),
                       4.f * r2 * v / radii.z());
    const float gn = grad_g.norm();
    if (!(gn > 0.f)) return -radii.minCoeff();
    return f * 4.f * std::pow(g, 0.75f) / gn;
}

std::vector<EarEnvelope> ear_envelopes(const Mesh& mesh, const Landmarks& l) {
    const float h = l.height;
    if (!(h > 0.f)) return {};
    const Vec3f forward = Vec3f(l.forward.x(), 0.f, l.forward.z()).normalized();
    const Vec3f left = Vec3f::UnitY().cross(forward);
    std::vector<EarEnvelope> out;
    for (const Vec3f& ear : {l.ear_left, l.ear_right}) {
        const float side = (ear - l.center).dot(left) >= 0.f ? 1.f : -1.f;
        const Vec3f across = side * left;
        const float outermost = (ear - l.center).dot(across);
        // The ear: skin near the landmark standing out nearly as far as it does.
        float up_lo = INFINITY, up_hi = -INFINITY, fw_lo = INFINITY, fw_hi = -INFINITY;
        float most = -INFINITY;
        size_t count = 0;
        for (const Vec3f& v : mesh.vertices) {
            if ((v - ear).squaredNorm() > 0.04f * h * h) continue;
            const Vec3f d = v - l.center;
            const float a = d.dot(across);
            if (a < outermost - 0.06f * h) continue;
            most = std::max(most, a);
            up_lo = std::min(up_lo, d.y()), up_hi = std::max(up_hi, d.y());
            fw_lo = std::min(fw_lo, d.dot(forward)), fw_hi = std::max(fw_hi, d.dot(forward));
            ++count;
        }
        if (count < 8) return {};
        EarEnvelope e;
        e.out = across;
        e.forward = forward;
        const float r_across = 0.12f * h;
        e.radii = Vec3f(r_across, 0.5f * (up_hi - up_lo) / 0.7f + 0.01f * h,
                        0.5f * (fw_hi - fw_lo) / 0.7f + 0.01f * h);
        e.center = l.center + (most + 0.01f * h - r_across) * across +
                   0.5f * (up_lo + up_hi) * Vec3f::UnitY() + 0.5f * (fw_lo + fw_hi) * forward;
        out.push_back(e);
    }
    return out;
}

}  // namespace wisp
