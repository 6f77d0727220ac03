// wisp.generate and the pipeline's stages one at a time (solve/pipeline.hpp), run without the
// GIL in a task arena of the call's thread count.
#include "bindings.hpp"
#include "core/error.hpp"
#include "dynamics/animate.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp::python {
namespace {

using ssize = py::ssize_t;

// The style with the call's seed (checked as the style's `seed` field is).
Style with_seed(const PyStyle& s, const py::object& seed) {
    Style style = s.style;
    if (!seed.is_none()) {
        if (py::isinstance<py::bool_>(seed) || !py::isinstance<py::int_>(seed))
            throw py::type_error("seed: expected None or an integer");
        set_style_field(style, "seed", py::str(seed).cast<std::string>(), "generate");
    }
    return style;
}

HeadPtr head_for(const Style& style, const HeadPtr& head) {
    if (head) return head;
    return std::make_shared<Head>(run_released(0, [&] { return load_head(style.head); }));
}

py::dict solve_stats(const SolveStats& solve, bool enabled) {
    py::dict d;
    d["enabled"] = enabled;
    d["joints"] = solve.joints;
    d["collision_iterations"] = solve.bends;
    d["colliding_joints"] = solve.collisions;
    d["unresolved_joints"] = solve.unresolved;
    d["projected_joints"] = solve.projected;
    d["constrained_joints"] = solve.constrained;
    py::list groups;
    for (const SolveStats::Group& g : solve.groups) {
        py::dict e;
        e["name"] = g.name;
        e["constraints"] = g.constraints;
        e["completed"] = g.completed;
        e["wisps"] = g.wisps;
        e["met"] = g.met;
        groups.append(e);
    }
    d["groups"] = groups;
    return d;
}

py::dict times_dict(const StageTimes& times) {
    py::dict d;
    for (const auto& [stage, ms] : times)
        d[py::str(stage)] = ms;
    return d;
}

template <typename T>
py::array points_view(const py::object& owner, const std::vector<T>& v, ssize cols) {
    return view(owner, v.empty() ? nullptr : v.data()->data(), {static_cast<ssize>(v.size()), cols},
                false);
}

// A surface point array as its positions (#×3), normals (#×3) and scalp UVs (#×2).
py::array surface_positions(const std::vector<SurfacePoint>& ps) {
    py::array_t<float> out({static_cast<ssize>(ps.size()), ssize(3)});
    for (size_t i = 0; i < ps.size(); ++i)
        for (int k = 0; k < 3; ++k)
            out.mutable_at(i, k) = ps[i].position[k];
    return out;
}

py::dict animation_stats(const AnimationStats& stats, const Hair& rest, const Motion& motion,
                         int frames, double fps) {
    py::dict j;
    j["motion"] = motion.name;
    j["frames"] = frames;
    j["fps"] = fps;
    j["strands"] = rest.strand_count();
    j["points"] = rest.point_count();
    j["links"] = stats.rigid ? "rigid" : "soft";
    py::dict h;
    h["levels"] = stats.levels;
    h["sections"] = stats.sections;
    h["gcs_per_level"] = stats.gcs_per_level;
    h["nodes"] = stats.nodes;
    h["finest_nodes"] = stats.finest_nodes;
    h["held_finest_nodes"] = stats.held_finest_nodes;
    j["hierarchy"] = h;
    j["body_spheres"] = stats.spheres;
    j["steps"] = stats.steps;
    j["steps_per_frame"] = stats.steps_per_frame;
    j["dt_s"] = stats.dt;
    j["ms_per_step"] =
        py::dict(py::arg("mean") = stats.step_ms_mean, py::arg("max") = stats.step_ms_max);
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

}  // namespace

void bind_stages(py::module_& m) {
    m.def(
        "generate",
        [](const PyStyle& s, const HeadPtr& head_in, const py::object& seed,
           const py::object& threads) {
            const Style style = with_seed(s, seed);
            const int n = thread_count(threads);
            const HeadPtr head = head_for(style, head_in);
            HairstyleResult r = run_released(n, [&] { return generate_hairstyle(style, *head); });
            py::dict stats;
            stats["strands"] = r.hair.strand_count();
            stats["points"] = r.hair.point_count();
            stats["wisps"] = r.masters.count();
            stats["seed"] = style.seed;
            stats["style"] = style.name;
            stats["head"] = head->source;
            stats["time_ms"] = times_dict(r.times);
            stats["solver"] = solve_stats(r.solve, style.solve.enabled);
            stats["points_pushed_out_of_head"] = r.points_pushed;
            stats["points_inside_head"] = r.points_inside_head;
            stats["strands_cut"] = r.strands_cut;
            stats["strands_removed_by_cut"] = r.strands_removed;
            auto hair = std::make_shared<Hair>(std::move(r.hair));
            return py::make_tuple(hair, stats, head);
        },
        py::arg("style"), py::arg("head"), py::arg("seed"), py::arg("threads"));

    // The statistical model alone (groom/generate.hpp: roots, masters, members, colour, no
    // solver): what bench/generate_bench.cpp's BM_Generate100k times, for the overhead check.
    m.def(
        "generate_model",
        [](const PyStyle& s, const HeadPtr& head_in, const py::object& threads) {
            const HeadPtr head = head_for(s.style, head_in);
            GenerateResult r =
                run_released(thread_count(threads), [&] { return generate(s.style, *head); });
            return std::make_shared<Hair>(std::move(r.hair));
        },
        py::arg("style"), py::arg("head"), py::arg("threads") = py::none());

    py::class_<Roots, std::shared_ptr<Roots>>(m, "Roots", "The roots stage's output (§2.3)")
        .def_property_readonly(
            "master_positions", [](const Roots& r) { return surface_positions(r.masters); },
            "W×3 float32 master roots on the scalp, cm")
        .def_property_readonly(
            "member_positions", [](const Roots& r) { return surface_positions(r.members); },
            "S×3 float32 member roots, cm, grouped by wisp")
        .def_property_readonly(
            "wisp_offsets",
            [](py::object self) {
                const Roots& r = self.cast<const Roots&>();
                return view(self, r.wisp_offsets.data(),
                            {static_cast<ssize>(r.wisp_offsets.size())}, false);
            },
            "W+1 uint32: wisp w owns member_positions[wisp_offsets[w]:wisp_offsets[w+1]]")
        .def_property_readonly(
            "wisp_radius",
            [](py::object self) {
                const Roots& r = self.cast<const Roots&>();
                return view(self, r.wisp_radius.data(), {static_cast<ssize>(r.wisp_radius.size())},
                            false);
            },
            "W float32 root radius of each wisp, cm")
        .def("__len__", [](const Roots& r) { return r.masters.size(); });

    py::class_<Masters, std::shared_ptr<Masters>>(m, "Masters", "Master strands (§2.2)")
        .def_property_readonly("points_per_master", [](const Masters& ms) { return ms.points; })
        .def_property_readonly(
            "control",
            [](py::object self) {
                const Masters& ms = self.cast<const Masters&>();
                return view(self, ms.control.empty() ? nullptr : ms.control.data()->data(),
                            {static_cast<ssize>(ms.count()), ms.points, 3}, false);
            },
            "W×n×3 float32 control points of every master, cm (read-only view)")
        .def_property_readonly(
            "outline",
            [](py::object self) {
                const Masters& ms = self.cast<const Masters&>();
                return view(self, ms.outline.empty() ? nullptr : ms.outline.data()->data(),
                            {static_cast<ssize>(ms.count()), ms.points, 3}, false);
            },
            "W×n×3 float32 outline joint centres, cm (read-only view)")
        .def("__len__", &Masters::count);

    // The Adaptive Wisp Tree run of `wisp animate` (dynamics/animate.hpp) on a style's hair
    // (generated here, its ties held) or on a Hair; on_frame(index, time_s, points P×3 float32
    // (a copy: the next frame reuses the memory), head rotation 3×3, head translation 3) is
    // called with the GIL for every frame. Returns the run's stats.
    m.def(
        "animate",
        [](const PyStyle& s, const std::shared_ptr<Hair>& hair_in, const HeadPtr& head_in,
           const std::string& motion_name, int frames, double fps, const py::object& seed,
           const py::object& threads, const py::function& on_frame) {
            if (frames < 1 || frames > 100000)
                throw py::value_error(cat("frames: expected 1 to 100000, got ", frames));
            if (!(fps > 0 && fps <= 1000))
                throw py::value_error(cat("fps: expected > 0 and <= 1000, got ", fps));
            const Style style = with_seed(s, seed);
            const int n = thread_count(threads);
            const HeadPtr head = head_for(style, head_in);
            const HeadFrame frame = head_frame(*head->scalp);
            const Motion motion = load_motion(motion_name, frame);
            AnimateSettings settings;
            settings.frames = frames;
            settings.fps = fps;
            Hair rest;
            if (hair_in) {
                rest = *hair_in;
            } else {
                HairstyleResult r =
                    run_released(n, [&] { return generate_hairstyle(style, *head); });
                rest = std::move(r.hair);
                settings.wisp_held = std::move(r.solve.held_length);
            }
            const AnimationStats stats = run_released(n, [&] {
                return animate(rest, *head->mesh, frame, motion, style.dynamics,
                               style.prototype.kind, settings,
                               [&](int f, const Hair& hair, const FramePose& pose) {
                                   py::gil_scoped_acquire gil;
                                   py::array_t<float> points(
                                       {static_cast<ssize>(hair.point_count()), ssize(3)});
                                   std::copy_n(hair.points.data()->data(), 3 * hair.point_count(),
                                               points.mutable_data());
                                   py::array_t<float> rotation({ssize(3), ssize(3)});
                                   py::array_t<float> translation(ssize(3));
                                   for (int r = 0; r < 3; ++r) {
                                       translation.mutable_at(r) = pose.head.translation[r];
                                       for (int c = 0; c < 3; ++c)
                                           rotation.mutable_at(r, c) = pose.head.rotation(r, c);
                                   }
                                   on_frame(f, pose.time, points, rotation, translation);
                               });
            });
            py::dict out = animation_stats(stats, rest, motion, frames, fps);
            out["rest"] = std::make_shared<Hair>(std::move(rest));
            return out;
        },
        py::arg("style"), py::arg("hair"), py::arg("head"), py::arg("motion"), py::arg("frames"),
        py::arg("fps"), py::arg("seed"), py::arg("threads"), py::arg("on_frame"));

    m.def(
        "stage_roots",
        [](const PyStyle& s, const HeadPtr& head, const py::object& threads) {
            return std::make_shared<Roots>(
                run_released(thread_count(threads), [&] { return grow_roots(s.style, *head); }));
        },
        py::arg("style"), py::arg("head"), py::arg("threads") = py::none());
    m.def(
        "stage_masters",
        [](const PyStyle& s, const HeadPtr& head, const Roots& roots, const py::object& threads) {
            return std::make_shared<Masters>(run_released(
                thread_count(threads), [&] { return synthesize_masters(s.style, *head, roots); }));
        },
        py::arg("style"), py::arg("head"), py::arg("roots"), py::arg("threads") = py::none());
    m.def(
        "stage_solve",
        [](const PyStyle& s, const HeadPtr& head, const Roots& roots, const Masters& masters,
           const py::object& threads) {
            auto solved = std::make_shared<Masters>(masters);
            SolveStats stats;
            run_released(thread_count(threads), [&] {
                const HeadField field = build_head_field(s.style, *head);
                const GroupSelection groups = select_groups(s.style, *head, roots);
                if (s.style.solve.enabled)
                    stats = solve_stage(s.style, *head, field, roots, groups, *solved);
                return 0;
            });
            return py::make_tuple(solved, solve_stats(stats, s.style.solve.enabled));
        },
        py::arg("style"), py::arg("head"), py::arg("roots"), py::arg("masters"),
        py::arg("threads") = py::none());
    m.def(
        "stage_members",
        [](const PyStyle& s, const HeadPtr& head, const Roots& roots, const Masters& masters,
           const py::object& threads) {
            if (masters.count() != roots.masters.size())
                throw py::value_error(cat("masters: ", masters.count(), " masters for ",
                                          roots.masters.size(), " wisps of the roots"));
            return std::make_shared<Hair>(run_released(thread_count(threads), [&] {
                const HeadField field = build_head_field(s.style, *head);
                const GroupSelection groups = select_groups(s.style, *head, roots);
                return members_stage(s.style, *head, field, roots, masters, groups.wisp_group).hair;
            }));
        },
        py::arg("style"), py::arg("head"), py::arg("roots"), py::arg("masters"),
        py::arg("threads") = py::none());
    m.def(
        "stage_color",
        [](const PyStyle& s, Hair& hair, const py::object& threads) {
            run_released(thread_count(threads), [&] {
                color_stage(s.style, hair);
                return 0;
            });
        },
        py::arg("style"), py::arg("hair"), py::arg("threads") = py::none());
}

}  // namespace wisp::python
