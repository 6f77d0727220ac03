// The grooming details beyond the wisps and clumps: tips that taper in width over their last
// centimetres, a hairline whose density ramps up from the scalp's edge with baby hairs in it,
// flyaways that leave their clump along short arcs, and waves that differ from wisp to wisp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <vector>

#include "core/rng.hpp"
#include "groom/generate.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace {

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

Style base_style() {
    Style s;
    s.wisps = 500;
    s.strands = 20000;
    s.points_per_strand = 24;
    s.seed = 11;
    s.length = ScalarMap{ScalarMap::Kind::kConstant, 30.f};
    s.wisp.length = Distribution{Distribution::Kind::kConstant, 1.f};
    s.clump.pull = 0.6f;
    s.clump.sub_pull = 0.4f;
    return s;
}

struct Grown {
    Roots roots;
    Masters masters;
    Hair hair;
};

Grown grow(const Style& style) {
    Grown g;
    g.roots = grow_roots(style, builtin());
    g.masters = synthesize_masters(style, builtin(), g.roots);
    g.hair = grow_members(style, *builtin().scalp, g.masters, g.roots);
    return g;
}

float arc_length(std::span<const Vec3f> s) {
    float l = 0.f;
    for (size_t k = 1; k < s.size(); ++k)
        l += (s[k] - s[k - 1]).norm();
    return l;
}

}  // namespace

TEST(Taper, StrandsKeepTheirRootWidthUntilTheLastCentimetresThenNarrowToTheTip) {
    Style style = base_style();
    style.taper = 4.f;
    style.hairline.baby = 0.f;
    const Grown g = grow(style);
    const float segment = 30.f / static_cast<float>(style.points_per_strand - 1);
    size_t full = 0, narrowing = 0;
    for (size_t i = 0; i < g.hair.strand_count(); ++i) {
        const uint32_t o = g.hair.offsets[i], count = g.hair.offsets[i + 1] - o;
        ASSERT_EQ(count, static_cast<uint32_t>(style.points_per_strand));
        EXPECT_FLOAT_EQ(g.hair.widths[o + count - 1], style.tip_width);
        for (uint32_t k = 0; k + 1 < count; ++k) {
            const float w = g.hair.widths[o + k];
            EXPECT_GE(w, g.hair.widths[o + k + 1]) << "strand " << i << " widens at " << k;
            const float to_tip = static_cast<float>(count - 1 - k) * segment;
            if (to_tip >= style.taper + 1e-3f) {
                EXPECT_FLOAT_EQ(w, style.root_width);
                ++full;
            } else {
                EXPECT_LT(w, style.root_width);
                EXPECT_NEAR(
                    w,
                    style.tip_width + (style.root_width - style.tip_width) * to_tip / style.taper,
                    1e-6f);
                ++narrowing;
            }
        }
    }
    EXPECT_GT(full, 5 * narrowing) << "most of a 30 cm strand keeps its width";
    EXPECT_GT(narrowing, 0u);

    style.taper = 0.f;
    const Grown blunt = grow(style);
    for (const float w : blunt.hair.widths)
        ASSERT_EQ(w, style.root_width) << "taper 0 is a blunt cut, one width all along";
}

