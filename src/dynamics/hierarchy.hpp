#pragma once
// The multiresolution hair geometry of Bertails et al. 2003 §2.1–§2.2: a hierarchy of
// generalized cylinders (GCs) with circular cross-sections, built from a Hair.
//
// Levels, coarse to fine (DynamicsSpec::levels):
//   2: wisps, sub-wisps
//   3: groups of neighbouring wisps, wisps, sub-wisps
//   4: groups, wisps, sub-wisps, sub-sub-wisps
// The wisps are the statistical wisps of the hairstyle (Hair::wisp); hair without wisp ids
// (imported files) is first clustered into wisps of at most `strands_per_wisp` strands (and
// more than half that) by root position and shape. Every cluster below and above is made by
// recursive bisection along the principal axis of the strands' (or wisps') resampled curves, so
// clusters are neighbours in root position and alike in shape, and the result is deterministic.
// Groups number ⌈wisps / wisps_per_group⌉, and more where a group's wisps part ways (at some
// section they lie more than 3 times as far from its centre as their roots do, the roots
// counted at least 1 cm apart): such a group is bisected again, so that no top-level GC spans
// hair falling on both sides of a shoulder.
//
// Every GC has the same number of cross-sections, `sections` (§2.2: "the number of
// cross-sections is the same at each hierarchy level"), so node k of a GC corresponds to node
// k of its sub-GCs: its super-node and sub-nodes. Node 0 is at the roots. Cross-section k of
// a strand is its point at arc-length fraction k/(sections−1).
//
// At rest (the hairstyle as given):
//   finest node  = mean of its strands' cross-section points; radius = the distance from the
//                  node within which 90% of them lie (at least 0.05 cm)
//   super-node   = centre of mass of its sub-nodes; radius fitted to enclose the sub-GCs
//                  (§2.1): max over sub-nodes of |sub − super| + sub radius
//   mass         = strands × (strand length / (sections−1)) × linear density, summed over
//                  sub-nodes for super-nodes (so mass is exactly additive)
// Every strand is attached to one finest GC.
#include <cstdint>
#include <span>
#include <vector>

#include "core/hair.hpp"
#include "core/math.hpp"

namespace wisp {

struct HierarchyOptions {
    int levels = 3;
    int wisps_per_group = 6;
    int sub_wisps = 3;
    int sections = 8;
    int strands_per_wisp = 50;       // hair without wisp ids
    float linear_density = 6.5e-5f;  // g/cm
    // Per wisp id (Hair::wisp): the arc length from the root, cm, through which the wisp is
    // held rigidly to the head by a tie or a bun (SolveStats::held_length); empty or 0: free.
    // Top-level groups never mix held and free wisps.
    std::vector<float> wisp_held;
    // Per strand: the same, for holds that are not per wisp (held_lengths(), an imported
    // ponytail's tie); empty: none. A strand is held through the longer of the two. Hair
    // without wisp ids makes its wisps of held and free strands apart.
    std::vector<float> strand_held;
};

// A tie for hair that carries no constraints (`wisp animate --tie`): every strand passing
// within `radius` of `point` (the rest hair's coordinates, cm) is held from its root to its
// nearest approach to the point.
struct Tie {
    Vec3f point = Vec3f::Zero();
    float radius = 2.f;  // cm, > 0
};

// Per strand, the arc length (cm) the ties hold (the longest, where several catch it); 0
// for strands no tie catches. Throws wisp::Error for a tie that is not finite or a radius
// that is not > 0.
std::vector<float> held_lengths(const Hair& hair, std::span<const Tie> ties);

// The holds of ties a user gives (`wisp animate --tie`, `wisp.animate(..., ties=)`): per
// strand, the longest length any tie holds (HierarchyOptions::strand_held; empty for no
// ties). Each tie must catch a strand: one that catches none is a mistake in its
// coordinates, and throws wisp::Error "tie T (x,y,z, radius r cm) passes within r cm of no
// strand (the hair spans ...)". `caught`, if given, receives each tie's strand count.
std::vector<float> tie_holds(const Hair& hair, std::span<const Tie> ties,
                             std::vector<size_t>* caught = nullptr);

struct Hierarchy {
    int levels = 0;
    int sections = 0;  // n: nodes per GC
    // GCs, coarsest level first. Level l holds GCs [level_begin[l], level_begin[l+1]).
    // The sub-GCs of a GC are contiguous: [child_begin[g], child_begin[g] + child_count[g]).
    std::vector<uint32_t> level_begin;   // #levels+1
    std::vector<uint8_t> level;          // #G
    std::vector<int32_t> super;          // #G super-GC, −1 at the top level
    std::vector<uint32_t> child_begin;   // #G (finest: 0)
    std::vector<uint32_t> child_count;   // #G (finest: 0)
    std::vector<uint32_t> strand_count;  // #G strands carried
    // Nodes: node k of GC g is g·sections + k.
    std::vector<Vec3f> rest;    // #G·n centre at rest, head space, cm
    std::vector<float> radius;  // #G·n cross-section radius at rest, cm
    std::vector<float> mass;    // #G·n g
    // #G·n the fraction of the node's mass held rigidly to the head (HierarchyOptions::
    // wisp_held, strand_held): 1 at the roots; 0 or 1 at the finest level (a strand's cross-section
    // is held when it lies within the held length, to the nearest section); mass-weighted means
    // above.
    std::vector<float> held;
    // Strands.
    std::vector<uint32_t> strand_gc;  // #S the finest GC of each strand

    size_t gc_count() const { return level.size(); }
    size_t node_count() const { return rest.size(); }
    uint32_t node(uint32_t gc, int k) const { return gc * static_cast<uint32_t>(sections) + k; }
    uint32_t gc_of(uint32_t node) const { return node / static_cast<uint32_t>(sections); }
    int section_of(uint32_t node) const { return static_cast<int>(node % sections); }
    uint32_t finest_begin() const { return level_begin[levels - 1]; }
    uint32_t level_size(int l) const { return level_begin[l + 1] - level_begin[l]; }
};

// Builds the hierarchy. Throws wisp::Error for options out of range or a Hair without
// strands (or with a strand of fewer than 2 points).
Hierarchy build_hierarchy(const Hair& hair, const HierarchyOptions& options);

// The point at arc-length fraction t ∈ [0, 1] of a polyline (2+ points).
Vec3f point_at_fraction(std::span<const Vec3f> strand, float t);

}  // namespace wisp
