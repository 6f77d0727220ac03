#include "groom/synthesis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "groom/prototype.hpp"

namespace wisp {
namespace {

constexpr float kAmplitude = 0.8f;
constexpr float kSegment = 0.5f;  // cm between output details: 6 a period
constexpr int kSubsteps = 4;

// The prototype's details at 1/kSubsteps of the output spacing.
std::vector<Vec3f> wavy_details() {
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kWavy;
    spec.amplitude = kAmplitude;
    spec.period = 3.f;
    spec.length = 40.f;
    const PrototypeCurve curve = make_prototype_curve(spec);
    return decompose(curve, kSegment / kSubsteps);
}

SynthesisParams params(const std::vector<Vec3f>& proto, float temperature) {
    SynthesisParams p;
    p.window = 4;
    p.substeps = kSubsteps;
    p.temperature = temperature;
    p.scale = synthesis_scale(proto, p.window);
    return p;
}

struct Spread {
    double departure = 0;  // RMS distance from the prototype continued from the chain's start
    double roughness = 0;  // RMS second difference of the details
};

// Fig. 7's measures over `strands` synthesized strands of 48 details, in cm.
Spread spread(const std::vector<Vec3f>& proto, float temperature, int strands) {
    const SynthesisParams p = params(proto, temperature);
    std::vector<Vec3f> out(48);
    std::vector<int32_t> chosen(48);
    SynthesisScratch scratch;
    double departure = 0, roughness = 0;
    size_t d_count = 0, r_count = 0;
    for (int s = 0; s < strands; ++s) {
        Rng rng(5, Stream::kMaster, s);
        synthesize_details(proto, p, rng, out, chosen, scratch);
        for (size_t i = 0; i < out.size(); ++i) {
            const size_t copy = chosen[0] + i * kSubsteps;
            if (copy >= proto.size()) break;
            departure += (out[i] - proto[copy]).squaredNorm();
            ++d_count;
        }
        for (size_t i = 1; i + 1 < out.size(); ++i) {
            roughness += (out[i - 1] - 2.f * out[i] + out[i + 1]).squaredNorm();
            ++r_count;
        }
    }
    return {std::sqrt(departure / d_count), std::sqrt(roughness / r_count)};
}

// The prototype's own RMS second difference at the output spacing.
double prototype_roughness(const std::vector<Vec3f>& proto) {
    double sum = 0;
    size_t count = 0;
    for (size_t k = kSubsteps; k + kSubsteps < proto.size(); ++k) {
        sum += (proto[k - kSubsteps] - 2.f * proto[k] + proto[k + kSubsteps]).squaredNorm();
        ++count;
    }
    return std::sqrt(sum / count);
}

}  // namespace

TEST(Synthesis, WindowDistanceIsEquationTwo) {
    const std::vector<Vec3f> a = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {9, 9, 9}};
    const std::vector<Vec3f> b = {{0, 0, 1}, {1, 0, 0}, {0, 0, 0}, {5, 5, 5}};
    // ε over the h = 3 details before index 3: sqrt(1 + 0 + 4).
    EXPECT_NEAR(window_distance(a, 3, b, 3, 3), std::sqrt(5.f), 1e-6f);
}

TEST(Synthesis, WindowDistanceStridesThroughThePrototype) {
    const std::vector<Vec3f> out = {{1, 0, 0}, {2, 0, 0}, {0, 0, 0}};
    std::vector<Vec3f> proto(8, Vec3f::Zero());
    proto[3] = {1, 0, 0};  // k − 2·stride for k = 7, stride 2
    proto[5] = {2, 0, 3};  // k − stride
    EXPECT_NEAR(window_distance(out, 2, proto, 7, 2, 2), 3.f, 1e-6f);
}

TEST(Synthesis, SubstepsSampleAboutTwentyFourTimesAPeriod) {
    EXPECT_EQ(synthesis_substeps(1.f, 8.f), 3);  // 8 steps a period, 24 samples
    EXPECT_EQ(synthesis_substeps(0.1f, 8.f), 1);
    EXPECT_EQ(synthesis_substeps(5.f, 1.f), 4);  // capped
    EXPECT_EQ(synthesis_substeps(1.f, 0.f), 1);
}

TEST(Synthesis, ZeroTemperatureReproducesThePrototype) {
    const std::vector<Vec3f> proto = wavy_details();
    ASSERT_GT(proto.size(), 200u);
    const SynthesisParams p = params(proto, 0.f);
    std::vector<Vec3f> out(32);
    std::vector<int32_t> chosen(32);
    SynthesisScratch scratch;
    for (int s = 0; s < 50; ++s) {
        Rng rng(1, Stream::kMaster, s);
        synthesize_details(proto, p, rng, out, chosen, scratch);
        // Every step continues the prototype exactly (the argmin window has ε = 0) until
        // the prototype's end, where the chain must jump back (and feathers the seam).
        for (size_t i = 1; i < out.size(); ++i) {
            const size_t next = chosen[i - 1] + kSubsteps;
            if (next >= proto.size()) break;
            EXPECT_EQ(chosen[i], static_cast<int32_t>(next)) << "strand " << s << " step " << i;
            EXPECT_LT((out[i] - proto[next]).norm(), 1e-5f) << "strand " << s << " step " << i;
        }
    }
}

