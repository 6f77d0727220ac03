#include "dynamics/skin.hpp"

#include <algorithm>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

namespace {

// A point at u along a finest GC with rest offset o; x, rotations: the GC's first node's.
inline Vec3f skinned(int n, float u, const Vec3f& o, const Vec3f* x, const Mat3f* rotations) {
    const int k = std::min(static_cast<int>(u), n - 2);
    const float f = u - static_cast<float>(k);
    return (1 - f) * (x[k] + rotations[k] * o) + f * (x[k + 1] + rotations[k + 1] * o);
}

// Point i of the rest hair.
inline Vec3f skinned(const Hierarchy& h, const StrandBinding& b, const Vec3f* x,
                     const Mat3f* rotations, uint32_t i) {
    return skinned(h.sections, b.u[i], b.offset[i], x, rotations);
}

}  // namespace

void skin_strands(const Hierarchy& h, const StrandBinding& b, std::span<const Vec3f> positions,
                  std::span<const Mat3f> rotations, Hair& out) {
    const uint32_t finest = h.finest_begin();
    parallel_for(
        out.strand_count(),
        [&](size_t s) {
            const uint32_t g = h.strand_gc[s];
            const Vec3f* x = positions.data() + h.node(g, 0);
            const Mat3f* m = rotations.data() + static_cast<size_t>(g - finest) * h.sections;
            for (uint32_t i = out.offsets[s]; i < out.offsets[s + 1]; ++i)
                out.points[i] = skinned(h, b, x, m, i);
        },
        256);
}

void skin_strands(const Hierarchy& h, const StrandBinding& b, std::span<const Vec3f> positions,
                  std::span<const Mat3f> rotations, std::span<const uint32_t> offsets,
                  std::span<const uint32_t> strands, std::span<Vec3f> points) {
    // Where each listed strand's points start in `points`: a running sum, computed in blocks
    // so the parallel loop below needs no allocation per strand.
    const uint32_t finest = h.finest_begin();
    constexpr size_t kBlock = 256;
    const size_t blocks = (strands.size() + kBlock - 1) / kBlock;
    std::vector<size_t> block_start(blocks + 1, 0);
    for (size_t j = 0; j < strands.size(); ++j) {
        const uint32_t s = strands[j];
        if (s + 1 >= offsets.size()) fail("dynamics: strand ", s, " is not in the hair");
        block_start[j / kBlock + 1] += offsets[s + 1] - offsets[s];
    }
    for (size_t k = 0; k < blocks; ++k)
        block_start[k + 1] += block_start[k];
    if (block_start[blocks] != points.size())
        fail("dynamics: ", points.size(), " points given for strands holding ",
             block_start[blocks]);
    parallel_for(
        blocks,
        [&](size_t k) {
            size_t at = block_start[k];
            const size_t end = std::min(strands.size(), (k + 1) * kBlock);
            for (size_t j = k * kBlock; j < end; ++j) {
                const uint32_t s = strands[j];
                const uint32_t g = h.strand_gc[s];
                const Vec3f* x = positions.data() + h.node(g, 0);
                const Mat3f* m = rotations.data() + static_cast<size_t>(g - finest) * h.sections;
                for (uint32_t i = offsets[s]; i < offsets[s + 1]; ++i)
                    points[at++] = skinned(h, b, x, m, i);
            }
        },
        1);
}

SubsetBinding bind_subset(const Hierarchy& h, const StrandBinding& b,
                          std::span<const uint32_t> offsets, std::span<const uint32_t> strands) {
    SubsetBinding out;
    out.strands.assign(strands.begin(), strands.end());
    out.gc.resize(strands.size());
    out.first.resize(strands.size() + 1);
    out.first[0] = 0;
    for (size_t j = 0; j < strands.size(); ++j) {
        const uint32_t s = strands[j];
        if (s + 1 >= offsets.size() || s >= h.strand_gc.size())
            fail("dynamics: strand ", s, " is not in the hair");
        out.gc[j] = h.strand_gc[s];
        out.first[j + 1] = out.first[j] + (offsets[s + 1] - offsets[s]);
    }
    out.u.resize(out.first.back());
    out.offset.resize(out.first.back());
    for (size_t j = 0; j < strands.size(); ++j) {
        const uint32_t s = strands[j];
        std::copy(b.u.begin() + offsets[s], b.u.begin() + offsets[s + 1],
                  out.u.begin() + out.first[j]);
        std::copy(b.offset.begin() + offsets[s], b.offset.begin() + offsets[s + 1],
                  out.offset.begin() + out.first[j]);
    }
    return out;
}

namespace {

#if defined(__SSE2__)
// x, y, z, 0 from three floats, reading none past them.
inline __m128 load3(const float* p) {
    return _mm_movelh_ps(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(p))),
                         _mm_load_ss(p + 2));
}

