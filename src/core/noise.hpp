#pragma once
// Smooth value noise in three dimensions: a field that varies gently over a set distance and
// is the same on every platform (integer hashing and arithmetic only, no sin or cos), for
// properties that neighbouring wisps share, such as the phase of their waves.
#include <cmath>
#include <cstdint>

#include "core/math.hpp"
#include "core/rng.hpp"

namespace wisp {

// Value noise in [0, 1] at p (in lattice units): random values at the integer lattice,
// blended with the quintic fade 6t⁵ − 15t⁴ + 10t³ so the field and its slope are continuous.
inline float value_noise(uint64_t seed, const Vec3f& p) {
    const float fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
    const auto cell = [](float f) { return static_cast<int64_t>(f); };
    const int64_t x0 = cell(fx), y0 = cell(fy), z0 = cell(fz);
    const auto fade = [](float t) { return t * t * t * (t * (6.f * t - 15.f) + 10.f); };
    const float u = fade(p.x() - fx), v = fade(p.y() - fy), w = fade(p.z() - fz);
    const auto at = [&](int64_t x, int64_t y, int64_t z) {
        const uint64_t h =
            mix64(seed ^ mix64(static_cast<uint64_t>(x) ^
                               mix64(static_cast<uint64_t>(y) ^ mix64(static_cast<uint64_t>(z)))));
        return static_cast<float>(h >> 40) * 0x1.0p-24f;
    };
    const auto lerp = [](float a, float b, float t) { return a + t * (b - a); };
    const float c00 = lerp(at(x0, y0, z0), at(x0 + 1, y0, z0), u);
    const float c10 = lerp(at(x0, y0 + 1, z0), at(x0 + 1, y0 + 1, z0), u);
    const float c01 = lerp(at(x0, y0, z0 + 1), at(x0 + 1, y0, z0 + 1), u);
    const float c11 = lerp(at(x0, y0 + 1, z0 + 1), at(x0 + 1, y0 + 1, z0 + 1), u);
    return lerp(lerp(c00, c10, v), lerp(c01, c11, v), w);
}

}  // namespace wisp
