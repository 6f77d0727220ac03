#include "groom/generate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "groom/color.hpp"

namespace wisp {
namespace {

Style small_style() {
    Style s;
    s.wisps = 120;
    s.strands = 6000;
    s.points_per_strand = 16;
    s.seed = 17;
    // The paper's model alone: no baby hairs, flyaways or roots laid down at the hairline
    // (grooming_details_test.cpp checks those).
    s.hairline.baby = 0.f;
    s.hairline.lie = 0.f;
    s.flyaway.fraction = 0.f;
    return s;
}

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

}  // namespace

TEST(Generate, ExactStrandAndWispCounts) {
    const Style style = small_style();
    const GenerateResult r = generate(style, builtin());
    EXPECT_EQ(r.hair.strand_count(), static_cast<size_t>(style.strands));
    EXPECT_EQ(r.masters.count(), static_cast<size_t>(style.wisps));
    EXPECT_NO_THROW(r.hair.validate("generated"));
    EXPECT_EQ(r.hair.colors.size(), r.hair.strand_count());
    EXPECT_EQ(r.hair.widths.size(), r.hair.point_count());
}

TEST(Generate, RootsLieOnTheScalpInTheirVoronoiRegion) {
    const Style style = small_style();
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const std::unordered_set<uint32_t> scalp(head.scalp->faces().begin(),
                                             head.scalp->faces().end());
    ASSERT_EQ(roots.members.size(), static_cast<size_t>(style.strands));
    for (const SurfacePoint& p : roots.masters)
        EXPECT_TRUE(scalp.count(p.face));
    for (size_t w = 0; w < roots.masters.size(); ++w) {
        for (uint32_t j = roots.wisp_offsets[w]; j < roots.wisp_offsets[w + 1]; ++j) {
            const SurfacePoint& p = roots.members[j];
            ASSERT_TRUE(scalp.count(p.face));
            const float own = (p.position - roots.masters[w].position).squaredNorm();
            for (const SurfacePoint& m : roots.masters)
                ASSERT_LE(own, (p.position - m.position).squaredNorm() + 1e-6f);
        }
    }
}

// The editor builds the scalp surface once per head and passes it in: the roots are the ones
// place_roots gives building it itself, bit for bit.
TEST(Generate, APrebuiltScalpSurfaceGivesTheSameRoots) {
    const Style style = small_style();
    const Head& head = builtin();
    const MeshDistance surface = scalp_surface(*head.scalp);
    const Roots a = grow_roots(style, head), b = grow_roots(style, head, &surface);
    const auto same = [](const std::vector<SurfacePoint>& x, const std::vector<SurfacePoint>& y) {
        return std::equal(x.begin(), x.end(), y.begin(), y.end(),
                          [](const SurfacePoint& p, const SurfacePoint& q) {
                              return p.face == q.face && p.bary == q.bary &&
                                     p.position == q.position && p.normal == q.normal &&
                                     p.uv == q.uv;
                          });
    };
    EXPECT_TRUE(same(a.masters, b.masters));
    EXPECT_TRUE(same(a.members, b.members));
    EXPECT_EQ(a.wisp_offsets, b.wisp_offsets);
    EXPECT_EQ(a.wisp_radius, b.wisp_radius);
}

TEST(Generate, MasterRootsAreEvenlySpread) {
    // Lloyd relaxation: the nearest-neighbour distance of master roots is far more even than
    // that of uniform random points (whose mean is about 0.5·sqrt(area/N)).
    Style style = small_style();
    style.wisps = 300;
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const float spacing = std::sqrt(head.scalp->area() / style.wisps);
    double sum = 0;
    float min_d = INFINITY;
    for (size_t i = 0; i < roots.masters.size(); ++i) {
        float best = INFINITY;
        for (size_t j = 0; j < roots.masters.size(); ++j)
            if (i != j)
                best =
                    std::min(best, (roots.masters[i].position - roots.masters[j].position).norm());
        sum += best;
        min_d = std::min(min_d, best);
    }
    EXPECT_GT(sum / roots.masters.size(), 0.75 * spacing);  // uniform random: about 0.5
    EXPECT_GT(min_d, 0.2f * spacing);                       // uniform random: about 0.03
}

TEST(Generate, EveryMemberPointIsWithinTheDeviationRadius) {
    Style style = small_style();
    style.wisp.fuzziness = 1.f;
    style.wisp.deviation_radius = {1.f, 2.f, 0.5f, 1.5f};
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const Masters masters = synthesize_masters(style, head, roots);
    const Hair hair = grow_members(style, *head.scalp, masters, roots);
    const int n = masters.points;
    for (size_t w = 0; w < masters.count(); ++w) {
        const auto master = masters.strand(w);
        for (uint32_t j = roots.wisp_offsets[w]; j < roots.wisp_offsets[w + 1]; ++j) {
            const auto strand = hair.strand(j);
            for (size_t k = 0; k + 1 < strand.size(); ++k) {
                const float s = static_cast<float>(k) / (n - 1);
                const float r = roots.wisp_radius[w] *
                                deviation_radius(style.wisp.deviation_radius, s) /
                                deviation_radius(style.wisp.deviation_radius, 0.f);
                ASSERT_LE((strand[k] - master[k]).norm(), r * 1.0001f + 1e-5f)
                    << "wisp " << w << " strand " << j << " point " << k;
            }
        }
    }
}

TEST(Generate, MeasuredLengthsFollowTheLengthDistribution) {
    // With a straight prototype, no fuzziness and a constant radius, a member is a copy of
    // its master cut at u: its length over the master's is exactly the drawn u.
    Style style = small_style();
    style.prototype.kind = PrototypeSpec::Kind::kStraight;
    style.wisp.fuzziness = 0.f;
    style.wisp.deviation_radius = {1.f};
    style.wisp.length = Distribution{Distribution::Kind::kUniform, 0.f, 0.6f, 1.f};
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const Masters masters = synthesize_masters(style, head, roots);
    const Hair hair = grow_members(style, *head.scalp, masters, roots);
    std::vector<double> u;
    for (size_t j = 0; j < hair.strand_count(); ++j) {
        const auto s = hair.strand(j);
        const int w = hair.wisp[j];
        const double len = (s.back() - s.front()).norm();
        const double master_len = masters.segment[w] * (masters.points - 1);
        u.push_back(len / master_len);
    }
    std::sort(u.begin(), u.end());
    // Kolmogorov-Smirnov distance to U[0.6, 1].
    double ks = 0;
    for (size_t i = 0; i < u.size(); ++i) {
        const double cdf = std::clamp((u[i] - 0.6) / 0.4, 0.0, 1.0);
        ks = std::max({ks, std::abs(cdf - static_cast<double>(i) / u.size()),
                       std::abs(cdf - static_cast<double>(i + 1) / u.size())});
    }
    EXPECT_LT(ks, 1.63 / std::sqrt(static_cast<double>(u.size())));  // 1% level
    EXPECT_GE(u.front(), 0.6 - 1e-3);
    EXPECT_LE(u.back(), 1.0 + 1e-3);
}

TEST(Generate, SameSeedSameHairAtAnyThreadCount) {
    const Style style = small_style();
    Hair a, b;
    {
        const ThreadLimit one(1);
        a = generate(style, builtin()).hair;
    }
    {
        const ThreadLimit two(2);
        b = generate(style, builtin()).hair;
    }
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_EQ(a.offsets, b.offsets);
    EXPECT_EQ(a.widths, b.widths);
    EXPECT_EQ(a.wisp, b.wisp);
    for (size_t i = 0; i < a.points.size(); ++i)
        ASSERT_EQ(a.points[i], b.points[i]) << i;
    for (size_t i = 0; i < a.colors.size(); ++i)
        ASSERT_EQ(a.colors[i], b.colors[i]) << i;
}

// The roots are the same bytes at one and two threads: each candidate and member root draws
// from its own stream, and the Lloyd centroids are summed in candidate order.
TEST(Generate, RootsAreTheSameAtOneAndTwoThreads) {
    Style style = small_style();
    style.wisps = 600;
    style.strands = 20000;
    Roots a, b;
    {
        const ThreadLimit one(1);
        a = grow_roots(style, builtin());
    }
    {
        const ThreadLimit two(2);
        b = grow_roots(style, builtin());
    }
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    EXPECT_EQ(a.lloyd_iterations, b.lloyd_iterations);
    EXPECT_TRUE(bytes(a.masters) == bytes(b.masters));
    EXPECT_TRUE(bytes(a.members) == bytes(b.members));
    EXPECT_EQ(a.wisp_offsets, b.wisp_offsets);
    EXPECT_EQ(a.wisp_radius, b.wisp_radius);
}

// synthesize_masters is its parts one after the other, byte for byte, and the details
// synthesized without their frames, then update_master, give the same masters (what the
// editor does beside the solve).
TEST(Generate, MasterPartsGiveSynthesizeMasters) {
    Style style = small_style();
    style.prototype.kind = PrototypeSpec::Kind::kCurly;
    const Roots roots = grow_roots(style, builtin());
    const Masters whole = synthesize_masters(style, builtin(), roots);
    Masters parts = master_outlines(style, builtin(), roots);
    const MasterPrototype prototype = master_prototype(style, parts);
    Masters later = parts;
    synthesize_master_details(style, prototype, parts);
    synthesize_master_details(style, prototype, later, /*update_frames=*/false);
    for (size_t w = 0; w < later.count(); ++w)
        update_master(later, w);
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    for (const Masters* m : {&parts, &later}) {
        EXPECT_TRUE(bytes(m->segment) == bytes(whole.segment));
        EXPECT_TRUE(bytes(m->direction) == bytes(whole.direction));
        EXPECT_TRUE(bytes(m->root_frame) == bytes(whole.root_frame));
        EXPECT_TRUE(bytes(m->outline) == bytes(whole.outline));
        EXPECT_TRUE(bytes(m->details) == bytes(whole.details));
        EXPECT_TRUE(bytes(m->frames) == bytes(whole.frames));
        EXPECT_TRUE(bytes(m->control) == bytes(whole.control));
    }
}

// The members grown in bands of master points (the editor's preview beside the solve), the
// masters' frames and control points also made band by band, are grow_members' hair to the
// bit, for the whole hair and for a subset, whatever the bands.
TEST(Generate, MembersGrownInBandsAreTheWholeGrowthToTheBit) {
    Style style = small_style();
    style.prototype.kind = PrototypeSpec::Kind::kCurly;
    style.wisp.length = {Distribution::Kind::kUniform, 0.f, 0.3f, 1.f};
    // With clumps: a member reads its guide's master as well as its own.
    style.clump.pull = 0.7f;
    style.clump.sub_pull = 0.5f;
    const Roots roots = grow_roots(style, builtin());
    const Masters masters = synthesize_masters(style, builtin(), roots);
    const int n = masters.points;
    Masters banded = masters;
    std::fill(banded.frames.begin(), banded.frames.end(), Frame{});
    std::fill(banded.control.begin(), banded.control.end(), Vec3f::Zero());
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    std::vector<uint32_t> some;
    for (uint32_t j = 0; j < roots.members.size(); j += 7)
        some.push_back(static_cast<uint32_t>(roots.members.size()) - 1 - j);
    for (const std::span<const uint32_t> only :
         {std::span<const uint32_t>(), std::span<const uint32_t>(some)}) {
        const Hair whole = grow_members(style, *builtin().scalp, masters, roots, {}, only);
        for (const int band : {1, 3, 5, n}) {
            MemberGrowth growth(style, *builtin().scalp, roots, n, {}, only);
            for (int k0 = 0; k0 < n; k0 += band) {
                const int k1 = std::min(n, k0 + band);
                for (size_t w = 0; w < banded.count(); ++w)
                    update_master(banded, w, k0, k1);
                growth.grow(banded, k0, k1);
            }
            EXPECT_TRUE(bytes(banded.frames) == bytes(masters.frames)) << band;
            EXPECT_TRUE(bytes(banded.control) == bytes(masters.control)) << band;
            const Hair& h = growth.hair();
            EXPECT_TRUE(bytes(h.points) == bytes(whole.points)) << band;
            EXPECT_TRUE(bytes(h.widths) == bytes(whole.widths)) << band;
            EXPECT_TRUE(h.offsets == whole.offsets) << band;
            EXPECT_TRUE(h.wisp == whole.wisp) << band;
            EXPECT_TRUE(bytes(h.root_uv) == bytes(whole.root_uv)) << band;
        }
    }
}

TEST(Generate, DifferentSeedsDiffer) {
    Style style = small_style();
    const Hair a = generate(style, builtin()).hair;
    style.seed = 18;
    const Hair b = generate(style, builtin()).hair;
    EXPECT_NE(a.points[5], b.points[5]);
}

TEST(Generate, LengthMapSetsMasterLength) {
    Style style = small_style();
    style.length = ScalarMap{ScalarMap::Kind::kConstant, 12.f};
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const Masters m = synthesize_masters(style, head, roots);
    for (size_t w = 0; w < m.count(); ++w)
        EXPECT_NEAR(m.segment[w] * (m.points - 1), 12.f, 1e-4f);
}

TEST(Generate, ProtrusionTurnsMastersOffTheSurface) {
    const Head& head = builtin();
    for (float protrusion : {0.f, 0.5f, 1.f}) {
        Style style = small_style();
        style.protrusion = ScalarMap{ScalarMap::Kind::kConstant, protrusion};
        const Roots roots = grow_roots(style, head);
        const Masters m = synthesize_masters(style, head, roots);
        for (size_t w = 0; w < m.count(); ++w) {
            const float angle =
                std::asin(std::clamp(m.direction[w].dot(m.roots[w].normal), -1.f, 1.f));
            EXPECT_NEAR(angle, protrusion * 0.5f * kPi, 1e-3f);
        }
    }
}

TEST(Generate, ShortPolylinePrototypeIsRejected) {
    Style style = small_style();
    style.prototype.kind = PrototypeSpec::Kind::kPolyline;
    style.prototype.polyline = {{0, 0, 0}, {0, 1, 0}, {0.2f, 2, 0}, {0, 3, 0}};
    EXPECT_THROW(generate(style, builtin()), Error);
}

TEST(Color, ConstantColorIsExact) {
    ColorSpec spec;
    spec.hue = Distribution{Distribution::Kind::kConstant, 30.f};
    spec.saturation = Distribution{Distribution::Kind::kConstant, 0.5f};
    spec.value = Distribution{Distribution::Kind::kConstant, 0.4f};
    std::vector<int32_t> wisp(100, 0);
    std::vector<Vec3f> out(100);
    color_strands(spec, 1, wisp, out);
    for (const Vec3f& c : out)
        EXPECT_EQ(c, out[0]);
    const Vec3f rgb = hsv_to_rgb({30.f, 0.5f, 0.4f});
    EXPECT_NEAR(out[0].x(), srgb_to_linear(rgb.x()), 1e-6f);
}

TEST(Color, WispVariationMakesWispsDistinct) {
    // Fig. 12d: the spread between wisps exceeds the spread within a wisp.
    ColorSpec spec;
    spec.value = Distribution{Distribution::Kind::kNormal, 0.f, 0.f, 1.f, 0.4f, 0.01f};
    spec.wisp_value = 0.1f;
    const int wisps = 50, per = 40;
    std::vector<int32_t> wisp(wisps * per);
    for (int i = 0; i < wisps * per; ++i)
        wisp[i] = i / per;
    std::vector<Vec3f> out(wisp.size());
    color_strands(spec, 3, wisp, out);
    double within = 0, between = 0;
    std::vector<double> means(wisps, 0);
    for (int i = 0; i < wisps * per; ++i)
        means[i / per] += out[i].sum() / per;
    double grand = 0;
    for (double m : means)
        grand += m / wisps;
    for (int i = 0; i < wisps * per; ++i)
        within += std::pow(out[i].sum() - means[i / per], 2);
    for (double m : means)
        between += std::pow(m - grand, 2);
    EXPECT_GT(between / wisps, 4 * within / (wisps * per));
}

TEST(Color, HsvPrimaries) {
    EXPECT_LT((hsv_to_rgb({0, 1, 1}) - Vec3f(1, 0, 0)).norm(), 1e-6f);
    EXPECT_LT((hsv_to_rgb({120, 1, 1}) - Vec3f(0, 1, 0)).norm(), 1e-6f);
    EXPECT_LT((hsv_to_rgb({240, 1, 0.5f}) - Vec3f(0, 0, 0.5f)).norm(), 1e-6f);
    EXPECT_LT((hsv_to_rgb({77, 0, 0.3f}) - Vec3f::Constant(0.3f)).norm(), 1e-6f);
}

}  // namespace wisp
