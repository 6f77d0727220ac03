#pragma once
// The whole grooming pipeline of DESIGN.md with the solver in place:
// roots → masters → head field → styling field → solve → members → cut → collide → color.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/cancel.hpp"
#include "core/hair.hpp"
#include "core/timer.hpp"
#include "groom/generate.hpp"
#include "solve/head_field.hpp"
#include "solve/solver.hpp"

namespace wisp {

struct HairstyleResult {
    Hair hair;
    Masters masters;
    std::vector<int32_t> wisp_group;  // #W the group of each wisp (Hair::group's values)
    StageTimes times;                 // one entry per stage, in order
    SolveStats solve;
    size_t points_pushed = 0;       // member points moved out of the head (collide stage)
    size_t points_inside_head = 0;  // after the collide stage: must be 0
    size_t strands_cut = 0;         // strands shortened by the cut plane
    size_t strands_removed = 0;     // strands whose root lay beyond the cut plane
};

// The centre and radius of the head (the scalp's fitted sphere).
HeadFrame head_frame(const Scalp& scalp);
// The same with where the shoulders are (HeadFrame::shoulder_top), from the head's landmarks
// and the top of its body beside the neck.
HeadFrame head_frame(const Head& head);

// Shortens every strand at the plane n·p = offset (n unit): points beyond it go, and the
// strand ends on the plane. Strands whose root is beyond are removed. Returns the number of
// strands shortened; `removed` receives the number removed. With `offsets` (#strands), each
// strand is cut at its own plane n·p = offsets[i] instead, or not at all where it is NaN.
// `was_cut` receives, per strand of the result, whether the plane shortened it.
size_t cut_hair(Hair& hair, const Vec3f& normal, float offset, size_t* removed,
                const std::vector<float>* offsets = nullptr,
                std::vector<uint8_t>* was_cut = nullptr);

// Turns the last `bevel` cm of each strand with `turn` set under, toward the vertical axis
// through `center`: a point that far from the start of the stretch at fraction t of it moves
// inward by bevel·t²/2, so the tip comes in by half the bevel and the turn starts tangent.
void bevel_ends(Hair& hair, std::span<const uint8_t> turn, float bevel, const Vec3f& center);

// Moves every non-root point whose head distance is below `clearance` cm out along the
// head's gradient to that clearance. Returns the number of points moved. With `near`
// (#W·n flags, n = points per master) only points k of strands of wisp w with
// near[w·n + k] (or near[w·n + k − 1]) are examined: wisps far from the head are skipped.
// `inside` receives the number of examined points still inside afterwards (0 unless the
// head field cannot resolve them).
size_t push_out_of_head(Hair& hair, const HeadField& head, float clearance,
                        const std::vector<uint8_t>* near = nullptr, int n = 0,
                        size_t* inside = nullptr);

// The stages generate_hairstyle runs, each a function of the outputs before it (the
// editor's stage cache, edit/stage_cache.hpp, keeps those and re-runs from a change on).
// Each appends its sub-stages' times to `times` when given.

// The head's distance field at head_field_cell(style.solve), bridged by style.solve.bridge;
// throws wisp::Error naming the head if its grid would be too large.
HeadField build_head_field(const Style& style, const Head& head);

// The wisps of each constraint group (selected: #groups lists of wisp ids) and the group of
// each wisp (wisp_group: #W, 1 + the first group that selects it, 0 for none: the solver's
// rule, and the group its strands export with, Hair::group).
struct GroupSelection {
    std::vector<std::vector<uint32_t>> selected;
    std::vector<int32_t> wisp_group;
};
GroupSelection select_groups(const Style& style, const Head& head, const Roots& roots);

// The box the solver's grids span: the head, grown by the longest master around the roots.
// Throws wisp::Error naming solve.cell and the lengths when the grids would be too large.
Box3 solve_bounds(const Style& style, const Head& head, const Roots& roots, const Masters& masters);
// The styling field Φ of style.solve.field over `bounds` at solve.cell (§3.1).
StylingField styling_field(const Style& style, const Head& head, const Box3& bounds);

// Styling field, density grid and Algorithm 1 (§3, §4): solves `masters` in place. `field`,
// when given, is styling_field(style, head, solve_bounds(…)) kept from an earlier solve (the
// editor keeps it while only κ or τ move). A cancelled solve (SolveStats::cancelled) leaves
// `masters` partly solved. Without `update_frames`, the masters' frames and control points are
// left for the caller to compute (SolveInput::update_frames); `joints_final` is
// SolveInput::joints_final.
SolveStats solve_stage(const Style& style, const Head& head, const HeadField& head_field,
                       const Roots& roots, const GroupSelection& groups, Masters& masters,
                       StageTimes* times = nullptr, const StylingField* field = nullptr,
                       const CancelToken& cancel = {}, bool update_frames = true,
                       std::atomic<int>* joints_final = nullptr);

struct MembersResult {
    Hair hair;  // without colors
    size_t points_pushed = 0, points_inside_head = 0, strands_cut = 0, strands_removed = 0;
};
// Members (§2.1) with their group (wisp_group, #W), the cut plane (§6.2) and the push out
// of the head.
// With `only` (ids into roots.members, grow_members), just those strands, in that order
// (the editor's preview). `cancel` is polled per wisp, and told the progress: the growth is
// the first half, the rest ends at 1; a cancelled call returns partial hair.
MembersResult members_stage(const Style& style, const Head& head, const HeadField& head_field,
                            const Roots& roots, const Masters& masters,
                            std::span<const int32_t> wisp_group, StageTimes* times = nullptr,
                            std::span<const uint32_t> only = {}, const CancelToken& cancel = {});

// members_stage in bands of master points (MemberGrowth), so that the members can follow
// the solve's layers (the editor's preview, beside the solve): grow(masters, k0, k1) grows
// the points k0 ≤ k < k1 of every strand, then push(masters, k0, k1) pushes out of the head
// those no later band reads; both read the masters' control points and frames below k1
// only. After bands covering [0, n) in order, finish() cuts the whole strands (a style's
// `[cut]`) and is members_stage's result to the bit; finish(false) returns the strands as
// the bands left them (a cancelled growth).
class MemberBands {
  public:
    // `style`, `head_field`, `scalp` and `roots` must outlive the object; the rest is copied.
    MemberBands(const Style& style, const HeadField& head_field, const Scalp& scalp,
                const Roots& roots, std::span<const int32_t> wisp_group, int points,
                std::span<const uint32_t> only = {});
    void grow(const Masters& masters, int k0, int k1, const CancelToken& cancel = {});
    void push(const Masters& masters, int k0, int k1);
    MembersResult finish(bool cut = true);

