#pragma once
// A classic depth shadow map (Williams 1978) of the head mesh from a directional light, so
// that the head shadows the hair and itself. Opaque surfaces only; the hair's own shadow is
// the opacity shadow map.
#include <vector>

#include "geometry/mesh.hpp"
#include "render/opacity_shadow_map.hpp"

namespace wisp {

class ShadowDepthMap {
  public:
    ShadowDepthMap() = default;
    // Rasterizes every triangle of `mesh` in the light frame over `bounds` (cm, head space)
    // at resolution × resolution texels, keeping the depth nearest the light.
    ShadowDepthMap(const Mesh& mesh, const LightFrame& light, const Box3& bounds, int resolution);

    // Fraction in [0, 1] of the light reaching p (percentage-closer filtering: nine bilinear
    // tests a texel apart, over the 4×4 nearest texels), with a depth bias of `bias` cm plus
    // 1.5 texels.
    // 1 for an empty map.
    float visibility(const Vec3f& p, float bias = 0.05f) const;

    // How far behind p (cm, along the light) the head's surface nearest the light lies, at
    // the texel nearest p: 0 where p is behind it, +inf where no head is in line.
    float distance_to_surface(const Vec3f& p) const;

    float texel_size() const { return texel_; }  // cm

  private:
    LightFrame light_{};
    Vec3f lo_ = Vec3f::Zero();
    float texel_ = 1;
    int n_ = 0;
    std::vector<float> depth_;  // #n·n, light-space depth nearest the light (+inf if none)
    // #n·n, the least and greatest depth_ over the 4×4 texels visibility() reads for a lookup
    // whose first bilinear texel is (x, y): texels [x−1, x+2] × [y−1, y+2], +inf outside.
    std::vector<float> footprint_lo_, footprint_hi_;
};

}  // namespace wisp