// Roots per area, in bands of distance from the scalp's edge, relative to their density far
// from it: the ramp's smoothstep, not a hard edge.
TEST(Hairline, RootDensityRampsUpOverTheWidthFromTheScalpsEdge) {
    const Scalp& scalp = *builtin().scalp;
    // Away from the temples (the ramp's own width) or at them (2.5 times as wide).
    enum Where { kForehead, kTemples };
    const auto in = [&](const Vec3f& p, Where where) {
        const float ramp = hairline_ramp(scalp, p, 1.f);
        return where == kForehead ? ramp < 1.001f : ramp > 2.2f;
    };
    const auto band_density = [&](float width, Where where) {
        Style style = base_style();
        style.wisps = 2000;
        style.strands = 200000;
        style.hairline.width = width;
        style.hairline.irregularity = 0.f;  // the ramp alone, from the edge itself
        const Roots roots = grow_roots(style, builtin());
        // Area in each band, from an area-uniform sample of the scalp, against the density
        // far from the edge, anywhere.
        const float edges[] = {0.f, 0.2f, 0.4f, 0.6f, 1.2f, 3.f, 1e9f};
        constexpr size_t kBands = 6;
        std::vector<double> area(kBands, 0.0), count(kBands, 0.0);
        const auto band = [&](float e) {
            size_t b = 0;
            while (b + 1 < kBands && e >= edges[b + 1])
                ++b;
            return b;
        };
        Rng rng(3);
        for (int k = 0; k < 800000; ++k) {
            const SurfacePoint p = scalp.sample(rng);
            const size_t b = band(scalp.edge_distance(p));
            if (b + 1 == kBands || in(p.position, where)) area[b] += 1.0;
        }
        for (const SurfacePoint& p : roots.members) {
            const size_t b = band(scalp.edge_distance(p));
            if (b + 1 == kBands || in(p.position, where)) count[b] += 1.0;
        }
        std::vector<double> density(kBands);
        for (size_t b = 0; b < kBands; ++b)
            density[b] = area[b] > 0.0 ? count[b] / area[b] : 0.0;
        const double far = density[kBands - 1];
        for (double& d : density)
            d /= far;
        return density;
    };
    const std::vector<double> soft = band_density(0.6f, kForehead);
    // smoothstep(0, 0.6, e) averaged over [0, 0.2], [0.2, 0.4], [0.4, 0.6]: 0.07, 0.5, 0.93.
    EXPECT_LT(soft[0], 0.2) << "roots thin out at the edge";
    EXPECT_NEAR(soft[1], 0.5, 0.15);
    EXPECT_GT(soft[2], 0.75);
    EXPECT_NEAR(soft[3], 1.0, 0.12) << "full density past the ramp";
    EXPECT_NEAR(soft[4], 1.0, 0.12);
    // At the temples the ramp runs to 1.5 cm: smoothstep(0, 1.5, e) averaged over [0.4, 0.6]
    // and [0.6, 1.2] is 0.26 and 0.6.
    const std::vector<double> temples = band_density(0.6f, kTemples);
    EXPECT_LT(temples[2], 0.45) << "the temples recede";
    EXPECT_NEAR(temples[3], 0.6, 0.2);
    EXPECT_NEAR(temples[4], 1.0, 0.15);
    const std::vector<double> hard = band_density(0.f, kForehead);
    EXPECT_GT(hard[0], 0.85) << "width 0 is a hard edge";
}

// A hairline is not a drawn line: with `irregularity`, where it starts wanders in from the
// scalp's edge along it, and furthest at the temples. Measured with a hard edge (width 0), by
// the nearest root to the edge in each 6° sector round the head's vertical axis.
TEST(Hairline, TheLineWandersInFromTheScalpsEdgeMostAtTheTemples) {
    const Scalp& scalp = *builtin().scalp;
    const Vec3f c = scalp.center();
    constexpr float kSector = 6.f * kPi / 180.f;
    struct Line {
        std::vector<float> depth;             // per sector with roots near the edge
        float forehead = 0.f, temples = 0.f;  // mean depth there
        float outside = 0.f;                  // the furthest a root lies outside the line
    };
    const auto line = [&](float irregularity) {
        Style style = base_style();
        style.wisps = 2000;
        style.strands = 200000;
        style.hairline.width = 0.f;
        style.hairline.irregularity = irregularity;
        const Roots roots = grow_roots(style, builtin());
        std::map<int, float> nearest;
        std::map<int, Vec3f> where;
        Line l;
        for (const SurfacePoint& p : roots.members) {
            l.outside = std::max(l.outside, -hairline_edge(scalp, p, irregularity));
            const float e = scalp.edge_distance(p);
            if (e > 3.f) continue;
            const Vec3f d = p.position - c;
            // The front hairline and the temples: above the centre, within 60° of the front.
            const float around = std::atan2(d.x(), d.z());
            if (d.y() < 0.f || std::abs(around) > 60.f * kPi / 180.f) continue;
            const int sector = static_cast<int>(std::floor(around / kSector));
            auto [it, fresh] = nearest.try_emplace(sector, e);
            if (fresh || e < it->second) {
                it->second = e;
                where[sector] = d.normalized();
            }
        }
        std::vector<float> forehead, temples;
        for (const auto& [sector, e] : nearest) {
            l.depth.push_back(e);
            const Vec3f& r = where[sector];
            if (std::abs(r.x()) < 0.3f && r.z() > 0.5f) forehead.push_back(e);
            if (std::abs(r.x()) > 0.65f && r.z() > -0.2f) temples.push_back(e);
        }
        const auto mean = [](const std::vector<float>& v) {
            float s = 0.f;
            for (float x : v)
                s += x;
            return v.empty() ? 0.f : s / static_cast<float>(v.size());
        };
        l.forehead = mean(forehead);
        l.temples = mean(temples);
        return l;
    };
    const auto spread = [](const std::vector<float>& v) {
        return *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end());
    };
    const Line drawn = line(0.f), wandering = line(0.6f);
    ASSERT_GT(drawn.depth.size(), 15u);
    EXPECT_LT(spread(drawn.depth), 0.2f) << "irregularity 0: the roots start at the edge";
    EXPECT_GT(spread(wandering.depth), 0.4f) << "the line wanders";
    EXPECT_LE(spread(wandering.depth), 1.5f * 0.6f + 0.2f) << "by no more than 1.5 × it";
    EXPECT_LT(wandering.outside, 0.01f) << "no root outside the line";
    EXPECT_GT(wandering.temples, wandering.forehead + 0.1f) << "the temples recede";
}

