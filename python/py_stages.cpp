// wisp.generate and the pipeline's stages one at a time (solve/pipeline.hpp), run without the
// GIL in a task arena of the call's thread count.
#include "bindings.hpp"
#include "core/error.hpp"
#include "dynamics/animate.hpp"
#include "dynamics/motion.hpp"
#include "geometry/mesh_distance.hpp"
#include "groom/master.hpp"
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

// JSON (the figures the CLI writes) as Python dicts, lists and numbers.
py::object to_python(const nlohmann::json& j) {
    return py::module_::import("json").attr("loads")(j.dump());
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

// `ties`: a sequence of (x, y, z) or (x, y, z, radius) in cm (radius 2 by default), or an
// array T×3 or T×4, as `wisp animate --tie x,y,z[,radius]`.
std::vector<Tie> ties_from(const py::object& ties) {
    std::vector<Tie> out;
    if (ties.is_none()) return out;
    if (py::isinstance<py::str>(ties) || !py::isinstance<py::iterable>(ties))
        throw py::type_error("ties: expected a sequence of (x, y, z) or (x, y, z, radius)");
    size_t t = 0;
    for (const py::handle item : ties) {
        const std::string name = cat("ties[", t++, "]");
        py::object numbers;
        try {
            numbers = py::module_::import("numpy").attr("asarray")(item, "float64");
        } catch (const py::error_already_set&) {
            throw py::type_error(cat(name, ": expected numbers x, y, z[, radius]"));
        }
        const auto v = float_array(numbers, name, -1, 0, "(3,) or (4,): x, y, z[, radius]");
        if (v.shape(0) != 3 && v.shape(0) != 4)
            throw py::value_error(
                cat(name, ": expected x, y, z or x, y, z, radius, got ", v.shape(0), " numbers"));
        Tie tie;
        tie.point = Vec3f(v.at(0), v.at(1), v.at(2));
        if (v.shape(0) == 4) {
            tie.radius = v.at(3);
            if (!(tie.radius > 0))
                throw py::value_error(cat(name, ": the radius must be > 0 cm, got ", tie.radius));
        }
        out.push_back(tie);
    }
    return out;
}

// Roots from a user's arrays: each position snapped to the nearest point of the head's
// surface (within kMaxRootDistance), its normal and scalp UV taken there; wisp radii from
// the members.
constexpr float kMaxRootDistance = 1.f;  // cm

SurfacePoint snap_root(const Head& head, const MeshDistance& surface, const Vec3f& p,
                       const std::string& name, ssize row) {
    uint32_t face = 0;
    const Vec3f q = surface.closest_point(p, &face);
    const float d = (q - p).norm();
    if (!(d <= kMaxRootDistance))
        throw py::value_error(cat(name, ": row ", row, " (", p.x(), ", ", p.y(), ", ", p.z(),
                                  ") is ", d, " cm from the head's surface; roots must lie within ",
                                  kMaxRootDistance, " cm of it"));
    const Mesh& mesh = *head.mesh;
    const Vec3i& f = mesh.faces[face];
    const Vec3f a = mesh.vertices[f[0]], e1 = mesh.vertices[f[1]] - a, e2 = mesh.vertices[f[2]] - a;
    // Barycentrics of q (on the triangle) by least squares on the two edges.
    const float d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const float r1 = (q - a).dot(e1), r2 = (q - a).dot(e2), det = d11 * d22 - d12 * d12;
    Vec2f bary(0.f, 0.f);
    if (det > 0) bary = Vec2f((d22 * r1 - d12 * r2) / det, (d11 * r2 - d12 * r1) / det);
    SurfacePoint sp = head.scalp->point_on(face, bary);
    sp.position = p;  // the user's point, not moved
    return sp;
}

std::shared_ptr<Roots> roots_from_arrays(const HeadPtr& head, const py::object& masters_in,
                                         const py::object& members_in,
                                         const py::object& offsets_in) {
    if (!head) throw py::type_error("head: expected a wisp.Head, got None");
    const auto m = float_array(masters_in, "master_positions", -1, 3, "(W, 3)");
    const ssize W = m.shape(0);
    if (W < 1) throw py::value_error("master_positions: expected at least one wisp, got 0");
    const auto s = float_array(members_in, "member_positions", -1, 3, "(S, 3)");
    const ssize S = s.shape(0);
    const std::vector<int64_t> o =
        offsets_array(offsets_in, "wisp_offsets", W + 1, "(W + 1,)", S, "the member count");
    auto roots = std::make_shared<Roots>();
    py::gil_scoped_release release;
    const MeshDistance surface(*head->mesh);
    const auto point = [](const float* p, ssize i) {
        return Vec3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    };
    // py::value_error is a C++ exception: thrown here, it is raised once the GIL is back.
    for (ssize w = 0; w < W; ++w)
        roots->masters.push_back(
            snap_root(*head, surface, point(m.data(), w), "master_positions", w));
    for (ssize i = 0; i < S; ++i)
        roots->members.push_back(
            snap_root(*head, surface, point(s.data(), i), "member_positions", i));
    roots->wisp_offsets.assign(o.begin(), o.end());
    roots->wisp_radius.assign(W, 0.f);
    for (ssize w = 0; w < W; ++w)
        for (int64_t i = o[w]; i < o[w + 1]; ++i)
            roots->wisp_radius[w] =
                std::max(roots->wisp_radius[w],
                         (roots->members[i].position - roots->masters[w].position).norm());
    return roots;
}

// A W×n×3 float array as its float32 values, checked: name, shape and finiteness.
std::vector<float> master_array(const py::object& o, const std::string& name, ssize W, ssize n) {
    py::array a = as_array(o, name);
    if (a.dtype().kind() != 'f')
        throw py::type_error(
            cat(name, ": expected a floating-point array (float32 or float64), got dtype ",
                dtype_text(a)));
    if (a.ndim() != 3 || a.shape(0) != W || a.shape(1) != n || a.shape(2) != 3)
        throw py::value_error(
            cat(name, ": expected shape (", W, ", ", n, ", 3), got ", shape_text(a)));
    auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    const float* p = f.data();
    for (ssize i = 0; i < f.size(); ++i)
        if (!std::isfinite(p[i]) || std::abs(p[i]) > 1e5f)
            throw py::value_error(cat(name, "[", i / (3 * n), ", ", (i / 3) % n,
                                      "]: not a finite coordinate within 1 km (", p[i], ")"));
    return {p, p + f.size()};
}

// Masters with a user's outline and/or details (W×n×3): frames and control points follow
// (update_master); each master's segment length becomes its outline's mean.
std::shared_ptr<Masters> replace_masters(const Masters& in, const py::object& outline,
                                         const py::object& details) {
    auto out = std::make_shared<Masters>(in);
    const ssize W = static_cast<ssize>(in.count()), n = in.points;
    const auto copy = [&](const std::vector<float>& v, std::vector<Vec3f>& to) {
        std::copy_n(v.data(), v.size(), to.data()->data());
    };
    if (!outline.is_none()) {
        const std::vector<float> v = master_array(outline, "outline", W, n);
        for (ssize w = 0; w < W; ++w) {
            const Vec3f first(v[3 * w * n], v[3 * w * n + 1], v[3 * w * n + 2]);
            const float d = (first - in.roots[w].position).norm();
            if (d > 0.01f)
                throw py::value_error(cat("outline[", w, ", 0]: the first joint must be master ", w,
                                          "'s root (within 0.01 cm), but it is ", d,
                                          " cm from it"));
        }
        copy(v, out->outline);
        for (ssize w = 0; w < W; ++w) {
            float length = 0;
            for (ssize i = 1; i < n; ++i)
                length += (out->outline[w * n + i] - out->outline[w * n + i - 1]).norm();
            if (!(length > 0))
                throw py::value_error(cat("outline[", w, "]: the master has zero length"));
            out->segment[w] = length / static_cast<float>(n - 1);
        }
    }
    if (!details.is_none()) copy(master_array(details, "details", W, n), out->details);
    for (ssize w = 0; w < W; ++w)
        update_master(*out, static_cast<size_t>(w));
    return out;
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
            stats["solver"] = to_python(solve_stats_json(r.solve, style.solve));
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
        .def_static("from_arrays", &roots_from_arrays, py::arg("head"), py::arg("master_positions"),
                    py::arg("member_positions"), py::arg("wisp_offsets"),
                    R"(Roots from one's own arrays, for the masters stage and after.

master_positions: W×3 float, cm, head space: one root per wisp (W ≥ 1).
member_positions: S×3 float, cm: the member roots, grouped by wisp.
wisp_offsets: W+1 integers: wisp w owns member_positions[wisp_offsets[w]:wisp_offsets[w+1]]
(0 first, non-decreasing, S last).
Every root must lie within 1 cm of the head's surface: it keeps its position and takes the
normal and scalp UV of the nearest surface point; a wisp's radius is its farthest member.
Raises TypeError or ValueError naming the array, the row and what was expected.)")
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
        .def_property_readonly(
            "details",
            [](py::object self) {
                const Masters& ms = self.cast<const Masters&>();
                return view(self, ms.details.empty() ? nullptr : ms.details.data()->data(),
                            {static_cast<ssize>(ms.count()), ms.points, 3}, false);
            },
            "W×n×3 float32 details δ_i in the frame of segment i, cm (read-only view)")
        .def("replaced", &replace_masters, py::arg("outline") = py::none(),
             py::arg("details") = py::none(),
             R"(A copy of these masters with one's own outline and/or details, for the solve
or members stage.

outline: W×n×3 float, cm, head space: the joint centres of every master (n =
points_per_master); the first joint of master w must be its root (within 0.01 cm). Each
master's segment length becomes its outline's length / (n − 1).
details: W×n×3 float, cm: δ_i in the frame of segment i (Choe & Ko §2.2).
Frames and control points are recomputed from them. Raises TypeError or ValueError naming
the array, the master and what was expected.)")
        .def("__len__", &Masters::count);

    // The Adaptive Wisp Tree run of `wisp animate` (dynamics/animate.hpp) on a style's hair
    // (generated here, its ties held) or on a Hair; on_frame(index, time_s, points P×3 float32
    // (a copy: the next frame reuses the memory), head rotation 3×3, head translation 3) is
    // called with the GIL for every frame. Returns the run's stats.
    m.def(
        "animate",
        [](const PyStyle& s, const std::shared_ptr<Hair>& hair_in, const HeadPtr& head_in,
           const std::string& motion_name, int frames, double fps, const py::object& seed,
           const py::object& threads, const py::object& ties_in, const py::function& on_frame) {
            const std::vector<Tie> ties = ties_from(ties_in);
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
                hair_in->validate("Hair");  // its arrays are writable views
                rest = *hair_in;
            } else {
                HairstyleResult r =
                    run_released(n, [&] { return generate_hairstyle(style, *head); });
                rest = std::move(r.hair);
                settings.wisp_held = std::move(r.solve.held_length);
            }
            settings.strand_held = run_released(n, [&] { return tie_holds(rest, ties); });
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
            py::dict out = to_python(animation_stats_json(stats, rest, motion, frames, fps));
            out["rest"] = std::make_shared<Hair>(std::move(rest));
            return out;
        },
        py::arg("style"), py::arg("hair"), py::arg("head"), py::arg("motion"), py::arg("frames"),
        py::arg("fps"), py::arg("seed"), py::arg("threads"), py::arg("ties"), py::arg("on_frame"));

    m.def("motion_names", &motion_preset_names, "The motion presets' names");
    m.def(
        "check_ties", [](const py::object& ties) { ties_from(ties); }, py::arg("ties"),
        "Raises TypeError or ValueError naming the tie if `ties` is not a sequence of (x, y, z) "
        "or (x, y, z, radius > 0)");
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
            return py::make_tuple(solved, to_python(solve_stats_json(stats, s.style.solve)));
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
            hair.validate("Hair");
            run_released(thread_count(threads), [&] {
                color_stage(s.style, hair);
                return 0;
            });
        },
        py::arg("style"), py::arg("hair"), py::arg("threads") = py::none());
}

}  // namespace wisp::python
