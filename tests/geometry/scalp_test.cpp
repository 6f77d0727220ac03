#include "geometry/scalp.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "core/error.hpp"
#include "core/image.hpp"
#include "core/rng.hpp"
#include "geometry/builtin_head.hpp"
#include "test_meshes.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

using test::kBase;
using test::kHeadNeckShoulders;

const Mesh& head() {
    return test::builtin_mesh();
}

ScalpSpec hairline() {
    ScalpSpec s;
    s.kind = ScalpSpec::Kind::kHairline;
    return s;
}

Vec3f centroid(const Mesh& m, uint32_t f) {
    const Vec3i& t = m.faces[f];
    return (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.f;
}

std::string error_of(const Mesh& m, const ScalpSpec& spec, const std::string& source) {
    try {
        Scalp s(m, spec, source);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Properties every scalp has, whichever way it was selected.
void check_scalp(const Scalp& scalp) {
    const Mesh& m = scalp.mesh();
    ASSERT_FALSE(scalp.faces().empty());
    double area = 0;
    for (uint32_t f : scalp.faces())
        area += m.face_area(f);
    EXPECT_NEAR(scalp.area(), area, 1e-3 * area);
    // The crown is the top of the cap and the centre of the UV disk.
    EXPECT_LT((scalp.uv_of(scalp.crown()) - Vec2f(0.5f, 0.5f)).norm(), 1e-3f);
    EXPECT_GT(scalp.crown().y(), scalp.center().y());
    // UV orientation: front toward v = 1, the character's left (+X) toward u = 0 (top view).
    const Vec3f up = scalp.crown() - scalp.center();
    EXPECT_GT(scalp.uv_of(scalp.center() + up + Vec3f(0, 0, 5)).y(), 0.55f);
    EXPECT_LT(scalp.uv_of(scalp.center() + up + Vec3f(5, 0, 0)).x(), 0.45f);

    const std::set<uint32_t> faces(scalp.faces().begin(), scalp.faces().end());
    Rng rng(42, Stream::kRoots, 0);
    float max_r = 0.f;
    for (int i = 0; i < 5000; ++i) {
        const SurfacePoint sp = scalp.sample(rng);
        ASSERT_TRUE(faces.count(sp.face)) << "sample on non-scalp face " << sp.face;
        ASSERT_GE(sp.bary.x(), 0.f);
        ASSERT_GE(sp.bary.y(), 0.f);
        ASSERT_LE(sp.bary.x() + sp.bary.y(), 1.f + 1e-6f);
        EXPECT_NEAR(sp.normal.norm(), 1.f, 1e-4f);
        EXPECT_GT(sp.normal.dot(m.face_normal(sp.face)), 0.5f);
        EXPECT_GT(sp.normal.dot((sp.position - scalp.center()).normalized()), 0.f);
        const float r = (sp.uv - Vec2f(0.5f, 0.5f)).norm();
        ASSERT_LE(r, 0.5f + 1e-5f);
        max_r = std::max(max_r, r);
        const SurfacePoint again = scalp.point_on(sp.face, sp.bary);
        ASSERT_LT((again.position - sp.position).norm(), 1e-5f);
        ASSERT_LT((again.uv - scalp.uv_of(sp.position)).norm(), 1e-6f);
    }
    EXPECT_GT(max_r, 0.45f);  // the map fills the unit disk
}

// Area uniformity: 16 strata of faces (by index), sample counts against area, chi-square with
// 15 degrees of freedom (the 99.99% quantile is 42.6).
void check_area_uniform(const Scalp& scalp, uint64_t seed) {
    constexpr int kStrata = 16, kSamples = 64000;
    std::vector<double> expected(kStrata, 0.0), observed(kStrata, 0.0);
    std::vector<int> stratum(scalp.mesh().faces.size(), -1);
    for (size_t i = 0; i < scalp.faces().size(); ++i) {
        const uint32_t f = scalp.faces()[i];
        stratum[f] = static_cast<int>((f * 2654435761u >> 7) % kStrata);
        expected[stratum[f]] += scalp.mesh().face_area(f) / scalp.area() * kSamples;
    }
    Rng rng(seed);
    for (int i = 0; i < kSamples; ++i)
        observed[stratum[scalp.sample(rng).face]] += 1;
    double chi2 = 0;
    for (int s = 0; s < kStrata; ++s)
        if (expected[s] > 0)
            chi2 += (observed[s] - expected[s]) * (observed[s] - expected[s]) / expected[s];
    EXPECT_LT(chi2, 42.6) << "sampling is not area-uniform";
}

TEST(Scalp, BuiltinGroup) {
    const Scalp scalp(head(), ScalpSpec{}, "built-in head");
    check_scalp(scalp);
    check_area_uniform(scalp, 7);
    EXPECT_GT(scalp.area(), 450.f);
    EXPECT_LT(scalp.area(), 800.f);
    EXPECT_NEAR(scalp.crown().y(), head().bounds().hi.y(), 0.3f);
    EXPECT_NEAR(scalp.crown().x(), 0.f, 0.3f);
    // Upper half of the scalp: left/right halves get samples in proportion to their areas.
    double left = 0;
    for (uint32_t f : scalp.faces())
        if (centroid(head(), f).x() > 0) left += head().face_area(f);
    Rng rng(3);
    int n_left = 0;
    constexpr int n = 40000;
    for (int i = 0; i < n; ++i)
        n_left += scalp.sample(rng).position.x() > 0;
    const double p = left / scalp.area();
    EXPECT_NEAR(n_left / static_cast<double>(n), p, 4 * std::sqrt(p * (1 - p) / n));
}

TEST(Scalp, SamplingIsDeterministic) {
    const Scalp scalp(head(), ScalpSpec{}, "built-in head");
    Rng a(11, Stream::kRoots, 5), b(11, Stream::kRoots, 5);
    for (int i = 0; i < 100; ++i) {
        const SurfacePoint pa = scalp.sample(a), pb = scalp.sample(b);
        ASSERT_EQ(pa.face, pb.face);
        ASSERT_EQ(pa.position, pb.position);
    }
}

// The guide table only narrows the search: at every bucket edge, every cumulative area and
// the floats either side of both, and at random u, the face slot is the first whose cumulative
// area exceeds u, as a binary search of the whole table finds it.
TEST(Scalp, GuidedFaceSlotIsTheFullBinarySearch) {
    for (const ScalpSpec& spec : {ScalpSpec{}, hairline()}) {
        const Scalp scalp(head(), spec, "builtin");
        const std::vector<float>& cdf = scalp.cumulative_area();
        const size_t n = cdf.size();
        const auto full = [&](float u) {
            return std::min<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin(),
                                    n - 1);
        };
        std::vector<float> us;
        for (size_t b = 0; b <= n; ++b)
            us.push_back(static_cast<float>(b) / static_cast<float>(n));
        us.insert(us.end(), cdf.begin(), cdf.end());
        Rng rng(3);
        for (int i = 0; i < 100000; ++i)
            us.push_back(rng.uniform());
        for (const float x : us)
            for (const float u : {std::nextafter(x, -1.f), x, std::nextafter(x, 2.f)})
                if (u >= 0.f && u < 1.f) ASSERT_EQ(scalp.face_slot(u), full(u)) << u;
    }
}

TEST(Scalp, BuiltinHairline) {
    const Scalp scalp(head(), hairline(), "built-in head");
    check_scalp(scalp);
    check_area_uniform(scalp, 8);
    EXPECT_GT(scalp.area(), 400.f);
    EXPECT_LT(scalp.area(), 900.f);
    const float top = head().bounds().hi.y();
    for (uint32_t f : scalp.faces()) {
        const Vec3f c = centroid(head(), f);
        ASSERT_GT(c.y(), top - hairline().hairline_back - 0.5f);
        if (c.z() > 5.f && std::abs(c.x()) < 3.f) {
            ASSERT_GT(c.y(), top - 7.f) << "scalp on the face";
        }
        ASSERT_FALSE(std::abs(c.x()) > 8.f && c.y() < 2.7f) << "scalp on the ears";
    }
    // It largely agrees with the hand-made scalp group.
    const Scalp group(head(), ScalpSpec{}, "built-in head");
    std::vector<uint32_t> common;
    std::set_intersection(scalp.faces().begin(), scalp.faces().end(), group.faces().begin(),
                          group.faces().end(), std::back_inserter(common));
    EXPECT_GT(common.size(), 0.75 * group.faces().size());
}

TEST(Scalp, BuiltinMask) {
    // A white disk of radius 0.2 around the crown in the head's UV space (the polar map).
    RgbImage img;
    img.width = img.height = 128;
    img.rgb.assign(128 * 128 * 3, 0);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            const float u = (x + 0.5f) / 128.f, v = 1.f - (y + 0.5f) / 128.f;
            if (std::hypot(u - 0.5f, v - 0.5f) < 0.2f)
                for (int c = 0; c < 3; ++c)
                    img.rgb[(y * 128 + x) * 3 + c] = 255;
        }
    const fs::path mask =
        fs::temp_directory_path() / ("wisp_scalp_mask_" + std::to_string(::getpid()) + ".png");
    write_png(mask, img);
    ScalpSpec spec;
    spec.kind = ScalpSpec::Kind::kMask;
    spec.mask = mask;
    const Scalp scalp(head(), spec, "built-in head");
    check_scalp(scalp);
    for (uint32_t f : scalp.faces()) {
        const Vec3i& t = head().face_uvs[f];
        const Vec2f uv = (head().uvs[t[0]] + head().uvs[t[1]] + head().uvs[t[2]]) / 3.f;
        ASSERT_LT((uv - Vec2f(0.5f, 0.5f)).norm(), 0.2f + 0.02f);
        ASSERT_GT(centroid(head(), f).y(), 0.f);
    }
    fs::remove(mask);

    Mesh no_uv = head();
    no_uv.uvs.clear();
    no_uv.face_uvs.clear();
    const std::string err = error_of(no_uv, spec, "plain.obj");
    EXPECT_NE(err.find("plain.obj"), std::string::npos) << err;
    EXPECT_NE(err.find("mask"), std::string::npos) << err;
}

TEST(Scalp, EmptySelectionNamesSourceAndMethod) {
    ScalpSpec spec;
    spec.group = "hat";
    std::string err = error_of(head(), spec, "my_head.obj");
    EXPECT_NE(err.find("my_head.obj"), std::string::npos) << err;
    EXPECT_NE(err.find("'hat'"), std::string::npos) << err;
    EXPECT_NE(err.find("scalp, body"), std::string::npos) << err;  // lists what there is

    ScalpSpec none = hairline();
    none.hairline_front = none.hairline_side = none.hairline_back = 0.f;
    err = error_of(head(), none, "my_head.obj");
    EXPECT_NE(err.find("my_head.obj"), std::string::npos) << err;
    EXPECT_NE(err.find("hairline"), std::string::npos) << err;
    EXPECT_NE(err.find("empty"), std::string::npos) << err;
}

TEST(Scalp, MakeHumanHeadHairline) {
    if (!fs::exists(kHeadNeckShoulders)) GTEST_SKIP() << kHeadNeckShoulders << " not present";
    const Mesh m = read_obj_mesh(kHeadNeckShoulders, 10.f);
    const Scalp scalp(m, hairline(), kHeadNeckShoulders);
    check_scalp(scalp);
    check_area_uniform(scalp, 9);
    EXPECT_GT(scalp.area(), 400.f);
    EXPECT_LT(scalp.area(), 900.f);
    EXPECT_NEAR(scalp.crown().y(), m.bounds().hi.y(), 0.5f);
    const float top = m.bounds().hi.y();
    const float nape = hairline().hairline_back;
    // No scalp below the nape hairline; the nape reaches it in the middle of the back of the
    // neck and runs nearly level from there to behind the ears, as on a real head (a hairline
    // sloping up from the nape to above the ears leaves a bald patch behind each ear).
    const Vec3f c0 = scalp.center();
    float lowest_middle = INFINITY, lowest_behind_ear = INFINITY;
    for (uint32_t f : scalp.faces()) {
        const Vec3f c = centroid(m, f);
        ASSERT_GT(c.y(), top - nape - 0.5f);
        const float azimuth = std::abs(std::atan2(c.x() - c0.x(), c.z() - c0.z()));
        if (azimuth > 0.95f * kPi) lowest_middle = std::min(lowest_middle, c.y());
        if (azimuth > 0.7f * kPi && azimuth < 0.75f * kPi)
            lowest_behind_ear = std::min(lowest_behind_ear, c.y());
    }
    EXPECT_LT(lowest_middle, top - nape + 1.5f);
    EXPECT_LT(lowest_behind_ear, top - nape + 3.f);
    // No slot up the middle of the nape, where the neck's furrow turns the faces' normals down:
    // a slot's edges inside the scalp thin the roots around them into a bald spot. Up the
    // back's midline, from 1.5 cm above the hairline, the edge is more than a centimetre away.
    for (uint32_t f : scalp.faces()) {
        const Vec3f c = centroid(m, f);
        const float azimuth = std::abs(std::atan2(c.x() - c0.x(), c.z() - c0.z()));
        if (azimuth > 0.97f * kPi && c.y() > lowest_middle + 1.5f)
            EXPECT_GT(scalp.edge_distance(f, c), 1.f) << "face " << f << " at " << c.transpose();
    }
    // The group "helper-hair" is not part of this file.
    ScalpSpec spec;
    spec.group = "helper-hair";
    EXPECT_NE(error_of(m, spec, "hns").find("helper-hair"), std::string::npos);
}

TEST(Scalp, MakeHumanBodyGroupAndHairline) {
    if (!fs::exists(kBase)) GTEST_SKIP() << kBase << " not present";
    const Mesh m = read_obj_mesh(kBase, 10.f);
    ScalpSpec spec;
    spec.group = "helper-hair";
    const Scalp helper(m, spec, kBase);
    EXPECT_EQ(helper.faces().size(), 2u * 198u);

    // The hairline finds the scalp of the body, not the helper shells above it.
    const Scalp scalp(m, hairline(), kBase);
    check_scalp(scalp);
    EXPECT_GT(scalp.area(), 400.f);
    EXPECT_LT(scalp.area(), 900.f);
    int body = -1;
    for (size_t g = 0; g < m.group_names.size(); ++g)
        if (m.group_names[g] == "body") body = static_cast<int>(g);
    for (uint32_t f : scalp.faces())
        ASSERT_EQ(m.face_group[f], body);
}

}  // namespace
}  // namespace wisp