TEST(Hairline, BabyHairsAreShortAndOnlyAtTheEdge) {
    Style style = base_style();
    style.flyaway.fraction = 0.f;
    style.hairline.width = 0.8f;
    style.hairline.baby = 0.5f;
    style.hairline.baby_length = 2.f;
    style.hairline.irregularity = 0.f;  // measured from the edge itself
    const Grown g = grow(style);
    const Scalp& scalp = *builtin().scalp;
    size_t near = 0, near_short = 0;
    for (size_t i = 0; i < g.hair.strand_count(); ++i) {
        const float edge = scalp.edge_distance(g.roots.members[i]);
        const float length = arc_length(g.hair.strand(i));
        const bool baby = length < 5.f;  // the others are 30 cm
        if (edge >= style.hairline.width) {
            EXPECT_FALSE(baby) << "strand " << i << " is " << length << " cm, " << edge
                               << " cm from the edge";
            continue;
        }
        ++near;
        if (!baby) continue;
        ++near_short;
        EXPECT_LE(length, 1.6f * style.hairline.baby_length) << "bent a little, not longer";
        EXPECT_GE(length, 0.3f * style.hairline.baby_length);
    }
    ASSERT_GT(near, 200u);
    // baby·(1 − e/width) over the ramp, whose roots sit mostly toward its inner side.
    const double fraction = static_cast<double>(near_short) / static_cast<double>(near);
    EXPECT_GT(fraction, 0.08);
    EXPECT_LT(fraction, 0.3);
}

// Flyaways are the strands that change when the fraction is raised; each leaves its place
// over no more than its last `length` cm, by no more than `lift`, and the rest of the hair
// stays as it was.
TEST(Flyaway, AFractionOfStrandsLeaveTheirClumpsAlongShortArcsNearTheTips) {
    Style style = base_style();
    style.hairline.baby = 0.f;
    style.flyaway.fraction = 0.f;
    const Grown before = grow(style);
    style.flyaway.fraction = 0.03f;
    style.flyaway.length = 5.f;
    style.flyaway.lift = 1.5f;
    const Grown after = grow(style);
    ASSERT_EQ(before.hair.points.size(), after.hair.points.size());
    const float segment = 30.f / static_cast<float>(style.points_per_strand - 1);
    size_t changed = 0;
    double lifted = 0.0;
    for (size_t i = 0; i < after.hair.strand_count(); ++i) {
        const auto a = before.hair.strand(i), b = after.hair.strand(i);
        size_t first = a.size();
        float most = 0.f;
        for (size_t k = 0; k < a.size(); ++k) {
            const float d = (a[k] - b[k]).norm();
            if (d > 0.f && first == a.size()) first = k;
            most = std::max(most, d);
        }
        if (first == a.size()) continue;
        ++changed;
        const float from_tip = static_cast<float>(a.size() - 1 - first) * segment;
        EXPECT_LE(from_tip, style.flyaway.length + segment) << "strand " << i;
        // The lift, and the clump it lets go of (its pull is at most 0.6 + 0.4 of the way).
        EXPECT_LE(most, style.flyaway.lift + 6.f) << "strand " << i;
        lifted += (a.back() - b.back()).norm();
    }
    const double n = static_cast<double>(after.hair.strand_count());
    const double expected = 0.03 * n, sd = std::sqrt(n * 0.03 * 0.97);
    EXPECT_NEAR(static_cast<double>(changed), expected, 4 * sd);
    EXPECT_GT(lifted / static_cast<double>(changed), 0.5 * style.flyaway.lift)
        << "flyaway tips leave their place";
}

