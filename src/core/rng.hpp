#pragma once
// Deterministic random streams. Every random choice in wisp takes an explicit Rng whose
// state derives from the style seed and the id of what it decides (a wisp, a strand), so
// results never depend on the thread count or the order of work. No std:: distributions:
// their output differs between standard libraries.
#include <cmath>
#include <cstdint>

#include "core/math.hpp"

namespace wisp {

// SplitMix64 finalizer: a bijective 64-bit mix.
inline constexpr uint64_t mix64(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Named stream domains, so that the stream of wisp 7's master never equals that of
// strand 7's color.
enum class Stream : uint64_t {
    kRoots = 1,
    kMaster = 2,
    kMember = 3,
    kColor = 4,
    kWispColor = 5,
    kLength = 6,
    kMisc = 7,
    kMemberRoot = 8,
    kRoll = 9,
    kCut = 10,
    kClump = 11,
    kWave = 12,
    kHairline = 13,
    kFlyaway = 14,
    kWaveField = 15,  // the value-noise field that sets waves in step over the scalp
};

// A 64-bit seed for the stream (seed, domain, id): for fields drawn by hashing rather than
// by an Rng's sequence (core/noise.hpp).
inline constexpr uint64_t stream_seed(uint64_t seed, Stream domain, uint64_t id = 0) {
    return mix64(seed ^ mix64(static_cast<uint64_t>(domain) * 0x632BE59BD9B4E019ull ^
                              mix64(id + 0x1234567ull)));
}

// xoshiro256** seeded through SplitMix64 from (seed, domain, id).
class Rng {
  public:
    explicit Rng(uint64_t seed, Stream domain = Stream::kMisc, uint64_t id = 0) {
        uint64_t x = stream_seed(seed, domain, id);
        for (auto& s : s_) {
            x = mix64(x);
            s = x;
        }
    }

    uint64_t next() {
        const uint64_t result = rotl(s_[1] * 5, 7) * 9;
        const uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }

    // Uniform in [0, 1) with 53 bits.
    double uniform_double() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    // Uniform in [0, 1) with 24 bits.
    float uniform() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift, bias < 2^-32 for small n).
    uint32_t below(uint32_t n) {
        return static_cast<uint32_t>(((next() >> 32) * static_cast<uint64_t>(n)) >> 32);
    }
    // Standard normal by Box-Muller (one value per call; deterministic on every platform).
    float normal() {
        double u1 = uniform_double();
        const double u2 = uniform_double();
        if (u1 < 1e-300) u1 = 1e-300;
        return static_cast<float>(std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
    }
    float normal(float mean, float stddev) { return mean + stddev * normal(); }
    // A direction uniform on the unit sphere.
    Vec3f unit_vector() {
        const float z = uniform(-1.f, 1.f);
        const float phi = uniform(0.f, 2.f * kPi);
        const float r = std::sqrt(std::max(0.f, 1.f - z * z));
        return {r * std::cos(phi), r * std::sin(phi), z};
    }

  private:
    static constexpr uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t s_[4];
};

}  // namespace wisp
