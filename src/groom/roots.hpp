#pragma once
// Root placement (Choe & Ko §2.3): master roots spread evenly over the scalp, a Voronoi
// region per master, and exactly N_s member roots placed inside the regions by the
// density map.
#include <cstdint>
#include <vector>

#include "geometry/mesh_distance.hpp"
#include "geometry/scalp.hpp"
#include "groom/maps.hpp"

namespace wisp {

struct Roots {
    std::vector<SurfacePoint> masters;   // #W master roots
    std::vector<SurfacePoint> members;   // #S member roots, grouped by wisp
    std::vector<uint32_t> wisp_offsets;  // #W+1: wisp w owns members[wisp_offsets[w] ..
                                         // wisp_offsets[w+1])
    std::vector<float> wisp_radius;      // #W root radius: the largest distance from the
                                         // master root to a member root of its region, cm
    int lloyd_iterations = 0;
};

struct RootParams {
    int wisps = 2000;              // N_w ≥ 1
    int strands = 100000;          // N_s ≥ 0
    int candidates_per_wisp = 12;  // density of the candidate cloud for Lloyd relaxation
    int lloyd_iterations = 12;
    uint64_t seed = 1;
};

// Draws an area-uniform scalp point accepted with probability density/max_density
// (rejection sampling; at most 256 tries, then the last draw). max_density > 0.
SurfacePoint sample_by_density(const Scalp& scalp, const MapSampler& density, float max_density,
                               Rng& rng);

// The scalp's own faces (face i of it is scalp.faces()[i]) with closest-point queries: what
// place_roots projects the relaxed master roots onto. It depends on the scalp alone, so a
// caller that places roots again and again on one head (the editor, at each map stroke)
// builds it once.
MeshDistance scalp_surface(const Scalp& scalp);

// The first rejection-sampling proposal of every draw place_roots makes (the density probe's
// points, and each candidate's and member root's first try with its acceptance number). They
// depend on the scalp, the seed and the counts but not on the density map, which only accepts
// or rejects them: a caller that places roots again and again on one head with new maps (the
// editor, at each map stroke) draws them once. 48 bytes per candidate and member root (6 MB
// for 100,000 strands).
struct RootProposals {
    // What they were drawn for: place_roots uses them only for the same.
    uint64_t seed = 0;
    size_t candidates = 0, members = 0;
    std::vector<SurfacePoint> probe;  // #4096 the density probe's points
    std::vector<SurfacePoint> first;  // #candidates then #members: each one's first try
    std::vector<float> accept;        // the uniform number that accepts or rejects it

    // Whether they were drawn for these params (place_roots ignores them otherwise).
    bool fit(const RootParams& params) const;
};
RootProposals root_proposals(const Scalp& scalp, const RootParams& params);

// Places the roots. Master roots: a density-weighted candidate cloud of
// candidates_per_wisp·N_w scalp points, relaxed by Lloyd's algorithm restricted to the
// cloud (k-means), each master snapped to its region's candidate nearest the centroid so it
// stays on the surface. Member roots: N_s density-weighted samples, each assigned to the
// Voronoi region (nearest master root). Deterministic for a seed, any thread count.
// `surface` is scalp_surface(scalp), built here when null; `proposals`, root_proposals(scalp,
// params), drawn here when null or drawn for other params (the roots are the same either way).
Roots place_roots(const Scalp& scalp, const MapSampler& density, const RootParams& params,
                  const MeshDistance* surface = nullptr, const RootProposals* proposals = nullptr);

}  // namespace wisp
