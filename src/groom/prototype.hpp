#pragma once
// Prototype strands and their outline/details decomposition (Choe & Ko §2.2.1, Fig. 5).
#include <span>
#include <vector>

#include "core/math.hpp"
#include "groom/style.hpp"

namespace wisp {

// The dense polyline of a prototype (cm, root first): a built-in preset generated along +Y
// with the spec's amplitude, period and length, or the user's polyline as given.
//   straight  a line
//   wavy      a planar sine wave of the given amplitude and period
//   curly     a helix of radius `amplitude` and pitch `period`
//   kinky     a tight coil (radius amplitude, pitch period/2) with a second, small
//             zig-zag riding on it, as in type-4 hair
std::vector<Vec3f> prototype_polyline(const PrototypeSpec& spec);

// True for a prototype without details: the straight preset, or a wave or coil of no
// amplitude.
inline bool is_straight(const PrototypeSpec& spec) {
    return spec.kind == PrototypeSpec::Kind::kStraight ||
           (spec.kind != PrototypeSpec::Kind::kPolyline && spec.amplitude <= 0.f);
}

// A polyline resampled at even arc length and its low-pass centre line, from which
// outlines of any segment length are cut (decompose() below).
struct PrototypeCurve {
    std::vector<Vec3f> curve;       // #K samples of the prototype, evenly spaced in arc length
    std::vector<Vec3f> centre;      // #K the same samples smoothed over `smoothing` cm
    std::vector<float> centre_arc;  // #K arc length along centre, from 0
};

// The prototype of a style, ready to decompose: presets sampled along their parameter with
// their exact centre line (the axis of the wave or coil); a user polyline through
// prepare_prototype() with spacing period/41 and smoothing `period` (the scale of its largest
// regular structure, §2.2.2).
PrototypeCurve make_prototype_curve(const PrototypeSpec& spec);

// Resamples `polyline` (#≥2) every `spacing` cm and smooths it with a centred moving
// average over `smoothing` cm of arc length (the window shrinks symmetrically at the ends,
// so the root keeps a zero detail). A smoothing equal to the wave period removes a sine
// wave exactly, leaving the straight outline of Fig. 5b.
PrototypeCurve prepare_prototype(std::span<const Vec3f> polyline, float spacing, float smoothing);

// Cuts the centre line into an outline of equal segments of `segment` cm (§2.2.1) and
// returns the details δ_i = p_i − c_i expressed in each outline segment's local frame
// (Frame::to_local), #⌊length/segment⌋+1. Empty if the curve is shorter than 2 segments.
std::vector<Vec3f> decompose(const PrototypeCurve& proto, float segment);
// The same into `details` (resized; emptied where the above returns empty), with `work`
// (#2·count, resized) for the outline and curve samples: reused buffers, so that
// decomposing once per master does not allocate.
void decompose(const PrototypeCurve& proto, float segment, std::vector<Vec3f>& details,
               std::vector<Vec3f>& work);

}  // namespace wisp
