#include "render/shadow_depth_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/strand_raster.hpp"  // floor_to_int

namespace wisp {

ShadowDepthMap::ShadowDepthMap(const Mesh& mesh, const LightFrame& light, const Box3& bounds,
                               int resolution)
    : light_(light), n_(std::max(1, resolution)) {
    Box3 box;
    for (int k = 0; k < 8; ++k)
        box.extend(light.to_light_space(Vec3f((k & 1) ? bounds.hi.x() : bounds.lo.x(),
                                              (k & 2) ? bounds.hi.y() : bounds.lo.y(),
                                              (k & 4) ? bounds.hi.z() : bounds.lo.z())));
    if (box.empty()) box.extend(Vec3f::Zero());
    lo_ = box.lo;
    texel_ = std::max(box.size().x(), box.size().y()) / n_;
    texel_ = std::max(texel_, 1e-4f);
    depth_.assign(static_cast<size_t>(n_) * n_, std::numeric_limits<float>::infinity());

    // Serial: a head is ~10⁵ small triangles, a few milliseconds, and a min-depth buffer
    // written from several threads would need atomics for no gain.
    std::vector<Vec3f> q(mesh.vertices.size());
    for (size_t i = 0; i < q.size(); ++i) {
        const Vec3f l = light.to_light_space(mesh.vertices[i]);
        q[i] = Vec3f((l.x() - lo_.x()) / texel_, (l.y() - lo_.y()) / texel_, l.z());
    }
    for (const Vec3i& f : mesh.faces) {
        const Vec3f &a = q[f[0]], &b = q[f[1]], &c = q[f[2]];
        const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        if (std::abs(area) < 1e-12f) continue;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
        const int x1 =
            std::min(n_ - 1, static_cast<int>(std::floor(std::max({a.x(), b.x(), c.x()}))));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
        const int y1 =
            std::min(n_ - 1, static_cast<int>(std::floor(std::max({a.y(), b.y(), c.y()}))));
        const float inv = 1.f / area;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const float px = x + 0.5f, py = y + 0.5f;
                const float w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) * inv;
                const float w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) * inv;
                const float w2 = 1.f - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const float z = w0 * a.z() + w1 * b.z() + w2 * c.z();
                float& d = depth_[static_cast<size_t>(y) * n_ + x];
                d = std::min(d, z);
            }
    }

    // The nearest and farthest depth of each texel's lookup footprint (the 4×4 texels from
    // x − 1, y − 1), texels outside the map counting as empty (+inf): two separable passes.
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const size_t cells = static_cast<size_t>(n_) * n_;
    std::vector<float> row_lo(cells), row_hi(cells);
    for (int y = 0; y < n_; ++y)
        for (int x = 0; x < n_; ++x) {
            float lo = kInf, hi = -kInf;
            for (int i = x - 1; i <= x + 2; ++i) {
                const float d = i < 0 || i >= n_ ? kInf : depth_[static_cast<size_t>(y) * n_ + i];
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            }
            row_lo[static_cast<size_t>(y) * n_ + x] = lo;
            row_hi[static_cast<size_t>(y) * n_ + x] = hi;
        }
    footprint_lo_.assign(cells, kInf);
    footprint_hi_.assign(cells, kInf);
    for (int y = 0; y < n_; ++y)
        for (int x = 0; x < n_; ++x) {
            float lo = kInf, hi = -kInf;
            for (int j = y - 1; j <= y + 2; ++j) {
                const size_t k = static_cast<size_t>(j) * n_ + x;
                lo = std::min(lo, j < 0 || j >= n_ ? kInf : row_lo[k]);
                hi = std::max(hi, j < 0 || j >= n_ ? kInf : row_hi[k]);
            }
            footprint_lo_[static_cast<size_t>(y) * n_ + x] = lo;
            footprint_hi_[static_cast<size_t>(y) * n_ + x] = hi;
        }
}

float ShadowDepthMap::distance_to_surface(const Vec3f& p) const {
    constexpr float kNone = std::numeric_limits<float>::infinity();
    if (depth_.empty()) return kNone;
    const Vec3f l = light_.to_light_space(p);
    const int x = floor_to_int((l.x() - lo_.x()) / texel_),
              y = floor_to_int((l.y() - lo_.y()) / texel_);
    if (x < 0 || y < 0 || x >= n_ || y >= n_) return kNone;
    return std::max(0.f, depth_[static_cast<size_t>(y) * n_ + x] - l.z());
}

float ShadowDepthMap::visibility(const Vec3f& p, float bias) const {
    if (depth_.empty()) return 1.f;
    const Vec3f l = light_.to_light_space(p);
    // Percentage-closer filtering: nine bilinear depth tests a texel apart, which weighs the
    // 4×4 nearest texels by (1 − a, 1, 1, a) / 3 along each axis, so a shadow's edge fades over
    // three texels instead of stepping along the texel grid.
    const float fx = (l.x() - lo_.x()) / texel_ - 0.5f, fy = (l.y() - lo_.y()) / texel_ - 0.5f;
    const int x0 = floor_to_int(fx), y0 = floor_to_int(fy);  // no libm floor: strand_raster.hpp
    const float ax = fx - x0, ay = fy - y0;
    const float z = l.z() - bias - 1.5f * texel_;
    const float wx[4] = {(1.f - ax) / 3.f, 1.f / 3.f, 1.f / 3.f, ax / 3.f};
    const float wy[4] = {(1.f - ay) / 3.f, 1.f / 3.f, 1.f / 3.f, ay / 3.f};
    // Most points are well in front of the head or well behind it: when every texel of the
    // footprint passes (or fails) the test, the sum below is known without reading them. The
    // weights are summed as below, so the result is the same to the bit.
    if (x0 >= 0 && y0 >= 0 && x0 < n_ && y0 < n_) {
        const size_t k = static_cast<size_t>(y0) * n_ + x0;
        if (footprint_hi_[k] < z) return 0.f;
        if (footprint_lo_[k] >= z) {
            float sum = 0.f;
            for (int j = 0; j < 4; ++j) {
                float row = 0.f;
                for (int i = 0; i < 4; ++i)
                    row += wx[i];
                sum += wy[j] * row;
            }
            return sum;
        }
    }
    auto lit = [&](int x, int y) {
        return x < 0 || y < 0 || x >= n_ || y >= n_ || depth_[static_cast<size_t>(y) * n_ + x] >= z
                   ? 1.f
                   : 0.f;
    };
    float sum = 0.f;
    for (int j = 0; j < 4; ++j) {
        float row = 0.f;
        for (int i = 0; i < 4; ++i)
            row += wx[i] * lit(x0 - 1 + i, y0 - 1 + j);
        sum += wy[j] * row;
    }
    return sum;
}

}  // namespace wisp
