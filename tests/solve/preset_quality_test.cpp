// Every shipped preset reads as hair, on the built-in head and on the CC0 MakeHuman head with a
// hairline scalp: the face stays visible, the scalp is covered away from the parting, every
// constraint group completes, no point is inside the head or non-finite, none below the body,
// through an ear or hanging down the outside of the arms.
//
// How it is measured (solve/coverage.hpp): orthographic grids of 0.5 cm cells.
//  - face: the window from the eye line to the chin, 4.5 cm either side of the midline, seen
//    from the front; a cell is covered when the hair on or in front of the face makes it at
//    least half opaque (the strands' projected area, widths scaled to the full strand count).
//  - scalp: from the top, the back and each side, the cells whose nearest surface is scalp,
//    less those within 1.2 cm of the parting line; a cell is bare when the hair on or in
//    front of the scalp there leaves it more than half see-through.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "groom/style_toml.hpp"
#include "solve/constraint.hpp"
#include "solve/coverage.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

const char* const kMakeHuman =
    WISP_SHARED_DIR "/data/heads/makehuman/makehuman_hm08_head_neck_shoulders.obj";

struct Measured {
    float face = 0.f;
    float bare[4] = {};  // top, back, left, right
    size_t inside = 0, non_finite = 0;
    size_t below_body = 0;     // points more than 1 cm below the lowest point of the body
    size_t ear_piercings = 0;  // segments near an ear that pass through it
    float profile = 0.f;       // of the face's profile, seen from either side, the part hair hides
    // Of all strands, those that hang over the forehead, off the skin between the brows and
    // the front hairline (a fringe's do, by design).
    float over_forehead = 0.f;
    // Of all points, those hanging beside the upper arms: below the shoulders' top by more
    // than a third of the head's height, further out than 2.5 neck radii from the neck and
    // within a neck radius of the plane hair divides at (not in front of the arms, on the
    // chest, or behind them, on the back).
    float over_arms = 0.f;
    std::vector<SolveStats::Group> groups;
};

const char* const kViews[4] = {"top", "back", "left", "right"};

// A preset with a fifth of its strands and half its wisps, which keeps the tests
// quick; the wisps' shapes and the solver's work per wisp stay those of the preset.
// `widths` receives the factor that gives the fewer strands the same hair area.
Style reduced(const std::string& preset, float* widths = nullptr) {
    Style style = load_preset(preset);
    const int full = style.strands;
    style.strands = std::max(style.strands / 5, 1);
    style.wisps = std::max(std::min(style.wisps / 2, style.strands), 1);
    if (widths) *widths = float(full) / float(style.strands);
    return style;
}

