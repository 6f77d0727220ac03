#include "groom/hairdressing.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace wisp {
namespace {

constexpr float kEps = 1e-4f;

// The braid's frame as braid_trajectory documents it: axis, width direction ⟂ axis, depth.
struct BraidFrame {
    Vec3f axis, side, depth;
};

BraidFrame frame_of(const BraidSpec& spec) {
    BraidFrame f;
    f.axis = spec.axis.normalized();
    f.side = (spec.side - spec.side.dot(f.axis) * f.axis).normalized();
    f.depth = f.axis.cross(f.side);
    return f;
}

BraidSpec wide_braid(int strands) {
    BraidSpec spec;
    spec.strands = strands;
    spec.start = Vec3f(0.1f, -0.3f, -1.2f);
    spec.axis = Vec3f(0.f, -1.f, -0.2f);
    spec.side = Vec3f(1.f, 0.1f, 0.f);  // not ⟂ axis: braid_trajectory must fix that
    spec.length = 2.f;
    spec.width = 0.4f;
    spec.period = 0.5f;
    return spec;
}

TEST(Hairdressing, TieIsOnePointConstraintOnTheSelection) {
    TieSpec spec;
    spec.selection.kind = Selection::Kind::kRegion;
    spec.selection.region = "back";
    spec.point = Vec3f(0.f, 0.4f, -1.1f);
    spec.radius = 0.2f;
    const auto groups = tie_groups(spec);
    ASSERT_EQ(groups.size(), 1u);
    EXPECT_EQ(groups[0].selection.kind, Selection::Kind::kRegion);
    EXPECT_EQ(groups[0].selection.region, "back");
    ASSERT_EQ(groups[0].queue.size(), 1u);
    const ConstraintSpec& c = groups[0].queue[0];
    EXPECT_EQ(c.kind, ConstraintSpec::Kind::kPoint);
    EXPECT_TRUE(c.point.isApprox(spec.point));
    EXPECT_FLOAT_EQ(c.radius, 0.2f);
    EXPECT_FLOAT_EQ(c.weight, 1.f);  // §6.2: tying uses w = 1
    EXPECT_TRUE(c.head_relative);
}

TEST(Hairdressing, BraidSplitsTheSelectionIntoStrandsWithPointThenTrajectory) {
    for (int strands : {3, 4, 5}) {
        BraidSpec spec = wide_braid(strands);
        spec.selection.kind = Selection::Kind::kRegion;
        spec.selection.region = "back";
        spec.weight = 0.9f;
        const auto groups = braid_groups(spec);
        ASSERT_EQ(groups.size(), size_t(strands));
        for (int i = 0; i < strands; ++i) {
            SCOPED_TRACE(i);
            const GroupSpec& g = groups[i];
            EXPECT_EQ(g.selection.kind, Selection::Kind::kRegion);
            EXPECT_EQ(g.selection.region, "back");
            EXPECT_EQ(g.selection.part, i);
            EXPECT_EQ(g.selection.parts, strands);
            ASSERT_EQ(g.queue.size(), 2u);
            EXPECT_EQ(g.queue[0].kind, ConstraintSpec::Kind::kPoint);
            EXPECT_TRUE(g.queue[0].point.isApprox(spec.start));
            EXPECT_FLOAT_EQ(g.queue[0].radius, spec.radius);
            EXPECT_FLOAT_EQ(g.queue[0].weight, 0.9f);
            EXPECT_EQ(g.queue[1].kind, ConstraintSpec::Kind::kTrajectory);
            EXPECT_TRUE(g.queue[1].smooth);
            EXPECT_FLOAT_EQ(g.queue[1].radius, spec.radius);
            EXPECT_FLOAT_EQ(g.queue[1].weight, 0.9f);
            ASSERT_GE(g.queue[1].trajectory.size(), 2u);
            // The trajectory the group follows is this strand's braid trajectory.
            const auto& traj = g.queue[1].trajectory;
            const auto expected = braid_trajectory(spec, i, int(traj.size()));
            for (size_t k = 0; k < traj.size(); ++k)
                EXPECT_LT((traj[k] - expected[k]).norm(), kEps) << k;
        }
    }
}

TEST(Hairdressing, BraidTrajectoryFollowsTheDocumentedFormula) {
    const BraidSpec spec = wide_braid(3);
    const BraidFrame f = frame_of(spec);
    const int samples = 101;
    for (int i = 0; i < spec.strands; ++i) {
        const auto traj = braid_trajectory(spec, i, samples);
        ASSERT_EQ(traj.size(), size_t(samples));
        const float phase = 2.f * kPi * i / spec.strands;
        for (int k = 0; k < samples; ++k) {
            const float t = float(k) / (samples - 1);
            const float a = 2.f * kPi * t * spec.length / spec.period + phase;
            const Vec3f p = spec.start + t * spec.length * f.axis +
                            0.5f * spec.width * std::sin(a) * f.side +
                            0.25f * spec.width * std::sin(2.f * a) * f.depth;
            EXPECT_LT((traj[k] - p).norm(), kEps) << "strand " << i << " sample " << k;
        }
    }
}

TEST(Hairdressing, BraidTrajectoriesStartInTheCrossSectionAtStartAndEndAtLength) {
    const BraidSpec spec = wide_braid(4);
    const BraidFrame f = frame_of(spec);
    for (int i = 0; i < spec.strands; ++i) {
        const auto traj = braid_trajectory(spec, i, 33);
        const Vec3f first = traj.front() - spec.start;
        EXPECT_NEAR(first.dot(f.axis), 0.f, kEps) << i;  // in the plane ⟂ axis through start
        EXPECT_LE(first.norm(), 0.5f * spec.width * std::sqrt(1.25f) + kEps) << i;
        EXPECT_NEAR((traj.back() - spec.start).dot(f.axis), spec.length, kEps) << i;
        // Monotone along the axis: the braid never turns back.
        for (size_t k = 1; k < traj.size(); ++k)
            EXPECT_GT((traj[k] - traj[k - 1]).dot(f.axis), 0.f);
    }
    // Strand 0 has phase 0: it starts exactly at the gathering point.
    EXPECT_LT((braid_trajectory(spec, 0, 9).front() - spec.start).norm(), kEps);
}

TEST(Hairdressing, BraidStrandPhasesAreEvenlySpaced) {
    // Strand i is strand 0 shifted back along the axis by i·period/strands: phase 2πi/strands.
    const BraidSpec spec = wide_braid(5);
    const BraidFrame f = frame_of(spec);
    const int samples = 2001;
    const auto s0 = braid_trajectory(spec, 0, samples);
    const float dt = 1.f / (samples - 1);
    for (int i = 1; i < spec.strands; ++i) {
        const auto si = braid_trajectory(spec, i, samples);
        const float shift = spec.period * i / spec.strands / spec.length;  // in t
        const int dk = int(std::lround(shift / dt));
        ASSERT_NEAR(dk * dt, shift, 1e-6f);
        for (int k = 0; k + dk < samples; k += 37) {
            const Vec3f a = si[k] - spec.start - (k * dt) * spec.length * f.axis;
            const Vec3f b = s0[k + dk] - spec.start - ((k + dk) * dt) * spec.length * f.axis;
            EXPECT_LT((a - b).norm(), 1e-3f) << "strand " << i << " sample " << k;
        }
    }
}

TEST(Hairdressing, NeighbouringBraidStrandsCrossOverAndUnder) {
    for (int strands : {3, 4, 6}) {
        SCOPED_TRACE(strands);
        const BraidSpec spec = wide_braid(strands);
        const BraidFrame f = frame_of(spec);
        const int samples = 4001;
        std::vector<std::vector<Vec3f>> traj;
        for (int i = 0; i < strands; ++i)
            traj.push_back(braid_trajectory(spec, i, samples));
        for (int i = 0; i < strands; ++i) {
            const int j = (i + 1) % strands;
            int crossings = 0;
            float min_gap = INFINITY;
            for (int k = 1; k < samples; ++k) {
                const float before = (traj[i][k - 1] - traj[j][k - 1]).dot(f.side);
                const float after = (traj[i][k] - traj[j][k]).dot(f.side);
                if ((before < 0) == (after < 0)) continue;
                ++crossings;
                // Where they swap sides, they pass at different depths (over and under).
                min_gap = std::min(min_gap, std::abs((traj[i][k] - traj[j][k]).dot(f.depth)));
            }
            // Each neighbouring pair crosses twice per period.
            const float periods = spec.length / spec.period;
            EXPECT_NEAR(crossings, 2.f * periods, 1.f) << i << "/" << j;
            EXPECT_GT(min_gap, 0.1f * spec.width) << i << "/" << j;
        }
    }
}

TEST(Hairdressing, BraidSideParallelToTheAxisStillGivesAFrame) {
    BraidSpec spec = wide_braid(3);
    spec.side = spec.axis;
    for (const Vec3f& p : braid_trajectory(spec, 1, 17))
        EXPECT_TRUE(p.allFinite());
}

TEST(Hairdressing, UpdoTiesThenWindsASpiralInThePlaneFacingOut) {
    UpdoSpec spec;
    spec.selection.kind = Selection::Kind::kAll;
    spec.turns = 2.5f;
    const auto groups = updo_groups(spec);
    ASSERT_EQ(groups.size(), 1u);
    ASSERT_EQ(groups[0].queue.size(), 2u);
    const ConstraintSpec& tie = groups[0].queue[0];
    EXPECT_EQ(tie.kind, ConstraintSpec::Kind::kPoint);
    EXPECT_TRUE(tie.point.isApprox(spec.point));
    EXPECT_FLOAT_EQ(tie.radius, spec.radius);
    EXPECT_FLOAT_EQ(tie.weight, spec.weight);
    const ConstraintSpec& bun = groups[0].queue[1];
    EXPECT_EQ(bun.kind, ConstraintSpec::Kind::kTrajectory);
    EXPECT_TRUE(bun.smooth);
    const auto& spiral = bun.trajectory;
    ASSERT_GE(spiral.size(), 9u);
    EXPECT_LT((spiral.front() - spec.point).norm(), kEps);  // starts at the tie
    const Vec3f n = spec.facing.normalized();
    float max_r = 0.f, winding = 0.f;
    for (size_t k = 0; k < spiral.size(); ++k) {
        const Vec3f d = spiral[k] - spec.point;
        EXPECT_NEAR(d.dot(n), 0.f, kEps) << k;  // in the plane ⟂ facing
        max_r = std::max(max_r, d.norm());
        if (k >= 1) {  // winding outward
            EXPECT_GE(d.norm() + kEps, (spiral[k - 1] - spec.point).norm());
        }
        if (k >= 2) {  // the angle swept about the point, from the first step on
            const Vec3f a = spiral[k - 1] - spec.point;
            winding += std::atan2(a.cross(d).dot(n), a.dot(d));
        }
    }
    EXPECT_NEAR(max_r, spec.bun_radius, kEps);
    const float swept = 2.f * kPi * spec.turns * (1.f - 1.f / float(spiral.size() - 1));
    EXPECT_NEAR(std::abs(winding), swept, 1e-3f);
}

TEST(Hairdressing, CombIsOneDirectionConstraint) {
    CombSpec spec;
    spec.selection.kind = Selection::Kind::kRegion;
    spec.selection.region = "front";
    spec.trajectory = {Vec3f(0, 0.9f, 1.f), Vec3f(0, 1.2f, 0), Vec3f(0, 0.6f, -1.2f)};
    spec.weight = 0.5f;
    spec.radius = 0.3f;
    const auto groups = comb_groups(spec);
    ASSERT_EQ(groups.size(), 1u);
    EXPECT_EQ(groups[0].selection.region, "front");
    ASSERT_EQ(groups[0].queue.size(), 1u);
    const ConstraintSpec& c = groups[0].queue[0];
    EXPECT_EQ(c.kind, ConstraintSpec::Kind::kDirection);
    EXPECT_EQ(c.trajectory.size(), 3u);
    EXPECT_TRUE(c.smooth);
    EXPECT_FLOAT_EQ(c.radius, 0.3f);
    EXPECT_FLOAT_EQ(c.weight, 0.5f);
}

}  // namespace
}  // namespace wisp
