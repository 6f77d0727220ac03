#pragma once
// Stochastic HSV hair color (Choe & Ko §5, Fig. 12).
#include <cstdint>
#include <span>

#include "core/math.hpp"
#include "groom/style.hpp"

namespace wisp {

// HSV (hue in degrees, saturation and value in [0,1]) to RGB in [0,1].
Vec3f hsv_to_rgb(const Vec3f& hsv);
// sRGB-encoded value to linear.
float srgb_to_linear(float c);

// Colors every strand: hue, saturation and value drawn independently from their
// distributions (per strand), each offset by the strand's wisp draw when the wisp
// variation is non-zero (Fig. 12d). The HSV model is over display (sRGB) values; the
// result is linear RGB.
//   wisp   #S wisp id per strand;  out  #S linear RGB
//   ids    #S the strand whose colour out[i] is (its random stream), or empty for i: a
//          subset of the strands gets the colours the whole hair gives them
void color_strands(const ColorSpec& spec, uint64_t seed, std::span<const int32_t> wisp,
                   std::span<Vec3f> out, std::span<const uint32_t> ids = {});

}  // namespace wisp
