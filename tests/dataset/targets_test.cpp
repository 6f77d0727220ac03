// The training targets on synthetic strands of known direction and depth.
#include "dataset/targets.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"

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

// Strands added one after another into one Hair (each keeps its points and the first's width).
Hair together(std::initializer_list<Hair> parts) {
    Hair out;
    for (const Hair& h : parts) {
        out.points.insert(out.points.end(), h.points.begin(), h.points.end());
        out.offsets.push_back(static_cast<uint32_t>(out.points.size()));
    }
    out.default_width = parts.begin()->default_width;
    return out;
}

// HairStep's strand map: the direction from root to tip, not only its line; the head shows at
// half red where no hair covers it.
TEST(Targets, StrandMapIsDirectedRootToTip) {
    Mesh quad;
    quad.vertices = {{-10, -10, -5}, {10, -10, -5}, {10, 10, -5}, {-10, 10, -5}};
    quad.faces = {{0, 1, 2}, {0, 2, 3}};
    struct Case {
        Vec3f from, to;
        uint8_t g, b;  // (1 + dx)/2, (1 + dy)/2, y up
    };
    const Case cases[] = {
        {{0, 5, 0}, {0, -5, 0}, 128, 0},    // falling: root above the tip
        {{0, -5, 0}, {0, 5, 0}, 128, 255},  // rising
        {{-5, 0, 0}, {5, 0, 0}, 255, 128},  // to the right
        {{5, 0, 0}, {-5, 0, 0}, 0, 128},    // to the left
    };
    for (const Case& c : cases) {
        const TargetMaps m = draw_targets(straight(c.from, c.to), &quad, front());
        const RgbImage img = strand_map_image(m);
        int hair = 0, head = 0;
        for (size_t i = 0; i < m.hair.size(); ++i) {
            const uint8_t* px = &img.rgb[3 * i];
            if (m.hair[i]) {
                ++hair;
                EXPECT_EQ(px[0], 255);
                // 8 bits: 127.5 may round either way.
                EXPECT_NEAR(px[1], c.g, 1) << c.to.transpose();
                EXPECT_NEAR(px[2], c.b, 1) << c.to.transpose();
            } else {
                head += px[0] == 128;
                EXPECT_TRUE(px[0] == 128 || px[0] == 0);
                EXPECT_EQ(px[1], 0);
                EXPECT_EQ(px[2], 0);
            }
        }
        EXPECT_GT(hair, 10);
        EXPECT_GT(head, 500);
    }
}

// Confidence: one orientation over a pixel's visible strands is 1; strands crossing at right
// angles where the front ones let half the pixel through to the back ones pull it toward 0,
// and an opaque front layer hides the back one again.
TEST(Targets, ConfidenceFallsWhereVisibleStrandsCross) {
    const float px = 50.f / kFocal;  // cm: a pixel at 50 cm
    auto sheet = [&](bool vertical, float z, float width) {
        Hair h;
        for (int k = -8; k <= 8; ++k) {
            const float o = 0.5f * px * k;
            const Hair one = vertical ? straight({o, -3, z}, {o, 3, z}, 16, width)
                                      : straight({-3, o, z}, {3, o, z}, 16, width);
            h.points.insert(h.points.end(), one.points.begin(), one.points.end());
            h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
        }
        h.default_width = width;
        return h;
    };
    auto centre_confidence = [&](const Hair& h) {
        const TargetMaps m = draw_targets(h, nullptr, front(), true);
        const size_t centre = 32 * 64 + 32;
        EXPECT_EQ(m.hair[centre], 1);
        return m.confidence[centre];
    };
    const float thin = 0.15f * px, thick = 2.f * px;
    EXPECT_NEAR(centre_confidence(sheet(false, 0, thin)), 1.f, 1e-5f);
    // Thin strands crossing: each layer covers about half; the back shows through.
    Hair crossing = sheet(false, 1, thin);
    const Hair back = sheet(true, 0, thin);
    for (size_t i = 1; i < back.offsets.size(); ++i) {
        crossing.points.insert(crossing.points.end(), back.points.begin() + back.offsets[i - 1],
                               back.points.begin() + back.offsets[i]);
        crossing.offsets.push_back(static_cast<uint32_t>(crossing.points.size()));
    }
    EXPECT_LT(centre_confidence(crossing), 0.7f);
    // An opaque front layer: the back layer is hidden.
    Hair hidden = sheet(false, 1, thick);
    for (size_t i = 1; i < back.offsets.size(); ++i) {
        hidden.points.insert(hidden.points.end(), back.points.begin() + back.offsets[i - 1],
                             back.points.begin() + back.offsets[i]);
        hidden.offsets.push_back(static_cast<uint32_t>(hidden.points.size()));
    }
    EXPECT_GT(centre_confidence(hidden), 0.99f);
}

