#pragma once
// Styling constraints (Choe & Ko §4, Fig. 10, eq. (7)) and wisp selection.
#include <cstdint>
#include <vector>

#include "geometry/scalp.hpp"
#include "groom/style.hpp"
#include "solve/styling_field.hpp"

namespace wisp {

// A constraint with its positions resolved to centimetres in head space.
struct Constraint {
    ConstraintSpec::Kind kind = ConstraintSpec::Kind::kPoint;
    Vec3f point = Vec3f::Zero();
    std::vector<Vec3f> path;  // #≥2 dense polyline of the trajectory (Catmull-Rom sampled
                              // when smooth)
    std::vector<float> arc;   // #path cumulative arc length, cm
    float radius = 1.f;       // cm
    float weight = 1.f;
    bool hold = false;  // ConstraintSpec::hold
    // The head's sphere (HeadFrame): a point constraint's pull wraps around it. Radius 0: no
    // head, pull in straight lines.
    Vec3f head_center = Vec3f::Zero();
    float head_radius = 0.f;
    float repeat_from = -1.f;  // arc length from which a bun's trajectory repeats; < 0: never
};

Constraint resolve_constraint(const ConstraintSpec& spec, const HeadFrame& head);

// Nearest point of the constraint's path to x: its position, unit tangent and parameter in
// [0, 1] by arc length.
struct PathPoint {
    Vec3f position, tangent;
    float t = 0.f;
};
PathPoint nearest_on_path(const Constraint& c, const Vec3f& x);
// The same among the path's points with arc length in [lo, hi] (cm); `arc` receives the
// nearest point's arc length.
PathPoint nearest_on_path(const Constraint& c, const Vec3f& x, float lo, float hi, float* arc);
// The path's point at arc length s (clamped to the path), and its unit tangent.
PathPoint point_at_arc(const Constraint& c, float s);

// Ψ(x) of §4: point: the unit vector toward the attraction point, or, further than ~15° from
// it seen from the head's centre, along the head's sphere toward it (as a hand draws hair
// over the scalp to a tie), drawn in a little to hug the scalp; trajectory:
// toward the
// nearest point of the trajectory outside the tolerance radius, along its tangent inside;
// direction: along the tangent inside the influence radius, zero outside.
Vec3f constraint_force(const Constraint& c, const Vec3f& x);

// Whether a wisp whose segment runs from a to b meets the constraint: point: the segment
// passes through the tolerance sphere (segments may be longer than the sphere is wide);
// trajectory: b is within tolerance at the trajectory's end; direction: b is at the end of
// the trajectory, or outside the influence radius (the comb no longer holds it).
bool constraint_met(const Constraint& c, const Vec3f& a, const Vec3f& b);

// Eq. (7): Φ' = (1 − w)Φ + wΨ.
inline Vec3f constrained_field(const Vec3f& phi, const Vec3f& psi, float w) {
    return (1.f - w) * phi + w * psi;
}

// The wisps a selection holds, ascending. roots  #W master roots; `growth` places the part
// of the part regions.
std::vector<uint32_t> select_wisps(const Selection& selection,
                                   const std::vector<SurfacePoint>& roots, const Scalp& scalp,
                                   const HeadFrame& head, const GrowthSpec& growth = {});

}  // namespace wisp
