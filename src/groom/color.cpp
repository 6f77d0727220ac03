#include "groom/color.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "groom/distribution.hpp"

namespace wisp {

Vec3f hsv_to_rgb(const Vec3f& hsv) {
    float h = std::fmod(hsv.x(), 360.f);
    if (h < 0.f) h += 360.f;
    const float s = std::clamp(hsv.y(), 0.f, 1.f), v = std::clamp(hsv.z(), 0.f, 1.f);
    const float c = v * s;
    const float hp = h / 60.f;
    const float x = c * (1.f - std::abs(std::fmod(hp, 2.f) - 1.f));
    Vec3f rgb;
    if (hp < 1)
        rgb = {c, x, 0};
    else if (hp < 2)
        rgb = {x, c, 0};
    else if (hp < 3)
        rgb = {0, c, x};
    else if (hp < 4)
        rgb = {0, x, c};
    else if (hp < 5)
        rgb = {x, 0, c};
    else
        rgb = {c, 0, x};
    return rgb + Vec3f::Constant(v - c);
}

float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

void color_strands(const ColorSpec& spec, uint64_t seed, std::span<const int32_t> wisp,
                   std::span<Vec3f> out, std::span<const uint32_t> ids) {
    const bool per_wisp =
        spec.wisp_hue > 0.f || spec.wisp_saturation > 0.f || spec.wisp_value > 0.f;
    parallel_for(
        out.size(),
        [&](size_t i) {
            Rng rng(seed, Stream::kColor, ids.empty() ? i : ids[i]);
            Vec3f hsv(sample(spec.hue, rng), sample(spec.saturation, rng), sample(spec.value, rng));
            if (per_wisp && wisp[i] >= 0) {
                Rng wrng(seed, Stream::kWispColor, static_cast<uint64_t>(wisp[i]));
                hsv += Vec3f(spec.wisp_hue * wrng.normal(), spec.wisp_saturation * wrng.normal(),
                             spec.wisp_value * wrng.normal());
            }
            const Vec3f rgb = hsv_to_rgb(hsv);
            out[i] = {srgb_to_linear(rgb.x()), srgb_to_linear(rgb.y()), srgb_to_linear(rgb.z())};
        },
        1024);
}

}  // namespace wisp
