#include "solve/solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include <tbb/task_group.h>

#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "geometry/builtin_head.hpp"
#include "geometry/mesh_distance.hpp"
#include "groom/generate.hpp"
#include "groom/maps.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

Style small_style() {
    Style s;
    s.wisps = 200;
    s.strands = 4000;
    s.points_per_strand = 24;
    s.length = ScalarMap{ScalarMap::Kind::kConstant, 30.f};
    s.seed = 3;
    s.solve.field = {FieldTerm{}};  // gravity alone, as in Fig. 9
    return s;
}

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

const HeadField& builtin_field() {
    static const HeadField field(*builtin().mesh, head_field_cell(SolveSpec{}));
    return field;
}

// The hair's volume around the head: the mean horizontal distance of master joints above
// the chin from the head's vertical axis.
double hair_radius(const Masters& m) {
    const HeadFrame f = head_frame(*builtin().scalp);
    double sum = 0;
    size_t count = 0;
    for (const Vec3f& p : m.outline) {
        if (p.y() < f.center.y() - f.radius) continue;
        sum += std::hypot(p.x() - f.center.x(), p.z() - f.center.z());
        ++count;
    }
    return sum / std::max<size_t>(count, 1);
}

// How far the masters `keep` takes (by their root) rise off the skin within their first
// `reach` cm, on the mean, and how many it took: how much they are lifted.
struct Rise {
    double mean;
    size_t count;
};
template <class Keep>
Rise mean_rise(const Masters& m, float reach, Keep keep) {
    const HeadField& field = builtin_field();
    const size_t n = static_cast<size_t>(m.points);
    double sum = 0;
    size_t count = 0;
    for (size_t w = 0; w < m.count(); ++w) {
        if (!keep(m.roots[w])) continue;
        float most = 0.f;
        for (size_t k = 0; k < n && static_cast<float>(k) * m.segment[w] <= reach; ++k)
            most = std::max(most, field.sdf(m.outline[w * n + k]));
        sum += most;
        ++count;
    }
    return {sum / static_cast<double>(std::max<size_t>(count, 1)), count};
}

}  // namespace

TEST(Solver, BestDirectionMaximizesEquationFive) {
    Rng rng(1);
    for (int t = 0; t < 200; ++t) {
        const Vec3f phi = rng.unit_vector() * rng.uniform(0.f, 3.f);
        const Vec3f q0 = rng.unit_vector();
        const float kappa = rng.uniform(0.f, 4.f);
        const Vec3f best = best_direction(phi, q0, kappa);
        EXPECT_NEAR(best.norm(), 1.f, 1e-5f);
        const float e_best = phi.dot(best) + kappa * q0.dot(best);
        for (int k = 0; k < 100; ++k) {
            const Vec3f q = rng.unit_vector();
            EXPECT_LE(phi.dot(q) + kappa * q0.dot(q), e_best + 1e-5f);
        }
    }
}

TEST(Solver, StifferHairBendsLess) {
    // Fig. 9a/b: κ = 2.5 bends the hair less than κ = 0.5: it keeps more of the direction it
    // leaves the scalp with, so it stands further off the head before it falls. (Summed joint
    // angles no longer tell them apart: hair lying on the skin slides along it, bending as the
    // head and the body curve whatever its stiffness.)
    Style soft = small_style(), stiff = small_style();
    soft.solve.stiffness = 0.5f;
    stiff.solve.stiffness = 2.5f;
    const Masters m_soft = generate_hairstyle(soft, builtin(), &builtin_field()).masters;
    const Masters m_stiff = generate_hairstyle(stiff, builtin(), &builtin_field()).masters;
    std::printf("hair radius: soft %.2f cm, stiff %.2f cm\n", hair_radius(m_soft),
                hair_radius(m_stiff));
    EXPECT_GT(hair_radius(m_stiff), 1.03 * hair_radius(m_soft));  // measured: 6% further
}

TEST(Solver, RootLiftRaisesTheHairOffTheScalpAtItsRootsOnly) {
    // maps.lift: on top of the head (crown-part high), each master rises about `lift` off the
    // scalp before it falls; low on the sides, where the map is 0, it lies as without.
    const HeadField& field = builtin_field();
    const auto rise = [&](const Style& style, bool top) {
        const Masters m = generate_hairstyle(style, builtin(), &field).masters;
        return mean_rise(m, 5.f,
                         [&](const SurfacePoint& root) {
                             const float up = root.normal.y();
                             return top ? up >= 0.9f : std::abs(up) <= 0.3f;
                         })
            .mean;
    };
    Style flat = small_style(), lifted = small_style();
    lifted.lift.kind = ScalarMap::Kind::kProcedural;
    lifted.lift.procedural = "crown-part";
    lifted.lift.low = 0.f;
    lifted.lift.high = 2.f;
    const double top_flat = rise(flat, true), top_lifted = rise(lifted, true);
    std::printf("rise in the first 5 cm on top: %.2f cm flat, %.2f cm lifted\n", top_flat,
                top_lifted);
    EXPECT_GT(top_lifted, top_flat + 0.8);
    EXPECT_LT(top_lifted, top_flat + 3.0) << "about the lift, not a spike";
    EXPECT_NEAR(rise(lifted, false), rise(flat, false), 0.5) << "the sides, barely lifted";
    // It bends over in an arc, not at a knee: the sharpest turn between two segments of a
    // lifted master on top, over its first 8 cm, is no sharper than a flat one's.
    const auto knee = [&](const Style& style) {
        const Masters m = generate_hairstyle(style, builtin(), &field).masters;
        const size_t n = static_cast<size_t>(m.points);
        double sum = 0;
        size_t count = 0;
        for (size_t w = 0; w < m.count(); ++w) {
            if (m.roots[w].normal.y() < 0.9f) continue;
            float sharpest = 0.f;
            for (size_t k = 1; k + 1 < n && static_cast<float>(k) * m.segment[w] <= 8.f; ++k) {
                const Vec3f a = m.outline[w * n + k] - m.outline[w * n + k - 1];
                const Vec3f b = m.outline[w * n + k + 1] - m.outline[w * n + k];
                sharpest = std::max(
                    sharpest, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.f, 1.f)));
            }
            sum += sharpest;
            ++count;
        }
        return sum / static_cast<double>(std::max<size_t>(count, 1));
    };
    const double knee_flat = knee(flat), knee_lifted = knee(lifted);
    std::printf("sharpest turn in the first 8 cm on top: %.1f° flat, %.1f° lifted\n",
                knee_flat * 180 / M_PI, knee_lifted * 180 / M_PI);
    EXPECT_LT(knee_lifted, 1.2 * knee_flat);
}