// Strands of up to this many sections keep their nodes' columns in registers' reach.
constexpr int kMaxSseSections = 64;
#endif

// skin_strands() of a subset, written as float32 triples from `out` (#P' × 3 floats).
void skin_subset(const Hierarchy& h, const SubsetBinding& subset, std::span<const Vec3f> positions,
                 std::span<const Mat3f> rotations, size_t count, float* out) {
    if (count != subset.point_count())
        fail("dynamics: ", count, " points given for strands holding ", subset.point_count());
    const uint32_t finest = h.finest_begin();
    const int n = h.sections;
    constexpr size_t kBlock = 256;  // strands
    const size_t strands = subset.gc.size();
    parallel_for((strands + kBlock - 1) / kBlock, [&](size_t block) {
        const size_t end = std::min(strands, (block + 1) * kBlock);
#if defined(__SSE2__)
        // skinned() four lanes at a time, the same operations in the same order, so the same
        // bits: Eigen's M·o is o₀·M₀ + (o₁·M₁ + o₂·M₂) per row (its unrolled reduction halves
        // the sum), the columns loaded once per strand. Most of skinning was the scalar
        // arithmetic of the two 3×3 products per point.
        if (n >= 2 && n <= kMaxSseSections) {
            __m128 columns[kMaxSseSections][3], nodes[kMaxSseSections];
            for (size_t j = block * kBlock; j < end; ++j) {
                const uint32_t g = subset.gc[j];
                const Vec3f* x = positions.data() + h.node(g, 0);
                const Mat3f* m = rotations.data() + static_cast<size_t>(g - finest) * n;
                for (int k = 0; k < n; ++k) {
                    nodes[k] = load3(x[k].data());
                    for (int c = 0; c < 3; ++c)
                        columns[k][c] = load3(m[k].data() + 3 * c);
                }
                const auto at = [&](int k, __m128 o0, __m128 o1, __m128 o2) {
                    return _mm_add_ps(nodes[k],
                                      _mm_add_ps(_mm_mul_ps(columns[k][0], o0),
                                                 _mm_add_ps(_mm_mul_ps(columns[k][1], o1),
                                                            _mm_mul_ps(columns[k][2], o2))));
                };
                const uint32_t first = subset.first[j], last = subset.first[j + 1];
                for (uint32_t i = first; i < last; ++i) {
                    const float u = subset.u[i];
                    const int k = std::min(static_cast<int>(u), n - 2);
                    const float f = u - static_cast<float>(k);
                    const __m128 o = load3(subset.offset[i].data());
                    const __m128 o0 = _mm_shuffle_ps(o, o, 0x00), o1 = _mm_shuffle_ps(o, o, 0x55),
                                 o2 = _mm_shuffle_ps(o, o, 0xaa);
                    const __m128 p = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(1 - f), at(k, o0, o1, o2)),
                                                _mm_mul_ps(_mm_set1_ps(f), at(k + 1, o0, o1, o2)));
                    float* to = out + 3 * size_t{i};
                    if (i + 1 < last) {
                        _mm_storeu_ps(to, p);  // its fourth lane is the next point's x, next
                    } else {
                        _mm_storel_pi(reinterpret_cast<__m64*>(to), p);
                        _mm_store_ss(to + 2, _mm_movehl_ps(p, p));
                    }
                }
            }
            return;
        }
#endif
        for (size_t j = block * kBlock; j < end; ++j) {
            const uint32_t g = subset.gc[j];
            const Vec3f* x = positions.data() + h.node(g, 0);
            const Mat3f* m = rotations.data() + static_cast<size_t>(g - finest) * n;
            for (uint32_t i = subset.first[j]; i < subset.first[j + 1]; ++i) {
                const Vec3f p = skinned(n, subset.u[i], subset.offset[i], x, m);
                std::memcpy(out + 3 * size_t{i}, p.data(), 12);
            }
        }
    });
}

}  // namespace

void skin_strands(const Hierarchy& h, const SubsetBinding& subset, std::span<const Vec3f> positions,
                  std::span<const Mat3f> rotations, std::span<Vec3f> points) {
    static_assert(sizeof(Vec3f) == 12, "positions are float32 triples");
    skin_subset(h, subset, positions, rotations, points.size(),
                reinterpret_cast<float*>(points.data()));
}

void skin_strands(const Hierarchy& h, const SubsetBinding& subset, std::span<const Vec3f> positions,
                  std::span<const Mat3f> rotations, std::span<char> xyz) {
    static_assert(sizeof(Vec3f) == 12, "positions are float32 triples");
    if (xyz.size() % 12 != 0) fail("dynamics: ", xyz.size(), " bytes is not a number of points");
    skin_subset(h, subset, positions, rotations, xyz.size() / 12,
                reinterpret_cast<float*>(xyz.data()));
}

}  // namespace wisp
