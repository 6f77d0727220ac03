#pragma once
// Moving the render strands with the AWT (Bertails et al. 2003 §2.2: "each hair strand is
// attached to one of the finest GCs ... and thus controlled by the set of active segments").
//
// At rest every strand point p with arc-length fraction t lies at u = t·(n−1) along its
// finest GC's centre curve (node k = ⌊u⌋, f = u − k) and keeps the offset
//   o = p − lerp(X_k, X_k+1, f)
// in the rest frame. Animated, with node positions x and node rotations M (rest frame to
// now, AwtSimulation::finest_rotations):
//   p = (1 − f)·(x_k + M_k·o) + f·(x_k+1 + M_k+1·o)
// so roots move rigidly with the head, strands keep their curls and offsets, and the
// geometry is continuous whenever the nodes are (splits and merges never move a node).
#include <cstdint>
#include <span>
#include <vector>

#include "core/hair.hpp"
#include "dynamics/hierarchy.hpp"

namespace wisp {

struct StrandBinding {
    std::vector<float> u;       // #P position along the finest GC, in [0, n−1]
    std::vector<Vec3f> offset;  // #P rest offset from the GC's centre curve, cm
};

StrandBinding bind_strands(const Hair& rest, const Hierarchy& hierarchy);

// Writes the animated points into `out.points` (out must have rest's topology). `positions`
// holds every hierarchy node (AwtSimulation::positions after sync), `rotations` the finest
// nodes' rotations. Parallel over strands; no allocation.
void skin_strands(const Hierarchy& hierarchy, const StrandBinding& binding,
                  std::span<const Vec3f> positions, std::span<const Mat3f> rotations, Hair& out);
// The same for the listed strands only (indices into the rest hair whose `offsets` are
// given), written one after another into `points`, which holds exactly their points.
void skin_strands(const Hierarchy& hierarchy, const StrandBinding& binding,
                  std::span<const Vec3f> positions, std::span<const Mat3f> rotations,
                  std::span<const uint32_t> offsets, std::span<const uint32_t> strands,
                  std::span<Vec3f> points);

// The binding of a list of strands (the editor's preview subset), their points gathered in
// the order they are skinned: a frame reads it in sequence instead of hopping over the whole
// binding (the memory traffic, not the arithmetic, bounded skinning a preview).
struct SubsetBinding {
    std::vector<uint32_t> strands;  // #S' indices into the rest hair
    std::vector<uint32_t> gc;       // #S' finest GC of each
    std::vector<uint32_t> first;    // #S'+1 where each strand's points start
    std::vector<float> u;           // #P' as StrandBinding::u
    std::vector<Vec3f> offset;      // #P' as StrandBinding::offset, cm
    size_t point_count() const { return u.size(); }
};

// Gathers the binding of `strands` (indices into the rest hair whose `offsets` are given).
// Throws wisp::Error for a strand not in the hair.
SubsetBinding bind_subset(const Hierarchy& hierarchy, const StrandBinding& binding,
                          std::span<const uint32_t> offsets, std::span<const uint32_t> strands);
// skin_strands() for a subset: the same points, bit for bit, into `points` (#P'). Parallel
// over fixed blocks of strands; no allocation.
void skin_strands(const Hierarchy& hierarchy, const SubsetBinding& subset,
                  std::span<const Vec3f> positions, std::span<const Mat3f> rotations,
                  std::span<Vec3f> points);
// The same points as float32 x, y, z triples (12·#P' bytes, the host's byte order): straight
// into a frame's bytes (wire.hpp's begin_frame).
void skin_strands(const Hierarchy& hierarchy, const SubsetBinding& subset,
                  std::span<const Vec3f> positions, std::span<const Mat3f> rotations,
                  std::span<char> xyz);

}  // namespace wisp
