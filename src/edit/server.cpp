#include "edit/server.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "edit/stage_cache.hpp"
#include "edit/wire.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"

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

void send_json(httplib::Response& res, const nlohmann::json& j, int status = 200) {
    res.status = status;
    res.set_content(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message,
                const std::string& field = {}) {
    nlohmann::json j{{"error", excerpt(message, 1000)}};
    if (!field.empty()) j["field"] = excerpt(field, 200);
    send_json(res, j, status);
}

// Constant-time comparison, so the token cannot be found a byte at a time by timing.
bool same_token(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    unsigned char diff = 0;
    for (size_t i = 0; i < a.size(); ++i)
        diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
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

    Impl(Style style, std::filesystem::path dir, EditOptions opts)
        : options(std::move(opts)), base_dir(std::move(dir)), cache(std::move(style), base_dir) {
        if (options.token.empty()) options.token = random_token();
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
        server.set_payload_max_length(options.max_body);
        server.set_read_timeout(5, 0);
        server.set_write_timeout(30, 0);
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
            send_json(res, {{"values", style_values_json(cache.style())},
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
                cache.set(path, value, "value");
                send_json(res, {{"stale", stage_name(cache.stale())},
                                {"value", style_values_json(cache.style())[path]}});
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
            const Hair* hair = cache.update_preview(limit, CancelToken(hair_requests, ticket));
            if (!hair) return send_error(res, 409, "superseded by a newer request");
            res.set_content(encode_strands(*hair, limit, cache.strands_in_all()),
                            "application/octet-stream");
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
