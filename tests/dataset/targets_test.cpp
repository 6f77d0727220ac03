// The training targets on synthetic strands of known direction and depth.
#include "dataset/targets.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace wisp {
namespace {

// A camera on +Z looking at the origin, 64×64 pixels.
Camera front() {
    return look_at(Vec3f(0, 0, 50), Vec3f(0, 0, 0), Vec3f::UnitY(), 30.f, 64, 64);
}

// The camera's focal length in pixels: 32 / tan(15°).
constexpr float kFocal = 119.43f;

// A straight strand; width in cm (0.5 cm: 1.2 pixels wide at 50 cm).
Hair straight(const Vec3f& from, const Vec3f& to, int points = 16, float width = 0.5f) {
    Hair h;
    for (int i = 0; i < points; ++i)
        h.points.push_back(from + (to - from) * (float(i) / (points - 1)));
    h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
    h.default_width = width;
    return h;
}

int hair_pixels(const TargetMaps& m) {
    int n = 0;
    for (uint8_t h : m.hair)
        n += h;
    return n;
}

// The mean orientation over hair pixels, as the doubled angle (θ and θ + π agree).
double mean_theta(const TargetMaps& m, int* pixels) {
    double c = 0, s = 0;
    *pixels = 0;
    for (size_t i = 0; i < m.hair.size(); ++i)
        if (m.hair[i]) {
            c += std::cos(2 * m.orientation[i]);
            s += std::sin(2 * m.orientation[i]);
            ++*pixels;
        }
    double t = 0.5 * std::atan2(s, c);
    return t < 0 ? t + M_PI : t;
}

TEST(Targets, OrientationOfStrandsOfKnownDirection) {
    struct Case {
        Vec3f from, to;
        double theta;  // in the image, from +x towards up
    };
    const Case cases[] = {
        {{-5, 0, 0}, {5, 0, 0}, 0},              // left to right
        {{5, 0, 0}, {-5, 0, 0}, 0},              // the same line, drawn the other way
        {{0, -5, 0}, {0, 5, 0}, M_PI / 2},       // vertical
        {{-4, -4, 0}, {4, 4, 0}, M_PI / 4},      // rising to the right
        {{-4, 4, 0}, {4, -4, 0}, 3 * M_PI / 4},  // falling to the right
        {{0, 0, -5}, {3, 0, 5}, 0},              // through depth: horizontal on screen
    };
    for (const Case& c : cases) {
        const TargetMaps m = draw_targets(straight(c.from, c.to), nullptr, front());
        int pixels = 0;
        const double t = mean_theta(m, &pixels);
        EXPECT_GT(pixels, 5);
        const double diff = std::abs(std::remainder(t - c.theta, M_PI));
        EXPECT_LT(diff, 0.02) << c.from.transpose() << " -> " << c.to.transpose() << ": " << t;
        // Every pixel of a straight strand has the same orientation.
        for (size_t i = 0; i < m.hair.size(); ++i)
            if (m.hair[i]) {
                EXPECT_LT(std::abs(std::remainder(m.orientation[i] - c.theta, M_PI)), 0.02);
            }
    }
}

TEST(Targets, EncodingMaskAndDepth) {
    const TargetMaps m = draw_targets(straight({-5, 0, 0}, {5, 0, 0}), nullptr, front());
    const RgbImage o = orientation_image(m);
    const GrayImage mask = mask_image(m);
    int hair = 0;
    for (size_t i = 0; i < m.hair.size(); ++i) {
        if (!m.hair[i]) {
            EXPECT_EQ(o.rgb[3 * i], 0);
            EXPECT_EQ(mask.values[i], 0.f);
            EXPECT_EQ(m.depth[i], 0.f);
            continue;
        }
        ++hair;
        EXPECT_EQ(o.rgb[3 * i], 255);      // R: on hair
        EXPECT_EQ(o.rgb[3 * i + 1], 255);  // G: (1 + cos 0) / 2
        EXPECT_EQ(o.rgb[3 * i + 2], 128);  // B: (1 + sin 0) / 2
        EXPECT_EQ(mask.values[i], 1.f);
        EXPECT_NEAR(m.depth[i], 50.f, 1e-3f);  // the strand lies in the plane z = 0
    }
    EXPECT_GT(hair, 10);
}

TEST(Targets, HairBehindTheHeadIsHidden) {
    // A quad (two triangles) at z = 0 across the middle; a strand behind it at z = -2 and one
    // in front at z = 2.
    Mesh quad;
    quad.vertices = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
    quad.faces = {{0, 1, 2}, {0, 2, 3}};
    const TargetMaps behind = draw_targets(straight({-5, 0, -2}, {5, 0, -2}), &quad, front());
    for (size_t i = 0; i < behind.hair.size(); ++i)
        EXPECT_EQ(behind.hair[i], 0);
    const TargetMaps ahead = draw_targets(straight({-5, 0, 2}, {5, 0, 2}), &quad, front());
    int hair = 0, head = 0;
    for (size_t i = 0; i < ahead.hair.size(); ++i) {
        hair += ahead.hair[i];
        if (!ahead.hair[i] && ahead.depth[i] > 0) {
            ++head;
            EXPECT_NEAR(ahead.depth[i], 50.f, 1e-2f);
        }
        if (ahead.hair[i]) {
            EXPECT_NEAR(ahead.depth[i], 48.f, 1e-2f);
        }
    }
    EXPECT_GT(hair, 10);
    EXPECT_GT(head, 500);
}

// The mask follows coverage, as a picture does: a strand a tenth of a pixel wide alone covers
// no pixel by half, ten of them side by side within a pixel cover it (1 − 0.9¹⁰ ≈ 0.65), and
// a strand wider than a pixel covers its line.
TEST(Targets, TheMaskIsWhereHairCoversHalfThePixel) {
    const float tenth = 0.1f * 50.f / kFocal;  // cm: a tenth of a pixel at 50 cm
    const TargetMaps thin =
        draw_targets(straight({-5, 0, 0}, {5, 0, 0}, 16, tenth), nullptr, front());
    EXPECT_EQ(hair_pixels(thin), 0);
    int with_depth = 0;  // the depth map still has the strand, as geometry
    for (float d : thin.depth)
        with_depth += d > 0;
    EXPECT_GT(with_depth, 20);
    Hair clump;
    for (int k = 0; k < 10; ++k) {
        const Hair one = straight({-5, 0.001f * k, 0}, {5, 0.001f * k, 0}, 16, tenth);
        clump.points.insert(clump.points.end(), one.points.begin(), one.points.end());
        clump.offsets.push_back(static_cast<uint32_t>(clump.points.size()));
    }
    clump.default_width = tenth;
    const TargetMaps clumped = draw_targets(clump, nullptr, front());
    const int line = hair_pixels(draw_targets(straight({-5, 0, 0}, {5, 0, 0}), nullptr, front()));
    EXPECT_GT(line, 20);
    EXPECT_GE(hair_pixels(clumped), line - 2);
    // Three of them do not (a pixel gets one or two steps of a strand, so at most 1 − 0.9⁶).
    clump.points.resize(3 * 16);
    clump.offsets.resize(4);
    EXPECT_EQ(hair_pixels(draw_targets(clump, nullptr, front())), 0);
}

}  // namespace
}  // namespace wisp