TEST(Synthesis, EveryStepTakesAWindowThatMatchesBest) {
    // The chain updates its window distances step to step; they must stay eq. (2)'s. A
    // short, aperiodic prototype makes the chain jump back often, to imperfect matches.
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kPolyline;
    spec.period = 2.f;
    for (int j = 0; j <= 120; ++j) {
        const float y = 0.1f * j;
        spec.polyline.emplace_back(0.5f * std::sin(3.1f * y) + 0.3f * std::sin(7.7f * y), y,
                                   0.4f * std::cos(4.3f * y));
    }
    const std::vector<Vec3f> proto = decompose(make_prototype_curve(spec), kSegment / kSubsteps);
    const SynthesisParams p = params(proto, 0.f);
    std::vector<Vec3f> out(64), chain(64);
    std::vector<int32_t> chosen(64);
    SynthesisScratch scratch;
    const size_t span = p.window * kSubsteps;
    for (int s = 0; s < 20; ++s) {
        Rng rng(2, Stream::kMaster, s);
        synthesize_details(proto, p, rng, out, chosen, scratch);
        for (size_t i = 0; i < out.size(); ++i)
            chain[i] = proto[chosen[i]];
        for (size_t i = p.window; i < out.size(); ++i) {
            float least = INFINITY;
            for (size_t k = span; k < proto.size(); ++k)
                least = std::min(least, window_distance(chain, i, proto, k, p.window, kSubsteps));
            EXPECT_LE(window_distance(chain, i, proto, chosen[i], p.window, kSubsteps),
                      least + 1e-4f)
                << "strand " << s << " step " << i;
        }
    }
}

TEST(Synthesis, SmallTemperatureCopiesThePrototype) {
    // Fig. 7b: T = 0.01 gives strands that are the prototype.
    const std::vector<Vec3f> proto = wavy_details();
    EXPECT_LT(spread(proto, 0.01f, 100).departure, 0.02 * kAmplitude);
}

TEST(Synthesis, DiversityGrowsSmoothlyWithTemperature) {
    // Fig. 7: T = 0.01, 0.03, 0.07, 0.12 give increasingly diverse strands, whose waves
    // wander from the prototype's rather than break into zig-zags.
    const std::vector<Vec3f> proto = wavy_details();
    const double smooth = prototype_roughness(proto);
    double last = -1.0;
    for (float t : {0.01f, 0.03f, 0.07f, 0.12f}) {
        const Spread s = spread(proto, t, 200);
        EXPECT_GT(s.departure, 1.5 * last) << "T = " << t;
        EXPECT_LT(s.roughness, 1.25 * smooth) << "T = " << t;
        last = s.departure;
    }
    EXPECT_GT(last, 0.3 * kAmplitude);  // at T = 0.12 the waves are well out of phase
}

TEST(Synthesis, DeterministicForASeed) {
    const std::vector<Vec3f> proto = wavy_details();
    const SynthesisParams p = params(proto, 0.05f);
    std::vector<Vec3f> a(32), b(32);
    SynthesisScratch scratch;
    Rng r1(9, Stream::kMaster, 3), r2(9, Stream::kMaster, 3);
    synthesize_details(proto, p, r1, a, {}, scratch);
    synthesize_details(proto, p, r2, b, {}, scratch);
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_EQ(a[i], b[i]);
}