Measured measure(const std::string& preset, const Head& head) {
    float widths = 1.f;
    const Style style = reduced(preset, &widths);
    const HairstyleResult r = generate_hairstyle(style, head);
    Measured m;
    m.inside = r.points_inside_head;
    const float bottom = head.mesh->bounds().lo.y() - 1.f;
    for (const Vec3f& p : r.hair.points) {
        m.non_finite += !p.allFinite();
        m.below_body += p.y() < bottom;
    }
    // Ears: hair goes behind or over them, never through them. Points are pushed out of the
    // head, but a segment between two of them could still cut through the thin ear: sample
    // each segment near an ear.
    if (head.landmarks) {
        const HeadField field = build_head_field(style, head);
        const Vec3f ears[2] = {head.landmarks->ear_left, head.landmarks->ear_right};
        const float reach = 0.2f * head.landmarks->height;
        for (size_t i = 0; i < r.hair.strand_count(); ++i) {
            const auto s = r.hair.strand(i);
            for (size_t k = 1; k < s.size(); ++k)
                for (const Vec3f& ear : ears) {
                    if ((s[k] - ear).norm() > reach && (s[k - 1] - ear).norm() > reach) continue;
                    bool through = false;
                    for (float t : {0.25f, 0.5f, 0.75f})
                        through |= field.sdf(s[k - 1] + t * (s[k] - s[k - 1])) < -0.1f;
                    m.ear_piercings += through;
                }
        }
    }
    if (head.landmarks && style.growth.front != GrowthSpec::Front::kFringe) {
        const FaceLandmarks face = face_landmarks(head);
        const HeadFrame frame = head_frame(*head.scalp);
        const HeadField field = build_head_field(style, head);
        const float brows = face.eye_y + 0.15f * (face.eye_y - face.chin_y);
        size_t over = 0;
        for (size_t i = 0; i < r.hair.strand_count(); ++i)
            for (const Vec3f& p : r.hair.strand(i))
                if (std::abs(p.x() - frame.center.x()) < 0.4f * frame.radius && p.y() > brows &&
                    p.y() < brows + 0.25f * frame.radius && p.z() > face.eye_z &&
                    field.sdf(p) > 0.5f) {
                    ++over;
                    break;
                }
        m.over_forehead = float(over) / float(std::max<size_t>(r.hair.strand_count(), 1));
    }
    const HeadFrame body = head_frame(head);
    if (std::isfinite(body.shoulder_top) && head.landmarks) {
        const Vec3f side = Vec3f::UnitY().cross(body.forward);
        const float level = body.shoulder_top - head.landmarks->height / 3.f;
        size_t beside = 0;
        for (const Vec3f& p : r.hair.points) {
            const Vec3f d = p - body.neck;
            beside += p.y() < level && std::abs(d.dot(side)) > 2.5f * body.neck_radius &&
                      std::abs(d.dot(body.forward) - body.split) < body.neck_radius;
        }
        m.over_arms = float(beside) / float(std::max<size_t>(r.hair.points.size(), 1));
    }
    const FaceLandmarks face = face_landmarks(head);
    for (const char* side : {"left", "right"})
        m.profile = std::max(m.profile, profile_coverage(r.hair, *head.mesh, side, face.eye_y,
                                                         face.chin_y, face.eye_z, 0.5f, widths)
                                            .fraction());
    m.face =
        face_coverage(r.hair, *head.mesh, face.eye_y, face.chin_y, 4.5f, 0.5f, widths).fraction();
    const HeadFrame frame = head_frame(*head.scalp);
    const auto parting = [&](const Vec3f& p) {
        return on_part(style.growth, (p - frame.center).normalized(), 1.2f / frame.radius);
    };
    for (int v = 0; v < 4; ++v) {
        const Coverage c = scalp_coverage(r.hair, *head.scalp, ortho_view(kViews[v]), parting,
                                          widths, &style.hairline);
        m.bare[v] = c.cells ? 1.f - c.fraction() : 0.f;
    }
    m.groups = r.solve.groups;
    return m;
}

// The MakeHuman bust is cut open below the shoulders; the head field closes the cut
// (close_holes), so "inside" is defined there too, and a body proxy goes on below it ([body]
// auto), which long hair lies on: no hair hangs past the end of the body.
void expect_reads_as_hair(const std::string& preset, const Head& head) {
    const Measured m = measure(preset, head);
    EXPECT_LT(m.face, 0.10f) << preset << " on " << head.source << ": face covered";
    // Off the forehead: a few strands may stray over it, not a lock (side-swept's sweep takes
    // the most, about 0.4%).
    EXPECT_LT(m.over_forehead, 0.01f) << preset << " on " << head.source << ": over the forehead";
    // Hair frames the face: seen from the side, the eyes, nose, lips and chin show.
    EXPECT_LT(m.profile, 0.3f) << preset << " on " << head.source << ": profile hidden";
    for (int v = 0; v < 4; ++v)
        EXPECT_LT(m.bare[v], 0.05f)
            << preset << " on " << head.source << ": bare scalp seen from the " << kViews[v];
    EXPECT_EQ(m.inside, 0u) << preset << " on " << head.source;
    EXPECT_EQ(m.below_body, 0u) << preset << " on " << head.source << ": hair below the body";
    EXPECT_EQ(m.ear_piercings, 0u) << preset << " on " << head.source << ": hair through an ear";
    EXPECT_LT(m.over_arms, 0.001f)
        << preset << " on " << head.source << ": hair hanging down the outside of the arms";
    EXPECT_EQ(m.non_finite, 0u) << preset << " on " << head.source;
    for (const SolveStats::Group& g : m.groups) {
        EXPECT_EQ(g.completed, g.constraints) << preset << ": group " << g.name;
        ASSERT_FALSE(g.met.empty()) << preset << ": group " << g.name;
        EXPECT_GE(g.met.back(), 0.95f)
            << preset << ": group " << g.name << " reaches its last constraint";
    }
}

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

