#include "groom/synthesis.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// Before a loop whose stores overlap none of its loads: slide()'s reads and writes span more
// arrays than the compiler's runtime alias checks cover, and without this it stays scalar
// (1.7x its vector instructions).
#if defined(__clang__)
#define WISP_NO_ALIAS _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define WISP_NO_ALIAS _Pragma("GCC ivdep")
#else
#define WISP_NO_ALIAS
#endif

namespace wisp {
namespace {

// How much of a seam's mismatch is still carried one step later (see synthesize_details).
constexpr float kFeather = 0.5f;
// Gibbs weights below exp(−kCutoff) = 6·10⁻⁶ of the best are taken as 0: even a thousand
// of them would change a draw's odds by under 1%, and skipping them saves the
// exponentials of the far candidates, most of them at the usual temperatures.
constexpr float kCutoff = 12.f;

// The least of values[0, count), in lanes the compiler can vectorize.
float min_of(const float* values, size_t count) {
    constexpr size_t kLanes = 8;
    float lane[kLanes];
    std::fill(lane, lane + kLanes, std::numeric_limits<float>::infinity());
    size_t k = 0;
#if defined(__SSE2__)
    // GCC leaves the portable loop below scalar (8 minss a block); minps(v, lane) is
    // v < lane ? v : lane lane by lane, the same choice, NaN and −0 included.
    __m128 lo = _mm_loadu_ps(lane), hi = _mm_loadu_ps(lane + 4);
    for (; k + kLanes <= count; k += kLanes) {
        lo = _mm_min_ps(_mm_loadu_ps(values + k), lo);
        hi = _mm_min_ps(_mm_loadu_ps(values + k + 4), hi);
    }
    _mm_storeu_ps(lane, lo);
    _mm_storeu_ps(lane + 4, hi);
#endif
    for (; k + kLanes <= count; k += kLanes)
        for (size_t l = 0; l < kLanes; ++l)
            lane[l] = values[k + l] < lane[l] ? values[k + l] : lane[l];
    float least = std::numeric_limits<float>::infinity();
    for (; k < count; ++k)
        least = std::min(least, values[k]);
    for (float v : lane)
        least = std::min(least, v);
    return least;
}

// f(k, |c − δ*_{k − offset}|²) for k in [from, to), in order.
template <typename F>
inline void each_squared_distance(const SynthesisScratch& scratch, const Vec3f& c, size_t from,
                                  size_t to, size_t offset, F&& f) {
    const float* px = scratch.x.data() + from - offset;
    const float* py = scratch.y.data() + from - offset;
    const float* pz = scratch.z.data() + from - offset;
    const float cx = c.x(), cy = c.y(), cz = c.z();
    for (size_t k = 0; k < to - from; ++k) {
        const float dx = cx - px[k], dy = cy - py[k], dz = cz - pz[k];
        f(from + k, dx * dx + dy * dy + dz * dz);
    }
}

// energy[k] += sign·|c − δ*_{k − offset}|² for k in [from, to).
void accumulate(const SynthesisScratch& scratch, float* energy, const Vec3f& c, size_t from,
                size_t to, size_t offset, float sign) {
    each_squared_distance(scratch, c, from, to, offset,
                          [&](size_t k, float d2) { energy[k] += sign * d2; });
}

// term[k] = |c − δ*_{k − s}|² for k in [from, to): what c[i − 1] adds to candidate k's
// window at step i, recorded because the same window drops it h steps later (slide()).
void record(const SynthesisScratch& scratch, const Vec3f& c, size_t from, size_t to, size_t s,
            float* term) {
    each_squared_distance(scratch, c, from, to, s, [&](size_t k, float d2) { term[k] = d2; });
}

// next[k] = prev[k − s] + |c − δ*_{k − s}|² − |old − δ*_{k − s − h·s}|² for k in [from, to):
// the window of (i, k) is that of (i − 1, k − s) with c[i − 1] added and its oldest element
// dropped. One pass into the other buffer, in the float order of a shift (memmove) and the
// two accumulate() passes it replaces (x + 1·a, then + (−1)·b, are x + a − b exactly). The
// added terms go to term[k] (record()); the dropped one is the term the step h before added
// to candidate k − h·s, read from `dropped` when that step recorded it (kRecorded; the same
// expression of the same floats, so the same bits), computed otherwise.
template <bool kRecorded>
void slide(const SynthesisScratch& scratch, const float* prev, float* next, float* term,
           const float* dropped, const Vec3f& c, const Vec3f& old, size_t from, size_t to, size_t s,
           size_t span) {
    const float* px = scratch.x.data() + from - s;
    const float* py = scratch.y.data() + from - s;
    const float* pz = scratch.z.data() + from - s;
    const float* qx = scratch.x.data() + from - span - s;
    const float* qy = scratch.y.data() + from - span - s;
    const float* qz = scratch.z.data() + from - span - s;
    const float* drop = kRecorded ? dropped + from - span : nullptr;
    const float* e = prev + from - s;
    float* out = next + from;
    float* added = term + from;
    const float cx = c.x(), cy = c.y(), cz = c.z();
    const float ox = old.x(), oy = old.y(), oz = old.z();
    WISP_NO_ALIAS
    for (size_t k = 0; k < to - from; ++k) {
        const float dx = cx - px[k], dy = cy - py[k], dz = cz - pz[k];
        const float a = dx * dx + dy * dy + dz * dz;
        added[k] = a;
        float v = e[k];
        v += a;
        if constexpr (kRecorded) {
            v -= drop[k];
        } else {
            const float fx = ox - qx[k], fy = oy - qy[k], fz = oz - qz[k];
            v -= fx * fx + fy * fy + fz * fz;
        }
        out[k] = v;
    }
}

// Eq. (4)'s weights: for every k in [from, to) with energy[k] < reach2, in increasing order,
// near[c] = k and weight[c] = exp(−(ε_k/scale − best)/T); returns their count and adds them
// to z in that order. Four candidates a compare where SSE2 is there: most are out of reach,
// and a mask skips them without a store each; the exponent is the scalar expression's, lane
// by lane (sqrtps, mulps, subps round as their scalar forms; max(0, e) keeps e when it is
// not below 0, as std::max(e, 0) does).
size_t gibbs_weights(const float* energy, size_t from, size_t to, float reach2, float inv_scale,
                     float best, float inv_t, int32_t* near, float* weight, double& z) {
    size_t k = from, count = 0;
#if defined(__SSE2__)
    const __m128 r = _mm_set1_ps(reach2), zero = _mm_setzero_ps();
    const __m128 scale4 = _mm_set1_ps(inv_scale), best4 = _mm_set1_ps(best);
    const __m128 inv_t4 = _mm_set1_ps(inv_t), sign = _mm_set1_ps(-0.f);
    alignas(16) float exponent[4];
    for (; k + 4 <= to; k += 4) {
        const __m128 e2 = _mm_loadu_ps(energy + k);
        // cmplt is false for NaN, as `<` is.
        unsigned bits = static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(e2, r)));
        if (!bits) continue;
        const __m128 e = _mm_mul_ps(_mm_sqrt_ps(_mm_max_ps(zero, e2)), scale4);
        _mm_store_ps(exponent, _mm_mul_ps(_mm_xor_ps(_mm_sub_ps(e, best4), sign), inv_t4));
        while (bits) {
            const unsigned l = static_cast<unsigned>(std::countr_zero(bits));
            const float w = std::exp(exponent[l]);
            near[count] = static_cast<int32_t>(k + l);
            weight[count++] = w;
            z += w;
            bits &= bits - 1;
        }
    }
#endif
    for (; k < to; ++k) {
        if (!(energy[k] < reach2)) continue;
        const float e = std::sqrt(std::max(energy[k], 0.f)) * inv_scale;
        const float w = std::exp(-(e - best) * inv_t);
        near[count] = static_cast<int32_t>(k);
        weight[count++] = w;
        z += w;
    }
    return count;
}

}  // namespace