  private:
    const Style& style_;
    const HeadField& head_field_;
    const Scalp& scalp_;
    const Roots& roots_;
    int points_;
    MemberGrowth growth_;
    std::vector<float> clump_reach_;  // #W how far clumps can move a wisp's members
    std::vector<uint8_t> near_;       // #W·n near_head flags, filled band by band
    MembersResult result_;
};

// Beside a solve of `masters` that runs with update_frames = false and tells joints_final
// (solve_stage): the masters' frames and control points (update_master), and with `bands`
// the members' growth and push, band by band of joints as the solve's layers make them final,
// on the core the solve's serial layers leave idle. `joints_final` < 0 says the solve ended
// without finishing (cancelled, or it threw): then, or when `cancel` fires, it returns false
// at once, the masters and members partial. Returns true with the masters whole, byte for
// byte update_master's of the solved outlines, and the bands covering every joint.
bool follow_solve(Masters& masters, const std::atomic<int>& joints_final, MemberBands* bands,
                  const CancelToken& cancel = {});

// A color per strand (§5). With `ids` (#strands), strand i takes the colour of strand ids[i]
// of the whole hair (color_strands).
void color_stage(const Style& style, Hair& hair, std::span<const uint32_t> ids = {});

// Runs every stage. The head field is built here unless `head_field` is given (callers
// that solve repeatedly on one head, like the editor and benchmarks, keep it).
HairstyleResult generate_hairstyle(const Style& style, const Head& head,
                                   const HeadField* head_field = nullptr);

// The head field's cell for a head (3/4 of the solver cell, at most 0.75 cm).
float head_field_cell(const SolveSpec& spec);

// The solver's figures as `wisp generate --stats` and `wisp.generate(...).stats` give them
// ("solver"): enabled, order, joints, collision iterations, colliding, unresolved, projected
// and constrained joints, and per constraint group its constraints, completion and wisps.
nlohmann::json solve_stats_json(const SolveStats& stats, const SolveSpec& spec);

}  // namespace wisp
