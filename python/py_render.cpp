// wisp.render: the CLI's renderer (render/render.hpp) to an H×W×3 uint8 array that owns the
// image's memory (no copy), or H×W×4 with the coverage as alpha, with the options of `wisp
// render` (--eye, --shading, --rim, ...).
#include <cmath>

#include "bindings.hpp"
#include "core/error.hpp"
#include "core/hair.hpp"
#include "core/image.hpp"
#include "dataset/metrics.hpp"
#include "dataset/spec.hpp"
#include "dataset/targets.hpp"
#include "render/render.hpp"

namespace wisp::python {
namespace {

Vec3f vec3(const py::handle& v, const char* name) {
    std::vector<double> xs;
    try {
        xs = v.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
        throw py::type_error(cat(name, ": expected three numbers (x, y, z)"));
    }
    if (xs.size() != 3 || !std::isfinite(xs[0]) || !std::isfinite(xs[1]) || !std::isfinite(xs[2]))
        throw py::value_error(
            cat(name, ": expected three finite numbers, got ", xs.size(), " values"));
    return Vec3f(xs[0], xs[1], xs[2]);
}

double number(const py::handle& v, const char* name, double lo, double hi) {
    double x;
    try {
        x = v.cast<double>();
    } catch (const py::cast_error&) {
        throw py::type_error(cat(name, ": expected a number"));
    }
    if (!(x >= lo && x <= hi))
        throw py::value_error(cat(name, ": expected ", lo, " to ", hi, ", got ", x));
    return x;
}

// The `wisp render` look options, by the same names (LookArgs in app/cli.cpp).
RenderOptions render_options(const std::string& view, int width, int height, const py::dict& kw) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw py::value_error(
            cat("size: expected 1 to 16384 pixels a side, got ", width, "×", height));
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.view = view;
    bool view_known = false;
    for (const std::string& v : view_names())
        view_known |= v == view;
    if (!view_known) {
        std::string names;
        for (const std::string& v : view_names())
            names += (names.empty() ? "" : ", ") + v;
        throw py::value_error(cat("view: unknown view '", view, "' (one of ", names, ")"));
    }
    std::optional<Vec3f> eye, target;
    float specular = -1.f, rim = 1.f;
    for (const auto& [key, value] : kw) {
        const std::string k = key.cast<std::string>();
        if (k == "eye")
            eye = vec3(value, "eye");
        else if (k == "target")
            target = vec3(value, "target");
        else if (k == "fov")
            o.fov_y_degrees = number(value, "fov", 1, 170);
        else if (k == "background")
            o.background = vec3(value, "background");
        else if (k == "shading") {
            std::string s;
            try {
                s = value.cast<std::string>();
            } catch (const py::cast_error&) {
                throw py::type_error("shading: expected a name");
            }
            try {
                o.shading = parse_shading(s);
            } catch (const Error& e) {
                throw py::value_error(e.what());
            }
        } else if (k == "specular_exponent")
            o.specular_exponent = number(value, k.c_str(), 1, 10000);
        else if (k == "specular")
            specular = number(value, "specular", 0, 100);
        else if (k == "rim")
            rim = number(value, "rim", 0, 100);
        else if (k == "shadows")
            o.shadows = value.cast<bool>();
        else if (k == "width_scale")
            o.width_scale = number(value, k.c_str(), 0.01, 100);
        else
            throw py::type_error(
                cat("render: unknown option '", k,
                    "' (eye, target, fov, background, "
                    "shading, specular_exponent, specular, rim, shadows, width_scale)"));
    }
    if (eye.has_value() != target.has_value()) throw py::value_error("eye and target go together");
    if (eye) {
        if (*eye == *target)
            throw py::value_error("eye: the camera cannot look at its own position");
        o.look_at = LookAt{*eye, *target};
    }
    if (specular >= 0.f) {
        o.specular_strength = specular;
        o.hair.primary *= specular;
        o.hair.secondary *= specular;
    }
    o.rim.color *= rim;
    return o;
}

// An H×W×channels array owning `pixels` (no copy).
py::array image_array(std::vector<uint8_t> pixels, int width, int height, int channels) {
    auto* owned = new std::vector<uint8_t>(std::move(pixels));
    py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<uint8_t>*>(p); });
    return py::array_t<uint8_t>({py::ssize_t(height), py::ssize_t(width), py::ssize_t(channels)},
                                owned->data(), owner);
}

