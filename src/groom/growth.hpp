#pragma once
// The growth direction of hair on the scalp: the tangent direction in which hair leaves the
// skin, as real scalps have it. Hair grows away from a crown whorl, turning about it in the
// whorl's sense; a parting splits the hair on the top of the head to either side of its line;
// at the front hairline hair runs to the sides (past the temples), back, or forward as a
// fringe; at the temples and nape it runs down.
//
// Positions are unit directions from the centre of the scalp's fitted sphere (the head
// frame of solve/styling_field.hpp), in head space: Y up, +Z forward, +X the subject's left.
// The styling field's "growth" term carries the same directions off the scalp, so the
// hair's flow over the head continues what its roots start.
#include "core/math.hpp"

namespace wisp {

struct GrowthSpec {
    enum class Part { kNone, kCentre, kSide };
    enum class Front { kSides, kBack, kFringe };
    Part part = Part::kCentre;
    // kSide: the part's distance from the midline, in head units along x; positive on the
    // subject's left (+X, hair swept to the right), negative on the right. Ignored for kCentre.
    float part_offset = 0.3f;
    // How far the part runs back from the front hairline over the top: up to the whorl at 1,
    // on down the back beyond (2.5 reaches the nape). In (0, 3].
    float part_length = 1.f;
    // Front hairline hair: to the sides of the face past the temples (the part's sides; with
    // no part, either side of the midline), back over the head, or forward as a fringe.
    Front front = Front::kSides;
    // The crown whorl: a direction from the head centre (normalized on use), and its sense
    // seen from above: +1 clockwise (most people), −1 counter-clockwise.
    Vec3f whorl = Vec3f(0.f, 0.93f, -0.37f);
    float whorl_turn = 1.f;
    float whorl_swirl = 0.6f;  // how strongly hair turns about the whorl near it, in [0, 2]
};

// The growth direction at unit direction r from the head centre: a unit vector tangent to the
// sphere at r (⟂ r).
Vec3f growth_direction(const GrowthSpec& spec, const Vec3f& r);

// The part line's x (head units) at the front of the head, signed; 0 for a centre part.
float part_x(const GrowthSpec& spec);

// Whether unit direction r lies within `half_width` (head units) of the part line, which runs
// from the front hairline over the top (part_length). False when there is no part.
bool on_part(const GrowthSpec& spec, const Vec3f& r, float half_width);

}  // namespace wisp
