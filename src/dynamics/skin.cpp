#include "dynamics/skin.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/parallel.hpp"

namespace wisp {

StrandBinding bind_strands(const Hair& rest, const Hierarchy& h) {
    if (rest.strand_count() != h.strand_gc.size())
        fail("dynamics: the hair has ", rest.strand_count(), " strands, the hierarchy ",
             h.strand_gc.size());
    StrandBinding b;
    b.u.resize(rest.point_count());
    b.offset.resize(rest.point_count());
    const int n = h.sections;
    parallel_for(
        rest.strand_count(),
        [&](size_t s) {
            const auto strand = rest.strand(s);
            const uint32_t first = rest.offsets[s];
            float total = 0;
            for (size_t i = 1; i < strand.size(); ++i)
                total += (strand[i] - strand[i - 1]).norm();
            const uint32_t g = h.strand_gc[s];
            float walked = 0;
            for (size_t i = 0; i < strand.size(); ++i) {
                if (i > 0) walked += (strand[i] - strand[i - 1]).norm();
                const float u =
                    total > 0 ? std::min(walked / total, 1.f) * static_cast<float>(n - 1) : 0.f;
                const int k = std::min(static_cast<int>(u), n - 2);
                const float f = u - static_cast<float>(k);
                const Vec3f centre = (1 - f) * h.rest[h.node(g, k)] + f * h.rest[h.node(g, k + 1)];
                b.u[first + i] = u;
                b.offset[first + i] = strand[i] - centre;
            }
        },
        256);
    return b;
}

void skin_strands(const Hierarchy& h, const StrandBinding& b, std::span<const Vec3f> positions,
                  std::span<const Mat3f> rotations, Hair& out) {
    const int n = h.sections;
    const uint32_t finest = h.finest_begin();
    parallel_for(
        out.strand_count(),
        [&](size_t s) {
            const uint32_t g = h.strand_gc[s];
            const size_t r = static_cast<size_t>(g - finest) * n;
            const Vec3f* x = positions.data() + h.node(g, 0);
            for (uint32_t i = out.offsets[s]; i < out.offsets[s + 1]; ++i) {
                const float u = b.u[i];
                const int k = std::min(static_cast<int>(u), n - 2);
                const float f = u - static_cast<float>(k);
                const Vec3f& o = b.offset[i];
                out.points[i] = (1 - f) * (x[k] + rotations[r + k] * o) +
                                f * (x[k + 1] + rotations[r + k + 1] * o);
            }
        },
        256);
}

}  // namespace wisp
