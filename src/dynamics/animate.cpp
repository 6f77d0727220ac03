#include "dynamics/animate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/timer.hpp"

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
    // Down to where the hair reaches (long hair lies on the chest and the back), with as many
    // spheres per head radius of height as the default fit spends above the chest.
    BodyFitOptions options;
    float lowest = head.center.y();
    for (const Vec3f& p : h.rest)
        lowest = std::min(lowest, p.y());
    const float reach = (head.center.y() - lowest) / head.radius + 0.5f;
    if (reach > options.reach) {
        options.max_spheres = std::min(
            64, static_cast<int>(std::lround(options.max_spheres * reach / options.reach)));
        options.reach = reach;
    }
    std::vector<Sphere> spheres = fit_body_spheres(body, head, options);
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

Animator::Animator(const Hair& rest, const Mesh& body, const HeadFrame& head, const Motion& motion,
                   const DynamicsSpec& spec, PrototypeSpec::Kind prototype,
                   const AnimateSettings& settings)
    : rest_(rest), frame_stats_(settings.frame_stats), max_frame_events_(settings.frame_events) {
    frame_events_.reserve(max_frame_events_);
    if (!(settings.fps > 0) || !std::isfinite(settings.fps) || settings.fps > 1000)
        fail("animate: fps must be in (0, 1000], got ", settings.fps);
    AwtParams params = awt_params(spec, prototype, settings.single_level);
    stats_.rigid = params.rigid;
    stats_.steps_per_frame =
        std::max(1, static_cast<int>(std::lround(1.0 / (settings.fps * params.dt))));
    stats_.dt = 1.0 / (settings.fps * stats_.steps_per_frame);
    params.dt = static_cast<float>(stats_.dt);

    Stopwatch watch;
    HierarchyOptions options = hierarchy_options(spec);
    options.wisp_held = settings.wisp_held;
    options.strand_held = settings.strand_held;
    hierarchy_ = build_hierarchy(rest, options);
    const Hierarchy& h = hierarchy_;
    stats_.hierarchy_ms = watch.ms();
    stats_.levels = h.levels;
    stats_.sections = h.sections;
    stats_.gcs = h.gc_count();
    stats_.nodes = h.node_count();
    stats_.finest_nodes = static_cast<size_t>(h.gc_count() - h.finest_begin()) * h.sections;
    for (uint32_t g = h.finest_begin(); g < h.gc_count(); ++g)
        for (int k = 1; k < h.sections; ++k)
            stats_.held_finest_nodes += h.held[h.node(g, k)] >= 1;
    for (int l = 0; l < h.levels; ++l)
        stats_.gcs_per_level.push_back(h.level_size(l));

    watch = Stopwatch();
    std::vector<Sphere> spheres;
    if (params.body_collisions) spheres = body_spheres_for(body, head, h);
    stats_.spheres = spheres.size();
    stats_.bodies_ms = watch.ms();

    watch = Stopwatch();
    binding_ = bind_strands(rest, h);
    stats_.bind_ms = watch.ms();

    sim_ = std::make_unique<AwtSimulation>(hierarchy_, std::move(spheres), &motion, params, 0.0);
}

void Animator::set_dynamics(const DynamicsSpec& spec, PrototypeSpec::Kind prototype) {
    sim_->set_params(awt_params(spec, prototype, sim_->params().single_level));
}

void Animator::advance() {
    AwtSimulation& sim = *sim_;
    frame_events_.clear();
    if (++frame_ > 0)
        for (int s = 0; s < stats_.steps_per_frame; ++s) {
            Stopwatch step;
            sim.step();
            const double ms = step.ms();
            step_total_ += ms;
            stats_.step_ms_max = std::max(stats_.step_ms_max, ms);
            ++stats_.steps;
            const AwtStepStats& last = sim.last_step();
            stats_.pair_tests += last.pair_tests;
            stats_.hair_contacts += last.hair_contacts;
            stats_.body_contacts += last.body_contacts;
            // Where each happened at its own step: a frame of several steps flashes them all.
            const std::span<const Vec3f> x = sim.positions();
            for (const AwtEvent& e : sim.last_events())
                if (frame_events_.size() < max_frame_events_)
                    frame_events_.push_back({x[e.node], e.kind});
            const double e = sim.kinetic_energy();
            if (!std::isfinite(e))
                fail("animate: the simulation diverged at t = ", sim.time(),
                     " s (lower dt or stiffness)");
            stats_.max_kinetic_energy = std::max(stats_.max_kinetic_energy, e);
        }
    Stopwatch sync;
    sim.sync();
    sim.finest_rotations(rotations_);
    skin_total_ += sync.ms();
    if (frame_stats_) {
        stats_.active_per_level.push_back(sim.active_per_level());
        stats_.frame_splits.push_back(static_cast<uint32_t>(sim.total_splits() - splits_before_));
        stats_.frame_merges.push_back(static_cast<uint32_t>(sim.total_merges() - merges_before_));
    }
    splits_before_ = sim.total_splits();
    merges_before_ = sim.total_merges();
}

