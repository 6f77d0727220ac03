#pragma once
// The grooming pipeline of DESIGN.md: roots → masters → (solve) → members → color → Hair.
// Each stage is a plain function of its inputs, timed in the stats.
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.hpp"
#include "core/hair.hpp"
#include "core/timer.hpp"
#include "groom/clumps.hpp"
#include "groom/head.hpp"
#include "groom/master.hpp"
#include "groom/prototype.hpp"
#include "groom/roots.hpp"
#include "groom/style.hpp"

namespace wisp {

// The root placement parameters of a style.
RootParams root_params(const Style& style);
// Stage 1 (§2.3). `scalp_surface`: scalp_surface(*head.scalp) (groom/roots.hpp), built
// here when null; `proposals`: root_proposals(*head.scalp, root_params(style)), drawn here
// when null or drawn for another seed or count (the roots are the same either way).
Roots grow_roots(const Style& style, const Head& head, const MeshDistance* scalp_surface = nullptr,
                 const RootProposals* proposals = nullptr);

// Stage 2 (§2.2): master outlines along the protrusion direction with details synthesized
// from the prototype. Throws wisp::Error if the prototype is too short for the window.
Masters synthesize_masters(const Style& style, const Head& head, const Roots& roots);

// Stage 2 in its parts, synthesize_masters being master_outlines, then master_prototype, then
// synthesize_master_details. The outlines are what the solve reads before its end (roots,
// segment, direction, root_frame and the straight outline): the editor synthesizes the
// details beside the solve (edit/stage_cache.cpp). master_outlines leaves details, frames
// and control sized #W·n and zero; throws wisp::Error on a length map's bad value.
Masters master_outlines(const Style& style, const Head& head, const Roots& roots);
// The prototype curve every master's details are drawn from, for the masters' segment
// lengths. Throws wisp::Error if a polyline prototype is too short for the window.
struct MasterPrototype {
    PrototypeCurve curve;
    bool straight = false;  // is_straight(): one substep per segment
};
MasterPrototype master_prototype(const Style& style, const Masters& masters);
// Fills masters.details (#W·n) from the prototype, each wisp from its own stream, and with
// `update_frames` the frames and control points that follow (update_master); without, they
// are left for the caller to compute (the solve moves the outline first).
void synthesize_master_details(const Style& style, const MasterPrototype& prototype,
                               Masters& masters, bool update_frames = true);

// Stage 4 (§2.1): every member strand of every wisp, with widths, wisp ids and the scalp UV
// and normal of its root (no colors, no groups), gathered into the style's clumps
// (groom/clumps.hpp; a clump keeps to one group of wisp_group, #W or empty for one group).
// With `only` (ids into roots.members), strand i is member only[i], the same strand the whole
// hair has at index only[i] (the editor's preview of a subset). `cancel` is polled once per
// wisp (or strand of `only`) and told the progress every 1/32 of them; a cancelled call
// returns partial hair.
Hair grow_members(const Style& style, const Scalp& scalp, const Masters& masters,
                  const Roots& roots, std::span<const int32_t> wisp_group = {},
                  std::span<const uint32_t> only = {}, const CancelToken& cancel = {});

// grow_members in bands of master points, so that the members can grow beside the solve as
// its layers make the masters' joints final (the editor's preview): the constructor sets up
// everything that needs no master (each strand's length, point count, kind, wisp, root and
// random stream), the first band the widths, and grow(masters, k0, k1) grows the points
// k0 ≤ k < k1 of every strand,
// reading the masters' control points and frames below k1 only and carrying each strand on
// where the band before left it. Any split into bands gives grow_members' hair to the bit.
class MemberGrowth {
  public:
    // `scalp` and `roots` must outlive the object; `wisp_group` and `only` as grow_members'
    // (copied); `points`, the masters'.
    MemberGrowth(const Style& style, const Scalp& scalp, const Roots& roots, int points,
                 std::span<const int32_t> wisp_group = {}, std::span<const uint32_t> only = {});
    // Points k0 ≤ k < k1 of every strand, after those below k0 (parallel over strands; polls
    // `cancel` per strand and tells it the progress every 1/32 of them).
    void grow(const Masters& masters, int k0, int k1, const CancelToken& cancel = {});
    // How many of strand i's leading points no later band reads, once those below k1 grew
    // (member_points_settled): the push out of the head may move them.
    int settled(size_t i, int k1) const;
    Hair& hair() { return hair_; }

  private:
    const Roots& roots_;
    const Scalp& scalp_;
    ClumpSpec clump_;
    uint64_t seed_;
    std::vector<int32_t> wisp_group_;  // #W or empty
    std::vector<uint32_t> only_;
    int n_;
    float fuzziness_;
    float root_width_, tip_width_, taper_;
    HairlineSpec hairline_;
    FlyawaySpec flyaway_;
    Vec3f centre_;  // the scalp's centre: flyaways and baby hairs turn away from it
    // Each strand's kind: an ordinary member, a baby hair at the hairline (short, unclumped,
    // turned its own way) or a flyaway (leaving its clump near the tip).
    enum Kind : uint8_t { kOrdinary, kBaby, kFlyaway };
    std::vector<uint8_t> kind_;  // #strands
    // Clumps: each wisp's guide and clump size (set by the first band, which has the masters'
    // directions), each strand's sub-clump centre (a member id), the pulls at each master
    // point and each strand's share of its sub-clump's.
    ClumpGuides guides_;
    std::vector<uint32_t> sub_centre_;    // #strands, empty without sub-clumps
    std::vector<float> pull_, sub_pull_;  // #n
    std::vector<float> clump_share_;      // #W the share of the clump whose guide is w
    std::vector<float> weight_;           // #W·n each wisp's pull toward its guide, band by band
    // #W·n the point each wisp's members are pulled toward, band by band: where a blend by the
    // wisp's weight takes its master point to the clumped one (clump_point), which keeps the
    // curl of two masters turning in different phases.
    std::vector<Vec3f> guide_at_;
    std::vector<float> sub_share_;  // #strands
    Hair hair_;
    std::vector<float> u_;       // #strands relative length
    std::vector<float> radius_;  // #W·n deviation radius of each wisp at each master point
    std::vector<Vec3f> offset_;  // #strands the offset d_k of the last point grown
    std::vector<Rng> rng_;       // #strands the strand's stream after it
};

// The wisp of each member root in `ids` (wisp w owns roots.members[wisp_offsets[w] ..
// wisp_offsets[w+1])): grow_members' wisp ids for `only`, which a strand's colour needs.
void member_wisps(const Roots& roots, std::span<const uint32_t> ids, std::span<int32_t> out);

// The masters as strands (the guides a DCC or Unreal rebuilds or drives the members from):
// strand w is master w's control points, wisp id w, its root's scalp UV and normal, width
// `width`, and group wisp_group[w] (#W, or empty for none).
Hair guide_strands(const Masters& masters, std::span<const int32_t> wisp_group, float width);

// Deviation radius r(s) at s in [0,1] from the style's table (linear interpolation).
float deviation_radius(const std::vector<float>& table, float s);

struct GenerateResult {
    Hair hair;
    Masters masters;
    StageTimes times;  // roots, masters, members, color
};

// Runs every stage for a style on a head (loaded with load_head(style.head)).
GenerateResult generate(const Style& style, const Head& head);

}  // namespace wisp
