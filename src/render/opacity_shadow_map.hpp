#pragma once
// Opacity shadow maps (Kim & Neumann 2001, "Opacity Shadow Maps"; the self-shadowing of
// Bertails et al. 2003), the deep-shadow stand-in of Choe & Ko 2005 §5, with the slabs of deep
// opacity maps (Yuksel & Keyser 2008, "Deep Opacity Maps"). The hair's volume is cut along a
// directional light into `slices` slabs, per texel starting at the hair nearest the light
// there (the least depth over the texel and its neighbours); every strand piece deposits its
// opacity — width × length / texel area × strand_opacity — into the texel and slab it
// crosses; a running sum along the light gives, at each slab boundary, the optical depth τ of
// the hair in front of it. A point's transmittance is exp(-τ) with τ interpolated trilinearly.
// Slabs cut by planes (Kim & Neumann's) cross the curved surface of the hair, which then
// enters each slab at its start in some places and at its end in others, so the hair just
// under the surface is shadowed more or less in stripes across a crown. Slabs that start at
// the surface follow it. And they grow with depth (boundary k at depth D·(k/slices)², D the
// map's depth), as Yuksel & Keyser's layers do: thin where the outer layer of hair takes the
// light and its shadows show, thick deep inside, where little light arrives.
//
// Deposits are summed as fixed-point integers, so the map is bit-identical whatever the
// thread count or the order in which strands are visited.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/hair.hpp"
#include "core/math.hpp"

namespace wisp {

// An orthonormal light frame for a directional light: w is the direction the light travels
// (away from the light), u and v span the map.
struct LightFrame {
    Vec3f u, v, w;
    static LightFrame towards(const Vec3f& to_light);  // to_light: unit, towards the light
    Vec3f to_light_space(const Vec3f& p) const { return {p.dot(u), p.dot(v), p.dot(w)}; }
};

// The strands of `hair` ordered along a Z-order (Morton) curve of their middle control
// point projected on the light's (u, v) plane, so that strands visited one after another
// touch the same texels: the map's memory is then read and written with cache hits. Any
// order gives the same results; this one only makes them faster.
std::vector<uint32_t> light_space_order(const Hair& hair, const LightFrame& light);

// The indices of points (#n) sorted by the Z-order (Morton) code of the points in their
// bounding box (16 bits per axis), ties by index.
std::vector<uint32_t> morton_order(std::span<const Vec2f> points);

struct OpacityShadowMapOptions {
    int resolution = 256;         // texels along u and along v
    int slices = 64;              // slabs along the light
    float strand_opacity = 0.5f;  // fraction of the light one strand crossing a texel fully
                                  // would block
    float width_scale = 1.f;      // as RenderOptions::width_scale
    float tip_width = 0.3f;       // as RenderOptions::tip_width
    // Deposit every n-th strand of the (light-space ordered, so spatially even) order with n
    // times its opacity: the same expected optical depth for 1/n of the walk, for maps too
    // coarse to resolve single strands (the rim light's).
    int strand_stride = 1;
};

class OpacityShadowMap {
  public:
    OpacityShadowMap() = default;
    // Accumulates every strand of `hair` in the light frame over `bounds` (cm, head space;
    // hair outside it is clamped to its border texels and slabs), visiting the strands in
    // `order` (#S, a permutation; light_space_order() if empty).
    OpacityShadowMap(const Hair& hair, const LightFrame& light, const Box3& bounds,
                     const OpacityShadowMapOptions& options, std::span<const uint32_t> order = {});

    // Optical depth of the hair between the light and p (cm, head space); 0 without hair.
    float optical_depth(const Vec3f& p) const;
    float transmittance(const Vec3f& p) const;

    int resolution() const { return nx_; }
    int slices() const { return nz_; }
    float texel_size() const { return std::max(du_, dv_); }  // cm

  private:
    // The slab coordinate (boundary k at k) of a depth behind a texel's nearest hair.
    float slab(float depth) const {
        return static_cast<float>(nz_) * std::sqrt(std::max(depth, 0.f) * inv_depth_);
    }

    LightFrame light_{};
    Vec3f lo_ = Vec3f::Zero();  // light-space corner of the map
    float du_ = 1, dv_ = 1, dw_ = 1;
    float inv_depth_ = 1;  // 1 / D
    int nx_ = 0, ny_ = 0, nz_ = 0;
    // tau_  #ny·nx·(nz+1), optical depth at slab boundary k of texel (x, y), at
    //       ((y·nx + x)·(nz+1) + k); boundary k lies at depth near_[y·nx + x] + D·(k/nz)²,
    //       D = nz·dw_.
    // near_ #ny·nx, light-space depth where the texel's slabs start (+inf: no hair near).
    std::vector<float> tau_;
    std::vector<float> near_;
};

}  // namespace wisp
