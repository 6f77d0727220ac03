#pragma once
// Collision proxies for the character's body (Bertails et al. 2003 §4.1, §4.3): a few
// spheres fitted inside the head, neck and shoulders of a mesh. Hair is pushed out of them
// by moving the child node of the penetrating segment, whose velocity becomes the
// obstacle's (static friction rather than bouncing).
//
// The spheres are inscribed: each lies `inset` inside the surface, so none contains a hair
// root (roots sit on the surface) and hair at rest is already outside them. They are chosen
// to hug the surface where hair goes rather than to fill the volume (the deepest-point greedy
// spends them deep in the chest):
//   1. candidates: the interior samples of a grid of `spacing` over the mesh above the reach
//      of the hair, each with the largest inscribed sphere there (radius = depth − inset, at
//      least `min_radius`);
//   2. targets: the surface as area-weighted points, one per grid cell it crosses (a flat cut
//      at the bottom of the mesh, like the built-in head's chest, left out);
//   3. greedy set cover: the next sphere is the candidate that comes within `cover` of the
//      most target area no sphere comes within `cover` of yet (ties: the lowest grid index),
//      until `max_spheres` are placed or the best adds less than 0.1% of the area;
//   4. refinement: each sphere in turn, the others fixed, moves by half-cell steps (at most
//      4) toward whichever of its 26 neighbours comes near more target area, taking the
//      inscribed radius there.
// The spheres come in the order picked, the most useful first. An open mesh's holes are
// closed by a fan about each boundary loop's centroid before measuring depths, and spheres
// keep 0.5 cm more from these caps (near a hole the winding number is about 1/2, so "inside"
// is ambiguous there). On the built-in head (ears, nose and lips, which spheres fit least
// well) the default 32 spheres come within 1 cm of 82% of the surface above the chest cut
// and within 2 cm of 97.7%, in about 150 ms on 2 cores.
#include <vector>

#include "core/math.hpp"
#include "geometry/mesh.hpp"
#include "solve/styling_field.hpp"  // HeadFrame

namespace wisp {

struct Sphere {
    Vec3f center = Vec3f::Zero();  // cm, head space
    float radius = 0;              // cm
    bool head = true;              // moves with the head track (else with the body track)
};

struct BodyFitOptions {
    int max_spheres = 32;     // ≥ 0
    float min_radius = 1.0f;  // cm: the smallest sphere, ≥ 0
    float spacing = 1.0f;     // cm: the grid of candidate centres and surface targets, > 0
    float cover = 1.0f;       // cm: a sphere covers the surface within this distance, > 0
    float inset = 0.2f;       // cm: how far inside the surface spheres stay, ≥ 0
    float reach = 4.5f;       // head radii: fit the mesh above head.center.y − reach·radius
                              // only (of a full body, the part down to the chest), > 0
};

// Fits spheres inside `mesh` (closed, or open like a head cut at the chest: inside is the
// winding number). Spheres whose centre lies above the chin level (head.center.y −
// 0.8·head.radius) are head spheres; the rest body. Deterministic: the same mesh and options
// give identical spheres at any thread count. Throws wisp::Error on invalid options or when
// the mesh encloses no volume (no faces, or no interior sample deep enough).
std::vector<Sphere> fit_body_spheres(const Mesh& mesh, const HeadFrame& head,
                                     const BodyFitOptions& options = {});

// Shrinks every sphere that comes within `margin` cm of one of `points` (head space), centre
// kept, until the nearest such point lies `margin` cm outside it; a sphere that would shrink
// below 0.25 cm is removed (the others keep their order). Used so that the rest pose of the
// hair is collision-free. O(#spheres · #points).
void clear_spheres_of(std::vector<Sphere>& spheres, const std::vector<Vec3f>& points, float margin);

// Signed distance from p to the union of spheres (world space: spheres given already moved):
// the minimum over spheres of |p − center| − radius, with that sphere's index in *nearest
// (if not null); +infinity and −1 when there are none.
float sphere_distance(const std::vector<Sphere>& spheres, const Vec3f& p, int* nearest);

}  // namespace wisp