const Head& makehuman() {
    static const Head head = [] {
        HeadSpec spec;
        spec.obj = kMakeHuman;
        spec.scale = 10.f;  // decimetres
        spec.scalp.kind = ScalpSpec::Kind::kHairline;
        return load_head(spec);
    }();
    return head;
}

std::string test_name(const testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

class OnTheBuiltInHead : public testing::TestWithParam<std::string> {};
TEST_P(OnTheBuiltInHead, ReadsAsHair) {
    expect_reads_as_hair(GetParam(), builtin());
}
INSTANTIATE_TEST_SUITE_P(Presets, OnTheBuiltInHead, testing::ValuesIn(preset_names()), test_name);

class OnTheMakeHumanHead : public testing::TestWithParam<std::string> {};
TEST_P(OnTheMakeHumanHead, ReadsAsHair) {
    expect_reads_as_hair(GetParam(), makehuman());
}
INSTANTIATE_TEST_SUITE_P(Presets, OnTheMakeHumanHead, testing::ValuesIn(preset_names()), test_name);

// The measures themselves: bare scalp and a veiled face are seen when they are there.
TEST(Coverage, SparseHairLeavesScalpBareAndNoHairCoversNothing) {
    Style style = load_preset("default");
    style.strands = 300;
    style.wisps = 100;
    const HairstyleResult r = generate_hairstyle(style, builtin());
    const Coverage top = scalp_coverage(r.hair, *builtin().scalp, ortho_view("top"));
    EXPECT_GT(top.cells, 500u);
    EXPECT_GT(1.f - top.fraction(), 0.15f);
    const Coverage none = scalp_coverage(Hair{}, *builtin().scalp, ortho_view("top"));
    EXPECT_EQ(none.covered, 0u);
    EXPECT_EQ(none.cells, top.cells);
}

TEST(Coverage, AVeilOverTheFaceCoversItsWindow) {
    const FaceLandmarks face = face_landmarks(builtin());
    EXPECT_GT(face.nose_tip.z(), 8.f);
    EXPECT_GT(face.eye_y, face.nose_tip.y());
    EXPECT_LT(face.chin_y, face.nose_tip.y());
    // Vertical strands 0.25 cm apart, 1 cm in front of the face: every cell covered.
    Hair veil;
    veil.default_width = 0.3f;  // ribbons, each hiding what is behind it
    for (float x = -6.f; x <= 6.f; x += 0.25f) {
        const std::vector<Vec3f> s = {{x, 8.f, 16.f}, {x, -14.f, 16.f}};
        veil.add_strand(s);
    }
    const Coverage c = face_coverage(veil, *builtin().mesh, face.eye_y, face.chin_y);
    EXPECT_GT(c.cells, 300u);
    EXPECT_EQ(c.covered, c.cells);
    // Behind the head it covers nothing.
    for (Vec3f& p : veil.points)
        p.z() = -20.f;
    EXPECT_EQ(face_coverage(veil, *builtin().mesh, face.eye_y, face.chin_y).covered, 0u);
}

TEST(Coverage, ASheetBesideTheFaceHidesItsProfile) {
    const FaceLandmarks face = face_landmarks(builtin());
    EXPECT_LT(face.eye_z, face.nose_tip.z());
    EXPECT_GT(face.eye_z, face.nose_tip.z() - 5.f);
    // Vertical ribbons in a plane beside the face on its left (+X), from the ear forward past
    // the nose: seen from the left, every cell of the profile is covered, from the right none.
    Hair sheet;
    sheet.default_width = 0.3f;
    for (float z = -2.f; z <= 16.f; z += 0.25f) {
        const std::vector<Vec3f> s = {{12.f, 8.f, z}, {12.f, -14.f, z}};
        sheet.add_strand(s);
    }
    const Mesh& mesh = *builtin().mesh;
    const Coverage left =
        profile_coverage(sheet, mesh, "left", face.eye_y, face.chin_y, face.eye_z);
    EXPECT_GT(left.cells, 40u);
    EXPECT_EQ(left.covered, left.cells);
    const Coverage right =
        profile_coverage(sheet, mesh, "right", face.eye_y, face.chin_y, face.eye_z);
    EXPECT_GT(right.cells, 40u);
    EXPECT_EQ(right.covered, 0u);
}

// A fringe is cut along a natural line, not a ruler: the bangs preset's fringe ends lower
// toward its corners than at the middle (a curve blending into the side hair), and its ends
// are uneven within a few millimetres (point-cut texture), on any head.
void expect_natural_fringe(const Head& head) {
    const Style style = reduced("bangs");
    const HairstyleResult r = generate_hairstyle(style, head);
    const FaceLandmarks face = face_landmarks(head);
    const HeadFrame frame = head_frame(*head.scalp);
    // Fringe ends: strand tips in front of the forehead, above the eyes.
    std::vector<float> middle, outer;
    for (size_t i = 0; i < r.hair.strand_count(); ++i) {
        const Vec3f tip = r.hair.strand(i).back() - frame.center;
        if (tip.z() < 0.5f * frame.radius || tip.y() + frame.center.y() < face.eye_y) continue;
        const float x = std::abs(tip.x()) / frame.radius;
        if (x < 0.12f)
            middle.push_back(tip.y());
        else if (x > 0.3f && x < 0.45f)
            outer.push_back(tip.y());
    }
    ASSERT_GT(middle.size(), 20u) << head.source;
    ASSERT_GT(outer.size(), 20u) << head.source;
    const auto median = [](std::vector<float> v) {
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        return v[v.size() / 2];
    };
    const auto spread = [&](const std::vector<float>& v) {  // interquartile range, cm
        std::vector<float> w = v;
        std::sort(w.begin(), w.end());
        return w[w.size() * 3 / 4] - w[w.size() / 4];
    };
    EXPECT_GT(median(middle) - median(outer), 0.02f * frame.radius)
        << head.source << ": the fringe's outer ends are no lower than its middle";
    EXPECT_GT(spread(middle), 0.1f) << head.source << ": the fringe's ends lie on one line";
    EXPECT_LT(spread(middle), 1.f) << head.source << ": the fringe's ends are ragged";
}

TEST(Fringe, CutOnAGentleCurveWithUnevenEnds) {
    expect_natural_fringe(builtin());
    expect_natural_fringe(makehuman());
}

// Combed back reads as combed back on any head: the sides go behind the ears with the rest (no
// section falls forward onto the chest), and the back falls as a curtain about as wide as the
// head, not gathered into a tail at the nape. Measured on the strands' tips: in front of the
// ears' plane, and their spread across the back against the distance between the ears.
void expect_combed_back(const Head& head) {
    const Style style = reduced("combed-back");
    const HairstyleResult r = generate_hairstyle(style, head);
    ASSERT_TRUE(head.landmarks);
    const Landmarks& l = *head.landmarks;
    const Vec3f side = Vec3f::UnitY().cross(l.forward);
    const Vec3f ears = 0.5f * (l.ear_left + l.ear_right);
    size_t in_front = 0;
    std::vector<float> across;
    for (size_t i = 0; i < r.hair.strand_count(); ++i) {
        const Vec3f tip = r.hair.strand(i).back() - ears;
        in_front += tip.dot(l.forward) > 0.f;
        across.push_back(tip.dot(side));
    }
    const size_t n = across.size();
    ASSERT_GT(n, 1000u);
    std::sort(across.begin(), across.end());
    EXPECT_LT(float(in_front) / float(n), 0.02f)
        << head.source << ": tips in front of the ears' plane";
    const float width = (l.ear_left - l.ear_right).norm();
    EXPECT_GT(across[n * 9 / 10] - across[n / 10], 0.65f * width)
        << head.source << ": the back is gathered into a tail";
}

// The fraction of an ear's outer face that hair lies on: of the skin faces within 0.13 head
// heights of the ear's outermost point, within 0.03 of its lateral extent (the part that stands
// off the head) and facing out, those with a hair point within 0.6 cm of their centre.
float ear_covered(const Hair& hair, const Head& head, const Vec3f& ear) {
    const Landmarks& l = *head.landmarks;
    const float reach = 0.13f * l.height, near = 0.6f;
    const Vec3f out = (ear - l.center).normalized();
    const float extent = (ear - l.center).dot(out) - 0.03f * l.height;
    std::vector<Vec3f> hair_near;
    for (const Vec3f& p : hair.points)
        if ((p - ear).norm() < reach + near) hair_near.push_back(p);
    const Mesh& mesh = *head.mesh;
    size_t skin = 0, covered = 0;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f x = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.f;
        if ((x - ear).norm() > reach || (x - l.center).dot(out) < extent ||
            mesh.face_normal(f).dot(out) < 0.3f)
            continue;
        ++skin;
        covered += std::any_of(hair_near.begin(), hair_near.end(),
                               [&](const Vec3f& p) { return (p - x).norm() < near; });
    }
    return skin ? float(covered) / float(skin) : 1.f;
}