FramePose Animator::pose() const {
    return FramePose{sim_->time(), sim_->head_transform(), sim_->body_transform()};
}

void Animator::skin(Hair& out) {
    Stopwatch watch;
    skin_strands(hierarchy_, binding_, sim_->positions(), rotations_, out);
    skin_total_ += watch.ms();
    ++skins_;
}

void Animator::skin(std::span<const uint32_t> strands, std::span<Vec3f> points) {
    Stopwatch watch;
    if (!std::ranges::equal(strands, subset_.strands))
        subset_ = bind_subset(hierarchy_, binding_, rest_.offsets, strands);
    skin_strands(hierarchy_, subset_, sim_->positions(), rotations_, points);
    skin_total_ += watch.ms();
    ++skins_;
}

void Animator::skin(std::span<const uint32_t> strands, std::span<char> xyz) {
    Stopwatch watch;
    if (!std::ranges::equal(strands, subset_.strands))
        subset_ = bind_subset(hierarchy_, binding_, rest_.offsets, strands);
    skin_strands(hierarchy_, subset_, sim_->positions(), rotations_, xyz);
    skin_total_ += watch.ms();
    ++skins_;
}

AnimationStats Animator::stats() const {
    AnimationStats s = stats_;
    s.splits = sim_->total_splits();
    s.merges = sim_->total_merges();
    s.step_ms_mean = s.steps ? step_total_ / static_cast<double>(s.steps) : 0;
    s.skin_ms_mean = frame_ >= 0 ? skin_total_ / (frame_ + 1) : 0;
    return s;
}

AnimationStats animate(const Hair& rest, const Mesh& body, const HeadFrame& head,
                       const Motion& motion, const DynamicsSpec& spec,
                       PrototypeSpec::Kind prototype, const AnimateSettings& settings,
                       const std::function<void(int, const Hair&, const FramePose&)>& frame) {
    if (settings.frames < 1) fail("animate: frames must be ≥ 1, got ", settings.frames);
    Animator animator(rest, body, head, motion, spec, prototype, settings);
    Hair moved = rest;
    for (int f = 0; f < settings.frames; ++f) {
        animator.advance();
        animator.skin(moved);
        frame(f, moved, animator.pose());
    }
    return animator.stats();
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

nlohmann::json animation_stats_json(const AnimationStats& stats, const Hair& rest,
                                    const Motion& motion, int frames, double fps) {
    nlohmann::json j;
    j["motion"] = motion.name;
    j["frames"] = frames;
    j["fps"] = fps;
    j["strands"] = rest.strand_count();
    j["points"] = rest.point_count();
    j["links"] = stats.rigid ? "rigid" : "soft";
    j["hierarchy"] = {{"levels", stats.levels},
                      {"sections", stats.sections},
                      {"gcs_per_level", stats.gcs_per_level},
                      {"nodes", stats.nodes},
                      {"finest_nodes", stats.finest_nodes},
                      {"held_finest_nodes", stats.held_finest_nodes}};
    j["body_spheres"] = stats.spheres;
    j["steps"] = stats.steps;
    j["steps_per_frame"] = stats.steps_per_frame;
    j["dt_s"] = stats.dt;
    j["ms_per_step"] = {{"mean", stats.step_ms_mean}, {"max", stats.step_ms_max}};
    j["skin_ms_per_frame"] = stats.skin_ms_mean;
    j["splits"] = stats.splits;
    j["merges"] = stats.merges;
    j["hair_pair_tests"] = stats.pair_tests;
    j["hair_contacts"] = stats.hair_contacts;
    j["body_contacts"] = stats.body_contacts;
    j["max_kinetic_energy"] = stats.max_kinetic_energy;
    j["active_nodes_per_level"] = stats.active_per_level;
    j["splits_per_frame"] = stats.frame_splits;
    j["merges_per_frame"] = stats.frame_merges;
    return j;
}

}  // namespace wisp