// Each master's waves have their own amplitude (with the variation) and phase (always): the
// detail offsets along the master's main detail axis, fitted with the prototype's period.
TEST(Waves, EachWispWavesWithItsOwnPhaseAndAmplitude) {
    Style style = base_style();
    style.prototype.kind = PrototypeSpec::Kind::kWavy;
    style.prototype.period = 4.f;
    style.prototype.amplitude = 0.8f;
    style.points_per_strand = 61;  // 0.5 cm segments: 8 a period
    const auto measure = [&](float variation, double& spread, double& resultant) {
        style.prototype.amplitude_variation = variation;
        const Roots roots = grow_roots(style, builtin());
        const Masters m = synthesize_masters(style, builtin(), roots);
        const size_t n = static_cast<size_t>(m.points);
        std::vector<double> amplitude;
        std::complex<double> sum(0.0, 0.0);
        for (size_t w = 0; w < m.count(); ++w) {
            const Vec3f* d = m.details.data() + w * n;
            // Details lie in the wave's plane: its axis is the largest of (n, b).
            double nn = 0, bb = 0, nb = 0;
            for (size_t k = 0; k < n; ++k)
                nn += d[k].y() * d[k].y(), bb += d[k].z() * d[k].z(), nb += d[k].y() * d[k].z();
            const double angle = 0.5 * std::atan2(2 * nb, nn - bb);
            std::complex<double> fit(0.0, 0.0);
            double rms = 0.0;
            for (size_t k = 0; k < n; ++k) {
                const double x = std::cos(angle) * d[k].y() + std::sin(angle) * d[k].z();
                const double s = static_cast<double>(k) * m.segment[w];
                fit += x * std::polar(1.0, 2.0 * 3.14159265 * s / style.prototype.period);
                rms += x * x;
            }
            amplitude.push_back(std::sqrt(rms / static_cast<double>(n)));
            // The axis's sign is arbitrary: the doubled phase is not.
            sum += std::polar(1.0, 2.0 * std::arg(fit));
        }
        std::sort(amplitude.begin(), amplitude.end());
        spread = amplitude[amplitude.size() * 9 / 10] / amplitude[amplitude.size() / 10];
        resultant = std::abs(sum) / static_cast<double>(m.count());
    };
    double even_spread = 0, even_phase = 0, varied_spread = 0, varied_phase = 0;
    measure(0.f, even_spread, even_phase);
    measure(0.5f, varied_spread, varied_phase);
    EXPECT_LT(even_phase, 0.15) << "phases spread around the circle, not in step";
    EXPECT_LT(varied_phase, 0.15);
    EXPECT_GT(varied_spread, even_spread + 0.5) << "amplitudes differ from wisp to wisp";
    EXPECT_GT(varied_spread, 1.8);
}

