#include "core/hair.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "core/parallel.hpp"

namespace wisp {

static_assert(sizeof(Vec3f) == 3 * sizeof(float), "points are read as a flat float array");

namespace {

// Whether every coordinate of `points` is finite and within ±limit.
// Whether every one of the n floats at f lies in [lo, hi] (NaN does not). Branch-free, so the
// compiler vectorizes it, and in chunks of a fixed size on all cores: 3.2 M coordinates took
// a fifth of a .usda write's wall time on one core before every writer could begin.
bool floats_within(const float* f, size_t n, float lo, float hi) {
    constexpr size_t kChunk = size_t{1} << 18;
    const size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<unsigned char> outside(chunks, 0);
    parallel_for(chunks, [&](size_t c) {
        const size_t end = std::min(n, (c + 1) * kChunk);
        unsigned out = 0;  // NaN compares false: outside
        for (size_t i = c * kChunk; i < end; ++i)
            out |= !(f[i] >= lo && f[i] <= hi);
        outside[c] = static_cast<unsigned char>(out);
    });
    return std::find(outside.begin(), outside.end(), 1) == outside.end();
}

bool coordinates_within(std::span<const Vec3f> points, float limit) {
    return floats_within(points.empty() ? nullptr : points.data()->data(), 3 * points.size(),
                         -limit, limit);
}

// Chunks of a fixed size (not one per thread), so the reductions below combine the same
// partial results in the same order at any thread count.
constexpr size_t kReduceChunk = size_t{1} << 16;

}  // namespace

Box3 Hair::bounds() const {
    const size_t n = points.size();
    const size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
    std::vector<Box3> part(chunks);
    parallel_for(chunks, [&](size_t c) {
        // On the flat floats, four points (12 floats) at a time in three 4-wide minima and
        // maxima: Eigen's per-point cwiseMin and cwiseMax were scalar, a chain of min latencies
        // (the compiler does not vectorize a float min reduction by itself). Lane j holds
        // coordinate j % 3.
        using Lanes = Eigen::Array4f;
        const size_t begin = c * kReduceChunk, end = std::min(n, begin + kReduceChunk);
        const float* f = points[begin].data();
        const size_t floats = 3 * (end - begin), whole = floats - floats % 12;
        Lanes lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = Lanes::Constant(INFINITY);
            hi[k] = Lanes::Constant(-INFINITY);
        }
        for (size_t i = 0; i < whole; i += 12)
            for (int k = 0; k < 3; ++k) {
                const Lanes v = Eigen::Map<const Lanes>(f + i + 4 * k);
                lo[k] = lo[k].min(v);
                hi[k] = hi[k].max(v);
            }
        Box3& b = part[c];
        for (size_t j = 0; j < 12; ++j) {
            b.lo[j % 3] = std::min(b.lo[j % 3], lo[j / 4][j % 4]);
            b.hi[j % 3] = std::max(b.hi[j % 3], hi[j / 4][j % 4]);
        }
        for (size_t i = whole; i < floats; ++i) {
            b.lo[i % 3] = std::min(b.lo[i % 3], f[i]);
            b.hi[i % 3] = std::max(b.hi[i % 3], f[i]);
        }
    });
    Box3 box;
    for (const Box3& b : part)
        box.extend(b);
    return box;
}

float Hair::max_width() const {
    if (widths.empty()) return default_width;
    const size_t n = widths.size();
    const size_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
    std::vector<float> part(chunks, 0.f);
    parallel_for(chunks, [&](size_t c) {
        const size_t end = std::min(n, (c + 1) * kReduceChunk);
        float m = 0.f;  // widths are >= 0 (validate)
        for (size_t i = c * kReduceChunk; i < end; ++i)
            m = std::max(m, widths[i]);
        part[c] = m;
    });
    return *std::max_element(part.begin(), part.end());
}

