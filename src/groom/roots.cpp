#include "groom/roots.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/point_grid.hpp"

namespace wisp {
namespace {

constexpr int kProbes = 4096;

// Upper bound of the density map over the scalp, from a deterministic probe (at the points
// given, when given: the same ones).
float probe_max_density(const Scalp& scalp, const MapSampler& density, uint64_t seed,
                        const std::vector<SurfacePoint>* points) {
    float hi = 0.f;
    if (points) {
        for (const SurfacePoint& p : *points)
            hi = std::max(hi, density(p));
        return hi;
    }
    Rng rng(seed, Stream::kRoots, ~uint64_t{0});
    for (int i = 0; i < kProbes; ++i)
        hi = std::max(hi, density(scalp.sample(rng)));
    return hi;
}

// sample_by_density's tries after a rejected first one (`first`, whose 3 draws for the point
// and 1 to accept it were made beforehand): the same point.
SurfacePoint sample_after(const Scalp& scalp, const MapSampler& density, float max_density, Rng rng,
                          const SurfacePoint& first) {
    for (int k = 0; k < 4; ++k)
        rng.next();
    SurfacePoint p = first;
    for (int tries = 1; tries < 256; ++tries) {
        p = scalp.sample(rng);
        if (rng.uniform() * max_density < density(p)) return p;
    }
    return p;
}

std::vector<Vec3f> positions(const std::vector<SurfacePoint>& pts) {
    std::vector<Vec3f> out(pts.size());
    for (size_t i = 0; i < pts.size(); ++i)
        out[i] = pts[i].position;
    return out;
}

// Barycentric coordinates (of vertices 1 and 2) of q on face f, clamped into the triangle.
Vec2f barycentric(const Mesh& mesh, uint32_t f, const Vec3f& q) {
    const Vec3i& t = mesh.faces[f];
    const Vec3f a = mesh.vertices[t[0]], e1 = mesh.vertices[t[1]] - a, e2 = mesh.vertices[t[2]] - a,
                d = q - a;
    const float d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const float det = d11 * d22 - d12 * d12;
    if (!(std::abs(det) > 0.f)) return Vec2f(1.f / 3, 1.f / 3);
    float b1 = (d22 * d.dot(e1) - d12 * d.dot(e2)) / det;
    float b2 = (d11 * d.dot(e2) - d12 * d.dot(e1)) / det;
    b1 = std::clamp(b1, 0.f, 1.f);
    b2 = std::clamp(b2, 0.f, 1.f - b1);
    return Vec2f(b1, b2);
}

}  // namespace

MeshDistance scalp_surface(const Scalp& scalp) {
    // The scalp faces alone, so that closest points land on the scalp.
    Mesh cap;
    cap.vertices = scalp.mesh().vertices;
    cap.faces.reserve(scalp.faces().size());
    for (uint32_t f : scalp.faces())
        cap.faces.push_back(scalp.mesh().faces[f]);
    return MeshDistance(cap);
}

SurfacePoint sample_by_density(const Scalp& scalp, const MapSampler& density, float max_density,
                               Rng& rng) {
    SurfacePoint p;
    for (int tries = 0; tries < 256; ++tries) {
        p = scalp.sample(rng);
        if (rng.uniform() * max_density < density(p)) return p;
    }
    return p;
}

namespace {

size_t candidate_count(const RootParams& params) {
    return static_cast<size_t>(std::max(1, params.wisps)) *
           static_cast<size_t>(std::max(1, params.candidates_per_wisp));
}

}  // namespace

bool RootProposals::fit(const RootParams& params) const {
    return seed == params.seed && candidates == candidate_count(params) &&
           members == static_cast<size_t>(std::max(0, params.strands));
}

RootProposals root_proposals(const Scalp& scalp, const RootParams& params) {
    RootProposals out;
    out.seed = params.seed;
    out.candidates = candidate_count(params);
    out.members = static_cast<size_t>(std::max(0, params.strands));
    Rng probe(params.seed, Stream::kRoots, ~uint64_t{0});
    out.probe.resize(kProbes);
    for (SurfacePoint& p : out.probe)
        p = scalp.sample(probe);
    const size_t n = out.candidates + out.members;
    out.first.resize(n);
    out.accept.resize(n);
    parallel_for(
        n,
        [&](size_t k) {
            Rng rng = k < out.candidates
                          ? Rng(params.seed, Stream::kRoots, k)
                          : Rng(params.seed, Stream::kMemberRoot, k - out.candidates);
            out.first[k] = scalp.sample(rng);
            out.accept[k] = rng.uniform();
        },
        512);
    return out;
}

Roots place_roots(const Scalp& scalp, const MapSampler& density, const RootParams& params,
                  const MeshDistance* surface, const RootProposals* proposals) {
    if (params.wisps < 1) fail("roots: the number of wisps must be ≥ 1");
    const size_t w_count = static_cast<size_t>(params.wisps);
    const size_t c_count = candidate_count(params);
    const size_t s_count = static_cast<size_t>(std::max(0, params.strands));
    if (proposals && !proposals->fit(params)) proposals = nullptr;
    const float max_density =
        probe_max_density(scalp, density, params.seed, proposals ? &proposals->probe : nullptr);
    if (!(max_density > 0.f))
        fail("roots: the density map is zero over the whole scalp: no hair can grow");
    // Draw k (candidates first, then members) from its own stream (seeded only when used:
    // most draws take their first proposal).
    const auto draw = [&](size_t k) {
        const auto stream = [&] {
            return k < c_count ? Rng(params.seed, Stream::kRoots, k)
                               : Rng(params.seed, Stream::kMemberRoot, k - c_count);
        };
        if (!proposals) {
            Rng rng = stream();
            return sample_by_density(scalp, density, max_density, rng);
        }
        const SurfacePoint& first = proposals->first[k];
        if (proposals->accept[k] * max_density < density(first)) return first;
        return sample_after(scalp, density, max_density, stream(), first);
    };

    // Candidate cloud, one stream per candidate.
    std::vector<SurfacePoint> cand(c_count);
    parallel_for(
        c_count, [&](size_t i) { cand[i] = draw(i); }, 256);
    const std::vector<Vec3f> cand_pos = positions(cand);
    const float spacing = std::sqrt(scalp.area() / static_cast<float>(w_count));

    // Lloyd relaxation restricted to the cloud: masters move to the centroids of their
    // candidates (off the surface by the cap's curvature, harmless for assignment) and are
    // projected back onto the scalp at the end.
    const size_t stride = c_count / w_count;
    std::vector<Vec3f> mpos(w_count);
    for (size_t w = 0; w < w_count; ++w)
        mpos[w] = cand_pos[w * stride];
    std::vector<int> label(c_count, -1);
    Roots roots;
    for (int it = 0; it < params.lloyd_iterations; ++it) {
        const PointGrid grid(mpos, spacing);
        parallel_for(
            // Last iteration's master barely moved: its distance bounds the search (the
            // answer is the same with or without the hint).
            c_count, [&](size_t i) { label[i] = grid.nearest(cand_pos[i], label[i]); }, 1024);
        // Centroids, accumulated in candidate order (deterministic).
        std::vector<Vec3d> sum(w_count, Vec3d::Zero());
        std::vector<uint32_t> cnt(w_count, 0);
        for (size_t i = 0; i < c_count; ++i) {
            sum[label[i]] += cand_pos[i].cast<double>();
            ++cnt[label[i]];
        }
        for (size_t w = 0; w < w_count; ++w)
            if (cnt[w] > 0) mpos[w] = (sum[w] / cnt[w]).cast<float>();
        roots.lloyd_iterations = it + 1;
    }
    roots.masters.resize(w_count);
    std::optional<MeshDistance> own;
    if (!surface) surface = &own.emplace(scalp_surface(scalp));
    parallel_for(
        w_count,
        [&](size_t w) {
            uint32_t sub = 0;
            const Vec3f q = surface->closest_point(mpos[w], &sub);
            const uint32_t face = scalp.faces()[sub];
            roots.masters[w] = scalp.point_on(face, barycentric(scalp.mesh(), face, q));
        },
        64);

    // Member roots and their Voronoi regions.
    std::vector<SurfacePoint> members(s_count);
    std::vector<int> wisp_of(s_count);
    const std::vector<Vec3f> root_pos = positions(roots.masters);
    const PointGrid grid(root_pos, spacing);
    // A first guess of each member's master: the last label of a candidate on its face (the
    // lowest such candidate; -1 where none fell). It is usually the nearest master or its
    // neighbour, so the search starts from a small radius instead of growing rings of cells
    // (the answer is the same with or without the hint).
    std::vector<int> face_hint(scalp.mesh().faces.size(), -1);
    for (size_t i = 0; i < c_count; ++i)
        if (face_hint[cand[i].face] < 0) face_hint[cand[i].face] = label[i];
    parallel_for(
        s_count,
        [&](size_t j) {
            members[j] = draw(c_count + j);
            wisp_of[j] = grid.nearest(members[j].position, face_hint[members[j].face]);
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