// The matte is the hair's coverage (the mask is where it reaches a half), the strand-id map
// names the nearest strand, and HairStep's depth runs from 0 at the nearest hair to 1 at the
// farthest over the mask, 0 off it.
TEST(Targets, MatteStrandIdsAndHairStepDepth) {
    // Strand 0 at z = 2 on the left, strand 1 at z = 0 across the whole width (behind strand
    // 0 where they overlap), strand 2 at z = -2 on the right, lower.
    const Hair h =
        together({straight({-5, 0.4f, 2}, {-1, 0.4f, 2}), straight({-5, 0.4f, 0}, {5, 0.4f, 0}),
                  straight({1, -0.6f, -2}, {5, -0.6f, -2})});
    const TargetMaps m = draw_targets(h, nullptr, front());
    const GrayImage matte = matte_image(m);
    const std::vector<float> d = hairstep_depth(m);
    int seen[3] = {0, 0, 0};
    float lo = 1, hi = 0;
    for (size_t i = 0; i < m.hair.size(); ++i) {
        EXPECT_GE(matte.values[i], 0.f);
        EXPECT_LE(matte.values[i], 1.f);
        EXPECT_EQ(m.hair[i], matte.values[i] >= 0.5f) << i;
        if (m.strand[i] < 0) {
            EXPECT_EQ(m.depth[i], 0.f);
            continue;
        }
        ASSERT_LT(m.strand[i], 3);
        ++seen[m.strand[i]];
        const float expected_z = 50.f - (2.f - 2.f * m.strand[i]);
        EXPECT_NEAR(m.depth[i], expected_z, 0.05f) << i;
        if (!m.hair[i]) {
            EXPECT_EQ(d[i], 0.f);
            continue;
        }
        lo = std::min(lo, d[i]);
        hi = std::max(hi, d[i]);
        // Linear in depth: 48 cm → 0, 52 cm → 1.
        EXPECT_NEAR(d[i], (m.depth[i] - 48.f) / 4.f, 0.02f) << i;
    }
    EXPECT_GT(seen[0], 5);
    EXPECT_GT(seen[1], 5);
    EXPECT_GT(seen[2], 5);
    EXPECT_EQ(lo, 0.f);
    EXPECT_EQ(hi, 1.f);
}

// The volume of a straight strand along x: the voxels of its row are occupied with direction
// +x (its root to tip), and no other; reversed, the direction turns.
TEST(Targets, VolumeOfAStrandAlongX) {
    const Vec3f lo(-4, -4, -4), hi(4, 4, 4);
    const Vec3i dims(8, 8, 8);  // 1 cm voxels
    const HairVolume v =
        hair_volume(straight({-3.5f, 0.5f, -0.5f}, {3.5f, 0.5f, -0.5f}), lo, hi, dims);
    int occupied = 0;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const size_t at = (static_cast<size_t>(z) * 8 + y) * 8 + x;
                const bool row = y == 4 && z == 3 && x >= 0 && x <= 7;
                EXPECT_EQ(v.occupancy[at], row ? 1 : 0) << x << " " << y << " " << z;
                occupied += v.occupancy[at];
                if (row) EXPECT_NEAR(v.orientation[3 * at], 1.f, 1e-6f);
            }
    EXPECT_EQ(occupied, 8);
    const HairVolume back =
        hair_volume(straight({3.5f, 0.5f, -0.5f}, {-3.5f, 0.5f, -0.5f}), lo, hi, dims);
    EXPECT_NEAR(back.orientation[3 * ((3 * 8 + 4) * 8 + 2)], -1.f, 1e-6f);
    EXPECT_THROW(hair_volume(Hair{}, hi, lo, dims), Error);
    EXPECT_THROW(hair_volume(Hair{}, lo, hi, Vec3i(4096, 4096, 4096)), Error);
}

