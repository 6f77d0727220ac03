#include "edit/server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "edit/http_util.hpp"
#include "edit/motion_routes.hpp"
#include "edit/progress_events.hpp"
#include "edit/routes_features.hpp"
#include "edit/stage_cache.hpp"
#include "edit/wire.hpp"
#include "groom/maps.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"
#include "io/hair_io.hpp"

namespace wisp {
namespace detail {
// Defined in web_assets.cpp, generated from web/dist by embed_web.cmake (a page saying the
// front end was not built when Node was missing).
struct WebAsset {
    std::string_view path;  // "/index.html", "/assets/index-abc.js"
    std::string_view mime;
    std::string_view body;
};
extern const WebAsset kWebAssets[];
extern const size_t kWebAssetCount;
extern const bool kWebBuilt;
}  // namespace detail

bool editor_front_end_built() {
    return detail::kWebBuilt;
}

namespace {

// The hair formats Export writes (every one `wisp` writes but scenes); GET /api/export
// gives them to the front end's menu.
const std::initializer_list<std::string_view> kExportFormats = {".usda", ".hair", ".obj",
                                                                ".ply",  ".data", ".npz"};

// The most strands a /api/hair request may ask for (the style's own count bounds it too).
constexpr size_t kMaxStrandsSent = 10'000'000;

std::string random_token() {
    std::ifstream urandom("/dev/urandom", std::ios::binary);
    unsigned char bytes[16] = {};
    if (!urandom.read(reinterpret_cast<char*>(bytes), sizeof bytes))
        fail("cannot read /dev/urandom for the editor's token");
    std::string hex;
    for (const unsigned char b : bytes) {
        hex += "0123456789abcdef"[b >> 4];
        hex += "0123456789abcdef"[b & 15];
    }
    return hex;
}

}  // namespace

// Shared with the other route files (edit/http_util.hpp).
void send_json(httplib::Response& res, const nlohmann::json& j, int status) {
    res.status = status;
    res.set_content(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message,
                const std::string& field) {
    nlohmann::json j{{"error", excerpt(message, 1000)}};
    if (!field.empty()) j["field"] = excerpt(field, 200);
    send_json(res, j, status);
}

namespace {

// Sends `bytes` as they are, without copying them into the response (a full hair is tens of
// megabytes): the response holds the buffer until it has been written.
void send_shared(httplib::Response& res, std::shared_ptr<const std::string> bytes) {
    const size_t size = bytes->size();
    res.set_content_provider(
        size, "application/octet-stream",
        [bytes = std::move(bytes)](size_t offset, size_t length, httplib::DataSink& sink) {
            return sink.write(bytes->data() + offset, std::min(length, bytes->size() - offset));
        });
}

// Constant-time comparison, so the token cannot be found a byte at a time by timing.
bool same_token(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < a.size(); ++i)
        diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
}

// A painted map's side: [kMinMapSide, kMaxMapSide] pixels.
constexpr int kMinMapSide = 2;
constexpr int kMaxMapSide = 1024;
// The side of the image a constant or procedural map is rasterized to for painting.
constexpr int kPaintSide = 256;

}  // namespace

// `name` as a file of the style's folder `dir`: a plain file name (letters, digits, '.', '-',
// '_', ' '; not hidden, no separators, so nothing outside the folder), at most 128 bytes,
// ending in one of `extensions`. Throws wisp::Error saying what is wrong.
std::filesystem::path file_in_folder(const std::filesystem::path& dir, const std::string& name,
                                     std::initializer_list<std::string_view> extensions) {
    if (name.empty() || name.size() > 128)
        fail("must be a file name of 1 to 128 characters, got ", name.size());
    for (const char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_' ||
              c == ' '))
            fail("'", excerpt(name),
                 "': a file name in the style's folder may hold letters, "
                 "digits, '.', '-', '_' and spaces only (no folders)");
    if (name.front() == '.' || name.find("..") != std::string::npos)
        fail("'", excerpt(name), "': must not start with '.' or hold '..'");
    bool ok = false;
    std::string list;
    for (const std::string_view ext : extensions) {
        ok |= name.size() > ext.size() &&
              name.compare(name.size() - ext.size(), ext.size(), ext) == 0;
        list += (list.empty() ? "" : ", ") + std::string(ext);
    }
    if (!ok) fail("'", excerpt(name), "': must end in ", list);
    return dir / name;
}

