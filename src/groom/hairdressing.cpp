#include "groom/hairdressing.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace wisp {
namespace {

ConstraintSpec point_constraint(const Vec3f& point, float radius, float weight) {
    ConstraintSpec c;
    c.kind = ConstraintSpec::Kind::kPoint;
    c.point = point;
    c.radius = radius;
    c.weight = weight;
    c.hold = true;  // a tie
    return c;
}

ConstraintSpec trajectory_constraint(ConstraintSpec::Kind kind, std::vector<Vec3f> trajectory,
                                     bool smooth, float radius, float weight) {
    ConstraintSpec c;
    c.kind = kind;
    c.trajectory = std::move(trajectory);
    c.smooth = smooth;
    c.radius = radius;
    c.weight = weight;
    return c;
}

}  // namespace

std::vector<GroupSpec> tie_groups(const TieSpec& spec) {
    GroupSpec group;
    group.name = "tie";
    group.selection = spec.selection;
    group.queue.push_back(point_constraint(spec.point, spec.radius, spec.weight));
    return {std::move(group)};
}

std::vector<Vec3f> braid_trajectory(const BraidSpec& spec, int strand, int samples) {
    samples = std::max(samples, 2);
    const int strands = std::max(spec.strands, 1);
    const Vec3f axis = unit_or(spec.axis, -Vec3f::UnitY(), 1e-12f);
    // The width direction is the part of `side` across the axis; the depth direction makes
    // strands pass over and under each other where they cross.
    const Frame frame = frame_from(axis, spec.side);
    const Vec3f side = frame.n;
    const Vec3f depth = axis.cross(side);
    const float phase = 2.f * kPi * float(strand) / float(strands);
    const float cycles = spec.period > 0.f ? spec.length / spec.period : 0.f;
    std::vector<Vec3f> points;
    points.reserve(samples);
    for (int k = 0; k < samples; ++k) {
        const float t = float(k) / float(samples - 1);
        const float angle = 2.f * kPi * t * cycles + phase;
        points.push_back(spec.start + t * spec.length * axis +
                         (0.5f * spec.width * std::sin(angle)) * side +
                         (0.25f * spec.width * std::sin(2.f * angle)) * depth);
    }
    return points;
}

std::vector<GroupSpec> braid_groups(const BraidSpec& spec) {
    // Enough samples that a Catmull-Rom curve through them keeps each crossing's shape.
    const float cycles = spec.period > 0.f ? spec.length / spec.period : 1.f;
    const int samples = std::clamp(int(std::ceil(cycles * 16.f)) + 1, 17, 1025);
    std::vector<GroupSpec> groups;
    groups.reserve(spec.strands);
    for (int i = 0; i < spec.strands; ++i) {
        GroupSpec group;
        group.name = "braid strand " + std::to_string(i);
        group.selection = spec.selection;
        group.selection.part = i;
        group.selection.parts = spec.strands;
        group.queue.push_back(point_constraint(spec.start, spec.radius, spec.weight));
        group.queue.push_back(trajectory_constraint(ConstraintSpec::Kind::kTrajectory,
                                                    braid_trajectory(spec, i, samples), true,
                                                    spec.radius, spec.weight));
        groups.push_back(std::move(group));
    }
    return groups;
}

std::vector<GroupSpec> updo_groups(const UpdoSpec& spec) {
    // The bun's plane: `up` is world up projected onto it, so the spiral leaves the tie
    // point upward whatever the facing.
    const Vec3f facing = unit_or(spec.facing, -Vec3f::UnitZ(), 1e-12f);
    const Frame frame = frame_from(facing, Vec3f::UnitY());
    const Vec3f up = frame.n, across = frame.b;
    // r = bun_radius·√t: a Fermat spiral, so the first turn is already wide enough for wisps
    // to follow and the turns lie evenly spaced in area, as a coiled bun does.
    const float turns = std::max(spec.turns, 0.f);
    const int samples = std::clamp(int(std::ceil(turns * 24.f)) + 1, 9, 2049);
    std::vector<Vec3f> spiral;
    spiral.reserve(samples);
    for (int k = 0; k < samples; ++k) {
        const float t = float(k) / float(samples - 1);
        const float angle = 2.f * kPi * turns * t;
        const float r = spec.bun_radius * std::sqrt(t);
        spiral.push_back(spec.point + r * (std::cos(angle) * up + std::sin(angle) * across));
    }
    GroupSpec group;
    group.name = "updo";
    group.selection = spec.selection;
    group.queue.push_back(point_constraint(spec.point, spec.radius, spec.weight));
    group.queue.push_back(trajectory_constraint(ConstraintSpec::Kind::kTrajectory,
                                                std::move(spiral), true, spec.radius, spec.weight));
    group.queue.back().hold = true;  // pinned: the bun moves with the head
    // Hair longer than the spiral winds on round its outer turn, tucked into the bun.
    group.queue.back().repeat = turns > 1.f ? 1.f / turns : 1.f;
    return {std::move(group)};
}

std::vector<GroupSpec> comb_groups(const CombSpec& spec) {
    GroupSpec group;
    group.name = "comb";
    group.selection = spec.selection;
    group.queue.push_back(trajectory_constraint(ConstraintSpec::Kind::kDirection, spec.trajectory,
                                                spec.smooth, spec.radius, spec.weight));
    return {std::move(group)};
}

}  // namespace wisp