// A crop is cut short around the ears: their outer faces stay mostly clear on any head (hair
// that hung over them from above lay on all of the built-in head's). Hair may still pass where
// the ear's front meets the head.
TEST(Ears, ACropLeavesThemClear) {
    for (const Head* head : {&builtin(), &makehuman()}) {
        const HairstyleResult r = generate_hairstyle(reduced("short"), *head);
        for (const Vec3f& ear : {head->landmarks->ear_left, head->landmarks->ear_right})
            EXPECT_LT(ear_covered(r.hair, *head, ear), 0.3f)
                << "short on " << head->source << ", the ear at " << ear.transpose();
    }
}

TEST(CombedBack, SidesGoBehindTheEarsAndTheBackFallsAsACurtain) {
    expect_combed_back(builtin());
    expect_combed_back(makehuman());
}

// A bob reads by its line: the hair ends together at the jaw, above the shoulders, on a line
// that falls toward the face, rather than layered down the back as long hair is, and its ends
// turn under toward the neck rather than standing off it as a shelf.
void expect_bob_line(const Head& head) {
    const Style style = reduced("wavy-bob");
    const HairstyleResult r = generate_hairstyle(style, head);
    const HeadFrame frame = head_frame(*head.scalp);
    const HeadFrame body = head_frame(head);
    const FaceLandmarks face = face_landmarks(head);
    const Vec3f normal = style.cut.normal.normalized();
    // Strands rooted behind the ears: where a bob is shortest and its line shows most.
    std::vector<float> past, back_tips, side_tips, gap;
    const HeadField field = build_head_field(style, head);
    float lowest = INFINITY;
    for (size_t i = 0; i < r.hair.strand_count(); ++i) {
        const auto s = r.hair.strand(i);
        for (const Vec3f& p : s)
            lowest = std::min(lowest, p.y());
        const Vec3f tip = (s.back() - frame.center) / frame.radius;
        const Vec3f root = (s.front() - frame.center) / frame.radius;
        past.push_back(frame.radius * (normal.dot(tip) - style.cut.offset));
        if (root.y() < 0.3f && root.z() < -0.5f) {
            back_tips.push_back(s.back().y());
            gap.push_back(field.sdf(s.back()));
        }
        if (root.y() < 0.3f && std::abs(root.x()) > 0.6f && root.z() > -0.2f)
            side_tips.push_back(s.back().y());
    }
    const auto quantile = [](std::vector<float> v, float q) {
        std::sort(v.begin(), v.end());
        return v[static_cast<size_t>(q * static_cast<float>(v.size() - 1))];
    };
    const std::string on = "on " + head.source;
    ASSERT_GT(back_tips.size(), 100u) << on;
    ASSERT_GT(side_tips.size(), 100u) << on;
    // Nothing hangs past the plane but the point-cut texture (up to 4/3 of it) and the bevel's
    // turn (half the bevel, horizontal); an end pushed off the skin after the cut may, a
    // little: hair is moved out of the head before it is cut, so no end inside the jaw is
    // pushed down its underside, under the cut line.
    const float allowed = style.cut.texture * 4.f / 3.f +
                          0.5f * style.cut.bevel * std::hypot(normal.x(), normal.z()) + 0.05f;
    EXPECT_LE(quantile(past, 0.99f), allowed) << on;
    EXPECT_LE(quantile(past, 1.f), allowed + 0.5f) << on;
    // Above the shoulders.
    if (std::isfinite(body.shoulder_top)) {
        EXPECT_GT(lowest, body.shoulder_top) << on;
    }
    // The back ends together: nine in ten of them within 4 cm of one another (the point-cut
    // texture takes up to about 1.3 cm), near the level of the chin.
    const float height = head.landmarks->height;
    const float b10 = quantile(back_tips, 0.1f), b90 = quantile(back_tips, 0.9f);
    EXPECT_LT(b90 - b10, 4.f) << on;
    EXPECT_GT(b10, face.chin_y - 0.1f * height) << on;
    EXPECT_LT(b90, face.chin_y + 0.25f * height) << on;
    // The ends turn under to rest on the neck (the bevel): most tips at the back lie within
    // half a centimetre of the skin, not a shelf standing off it.
    EXPECT_LT(quantile(gap, 0.5f), 0.5f) << on;
    // ... and the sides, nearer the face, end lower than the back.
    EXPECT_LT(quantile(side_tips, 0.5f), quantile(back_tips, 0.5f)) << on;
}

