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
    int substeps = 1;         // s: the prototype's details are sampled s times per output
                              // step, so the chain can move by a fraction of a step
    float temperature = 0.f;  // T of eq. (4); 0 selects the argmin of eq. (3)
    float scale = 1.f;        // ε is divided by this (see synthesis_scale) so that T is
                              // dimensionless, as in Fig. 7
    int start = -1;           // the chain's first sample in the prototype (clamped to where a
                              // window fits); −1: a random one
};

// The scale that makes T dimensionless for a prototype's details: 1.5·√h times their RMS
// norm (1 for a prototype without details). With it, two windows of a sine wave in
// antiphase are ε ≈ 1.3 apart and windows a phase φ (radians, small) apart ε ≈ 0.67·φ, so
// Fig. 7's temperatures behave as in the paper: T = 0.01 copies the prototype, T = 0.12
// lets each step slip by about a tenth of a radian and the waves wander (synthesis_test).
float synthesis_scale(std::span<const Vec3f> prototype, int window);

// How many substeps resolve a prototype of the given period (cm) at a master's segment
// length (cm): enough that the prototype is sampled about 24 times a period, at most 4
// (a master with fewer than 6 points a period cannot show a smooth wave anyway).
int synthesis_substeps(float segment, float period);

// Eq. (2): the Euclidean distance between the h details before out[i] and the h details
// `stride` apart before proto[k] (stride = the substeps, 1 for the paper's own sampling).
float window_distance(std::span<const Vec3f> out, size_t i, std::span<const Vec3f> proto, size_t k,
                      int window, int stride = 1);

// Reused between calls so that synthesis does not allocate per master.
struct SynthesisScratch {
    std::vector<float> x, y, z;      // the prototype's details, one plane per coordinate
    std::vector<float> energy;       // ε² of every candidate (unscaled)
    std::vector<float> energy_next;  // the same, one step on (the two alternate)
    std::vector<float> term;    // (h + 1) planes of #m: |c[i − 1] − δ*_{k − s}|² of step i
    std::vector<int32_t> near;  // the candidates within reach of the best
    std::vector<float> weight;  // their Gibbs weights
    std::vector<Vec3f> chain;   // the chosen prototype details, before feathering
};

// Synthesizes out.size() details from the prototype details `proto`, sampled at 1/s of the
// output spacing (#m > h·s). The first h are copied, s apart, from the prototype at
// params.start or a random place (the chain's start); every further step draws a δ*_k with
// probability P_k ∝ exp(−ε(ω_i, ω*_k) / T) (eq. (4)) over all k with a full window, or the first
// minimizer of ε when T = 0 (eq. (3)). Candidates lie s apart in the prototype's own
// sampling, so continuing the prototype means k + s and a slip of one sample is a fraction
// of a step: rising T makes the waves wander smoothly rather than jump a whole sample.
// Where the chain does jump, the seam is feathered as in texture synthesis: the mismatch
// between the last detail and the one before δ*_k is carried into the output and halves at
// each step, so the strand stays continuous. The window compares the chain's own choices.
// A continued prototype (T = 0) is copied exactly. `chosen` (#out or empty) receives each k.
void synthesize_details(std::span<const Vec3f> proto, const SynthesisParams& params, Rng& rng,
                        std::span<Vec3f> out, std::span<int32_t> chosen, SynthesisScratch& scratch);

}  // namespace wisp
