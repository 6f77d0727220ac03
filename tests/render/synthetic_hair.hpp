#pragma once
// Procedural test hair for the renderer's tests and benchmark, independent of the groom
// module: strands rooted on a spherical cap that leave the scalp along its normal, fall under
// a fake gravity, stay outside the sphere, and wave a little. Deterministic from the seed.
// Also a UV sphere mesh to stand in for the head.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/hair.hpp"
#include "core/rng.hpp"
#include "geometry/mesh.hpp"

namespace wisp::test {

struct SyntheticHairSpec {
    size_t strands = 1000;
    int points = 32;                 // control points per strand
    Vec3f center = Vec3f(0, 3, -1);  // cm, the scalp sphere
    float radius = 9.5f;
    float length = 25.f;   // cm, mean strand length (±20%)
    float width = 0.008f;  // cm at the root, tapering to 25% at the tip
    uint64_t seed = 1;
};

// A uniform random number in [0, 1) from a strand's own stream.
inline float unit_random(Rng& rng) {
    return static_cast<float>(rng.uniform_double());
}

inline Hair synthetic_hair(const SyntheticHairSpec& spec) {
    Hair hair;
    const int n = std::max(2, spec.points);
    hair.points.resize(spec.strands * n);
    hair.offsets.resize(spec.strands + 1);
    hair.widths.resize(spec.strands * n);
    hair.colors.resize(spec.strands);
    for (size_t s = 0; s <= spec.strands; ++s)
        hair.offsets[s] = static_cast<uint32_t>(s * n);
    for (size_t s = 0; s < spec.strands; ++s) {
        Rng rng(spec.seed, Stream::kMember, s);
        // Root: the cap above the ears, leaving the face (front, low) bare.
        Vec3f normal;
        do {
            const float z = 2.f * unit_random(rng) - 1.f, phi = 2.f * kPi * unit_random(rng);
            const float r = std::sqrt(std::max(0.f, 1.f - z * z));
            normal = Vec3f(r * std::cos(phi), z, r * std::sin(phi));
        } while (normal.y() < -0.1f || (normal.z() > 0.35f && normal.y() < 0.55f));
        const float len = spec.length * (0.8f + 0.4f * unit_random(rng));
        const float step = len / static_cast<float>(n - 1);
        const float wave_phase = 2.f * kPi * unit_random(rng);
        const float wave = 0.15f + 0.2f * unit_random(rng);
        const float shade = 0.8f + 0.4f * unit_random(rng);
        hair.colors[s] = Vec3f(0.20f, 0.10f, 0.045f) * shade;
        Vec3f p = spec.center + spec.radius * normal;
        Vec3f dir = normal;
        const Vec3f side = normal.cross(Vec3f::UnitY()).norm() > 1e-3f
                               ? Vec3f(normal.cross(Vec3f::UnitY()).normalized())
                               : Vec3f::UnitX();
        for (int i = 0; i < n; ++i) {
            const float u = static_cast<float>(i) / static_cast<float>(n - 1);
            hair.points[s * n + i] = p;
            hair.widths[s * n + i] = spec.width * (1.f - 0.75f * u * u);
            // Bend towards -Y, wave sideways, and keep off the sphere (a layer per strand).
            dir = (dir + Vec3f(0, -0.35f, 0) + side * (wave * std::sin(wave_phase + 7.f * u)))
                      .normalized();
            p += step * dir;
            const Vec3f d = p - spec.center;
            const float min_r = spec.radius + 0.3f + 0.6f * unit_random(rng) * u;
            if (d.norm() < min_r) p = spec.center + d.normalized() * min_r;
        }
    }
    return hair;
}

// A UV sphere: `rings` latitude bands × 2·rings longitudes, counter-clockwise from outside.
inline Mesh sphere_mesh(const Vec3f& center, float radius, int rings = 24) {
    Mesh m;
    const int cols = 2 * rings;
    m.vertices.push_back(center + Vec3f(0, radius, 0));
    for (int r = 1; r < rings; ++r) {
        const float theta = kPi * static_cast<float>(r) / static_cast<float>(rings);
        for (int c = 0; c < cols; ++c) {
            const float phi = 2.f * kPi * static_cast<float>(c) / static_cast<float>(cols);
            m.vertices.push_back(center + radius * Vec3f(std::sin(theta) * std::cos(phi),
                                                         std::cos(theta),
                                                         -std::sin(theta) * std::sin(phi)));
        }
    }
    m.vertices.push_back(center - Vec3f(0, radius, 0));
    const int south = static_cast<int>(m.vertices.size()) - 1;
    auto ring = [&](int r, int c) { return 1 + (r - 1) * cols + (c % cols); };
    for (int c = 0; c < cols; ++c)
        m.faces.emplace_back(0, ring(1, c), ring(1, c + 1));
    for (int r = 1; r + 1 < rings; ++r)
        for (int c = 0; c < cols; ++c) {
            m.faces.emplace_back(ring(r, c), ring(r + 1, c), ring(r + 1, c + 1));
            m.faces.emplace_back(ring(r, c), ring(r + 1, c + 1), ring(r, c + 1));
        }
    for (int c = 0; c < cols; ++c)
        m.faces.emplace_back(south, ring(rings - 1, c + 1), ring(rings - 1, c));
    return m;
}

}  // namespace wisp::test