// "stem" of "stem.toml".
std::string stem_of(const std::string& toml_name) {
    return std::filesystem::path(toml_name).stem().string();
}

// A finite number from a query parameter, or throws naming it.
float query_number(const httplib::Request& req, const char* name, float fallback) {
    if (!req.has_param(name)) return fallback;
    const std::string s = req.get_param_value(name);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end || !std::isfinite(v) || std::abs(v) > 1e9)
        fail("must be a finite number, got '", excerpt(s), "'");
    return static_cast<float>(v);
}

namespace {

// The map of `field` as the painter's [0,1] image with its [low, high] and kind (wire.hpp
// encode_map): an image map at its own size (up to kMaxMapSide), a procedural map sampled at
// kPaintSide² through the inverse of the scalp's polar map, a constant filled.
struct PaintMap {
    GrayImage t;
    uint32_t kind = 0;
    float low = 0, high = 1;
};

PaintMap paint_map(const ScalarMap& m, const StyleField& field, const Scalp& scalp,
                   const GrowthSpec& growth) {
    PaintMap out;
    out.t.width = out.t.height = kPaintSide;
    out.t.values.assign(size_t(kPaintSide) * kPaintSide, 0.f);
    if (m.kind == ScalarMap::Kind::kConstant) {
        out.low = std::min(field.map_low, m.value);
        out.high = std::max(field.map_high, m.value);
        const float t = out.high > out.low ? (m.value - out.low) / (out.high - out.low) : 1.f;
        std::fill(out.t.values.begin(), out.t.values.end(), t);
        return out;
    }
    out.low = m.low;
    out.high = m.high;
    if (m.kind == ScalarMap::Kind::kImage) {
        out.kind = m.pixels ? 3 : 1;
        GrayImage image = m.pixels ? *m.pixels : read_gray_image(m.image);
        if (image.width <= kMaxMapSide && image.height <= kMaxMapSide) {
            out.t = std::move(image);
            return out;
        }
    } else {
        out.kind = 2;
    }
    const MapSampler sampler(m, scalp, growth);
    const float theta_max = scalp.max_polar_angle();
    const float radius = (scalp.crown() - scalp.center()).norm();
    const int n = kPaintSide;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            SurfacePoint p;
            p.uv = {float(i) / float(n - 1), 1.f - float(j) / float(n - 1)};
            const float du = p.uv.x() - 0.5f, dv = p.uv.y() - 0.5f;
            const float len = std::hypot(du, dv);
            const float theta = 2.f * len * theta_max;
            const Vec3f dir = len > 1e-9f ? Vec3f(-std::sin(theta) * du / len, std::cos(theta),
                                                  std::sin(theta) * dv / len)
                                          : Vec3f::UnitY();
            p.position = scalp.center() + radius * dir;
            const float v = sampler(p);
            out.t.values[size_t(j) * n + i] =
                out.high != out.low ? (v - out.low) / (out.high - out.low) : 1.f;
        }
    }
    return out;
}

}  // namespace

struct EditServer::Impl {
    EditOptions options;
    std::filesystem::path base_dir;
    StageCache cache;
    std::mutex cache_mutex;                  // the cache is used by one request at a time
    std::atomic<uint64_t> hair_requests{0};  // the newest request wins: older ones cancel
    httplib::Server server;
    std::thread thread;
    std::atomic<bool> listening_done{false};
    int port = 0;
    std::vector<std::string> hosts;  // allowed Host header values
    std::string document;            // the style's file name in base_dir (Save's default)
    MotionRoutes motion;             // the Motion mode's endpoints (motion_routes.hpp)
    ConstraintSections constraints;  // the placed ties, combs and groups, as TOML reads them
    ProgressEvents events;           // the long runs' progress (GET /api/events)
    EditState state{cache, cache_mutex, hair_requests, base_dir, document, constraints, events};

    Impl(Style style, std::filesystem::path dir, EditOptions opts)
        : options(std::move(opts)),
          base_dir(std::move(dir)),
          cache(std::move(style), base_dir),
          motion(motion_host()) {
        if (options.token.empty()) options.token = random_token();
        document = options.document.empty() ? "untitled.toml" : options.document;
        constraints.load(cache.style(), base_dir);
    }

