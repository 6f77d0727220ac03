#pragma once
// Clumps at two scales around Choe & Ko's wisps (style.hpp ClumpSpec, docs/style.md [clump]):
// neighbouring wisps gather into a clump around a guide, one of their masters, as Blender's
// Clump node gathers curves to guides and XGen's clump modifier to clump guides; inside a
// wisp, members gather into sub-clumps around a few of their own roots. The Adaptive Wisp
// Tree's levels (Bertails et al. 2003) are the same idea for motion: clumps of clumps.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "geometry/scalp.hpp"
#include "groom/master.hpp"
#include "groom/roots.hpp"
#include "groom/style.hpp"

namespace wisp {

// Which clump each wisp is in: the wisp whose master is its guide. Guides are chosen in wisp
// order, each at least the clump size (clump.size at its root) from every guide before it
// that it could share a clump with; every wisp then joins the nearest guide, by root, of
// its own group (wisp_group, #W or empty for one group) whose master leaves the scalp within
// 45° of its own and whose root lies within 1.5 clump sizes, or is its own guide.
struct ClumpGuides {
    std::vector<int32_t> guide;  // #W the guide's wisp id (guide[g] = g for a guide)
    std::vector<float> size;     // #W clump.size at the wisp's root, cm (empty: no clumps)
};
ClumpGuides clump_guides(const ClumpSpec& spec, const Scalp& scalp, const Masters& masters,
                         std::span<const int32_t> wisp_group);

// The sub-clump of each member root in `ids` (ids into roots.members): the nearest, by root,
// of the first sub_count members of its wisp (those come in random order within a wisp).
//   wisp  #ids the wisp of each id;  out  #ids member ids of the sub-clumps' centres
void sub_clump_centres(const ClumpSpec& spec, const Roots& roots, std::span<const uint32_t> ids,
                       std::span<const int32_t> wisp, std::span<uint32_t> out);

// The pull at each master point k of n (s = k/(n−1)): pull·s^shape.
std::vector<float> clump_profile(float pull, float shape, int n);

// Where master w's point k goes when pulled by `a` toward guide g's: its outline (the curl's
// axis) moves the pull's way, and its detail (the wave or curl about the axis) goes from its
// own toward the guide's, keeping the blend of their sizes. A plain blend of the two points
// would flatten curls whose phases differ (a quarter turn apart, to 0.71 of their size; half
// a turn apart, they cancel): clumped ringlets would read as a narrow column of crimp. Near
// half a turn apart the direction between them is unsure and the detail still shrinks.
Vec3f clump_point(const Masters& masters, size_t w, size_t g, size_t k, float a);

// A clump's or sub-clump's own share of its pull, uniform in [1 − variation, 1] from (seed,
// id): the same for every member of it, whichever strands are grown.
float clump_share(uint64_t seed, uint64_t id, float variation);

}  // namespace wisp
