#pragma once
// How much of the head a hairstyle hides, seen along a direction: the face it veils and the
// scalp it leaves bare. These are the measures by which wisp's presets are checked (issue
// 12): real styles frame the face and cover the scalp away from a parting.
//
// Both work on an orthographic grid of square cells across the view. The head mesh is
// rasterized into it (nearest surface per cell centre); hair is sampled along every segment
// at most half a cell apart, and the samples on or in front of the surface (within
// `tolerance` behind it, so hair lying on the skin counts) add their projected area, width ×
// length, to their cell. A cell is covered when that area makes it at least half opaque:
// 1 − exp(−area / cell²) ≥ ½. `width_scale` multiplies every strand's width, so a test with a
// fifth of a style's strands can stand in for all of them with widths × 5.
#include <functional>

#include "core/hair.hpp"
#include "geometry/scalp.hpp"
#include "groom/head.hpp"

namespace wisp {

// An orthographic view: cells of `cell` cm across the plane ⟂ `forward`, with `right` and
// `up` spanning it (unit, orthogonal).
struct OrthoView {
    Vec3f forward = -Vec3f::UnitZ();
    Vec3f right = Vec3f::UnitX();
    Vec3f up = Vec3f::UnitY();
    float cell = 0.5f;       // cm
    float tolerance = 0.3f;  // cm behind the surface that still counts as covering it
};

// The named views of the scalp check: "top" (from +Y, face up), "back" (from −Z), "left"
// (the subject's left, from +X), "right" (from −X), "front" (from +Z).
OrthoView ortho_view(const std::string& name, float cell = 0.5f);

struct Coverage {
    size_t cells = 0;    // cells of the region seen
    size_t covered = 0;  // of those, cells with hair on or in front of the surface
    float fraction() const { return cells ? float(covered) / float(cells) : 0.f; }
};

// The face window (eyes to chin, `half_width` cm either side of the midline x = 0), seen
// from the front: a cell is in the region when the head's surface is seen there.
// eye_y, chin_y  heights of the eye line and the chin, cm, head space.
Coverage face_coverage(const Hair& hair, const Mesh& head, float eye_y, float chin_y,
                       float half_width = 4.5f, float cell = 0.5f, float width_scale = 1.f);

// The face's profile seen from one side (`side` "left" or "right"): the head's surface
// between the chin and the eye line that lies forward of the eyes (z ≥ eye_z: eyes, nose,
// lips, chin), which hair framing a face leaves clear.
Coverage profile_coverage(const Hair& hair, const Mesh& head, const std::string& side, float eye_y,
                          float chin_y, float eye_z, float cell = 0.5f, float width_scale = 1.f);

// The scalp seen along `view`: cells whose nearest surface is a scalp face (and whose scalp
// point `exclude` does not reject, such as points along a parting, and that lies where the
// `hairline`'s density is full (hairline_density: a soft, irregular hairline thins out by
// design), and of those the ones hair covers. bare = cells − covered.
Coverage scalp_coverage(const Hair& hair, const Scalp& scalp, const OrthoView& view,
                        const std::function<bool(const Vec3f&)>& exclude = {},
                        float width_scale = 1.f, const HairlineSpec* hairline = nullptr);

// The face window's landmarks of a head facing +Z: the nose tip, the eye line and the chin,
// as find_landmarks found them on the head's own mesh (Head::landmarks). Where it found none,
// they are placed from the most forward vertex near the midline (the nose tip) and the crown in
// human proportion (coverage.cpp). Throws wisp::Error if no vertex can be the nose.
struct FaceLandmarks {
    Vec3f nose_tip = Vec3f::Zero();
    float eye_y = 0.f, chin_y = 0.f;  // cm
    float eye_z = 0.f;                // cm: how far forward the eyes lie
};
FaceLandmarks face_landmarks(const Head& head);

}  // namespace wisp
