#pragma once
// Master strand synthesis from a prototype by a Markov chain with Gibbs selection
// (Choe & Ko §2.2.2, eqs. (2)–(4), Fig. 6 and 7).
#include <span>
#include <vector>

#include "core/math.hpp"
#include "core/rng.hpp"

namespace wisp {

struct SynthesisParams {
    int window = 4;           // h, the causal window size, ≥ 1
    float temperature = 0.f;  // T of eq. (4); 0 selects the argmin of eq. (3)
    float scale = 1.f;        // ε is divided by this (see synthesis_scale) so that T is
                              // dimensionless, as in Fig. 7
};

// The scale that makes T dimensionless for a prototype's details: 4·√h times their RMS
// norm (1 for a prototype without details). With it, two windows of a sine wave in
// antiphase are ε = 0.5 apart, and Fig. 7's temperatures behave as in the paper: T = 0.01
// copies the prototype, T = 0.12 strays from it by about 40% of its amplitude.
float synthesis_scale(std::span<const Vec3f> prototype, int window);

// Eq. (2): the Euclidean distance between the h details before out[i] and before proto[k].
float window_distance(std::span<const Vec3f> out, size_t i, std::span<const Vec3f> proto, size_t k,
                      int window);

// Synthesizes out.size() details from the prototype details `proto` (#m > h). The first h
// are copied from a random place of the prototype (the chain's start); every further δ_i
// is a δ*_k drawn with probability P_k ∝ exp(−ε(ω_i, ω*_k) / T) (eq. (4)) over all k with a
// full window, or the first minimizer of ε when T = 0 (eq. (3)). `chosen` (#out or empty)
// receives each k. `weights` is scratch of #m, reused between calls to avoid allocation.
void synthesize_details(std::span<const Vec3f> proto, const SynthesisParams& params, Rng& rng,
                        std::span<Vec3f> out, std::span<int32_t> chosen,
                        std::vector<double>& weights);

}  // namespace wisp
