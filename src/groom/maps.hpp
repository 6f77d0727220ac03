#pragma once
// Scalp maps (Choe & Ko §2.3, Fig. 8): density, length and protrusion over the scalp.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/image.hpp"
#include "geometry/scalp.hpp"
#include "groom/style.hpp"

namespace wisp {

// Names accepted by ScalarMap::Kind::kProcedural, each a value in [0,1] over the scalp:
//   uniform     1 everywhere
//   bangs       1 except a fringe over the forehead that falls to 0.35 (short bangs when
//               used as a length map)
//   nape-short  1 on top falling to 0.3 toward the nape and the sides above the ears
//   crown       1 at the crown falling to 0 at the hairline
//   hairline    0 at the crown rising to 1 at the hairline
//   front       1 at the front hairline falling to 0 at the back
//   back        0 at the front rising to 1 at the back
//   side-part   0.15 along a parting line on the left of the crown, 1 elsewhere (density)
//   left        0 at the right hairline rising to 1 at the left (the character's left, +X);
//               above 0.5 on the left half
//   right       its mirror: above 0.5 on the right half
//   nape        1 along the nape hairline, 0 on top and at the front (the low back)
//   sides       1 above and behind the ears, 0 on top, at the front and at the nape
//   part        1 along the style's parting ([growth] part), falling to 0 about 1.3 cm to
//               either side of it; 0 everywhere with no part (the lift along the part)
//   crown-part  blow-dried lift: 1 on the top of the head (the inner 15% of the map), falling
//               smoothly to 0 by the upper sides (70%), and along the part (the larger)
//   tapered     a barber's taper: longest on top toward the front, falling down the back
//               (to 0.15 at the nape) and the sides (to 0.25), and 0 around the ears (within
//               about a fifth of the head's height of them, rising to 1 by half; the ears
//               where the head's landmarks place them, else under the map's sides)
// Constraint groups select a named region's roots where its map is above 0.5.
const std::vector<std::string>& procedural_map_names();

// How wide the hairline's density ramp is at scalp point p for a hairline of `width` cm
// ([hairline] width): 2.5 times as wide at the temples and down the sideburns (the sides of
// the head in front of the ears), so that the temples recede and sideburns thin to their
// ends instead of stopping at a line.
float hairline_ramp(const Scalp& scalp, const Vec3f& p, float width);

// How far scalp point p lies inside the hairline ([hairline] irregularity), cm: its distance
// from the scalp's edge (Scalp::edge_distance, `edge`) less how far the line wanders in
// there: `irregularity` times a smooth noise of p in [0, 1] (two octaves, about 1.5 and 0.6
// cm across), plus half of it at the temples. The noise is the head's, not the style's: every
// style on one head has the same hairline. Negative outside the line.
float hairline_edge(const Scalp& scalp, const Vec3f& p, float edge, float irregularity);
// The same, at a scalp point.
float hairline_edge(const Scalp& scalp, const SurfacePoint& p, float irregularity);
// The most hairline_edge() takes off the edge distance.
inline float hairline_wander(float irregularity) {
    return 1.5f * irregularity;
}

// The hairline's root density at scalp point p (0 … 1): a smooth ramp from 0 at the line to 1
// hairline_ramp() inside it; without a ramp (width 0), 0 outside the line and 1 inside.
float hairline_density(const Scalp& scalp, const Vec3f& p, float edge, const HairlineSpec& spec);

// How flat a root at the hairline lies ([hairline] lie, width): `lie` at the line, falling to
// 0 at three times `width` inside it; 0 without a ramp. Roots there lie low along their
// growth direction, neither protruding nor lifted.
float hairline_lie(const Scalp& scalp, const SurfacePoint& root, const HairlineSpec& spec);

// A map ready for lookups; image maps are loaded once.
class MapSampler {
  public:
    // Loads the image of an image map (throws wisp::Error naming it if unreadable). `growth`
    // places the part of the part maps (the default's centre part without one).
    MapSampler(const ScalarMap& map, const Scalp& scalp, const GrowthSpec& growth = {});
    // The map's value (in its own units) at a scalp point.
    float operator()(const SurfacePoint& p) const;
    // Multiplies the map by the hairline's density (hairline_density); a hard line at the
    // edge itself (width and irregularity 0) leaves the map as it is.
    void set_hairline(const HairlineSpec& spec) {
        if (spec.width > 0.f || spec.irregularity > 0.f) hairline_ = spec;
    }

  private:
    ScalarMap map_;
    const Scalp* scalp_;
    GrowthSpec growth_;
    std::shared_ptr<const GrayImage> image_;
    int procedural_ = -1;
    std::optional<HairlineSpec> hairline_;
    float value(const SurfacePoint& p) const;
};

}  // namespace wisp
