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

}  // namespace wisp
