#pragma once
// What hair lies on over an ear: a rounded, flat-faced solid on the side of the head that
// holds the ear and fills the hollow behind it, from the ear's outermost point to a little
// past its outline. Hair that covers an ear drapes over it in one smooth bulge, as real hair
// does, instead of wrapping round the thin rim (which then shows through the hair in a slit)
// or tucking into the hollow behind it. Found from the mesh and its landmarks, so on any head.
#include <array>

#include "geometry/landmarks.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

// A superellipsoid |q|⁴ + (w² + v²)² = 1 in the ear's frame: q across (out of the head), w up,
// v forward, each in units of its radius. Flat over the ear, its lateral extent falls off only
// near the outline. cm, head space.
struct EarEnvelope {
    Vec3f center = Vec3f::Zero();
    Vec3f out = Vec3f::UnitX();      // unit, horizontal, away from the head
    Vec3f forward = Vec3f::UnitZ();  // unit, horizontal, the face's direction
    Vec3f radii = Vec3f::Ones();     // across, up, forward; cm
    // An estimate of the signed distance (cm, negative inside), exact on the surface and
    // good near it: (g − 1) / |∇g| of the implicit g above (|·|⁴ makes g grow as distance⁴,
    // so it is taken to the ¼ power first).
    float distance(const Vec3f& p) const;
};

// The two ears' envelopes (the character's left first), or none when the ears are not found:
// a mesh without landmarks, or no surface standing out at an ear landmark. The ear is the
// skin within 0.2 head heights of its landmark that lies within 0.06 heights of its
// outermost point across the head; the envelope reaches 0.01 heights past that point and
// holds the ear's outline within 0.7 of its radius up and forward.
std::vector<EarEnvelope> ear_envelopes(const Mesh& mesh, const Landmarks& landmarks);

}  // namespace wisp