    MotionHost motion_host() {
        MotionHost host;
        host.with_hair = [this](const auto& use) {
            std::lock_guard lock(cache_mutex);
            const HairstyleResult& r = cache.update();
            use(cache.style(), cache.head(), r);
        };
        host.write_style = [this](const Style& style, const std::string& name) {
            std::vector<std::string> files;
            write_document(style, name, files);
            return files;
        };
        host.file_in_folder = [this](const std::string& name,
                                     std::initializer_list<std::string_view> extensions) {
            return file_in_folder(base_dir, name, extensions);
        };
        return host;
    }

    // The file a painted map of `field` is saved to beside the document `toml_name`.
    static std::string map_file(const std::string& toml_name, const StyleField& field) {
        return stem_of(toml_name) + "." + std::string(field_key(field.path)) + ".png";
    }

    // Writes `style` as `toml_name` in base_dir with its painted maps beside it (each
    // atomically; the TOML last, so it never names a map not yet written). Returns the style
    // as written (painted maps renamed to their files) and the files.
    Style write_document(Style style, const std::string& toml_name,
                         std::vector<std::string>& files) const {
        const std::filesystem::path toml = file_in_folder(base_dir, toml_name, {".toml"});
        for (const StyleField& f : style_schema()) {
            if (f.type != FieldType::kMap) continue;
            ScalarMap& m = *std::get<ScalarMap*>(f.ref(style));
            if (m.kind != ScalarMap::Kind::kImage || !m.pixels) continue;
            const std::string name = map_file(toml_name, f);
            m.image = file_in_folder(base_dir, name, {".png"});
            write_file_atomic(m.image, encode_gray_png(*m.pixels));
            files.push_back(name);
        }
        // The constraint sections as placed ([[tie]] …), with their painted selections.
        constraints.write_masks(base_dir, toml_name, files);
        Style plain = style;
        plain.groups.clear();
        write_file_atomic(toml, style_to_toml(plain, base_dir) + constraints.toml(toml_name));
        files.push_back(toml_name);
        style.groups = constraints.groups(style, base_dir, toml_name);
        return style;
    }

    bool allowed(const httplib::Request& req, httplib::Response& res) const {
        // DNS rebinding: a page of another site that resolves its name to 127.0.0.1 sends
        // its own name as Host, and its own origin.
        const std::string host = req.get_header_value("Host");
        if (std::find(hosts.begin(), hosts.end(), host) == hosts.end()) {
            send_error(res, 403, "refused: Host '" + host + "' is not this server");
            return false;
        }
        if (req.has_header("Origin")) {
            const std::string origin = req.get_header_value("Origin");
            bool ok = false;
            for (const std::string& h : hosts)
                ok |= origin == "http://" + h;
            if (!ok) {
                send_error(res, 403, "refused: Origin '" + origin + "' is not this server");
                return false;
            }
        }
        if (!body_allowed(req, res)) return false;
        if (req.path.rfind("/api/", 0) == 0) {
            const std::string token = req.has_header("X-Wisp-Token")
                                          ? req.get_header_value("X-Wisp-Token")
                                          : req.get_param_value("token");
            if (!same_token(token, options.token)) {
                send_error(res, 403,
                           "refused: the token is missing or wrong (use the URL "
                           "wisp edit printed)");
                return false;
            }
        }
        return true;
    }

    // The body's size, before it is read: a head upload (POST /api/head) may be up to
    // max_head_body bytes, any other request max_body; the server reads no more than the
    // larger (set_payload_max_length), so each route's limit is checked here from the
    // declared length, and a body of undeclared length (chunked) is refused.
    bool body_allowed(const httplib::Request& req, httplib::Response& res) const {
        const bool head = req.method == "POST" && req.path == "/api/head";
        const size_t limit = head ? options.max_head_body : options.max_body;
        if (req.has_header("Transfer-Encoding")) {
            send_error(res, 411, "refused: a request body must give its Content-Length");
            return false;
        }
        const std::string length = req.get_header_value("Content-Length");
        if (length.empty()) return true;
        char* end = nullptr;
        const unsigned long long n = std::strtoull(length.c_str(), &end, 10);
        if (*end || length[0] == '-' || n > limit) {
            send_error(res, 413,
                       cat("refused: the body is ", excerpt(length), " bytes; at most ", limit,
                           head ? " for a head upload" : ""));
            return false;
        }
        return true;
    }