TEST(Solver, RootsAtTheHairlineLieLowUnderALift) {
    // [hairline] lie holds the lift as it holds the protrusion: a root at the edge of the
    // scalp, which frames the face, is not stood up by the lift map, or the hair it holds arcs
    // over the hairline as a loop; a root a few centimetres in is lifted in full.
    const Scalp& scalp = *builtin().scalp;
    const auto rise = [&](const Style& style, bool edge) {
        const Masters m = generate_hairstyle(style, builtin(), &builtin_field()).masters;
        const Rise r = mean_rise(m, 4.f, [&](const SurfacePoint& root) {
            // From the hairline, which wanders in from the scalp's edge.
            const float d = hairline_edge(scalp, root, style.hairline.irregularity);
            return edge ? d <= 0.4f : d >= 4.f;
        });
        EXPECT_GT(r.count, 10u);
        return r.mean;
    };
    Style flat = small_style();
    flat.wisps = 1500;  // enough masters within 0.4 cm of the edge
    flat.length = ScalarMap{ScalarMap::Kind::kConstant, 10.f};
    flat.hairline.lie = 1.f;
    flat.hairline.irregularity = 0.f;  // the line at the edge: masters close to it to measure
    Style lying = flat;
    lying.lift = ScalarMap{ScalarMap::Kind::kConstant, 2.f};
    Style standing = lying;
    standing.hairline.lie = 0.f;
    const double edge_flat = rise(flat, true), edge_lying = rise(lying, true),
                 edge_standing = rise(standing, true);
    std::printf("rise at the hairline: %.2f cm flat, %.2f cm lifted (lie 1), %.2f cm (lie 0)\n",
                edge_flat, edge_lying, edge_standing);
    EXPECT_GT(edge_standing, edge_flat + 0.5) << "a lift stands the edge up without lie";
    EXPECT_LT(edge_lying, edge_flat + 0.5 * (edge_standing - edge_flat));
    EXPECT_GT(rise(lying, false), rise(flat, false) + 0.5) << "in from the edge, lifted in full";
}

TEST(Solver, WrapDrawsHairCombedOverTheHeadOntoIt) {
    // solve.wrap, a shrinkwrap: stiff 6 cm hair combed down the sides leaves the head in a
    // straight line below its widest point; drawn onto the skin, its ends lie near it. It
    // never goes into the skin for that.
    const HeadField& field = builtin_field();
    Style loose = small_style();
    loose.length = ScalarMap{ScalarMap::Kind::kConstant, 6.f};
    loose.solve.stiffness = 2.f;
    loose.solve.field = {FieldTerm{}, FieldTerm{FieldTerm::Kind::kGrowth, 2.f}};
    Style wrapped = loose;
    wrapped.solve.wrap = 1.5f;
    const auto gaps = [&](const Style& style, float& deepest) {
        const Masters m = generate_hairstyle(style, builtin(), &field).masters;
        const size_t n = static_cast<size_t>(m.points);
        double sum = 0;
        size_t count = 0;
        deepest = INFINITY;
        for (size_t w = 0; w < m.count(); ++w) {
            const float up = m.roots[w].normal.y();
            if (up < 0.f || up > 0.7f) continue;  // the upper sides and back, not the top
            sum += field.sdf(m.outline[w * n + n - 1]);
            ++count;
            for (size_t k = 0; k < n; ++k)
                deepest = std::min(deepest, field.sdf(m.outline[w * n + k]));
        }
        EXPECT_GT(count, 20u);
        return sum / static_cast<double>(std::max<size_t>(count, 1));
    };
    float loose_deepest, wrapped_deepest;
    const double loose_gap = gaps(loose, loose_deepest),
                 wrapped_gap = gaps(wrapped, wrapped_deepest);
    std::printf("ends off the skin: %.2f cm loose, %.2f cm wrapped (deepest point %.2f cm)\n",
                loose_gap, wrapped_gap, wrapped_deepest);
    EXPECT_LT(wrapped_gap, 0.6 * loose_gap);
    EXPECT_GT(wrapped_deepest, std::min(loose_deepest, 0.f) - 0.05f);
}

TEST(Solver, LowerThresholdGivesMoreVolume) {
    // Fig. 9a/c: τ = 0.1 makes the hair occupy a larger volume than τ = 0.9.
    Style flat = small_style(), full = small_style();
    flat.wisps = full.wisps = 2000;
    flat.strands = full.strands = 100000;  // a full head of hair, enough to fill space
    flat.solve.threshold = 0.9f;
    full.solve.threshold = 0.1f;
    const double v_flat =
        hair_radius(generate_hairstyle(flat, builtin(), &builtin_field()).masters);
    const double v_full =
        hair_radius(generate_hairstyle(full, builtin(), &builtin_field()).masters);
    EXPECT_GT(v_full, 1.15 * v_flat);
}

TEST(Solver, GravityPullsHairDown) {
    Style style = small_style();
    const HairstyleResult r = generate_hairstyle(style, builtin(), &builtin_field());
    double tip_y = 0, root_y = 0;
    for (size_t w = 0; w < r.masters.count(); ++w) {
        root_y += r.masters.outline[w * r.masters.points].y();
        tip_y += r.masters.outline[(w + 1) * r.masters.points - 1].y();
    }
    EXPECT_LT(tip_y, root_y - 15.0 * r.masters.count());  // 30 cm hair ends well below
}

TEST(Solver, NoHairPointInsideTheHead) {
    const Style style = small_style();
    const HairstyleResult r = generate_hairstyle(style, builtin(), &builtin_field());
    EXPECT_EQ(r.points_inside_head, 0u);
    // Exact check against the mesh itself (roots lie on the surface and are skipped).
    const MeshDistance exact(*builtin().mesh);
    std::atomic<size_t> inside{0};
    parallel_for(
        r.hair.strand_count(),
        [&](size_t i) {
            const auto s = r.hair.strand(i);
            for (size_t k = 1; k < s.size(); ++k)
                inside += exact.inside(s[k]);
        },
        64);
    EXPECT_EQ(inside.load(), 0u);
}

TEST(Solver, SameSeedSameHairAtAnyThreadCount) {
    const Style style = small_style();
    Hair a, b;
    {
        const ThreadLimit one(1);
        a = generate_hairstyle(style, builtin()).hair;
    }
    {
        const ThreadLimit two(2);
        b = generate_hairstyle(style, builtin()).hair;
    }
    ASSERT_EQ(a.points.size(), b.points.size());
    for (size_t i = 0; i < a.points.size(); ++i)
        ASSERT_EQ(a.points[i], b.points[i]) << i;
    EXPECT_EQ(a.colors.size(), b.colors.size());
}

