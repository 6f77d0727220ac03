#pragma once
// Head landmarks found from the mesh alone: which way the face looks, the crown, brow, nose,
// eyes, chin, ears and neck of any head (the built-in one, a scan, a MakeHuman body), with no
// face groups, UVs or markers. The mesh must be Y-up (wisp's convention) but may face any
// horizontal direction, be of any size (its units are kept) and sit anywhere.
#include "geometry/mesh.hpp"

namespace wisp {

// The landmarks of a head, in the mesh's space and units (cm for wisp's head meshes). Points on
// the midline lie on the head's plane of mirror symmetry.
struct Landmarks {
    Vec3f forward = Vec3f::UnitZ();  // unit, horizontal: the way the face looks
    Vec3f crown = Vec3f::Zero();     // the top of the head, on the midline
    Vec3f brow = Vec3f::Zero();      // glabella: the brow's most forward point on the midline
    Vec3f nose_tip = Vec3f::Zero();  // the nose's most forward point on the midline
    // Eye centres (approximate: the middle of each socket's hollow or opening, a fixed fraction
    // of the head's height behind the face's surface there). The character's left is +X when
    // facing +Z: left = up × forward.
    Vec3f eye_left = Vec3f::Zero(), eye_right = Vec3f::Zero();
    Vec3f chin = Vec3f::Zero();  // menton: the lowest point of the chin, on the midline
    // The ears' outermost points (smoothed: see find_landmarks).
    Vec3f ear_left = Vec3f::Zero(), ear_right = Vec3f::Zero();
    Vec3f center = Vec3f::Zero();  // the head's centre: midway between ear_left and ear_right
    float height = 0;              // chin to crown (crown.y - chin.y)
    // The centre of the neck's narrowest horizontal section below the chin, and that section's
    // radius (of the circle of the same area).
    Vec3f neck = Vec3f::Zero();
    float neck_radius = 0;
    // True when the mesh has no shoulders (a scan ending at the neck); neck_bottom is then the
    // y where the mesh ends below the neck, else NaN.
    bool head_only = false;
    float neck_bottom = NAN;
};

// Finds the landmarks of the head on the connected piece of `mesh` of largest area (so the
// eyes, teeth and helper shells of full-body meshes are skipped), in five stages:
//  1. horizontal sections walked down from the top, each as the radius of the circle of its
//     area: the head is where they first widen and then narrow by 15% or more; the neck is
//     the narrowest before they widen again by 30% (shoulders) or the mesh ends. Its height
//     below the top sets the scale of everything after;
//  2. the plane of mirror symmetry of the head above the mouth: the vertical plane that maps
//     the head's vertices nearest onto others (a sweep every 10°, the angle refined to 1/8°
//     with distances along the surface's normals, the offset by iterating closest points);
//  3. the midline profile, the head cut by that plane: the face is on the side with the
//     sharper bump (the nose); the nose tip is its most forward point; the crown its top (at
//     the middle of the chord just below, as the top of the head is flat); the chin the
//     extreme 10° forward of straight down on the face's outline below the nose, before it
//     falls back to the throat (so that a flat underside of the chin gives its front edge; the
//     mouth must be closed).
//     The neck is the narrowest closed section 0.02-0.8 height below the chin (its area
//     centroid), or just below the chin on a mesh that ends sooner;
//  4. the face as a depth map seen from the front, its columns closed over ±0.06 height (so
//     the eye sockets fill between brow and cheek, but not the slope beside the nose): each
//     eye is the centroid of its side's hollows (filled minus depth, capped at 0.02 height, so
//     that an eye opening into the head counts like a socket), 0.07 height behind the filled
//     surface; the brow is the most forward row above the eyes, averaged between them, on the
//     midline;
//  5. the ears: the head's lateral extremes from the bottom of the nose to 0.1 height above
//     the eye line, as the centroid of the vertices within 0.02 height of each extreme.
// The mesh is head_only when it ends less than 1.5 heights below the chin and no closed
// section between the neck and its end is more than 1.5 times the neck's radius; neck_bottom
// is then its lowest y. Deterministic; about 10-15 ms for 35k triangles on one core.
// Throws wisp::Error naming what is missing when the mesh has no head: no faces, no section
// that narrows below a wider one (a box, a cylinder), or no face on the midline (a sphere, an
// egg: no side has a bump like a nose); and naming the first non-finite vertex or face index
// out of range.
Landmarks find_landmarks(const Mesh& mesh);

}  // namespace wisp