float synthesis_scale(std::span<const Vec3f> prototype, int window) {
    double sum = 0.0;
    for (const Vec3f& d : prototype)
        sum += d.squaredNorm();
    const double rms = prototype.empty() ? 0.0 : std::sqrt(sum / prototype.size());
    return rms > 1e-6 ? static_cast<float>(1.5 * std::sqrt(static_cast<double>(window)) * rms)
                      : 1.f;
}

int synthesis_substeps(float segment, float period) {
    if (!(segment > 0.f) || !(period > 0.f)) return 1;
    return static_cast<int>(std::clamp(std::ceil(24.f * segment / period), 1.f, 4.f));
}

float window_distance(std::span<const Vec3f> out, size_t i, std::span<const Vec3f> proto, size_t k,
                      int window, int stride) {
    float sum = 0.f;
    for (int t = 1; t <= window; ++t)
        sum += (out[i - t] - proto[k - static_cast<size_t>(t * stride)]).squaredNorm();
    return std::sqrt(sum);
}

void synthesize_details(std::span<const Vec3f> proto, const SynthesisParams& params, Rng& rng,
                        std::span<Vec3f> out, std::span<int32_t> chosen,
                        SynthesisScratch& scratch) {
    const size_t m = proto.size();
    const size_t h = static_cast<size_t>(params.window);
    const size_t s = static_cast<size_t>(std::max(params.substeps, 1));
    const size_t span = h * s;  // the first candidate with a full window
    const size_t n = out.size();
    if (m <= span) {
        // Too short a prototype for the window: repeat it (callers validate beforehand).
        for (size_t i = 0; i < n; ++i) {
            out[i] = m ? proto[(i * s) % m] : Vec3f::Zero();
            if (!chosen.empty()) chosen[i] = m ? static_cast<int32_t>((i * s) % m) : -1;
        }
        return;
    }
    // One plane per coordinate, so that the candidate loop below runs in SIMD lanes.
    scratch.x.resize(m);
    scratch.y.resize(m);
    scratch.z.resize(m);
    for (size_t k = 0; k < m; ++k) {
        scratch.x[k] = proto[k].x();
        scratch.y[k] = proto[k].y();
        scratch.z[k] = proto[k].z();
    }
    scratch.energy.resize(m);
    scratch.energy_next.resize(m);
    // h + 1 planes: step i writes its terms while reading those of step i − h.
    scratch.term.resize((h + 1) * m);
    scratch.near.resize(m);
    scratch.weight.resize(m);
    scratch.chain.resize(n);
    // ε² of the current step and of the one before, swapped each step (see slide()).
    float* energy = scratch.energy.data();
    float* previous = scratch.energy_next.data();
    Vec3f* const chain = scratch.chain.data();

    const size_t start = params.start >= 0
                             ? std::min(static_cast<size_t>(params.start), m - span - 1)
                             : rng.below(static_cast<uint32_t>(m - span));
    for (size_t i = 0; i < std::min(h, n); ++i) {
        out[i] = chain[i] = proto[start + i * s];
        if (!chosen.empty()) chosen[i] = static_cast<int32_t>(start + i * s);
    }
    const float inv_scale = 1.f / params.scale;
    Vec3f seam = Vec3f::Zero();
    for (size_t i = h; i < n; ++i) {
        // ε² (unscaled) of every candidate. The window of (i, k) is that of (i − 1, k − s)
        // with its oldest element dropped and c[i − 1] added, so after the first step only
        // the s candidates without a predecessor are summed in full.
        const size_t full_to = i == h ? m : std::min(m, span + s);
        std::swap(energy, previous);
        float* const term = scratch.term.data() + (i % (h + 1)) * m;
        if (full_to < m) {
            // Steps from 2h on drop what a step since h added.
            if (i >= 2 * h)
                slide<true>(scratch, previous, energy, term,
                            scratch.term.data() + ((i - h) % (h + 1)) * m, chain[i - 1],
                            chain[i - 1 - h], full_to, m, s, span);
            else
                slide<false>(scratch, previous, energy, term, nullptr, chain[i - 1],
                             chain[i - 1 - h], full_to, m, s, span);
        }
        // The terms of candidates [s, full_to) too, which step i + h drops from k ≥ full_to.
        record(scratch, chain[i - 1], s, full_to, s, term);
        std::fill(energy + span, energy + full_to, 0.f);
        for (size_t t = 1; t <= h; ++t)
            accumulate(scratch, energy, chain[i - t], span, full_to, t * s, 1.f);
        size_t pick = span;
        if (params.temperature > 0.f) {
            // Eq. (4) over the candidates within reach of the best, shifted by the minimum
            // for numerical range (Z cancels the shift).
            const float best =
                std::sqrt(std::max(min_of(energy + span, m - span), 0.f)) * inv_scale;
            const float reach = (best + kCutoff * params.temperature) * params.scale;
            const float reach2 = reach * reach;
            double z = 0.0;
            const size_t count =
                gibbs_weights(energy, span, m, reach2, inv_scale, best, 1.f / params.temperature,
                              scratch.near.data(), scratch.weight.data(), z);
            double x = rng.uniform_double() * z;
            if (count) pick = static_cast<size_t>(scratch.near[count - 1]);
            for (size_t c = 0; c < count; ++c) {
                x -= scratch.weight[c];
                if (x < 0.0) {
                    pick = static_cast<size_t>(scratch.near[c]);
                    break;
                }
            }
        } else {
            // Eq. (3): the first minimizer.
            const float least = min_of(energy + span, m - span);
            while (pick + 1 < m && energy[pick] != least)
                ++pick;
        }
        chain[i] = proto[pick];
        seam = kFeather * (seam + chain[i - 1] - proto[pick - s]);
        out[i] = chain[i] + seam;
        if (!chosen.empty()) chosen[i] = static_cast<int32_t>(pick);
    }
}

}  // namespace wisp
