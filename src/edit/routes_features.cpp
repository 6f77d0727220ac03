#include "edit/routes_features.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "edit/http_util.hpp"
#include "edit/wire.hpp"
#include "geometry/mesh.hpp"
#include "groom/head.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"
#include "render/render.hpp"
#include "solve/pipeline.hpp"  // head_frame

namespace wisp {
namespace {

// A painted selection's side, as a painted map's (server.cpp).
constexpr int kMinMaskSide = 2;
constexpr int kMaxMaskSide = 1024;
// The blank selection a new group starts from.
constexpr int kBlankMaskSide = 128;
// The final picture's side.
constexpr int kMinPictureSide = 16;
constexpr int kMaxPictureSide = 1024;

// [x, y, z] of finite numbers within ±1e6, or throws naming `field`.
Vec3f json_vec3(const nlohmann::json& j, const char* field) {
    if (!j.contains(field) || !j[field].is_array() || j[field].size() != 3)
        fail("must be [x, y, z]");
    Vec3f v;
    for (int c = 0; c < 3; ++c) {
        if (!j[field][c].is_number()) fail("must be [x, y, z] of numbers");
        const double x = j[field][c].get<double>();
        if (!std::isfinite(x) || std::abs(x) > 1e6) fail("must be finite, within ±1e6 cm");
        v[c] = static_cast<float>(x);
    }
    return v;
}

// A PNG body decoded as a map reader decodes it, then as Save will write it, so that the
// hair is the same before and after Save.
std::shared_ptr<const GrayImage> selection_image(const std::string& body) {
    GrayImage image = std::move(decode_image_planes(body, "the selection", 1).front());
    if (image.width < kMinMaskSide || image.height < kMinMaskSide || image.width > kMaxMaskSide ||
        image.height > kMaxMaskSide)
        fail("the selection is ", image.width, "x", image.height, ": each side must be from ",
             kMinMaskSide, " to ", kMaxMaskSide, " pixels");
    return std::make_shared<const GrayImage>(
        std::move(decode_image_planes(encode_gray_png(image), "the selection", 1).front()));
}

nlohmann::json json_body(const httplib::Request& req) {
    nlohmann::json j = nlohmann::json::parse(req.body, nullptr, false);
    if (j.is_discarded() || !j.is_object()) fail("the request body must be a JSON object");
    return j;
}

}  // namespace

void add_feature_routes(httplib::Server& server, EditState& s) {
    // Placing constraints: the sections, and the selections painted on the scalp.
    server.Get("/api/constraints", [&s](const httplib::Request&, httplib::Response& res) {
        std::lock_guard lock(s.cache_mutex);
        const HeadFrame head = head_frame(*s.cache.head().scalp);
        send_json(res,
                  {{"sections", s.constraints.json()},
                   {"paths", section_paths(s.constraints.json(), s.cache.style().groups, head)},
                   {"frames", section_frames(s.constraints.json(), head)},
                   {"head", head_units_frame(head)},
                   {"document", s.document}});
    });
    server.Post("/api/constraints", [&s](const httplib::Request& req, httplib::Response& res) {
        nlohmann::json j;
        try {
            j = json_body(req);
        } catch (const Error& e) {
            return send_error(res, 400, e.what());
        }
        if (!j.contains("sections"))
            return send_error(res, 400, "required: the array of sections", "sections");
        ++s.hair_requests;  // an update running for the old groups is stale
        std::lock_guard lock(s.cache_mutex);
        Style next = s.cache.style();
        try {
            next.groups = s.constraints.set(j["sections"], next, s.base_dir, s.document);
        } catch (const SectionsError& e) {
            return send_error(res, 400, e.what(), e.field);
        }
        s.cache.set_style(std::move(next));
        s.cache.mark_stale(Stage::kSolve);  // painted masks are not in the groups' text
        const HeadFrame head = head_frame(*s.cache.head().scalp);
        send_json(res,
                  {{"stale", stage_name(s.cache.stale())},
                   {"sections", s.constraints.json()},
                   {"paths", section_paths(s.constraints.json(), s.cache.style().groups, head)},
                   {"frames", section_frames(s.constraints.json(), head)},
                   {"head", head_units_frame(head)}});
    });
    server.Get("/api/selection", [&s](const httplib::Request& req, httplib::Response& res) {
        const std::string key = req.get_param_value("key");
        std::lock_guard lock(s.cache_mutex);
        const GrayImage* mask = s.constraints.mask(key);
        GrayImage blank;
        if (!mask) {
            blank.width = blank.height = kBlankMaskSide;
            blank.values.assign(size_t(kBlankMaskSide) * kBlankMaskSide, 0.f);
        }
        res.set_content(encode_map(mask ? *mask : blank, mask ? 3 : 0, 0.f, 1.f),
                        "application/octet-stream");
    });
    server.Post("/api/selection", [&s](const httplib::Request& req, httplib::Response& res) {
        const std::string key = req.get_param_value("key");
        std::shared_ptr<const GrayImage> pixels;
        try {
            pixels = selection_image(req.body);
        } catch (const Error& e) {
            return send_error(res, 400, e.what(), "body");
        }
        ++s.hair_requests;
        std::lock_guard lock(s.cache_mutex);
        ConstraintSections before = s.constraints;
        try {
            s.constraints.set_mask(key, std::move(pixels));
            Style next = s.cache.style();
            next.groups = s.constraints.groups(next, s.base_dir, s.document);
            s.cache.set_style(std::move(next));
        } catch (const SectionsError& e) {
            s.constraints = std::move(before);
            return send_error(res, 400, e.what(), e.field);
        } catch (const Error& e) {
            s.constraints = std::move(before);
            return send_error(res, 400, e.what(), "key");
        }
        s.cache.mark_stale(Stage::kSolve);
        send_json(res, {{"stale", stage_name(s.cache.stale())}});
    });

    // The views: the HUD's figures and each group's progress, and the wisp and group of
    // every strand sent (colour by wisp or group).
    server.Get("/api/report", [&s](const httplib::Request&, httplib::Response& res) {
        std::lock_guard lock(s.cache_mutex);
        const HairstyleResult& r = s.cache.result();
        const bool solved = s.cache.stale() > Stage::kSolve;
        const bool grown = s.cache.stale() == Stage::kNone;
        nlohmann::json groups = nlohmann::json::array();
        if (solved)
            for (const SolveStats::Group& g : r.solve.groups)
                groups.push_back({{"name", g.name},
                                  {"wisps", g.wisps},
                                  {"constraints", g.constraints},
                                  {"completed", g.completed},
                                  {"met", g.met}});
        const auto when = [](bool ok, size_t v) { return ok ? nlohmann::json(v) : nullptr; };
        send_json(res, {{"solved", solved},
                        {"joints", when(solved, r.solve.joints)},
                        {"unresolved", when(solved, r.solve.unresolved)},
                        {"constrained", when(solved, r.solve.constrained)},
                        {"points_inside_head", when(grown, r.points_inside_head)},
                        {"points_pushed", when(grown, r.points_pushed)},
                        {"groups", groups}});
    });
    server.Get("/api/attributes", [&s](const httplib::Request& req, httplib::Response& res) {
        size_t limit = SIZE_MAX;
        if (req.has_param("strands")) {
            const std::string v = req.get_param_value("strands");
            char* end = nullptr;
            const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
            if (v.empty() || *end || v[0] == '-')
                return send_error(res, 400, cat("must be a count, got '", excerpt(v), "'"),
                                  "strands");
            limit = static_cast<size_t>(n);
        }
        const uint64_t ticket = ++s.hair_requests;
        std::lock_guard lock(s.cache_mutex);
        const Hair* hair = s.cache.update_preview(limit, CancelToken(s.hair_requests, ticket));
        if (!hair) return send_error(res, 409, "superseded by a newer request");
        // The order encode_strands sends them in.
        const size_t total = hair->strand_count();
        const std::vector<uint32_t> order = strand_order(total);
        const size_t count = std::min(limit, total);
        std::string out = "WISPATTR";
        put_u32(out, 2);
        put_u32(out, static_cast<uint32_t>(count));
        for (size_t i = 0; i < count; ++i)
            put_u32(out, static_cast<uint32_t>(hair->wisp.empty() ? -1 : hair->wisp[order[i]]));
        for (size_t i = 0; i < count; ++i)
            put_u32(out, static_cast<uint32_t>(hair->group.empty() ? 0 : hair->group[order[i]]));
        // The solve's figures are the current style's once the solve is up to date, which
        // update_preview made it.
        const SolveStats& solve = s.cache.result().solve;
        for (size_t i = 0; i < count; ++i) {
            const size_t strand = order[i];
            const int group = hair->group.empty() ? 0 : hair->group[strand];
            const int wisp = hair->wisp.empty() ? -1 : hair->wisp[strand];
            float progress = -1.f;
            if (group > 0 && size_t(group) <= solve.groups.size() && wisp >= 0 &&
                size_t(wisp) < solve.wisp_met.size()) {
                const int queue = solve.groups[group - 1].constraints;
                progress = queue > 0 ? float(solve.wisp_met[wisp]) / float(queue) : 1.f;
            }
            put_f32(out, progress);
        }
        res.set_content(out, "application/octet-stream");
    });

    // The final picture: wisp's own renderer, from the live view's camera.
    server.Post("/api/render", [&s](const httplib::Request& req, httplib::Response& res) {
        RenderOptions options;
        options.width = options.height = 512;
        std::string field = "body";
        try {
            const nlohmann::json j = json_body(req);
            LookAt look;
            field = "eye";
            look.eye = json_vec3(j, "eye");
            field = "target";
            look.target = json_vec3(j, "target");
            field = "up";
            if (j.contains("up")) look.up = json_vec3(j, "up");
            if ((look.eye - look.target).norm() < 1e-3f) fail("must differ from the target");
            options.look_at = look;
            for (const char* key : {"width", "height"}) {
                field = key;
                if (!j.contains(key)) continue;
                if (!j[key].is_number_integer() || j[key].get<int64_t>() < kMinPictureSide ||
                    j[key].get<int64_t>() > kMaxPictureSide)
                    fail("must be a whole number of pixels from ", kMinPictureSide, " to ",
                         kMaxPictureSide);
                (key[0] == 'w' ? options.width : options.height) = j[key].get<int>();
            }
            field = "fov";
            if (j.contains("fov")) {
                if (!j["fov"].is_number() || !(j["fov"].get<double>() >= 5) ||
                    j["fov"].get<double>() > 120)
                    fail("must be a number of degrees from 5 to 120");
                options.fov_y_degrees = j["fov"].get<float>();
            }
        } catch (const Error& e) {
            return send_error(res, 400, e.what(), field);
        }
        std::lock_guard lock(s.cache_mutex);
        // Progress: the stale stages, then the picture.
        ProgressEvents::Task task(s.events, "render",
                                  kStageCount - static_cast<int>(s.cache.stale()) + 1);
        const HairstyleResult& r = *s.cache.update(CancelToken(task.fractions()), task.stages());
        task.step("render");
        const RgbImage picture = render(r.hair, s.cache.head().mesh.get(), options);
        res.set_content(encode_png(picture), "image/png");
    });

    // A head uploaded as an OBJ: read by the OBJ reader before anything is written, then
    // written into the style's folder (atomically), and the style's head set to it.
    server.Post("/api/head", [&s](const httplib::Request& req, httplib::Response& res) {
        std::filesystem::path file;
        std::string field = "name";
        HeadSpec spec;
        try {
            file = file_in_folder(s.base_dir, req.get_param_value("name"), {".obj"});
            field = "scale";
            spec.scale = query_number(req, "scale", 1.f);
            if (!(spec.scale > 0.f) || spec.scale > 1e6f) fail("must be > 0 and ≤ 1e6");
        } catch (const Error& e) {
            return send_error(res, 400, e.what(), field);
        }
        const std::string method =
            req.has_param("method") ? req.get_param_value("method") : "group";
        if (method != "group" && method != "hairline")
            return send_error(res, 400, "must be group or hairline (a mask needs an image)",
                              "method");
        // The reader reads files: the upload goes to a temporary file of the folder first,
        // which becomes the named file only once the head loads.
        const std::filesystem::path tmp = s.base_dir / (file.stem().string() + ".upload.obj");
        std::lock_guard lock(s.cache_mutex);
        Style next = s.cache.style();
        try {
            write_file_atomic(tmp, req.body);
            next.head.obj = tmp;
            next.head.scale = spec.scale;
            next.head.scalp.kind =
                method == "group" ? ScalpSpec::Kind::kGroup : ScalpSpec::Kind::kHairline;
            load_head(next.head);  // the OBJ reader's and the scalp's checks
        } catch (const Error& e) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return send_error(res, 400, e.what(), "body");
        }
        std::filesystem::rename(tmp, file);
        next.head.obj = file;
        s.cache.set_style(std::move(next));
        s.cache.mark_stale(Stage::kHead);  // the same name may hold another mesh
        send_json(res, {{"stale", stage_name(s.cache.stale())},
                        {"values", style_values_json(s.cache.style(), s.base_dir)}});
    });
}

}  // namespace wisp