// The concurrent schedule of a breadth-first layer (SolveInput::Schedule) gives the bytes of
// placing wisps one after another in id order, on 2,000 crowded wisps (a tenth of the default
// preset's strands each: a quarter of the joints collide) with a tie that squeezes half of them
// together, at one and two threads, and in its own order on one thread (which any missed
// interaction between two wisps would change).
TEST(Solver, ConcurrentScheduleGivesTheSerialBytes) {
    Style style = small_style();
    style.wisps = 2000;
    style.strands = 20000;
    style.solve.field = SolveSpec{}.field;  // gravity and growth, as the presets
    GroupSpec tie;
    tie.name = "tie";
    tie.selection.kind = Selection::Kind::kHalfSpace;
    tie.selection.normal = Vec3f(0, 0, -1);
    ConstraintSpec point;
    point.kind = ConstraintSpec::Kind::kPoint;
    point.point = Vec3f(0.f, 0.1f, -1.2f);
    point.radius = 0.1f;
    point.weight = 1.f;
    tie.queue.push_back(point);
    style.groups.push_back(tie);
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const Masters fresh = synthesize_masters(style, head, roots);
    const StylingField field = styling_field(style, head, solve_bounds(style, head, roots, fresh));
    const GroupSelection groups = select_groups(style, head, roots);
    const HeadFrame frame = head_frame(*head.scalp);
    SolveInput in;
    in.field = &field;
    in.head = &builtin_field();
    in.groups.push_back({"tie", groups.selected[0], {resolve_constraint(point, frame)}});
    for (size_t w = 0; w < fresh.count(); ++w)
        in.wisp_strands.push_back(
            static_cast<int>(roots.wisp_offsets[w + 1] - roots.wisp_offsets[w]));
    in.wisp_radius = roots.wisp_radius;
    in.radius_profile.assign(fresh.points, 1.f);

    struct Solved {
        Masters masters;
        Grid3<float> density;
        SolveStats stats;
    };
    const auto solve = [&](SolveInput::Schedule schedule) {
        Solved r{fresh,
                 Grid3<float>(field.grid().origin(), field.grid().cell(), field.grid().dims()),
                 {}};
        in.schedule = schedule;
        r.stats = solve_masters(r.masters, in, style.solve, r.density);
        return r;
    };
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    const Solved serial = solve(SolveInput::Schedule::kIdOrder);
    // Crowded: a fifth of the joints met hair or the skin.
    ASSERT_GT(serial.stats.collisions + serial.stats.contacts, serial.stats.joints / 5);
    ASSERT_GT(serial.stats.constrained, 0u);
    for (const int threads : {1, 2})
        for (const auto schedule :
             {SolveInput::Schedule::kConcurrent, SolveInput::Schedule::kByLevel}) {
            const ThreadLimit limit(threads);
            const Solved r = solve(schedule);
            SCOPED_TRACE(testing::Message()
                         << threads << " threads, schedule " << static_cast<int>(schedule));
            EXPECT_TRUE(bytes(r.masters.outline) == bytes(serial.masters.outline));
            EXPECT_TRUE(bytes(r.masters.control) == bytes(serial.masters.control));
            EXPECT_TRUE(bytes(r.density.data()) == bytes(serial.density.data()));
            EXPECT_EQ(r.stats.joints, serial.stats.joints);
            EXPECT_EQ(r.stats.bends, serial.stats.bends);
            EXPECT_EQ(r.stats.collisions, serial.stats.collisions);
            EXPECT_EQ(r.stats.unresolved, serial.stats.unresolved);
            EXPECT_EQ(r.stats.projected, serial.stats.projected);
            EXPECT_EQ(r.stats.constrained, serial.stats.constrained);
            EXPECT_EQ(r.stats.groups.at(0).met, serial.stats.groups.at(0).met);
            EXPECT_EQ(r.stats.groups.at(0).completed, serial.stats.groups.at(0).completed);
        }
}

// The editor's map stroke (StageCache::solve_synthesizing): the solve of the masters'
// outlines without their frames (SolveInput::update_frames), while a task synthesizes the
// details, then update_master, gives the bytes of synthesize_masters then solve_stage, at one
// and two threads.
TEST(Solver, SynthesizingWhileSolvingGivesTheSameBytes) {
    Style style = small_style();
    style.solve.field = SolveSpec{}.field;
    style.prototype.kind = PrototypeSpec::Kind::kWavy;
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    const GroupSelection groups = select_groups(style, head, roots);
    Masters serial = synthesize_masters(style, head, roots);
    const SolveStats expected = solve_stage(style, head, builtin_field(), roots, groups, serial);
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    for (const int threads : {1, 2}) {
        SCOPED_TRACE(testing::Message() << threads << " threads");
        const ThreadLimit limit(threads);
        Masters synthesized = master_outlines(style, head, roots);
        const MasterPrototype prototype = master_prototype(style, synthesized);
        Masters solved = synthesized;
        tbb::task_group tasks;
        tasks.run([&] { synthesize_master_details(style, prototype, synthesized); });
        const SolveStats stats = solve_stage(style, head, builtin_field(), roots, groups, solved,
                                             nullptr, nullptr, {}, /*update_frames=*/false);
        tasks.wait();
        solved.details = synthesized.details;
        for (size_t w = 0; w < solved.count(); ++w)
            update_master(solved, w);
        EXPECT_TRUE(bytes(solved.outline) == bytes(serial.outline));
        EXPECT_TRUE(bytes(solved.details) == bytes(serial.details));
        EXPECT_TRUE(bytes(solved.frames) == bytes(serial.frames));
        EXPECT_TRUE(bytes(solved.control) == bytes(serial.control));
        EXPECT_EQ(stats.joints, expected.joints);
        EXPECT_EQ(stats.bends, expected.bends);
    }
}

