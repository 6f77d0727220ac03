#include "groom/synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

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

// energy[k] += sign·|c − δ*_{k − offset}|² for k in [from, to).
void accumulate(SynthesisScratch& scratch, const Vec3f& c, size_t from, size_t to, size_t offset,
                float sign) {
    const float* px = scratch.x.data() + from - offset;
    const float* py = scratch.y.data() + from - offset;
    const float* pz = scratch.z.data() + from - offset;
    float* e = scratch.energy.data() + from;
    const float cx = c.x(), cy = c.y(), cz = c.z();
    for (size_t k = 0; k < to - from; ++k) {
        const float dx = cx - px[k], dy = cy - py[k], dz = cz - pz[k];
        e[k] += sign * (dx * dx + dy * dy + dz * dz);
    }
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
    scratch.near.resize(m);
    scratch.weight.resize(m);
    scratch.chain.resize(n);
    float* const energy = scratch.energy.data();
    Vec3f* const chain = scratch.chain.data();

    const size_t start = rng.below(static_cast<uint32_t>(m - span));
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
        if (full_to < m) {
            std::memmove(energy + full_to, energy + full_to - s, (m - full_to) * sizeof(float));
            accumulate(scratch, chain[i - 1], full_to, m, s, 1.f);
            accumulate(scratch, chain[i - 1 - h], full_to, m, span + s, -1.f);
        }
        std::fill(energy + span, energy + full_to, 0.f);
        for (size_t t = 1; t <= h; ++t)
            accumulate(scratch, chain[i - t], span, full_to, t * s, 1.f);
        size_t pick = span;
        if (params.temperature > 0.f) {
            // Eq. (4) over the candidates within reach of the best, shifted by the minimum
            // for numerical range (Z cancels the shift).
            const float best =
                std::sqrt(std::max(min_of(energy + span, m - span), 0.f)) * inv_scale;
            const float reach = (best + kCutoff * params.temperature) * params.scale;
            const float reach2 = reach * reach;
            size_t count = 0;
            for (size_t k = span; k < m; ++k) {
                scratch.near[count] = static_cast<int32_t>(k);
                count += energy[k] < reach2;
            }
            const float inv_t = 1.f / params.temperature;
            double z = 0.0;
            for (size_t c = 0; c < count; ++c) {
                const float e = std::sqrt(std::max(energy[scratch.near[c]], 0.f)) * inv_scale;
                scratch.weight[c] = std::exp(-(e - best) * inv_t);
                z += scratch.weight[c];
            }
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
