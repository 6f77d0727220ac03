#include "groom/distribution.hpp"

#include <algorithm>
#include <cmath>

namespace wisp {

float sample(const Distribution& d, Rng& rng) {
    switch (d.kind) {
        case Distribution::Kind::kConstant:
            return d.value;
        case Distribution::Kind::kUniform:
            return rng.uniform(d.min, d.max);
        case Distribution::Kind::kNormal:
            for (int i = 0; i < 64; ++i) {
                const float x = rng.normal(d.mean, d.stddev);
                if (x >= d.min && x <= d.max) return x;
            }
            return std::clamp(d.mean, d.min, d.max);
        case Distribution::Kind::kTable: {
            float total = 0.f;
            for (float w : d.table)
                total += w;
            if (d.table.empty() || !(total > 0.f)) return d.min;
            float x = rng.uniform() * total;
            size_t bin = 0;
            for (; bin + 1 < d.table.size(); ++bin) {
                if (x < d.table[bin]) break;
                x -= d.table[bin];
            }
            const float width = (d.max - d.min) / static_cast<float>(d.table.size());
            return d.min + width * (static_cast<float>(bin) + rng.uniform());
        }
    }
    return d.value;
}

float mean_of(const Distribution& d) {
    switch (d.kind) {
        case Distribution::Kind::kConstant:
            return d.value;
        case Distribution::Kind::kUniform:
            return 0.5f * (d.min + d.max);
        case Distribution::Kind::kNormal: {
            // Numerical mean of the normal truncated to [min, max].
            double num = 0, den = 0;
            for (int i = 0; i <= 2000; ++i) {
                const double x = d.min + (d.max - d.min) * i / 2000.0;
                const double z = d.stddev > 0 ? (x - d.mean) / d.stddev : (x == d.mean ? 0 : 1e9);
                const double w = std::exp(-0.5 * z * z);
                num += w * x;
                den += w;
            }
            return den > 0 ? static_cast<float>(num / den) : std::clamp(d.mean, d.min, d.max);
        }
        case Distribution::Kind::kTable: {
            double num = 0, den = 0;
            const double width = (d.max - d.min) / std::max<size_t>(d.table.size(), 1);
            for (size_t i = 0; i < d.table.size(); ++i) {
                num += d.table[i] * (d.min + width * (i + 0.5));
                den += d.table[i];
            }
            return den > 0 ? static_cast<float>(num / den) : d.min;
        }
    }
    return d.value;
}

}  // namespace wisp
