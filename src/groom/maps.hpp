#pragma once
// Scalp maps (Choe & Ko §2.3, Fig. 8): density, length and protrusion over the scalp.
#include <memory>
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
//   tapered     a crop: nape-short's fall toward the nape (to 0.35), and 0 around the ears
//               (within about a fifth of the head's height of them, rising to 1 by two fifths;
//               the ears where the head's landmarks place them, else under the map's sides)
// Constraint groups select a named region's roots where its map is above 0.5.
const std::vector<std::string>& procedural_map_names();

// A map ready for lookups; image maps are loaded once.
class MapSampler {
  public:
    // Loads the image of an image map (throws wisp::Error naming it if unreadable).
    MapSampler(const ScalarMap& map, const Scalp& scalp);
    // The map's value (in its own units) at a scalp point.
    float operator()(const SurfacePoint& p) const;
    // Multiplies the map by a smooth ramp from 0 at the scalp's edge to 1 at `width` cm from
    // it (Scalp::edge_distance): the hairline's density. 0: no ramp.
    void set_edge_ramp(float width) { edge_ramp_ = width; }

  private:
    ScalarMap map_;
    const Scalp* scalp_;
    std::shared_ptr<const GrayImage> image_;
    int procedural_ = -1;
    float edge_ramp_ = 0.f;
    float value(const SurfacePoint& p) const;
};

}  // namespace wisp