// The masters' frames and the members made band by band beside the solve, as its layers
// make the joints final (follow_solve: the editor's preview), are the serial solve's masters
// and members_stage's hair to the bit, at 1 and 2 threads, breadth- and depth-first.
TEST(Solver, MembersFollowingTheSolveGiveTheSameBytes) {
    for (const bool depth_first : {false, true}) {
        Style style = small_style();
        style.solve.field = SolveSpec{}.field;
        style.solve.depth_first = depth_first;
        style.prototype.kind = PrototypeSpec::Kind::kWavy;
        const Head& head = builtin();
        const Roots roots = grow_roots(style, head);
        const GroupSelection groups = select_groups(style, head, roots);
        const Masters start = synthesize_masters(style, head, roots);
        Masters serial = start;
        solve_stage(style, head, builtin_field(), roots, groups, serial);
        std::vector<uint32_t> some;
        for (uint32_t j = 0; j < roots.members.size(); j += 3)
            some.push_back(j);
        const MembersResult expected = members_stage(style, head, builtin_field(), roots, serial,
                                                     groups.wisp_group, nullptr, some);
        ASSERT_GT(expected.points_pushed, 0u);  // the push runs on some band
        const auto bytes = [](const auto& v) {
            return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
        };
        for (const int threads : {1, 2}) {
            SCOPED_TRACE(testing::Message() << threads << " threads, depth-first " << depth_first);
            const ThreadLimit limit(threads);
            Masters solved = start;
            std::atomic<int> joints{1};
            MemberBands bands(style, builtin_field(), *head.scalp, roots, groups.wisp_group,
                              start.points, some);
            bool followed = false;
            tbb::task_group tasks;
            tasks.run([&] { followed = follow_solve(solved, joints, &bands); });
            solve_stage(style, head, builtin_field(), roots, groups, solved, nullptr, nullptr, {},
                        /*update_frames=*/false, &joints);
            tasks.wait();
            ASSERT_TRUE(followed);
            EXPECT_TRUE(bytes(solved.outline) == bytes(serial.outline));
            EXPECT_TRUE(bytes(solved.frames) == bytes(serial.frames));
            EXPECT_TRUE(bytes(solved.control) == bytes(serial.control));
            const MembersResult got = bands.finish();
            EXPECT_TRUE(bytes(got.hair.points) == bytes(expected.hair.points));
            EXPECT_TRUE(got.hair.offsets == expected.hair.offsets);
            EXPECT_TRUE(got.hair.group == expected.hair.group);
            EXPECT_EQ(got.points_pushed, expected.points_pushed);
            EXPECT_EQ(got.points_inside_head, expected.points_inside_head);
        }
    }
}

// A solve that ends without finishing (here cancelled at once) leaves the joints it told below
// n; the caller then says so (−1) and the work following it stops rather than wait forever.
TEST(Solver, FollowingACancelledSolveStops) {
    Style style = small_style();
    const Head& head = builtin();
    const Roots roots = grow_roots(style, head);
    Masters m = synthesize_masters(style, head, roots);
    std::atomic<uint64_t> newest{1};
    const CancelToken cancel(newest, 0);
    std::atomic<int> joints{1};
    bool followed = true;
    tbb::task_group tasks;
    tasks.run([&] { followed = follow_solve(m, joints, nullptr); });
    const SolveStats stats =
        solve_stage(style, head, builtin_field(), roots, select_groups(style, head, roots), m,
                    nullptr, nullptr, cancel, /*update_frames=*/false, &joints);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_LT(joints.load(), m.points);
    joints.store(-1);
    joints.notify_all();
    tasks.wait();
    EXPECT_FALSE(followed);
}

TEST(Solver, DepthFirstIsAnOptionAndDiffers) {
    Style bf = small_style(), df = small_style();
    df.solve.depth_first = true;
    const Masters a = generate_hairstyle(bf, builtin(), &builtin_field()).masters;
    const Masters b = generate_hairstyle(df, builtin(), &builtin_field()).masters;
    double diff = 0;
    for (size_t i = 0; i < a.outline.size(); ++i)
        diff += (a.outline[i] - b.outline[i]).norm();
    EXPECT_GT(diff, 0.0);
}

TEST(Solver, TiedGroupPassesThroughItsTolerance) {
    // Tying (§6.2): a point constraint with w = 1; every wisp of the group comes within the
    // tolerance radius of the tie point.
    Style style = small_style();
    GroupSpec tie;
    tie.selection.kind = Selection::Kind::kHalfSpace;  // the back half, as a half ponytail
    tie.selection.normal = Vec3f(0, 0, -1);
    tie.selection.offset = 0.f;
    ConstraintSpec point;
    point.kind = ConstraintSpec::Kind::kPoint;
    point.point = Vec3f(0.f, 0.1f, -1.2f);  // behind the head, head units
    point.radius = 0.1f;
    point.weight = 1.f;
    point.hold = true;
    tie.queue.push_back(point);
    style.groups.push_back(tie);
    const Head& head = builtin();
    const HairstyleResult r = generate_hairstyle(style, head, &builtin_field());
    const HeadFrame frame = head_frame(*head.scalp);
    const Vec3f target = frame.to_space(point.point);
    const float tolerance = point.radius * frame.radius;
    const std::vector<uint32_t> group =
        select_wisps(tie.selection, r.masters.roots, *head.scalp, frame);
    ASSERT_GT(group.size(), 50u);
    size_t missed = 0;
    for (uint32_t w : group) {
        // The closest approach of the outline's segments to the tie point.
        float best = INFINITY;
        for (int j = 0; j + 1 < r.masters.points; ++j) {
            const Vec3f a = r.masters.outline[w * r.masters.points + j];
            const Vec3f e = r.masters.outline[w * r.masters.points + j + 1] - a;
            const float f = std::clamp((target - a).dot(e) / e.squaredNorm(), 0.f, 1.f);
            best = std::min(best, (a + f * e - target).norm());
        }
        missed += best > tolerance * 1.001f;
    }
    EXPECT_EQ(missed, 0u);
    EXPECT_EQ(r.solve.groups.at(0).completed, 1);  // the group completed its queue
    EXPECT_EQ(r.solve.groups.at(0).met.at(0), 1.f);

    // A tie holds for the animation: every tied wisp is held from the root through the
    // segment that met the tie (a whole number of segments, short of the whole wisp), the
    // free ones not at all.
    ASSERT_EQ(r.solve.held_length.size(), r.masters.count());
    std::vector<bool> tied(r.masters.count(), false);
    for (uint32_t w : group)
        tied[w] = true;
    for (size_t w = 0; w < r.masters.count(); ++w) {
        const float held = r.solve.held_length[w], segment = r.masters.segment[w];
        if (!tied[w]) {
            EXPECT_EQ(held, 0.f) << "wisp " << w;
            continue;
        }
        EXPECT_GT(held, 0.f) << "wisp " << w;
        EXPECT_LT(held, segment * static_cast<float>(r.masters.points - 1)) << "wisp " << w;
        EXPECT_NEAR(held / segment, std::round(held / segment), 1e-3f) << "wisp " << w;
        // The joint at the held length is within a segment of the tie.
        const int j = static_cast<int>(std::lround(held / segment));
        EXPECT_LE((r.masters.outline[w * r.masters.points + j] - target).norm(),
                  tolerance + segment * 1.001f)
            << "wisp " << w;
    }
    // A point constraint that does not hold (ConstraintSpec::hold = false) styles the same
    // and holds nothing.
    style.groups.back().queue.back().hold = false;
    const HairstyleResult loose = generate_hairstyle(style, head, &builtin_field());
    EXPECT_EQ(loose.hair.points, r.hair.points);
    for (float held : loose.solve.held_length)
        EXPECT_EQ(held, 0.f);
}

