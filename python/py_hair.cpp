// wisp.Head and wisp.Hair: their arrays as numpy views of the C++ vectors (no copy; the
// array's base is the owning object), Hair.from_arrays checked at the boundary, and every
// format the CLI reads and writes through io/hair_io.hpp's dispatch by extension.
#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "core/catmull_rom.hpp"
#include "core/error.hpp"
#include "core/hair.hpp"
#include "core/parallel.hpp"
#include "geometry/builtin_head.hpp"
#include "groom/style_toml.hpp"
#include "io/hair_io.hpp"
#include "render/export_view.hpp"

namespace wisp::python {

using ssize = py::ssize_t;

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (ssize i = 0; i < a.ndim(); ++i)
        s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) {
    return py::str(a.dtype()).cast<std::string>();
}

py::array as_array(const py::object& o, const std::string& name) {
    if (o.is_none()) throw py::type_error(name + ": expected an array, got None");
    py::array a = py::module_::import("numpy").attr("asarray")(o);
    const char kind = a.dtype().kind();
    if (kind == 'O' || kind == 'U' || kind == 'S' || kind == 'V')
        throw py::type_error(name + ": expected a numeric array, got dtype " + dtype_text(a));
    return a;
}

// A float32 copy of a floating-point array of shape (rows, cols) (cols 0: 1-D of rows), every
// value finite.
py::array_t<float, py::array::c_style> float_array(const py::object& o, const std::string& name,
                                                   ssize rows, ssize cols, const char* shape) {
    py::array a = as_array(o, name);
    if (a.dtype().kind() != 'f')
        throw py::type_error(
            cat(name, ": expected a floating-point array (float32 or float64), got dtype ",
                dtype_text(a)));
    const bool ok = cols ? a.ndim() == 2 && a.shape(1) == cols && (rows < 0 || a.shape(0) == rows)
                         : a.ndim() == 1 && (rows < 0 || a.shape(0) == rows);
    if (!ok) throw py::value_error(cat(name, ": expected shape ", shape, ", got ", shape_text(a)));
    auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    const float* p = f.data();
    for (ssize i = 0; i < f.size(); ++i)
        if (!std::isfinite(p[i])) {
            const ssize row = cols ? i / cols : i;
            throw py::value_error(cat(name, ": row ", row, " is not finite (", p[i], ")"));
        }
    return f;
}