// An array of `shape` owning `values` (no copy).
template <class T>
py::array owned_array(std::vector<T> values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, owned->data(), owner);
}

// The maps of dataset/targets.hpp that `names` asks for (output_map_table()'s names, the
// picture aside), seen by the camera render() takes for `o`, with that camera as OpenCV has it.
py::dict target_maps(const Hair& hair, const Mesh* head, const RenderOptions& o,
                     const std::vector<std::string>& names, int threads) {
    uint32_t wanted = 0;
    for (const std::string& name : names) {
        const OutputMapInfo* map = find_output_map(name, true);
        if (!map)
            throw py::value_error(
                cat("targets: unknown map '", name, "' (", output_map_names(true), ")"));
        wanted |= 1u << static_cast<int>(map->map);
    }
    auto has = [&](OutputMap m) { return wanted >> static_cast<int>(m) & 1u; };
    const Camera cam = render_camera(hair, head, o);
    TargetMaps maps = run_released(
        threads, [&] { return draw_targets(hair, head, cam, has(OutputMap::kConfidence)); });
    const std::vector<py::ssize_t> hw = {maps.height, maps.width};
    py::dict out;
    if (has(OutputMap::kOrientation)) out["orientation"] = owned_array(maps.orientation, hw);
    if (has(OutputMap::kMask)) {
        std::vector<uint8_t> mask(maps.hair);
        out["mask"] = owned_array(std::move(mask), hw).attr("astype")("bool");
    }
    if (has(OutputMap::kDepth)) out["depth"] = owned_array(maps.depth, hw);
    if (has(OutputMap::kStrand)) {
        RgbImage img = strand_map_image(maps);
        out["strand"] = image_array(std::move(img.rgb), img.width, img.height, 3);
    }
    if (has(OutputMap::kConfidence)) out["confidence"] = owned_array(maps.confidence, hw);
    if (has(OutputMap::kMatte)) out["matte"] = owned_array(maps.coverage, hw);
    if (has(OutputMap::kStrandId)) out["strand_id"] = owned_array(maps.strand, hw);
    if (has(OutputMap::kDepthHairstep))
        out["depth_hairstep"] = owned_array(hairstep_depth(maps), hw);
    const CameraMatrices mats = opencv_matrices(cam);
    out["K"] = owned_array(std::vector<double>(mats.K.begin(), mats.K.end()), {3, 3});
    out["world_to_camera"] = owned_array(
        std::vector<double>(mats.world_to_camera.begin(), mats.world_to_camera.end()), {4, 4});
    return out;
}

}  // namespace