TEST(Solver, BraidGroupFollowsItsTrajectory) {
    Style style = small_style();
    style.points_per_strand = 40;
    style.length = ScalarMap{ScalarMap::Kind::kConstant, 45.f};
    GroupSpec g;
    g.selection.kind = Selection::Kind::kHalfSpace;
    g.selection.normal = Vec3f(0, 0, -1);
    g.selection.offset = 0.3f;  // the back of the head
    ConstraintSpec gather;
    gather.kind = ConstraintSpec::Kind::kPoint;
    gather.point = Vec3f(0.f, -0.3f, -1.15f);
    gather.radius = 0.12f;
    ConstraintSpec follow;
    follow.kind = ConstraintSpec::Kind::kTrajectory;
    follow.radius = 0.08f;
    for (int i = 0; i <= 12; ++i) {
        const float t = i / 12.f;
        follow.trajectory.push_back(
            Vec3f(0.2f * std::sin(6.f * t), -0.3f - 2.f * t, -1.15f - 0.2f * t));
    }
    follow.smooth = true;
    g.queue = {gather, follow};
    style.groups.push_back(g);
    const Head& head = builtin();
    const HeadFrame frame = head_frame(*head.scalp);
    const HairstyleResult r = generate_hairstyle(style, head, &builtin_field());
    const Constraint path = resolve_constraint(follow, frame);
    const std::vector<uint32_t> wisps =
        select_wisps(g.selection, r.masters.roots, *head.scalp, frame);
    ASSERT_GT(wisps.size(), 10u);
    // Once under the trajectory constraint, the joints stay close to the trajectory.
    double sum = 0;
    size_t count = 0;
    for (uint32_t w : wisps) {
        for (int j = r.masters.points / 2; j < r.masters.points; ++j) {
            const Vec3f p = r.masters.outline[w * r.masters.points + j];
            const PathPoint q = nearest_on_path(path, p);
            if (q.t > 0.05f && q.t < 0.95f) {
                sum += (q.position - p).norm();
                ++count;
            }
        }
    }
    ASSERT_GT(count, 0u);
    EXPECT_LT(sum / count, 3.f * path.radius);
    // Each wisp's progress is the group's, one wisp at a time: the counts sum to the
    // group's met fractions times its wisps, and wisps outside the group met nothing.
    ASSERT_EQ(r.solve.wisp_met.size(), r.masters.roots.size());
    const SolveStats::Group& group = r.solve.groups.at(0);
    double met = 0;
    for (const float m : group.met)
        met += double(m) * double(group.wisps);
    size_t in_group = 0, outside = 0;
    std::vector<bool> selected(r.solve.wisp_met.size(), false);
    for (uint32_t w : wisps)
        selected[w] = true;
    for (size_t w = 0; w < selected.size(); ++w)
        (selected[w] ? in_group : outside) += r.solve.wisp_met[w];
    EXPECT_NEAR(double(in_group), met, 0.5);
    EXPECT_GT(in_group, wisps.size());  // most wisps met both constraints
    EXPECT_EQ(outside, 0u);
}

// Long hair reaching the shoulders divides there, as a stylist lays it: beside the neck, hair
// in front of the ears' plane is carried forward over the shoulder onto the chest, hair behind
// it back, instead of landing on the shoulder's top and sliding out over the arm. Over the neck
// itself, far above the shoulders and well below them, the growth term is as before.
TEST(StylingField, LongHairDividesInFrontOfAndBehindTheShoulders) {
    const Head& head = builtin();
    const HeadFrame frame = head_frame(head);
    ASSERT_TRUE(std::isfinite(frame.shoulder_top));
    ASSERT_TRUE(head.landmarks);
    // The shoulders' top lies between the chin and a head's height below it.
    EXPECT_LT(frame.shoulder_top, head.landmarks->chin.y());
    EXPECT_GT(frame.shoulder_top, head.landmarks->chin.y() - head.landmarks->height);
    const GrowthField growth(GrowthSpec{}, *head.scalp);
    const FieldTerm term{FieldTerm::Kind::kGrowth};
    const HeadFrame plain = head_frame(*head.scalp);  // no shoulders known
    const float across = 2.f * frame.neck_radius;
    for (float side : {-1.f, 1.f}) {
        const Vec3f at(frame.neck.x() + side * across, frame.shoulder_top + 0.2f * frame.radius,
                       frame.neck.z() + frame.split);
        const Vec3f ahead = field_term(term, frame, growth, at + 2.f * frame.forward);
        const Vec3f behind = field_term(term, frame, growth, at - 2.f * frame.forward);
        EXPECT_GT(ahead.dot(frame.forward), 0.5f) << "side " << side;
        EXPECT_LT(behind.dot(frame.forward), -0.5f) << "side " << side;
        EXPECT_LT(ahead.y(), 0.f);  // still falling
        for (const Vec3f& p : {Vec3f(at + 2.f * frame.forward), Vec3f(at - 2.f * frame.forward)})
            EXPECT_NEAR(field_term(term, plain, growth, p).dot(frame.forward), 0.f, 1e-4f);
        const Vec3f far_below = at - 2.f * frame.radius * Vec3f::UnitY() + 2.f * frame.forward;
        EXPECT_EQ(field_term(term, frame, growth, far_below),
                  field_term(term, plain, growth, far_below));
    }
    const Vec3f over_neck(frame.neck.x(), frame.shoulder_top + 0.8f * frame.radius,
                          frame.neck.z() + frame.split + 2.f);
    EXPECT_EQ(field_term(term, frame, growth, over_neck),
              field_term(term, plain, growth, over_neck));
}

// Hair that reaches the shoulders' top rests there or is divided, never carried on along it:
// above them, hair beside the neck is carried outward (a curtain as wide as the head), but not
// on the shoulders' top, where it would slide out over the arm; and there the division's push
// is more than the skin's friction holds back (μ times the pull into the skin), or hair lying
// on the top would stay there, to be carried out over the arm by its own stiffness.
// Hair swept from a side part over the forehead is carried sideways, away from the part, and
// held up, so that it falls at the temple and not across the eyes; and along the head, not off
// it: where the forehead curves back toward the temple, a push straight sideways points out of
// the head, and hair lying on top of the rest followed it off the forehead as a visor.
TEST(StylingField, HairSweptOverTheForeheadFollowsTheHead) {
    const Head& head = builtin();
    const HeadFrame frame = head_frame(head);
    GrowthSpec spec;
    spec.part = GrowthSpec::Part::kSide;
    spec.part_offset = -0.28f;  // on the character's right, as wavy-bob's
    const GrowthField growth(spec, *head.scalp);
    const FieldTerm term{FieldTerm::Kind::kGrowth};
    const float part = part_x(spec);
    for (float x : {0.3f, 0.45f, 0.6f}) {
        for (float y : {0.1f, 0.3f}) {
            const float side = x > part ? 1.f : -1.f;
            const Vec3f r = Vec3f(x, y, std::sqrt(1.f - x * x - y * y));
            const Vec3f p = frame.center + 1.05f * frame.radius * r;
            const Vec3f phi = field_term(term, frame, growth, p);
            const std::string at = "at x " + std::to_string(x) + ", y " + std::to_string(y);
            EXPECT_GT(side * phi.x(), 1.f) << at;  // away from the part
            EXPECT_GT(phi.y(), 0.f) << at;         // held up
            EXPECT_LT(phi.dot(r), 0.05f) << at;    // not off the head
        }
    }
}

