#include "groom/clumps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace {

// Masters leaving the scalp further apart than this (cos 45°) never share a clump: across
// a parting, or where the growth field turns, their tips go different ways.
constexpr float kSameWay = 0.7071f;

// A uniform grid of buckets over the master roots, for the guides near a root.
class Buckets {
  public:
    Buckets(std::span<const SurfacePoint> roots, float cell) : cell_(cell) {
        Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
        for (const SurfacePoint& r : roots) {
            lo = lo.cwiseMin(r.position);
            hi = hi.cwiseMax(r.position);
        }
        origin_ = lo;
        for (int a = 0; a < 3; ++a)
            dims_[a] = std::clamp(static_cast<int>((hi[a] - lo[a]) / cell_) + 1, 1, 256);
        items_.resize(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2]);
    }
    Vec3i cell_of(const Vec3f& p) const {
        Vec3i c;
        for (int a = 0; a < 3; ++a)
            c[a] = std::clamp(static_cast<int>((p[a] - origin_[a]) / cell_), 0, dims_[a] - 1);
        return c;
    }
    void add(const Vec3f& p, int32_t id) { items_[index(cell_of(p))].push_back(id); }
    // f(id) for every id added within `reach` cells of p's cell, in cell then insertion order.
    template <typename F>
    void near(const Vec3f& p, int reach, F&& f) const {
        const Vec3i c = cell_of(p);
        for (int z = std::max(c[2] - reach, 0); z <= std::min(c[2] + reach, dims_[2] - 1); ++z)
            for (int y = std::max(c[1] - reach, 0); y <= std::min(c[1] + reach, dims_[1] - 1); ++y)
                for (int x = std::max(c[0] - reach, 0); x <= std::min(c[0] + reach, dims_[0] - 1);
                     ++x)
                    for (const int32_t id : items_[index(Vec3i(x, y, z))])
                        f(id);
    }

  private:
    size_t index(const Vec3i& c) const {
        return (static_cast<size_t>(c[2]) * dims_[1] + c[1]) * dims_[0] + c[0];
    }
    float cell_;
    Vec3f origin_ = Vec3f::Zero();
    Vec3i dims_ = Vec3i::Ones();
    std::vector<std::vector<int32_t>> items_;  // one list per cell, not per root
};

}  // namespace

ClumpGuides clump_guides(const ClumpSpec& spec, const Scalp& scalp, const Masters& masters,
                         std::span<const int32_t> wisp_group) {
    const size_t w_count = masters.count();
    ClumpGuides result;
    std::vector<int32_t>& guide = result.guide;
    guide.resize(w_count);
    for (size_t w = 0; w < w_count; ++w)
        guide[w] = static_cast<int32_t>(w);
    if (w_count == 0 || !(spec.pull > 0.f)) return result;
    const MapSampler size_map(spec.size, scalp);
    std::vector<float>& size = result.size;
    size.resize(w_count);
    float largest = 0.f;
    for (size_t w = 0; w < w_count; ++w) {
        size[w] = size_map(masters.roots[w]);
        if (!(size[w] >= 0.f) || !std::isfinite(size[w]))
            fail("clump.size: the map gives ", size[w], " cm at a root: it must be ≥ 0");
        largest = std::max(largest, size[w]);
    }
    if (!(largest > 0.f)) return result;
    const auto group = [&](size_t w) { return wisp_group.empty() ? 0 : wisp_group[w]; };
    const auto can_share = [&](size_t a, size_t b) {
        return group(a) == group(b) && masters.direction[a].dot(masters.direction[b]) >= kSameWay;
    };
    // Cells of the largest size: a guide within 1.5 sizes lies at most two cells away.
    Buckets guides(masters.roots, largest);
    std::vector<uint8_t> is_guide(w_count, 0);
    for (size_t w = 0; w < w_count; ++w) {
        const Vec3f& p = masters.roots[w].position;
        bool covered = false;
        guides.near(p, 1, [&](int32_t g) {
            covered = covered || ((masters.roots[g].position - p).norm() < size[w] &&
                                  can_share(w, static_cast<size_t>(g)));
        });
        if (covered) continue;
        is_guide[w] = 1;
        guides.add(p, static_cast<int32_t>(w));
    }
    for (size_t w = 0; w < w_count; ++w) {
        if (is_guide[w]) continue;
        const Vec3f& p = masters.roots[w].position;
        float best = 1.5f * size[w];
        guides.near(p, 2, [&](int32_t g) {
            const float d = (masters.roots[g].position - p).norm();
            // Ties go to the lower id, whatever order the cells give them in.
            if ((d < best || (d == best && g < guide[w])) && can_share(w, static_cast<size_t>(g))) {
                best = d;
                guide[w] = g;
            }
        });
    }
    return result;
}

void sub_clump_centres(const ClumpSpec& spec, const Roots& roots, std::span<const uint32_t> ids,
                       std::span<const int32_t> wisp, std::span<uint32_t> out) {
    const uint32_t count = static_cast<uint32_t>(std::max(spec.sub_count, 1));
    for (size_t i = 0; i < ids.size(); ++i) {
        const uint32_t first = roots.wisp_offsets[static_cast<size_t>(wisp[i])];
        const uint32_t last =
            std::min(roots.wisp_offsets[static_cast<size_t>(wisp[i]) + 1], first + count);
        const Vec3f& p = roots.members[ids[i]].position;
        uint32_t best = ids[i];
        float nearest = std::numeric_limits<float>::infinity();
        for (uint32_t c = first; c < last; ++c) {
            const float d = (roots.members[c].position - p).squaredNorm();
            if (d < nearest) {
                nearest = d;
                best = c;
            }
        }
        out[i] = best;
    }
}

std::vector<float> clump_profile(float pull, float shape, int n) {
    std::vector<float> p(static_cast<size_t>(std::max(n, 0)), 0.f);
    if (!(pull > 0.f)) return p;
    for (int k = 0; k < n; ++k) {
        const float s = n > 1 ? static_cast<float>(k) / static_cast<float>(n - 1) : 1.f;
        p[static_cast<size_t>(k)] = pull * std::pow(s, shape);
    }
    return p;
}

Vec3f clump_point(const Masters& masters, size_t w, size_t g, size_t k, float a) {
    const size_t n = static_cast<size_t>(masters.points);
    const Vec3f& own = masters.outline[w * n + k];
    const Vec3f& guide = masters.outline[g * n + k];
    const Vec3f own_detail = masters.control[w * n + k] - own;
    const Vec3f guide_detail = masters.control[g * n + k] - guide;
    const Vec3f blend = (1.f - a) * own_detail + a * guide_detail;
    const float size = (1.f - a) * own_detail.norm() + a * guide_detail.norm();
    const float length = blend.norm();
    // Where the two are nearly opposite the blend's direction is unsure: let the detail
    // shrink there rather than turn sharply.
    const float scale = length > 0.25f * size ? size / length : (length > 0.f ? 4.f : 0.f);
    return own + a * (guide - own) + scale * blend;
}

float clump_share(uint64_t seed, uint64_t id, float variation) {
    Rng rng(seed, Stream::kClump, id);
    return 1.f - variation * rng.uniform();
}

}  // namespace wisp