    // The JSON body of a request, or a 400.
    std::optional<nlohmann::json> body(const httplib::Request& req, httplib::Response& res) {
        nlohmann::json j = nlohmann::json::parse(req.body, nullptr, false);
        if (j.is_discarded() || !j.is_object()) {
            send_error(res, 400, "the request body must be a JSON object");
            return std::nullopt;
        }
        return j;
    }

    void routes() {
        server.set_payload_max_length(std::max(options.max_body, options.max_head_body));
        server.set_read_timeout(5, 0);
        server.set_write_timeout(30, 0);
        // Small send buffers, 64 KB (the kernel doubles it; connections inherit the listening
        // socket's) instead of the kernel's autotuned up to 4 MB: a stream (the Motion frames,
        // progress events) then has little in flight, not megabytes of frames queued for a
        // slow page, which gets the newest frame instead. On loopback the other answers do not
        // notice: a 100,000-strand preview (37.8 MB) still arrives in 17 ms.
        server.set_socket_options([](socket_t sock) {
            httplib::default_socket_options(sock);
            const int bytes = 64 * 1024;
            setsockopt(sock, SOL_SOCKET, SO_SNDBUF, &bytes, sizeof bytes);
        });
        server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
            return allowed(req, res) ? httplib::Server::HandlerResponse::Unhandled
                                     : httplib::Server::HandlerResponse::Handled;
        });
        server.set_exception_handler(
            [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
                try {
                    std::rethrow_exception(ep);
                } catch (const Error& e) {
                    send_error(res, 400, e.what());
                } catch (const std::bad_alloc&) {
                    send_error(res, 500, "out of memory");
                } catch (const std::exception& e) {
                    send_error(res, 500, e.what());
                }
            });

        server.Get("/api/schema", [](const httplib::Request&, httplib::Response& res) {
            send_json(res, schema_json());
        });
        server.Get("/api/presets", [](const httplib::Request&, httplib::Response& res) {
            send_json(res, preset_names());
        });
        server.Get("/api/style", [this](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(cache_mutex);
            send_json(res, {{"values", style_values_json(cache.style(), base_dir)},
                            {"document", document},
                            {"toml", style_to_toml(cache.style(), base_dir)},
                            {"stale", stage_name(cache.stale())}});
        });
        server.Post("/api/set", [this](const httplib::Request& req, httplib::Response& res) {
            const auto j = body(req, res);
            if (!j) return;
            if (!j->contains("path") || !(*j)["path"].is_string())
                return send_error(res, 400, "'path' must be a string: the field's TOML path");
            const std::string path = (*j)["path"];
            if (!j->contains("value")) return send_error(res, 400, "'value' is required", path);
            try {
                const std::string value = json_to_toml_value((*j)["value"], path);
                ++hair_requests;  // the update running for the old value is stale
                std::lock_guard lock(cache_mutex);
                const StyleField* f = find_style_field(path);
                if (f && f->type == FieldType::kMap) {
                    // A painted map keeps its pixels while its low and high change: the
                    // same image name is the same painting, whose file may not exist yet.
                    Style next = cache.style();
                    const ScalarMap old = *std::get<ScalarMap*>(f->ref(next));
                    set_style_field(next, path, value, "value", base_dir);
                    ScalarMap& m = *std::get<ScalarMap*>(f->ref(next));
                    if (m.kind == ScalarMap::Kind::kImage && old.pixels && m.image == old.image)
                        m.pixels = old.pixels;
                    cache.set_style(std::move(next));
                } else {
                    cache.set(path, value, "value");
                }
                send_json(res, {{"stale", stage_name(cache.stale())},
                                {"value", style_values_json(cache.style(), base_dir)[path]}});
            } catch (const Error& e) {
                send_error(res, 400, e.what(), path);
            }
        });
        server.Post("/api/preset", [this](const httplib::Request& req, httplib::Response& res) {
            const auto j = body(req, res);
            if (!j) return;
            if (!j->contains("name") || !(*j)["name"].is_string())
                return send_error(res, 400, "'name' must be a preset name", "name");
            try {
                Style style = load_preset((*j)["name"]);
                std::lock_guard lock(cache_mutex);
                cache.set_style(std::move(style));
                constraints.load(cache.style(), base_dir);
                send_json(res, {{"stale", stage_name(cache.stale())}});
            } catch (const Error& e) {
                send_error(res, 400, e.what(), "name");
            }
        });
        server.Get("/api/hair", [this](const httplib::Request& req, httplib::Response& res) {
            size_t limit = kMaxStrandsSent;
            if (req.has_param("strands")) {
                const std::string s = req.get_param_value("strands");
                char* end = nullptr;
                const unsigned long long n = std::strtoull(s.c_str(), &end, 10);
                if (s.empty() || *end || s[0] == '-' || n > kMaxStrandsSent)
                    return send_error(res, 400,
                                      cat("must be a count from 0 to ", kMaxStrandsSent, ", got '",
                                          excerpt(s), "'"),
                                      "strands");
                limit = static_cast<size_t>(n);
            }
            // A preview grows only the strands it sends; a newer request (or a set) cancels
            // this one, even while its stages run.
            const uint64_t ticket = ++hair_requests;
            std::lock_guard lock(cache_mutex);
            // The stale stages report their progress, and the long ones their fraction done:
            // the full hair's as "update", a preview's (the solve after κ) as "preview".
            std::optional<ProgressEvents::Task> task;
            if (const int stages = cache.stages_to_send(limit); stages > 0)
                task.emplace(events, limit >= cache.strands_in_all() ? "update" : "preview",
                             stages);
            std::shared_ptr<const std::string> bytes = cache.hair_bytes(
                limit, CancelToken(hair_requests, ticket, task ? task->fractions() : nullptr),
                task ? task->stages() : StageProgress{});
            if (!bytes && task) task->fail("superseded by a newer request");
            if (!bytes) return send_error(res, 409, "superseded by a newer request");
            send_shared(res, std::move(bytes));
        });
        server.Get("/api/masters", [this](const httplib::Request& req, httplib::Response& res) {
            const uint64_t ticket = ++hair_requests;
            std::lock_guard lock(cache_mutex);
            const CancelToken cancel(hair_requests, ticket);
            const Masters* m = req.get_param_value("preview") == "1"
                                   ? cache.update_masters_preview(cancel)
                                   : cache.update_masters(cancel);
            if (!m) return send_error(res, 409, "superseded by a newer request");
            res.set_content(encode_masters(*m), "application/octet-stream");
        });
        server.Get("/api/head", [this](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(cache_mutex);
            const Head& head = cache.head();
            std::vector<uint8_t> scalp(head.mesh->faces.size(), 0);
            for (const uint32_t f : head.scalp->faces())
                scalp[f] = 1;
            res.set_content(encode_head(*head.mesh, scalp), "application/octet-stream");
        });
        server.Get("/api/stats", [this](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(cache_mutex);
            nlohmann::json stages = nlohmann::json::object();
            for (int s = 0; s < kStageCount; ++s)
                stages[stage_name(Stage(s))] = {{"runs", cache.runs()[s]},
                                                {"ms", cache.last_ms()[s]}};
            send_json(res, {{"stale", stage_name(cache.stale())}, {"stages", stages}});
        });

        // Painting (issue 16 item 3): the map of a field as the painter's image, and a
        // painted map back as a PNG in scalp UV space.
        server.Get("/api/scalp", [this](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(cache_mutex);
            const Scalp& scalp = *cache.head().scalp;
            const Vec3f c = scalp.center(), crown = scalp.crown();
            send_json(res, {{"center", {c.x(), c.y(), c.z()}},
                            {"crown", {crown.x(), crown.y(), crown.z()}},
                            {"max_polar_angle", scalp.max_polar_angle()}});
        });
        server.Get("/api/map", [this](const httplib::Request& req, httplib::Response& res) {
            const std::string path = req.get_param_value("field");
            const StyleField* f = find_style_field(path);
            if (!f || f->type != FieldType::kMap)
                return send_error(res, 400, "must name a scalp map field (maps.density, …)",
                                  "field");
            try {
                std::lock_guard lock(cache_mutex);
                Style style = cache.style();
                const PaintMap m = paint_map(*std::get<ScalarMap*>(f->ref(style)), *f,
                                             *cache.head().scalp, style.growth);
                res.set_content(encode_map(m.t, m.kind, m.low, m.high), "application/octet-stream");
            } catch (const Error& e) {
                send_error(res, 400, e.what(), path);
            }
        });
        server.Post("/api/map", [this](const httplib::Request& req, httplib::Response& res) {
            const std::string path = req.get_param_value("field");
            const StyleField* f = find_style_field(path);
            if (!f || f->type != FieldType::kMap)
                return send_error(res, 400, "must name a scalp map field (maps.density, …)",
                                  "field");
            GrayImage image;
            try {
                image = std::move(decode_image_planes(req.body, "the map", 1).front());
            } catch (const Error& e) {
                return send_error(res, 400, e.what(), "body");
            }
            if (image.width < kMinMapSide || image.height < kMinMapSide ||
                image.width > kMaxMapSide || image.height > kMaxMapSide)
                return send_error(
                    res, 400,
                    cat("the map is ", image.width, "x", image.height, ": each side must be from ",
                        kMinMapSide, " to ", kMaxMapSide, " pixels"),
                    "body");
            // What Save will write, decoded as `wisp generate` will read it.
            auto pixels = std::make_shared<const GrayImage>(
                std::move(decode_image_planes(encode_gray_png(image), "the map", 1).front()));
            std::lock_guard lock(cache_mutex);
            Style next = cache.style();
            const ScalarMap& old = *std::get<ScalarMap*>(f->ref(next));
            const bool scaled = old.kind != ScalarMap::Kind::kConstant;
            float low = 0, high = 0;
            std::string which = "low";
            try {
                low = query_number(req, "low", scaled ? old.low : f->map_low);
                which = "high";
                high = query_number(req, "high", scaled ? old.high : f->map_high);
                which = path;
                nlohmann::json value{
                    {"image", map_file(document, *f)}, {"low", low}, {"high", high}};
                set_style_field(next, path, json_to_toml_value(value, path), "map", base_dir);
            } catch (const Error& e) {
                return send_error(res, 400, e.what(), which == path ? path : path + "." + which);
            }
            std::get<ScalarMap*>(f->ref(next))->pixels = std::move(pixels);
            cache.set_style(std::move(next));
            cache.mark_stale(f->stage);
            send_json(res, {{"stale", stage_name(cache.stale())},
                            {"value", style_values_json(cache.style(), base_dir)[path]}});
        });

        // The document (issue 16 item 6): Save, Open, autosave and export, all inside the
        // style's folder.
        server.Get("/api/files", [this](const httplib::Request&, httplib::Response& res) {
            std::vector<std::string> names;
            std::error_code ec;
            for (const auto& e : std::filesystem::directory_iterator(base_dir, ec)) {
                const std::string name = e.path().filename().string();
                if (e.is_regular_file(ec) && e.path().extension() == ".toml" && name[0] != '.')
                    names.push_back(name);
                if (names.size() >= 1000) break;
            }
            std::sort(names.begin(), names.end());
            std::lock_guard lock(cache_mutex);
            send_json(res, {{"document", document}, {"files", names}});
        });
        server.Post("/api/save", [this](const httplib::Request& req, httplib::Response& res) {
            const auto j = body(req, res);
            if (!j) return;
            std::lock_guard lock(cache_mutex);
            std::string name = document;
            if (j->contains("name")) {
                if (!(*j)["name"].is_string())
                    return send_error(res, 400, "must be a file name such as style.toml", "name");
                name = (*j)["name"];
            }
            std::vector<std::string> files;
            Style saved;
            try {
                saved = write_document(cache.style(), name, files);
            } catch (const Error& e) {
                return send_error(res, 400, e.what(), "name");
            }
            document = name;
            // The painted maps now live in their files under the new name: the same pixels.
            cache.set_style(std::move(saved));
            send_json(res, {{"document", document}, {"files", files}});
        });
        server.Post("/api/autosave", [this](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(cache_mutex);
            std::vector<std::string> files;
            const std::string name = stem_of(document) + ".autosave.toml";
            try {
                write_document(cache.style(), name, files);
            } catch (const Error& e) {
                return send_error(res, 400, e.what(), "document");
            }
            send_json(res, {{"document", document}, {"files", files}});
        });
        server.Post("/api/open", [this](const httplib::Request& req, httplib::Response& res) {
            const auto j = body(req, res);
            if (!j) return;
            if (!j->contains("name") || !(*j)["name"].is_string())
                return send_error(res, 400, "must be a file name such as style.toml", "name");
            const std::string name = (*j)["name"];
            try {
                Style style = load_style(file_in_folder(base_dir, name, {".toml"}));
                // A missing or bad map image is reported at Open, not at the next update. The
                // maps stay files (not pixels): Save leaves them where they are, at their depth.
                for (const StyleField& f : style_schema())
                    if (f.type == FieldType::kMap) {
                        const ScalarMap& m = *std::get<ScalarMap*>(f.ref(style));
                        if (m.kind == ScalarMap::Kind::kImage) read_gray_image(m.image);
                    }
                std::lock_guard lock(cache_mutex);
                cache.set_style(std::move(style));
                cache.mark_stale(Stage::kRoots);  // map files may differ under the same names
                constraints.load(cache.style(), base_dir);
                document = name;
                send_json(res, {{"document", document}, {"stale", stage_name(cache.stale())}});
            } catch (const Error& e) {
                send_error(res, 400, e.what(), "name");
            }
        });
        // The formats Export writes, for the front end's menu.
        server.Get("/api/export", [](const httplib::Request&, httplib::Response& res) {
            nlohmann::json formats = nlohmann::json::array();
            for (const std::string_view ext : kExportFormats)
                formats.push_back(ext);
            send_json(res, {{"formats", formats}});
        });
        server.Post("/api/export", [this](const httplib::Request& req, httplib::Response& res) {
            const auto j = body(req, res);
            if (!j) return;
            if (!j->contains("name") || !(*j)["name"].is_string())
                return send_error(res, 400, "must be a file name such as hair.usda", "name");
            std::filesystem::path file;
            try {
                file = file_in_folder(base_dir, (*j)["name"], kExportFormats);
            } catch (const Error& e) {
                return send_error(res, 400, e.what(), "name");
            }
            std::lock_guard lock(cache_mutex);
            ProgressEvents::Task task(events, "export",
                                      kStageCount - static_cast<int>(cache.stale()) + 1);
            const HairstyleResult& r = *cache.update(CancelToken(task.fractions()), task.stages());
            task.step("write");
            write_hair(file, r.hair);
            send_json(res,
                      {{"file", file.filename().string()}, {"strands", r.hair.strand_count()}});
        });

        motion.add_to(server);
        add_feature_routes(server, state);
        add_progress_route(server, events);

        // The front end: embedded files; "/" is index.html.
        server.Get(R"(/.*)", [](const httplib::Request& req, httplib::Response& res) {
            const std::string path = req.path == "/" ? "/index.html" : req.path;
            for (size_t i = 0; i < detail::kWebAssetCount; ++i) {
                const detail::WebAsset& a = detail::kWebAssets[i];
                if (a.path == path) {
                    res.set_content(std::string(a.body), std::string(a.mime).c_str());
                    res.set_header("X-Content-Type-Options", "nosniff");
                    return;
                }
            }
            send_error(res, 404, "not found");
        });
    }
};