TEST(StylingField, HairOnTheShouldersTopIsNotCarriedOutOverTheArm) {
    const Head& head = builtin();
    const HeadFrame frame = head_frame(head);
    ASSERT_TRUE(std::isfinite(frame.shoulder_top));
    const GrowthField growth(GrowthSpec{}, *head.scalp);
    const FieldTerm term{FieldTerm::Kind::kGrowth};
    const HeadFrame plain = head_frame(*head.scalp);  // no shoulders known
    const Vec3f side = Vec3f::UnitY().cross(frame.forward);
    const SolveSpec spec;
    for (float s : {-1.f, 1.f}) {
        const Vec3f beside_neck = frame.neck + s * 1.2f * frame.neck_radius * side +
                                  (frame.shoulder_top - frame.neck.y()) * Vec3f::UnitY() -
                                  3.f * frame.forward;
        EXPECT_GT(s * field_term(term, plain, growth, beside_neck).dot(side), 0.5f)
            << "side " << s << ": the curtain, without shoulders";
        EXPECT_LT(std::abs(field_term(term, frame, growth, beside_neck).dot(side)), 0.05f)
            << "side " << s;
        const Vec3f on_top = frame.neck + s * 2.f * frame.neck_radius * side +
                             (frame.shoulder_top - frame.neck.y()) * Vec3f::UnitY() +
                             frame.split * frame.forward;
        for (float f : {-1.f, 1.f}) {
            // The default field's Φ (gravity and growth); on the top, the skin faces up. What
            // friction leaves of the pull along it must outweigh κ·q₀, the stiffness that
            // carries hair on in the way it arrived (slide_direction).
            Vec3f phi = Vec3f::Zero();
            for (const FieldTerm& t : spec.field)
                phi += t.weight * field_term(t, frame, growth, on_top + f * frame.forward);
            EXPECT_GT(f * phi.dot(frame.forward) - spec.friction * -phi.y(), spec.stiffness)
                << "side " << s << ", " << (f > 0 ? "in front" : "behind");
        }
    }
}

TEST(Constraint, ForcesFollowSectionFour) {
    const HeadFrame frame;  // centre 0, radius 10
    ConstraintSpec spec;
    spec.kind = ConstraintSpec::Kind::kTrajectory;
    spec.head_relative = false;
    spec.trajectory = {Vec3f(0, 0, 0), Vec3f(10, 0, 0)};
    spec.radius = 1.f;
    const Constraint traj = resolve_constraint(spec, frame);
    // Outside the tolerance: toward the nearest point; inside: along the tangent.
    EXPECT_LT((constraint_force(traj, Vec3f(5, 3, 0)) - Vec3f(0, -1, 0)).norm(), 1e-5f);
    EXPECT_LT((constraint_force(traj, Vec3f(5, 0.5f, 0)) - Vec3f(1, 0, 0)).norm(), 1e-5f);
    EXPECT_FALSE(constraint_met(traj, Vec3f(4, 0.5f, 0), Vec3f(5, 0.5f, 0)));
    EXPECT_TRUE(constraint_met(traj, Vec3f(9, 0.3f, 0), Vec3f(10.2f, 0.3f, 0)));
    spec.kind = ConstraintSpec::Kind::kDirection;
    const Constraint dir = resolve_constraint(spec, frame);
    EXPECT_EQ(constraint_force(dir, Vec3f(5, 3, 0)), Vec3f::Zero());
    EXPECT_LT((constraint_force(dir, Vec3f(5, 0.5f, 0)) - Vec3f(1, 0, 0)).norm(), 1e-5f);
    spec.kind = ConstraintSpec::Kind::kPoint;
    spec.point = Vec3f(0, 0, 4);
    const Constraint pt = resolve_constraint(spec, frame);
    EXPECT_LT((constraint_force(pt, Vec3f(0, 0, 0)) - Vec3f(0, 0, 1)).norm(), 1e-5f);
    EXPECT_TRUE(constraint_met(pt, Vec3f(0, 0.5f, 3.5f), Vec3f(0, 0.5f, 4)));
    // A segment that jumps across the sphere still passes through it.
    EXPECT_TRUE(constraint_met(pt, Vec3f(0, 0.2f, 2), Vec3f(0, 0.2f, 6)));
    EXPECT_FALSE(constraint_met(pt, Vec3f(0, 3, 2), Vec3f(0, 3, 6)));
    // Eq. (7).
    EXPECT_EQ(constrained_field(Vec3f(0, -1, 0), Vec3f(1, 0, 0), 0.25f), Vec3f(0.25f, -0.75f, 0));
}

// A head cut open at the chest (most head meshes, the MakeHuman bust among them): far
// from its skin, its inside must still be inside, not one region with the outside through
// the cut, or hair could pass through the head.
TEST(HeadField, InsideOfAnOpenMeshIsInside) {
    // The built-in figure with its flat bottom (y = -62) cut away.
    const Mesh& whole = *builtin().mesh;
    const float bottom = whole.bounds().lo.y();
    Mesh bust;
    bust.vertices = whole.vertices;
    for (size_t f = 0; f < whole.faces.size(); ++f)
        if (whole.face_normal(f).y() > -0.9f ||
            whole.vertices[whole.faces[f][0]].y() > bottom + 1.f)
            bust.faces.push_back(whole.faces[f]);
    ASSERT_LT(bust.faces.size(), whole.faces.size());
    const HeadField field(bust, 0.75f);
    EXPECT_LT(field.sdf(Vec3f(0, -28, 0)), -3.f);           // the chest, far from the skin
    EXPECT_LT(field.sdf(Vec3f(0, -55, 0)), -3.f);           // the waist, just above the cut
    EXPECT_LT(field.sdf(Vec3f(0, 2, 0)), -3.f);             // the head
    EXPECT_GT(field.sdf(Vec3f(0, bottom - 1.5f, 0)), 1.f);  // below the cut
    EXPECT_GT(field.sdf(Vec3f(30, 0, 0)), 3.f);             // beside the head
}

