#pragma once
// Hairdressing operations of Choe & Ko §6.2 expressed as constraint groups (§4): tying,
// braiding, updos and combing. (Cutting is the length map and CutSpec; permanent waving is
// the prototype.) The style reader expands its [[tie]], [[braid]], [[updo]] and [[comb]]
// sections with these into Style::groups.
#include <vector>

#include "groom/style.hpp"

namespace wisp {

// Tying (a ponytail): a point constraint with w = 1 on the selected wisps.
struct TieSpec {
    Selection selection;
    Vec3f point = Vec3f(0.f, 0.1f, -1.15f);  // head units: behind the head
    float radius = 0.12f;                    // tolerance radius, head units
    float weight = 1.f;
};

// Braiding: the selection is split left to right into `strands` groups (≥ 3); each is
// gathered at `start` by a point constraint, then follows its own braid trajectory: strand i
// has phase φ_i = 2πi/strands and runs along the axis as
//     p(t) = start + t·length·axis + (width/2)·sin(2πt·length/period + φ_i)·side
//            + (width/4)·sin(2·(2πt·length/period + φ_i))·(axis × side)
// so neighbouring strands cross every period/strands along the axis.
struct BraidSpec {
    Selection selection;
    int strands = 3;
    Vec3f start = Vec3f(0.f, -0.35f, -1.15f);  // head units: the nape
    Vec3f axis = Vec3f(0.f, -1.f, -0.15f);     // normalized on use
    Vec3f side = Vec3f(1.f, 0.f, 0.f);         // the braid's width direction (made ⟂ axis)
    float length = 2.5f;                       // head units
    float width = 0.35f;                       // head units
    float period = 0.5f;                       // head units along the axis per full crossing cycle
    float radius = 0.06f;  // tolerance radius of the trajectory constraints, head units
    float weight = 1.f;
};

// An updo: a tie at `point`, then a trajectory that winds the hair into a bun: `turns` turns
// of a spiral of radius `bun_radius` about `point`, in the plane facing `facing`.
struct UpdoSpec {
    Selection selection;
    Vec3f point = Vec3f(0.f, 0.55f, -1.05f);
    Vec3f facing = Vec3f(0.f, 0.3f, -1.f);
    float radius = 0.12f;
    float bun_radius = 0.3f;
    float turns = 2.f;
    float weight = 1.f;
};

// Combing: a direction constraint along a trajectory with influence radius and weight w.
struct CombSpec {
    Selection selection;
    std::vector<Vec3f> trajectory;  // head units, ≥ 2 points
    bool smooth = true;
    float radius = 0.4f;
    float weight = 0.6f;
};

std::vector<GroupSpec> tie_groups(const TieSpec& spec);
std::vector<GroupSpec> braid_groups(const BraidSpec& spec);
// The braid trajectory of strand i, sampled with `samples` points (head units).
std::vector<Vec3f> braid_trajectory(const BraidSpec& spec, int strand, int samples = 64);
std::vector<GroupSpec> updo_groups(const UpdoSpec& spec);
std::vector<GroupSpec> comb_groups(const CombSpec& spec);

}  // namespace wisp
