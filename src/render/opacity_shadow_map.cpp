#include "render/opacity_shadow_map.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "render/strand_samples.hpp"

namespace wisp {

LightFrame LightFrame::towards(const Vec3f& to_light) {
    LightFrame f;
    f.w = -to_light.normalized();
    f.u = any_perpendicular(f.w);
    f.v = f.w.cross(f.u);
    return f;
}

namespace {

// Interleaves the low 16 bits of x with zeros.
uint32_t spread_bits(uint32_t x) {
    x &= 0xffffu;
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    x = (x | (x << 1)) & 0x55555555u;
    return x;
}

}  // namespace

std::vector<uint32_t> morton_order(std::span<const Vec2f> points) {
    const size_t n = points.size();
    Box3 box;
    for (const Vec2f& q : points)
        box.extend(Vec3f(q.x(), q.y(), 0.f));
    const Vec3f size =
        box.empty() ? Vec3f(Vec3f::Ones()) : Vec3f(box.size().cwiseMax(Vec3f::Constant(1e-6f)));
    const auto quantize = [](float t) {
        return static_cast<uint32_t>(std::clamp(t, 0.f, 1.f) * 65535.f);
    };
    std::vector<uint64_t> keyed(n);
    for (size_t i = 0; i < n; ++i) {
        const uint32_t code = spread_bits(quantize((points[i].x() - box.lo.x()) / size.x())) |
                              (spread_bits(quantize((points[i].y() - box.lo.y()) / size.y())) << 1);
        keyed[i] = (static_cast<uint64_t>(code) << 32) | i;
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i)
        order[i] = static_cast<uint32_t>(keyed[i]);
    return order;
}

std::vector<uint32_t> light_space_order(const Hair& hair, const LightFrame& light) {
    std::vector<Vec2f> mid(hair.strand_count());
    for (size_t s = 0; s < mid.size(); ++s) {
        const std::span<const Vec3f> p = hair.strand(s);
        const Vec3f q = p.empty() ? Vec3f::Zero() : light.to_light_space(p[p.size() / 2]);
        mid[s] = Vec2f(q.x(), q.y());
    }
    return morton_order(mid);
}

namespace {

constexpr float kFixedPoint = 65536.f;  // deposits are integers in units of 1/65536 of τ

}  // namespace

OpacityShadowMap::OpacityShadowMap(const Hair& hair, const LightFrame& light, const Box3& bounds,
                                   const OpacityShadowMapOptions& options,
                                   std::span<const uint32_t> order)
    : light_(light) {
    std::vector<uint32_t> own_order;
    if (order.size() != hair.strand_count()) {
        own_order = light_space_order(hair, light);
        order = own_order;
    }
    nx_ = ny_ = std::max(1, options.resolution);
    nz_ = std::max(1, options.slices);
    Box3 box;  // the light-space box holding the world box
    for (int k = 0; k < 8; ++k)
        box.extend(light.to_light_space(Vec3f((k & 1) ? bounds.hi.x() : bounds.lo.x(),
                                              (k & 2) ? bounds.hi.y() : bounds.lo.y(),
                                              (k & 4) ? bounds.hi.z() : bounds.lo.z())));
    if (box.empty()) box.extend(Vec3f::Zero());
    const Vec3f size = box.size().cwiseMax(Vec3f::Constant(1e-3f));
    lo_ = box.lo;
    du_ = size.x() / nx_;
    dv_ = size.y() / ny_;
    dw_ = size.z() / nz_;
    inv_depth_ = 1.f / size.z();
    const size_t cells = static_cast<size_t>(nx_) * ny_ * nz_;

    // The depth of the nearest hair in each texel, then a walk over the strands in pieces no
    // longer than a texel that adds each piece's opacity to the cell holding its midpoint, in
    // slabs counted from there.
    const float inv_du = 1.f / du_, inv_dv = 1.f / dv_;
    const float step = 2.f * std::min(du_, dv_);
    const size_t stride = static_cast<size_t>(std::max(1, options.strand_stride));
    const float area_scale =
        options.strand_opacity * static_cast<float>(stride) * kFixedPoint / (du_ * dv_);
    const size_t strands = hair.strand_count();
    const size_t plane = static_cast<size_t>(nx_) * ny_;
    auto texel = [&](const Vec3f& q) {
        const int x = std::clamp(static_cast<int>((q.x() - lo_.x()) * inv_du), 0, nx_ - 1);
        const int y = std::clamp(static_cast<int>((q.y() - lo_.y()) * inv_dv), 0, ny_ - 1);
        return static_cast<size_t>(y) * nx_ + x;
    };
    // Calls visit(q, amount) for every piece's midpoint q (light space) and opacity.
    // visit(grid, q, amount), with `grid` this thread's (looked up once per chunk).
    auto walk = [&](auto& per_thread, auto&& visit) {
        parallel_for(
            (strands + 63) / 64,
            [&](size_t chunk) {
                auto& grid = per_thread.local();
                for (size_t k = chunk * 64; k < std::min(strands, chunk * 64 + 64); ++k) {
                    if (k % stride != 0) continue;
                    const size_t s = order[k];
                    bool first = true;
                    Vec3f prev_q;
                    float prev_w = 0;
                    auto sub = [&](size_t, const Vec3f& b, const Vec3f& c) {
                        return std::min(8, static_cast<int>((c - b).norm() / (4.f * step)) + 1);
                    };
                    for_each_strand_sample<false>(
                        hair, s, options.width_scale, options.tip_width, sub,
                        [&](const StrandSample& sample) {
                            const Vec3f q = light.to_light_space(sample.p);
                            if (!first) {
                                const Vec3f d = q - prev_q;
                                // Only the extent across the light blocks it: a piece seen
                                // end-on by the light casts (almost) nothing.
                                const float across = std::sqrt(d.x() * d.x() + d.y() * d.y());
                                const int n = std::max(1, static_cast<int>(across / step) + 1);
                                const float amount = 0.5f * (prev_w + sample.width) * across *
                                                     area_scale / static_cast<float>(n);
                                for (int k = 0; k < n; ++k)
                                    visit(grid, prev_q + d * ((static_cast<float>(k) + 0.5f) / n),
                                          amount);
                            }
                            first = false;
                            prev_q = q;
                            prev_w = sample.width;
                        });
                }
            },
            1);
    };

    // The nearest hair per texel (a minimum: the same in any order), then the least over each
    // texel and its 8 neighbours, so that a lookup between texels, which reads four of them,
    // finds every one's slabs starting in front of it.
    constexpr float kInf = std::numeric_limits<float>::infinity();
    tbb::enumerable_thread_specific<std::vector<float>> partial_near(
        [&] { return std::vector<float>(plane, kInf); });
    // Along the chords between control points in steps of two texels, cheaper than the
    // pieces' walk (no curve, no widths): a texel stepped over, or one the curve strays into
    // from its chord, is a neighbour of one visited, and the least is taken over neighbours.
    const float texel_step = step;
    parallel_for((strands + 63) / 64,
                 [&](size_t chunk) {
                     std::vector<float>& near = partial_near.local();
                     for (size_t k = chunk * 64; k < std::min(strands, chunk * 64 + 64); ++k) {
                         if (k % stride != 0) continue;
                         const std::span<const Vec3f> p = hair.strand(order[k]);
                         Vec3f a = p.empty() ? Vec3f::Zero() : light.to_light_space(p[0]);
                         for (size_t i = 0; i < p.size(); ++i) {
                             const Vec3f b = light.to_light_space(p[i]);
                             const Vec3f d = b - a;
                             const float across = std::sqrt(d.x() * d.x() + d.y() * d.y());
                             const int n =
                                 std::min(4096, static_cast<int>(across / texel_step) + 1);
                             for (int j = 1; j <= n; ++j) {
                                 const Vec3f q = a + d * (static_cast<float>(j) / n);
                                 float& z = near[texel(q)];
                                 z = std::min(z, q.z());
                             }
                             a = b;
                         }
                     }
                 },
                 1);
    std::vector<float> nearest(plane, kInf);
    for (const std::vector<float>& g : partial_near)
        for (size_t i = 0; i < plane; ++i)
            nearest[i] = std::min(nearest[i], g[i]);
    near_.assign(plane, kInf);
    parallel_for(static_cast<size_t>(ny_), [&](size_t y) {
        for (int x = 0; x < nx_; ++x) {
            float z = kInf;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = static_cast<int>(y) + dy;
                    if (xx >= 0 && xx < nx_ && yy >= 0 && yy < ny_)
                        z = std::min(z, nearest[static_cast<size_t>(yy) * nx_ + xx]);
                }
            near_[y * nx_ + x] = z;
        }
    });