namespace {

// Each master's wave phase (radians, from the fit at the prototype's period along its main
// detail axis, the normal with no roll) and the RMS of its details before and after `split` cm.
struct WavePhases {
    std::vector<double> phase, before, after;
};
WavePhases wave_phases(const Style& style, const Masters& m, float split) {
    WavePhases r;
    const size_t n = static_cast<size_t>(m.points);
    for (size_t w = 0; w < m.count(); ++w) {
        const Vec3f* d = m.details.data() + w * n;
        std::complex<double> fit(0.0, 0.0);
        double b = 0, a = 0;
        int nb = 0, na = 0;
        for (size_t k = 0; k < n; ++k) {
            const double s = static_cast<double>(k) * m.segment[w];
            fit += static_cast<double>(d[k].y()) *
                   std::polar(1.0, 2.0 * 3.14159265 * s / style.prototype.period);
            const double sq = d[k].squaredNorm();
            if (s < split)
                b += sq, ++nb;
            else
                a += sq, ++na;
        }
        r.phase.push_back(std::arg(fit));
        r.before.push_back(nb ? std::sqrt(b / nb) : 0.0);
        r.after.push_back(na ? std::sqrt(a / na) : 0.0);
    }
    return r;
}

Style wave_style() {
    Style style;
    style.wisps = 800;
    style.strands = 4000;
    style.points_per_strand = 61;  // 0.5 cm segments: 8 a period
    style.seed = 5;
    style.length = ScalarMap{ScalarMap::Kind::kConstant, 30.f};
    style.prototype.kind = PrototypeSpec::Kind::kWavy;
    style.prototype.period = 4.f;
    style.prototype.amplitude = 0.8f;
    style.prototype.window = 6;
    style.prototype.roll = 0.f;
    return style;
}

// How alike the phases of neighbouring masters are: the mean cosine of their difference over
// pairs whose roots lie within 1.5 cm of each other at nearly one height (the coherent phase
// also follows the root's height, so crests meet at one height once the hair falls).
double neighbour_agreement(const Masters& m, const WavePhases& p) {
    double sum = 0.0;
    int pairs = 0;
    for (size_t a = 0; a < m.count(); ++a)
        for (size_t b = a + 1; b < m.count(); ++b) {
            const Vec3f d = m.roots[a].position - m.roots[b].position;
            if (d.norm() < 1.5f && std::abs(d.y()) < 0.25f) {
                sum += std::cos(p.phase[a] - p.phase[b]);
                ++pairs;
            }
        }
    EXPECT_GT(pairs, 50);
    return pairs ? sum / pairs : 0.0;
}

}  // namespace

// With coherence, neighbouring locks wave in step (their phases agree), while the paper's own
// synthesis gives each its own; over the head the phases still spread around the circle.
TEST(Waves, CoherentLocksWaveInStepWithTheirNeighbours) {
    Style style = wave_style();
    const Roots roots = grow_roots(style, builtin());
    const Masters own = synthesize_masters(style, builtin(), roots);
    const double apart = neighbour_agreement(own, wave_phases(style, own, 0.f));
    style.prototype.coherence = 1.f;
    style.prototype.coherence_size = 8.f;
    const Masters shared = synthesize_masters(style, builtin(), roots);
    const WavePhases p = wave_phases(style, shared, 0.f);
    const double together = neighbour_agreement(shared, p);
    EXPECT_LT(apart, 0.3) << "without coherence, neighbours keep their own phases";
    EXPECT_GT(together, 0.7) << "with coherence, neighbours wave in step";
    std::complex<double> sum(0.0, 0.0);
    for (const double a : p.phase)
        sum += std::polar(1.0, a);
    EXPECT_LT(std::abs(sum) / static_cast<double>(p.phase.size()), 0.5)
        << "not one phase over the whole head";
}

// The onset ramps the waves in from the root: smooth at the scalp, full further down.
TEST(Waves, OnsetGrowsTheWavesFromTheRoot) {
    Style style = wave_style();
    style.prototype.onset = 8.f;
    const Roots roots = grow_roots(style, builtin());
    const Masters m = synthesize_masters(style, builtin(), roots);
    const WavePhases p = wave_phases(style, m, 3.f);
    double before = 0, after = 0;
    for (size_t w = 0; w < p.before.size(); ++w)
        before += p.before[w], after += p.after[w];
    EXPECT_LT(before, 0.25 * after) << "the first 3 cm of an 8 cm onset hardly wave";
    style.prototype.onset = 0.f;
    const Masters full = synthesize_masters(style, builtin(), roots);
    const WavePhases q = wave_phases(style, full, 3.f);
    double full_before = 0;
    for (const double b : q.before)
        full_before += b;
    EXPECT_GT(full_before, 3.0 * before) << "without an onset the waves start at the root";
}

}  // namespace wisp