void Hair::validate(const std::string& what) const {
    if (offsets.empty() || offsets.front() != 0) fail(what, ": offsets must start with 0");
    for (size_t i = 0; i + 1 < offsets.size(); ++i)
        if (offsets[i + 1] < offsets[i]) fail(what, ": strand ", i, " has negative point count");
    if (offsets.back() != points.size())
        fail(what, ": offsets end at ", offsets.back(), " but there are ", points.size(),
             " points");
    const size_t s = strand_count();
    if (!widths.empty() && widths.size() != points.size())
        fail(what, ": widths has ", widths.size(), " values, expected ", points.size());
    if (!colors.empty() && colors.size() != s)
        fail(what, ": colors has ", colors.size(), " values, expected ", s);
    if (!wisp.empty() && wisp.size() != s)
        fail(what, ": wisp has ", wisp.size(), " values, expected ", s);
    if (!root_uv.empty() && root_uv.size() != s)
        fail(what, ": root_uv has ", root_uv.size(), " values, expected ", s);
    if (!root_normal.empty() && root_normal.size() != s)
        fail(what, ": root_normal has ", root_normal.size(), " values, expected ", s);
    if (!group.empty() && group.size() != s)
        fail(what, ": group has ", group.size(), " values, expected ", s);
    // One branch-free pass over every coordinate, which the compiler vectorizes (the loop
    // below took 45 instructions a point); that loop, which names the first bad point, runs
    // only when there is one.
    if (!coordinates_within(points, kMaxCoordinate))
        for (size_t st = 0; st < s; ++st)
            for (uint32_t i = offsets[st]; i < offsets[st + 1]; ++i) {
                const Vec3f& p = points[i];
                if (!p.allFinite())
                    fail(what, ": point ", i, " is not finite (strand ", st, ", its point ",
                         i - offsets[st], ")");
                if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
                    fail(what, ": point ", i, " (strand ", st, ", its point ", i - offsets[st],
                         ") is at (", p.x(), ", ", p.y(), ", ", p.z(), "), farther than ",
                         kMaxCoordinate, " cm from the origin on an axis (see docs/formats.md)");
            }
    if (!floats_within(widths.data(), widths.size(), 0.f, std::numeric_limits<float>::max()))
        for (size_t i = 0; i < widths.size(); ++i)
            if (!std::isfinite(widths[i]) || widths[i] < 0.f)
                fail(what, ": width ", i, " is negative or not finite");
    for (size_t i = 0; i < colors.size(); ++i)
        if (!colors[i].allFinite()) fail(what, ": color ", i, " is not finite");
    for (size_t i = 0; i < root_uv.size(); ++i)
        if (!root_uv[i].allFinite()) fail(what, ": root_uv ", i, " is not finite");
    for (size_t i = 0; i < root_normal.size(); ++i)
        if (!root_normal[i].allFinite()) fail(what, ": root_normal ", i, " is not finite");
    for (size_t i = 0; i < group.size(); ++i)
        if (group[i] < 0) fail(what, ": group ", i, " is ", group[i], ", below 0");
}

Hair select_strands(const Hair& hair, std::span<const uint32_t> keep) {
    const size_t S = hair.strand_count();
    Hair out;
    out.default_width = hair.default_width;
    out.default_color = hair.default_color;
    out.offsets.assign(keep.size() + 1, 0);
    for (size_t k = 0; k < keep.size(); ++k) {
        if (keep[k] >= S)
            fail("select_strands: strand ", keep[k], " of ", S, " strands is out of range");
        out.offsets[k + 1] = out.offsets[k] + hair.strand_size(keep[k]);
    }
    out.points.resize(out.offsets.back());
    if (!hair.widths.empty()) out.widths.resize(out.offsets.back());
    const auto per_strand = [&](const auto& from, auto& to) {
        if (from.empty()) return;
        to.resize(keep.size());
        for (size_t k = 0; k < keep.size(); ++k)
            to[k] = from[keep[k]];
    };
    per_strand(hair.colors, out.colors);
    per_strand(hair.wisp, out.wisp);
    per_strand(hair.root_uv, out.root_uv);
    per_strand(hair.root_normal, out.root_normal);
    per_strand(hair.group, out.group);
    parallel_for(
        keep.size(),
        [&](size_t k) {
            const uint32_t a = hair.offsets[keep[k]], b = hair.offsets[keep[k] + 1];
            std::copy(hair.points.begin() + a, hair.points.begin() + b,
                      out.points.begin() + out.offsets[k]);
            if (!hair.widths.empty())
                std::copy(hair.widths.begin() + a, hair.widths.begin() + b,
                          out.widths.begin() + out.offsets[k]);
        },
        1024);
    return out;
}

std::vector<uint32_t> even_subset(size_t total, size_t n) {
    n = std::min(n, total);
    std::vector<uint32_t> out(n);
    for (size_t k = 0; k < n; ++k)
        out[k] = static_cast<uint32_t>((unsigned __int128)(2 * k + 1) * total / (2 * n));
    return out;
}

}  // namespace wisp