    tbb::enumerable_thread_specific<std::vector<uint32_t>> partial(
        [&] { return std::vector<uint32_t>(cells, 0u); });
    walk(partial, [&](std::vector<uint32_t>& grid, const Vec3f& q, float amount) {
        const size_t t = texel(q);
        const int z = std::clamp(static_cast<int>(slab(q.z() - near_[t])), 0, nz_ - 1);
        grid[static_cast<size_t>(z) * plane + t] += static_cast<uint32_t>(amount + 0.5f);
    });

    // Sum the per-thread grids (integers: any order gives the same sum) and accumulate along
    // the light. The slabs are not blurred across texels: a neighbour's slab k lies at another
    // depth (each texel's slabs start at its own nearest hair), so a blur would move a dense
    // neighbour's opacity to this texel's depths, in front of skin that hair lies behind (the
    // side hair's shadow on a temple).
    std::vector<uint32_t> total(cells, 0u);
    for (const std::vector<uint32_t>& g : partial)
        for (size_t i = 0; i < cells; ++i)
            total[i] += g[i];
    // Running sum along the light into the lookup layout, texel-major (a lookup reads two
    // neighbouring boundaries of four texels).
    tau_.assign(plane * (nz_ + 1), 0.f);
    parallel_for(
        plane,
        [&](size_t texel) {
            float sum = 0;
            float* out = &tau_[texel * (nz_ + 1)];
            out[0] = 0;
            for (int z = 0; z < nz_; ++z) {
                sum += static_cast<float>(total[z * plane + texel]) * (1.f / kFixedPoint);
                out[z + 1] = sum;
            }
        },
        256);
}