// A body under a head (a proxy fitted under a head that ends at the neck) overlaps the head's
// neck: the field is their union, so a point outside the head's neck but inside the body's
// is inside, though the nearest skin is the head's, facing out.
TEST(HeadField, AHeadAndABodyAreTheirUnion) {
    const Mesh& whole = *builtin().mesh;
    Mesh figure;
    figure.vertices = whole.vertices;
    for (size_t f = 0; f < whole.faces.size(); ++f) {
        const Vec3i& t = whole.faces[f];
        if (std::min({whole.vertices[t[0]].y(), whole.vertices[t[1]].y(),
                      whole.vertices[t[2]].y()}) > -16.f)
            figure.faces.push_back(t);
    }
    const size_t head_faces = figure.faces.size();
    append_mesh(figure, builtin_torso_mesh(-12.f, 7.f));  // its neck column wider than the neck
    const HeadField two(figure, 0.5f, head_faces), one(figure, 0.5f);
    const Vec3f beside_neck(6.2f, -13.f, -1.9f);  // ~0.9 cm out of the neck, in the column
    EXPECT_LT(two.sdf(beside_neck), -0.2f);
    EXPECT_GT(one.sdf(beside_neck), 0.f);        // what a single piece's field would say
    EXPECT_LT(two.sdf(Vec3f(0, -30, 0)), -3.f);  // the chest
    EXPECT_LT(two.sdf(Vec3f(0, 3, 0)), -3.f);    // the head
    EXPECT_GT(two.sdf(Vec3f(0, -14, 12)), 3.f);  // under the chin, in front of the neck
}

// A closed box, its faces counter-clockwise seen from outside, appended to `mesh`.
static void add_box(Mesh& mesh, const Vec3f& lo, const Vec3f& hi) {
    const int base = static_cast<int>(mesh.vertices.size());
    for (int c = 0; c < 8; ++c)
        mesh.vertices.emplace_back(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(),
                                   c & 4 ? hi.z() : lo.z());
    // Two triangles per side, as corner bit patterns.
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
        mesh.faces.emplace_back(base + q[0], base + q[1], base + q[2]);
        mesh.faces.emplace_back(base + q[0], base + q[2], base + q[3]);
    }
}

// A wisp lies over a crease narrower than its diameter (the one behind an ear) instead of
// following the skin into it: the bridged field counts such a crease as inside, leaves a
// wider one open and the open skin where it was, and never moves the skin outward.
TEST(HeadField, TheBridgedFieldClosesNarrowCreasesOnly) {
    Mesh mesh;
    add_box(mesh, Vec3f(-10, -10, -10), Vec3f(10, 10, 10));   // a skull
    add_box(mesh, Vec3f(10.8f, -3, -2), Vec3f(11.3f, 3, 2));  // an ear 0.8 cm off it
    add_box(mesh, Vec3f(-13.5f, -3, -2), Vec3f(-13, 3, 2));   // a fin 3 cm off it
    const HeadField field(mesh, 0.25f, SIZE_MAX, 1.f);
    const HeadField& bridged = field.bridged();
    ASSERT_NE(&bridged, &field);
    const Vec3f in_crease(10.4f, 0, 0), in_gap(-11.5f, 0, 0), open_skin(0, 0, 10.5f);
    EXPECT_GT(field.sdf(in_crease), 0.2f);  // outside the skin (0.4 cm from both walls)
    EXPECT_LT(bridged.sdf(in_crease), 0.f);
    EXPECT_NEAR(bridged.sdf(in_gap), field.sdf(in_gap), 0.05f);
    EXPECT_GT(bridged.sdf(in_gap), 1.f);
    EXPECT_NEAR(bridged.sdf(open_skin), field.sdf(open_skin), 0.02f);
    // Closing only adds to the head: nowhere is the bridged distance larger.
    Rng rng(7);
    for (int i = 0; i < 20000; ++i) {
        const Vec3f p(rng.uniform(-14.f, 12.f), rng.uniform(-11.f, 11.f), rng.uniform(-11.f, 11.f));
        ASSERT_LE(bridged.sdf(p), field.sdf(p) + 1e-4f) << p.transpose();
    }
    // Without a bridge radius the bridged field is the field itself.
    const HeadField plain(mesh, 0.5f);
    EXPECT_EQ(&plain.bridged(), &plain);
}

TEST(HeadField, BeyondNeverClaimsAPointCloserThanItsDistance) {
    // beyond(p, d) spares the lookup only where the lookup would give ≥ d: over random points
    // around the head at the distances the solver (head margin) and the push out of the head
    // (clearance) ask about, it never claims a closer point, and it spares most far ones.
    const HeadField& field = builtin_field();
    const Box3 box = builtin().mesh->bounds();
    Rng rng(16);
    size_t far = 0, claimed = 0;
    for (int t = 0; t < 200000; ++t) {
        Vec3f p;
        for (int a = 0; a < 3; ++a)
            p[a] = rng.uniform(box.lo[a] - 3.f, box.hi[a] + 3.f);
        const float d = rng.uniform() < 0.5f ? 0.25f : 0.3f;
        const float sdf = field.sdf(p);
        const bool beyond = field.beyond(p, d);
        if (beyond) {
            ASSERT_GE(sdf, d) << p.transpose();
        }
        const bool clear = sdf >= d + 3.5f * field.grid().cell();
        far += clear;
        claimed += beyond && clear;
    }
    EXPECT_GT(far, 1000u);
    EXPECT_GT(claimed, 0.8 * double(far));  // most points a few cells out are spared
}

// sdf(p, &gradient) is the solver's one-lookup distance and normal, sdf(p) the push out of
// the head's: over random points around the head, at nodes, on the grid's faces and beyond
// them, both give the same distance to the bit (the grid's trilinear lookup inside its box, a
// large positive value and a zero gradient outside it).
TEST(HeadField, TheLookupWithTheGradientGivesTheSameDistance) {
    const HeadField& field = builtin_field();
    const Grid3<float>& grid = field.grid();
    const Vec3f lo = grid.origin();
    const Vec3f hi = grid.node(grid.dims().x() - 1, grid.dims().y() - 1, grid.dims().z() - 1);
    Rng rng(16);
    size_t outside = 0;
    for (int t = 0; t < 100000; ++t) {
        Vec3f p;
        for (int a = 0; a < 3; ++a) {
            switch (rng.next() % 4) {
                case 0:  // a node plane
                    p[a] = lo[a] + grid.cell() * float(rng.next() % grid.dims()[a]);
                    break;
                case 1:  // a face of the box
                    p[a] = rng.next() % 2 ? lo[a] : hi[a];
                    break;
                default:  // around the box, a little beyond it
                    p[a] = rng.uniform(lo[a] - 2.f, hi[a] + 2.f);
            }
        }
        Vec3f gradient = Vec3f::Constant(7.f);
        const float d = field.sdf(p);
        ASSERT_EQ(std::bit_cast<uint32_t>(field.sdf(p, &gradient)), std::bit_cast<uint32_t>(d))
            << p.transpose();
        bool in = true;
        for (int a = 0; a < 3; ++a)
            in = in && p[a] >= lo[a] && p[a] <= hi[a];
        if (in) {
            ASSERT_EQ(std::bit_cast<uint32_t>(d), std::bit_cast<uint32_t>(grid.trilinear(p)))
                << p.transpose();
        } else {
            ++outside;
            ASSERT_EQ(d, 1e6f) << p.transpose();
            ASSERT_EQ(gradient, Vec3f::Zero()) << p.transpose();
        }
    }
    EXPECT_GT(outside, 1000u);
    EXPECT_LT(outside, 90000u);
}