namespace wisp {
namespace {

// A flat 10 × 10 cm square of 1 cm cells in the xz-plane, all of it group "scalp"; with
// `seam`, the cells on either side of x = 5 have their own copies of the vertices there, as
// a UV seam leaves them.
Mesh square(bool seam) {
    Mesh m;
    // Vertex ids per (i, j, side): side 1 is the copy right of the seam.
    std::vector<int> id(11 * 11 * 2, -1);
    const auto at = [&](int i, int j, int side) {
        if (!seam || i != 5) side = 0;
        int& v = id[(i * 11 + j) * 2 + side];
        if (v < 0) {
            v = static_cast<int>(m.vertices.size());
            m.vertices.emplace_back(static_cast<float>(i), 0.f, static_cast<float>(j));
        }
        return v;
    };
    m.group_names = {"scalp"};
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
            const int side = i >= 5 ? 1 : 0;
            const int a = at(i, j, side), b = at(i + 1, j, side), c = at(i + 1, j + 1, side),
                      d = at(i, j + 1, side);
            m.faces.emplace_back(a, c, b);
            m.faces.emplace_back(a, d, c);
            m.face_group.push_back(0);
            m.face_group.push_back(0);
        }
    return m;
}

}  // namespace

TEST(ScalpEdge, DistanceGrowsFromTheBoundaryAndASeamIsNoEdge) {
    for (bool seam : {false, true}) {
        const Mesh m = square(seam);
        const Scalp scalp(m, ScalpSpec{}, "square");
        const auto at = [&](const Vec3f& q) {
            for (uint32_t f : scalp.faces()) {
                const Vec3i& t = m.faces[f];
                const Vec3f a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
                const Vec3f n = (b - a).cross(c - a);
                const auto inside = [&](const Vec3f& p, const Vec3f& e0, const Vec3f& e1) {
                    return (e1 - e0).cross(p - e0).dot(n) >= -1e-6f;
                };
                if (inside(q, a, b) && inside(q, b, c) && inside(q, c, a))
                    return scalp.edge_distance(f, q);
            }
            return -1.f;
        };
        EXPECT_NEAR(at(Vec3f(5.f, 0.f, 5.f)), 5.f, 0.15f) << "seam " << seam;
        EXPECT_NEAR(at(Vec3f(5.f, 0.f, 1.f)), 1.f, 0.15f) << "seam " << seam;
        EXPECT_NEAR(at(Vec3f(0.f, 0.f, 4.f)), 0.f, 1e-4f) << "seam " << seam;
        EXPECT_NEAR(at(Vec3f(2.5f, 0.f, 5.f)), 2.5f, 0.2f) << "seam " << seam;
    }
}

TEST(ScalpEdge, TheBuiltInHairlineIsNearAndTheCrownFar) {
    const Scalp scalp(head(), ScalpSpec{}, "built-in");
    Rng rng(4);
    float least = 1e9f, most = 0.f;
    for (int k = 0; k < 20000; ++k) {
        const float e = scalp.edge_distance(scalp.sample(rng));
        least = std::min(least, e);
        most = std::max(most, e);
    }
    EXPECT_LT(least, 0.1f) << "roots reach the hairline";
    EXPECT_GT(most, 6.f) << "the crown lies far from every edge";
    EXPECT_LT(most, Scalp::kNoEdge);
}

}  // namespace wisp
