#pragma once
// The pseudophysical deformation solver (Choe & Ko §3, Algorithm 1) with the
// constraint-based styler (§4): finds every master's joint angles under the styling force
// field, bending stiffness and density-field collisions.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cancel.hpp"
#include "core/grid.hpp"
#include "groom/master.hpp"
#include "groom/roots.hpp"
#include "groom/style.hpp"
#include "solve/constraint.hpp"
#include "solve/head_field.hpp"
#include "solve/styling_field.hpp"

namespace wisp {

// Eq. (5): the unit direction q* maximizing E = Φ·q + κ q0·q over unit q, which is
// (Φ + κ q0) normalized (q0 when that sum vanishes).
inline Vec3f best_direction(const Vec3f& phi, const Vec3f& q0, float kappa) {
    const Vec3f v = phi + kappa * q0;
    const float n = v.norm();
    return n > 1e-8f ? Vec3f(v / n) : q0;
}

// Contact with the skin (hair that lies on the shoulders, the chest, the back or the scalp):
// the unit direction along the skin, whose outward unit normal is n, that a segment takes
// instead of eq. (5)'s q* when q* would end inside the skin's margin. Coulomb friction holds the
// styling force's pull along the skin back by mu times its push into it (hair pressed on a
// shoulder stays there until the slope pulls harder than it presses); the bending stiffness κ
// keeps the previous direction q0 with its part into the skin taken out. Turned `lift` (the
// sine of the angle) out of the tangent plane, so the segment's end clears the margin. Where
// nothing pulls along the skin and q0 ran straight into it, the styling force's tangential
// part decides, else any tangent.
inline Vec3f slide_direction(const Vec3f& phi, const Vec3f& q0, const Vec3f& n, float kappa,
                             float mu, float lift) {
    const float into = -phi.dot(n);
    Vec3f pull = phi + into * n;  // tangential part
    const float t = pull.norm();
    const Vec3f free_pull = pull;
    if (t > 0.f) pull *= std::max(0.f, 1.f - mu * std::max(into, 0.f) / t);
    Vec3f along = pull + kappa * (q0 - std::min(0.f, q0.dot(n)) * n);
    along -= along.dot(n) * n;
    float len = along.norm();
    if (!(len > 1e-4f)) {
        along = free_pull;
        len = t;
    }
    if (!(len > 1e-6f)) {
        along = std::abs(n.x()) < 0.9f ? Vec3f::UnitX().cross(n) : Vec3f::UnitY().cross(n);
        len = along.norm();
    }
    const float up = std::clamp(lift, 0.f, 1.f);
    return along / len * std::sqrt(1.f - up * up) + up * n;
}

// A constraint group resolved for the solver.
struct SolverGroup {
    std::string name;
    std::vector<uint32_t> wisps;
    std::vector<Constraint> queue;
};

struct SolveStats {
    size_t joints = 0;       // joint placements (wisps × segments)
    size_t bends = 0;        // Δθ bends taken by collision handling (eq. (6) iterations)
    size_t collisions = 0;   // joints that collided at least once
    size_t unresolved = 0;   // joints still colliding after max_tries bends
    size_t projected = 0;    // joints pushed back out of the head after that
    size_t contacts = 0;     // joints that slid along the skin (slide_direction)
    size_t constrained = 0;  // joints placed under a constraint field
    // Per group (§4): how far through its queue it got. A wisp belongs to the first group
    // that selects it; `met[k]` is the fraction of the group's wisps that met constraint k.
    struct Group {
        std::string name;
        int constraints = 0;     // in its queue
        int completed = 0;       // constraints the group moved past (all or enough wisps met,
                                 // or 95% by the end)
        size_t wisps = 0;        // wisps it holds
        std::vector<float> met;  // #constraints
    };
    std::vector<Group> groups;
    // Per wisp: how many constraints of its group's queue it met (0 for a wisp in no group),
    // counted where `Group::met` is: over a group's wisps they sum to Σ_k met[k]·wisps (the
    // editor's colour by constraint progress).
    std::vector<uint16_t> wisp_met;
    // Per wisp: the arc length from the root (cm) through which a holding constraint
    // (Constraint::hold: a tie, a bun) holds it, the end of the last such segment; 0: none.
    std::vector<float> held_length;
    // The run was cancelled (SolveInput::cancel) before it finished: the masters are partly
    // solved and the other figures partial; the caller publishes nothing from it.
    bool cancelled = false;
};

// Everything the solver reads.
struct SolveInput {
    const StylingField* field = nullptr;
    const HeadField* head = nullptr;
    std::vector<SolverGroup> groups;
    std::vector<int> wisp_strands;      // #W strands carried by each wisp
    std::vector<float> wisp_radius;     // #W root radius of each wisp, cm
    std::vector<float> radius_profile;  // #n r(s_j)/r(0) at each joint
    // #W or empty: the arc length (cm) from each root over which the master keeps the
    // direction it leaves the scalp, easing off over the second half (root lift); a
    // constraint's pull takes over from it.
    std::vector<float> root_hold;
    // Polled once per layer of joints (breadth-first) or per wisp (depth-first), and told the
    // progress after each layer (every 1/64 of the wisps depth-first); null: never.
    const CancelToken* cancel = nullptr;
    // Breadth-first, how a layer's joints are placed; every schedule gives the same bytes.
    enum class Schedule {
        kIdOrder,     // one after another in wisp id order (the reference)
        kConcurrent,  // concurrently where they cannot interact, when threads allow (else kIdOrder)
        kByLevel,     // kConcurrent's schedule even on one thread, whose order then differs from
                      // id order: a test of its dependency analysis
    };
    // kIdOrder by default: on 2 idle cores kConcurrent's waits cost what its overlap gains
    // (BM_Solve2000Wisps 56.3 ms against 48.1, BM_EditStiffnessMasters 20.1 against 17.6).
    Schedule schedule = Schedule::kIdOrder;
    // The solve ends with every master's frames and control points (update_master); false
    // leaves them to the caller, whose details may still be being synthesized (the solve reads
    // only the outlines, roots, segments and directions).
    bool update_frames = true;
    // When given, told how many leading joints of every master are final: after each
    // breadth-first layer (its joints 0 … j + 1), and n when the solve finishes (depth-first,
    // only then); a store with release order, then notify_all. Work beside the solve (the
    // masters' frames and members, band by band) waits on it and may then read those joints of
    // the outlines, which the solve no longer writes. A cancelled solve leaves it below n.
    std::atomic<int>* joints_final = nullptr;
};

// Algorithm 1. Masters' outlines are rebuilt joint by joint from their roots; details ride on
// the rotated frames (update_master). `density` is the hair density grid, cleared first.
// Deterministic: the result is that of visiting wisps in id order, at any thread count
// (breadth-first, `schedule` may place wisps whose joints are far apart concurrently).
SolveStats solve_masters(Masters& masters, const SolveInput& in, const SolveSpec& spec,
                         Grid3<float>& density);

}  // namespace wisp
