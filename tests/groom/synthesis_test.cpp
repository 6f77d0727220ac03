#include "groom/synthesis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "groom/prototype.hpp"

namespace wisp {
namespace {

std::vector<Vec3f> wavy_details(float segment) {
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kWavy;
    spec.amplitude = 0.8f;
    spec.period = 3.f;
    spec.length = 40.f;
    const PrototypeCurve curve = make_prototype_curve(spec);
    return decompose(curve, segment);
}

// Mean distance between each synthesized detail and the detail that would simply continue
// the prototype from the previous choice (0 for a perfect copy), in cm.
double jump_rate(const std::vector<Vec3f>& proto, float temperature, int strands) {
    SynthesisParams p;
    p.window = 4;
    p.temperature = temperature;
    p.scale = synthesis_scale(proto, p.window);
    std::vector<Vec3f> out(32);
    std::vector<int32_t> chosen(32);
    std::vector<double> scratch;
    double jumps = 0;
    int steps = 0;
    for (int s = 0; s < strands; ++s) {
        Rng rng(5, Stream::kMaster, s);
        synthesize_details(proto, p, rng, out, chosen, scratch);
        for (size_t i = p.window; i < out.size(); ++i) {
            // A jump back by a whole number of periods continues the pattern just as well,
            // so compare the details themselves.
            const size_t next = chosen[i - 1] + 1;
            if (next >= proto.size()) continue;
            jumps += (out[i] - proto[next]).norm();
            ++steps;
        }
    }
    return jumps / steps;
}

}  // namespace

TEST(Synthesis, WindowDistanceIsEquationTwo) {
    const std::vector<Vec3f> a = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {9, 9, 9}};
    const std::vector<Vec3f> b = {{0, 0, 1}, {1, 0, 0}, {0, 0, 0}, {5, 5, 5}};
    // ε over the h = 3 details before index 3: sqrt(1 + 0 + 4).
    EXPECT_NEAR(window_distance(a, 3, b, 3, 3), std::sqrt(5.f), 1e-6f);
}

TEST(Synthesis, ZeroTemperatureReproducesThePrototype) {
    const std::vector<Vec3f> proto = wavy_details(0.5f);
    ASSERT_GT(proto.size(), 40u);
    SynthesisParams p;
    p.window = 4;
    p.temperature = 0.f;
    p.scale = synthesis_scale(proto, p.window);
    std::vector<Vec3f> out(32);
    std::vector<int32_t> chosen(32);
    std::vector<double> scratch;
    for (int s = 0; s < 50; ++s) {
        Rng rng(1, Stream::kMaster, s);
        synthesize_details(proto, p, rng, out, chosen, scratch);
        // Every step continues the prototype exactly (the argmin window has ε = 0) until
        // the prototype's end, where the chain must jump back.
        for (size_t i = 1; i < out.size(); ++i) {
            const size_t next = chosen[i - 1] + 1;
            if (next >= proto.size()) continue;
            EXPECT_LT((out[i] - proto[next]).norm(), 1e-5f) << "strand " << s << " step " << i;
        }
    }
}

TEST(Synthesis, SmallTemperatureStaysCloseToThePrototype) {
    const std::vector<Vec3f> proto = wavy_details(0.5f);
    EXPECT_LT(jump_rate(proto, 0.001f, 100), 0.01 * 0.8);  // 1% of the amplitude
}

TEST(Synthesis, DiversityGrowsWithTemperature) {
    // Figure 7: T = 0.01, 0.03, 0.07, 0.12 give increasingly diverse strands.
    const std::vector<Vec3f> proto = wavy_details(0.5f);
    double last = -1.0;
    for (float t : {0.01f, 0.03f, 0.07f, 0.12f}) {
        const double rate = jump_rate(proto, t, 200);
        EXPECT_GT(rate, last) << "T = " << t;
        last = rate;
    }
    EXPECT_GT(last, 0.1 * 0.8);  // at T = 0.12 details stray by over 10% of the amplitude
}

TEST(Synthesis, DeterministicForASeed) {
    const std::vector<Vec3f> proto = wavy_details(0.7f);
    SynthesisParams p;
    p.temperature = 0.05f;
    p.scale = synthesis_scale(proto, p.window);
    std::vector<Vec3f> a(32), b(32);
    std::vector<double> scratch;
    Rng r1(9, Stream::kMaster, 3), r2(9, Stream::kMaster, 3);
    synthesize_details(proto, p, r1, a, {}, scratch);
    synthesize_details(proto, p, r2, b, {}, scratch);
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_EQ(a[i], b[i]);
}

}  // namespace wisp