float OpacityShadowMap::optical_depth(const Vec3f& p) const {
    if (tau_.empty()) return 0.f;
    const Vec3f q = light_.to_light_space(p);
    // Texel centres for u, v; boundaries for w, evaluated half a slab towards the light so
    // that a strand does not shadow itself.
    const float fx = std::clamp((q.x() - lo_.x()) / du_ - 0.5f, 0.f, nx_ - 1.f);
    const float fy = std::clamp((q.y() - lo_.y()) / dv_ - 0.5f, 0.f, ny_ - 1.f);
    const int x0 = std::min(static_cast<int>(fx), nx_ - 1),
              y0 = std::min(static_cast<int>(fy), ny_ - 1);
    const int x1 = std::min(x0 + 1, nx_ - 1), y1 = std::min(y0 + 1, ny_ - 1);
    const float ax = fx - x0, ay = fy - y0;
    // Each of the four texels in its own slabs, which start at its nearest hair.
    auto column = [&](int x, int y) {
        const size_t t = static_cast<size_t>(y) * nx_ + x;
        const float fz = std::min(slab(q.z() - near_[t]) - 0.5f, static_cast<float>(nz_));
        if (!(fz > 0.f)) return 0.f;  // in front of its hair, or no hair there
        const int z0 = std::min(static_cast<int>(fz), nz_ - 1);
        const float az = std::min(fz - z0, 1.f);
        const float* c = &tau_[t * (nz_ + 1) + z0];
        return c[0] + (c[1] - c[0]) * az;
    };
    const float c00 = column(x0, y0), c10 = column(x1, y0);
    const float c01 = column(x0, y1), c11 = column(x1, y1);
    const float top = c00 + (c10 - c00) * ax;
    const float bottom = c01 + (c11 - c01) * ax;
    return top + (bottom - top) * ay;
}

float OpacityShadowMap::transmittance(const Vec3f& p) const {
    return std::exp(-optical_depth(p));
}

}  // namespace wisp