std::vector<int64_t> int_array(const py::object& o, const std::string& name, ssize rows,
                               const char* shape) {
    py::array a = as_array(o, name);
    if (a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
        throw py::type_error(cat(name, ": expected an integer array, got dtype ", dtype_text(a)));
    if (a.ndim() != 1 || (rows >= 0 && a.shape(0) != rows))
        throw py::value_error(cat(name, ": expected shape ", shape, ", got ", shape_text(a)));
    if (a.dtype().kind() == 'u' && a.dtype().itemsize() == 8) {
        auto u = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
        for (ssize i = 0; i < u.size(); ++i)
            if (u.data()[i] > uint64_t(std::numeric_limits<int64_t>::max()))
                throw py::value_error(
                    cat(name, ": value ", i, " (", u.data()[i], ") is too large"));
    }
    auto v = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    return {v.data(), v.data() + v.size()};
}

std::vector<int64_t> offsets_array(const py::object& o, const std::string& name, ssize rows,
                                   const char* shape, int64_t last, const char* last_is) {
    const std::vector<int64_t> v = int_array(o, name, rows, shape);
    if (v.empty()) throw py::value_error(cat(name, ": expected at least one value, got none"));
    if (v.front() != 0)
        throw py::value_error(cat(name, ": ", name, "[0] must be 0, got ", v.front()));
    for (size_t i = 1; i < v.size(); ++i)
        if (v[i] < v[i - 1])
            throw py::value_error(cat(name, ": not monotone: ", name, "[", i, "] = ", v[i], " < ",
                                      name, "[", i - 1, "] = ", v[i - 1]));
    if (v.back() != last)
        throw py::value_error(
            cat(name, ": the last offset must be ", last_is, " ", last, ", got ", v.back()));
    return v;
}

namespace {

static_assert(sizeof(Vec3f) == 3 * sizeof(float) && sizeof(Vec2f) == 2 * sizeof(float) &&
                  sizeof(Vec3i) == 3 * sizeof(int),
              "numpy views need packed Eigen vectors");

Hair from_arrays(const py::object& points, const py::object& offsets, const py::object& colors,
                 const py::object& widths, const py::object& wisp_ids) {
    Hair hair;
    const auto p = float_array(points, "points", -1, 3, "(P, 3)");
    const ssize P = p.shape(0);
    const std::vector<int64_t> o =
        offsets_array(offsets, "offsets", -1, "(N + 1,)", P, "the point count");
    if (o.back() > int64_t(std::numeric_limits<uint32_t>::max()))
        throw py::value_error(cat("points: ", P, " points, more than a Hair holds (2^32 - 1)"));
    const ssize N = static_cast<ssize>(o.size()) - 1;
    hair.points.resize(P);
    std::copy_n(p.data(), 3 * P, hair.points.data()->data());
    hair.offsets.assign(o.begin(), o.end());
    if (!colors.is_none()) {
        const auto c = float_array(colors, "colors", N, 3, "(N, 3)");
        hair.colors.resize(N);
        std::copy_n(c.data(), 3 * N, hair.colors.data()->data());
    }
    if (!widths.is_none()) {
        const auto w = float_array(widths, "widths", P, 0, "(P,)");
        for (ssize i = 0; i < P; ++i)
            if (w.data()[i] <= 0)
                throw py::value_error(cat("widths: value ", i, " is ", w.data()[i], ", not > 0"));
        hair.widths.assign(w.data(), w.data() + P);
    }
    if (!wisp_ids.is_none()) {
        const std::vector<int64_t> ids = int_array(wisp_ids, "wisp_ids", N, "(N,)");
        for (size_t i = 0; i < ids.size(); ++i)
            if (ids[i] < -1 || ids[i] > std::numeric_limits<int32_t>::max())
                throw py::value_error(cat("wisp_ids: value ", i, " is ", ids[i],
                                          ", expected -1 (none) or 0 to 2^31 - 1"));
        hair.wisp.assign(ids.begin(), ids.end());
    }
    hair.validate("Hair.from_arrays");
    return hair;
}

size_t strand_index(const Hair& hair, long long i) {
    const long long n = static_cast<long long>(hair.strand_count());
    const long long k = i < 0 ? i + n : i;
    if (k < 0 || k >= n)
        throw py::index_error(cat("strand ", i, " out of range for ", n, " strands"));
    return static_cast<size_t>(k);
}

py::array resampled(const Hair& hair, long long n, int threads) {
    if (n < 2 || n > 4096)
        throw py::value_error(cat("resampled: n must be 2 to 4096 points per strand, got ", n));
    hair.validate("Hair");  // its arrays are writable views: no NaN resampled into the output
    const size_t N = hair.strand_count();
    for (size_t s = 0; s < N; ++s)
        if (hair.strand_size(s) == 0)
            throw py::value_error(cat("resampled: strand ", s, " has no points"));
    py::array_t<float> out({static_cast<ssize>(N), static_cast<ssize>(n), ssize(3)});
    Vec3f* dst = reinterpret_cast<Vec3f*>(out.mutable_data());
    run_released(threads, [&] {
        parallel_for(
            N,
            [&](size_t s) {
                const std::span<const float> widths =
                    hair.widths.empty()
                        ? std::span<const float>()
                        : std::span<const float>(hair.widths.data() + hair.offsets[s],
                                                 hair.strand_size(s));
                thread_local std::vector<float> w;
                w.resize(n);
                catmull_rom_resample(hair.strand(s), widths, hair.default_width,
                                     {dst + s * n, static_cast<size_t>(n)}, w);
            },
            64);
        return 0;
    });
    return out;
}

}  // namespace

void bind_hair(py::module_& m) {
    py::class_<Head, HeadPtr>(m, "Head",
                              R"(A head: its mesh (cm, head space: Y up, +Z forward) and scalp.

Build one with Head.builtin() or Head.from_obj(path, scale=, scalp=).)")
        .def_static(
            "builtin",
            [] { return std::make_shared<Head>(run_released(0, [] { return load_head({}); })); },
            "The built-in procedural head and shoulders (docs/style.md [head])")
        .def_static(
            "from_obj",
            [](const std::filesystem::path& path, const py::object& scale,
               const py::object& scalp) {
                require_file(path, "head OBJ");
                // The head's fields set through the style schema: its checks and messages.
                Style style;
                set_style_field(style, "head.obj",
                                toml_quote(std::filesystem::absolute(path).string()),
                                "Head.from_obj");
                set_style_field(style, "head.scale", inline_toml(scale, "scale"), "Head.from_obj");
                if (py::isinstance<py::str>(scalp)) {
                    const std::string s = scalp.cast<std::string>();
                    if (s == "hairline")
                        set_style_field(style, "head.scalp.method", "\"hairline\"",
                                        "Head.from_obj");
                    else
                        set_style_field(style, "head.scalp.group", toml_quote(s), "Head.from_obj");
                } else if (py::isinstance<py::dict>(scalp)) {
                    for (const auto& [k, v] : scalp.cast<py::dict>()) {
                        const std::string key = "head.scalp." + k.cast<std::string>();
                        set_style_field(style, key, inline_toml(v, key), "Head.from_obj");
                    }
                } else if (!scalp.is_none()) {
                    throw py::type_error(
                        "scalp: expected a face group name, \"hairline\" or a dict of "
                        "[head.scalp] fields");
                }
                return std::make_shared<Head>(
                    run_released(0, [&] { return load_head(style.head); }));
            },
            py::arg("path"), py::arg("scale") = 1.0, py::arg("scalp") = py::none(),
            R"(A head from an OBJ file. scale multiplies its coordinates to reach cm (Y up, facing
+Z); scalp is a face group or material name (default "scalp"), "hairline", or a dict of
[head.scalp] fields ({"method": "mask", "mask": "scalp.png"}).)")
        .def_static(
            "from_style",
            [](const py::object& style) {
                // wisp.Style (the Python class around the extension's style) or that style.
                const py::object s = py::hasattr(style, "_s") ? style.attr("_s") : style;
                if (!py::isinstance<PyStyle>(s))
                    throw py::type_error(cat("Head.from_style: expected a wisp.Style, got ",
                                             py::str(py::type::of(style).attr("__name__"))));
                const Style& st = s.cast<const PyStyle&>().style;
                return std::make_shared<Head>(run_released(0, [&] { return load_head(st.head); }));
            },
            py::arg("style"), "The head a style's [head] section names")
        .def_property_readonly("source", [](const Head& h) { return h.source; })
        .def_property_readonly(
            "vertices",
            [](py::object self) {
                const Mesh& mesh = *self.cast<const Head&>().mesh;
                return view(self, mesh.vertices.data()->data(),
                            {static_cast<ssize>(mesh.vertices.size()), 3}, false);
            },
            "#V×3 float32 vertex positions, cm, head space (a read-only view)")
        .def_property_readonly(
            "faces",
            [](py::object self) {
                const Mesh& mesh = *self.cast<const Head&>().mesh;
                return view(self, mesh.faces.data()->data(),
                            {static_cast<ssize>(mesh.faces.size()), 3}, false);
            },
            "#F×3 int32 triangles, indices into vertices, counter-clockwise from outside")
        .def_property_readonly(
            "uvs",
            [](py::object self) {
                const Mesh& mesh = *self.cast<const Head&>().mesh;
                return view(self, mesh.uvs.data() ? mesh.uvs.data()->data() : nullptr,
                            {static_cast<ssize>(mesh.uvs.size()), 2}, false);
            },
            "#UV×2 float32 texture coordinates of the mesh (may be empty)")
        .def_property_readonly(
            "scalp_faces",
            [](py::object self) {
                const auto& faces = self.cast<const Head&>().scalp->faces();
                return view(self, faces.data(), {static_cast<ssize>(faces.size())}, false);
            },
            "#S uint32 indices into faces of the scalp's triangles, sorted")
        .def_property_readonly(
            "scalp_area", [](const Head& h) { return h.scalp->area(); }, "the scalp's area, cm²")
        .def(
            "scalp_uv",
            [](const Head& h, const py::object& points) {
                const auto p = float_array(points, "points", -1, 3, "(N, 3)");
                py::array_t<float> out({p.shape(0), ssize(2)});
                for (ssize i = 0; i < p.shape(0); ++i) {
                    const Vec2f uv = h.scalp->uv_of(Vec3f(p.at(i, 0), p.at(i, 1), p.at(i, 2)));
                    out.mutable_at(i, 0) = uv.x();
                    out.mutable_at(i, 1) = uv.y();
                }
                return out;
            },
            py::arg("points"),
            "Scalp UV (N×2 float32) of points (N×3, cm) on or near the scalp: the crown at (0.5, "
            "0.5), the lowest hairline on the circle of radius 0.5 about it")
        .def(
            "write_obj",
            [](const Head& h, const std::filesystem::path& path) {
                run_released(0, [&] {
                    write_obj_mesh(path, *h.mesh);
                    return 0;
                });
            },
            py::arg("path"), "Writes the mesh as OBJ, the scalp in face group `scalp`")
        .def("__repr__", [](const Head& h) {
            return cat("<wisp.Head ", h.source, ": ", h.mesh->vertices.size(), " vertices, ",
                       h.mesh->faces.size(), " faces, scalp ", static_cast<int>(h.scalp->area()),
                       " cm²>");
        });

    py::class_<Hair, std::shared_ptr<Hair>>(m, "Hair", py::dynamic_attr(),
                                            R"(Strands as flat arrays (DESIGN.md "Data layout").

points[offsets[i]:offsets[i+1]] are strand i's control points (uniform Catmull-Rom, pinned
ends, root first), cm, head space (Y up, +Z forward). Every array property is a numpy view
of the Hair's own memory (its base is the Hair): no copy is made.)")
        .def(py::init<>())
        .def_static("from_arrays", &from_arrays, py::arg("points"), py::arg("offsets"),
                    py::arg("colors") = py::none(), py::arg("widths") = py::none(),
                    py::arg("wisp_ids") = py::none(),
                    R"(A Hair from arrays (copied into the Hair), each checked:
points   P×3 float (float32 or float64), finite, cm
offsets  N+1 integers, offsets[0] = 0, non-decreasing, offsets[-1] = P
colors   N×3 float linear RGB, or None
widths   P float diameters in cm, > 0, or None
wisp_ids N integers (-1: none), or None)")
        .def("__len__", &Hair::strand_count)
        .def_property_readonly(
            "points",
            [](py::object self) {
                Hair& h = self.cast<Hair&>();
                return view(self, h.points.data() ? h.points.data()->data() : nullptr,
                            {static_cast<ssize>(h.points.size()), 3});
            },
            "P×3 float32 control points, cm, head space (a writable view)")
        .def_property_readonly(
            "offsets",
            [](py::object self) {
                const Hair& h = self.cast<const Hair&>();
                return view(self, h.offsets.data(), {static_cast<ssize>(h.offsets.size())}, false);
            },
            "N+1 uint32: strand i owns points[offsets[i]:offsets[i+1]] (a read-only view: the "
            "C++ Hair stores 32-bit offsets; .astype(numpy.int64) for a 64-bit copy)")
        .def_property_readonly(
            "colors",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.colors.empty()) return py::none();
                return view(self, h.colors.data()->data(),
                            {static_cast<ssize>(h.colors.size()), 3});
            },
            "N×3 float32 linear RGB in [0, 1] per strand, or None (imported hair without colours)")
        .def_property_readonly(
            "widths",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.widths.empty()) return py::none();
                return view(self, h.widths.data(), {static_cast<ssize>(h.widths.size())});
            },
            "P float32 strand diameter at each point, cm, or None (then default_width)")
        .def_property_readonly(
            "wisp_ids",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.wisp.empty()) return py::none();
                return view(self, h.wisp.data(), {static_cast<ssize>(h.wisp.size())});
            },
            "N int32 wisp id per strand (-1: none), or None when unknown (imported hair)")
        .def_property_readonly(
            "root_uv",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.root_uv.empty()) return py::none();
                return view(self, h.root_uv.data()->data(),
                            {static_cast<ssize>(h.root_uv.size()), 2});
            },
            "N×2 float32 scalp UV of each root, or None")
        .def_property_readonly(
            "root_normals",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.root_normal.empty()) return py::none();
                return view(self, h.root_normal.data()->data(),
                            {static_cast<ssize>(h.root_normal.size()), 3});
            },
            "N×3 float32 unit scalp normal at each root, head space, or None")
        .def_property_readonly(
            "group_ids",
            [](py::object self) -> py::object {
                Hair& h = self.cast<Hair&>();
                if (h.group.empty()) return py::none();
                return view(self, h.group.data(), {static_cast<ssize>(h.group.size())});
            },
            "N int32 constraint group of each strand (0: none, k: Style.groups[k-1]), or None")
        .def_readwrite("default_width", &Hair::default_width, "cm, used when widths is None")
        .def_property_readonly("point_count", &Hair::point_count)
        .def(
            "strand",
            [](py::object self, long long i) {
                Hair& h = self.cast<Hair&>();
                const size_t s = strand_index(h, i);
                return view(self, h.points[h.offsets[s]].data(),
                            {static_cast<ssize>(h.strand_size(s)), 3});
            },
            py::arg("i"), "Strand i's control points, n×3 float32, cm (a view)")
        .def(
            "resampled",
            [](const Hair& h, long long n, const py::object& threads) {
                return resampled(h, n, thread_count(threads));
            },
            py::arg("n"), py::arg("threads") = py::none(),
            "Every strand at n points evenly spaced in arc length along its curve, root and tip "
            "exact: N×n×3 float32, cm (a new array)")
        .def(
            "bounds",
            [](const Hair& h) {
                const Box3 b = h.bounds();
                py::array_t<float> out({ssize(2), ssize(3)});
                for (int k = 0; k < 3; ++k) {
                    out.mutable_at(0, k) = b.lo[k];
                    out.mutable_at(1, k) = b.hi[k];
                }
                return out;
            },
            "[[min x, y, z], [max x, y, z]], cm")
        .def(
            "copy", [](const Hair& h) { return Hair(h); }, "A deep copy")
        .def(
            "validate", [](const Hair& h) { h.validate("Hair"); },
            "Raises wisp.Error if the arrays disagree in size or hold non-finite values")
        .def(
            "write",
            [](py::object self, const std::filesystem::path& file, bool obj_segments, bool z_up,
               int resample, HeadPtr head) {
                const std::string path = file.string();
                const Hair& h = self.cast<const Hair&>();
                if (resample < 0)
                    throw py::value_error(cat("resample: expected >= 0 points, got ", resample));
                HairWriteOptions options;
                options.obj_segments = obj_segments;
                options.usda_z_up = z_up;
                options.resample_points = resample;
                // An unknown extension before the GIL is let go.
                const HairFormat format = hair_format_from_path(path);
                // Scenes frame the hair on its head as the CLI does: the head given, the one
                // the hair was generated on, or the built-in one (as `wisp convert`).
                if (!head && py::hasattr(self, "head") && py::isinstance<Head>(self.attr("head")))
                    head = self.attr("head").cast<HeadPtr>();
                run_released(0, [&] {
                    if (format == HairFormat::kRib || format == HairFormat::kPbrt)
                        options.camera = export_camera(h, head ? *head->mesh : builtin_head_mesh());
                    write_hair(path, h, options);
                    return 0;
                });
            },
            py::arg("path"), py::kw_only(), py::arg("obj_segments") = false,
            py::arg("z_up") = false, py::arg("resample") = 0, py::arg("head") = HeadPtr(),
            "Writes the hair in the format of path's extension (.usda .hair .obj .ply .data .rib "
            ".pbrt .npz), atomically, as `wisp generate -o` does; .rib and .pbrt scenes are framed "
            "on head (default: the hair's own head, else the built-in one)")
        .def("__repr__", [](const Hair& h) {
            return cat("<wisp.Hair ", h.strand_count(), " strands, ", h.point_count(), " points>");
        });

    m.def(
        "read",
        [](const std::filesystem::path& file) {
            const std::string path = file.string();
            hair_format_from_path(path);
            require_file(path, "hair file");
            return run_released(0, [&] { return read_hair(path); });
        },
        py::arg("path"), "Reads a hair file (.usda .hair .obj .ply .data), as `wisp convert` does");
    m.def("hair_formats", [] {
        py::list out;
        for (HairFormat f :
             {HairFormat::kUsda, HairFormat::kHair, HairFormat::kObj, HairFormat::kPly,
              HairFormat::kData, HairFormat::kRib, HairFormat::kPbrt, HairFormat::kNpz})
            out.append(hair_format_name(f));
        return out;
    });
}

}  // namespace wisp::python
