#include "groom/roots.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/point_grid.hpp"

namespace wisp {
namespace {

// Upper bound of the density map over the scalp, from a deterministic probe.
float probe_max_density(const Scalp& scalp, const MapSampler& density, uint64_t seed) {
    Rng rng(seed, Stream::kRoots, ~uint64_t{0});
    float hi = 0.f;
    for (int i = 0; i < 4096; ++i)
        hi = std::max(hi, density(scalp.sample(rng)));
    return hi;
}

std::vector<Vec3f> positions(const std::vector<SurfacePoint>& pts) {
    std::vector<Vec3f> out(pts.size());
    for (size_t i = 0; i < pts.size(); ++i)
        out[i] = pts[i].position;
    return out;
}

}  // namespace

SurfacePoint sample_by_density(const Scalp& scalp, const MapSampler& density, float max_density,
                               Rng& rng) {
    SurfacePoint p;
    for (int tries = 0; tries < 256; ++tries) {
        p = scalp.sample(rng);
        if (rng.uniform() * max_density < density(p)) return p;
    }
    return p;
}

Roots place_roots(const Scalp& scalp, const MapSampler& density, const RootParams& params) {
    if (params.wisps < 1) fail("roots: the number of wisps must be ≥ 1");
    const float max_density = probe_max_density(scalp, density, params.seed);
    if (!(max_density > 0.f))
        fail("roots: the density map is zero over the whole scalp: no hair can grow");
    const size_t w_count = static_cast<size_t>(params.wisps);
    const size_t c_count = w_count * static_cast<size_t>(std::max(1, params.candidates_per_wisp));

    // Candidate cloud, one stream per candidate.
    std::vector<SurfacePoint> cand(c_count);
    parallel_for(
        c_count,
        [&](size_t i) {
            Rng rng(params.seed, Stream::kRoots, i);
            cand[i] = sample_by_density(scalp, density, max_density, rng);
        },
        256);
    const std::vector<Vec3f> cand_pos = positions(cand);
    const float spacing = std::sqrt(scalp.area() / static_cast<float>(w_count));

    // Initial masters: every k-th candidate (the cloud is already random).
    const size_t stride = c_count / w_count;
    std::vector<uint32_t> master_cand(w_count);
    for (size_t w = 0; w < w_count; ++w)
        master_cand[w] = static_cast<uint32_t>(w * stride);

    std::vector<int> label(c_count);
    Roots roots;
    for (int it = 0; it < params.lloyd_iterations; ++it) {
        std::vector<Vec3f> mpos(w_count);
        for (size_t w = 0; w < w_count; ++w)
            mpos[w] = cand_pos[master_cand[w]];
        const PointGrid grid(mpos, spacing);
        parallel_for(
            c_count, [&](size_t i) { label[i] = grid.nearest(cand_pos[i]); }, 1024);
        // Centroids, accumulated in candidate order (deterministic).
        std::vector<Vec3d> sum(w_count, Vec3d::Zero());
        std::vector<uint32_t> cnt(w_count, 0);
        for (size_t i = 0; i < c_count; ++i) {
            sum[label[i]] += cand_pos[i].cast<double>();
            ++cnt[label[i]];
        }
        // Snap each centroid to its nearest member candidate.
        std::vector<float> best(w_count, INFINITY);
        std::vector<uint32_t> next = master_cand;
        for (size_t i = 0; i < c_count; ++i) {
            const int w = label[i];
            const Vec3f centroid = (sum[w] / std::max<uint32_t>(cnt[w], 1)).cast<float>();
            const float d = (cand_pos[i] - centroid).squaredNorm();
            if (d < best[w]) {
                best[w] = d;
                next[w] = static_cast<uint32_t>(i);
            }
        }
        master_cand = next;
        roots.lloyd_iterations = it + 1;
    }
    roots.masters.resize(w_count);
    for (size_t w = 0; w < w_count; ++w)
        roots.masters[w] = cand[master_cand[w]];

    // Member roots and their Voronoi regions.
    const size_t s_count = static_cast<size_t>(std::max(0, params.strands));
    std::vector<SurfacePoint> members(s_count);
    std::vector<int> wisp_of(s_count);
    const std::vector<Vec3f> mpos = positions(roots.masters);
    const PointGrid grid(mpos, spacing);
    parallel_for(
        s_count,
        [&](size_t j) {
            Rng rng(params.seed, Stream::kMemberRoot, j);
            members[j] = sample_by_density(scalp, density, max_density, rng);
            wisp_of[j] = grid.nearest(members[j].position);
        },
        512);
    // Counting sort by wisp, stable in j.
    roots.wisp_offsets.assign(w_count + 1, 0);
    for (size_t j = 0; j < s_count; ++j)
        ++roots.wisp_offsets[wisp_of[j] + 1];
    for (size_t w = 0; w < w_count; ++w)
        roots.wisp_offsets[w + 1] += roots.wisp_offsets[w];
    roots.members.resize(s_count);
    std::vector<uint32_t> fill(roots.wisp_offsets.begin(), roots.wisp_offsets.end() - 1);
    for (size_t j = 0; j < s_count; ++j)
        roots.members[fill[wisp_of[j]]++] = members[j];
    roots.wisp_radius.assign(w_count, 0.f);
    parallel_for(w_count, [&](size_t w) {
        float r = 0.f;
        for (uint32_t j = roots.wisp_offsets[w]; j < roots.wisp_offsets[w + 1]; ++j)
            r = std::max(r, (roots.members[j].position - roots.masters[w].position).norm());
        // A wisp always has some body, even with a single strand at its master's root.
        roots.wisp_radius[w] = std::max(r, 0.05f * spacing);
    });
    return roots;
}

}  // namespace wisp