// Against the strands it comes from: every point of a curled hair lies in an occupied voxel,
// and the voxel's direction is within 30° of the strand's there for nearly all of them (a
// voxel holds the mean of what crosses it).
TEST(Targets, VolumeAgreesWithItsStrands) {
    Hair h;
    for (int s = 0; s < 60; ++s) {
        const float phase = 0.37f * s, x0 = -3.f + 0.1f * s;
        for (int i = 0; i < 64; ++i) {
            const float t = i / 63.f;
            h.points.emplace_back(x0 + 0.6f * std::cos(6.f * t + phase), 3.f - 6.f * t,
                                  0.6f * std::sin(6.f * t + phase));
        }
        h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
    }
    const Vec3f lo(-5, -5, -5), hi(5, 5, 5);
    const Vec3i dims(40, 40, 40);
    const HairVolume v = hair_volume(h, lo, hi, dims);
    int agree = 0, total = 0;
    for (size_t s = 0; s < h.strand_count(); ++s) {
        const auto p = h.strand(s);
        for (size_t i = 0; i + 1 < p.size(); ++i) {
            const Vec3f mid = 0.5f * (p[i] + p[i + 1]);
            const Vec3f q = (mid - lo) / 0.25f;
            const size_t at = (static_cast<size_t>(q.z()) * 40 + static_cast<size_t>(q.y())) * 40 +
                              static_cast<size_t>(q.x());
            ASSERT_EQ(v.occupancy[at], 1);
            const Vec3f o(v.orientation[3 * at], v.orientation[3 * at + 1],
                          v.orientation[3 * at + 2]);
            agree += o.dot((p[i + 1] - p[i]).normalized()) > std::cos(30.f * kPi / 180.f);
            ++total;
        }
    }
    EXPECT_GT(agree, 0.9 * total) << agree << " of " << total;
}

// The scalp texture: each texel holds the strand rooted nearest its centre among those rooted
// in it, as offsets from its root, resampled evenly; texels without a root are empty.
TEST(Targets, ScalpTextureHoldsTheStrandRootedInEachTexel) {
    Hair h;
    // Three vertical strands 10 cm long: two in texel (row 1, column 2) of a 4² texture (u in
    // [0.5, 0.75), v in [0.5, 0.75)), the second nearer its centre (0.625, 0.625); one in
    // texel (3, 0).
    const Vec2f uvs[] = {{0.51f, 0.74f}, {0.62f, 0.63f}, {0.1f, 0.1f}};
    for (int s = 0; s < 3; ++s) {
        for (int i = 0; i < 11; ++i)
            h.points.emplace_back(float(s), -float(i), 0.f);
        h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
        h.root_uv.push_back(uvs[s]);
        h.root_normal.push_back(Vec3f::UnitY());
    }
    const ScalpTexture t = scalp_texture(h, 4, 6);
    int filled = 0;
    for (uint8_t m : t.mask)
        filled += m;
    EXPECT_EQ(filled, 2);
    const size_t a = 1 * 4 + 2, b = 3 * 4 + 0;
    EXPECT_EQ(t.strand[a], 1);
    EXPECT_EQ(t.strand[b], 2);
    EXPECT_EQ(t.roots[a * 3], 1.f);
    EXPECT_EQ(t.normals[a * 3 + 1], 1.f);
    for (int k = 0; k < 6; ++k) {  // 0, −2, −4, … −10 cm below the root
        EXPECT_NEAR(t.offsets[(a * 6 + k) * 3 + 0], 0.f, 1e-4f);
        EXPECT_NEAR(t.offsets[(a * 6 + k) * 3 + 1], -2.f * k, 1e-3f) << k;
    }
    EXPECT_EQ(t.strand[0], -1);
    Hair no_uv = h;
    no_uv.root_uv.clear();
    EXPECT_THROW(scalp_texture(no_uv, 4, 6), Error);
    EXPECT_THROW(scalp_texture(h, 4096, 64), Error);
}

}  // namespace
}  // namespace wisp