TEST(Solver, ACancelledSolveStopsAtOnceAndSaysSo) {
    Style style = small_style();
    const Roots roots = grow_roots(style, builtin());
    Masters masters = synthesize_masters(style, builtin(), roots);
    const std::vector<Vec3f> before = masters.outline;
    const std::atomic<uint64_t> newest{2};
    const CancelToken overtaken(newest, 1);
    const SolveStats stats =
        solve_stage(style, builtin(), builtin_field(), roots,
                    select_groups(style, builtin(), roots), masters, nullptr, nullptr, overtaken);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(stats.joints, 0u);
    EXPECT_EQ(masters.outline, before);
    // Not overtaken: it runs to the end.
    const SolveStats done = solve_stage(style, builtin(), builtin_field(), roots,
                                        select_groups(style, builtin(), roots), masters, nullptr,
                                        nullptr, CancelToken(newest, 2));
    EXPECT_FALSE(done.cancelled);
    EXPECT_EQ(done.joints, masters.count() * (masters.points - 1));
}

// The solve tells its token's report the fraction done after each breadth-first layer, on
// the calling thread, and reporting changes nothing in the result.
TEST(Solver, ReportsItsLayersAndTheResultIsTheSame) {
    Style style = small_style();
    const Roots roots = grow_roots(style, builtin());
    const Masters start = synthesize_masters(style, builtin(), roots);
    Masters quiet = start, told = start;
    solve_stage(style, builtin(), builtin_field(), roots, select_groups(style, builtin(), roots),
                quiet);
    std::vector<float> fractions;
    const std::thread::id caller = std::this_thread::get_id();
    bool other_thread = false;
    const FractionReport report = [&](float f) {
        fractions.push_back(f);
        other_thread |= std::this_thread::get_id() != caller;
    };
    solve_stage(style, builtin(), builtin_field(), roots, select_groups(style, builtin(), roots),
                told, nullptr, nullptr, CancelToken(&report));
    EXPECT_EQ(told.outline, quiet.outline);
    EXPECT_EQ(told.control, quiet.control);
    EXPECT_FALSE(other_thread);
    ASSERT_EQ(fractions.size(), size_t(start.points - 1));  // one per layer of joints
    for (size_t i = 0; i < fractions.size(); ++i)
        EXPECT_FLOAT_EQ(fractions[i], float(i + 1) / float(start.points - 1));
}

TEST(Cut, PlaneShortensAndRemoves) {
    Hair hair;
    hair.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, -2, 0}, {0, -4, 0}});
    hair.add_strand(std::vector<Vec3f>{{0, -5, 0}, {0, -6, 0}});
    size_t removed = 0;
    const size_t cut = cut_hair(hair, Vec3f(0, -1, 0), 3.f, &removed);  // keep y ≥ -3
    EXPECT_EQ(cut, 1u);
    EXPECT_EQ(removed, 1u);
    ASSERT_EQ(hair.strand_count(), 1u);
    EXPECT_LT((hair.strand(0).back() - Vec3f(0, -3, 0)).norm(), 1e-6f);
}

// A cut at each strand's own plane (a fringe cut, a textured cut) leaves the strands it does
// not cut (NaN) whole, even where they pass the plane or start beyond it.
TEST(Cut, EachStrandAtItsOwnPlane) {
    Hair hair;
    hair.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, -2, 0}, {0, -4, 0}});
    hair.add_strand(std::vector<Vec3f>{{1, 0, 0}, {1, -2, 0}, {1, -4, 0}});
    hair.add_strand(std::vector<Vec3f>{{0, -5, 0}, {0, -6, 0}});
    const float no = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> offsets = {no, 1.f, no};
    size_t removed = 0;
    const size_t cut = cut_hair(hair, Vec3f(0, -1, 0), 3.f, &removed, &offsets);
    EXPECT_EQ(cut, 1u);
    EXPECT_EQ(removed, 0u);
    ASSERT_EQ(hair.strand_count(), 3u);
    EXPECT_EQ(hair.strand(0).size(), 3u);
    EXPECT_LT((hair.strand(1).back() - Vec3f(1, -1, 0)).norm(), 1e-6f);
    EXPECT_EQ(hair.strand(2).size(), 2u);
}

// A bevel turns the cut ends under: the tip comes half the bevel in toward the axis, the turn
// starts where the stretch does, and uncut strands keep their ends.
TEST(Cut, BevelTurnsTheCutEndsTowardTheAxis) {
    Hair hair;
    std::vector<Vec3f> hanging;  // 5 cm behind the axis, from y = 0 down to y = -10, 0.5 cm steps
    for (int k = 0; k <= 20; ++k)
        hanging.push_back(Vec3f(0.f, -0.5f * float(k), -5.f));
    hair.add_strand(hanging);
    hair.add_strand(hanging);
    std::vector<uint8_t> was_cut;
    cut_hair(hair, Vec3f(0, -1, 0), 8.f, nullptr, nullptr, &was_cut);  // both end at y = -8
    ASSERT_EQ(was_cut, (std::vector<uint8_t>{1, 1}));
    was_cut[1] = 0;
    const Hair before = hair;
    bevel_ends(hair, was_cut, 3.f, Vec3f::Zero());
    const auto s = hair.strand(0);
    EXPECT_NEAR(s.back().z(), -5.f + 1.5f, 1e-4f);  // half the bevel, toward the axis
    EXPECT_NEAR(s.back().x(), 0.f, 1e-6f);
    EXPECT_NEAR(s.back().y(), -8.f, 1e-6f);
    for (size_t k = 0; k < s.size(); ++k) {
        if (s[k].y() > -8.f + 3.f) {
            EXPECT_EQ(s[k], before.strand(0)[k]) << k;  // above the last 3 cm
        }
        EXPECT_LE(s[k].z(), s.back().z() + 1e-6f) << "the turn grows toward the tip";
    }
    for (size_t k = 0; k < hair.strand(1).size(); ++k)
        EXPECT_EQ(hair.strand(1)[k], before.strand(1)[k]);
}

}  // namespace wisp
