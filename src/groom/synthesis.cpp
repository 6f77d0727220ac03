#include "groom/synthesis.hpp"

#include <cmath>
#include <limits>

namespace wisp {

float synthesis_scale(std::span<const Vec3f> prototype, int window) {
    double sum = 0.0;
    for (const Vec3f& d : prototype)
        sum += d.squaredNorm();
    const double rms = prototype.empty() ? 0.0 : std::sqrt(sum / prototype.size());
    return rms > 1e-6 ? static_cast<float>(4.0 * std::sqrt(static_cast<double>(window)) * rms)
                      : 1.f;
}

float window_distance(std::span<const Vec3f> out, size_t i, std::span<const Vec3f> proto, size_t k,
                      int window) {
    float sum = 0.f;
    for (int t = 1; t <= window; ++t)
        sum += (out[i - t] - proto[k - t]).squaredNorm();
    return std::sqrt(sum);
}

void synthesize_details(std::span<const Vec3f> proto, const SynthesisParams& params, Rng& rng,
                        std::span<Vec3f> out, std::span<int32_t> chosen,
                        std::vector<double>& weights) {
    const size_t m = proto.size();
    const size_t h = static_cast<size_t>(params.window);
    const size_t n = out.size();
    if (m <= h) {
        // Too short a prototype for the window: repeat it (callers validate beforehand).
        for (size_t i = 0; i < n; ++i) {
            out[i] = m ? proto[i % m] : Vec3f::Zero();
            if (!chosen.empty()) chosen[i] = m ? static_cast<int32_t>(i % m) : -1;
        }
        return;
    }
    const size_t start = rng.below(static_cast<uint32_t>(m - h));
    for (size_t i = 0; i < std::min(h, n); ++i) {
        out[i] = proto[start + i];
        if (!chosen.empty()) chosen[i] = static_cast<int32_t>(start + i);
    }
    weights.resize(m);
    const float inv_scale = 1.f / params.scale;
    for (size_t i = h; i < n; ++i) {
        float best = std::numeric_limits<float>::infinity();
        size_t best_k = h;
        for (size_t k = h; k < m; ++k) {
            const float e = window_distance(out, i, proto, k, params.window) * inv_scale;
            weights[k] = e;
            if (e < best) {
                best = e;
                best_k = k;
            }
        }
        size_t pick = best_k;
        if (params.temperature > 0.f) {
            // Eq. (4), shifted by the minimum for numerical range (Z cancels the shift).
            const double inv_t = 1.0 / params.temperature;
            double z = 0.0;
            for (size_t k = h; k < m; ++k) {
                weights[k] = std::exp(-(weights[k] - best) * inv_t);
                z += weights[k];
            }
            double x = rng.uniform_double() * z;
            for (size_t k = h; k < m; ++k) {
                x -= weights[k];
                if (x < 0.0) {
                    pick = k;
                    break;
                }
            }
        }
        out[i] = proto[pick];
        if (!chosen.empty()) chosen[i] = static_cast<int32_t>(pick);
    }
}

}  // namespace wisp
