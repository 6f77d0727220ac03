#pragma once
// Kajiya & Kay's hair reflectance ("Rendering Fur with Three Dimensional Textures",
// SIGGRAPH 1989, §4), the shading model of Choe & Ko 2005 §5. A strand is a thin cylinder
// seen only through its unit tangent t: the diffuse term integrates Lambert over the
// half-cylinder facing the light, the specular term is a Phong lobe around the cone of
// mirror directions. Pure functions on unit vectors.
#include <algorithm>
#include <cmath>

#include "core/math.hpp"

namespace wisp {

// sin of the angle between unit vectors a and b, from their dot product.
inline float sin_from_cos(float cos_ab) {
    return std::sqrt(std::max(0.f, 1.f - cos_ab * cos_ab));
}

// Diffuse term: sin(t, l) (Kajiya & Kay eq. for Ψ_diffuse up to the constant k_d).
// t  unit tangent, l  unit vector towards the light. In [0, 1]; 1 when l ⟂ t.
inline float kajiya_kay_diffuse(const Vec3f& t, const Vec3f& l) {
    return sin_from_cos(t.dot(l));
}

// Cosine between the eye direction and the cone of mirror directions of the light around t:
// cos(θ_e + θ_l − π) = sin(t,l)·sin(t,e) − (t·l)(t·e). 1 exactly when e lies on the cone,
// i.e. t·e = −t·l.
inline float kajiya_kay_cone_cosine(const Vec3f& t, const Vec3f& l, const Vec3f& e) {
    const float tl = t.dot(l), te = t.dot(e);
    return sin_from_cos(tl) * sin_from_cos(te) - tl * te;
}

// Specular term: max(0, cone cosine)^exponent (Kajiya & Kay's Ψ_specular up to k_s).
// e  unit vector towards the eye.
inline float kajiya_kay_specular(const Vec3f& t, const Vec3f& l, const Vec3f& e, float exponent) {
    const float c = kajiya_kay_cone_cosine(t, l, e);
    return c > 0.f ? std::pow(c, exponent) : 0.f;
}

// Lambert's cosine for the head's skin: max(0, n·l).
inline float lambert(const Vec3f& n, const Vec3f& l) {
    return std::max(0.f, n.dot(l));
}

}  // namespace wisp