// Long hair seen from behind falls as a curtain about as wide as the head, not stepping in to
// the neck's width below the skull (a mullet's outline): between the nape and the shoulders'
// top, the hair behind the ears spans well over half of the head's width.
float curtain_width(const std::string& preset, const Head& head) {
    const HairstyleResult r = generate_hairstyle(reduced(preset), head);
    const HeadFrame body = head_frame(head);
    const HeadFrame frame = head_frame(*head.scalp);
    const float level = 0.5f * (body.shoulder_top + (frame.center.y() - frame.radius));
    std::vector<float> x;
    for (const Vec3f& p : r.hair.points)
        if (std::abs(p.y() - level) < 1.f &&
            (p - body.neck).dot(body.forward) < body.split - body.neck_radius)
            x.push_back(p.x());
    if (x.size() < 100) return 0.f;
    std::sort(x.begin(), x.end());
    const float width = x[x.size() * 97 / 100] - x[x.size() * 3 / 100];
    return width / (2.f * frame.radius);
}

TEST(LongHair, FallsBehindAsACurtainAboutAsWideAsTheHead) {
    for (const Head* head : {&builtin(), &makehuman()})
        for (const char* preset : {"default", "long-straight"}) {
            const float w = curtain_width(preset, *head);
            std::printf("%s on %s: curtain %.2f of the head's width\n", preset,
                        head->source.c_str(), w);
            EXPECT_GT(w, 0.6f) << preset << " on " << head->source;
        }
}

