#include "dynamics/animate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "dynamics/skin.hpp"

namespace wisp {

HierarchyOptions hierarchy_options(const DynamicsSpec& spec) {
    HierarchyOptions o;
    o.levels = spec.levels;
    o.wisps_per_group = spec.wisps_per_group;
    o.sub_wisps = spec.sub_wisps;
    o.sections = spec.sections;
    o.strands_per_wisp = spec.strands_per_wisp;
    o.linear_density = spec.linear_density;
    return o;
}

std::vector<Sphere> body_spheres_for(const Mesh& body, const HeadFrame& head, const Hierarchy& h) {
    std::vector<Sphere> spheres = fit_body_spheres(body, head);
    // The rest pose must be collision-free: every node past the roots and the child half of
    // its segment (what the body test checks, awt.cpp) clear every sphere.
    for (Sphere& sphere : spheres) {
        for (uint32_t i = 0; i < h.node_count(); ++i) {
            if (h.section_of(i) == 0) continue;
            const Vec3f a = h.rest[i - 1], ab = h.rest[i] - a;
            const float len2 = ab.squaredNorm();
            const float t =
                len2 > 1e-12f ? std::clamp((sphere.center - a).dot(ab) / len2, 0.5f, 1.f) : 1.f;
            sphere.radius = std::min(sphere.radius, (a + t * ab - sphere.center).norm() - 0.05f);
        }
    }
    std::erase_if(spheres, [](const Sphere& s) { return !(s.radius >= 0.25f); });
    return spheres;
}

AnimationStats animate(const Hair& rest, const Mesh& body, const HeadFrame& head,
                       const Motion& motion, const DynamicsSpec& spec,
                       PrototypeSpec::Kind prototype, const AnimateSettings& settings,
                       const std::function<void(int, const Hair&, const FramePose&)>& frame) {
    if (settings.frames < 1) fail("animate: frames must be ≥ 1, got ", settings.frames);
    if (!(settings.fps > 0) || !std::isfinite(settings.fps) || settings.fps > 1000)
        fail("animate: fps must be in (0, 1000], got ", settings.fps);
    AwtParams params = awt_params(spec, prototype, settings.single_level);
    AnimationStats stats;
    stats.rigid = params.rigid;
    stats.steps_per_frame =
        std::max(1, static_cast<int>(std::lround(1.0 / (settings.fps * params.dt))));
    stats.dt = 1.0 / (settings.fps * stats.steps_per_frame);
    params.dt = static_cast<float>(stats.dt);

    Stopwatch watch;
    HierarchyOptions options = hierarchy_options(spec);
    options.wisp_held = settings.wisp_held;
    options.strand_held = settings.strand_held;
    const Hierarchy h = build_hierarchy(rest, options);
    stats.hierarchy_ms = watch.ms();
    stats.levels = h.levels;
    stats.sections = h.sections;
    stats.gcs = h.gc_count();
    stats.nodes = h.node_count();
    stats.finest_nodes = static_cast<size_t>(h.gc_count() - h.finest_begin()) * h.sections;
    for (uint32_t g = h.finest_begin(); g < h.gc_count(); ++g)
        for (int k = 1; k < h.sections; ++k)
            stats.held_finest_nodes += h.held[h.node(g, k)] >= 1;
    for (int l = 0; l < h.levels; ++l)
        stats.gcs_per_level.push_back(h.level_size(l));

    watch = Stopwatch();
    std::vector<Sphere> spheres;
    if (params.body_collisions) spheres = body_spheres_for(body, head, h);
    stats.spheres = spheres.size();
    stats.bodies_ms = watch.ms();

    watch = Stopwatch();
    const StrandBinding binding = bind_strands(rest, h);
    stats.bind_ms = watch.ms();

    AwtSimulation sim(h, std::move(spheres), motion, params, 0.0);
    Hair moved = rest;
    std::vector<Mat3f> rotations;
    double skin_total = 0, step_total = 0;
    uint64_t splits_before = 0, merges_before = 0;
    for (int f = 0; f < settings.frames; ++f) {
        if (f > 0)
            for (int s = 0; s < stats.steps_per_frame; ++s) {
                Stopwatch step;
                sim.step();
                const double ms = step.ms();
                step_total += ms;
                stats.step_ms_max = std::max(stats.step_ms_max, ms);
                ++stats.steps;
                const AwtStepStats& last = sim.last_step();
                stats.pair_tests += last.pair_tests;
                stats.hair_contacts += last.hair_contacts;
                stats.body_contacts += last.body_contacts;
                const double e = sim.kinetic_energy();
                if (!std::isfinite(e))
                    fail("animate: the simulation diverged at t = ", sim.time(),
                         " s (lower dt or stiffness)");
                stats.max_kinetic_energy = std::max(stats.max_kinetic_energy, e);
            }
        Stopwatch skin;
        sim.sync();
        sim.finest_rotations(rotations);
        skin_strands(h, binding, sim.positions(), rotations, moved);
        skin_total += skin.ms();
        stats.active_per_level.push_back(sim.active_per_level());
        stats.frame_splits.push_back(static_cast<uint32_t>(sim.total_splits() - splits_before));
        stats.frame_merges.push_back(static_cast<uint32_t>(sim.total_merges() - merges_before));
        splits_before = sim.total_splits();
        merges_before = sim.total_merges();
        frame(f, moved, FramePose{sim.time(), sim.head_transform(), sim.body_transform()});
    }
    stats.splits = sim.total_splits();
    stats.merges = sim.total_merges();
    stats.step_ms_mean = stats.steps ? step_total / static_cast<double>(stats.steps) : 0;
    stats.skin_ms_mean = skin_total / settings.frames;
    return stats;
}

}  // namespace wisp

namespace wisp {

Mesh pose_body(const Mesh& body, const HeadFrame& head, const FramePose& pose) {
    Mesh posed = body;
    const float top = head.center.y() - 0.8f * head.radius;     // chin level
    const float bottom = head.center.y() - 1.6f * head.radius;  // neck base
    for (Vec3f& v : posed.vertices) {
        const float w = std::clamp((v.y() - bottom) / (top - bottom), 0.f, 1.f);
        v = w * pose.head.apply(v) + (1 - w) * pose.body.apply(v);
    }
    return posed;
}

}  // namespace wisp
