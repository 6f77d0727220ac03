#include "groom/prototype.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace wisp {

TEST(Prototype, StraightHasNoDetails) {
    PrototypeSpec spec;
    const PrototypeCurve c = prepare_prototype(prototype_polyline(spec), 0.1f, 0.f);
    for (const Vec3f& d : decompose(c, 1.f))
        EXPECT_LT(d.norm(), 1e-5f);
}

TEST(Prototype, WavyOutlineIsStraightAndDetailsCarryTheWave) {
    // Fig. 5: smoothing over one period removes the sine wave, leaving a straight outline;
    // the details hold the wave, perpendicular to it, with the prototype's amplitude.
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kWavy;
    spec.amplitude = 1.f;
    spec.period = 4.f;
    spec.length = 40.f;
    const PrototypeCurve c = make_prototype_curve(spec);
    // Away from the ends, the centre line is on the axis.
    for (size_t k = c.centre.size() / 4; k < 3 * c.centre.size() / 4; ++k)
        EXPECT_LT(std::abs(c.centre[k].x()), 0.02f);
    const std::vector<Vec3f> d = decompose(c, 0.25f);
    float peak = 0.f;
    for (size_t i = d.size() / 4; i < 3 * d.size() / 4; ++i) {
        EXPECT_LT(std::abs(d[i].x()), 0.02f);  // no detail along the outline
        peak = std::max(peak, d[i].norm());
    }
    EXPECT_NEAR(peak, 1.f, 0.03f);
}

TEST(Prototype, CurlyDetailsHaveTheCoilRadius) {
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kCurly;
    spec.amplitude = 0.7f;
    spec.period = 2.f;
    spec.length = 30.f;
    const PrototypeCurve c = make_prototype_curve(spec);
    const std::vector<Vec3f> d = decompose(c, 0.3f);
    for (size_t i = d.size() / 4; i < 3 * d.size() / 4; ++i)
        EXPECT_NEAR(d[i].norm(), 0.7f, 0.05f);
}

TEST(Prototype, SmoothingAUserPolylineRecoversItsAxis) {
    // A user polyline has no known axis: a moving average over one period (in arc length)
    // finds it. Build a wave sampled evenly in arc length, like a digitized curve.
    PrototypeSpec spec;
    spec.kind = PrototypeSpec::Kind::kWavy;
    spec.amplitude = 0.3f;
    spec.period = 4.f;
    spec.length = 40.f;
    const std::vector<Vec3f> wave = prototype_polyline(spec);
    PrototypeSpec user;
    user.kind = PrototypeSpec::Kind::kPolyline;
    user.polyline = wave;
    user.period = 4.f;
    const PrototypeCurve c = make_prototype_curve(user);
    for (size_t k = c.centre.size() / 4; k < 3 * c.centre.size() / 4; ++k)
        EXPECT_LT(std::abs(c.centre[k].x()), 0.05f);
}

TEST(Prototype, OutlineSegmentsHaveTheRequestedCount) {
    PrototypeSpec spec;
    spec.length = 10.f;
    const PrototypeCurve c = prepare_prototype(prototype_polyline(spec), 0.05f, 0.f);
    EXPECT_EQ(decompose(c, 1.f).size(), 11u);
}

TEST(Prototype, DecomposeIntoReusedBuffersIsTheReturnedVectorToTheBit) {
    // The masters decompose into per-thread buffers, growing and shrinking between calls.
    std::vector<Vec3f> details, work;
    for (const PrototypeSpec::Kind kind :
         {PrototypeSpec::Kind::kWavy, PrototypeSpec::Kind::kCurly, PrototypeSpec::Kind::kKinky}) {
        PrototypeSpec spec;
        spec.kind = kind;
        spec.amplitude = 0.4f;
        spec.period = 3.f;
        spec.length = 30.f;
        const PrototypeCurve c = make_prototype_curve(spec);
        for (const float segment : {0.29f, 1.7f, 0.05f, 0.81f, 20.f, 0.f, 0.33f}) {
            const std::vector<Vec3f> expected = decompose(c, segment);
            decompose(c, segment, details, work);
            ASSERT_EQ(details.size(), expected.size()) << segment;
            EXPECT_EQ(0,
                      std::memcmp(details.data(), expected.data(), expected.size() * sizeof(Vec3f)))
                << segment;
        }
    }
}

}  // namespace wisp