void bind_render(py::module_& m) {
    m.def(
        "render",
        [](const Hair& hair, const HeadPtr& head, const std::string& view, int width, int height,
           const py::object& threads, bool alpha, const py::kwargs& kw) {
            // Its arrays are writable numpy views: a NaN or a far-off point set through them
            // would size the renderer's grids from nonsense.
            hair.validate("Hair");
            const RenderOptions o = render_options(view, width, height, kw);
            const int n = thread_count(threads);
            if (!alpha) {
                RgbImage image = run_released(
                    n, [&] { return render(hair, head ? head->mesh.get() : nullptr, o); });
                return image_array(std::move(image.rgb), image.width, image.height, 3);
            }
            std::vector<uint8_t> rgba = run_released(n, [&] {
                std::vector<uint8_t> a;
                const RgbImage image =
                    render(hair, head ? head->mesh.get() : nullptr, o, nullptr, &a);
                std::vector<uint8_t> out(a.size() * 4);
                for (size_t i = 0; i < a.size(); ++i) {
                    std::copy_n(&image.rgb[3 * i], 3, &out[4 * i]);
                    out[4 * i + 3] = a[i];
                }
                return out;
            });
            return image_array(std::move(rgba), o.width, o.height, 4);
        },
        py::arg("hair"), py::arg("head"), py::arg("view"), py::arg("width"), py::arg("height"),
        py::arg("threads") = py::none(), py::arg("alpha") = false);
    m.def(
        "encode_png",
        [](const py::array_t<uint8_t, py::array::c_style | py::array::forcecast>& rgb) {
            if (rgb.ndim() != 3 || rgb.shape(2) != 3)
                throw py::value_error("image: expected shape (H, W, 3) uint8");
            RgbImage image{static_cast<int>(rgb.shape(1)), static_cast<int>(rgb.shape(0)),
                           std::vector<uint8_t>(rgb.data(), rgb.data() + rgb.size())};
            return py::bytes(encode_png(image));
        },
        py::arg("image"), "PNG bytes of an H×W×3 uint8 image");
    m.def(
        "compare",
        [](const Hair& a, const Hair& b, const HeadPtr& head, const std::vector<std::string>& views,
           int size, float voxel, const py::object& threads) {
            CompareOptions o;
            o.views = views;
            o.size = size;
            o.voxel = voxel;
            const int n = thread_count(threads);
            const CompareResult r = run_released(
                n, [&] { return compare_hair(a, b, head ? head->mesh.get() : nullptr, o); });
            return py::module_::import("json").attr("loads")(to_json(r).dump());
        },
        py::arg("a"), py::arg("b"), py::arg("head"), py::arg("views"), py::arg("size"),
        py::arg("voxel"), py::arg("threads") = py::none());
    m.def(
        "targets",
        [](const Hair& hair, const HeadPtr& head, const std::string& view, int width, int height,
           const std::vector<std::string>& names, const py::object& threads, const py::kwargs& kw) {
            hair.validate("Hair");
            const RenderOptions o = render_options(view, width, height, kw);
            return target_maps(hair, head ? head->mesh.get() : nullptr, o, names,
                               thread_count(threads));
        },
        py::arg("hair"), py::arg("head"), py::arg("view"), py::arg("width"), py::arg("height"),
        py::arg("names"), py::arg("threads") = py::none());
    m.def("view_names", &view_names);
    m.def("shading_names", &shading_names);
    m.def(
        "melanin_from_color",
        [](const py::array_t<float, py::array::c_style | py::array::forcecast>& colors,
           double beta_n) {
            if (colors.ndim() != 2 || colors.shape(1) != 3)
                throw py::value_error("colors: expected shape (N, 3), linear RGB");
            if (!(beta_n >= 0.1 && beta_n <= 1))
                throw py::value_error(cat("beta_n: expected 0.1 to 1, got ", beta_n));
            const size_t n = static_cast<size_t>(colors.shape(0));
            py::array_t<float> out({py::ssize_t(n), py::ssize_t(2)});
            const float* c = colors.data();
            float* o = out.mutable_data();
            for (size_t i = 0; i < n; ++i) {
                const Vec3f color(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
                if (!color.allFinite())
                    throw py::value_error(cat("colors: row ", i, " is not finite"));
                const Melanin m = melanin_from_color(color, static_cast<float>(beta_n));
                o[2 * i] = m.eumelanin;
                o[2 * i + 1] = m.pheomelanin;
            }
            return out;
        },
        py::arg("colors"), py::arg("beta_n") = 0.3,
        "The eumelanin and pheomelanin concentrations (N×2; Chiang et al. 2016's units, as "
        "pbrt's) whose hair has each colour, as the renderer's fibre model takes them");
}

}  // namespace wisp::python