namespace {

// synthesize_details as it was before its energies slid between two buffers and its
// candidates in reach were gathered four at a time (f27f0b8): a shift (memmove) and two
// accumulating passes per step, and one compare per candidate. The new loops must reproduce
// it to the bit: the masters' details, and so every output, are unchanged.
void previous_synthesize_details(std::span<const Vec3f> proto, const SynthesisParams& params,
                                 Rng& rng, std::span<Vec3f> out, std::span<int32_t> chosen) {
    const size_t m = proto.size(), h = static_cast<size_t>(params.window);
    const size_t s = static_cast<size_t>(std::max(params.substeps, 1)), span = h * s;
    const size_t n = out.size();
    std::vector<float> x(m), y(m), z(m), energy(m), weight(m);
    std::vector<int32_t> near(m);
    std::vector<Vec3f> chain(n);
    for (size_t k = 0; k < m; ++k) {
        x[k] = proto[k].x();
        y[k] = proto[k].y();
        z[k] = proto[k].z();
    }
    const auto accumulate = [&](const Vec3f& c, size_t from, size_t to, size_t offset, float sign) {
        for (size_t k = from; k < to; ++k) {
            const float dx = c.x() - x[k - offset], dy = c.y() - y[k - offset],
                        dz = c.z() - z[k - offset];
            energy[k] += sign * (dx * dx + dy * dy + dz * dz);
        }
    };
    const auto least = [&] {
        float v = std::numeric_limits<float>::infinity();
        for (size_t k = span; k < m; ++k)
            v = std::min(v, energy[k]);
        return v;
    };
    const size_t start = rng.below(static_cast<uint32_t>(m - span));
    for (size_t i = 0; i < std::min(h, n); ++i) {
        out[i] = chain[i] = proto[start + i * s];
        chosen[i] = static_cast<int32_t>(start + i * s);
    }
    const float inv_scale = 1.f / params.scale;
    Vec3f seam = Vec3f::Zero();
    for (size_t i = h; i < n; ++i) {
        const size_t full_to = i == h ? m : std::min(m, span + s);
        if (full_to < m) {
            std::memmove(energy.data() + full_to, energy.data() + full_to - s,
                         (m - full_to) * sizeof(float));
            accumulate(chain[i - 1], full_to, m, s, 1.f);
            accumulate(chain[i - 1 - h], full_to, m, span + s, -1.f);
        }
        std::fill(energy.begin() + span, energy.begin() + full_to, 0.f);
        for (size_t t = 1; t <= h; ++t)
            accumulate(chain[i - t], span, full_to, t * s, 1.f);
        size_t pick = span;
        if (params.temperature > 0.f) {
            const float best = std::sqrt(std::max(least(), 0.f)) * inv_scale;
            const float reach = (best + 12.f * params.temperature) * params.scale;
            const float reach2 = reach * reach;
            size_t count = 0;
            for (size_t k = span; k < m; ++k) {
                near[count] = static_cast<int32_t>(k);
                count += energy[k] < reach2;
            }
            const float inv_t = 1.f / params.temperature;
            double zsum = 0.0;
            for (size_t c = 0; c < count; ++c) {
                const float e = std::sqrt(std::max(energy[near[c]], 0.f)) * inv_scale;
                weight[c] = std::exp(-(e - best) * inv_t);
                zsum += weight[c];
            }
            double u = rng.uniform_double() * zsum;
            if (count) pick = static_cast<size_t>(near[count - 1]);
            for (size_t c = 0; c < count; ++c) {
                u -= weight[c];
                if (u < 0.0) {
                    pick = static_cast<size_t>(near[c]);
                    break;
                }
            }
        } else {
            const float v = least();
            while (pick + 1 < m && energy[pick] != v)
                ++pick;
        }
        chain[i] = proto[pick];
        seam = 0.5f * (seam + chain[i - 1] - proto[pick - s]);
        out[i] = chain[i] + seam;
        chosen[i] = static_cast<int32_t>(pick);
    }
}

// Details with no structure at all (each coordinate uniform in ±1 cm), so that many
// candidates are in reach and ties and near-ties are common.
std::vector<Vec3f> noise_details(size_t count, uint64_t seed) {
    Rng rng(seed);
    std::vector<Vec3f> out(count);
    for (Vec3f& d : out)
        d = Vec3f(rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f));
    return out;
}

}  // namespace

TEST(Synthesis, SlidingEnergiesChooseAsTheShiftedSumsDidToTheBit) {
    const std::vector<Vec3f> wavy = wavy_details();
    SynthesisScratch scratch;  // shared across sizes, as the masters' threads share theirs
    int cases = 0;
    for (const size_t m : {wavy.size(), size_t{23}, size_t{64}, size_t{101}, size_t{257}}) {
        const std::vector<Vec3f> proto =
            m == wavy.size() ? wavy : noise_details(m, static_cast<uint64_t>(m));
        for (int h = 1; h <= 5; ++h)
            for (int sub = 1; sub <= 4; ++sub) {
                if (m <= static_cast<size_t>(h * sub)) continue;
                for (const float t : {0.f, 0.01f, 0.03f, 0.12f, 1.f}) {
                    SynthesisParams p;
                    p.window = h;
                    p.substeps = sub;
                    p.temperature = t;
                    p.scale = synthesis_scale(proto, h);
                    for (const size_t n : {size_t{3}, size_t{32}, size_t{77}}) {
                        std::vector<Vec3f> a(n), b(n);
                        std::vector<int32_t> ca(n), cb(n);
                        Rng ra(11, Stream::kMaster, cases), rb(11, Stream::kMaster, cases);
                        synthesize_details(proto, p, ra, a, ca, scratch);
                        previous_synthesize_details(proto, p, rb, b, cb);
                        ASSERT_EQ(ca, cb) << "m " << m << " h " << h << " s " << sub << " T " << t;
                        ASSERT_EQ(0, std::memcmp(a.data(), b.data(), n * sizeof(Vec3f)))
                            << "m " << m << " h " << h << " s " << sub << " T " << t;
                        ++cases;
                    }
                }
            }
    }
    EXPECT_GT(cases, 1000);
}

}  // namespace wisp