EditServer::EditServer(Style style, std::filesystem::path base_dir, EditOptions options)
    : impl_(std::make_unique<Impl>(std::move(style), std::move(base_dir), std::move(options))) {
    impl_->routes();
}

EditServer::~EditServer() {
    stop();
}

void EditServer::start() {
    Impl& s = *impl_;
    if (s.options.port == 0) {
        s.port = s.server.bind_to_any_port(s.options.host);
    } else {
        s.port = s.server.bind_to_port(s.options.host, s.options.port) ? s.options.port : -1;
    }
    if (s.port <= 0)
        fail("wisp edit: cannot listen on ", s.options.host, ":", s.options.port,
             s.options.port ? " (is the port in use?)" : "");
    const std::string port = std::to_string(s.port);
    s.hosts = {s.options.host + ":" + port, "localhost:" + port, "127.0.0.1:" + port};
    s.listening_done = false;
    s.thread = std::thread([&s] {
        s.server.listen_after_bind();
        s.listening_done = true;
    });
    // A stop() before the loop runs would be lost (httplib's stop only ends a running loop)
    // and the join would wait forever: start() returns once the server is running.
    while (!s.server.is_running() && !s.listening_done)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

void EditServer::stop() {
    if (!impl_ || !impl_->thread.joinable()) return;
    impl_->events.close();  // the progress streams end, freeing their threads
    impl_->server.stop();
    impl_->thread.join();
}

int EditServer::port() const {
    return impl_->port;
}
const std::string& EditServer::token() const {
    return impl_->options.token;
}
std::string EditServer::url() const {
    return cat("http://", impl_->options.host, ":", impl_->port, "/?token=", impl_->options.token);
}

}  // namespace wisp