TEST(WavyBob, EndsOnALineAtTheJaw) {
    expect_bob_line(builtin());
    expect_bob_line(makehuman());
}

}  // namespace
}  // namespace wisp

namespace wisp {
namespace {

// Fig. 11b, 15d: the braid preset's three strands cross over one another down the braid, at
// least 6 times over its 20 cm, and the braid is tight and round in section.
TEST(Braid, ThreeStrandsCrossDownAPlait) {
    const Style style = reduced("braid");
    const HairstyleResult r = generate_hairstyle(style, builtin());
    const HeadFrame frame = head_frame(*builtin().scalp);
    // The preset's [[braid]]: start, axis and side in head units, about 2 head units long.
    const Vec3f start = frame.to_space(Vec3f(0.f, -0.45f, -1.15f));
    const Vec3f axis = Vec3f(0.f, -1.f, -0.12f).normalized();
    const Vec3f side = Vec3f::UnitX();
    const Vec3f depth = axis.cross(side);
    const float length = 2.0f * frame.radius;
    constexpr int kBins = 40;
    std::vector<std::vector<double>> sum(3, std::vector<double>(kBins, 0.0));
    std::vector<std::vector<int>> count(3, std::vector<int>(kBins, 0));
    float lo_side = INFINITY, hi_side = -INFINITY, lo_depth = INFINITY, hi_depth = -INFINITY;
    for (int g = 0; g < 3; ++g) {
        const GroupSpec& group = style.groups.at(g);
        ASSERT_EQ(group.name, "braid strand " + std::to_string(g));
        for (uint32_t w : select_wisps(group.selection, r.masters.roots, *builtin().scalp, frame))
            for (const Vec3f& p : r.masters.strand(w)) {
                const Vec3f d = p - start;
                const float t = d.dot(axis);
                const float across = d.dot(side), deep = d.dot(depth);
                if (t < 0.f || t >= length || std::hypot(across, deep) > 4.f) continue;
                const int bin = static_cast<int>(t / length * kBins);
                sum[g][bin] += across;
                ++count[g][bin];
                if (t > 0.15f * length && t < 0.85f * length) {
                    lo_side = std::min(lo_side, across), hi_side = std::max(hi_side, across);
                    lo_depth = std::min(lo_depth, deep), hi_depth = std::max(hi_depth, deep);
                }
            }
    }
    int crossings = 0;
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) {
            int last = 0;
            for (int k = 0; k < kBins; ++k) {
                if (!count[a][k] || !count[b][k]) continue;
                const double diff = sum[a][k] / count[a][k] - sum[b][k] / count[b][k];
                const int sign = diff > 0.1 ? 1 : diff < -0.1 ? -1 : 0;
                if (sign && last && sign != last) ++crossings;
                if (sign) last = sign;
            }
        }
    EXPECT_GE(crossings, 6);
    EXPECT_LT(hi_side - lo_side, 6.f);    // cm across
    EXPECT_LT(hi_depth - lo_depth, 5.f);  // cm deep: round, not a flat ribbon
    EXPECT_GT(hi_depth - lo_depth, 1.f);  // strands pass over and under
}

// Fig. 15c: the updo's hair past the tie is wound round the bun's centre into a compact
// mass, not hanging below it.
// The curl presets' strands coil at the preset's radius and pitch once grown, clumped and
// solved: members wound together around their wisp's helix, not a fuzz around it, and clumps
// that keep their coils rather than averaging them flat. Each strand is measured around its
// own axis, the moving average of its points over one nominal turn: the coil's radius is the
// points' median distance from it, its pitch the axis's length over the turns the points wind
// around it.
struct Coil {
    float radius = 0.f, pitch = 0.f;
};

float median(std::vector<float>& v) {
    if (v.empty()) return 0.f;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

Coil measure_coil(const HairstyleResult& r, float turn) {
    std::vector<float> radii, pitches, strand_radii;
    std::vector<Vec3f> once, axis;
    // The moving average over [k − h, k + h] of v's points from `from` to `to`.
    const auto average = [](std::span<const Vec3f> v, int h, size_t from, size_t to,
                            std::vector<Vec3f>& out) {
        out.assign(v.size(), Vec3f::Zero());
        for (size_t k = from; k < to; ++k) {
            Vec3f sum = Vec3f::Zero();
            for (int j = -h; j <= h; ++j)
                sum += v[k + j];
            out[k] = sum / static_cast<float>(2 * h + 1);
        }
    };
    for (size_t i = 0; i < r.hair.strand_count(); i += 7) {
        const auto s = r.hair.strand(i);
        const size_t w = static_cast<size_t>(r.hair.wisp[i]);
        const float segment = r.masters.segment[w];
        const int h = std::max(1, static_cast<int>(std::lround(0.5f * turn / segment)));
        const size_t margin = static_cast<size_t>(2 * h + 1);
        if (s.size() < 4 * margin) continue;
        // Averaged twice: a turn's average leaves a small wobble where the strand's own turn
        // is a little longer or shorter than the preset's, the second removes it.
        average(s, h, static_cast<size_t>(h), s.size() - h, once);
        average(once, h, margin - 1, s.size() - margin + 1, axis);
        float winding = 0.f, along = 0.f;
        Vec3f before = Vec3f::Zero();
        strand_radii.clear();
        for (size_t k = margin; k + margin < s.size(); ++k) {
            const Vec3f t = (axis[k + 1] - axis[k - 1]).normalized();
            Vec3f d = s[k] - axis[k];
            strand_radii.push_back(d.norm());
            d -= d.dot(t) * t;
            if (k > margin) {
                winding += std::atan2(before.cross(d).dot(t), before.dot(d));
                along += (axis[k] - axis[k - 1]).norm();
            }
            before = d;
        }
        const float turns = std::abs(winding) / (2.f * kPi);
        if (turns < 2.f) continue;
        radii.push_back(median(strand_radii));
        pitches.push_back(along / turns);
    }
    return Coil{median(radii), median(pitches)};
}

class CoilPreset : public testing::TestWithParam<std::string> {};
TEST_P(CoilPreset, StrandsCoilAtThePresetsRadiusAndPitch) {
    const Style style = reduced(GetParam());
    const HairstyleResult r = generate_hairstyle(style, builtin());
    // The kinky prototype coils at half its period (groom/prototype.hpp).
    const float pitch = style.prototype.kind == PrototypeSpec::Kind::kKinky
                            ? 0.5f * style.prototype.period
                            : style.prototype.period;
    const Coil coil = measure_coil(r, pitch);
    std::printf("%s: coil radius %.2f cm (preset %.2f), pitch %.2f cm (preset %.2f)\n",
                GetParam().c_str(), coil.radius, style.prototype.amplitude, coil.pitch, pitch);
    EXPECT_GT(coil.radius, 0.7f * style.prototype.amplitude);
    EXPECT_LT(coil.radius, 1.3f * style.prototype.amplitude);
    EXPECT_GT(coil.pitch, 0.8f * pitch);
    EXPECT_LT(coil.pitch, 1.2f * pitch);
}
INSTANTIATE_TEST_SUITE_P(Presets, CoilPreset, testing::Values("curly", "afro"), test_name);

TEST(Bun, HairIsWoundIntoACompactMass) {
    const Style style = reduced("updo");
    const HairstyleResult r = generate_hairstyle(style, builtin());
    const HeadFrame frame = head_frame(*builtin().scalp);
    const Vec3f centre = frame.to_space(Vec3f(0.f, 0.55f, -1.05f));  // the preset's [[updo]]
    const float bun_radius = 0.38f * frame.radius;
    size_t near = 0, total = 0;
    float lowest = INFINITY;
    for (size_t w = 0; w < r.masters.count(); ++w) {
        const auto s = r.masters.strand(w);
        // The part of the wisp after it first comes within the tie's tolerance.
        size_t k = 0;
        while (k < s.size() && (s[k] - centre).norm() > 0.18f * frame.radius + 1.f)
            ++k;
        for (; k < s.size(); ++k) {
            ++total;
            near += (s[k] - centre).norm() < 1.6f * bun_radius;
            lowest = std::min(lowest, s[k].y());
        }
    }
    ASSERT_GT(total, 1000u);
    EXPECT_GT(double(near) / double(total), 0.95);
    EXPECT_GT(lowest, centre.y() - 1.6f * bun_radius);
}

}  // namespace
}  // namespace wisp
