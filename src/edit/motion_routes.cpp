#include "edit/motion_routes.hpp"

#include <httplib.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "dynamics/animation_pictures.hpp"
#include "dynamics/motion.hpp"
#include "edit/http_util.hpp"
#include "edit/motion_session.hpp"
#include "edit/wire.hpp"
#include "groom/style_toml.hpp"
#include "io/frame_files.hpp"
#include "io/hair_io.hpp"
#include "io/usda.hpp"

namespace wisp {
namespace {

// A bad value in a request: a 400 naming the field.
struct BadField {
    std::string field, error;
};

nlohmann::json body_of(const httplib::Request& req) {
    if (req.body.empty()) return nlohmann::json::object();
    nlohmann::json j = nlohmann::json::parse(req.body, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        throw BadField{"body", "the request body must be a JSON object"};
    return j;
}

// A finite number in [lo, hi], or `fallback` when absent.
double number(const nlohmann::json& j, const char* name, double fallback, double lo, double hi) {
    if (!j.contains(name)) return fallback;
    const nlohmann::json& v = j[name];
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo ||
        v.get<double>() > hi)
        throw BadField{
            name, cat("must be a number from ", lo, " to ", hi, ", got ", excerpt(v.dump(), 64))};
    return v.get<double>();
}

// Three finite numbers each within ±limit, or `fallback` when absent.
Vec3f vec3(const nlohmann::json& j, const char* name, const Vec3f& fallback, double limit) {
    if (!j.contains(name)) return fallback;
    const nlohmann::json& v = j[name];
    bool ok = v.is_array() && v.size() == 3;
    Vec3f out = Vec3f::Zero();
    for (int c = 0; ok && c < 3; ++c) {
        ok = v[c].is_number() && std::isfinite(v[c].get<double>()) &&
             std::abs(v[c].get<double>()) <= limit;
        if (ok) out[c] = v[c].get<float>();
    }
    if (!ok)
        throw BadField{name, cat("must be three finite numbers within ±", limit, ", got ",
                                 excerpt(v.dump(), 64))};
    return out;
}

nlohmann::json vec_json(const Vec3f& v) {
    return {v.x(), v.y(), v.z()};
}

// The dynamics fields a running session takes on its next step (AwtSimulation::set_params);
// the others shape the wisp tree and apply when Motion starts again.
constexpr std::string_view kLiveDynamics[] = {
    "dynamics.stiffness",  "dynamics.stretch",         "dynamics.damping",
    "dynamics.air_drag",   "dynamics.split_threshold", "dynamics.merge_velocity",
    "dynamics.friction",   "dynamics.repulsion",       "dynamics.repulsion_angle",
    "dynamics.iterations", "dynamics.hair_collisions", "dynamics.body_collisions"};

// 12 numbers: the rotation row by row, then the translation (cm).
std::string pose_text(const RigidTransform& t) {
    std::string out;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            out += cat(t.rotation(r, c), " ");
    return out + cat(t.translation.x(), " ", t.translation.y(), " ", t.translation.z());
}

// What a session starts from: the style and its hair when Motion was switched on.
struct Start {
    Style style;
    Hair rest;
    std::vector<float> held;  // per wisp (SolveStats::held_length)
    Mesh body;
    HeadFrame frame;
};

}  // namespace

struct MotionRoutes::Impl {
    MotionHost host;
    std::mutex mutex;  // guards what follows; the session is thread-safe itself
    std::shared_ptr<const Start> start;
    std::shared_ptr<MotionSession> session;
    MotionSessionSettings settings;
    DynamicsSpec dynamics;  // the start style's, with the live changes since
    bool wind_changed_while_playing = false;
    bool dynamics_changed_while_playing = false;
    std::mutex export_mutex;  // one export at a time
    // The export's progress (GET /api/motion/export): frames written of all, and the stage.
    std::atomic<int> export_done{0}, export_frames{0};
    std::atomic<bool> exporting{false};
    std::atomic<const char*> export_stage{""};
    // Open frame streams. Each holds one of the server's 8 threads while it is open, as a
    // progress stream does (at most ProgressEvents::kMaxListeners): 2 frame streams (a page
    // and its reload, say) leave requests at least 2 threads.
    static constexpr int kMaxStreams = 2;
    std::atomic<int> streams{0};

    std::shared_ptr<MotionSession> current() {
        std::lock_guard lock(mutex);
        if (!session) throw BadField{"session", "Motion is not started (POST /api/motion/start)"};
        return session;
    }

    std::shared_ptr<MotionSession> make_session(const Start& s, const MotionSessionSettings& base,
                                                const DynamicsSpec& dynamics) const {
        MotionSessionSettings settings = base;
        settings.wisp_held = s.held;
        return std::make_shared<MotionSession>(s.rest, s.body, s.frame, dynamics,
                                               s.style.prototype.kind, settings);
    }

    // One live dynamics field, checked by the style reader and then by the simulation.
    void set_dynamics(const nlohmann::json& j) {
        if (!j.contains("path") || !j["path"].is_string())
            throw BadField{"path", "must be a dynamics field's TOML path (dynamics.stiffness, …)"};
        const std::string path = j["path"];
        if (std::find(std::begin(kLiveDynamics), std::end(kLiveDynamics), path) ==
            std::end(kLiveDynamics))
            throw BadField{path,
                           "is not a live dynamics field: it shapes the wisp tree and applies "
                           "when Motion starts again"};
        if (!j.contains("value")) throw BadField{path, "'value' is required"};
        std::shared_ptr<MotionSession> m = current();
        Style probe;
        {
            std::lock_guard lock(mutex);
            probe.dynamics = dynamics;
        }
        try {
            set_style_field(probe, path, json_to_toml_value(j["value"], path), "value");
            m->set_dynamics(probe.dynamics);
        } catch (const Error& e) {
            throw BadField{path, e.what()};
        }
        std::lock_guard lock(mutex);
        dynamics = probe.dynamics;
        if (m->frames_published() > 1) dynamics_changed_while_playing = true;
    }

    nlohmann::json describe(const MotionSession& m) {
        const AnimationStats stats = m.stats();
        size_t points = 0;
        MotionSessionSettings settings;
        HeadFrame head_frame;
        {
            std::lock_guard lock(mutex);
            head_frame = start->frame;
            for (uint32_t s : m.shown())
                points += start->rest.strand_size(s);
            settings = this->settings;
        }
        return {{"frame", m.frames_published() - 1},
                {"playing", m.playing()},
                {"error", m.error()},
                {"shown", m.shown().size()},
                {"points", points},
                {"fps", settings.fps},
                {"single_level", settings.single_level},
                {"pivot", vec_json(m.head_pivot())},
                {"head_center", vec_json(head_frame.center)},
                {"head_radius", head_frame.radius},
                {"levels", stats.levels},
                {"finest_nodes", stats.finest_nodes},
                {"active_per_level", m.active_per_level()},
                {"splits", stats.splits},
                {"merges", stats.merges},
                {"steps", stats.steps},
                {"step_ms", stats.step_ms_mean},
                {"skin_ms", stats.skin_ms_mean}};
    }

    void start_session(const nlohmann::json& j) {
        MotionSessionSettings next;
        next.shown_strands = static_cast<size_t>(number(j, "strands", 20000, 1, 1e7));
        next.fps = number(j, "fps", 25, 1, 120);
        if (j.contains("single_level")) {
            if (!j["single_level"].is_boolean())
                throw BadField{"single_level", "must be true or false"};
            next.single_level = j["single_level"];
        }
        auto s = std::make_shared<Start>();
        host.with_hair([&](const Style& style, const Head& head, const HairstyleResult& r) {
            s->style = style;
            s->rest = r.hair;
            s->held = r.solve.held_length;
            s->body = *head.mesh;
            s->frame = head_frame(*head.scalp);
        });
        std::shared_ptr<MotionSession> made;
        try {
            made = make_session(*s, next, s->style.dynamics);
        } catch (const Error& e) {
            throw BadField{"dynamics", e.what()};
        }
        std::shared_ptr<MotionSession> old;
        std::lock_guard lock(mutex);
        old = std::move(session);
        start = std::move(s);
        session = std::move(made);
        settings = next;
        dynamics = start->style.dynamics;
        wind_changed_while_playing = dynamics_changed_while_playing = false;
    }

    void reset() {
        std::shared_ptr<const Start> s;
        MotionSessionSettings at;
        DynamicsSpec now;
        {
            std::lock_guard lock(mutex);
            if (!start) throw BadField{"session", "Motion is not started (POST /api/motion/start)"};
            s = start;
            at = settings;
            now = dynamics;
        }
        auto made = make_session(*s, at, now);
        std::shared_ptr<MotionSession> old;
        std::lock_guard lock(mutex);
        old = std::move(session);
        session = std::move(made);
        wind_changed_while_playing = dynamics_changed_while_playing = false;
    }

    // {"name": "take.usda", "png": bool, "mp4": bool}: the animation, and with "png" its
    // frames as take_####.png, with "mp4" as take.mp4, rendered as `wisp animate --png
    // --mp4` renders them (animation_pictures.hpp).
    nlohmann::json export_animation(const nlohmann::json& j) {
        if (!j.contains("name") || !j["name"].is_string())
            throw BadField{"name", "must be a file name such as take.usda"};
        const std::string name = j["name"];
        bool pictures[2] = {false, false};  // png, mp4
        for (int k = 0; k < 2; ++k) {
            const char* key = k ? "mp4" : "png";
            if (!j.contains(key)) continue;
            if (!j[key].is_boolean()) throw BadField{key, "must be true or false"};
            pictures[k] = j[key];
        }
        const bool png = pictures[0], mp4 = pictures[1];
        // Before any work, as `wisp animate` checks its outputs first.
        if (mp4 && !program_on_path("ffmpeg"))
            throw BadField{"mp4",
                           "ffmpeg was not found on PATH, so no MP4 can be made (scripts/setup "
                           "installs it); export without MP4, or with PNG frames only"};
        std::shared_ptr<MotionSession> m = current();
        std::shared_ptr<const Start> s;
        MotionSessionSettings at;
        Style style;  // as the session runs: the start style with the live dynamics
        bool wind_changed = false, dynamics_changed = false;
        {
            std::lock_guard lock(mutex);
            s = start;
            at = settings;
            style = start->style;
            style.dynamics = dynamics;
            wind_changed = wind_changed_while_playing;
            dynamics_changed = dynamics_changed_while_playing;
        }
        const std::string ext = std::filesystem::path(name).extension().string();
        std::filesystem::path out;
        try {
            out = host.file_in_folder(name, {".usda", ".hair", ".obj", ".ply"});
        } catch (const Error& e) {
            throw BadField{"name", e.what()};
        }
        // Per-frame formats are numbered as `wisp animate -o take.hair` numbers them.
        const bool per_frame = ext != ".usda";
        const std::string base = std::filesystem::path(name).stem().string();
        const std::string pattern = per_frame ? base + "_####" + ext : name;

        std::lock_guard one_export(export_mutex);
        // Paused first, so the recording and the frame count agree.
        m->pause();
        const int frames = static_cast<int>(m->frames_published());
        struct Progress {
            Impl& impl;
            ~Progress() {
                impl.exporting = false;
                impl.export_stage = "";
            }
        } progress{*this};
        export_done = 0;
        export_frames = frames;
        export_stage = "animating";
        exporting = true;
        std::vector<std::string> files;
        const std::string motion_name = base + ".motion.json";
        const std::filesystem::path motion_path = host.file_in_folder(motion_name, {".json"});
        m->write_recording(motion_path);
        files.push_back(motion_name);
        const std::string style_name = base + ".style.toml";
        for (const std::string& f : host.write_style(style, style_name))
            files.push_back(f);

        // The frames from the files just written, as `wisp animate` reads them.
        const Motion motion = read_motion(motion_path, s->frame);
        AnimateSettings animate_settings;
        animate_settings.frames = frames;
        animate_settings.fps = at.fps;
        animate_settings.single_level = at.single_level;
        animate_settings.wisp_held = s->held;
        std::unique_ptr<UsdaClipWriter> clips;
        std::unique_ptr<FileSeries> series;
        if (!per_frame) {
            clips = std::make_unique<UsdaClipWriter>(out, s->rest, at.fps, size_t(frames));
        } else {
            const size_t first = pattern.find('#'), last = pattern.find_last_of('#') + 1;
            series = std::make_unique<FileSeries>(
                (out.parent_path() / pattern.substr(0, first)).string(), pattern.substr(last),
                static_cast<int>(last - first));
        }
        // The pictures: PNG frames beside the animation, or for an MP4 alone in a temporary
        // folder, removed however the export ends (as `wisp animate --mp4` does).
        const std::string png_name = base + "_####.png", mp4_name = base + ".mp4";
        std::filesystem::path mp4_path;
        if (mp4) mp4_path = host.file_in_folder(mp4_name, {".mp4"});
        const PictureFrames picture_frames(
            png ? (out.parent_path() / png_name).string() : std::string(), mp4);
        std::optional<AnimationPictures> pictures_out;
        if (!picture_frames.pattern().empty()) {
            RenderOptions look;  // `wisp animate`'s: its defaults of --view, --size and the look
            look.width = look.height = kAnimationPictureSide;
            pictures_out.emplace(look, s->body, s->frame, motion, frames / at.fps);
            export_stage = "rendering";
        }
        animate(s->rest, s->body, s->frame, motion, style.dynamics, style.prototype.kind,
                animate_settings, [&](int f, const Hair& hair, const FramePose& pose) {
                    if (clips) {
                        clips->add(hair);
                    } else {
                        write_hair(out.parent_path() / numbered(pattern, f), hair);
                        series->added(static_cast<size_t>(f));
                    }
                    if (pictures_out)
                        pictures_out->write(numbered(picture_frames.pattern(), f), hair, pose);
                    export_done = f + 1;
                });
        if (clips) clips->finish();
        if (series) series->keep();
        files.push_back(per_frame ? numbered(pattern, 0) : name);
        if (png) files.push_back(numbered(png_name, 0));
        if (mp4) {
            export_stage = "encoding";
            try {
                encode_mp4(picture_frames.pattern(), at.fps, mp4_path);
            } catch (const Error& e) {
                throw BadField{"mp4", e.what()};
            }
            files.push_back(mp4_name);
        }
        std::string command = "wisp animate '" + style_name + "' --motion '" + motion_name + "' " +
                              m->replay_arguments() + " -o '" + name + "'";
        if (png) command += " --png '" + png_name + "'";
        if (mp4) command += " --mp4 '" + mp4_name + "'";
        if (at.single_level) command += " --single-level";
        nlohmann::json result{{"files", files}, {"frames", frames}, {"command", command}};
        if (wind_changed || dynamics_changed)
            result["warning"] = cat(
                "the ", wind_changed ? "wind" : "", wind_changed && dynamics_changed ? " and " : "",
                dynamics_changed ? "dynamics" : "",
                " changed while the motion played: a motion file and a style hold one value "
                "each, so the replay uses the last ones and differs from what was shown");
        return result;
    }

    // The frame stream: a message (motion_session.hpp) whenever the simulation published a
    // frame and the client took the last one. Each call of the provider sends the newest
    // frame, so a slow client skips frames (TCP holds what is in flight, nothing queues
    // here) and the simulation never waits for it. The provider waits at most
    // kStreamWaitMs for a frame, so a server stopping (httplib checks between calls) ends
    // open streams promptly; a session replaced (start, reset, stop) ends them too.
    void stream(const httplib::Request& req, httplib::Response& res) {
        constexpr int kStreamWaitMs = 100;
        struct Stream {
            std::shared_ptr<MotionSession> session;
            bool tree = false;
            std::optional<uint32_t> after;
            uint64_t events = 0;
            std::string message;
        };
        auto st = std::make_shared<Stream>();
        st->session = current();
        if (req.has_param("tree")) {
            const std::string t = req.get_param_value("tree");
            if (t != "0" && t != "1")
                throw BadField{"tree", "must be 0 or 1, got '" + excerpt(t) + "'"};
            st->tree = t == "1";
        }
        if (++streams > kMaxStreams) {
            --streams;
            return send_error(res, 503, "too many motion streams open");
        }
        if (st->tree) st->session->tree();  // from now on every frame encodes its tree
        // Events from the current frame on: the ones before it flashed long ago.
        st->events = st->session->events_published();
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "application/octet-stream",
            [this, st](size_t, httplib::DataSink& sink) {
                {
                    std::lock_guard lock(mutex);
                    if (session != st->session) {
                        sink.done();
                        return true;
                    }
                }
                if (!st->session->stream_message(st->after, st->tree, kStreamWaitMs, st->events,
                                                 st->message))
                    return true;  // nothing new yet: asked again unless the server stops
                uint32_t frame = 0;
                std::memcpy(&frame, st->message.data() + 16, 4);
                st->after = frame;
                return sink.write(st->message.data(), st->message.size());
            },
            [this](bool) { --streams; });
    }

    void add_to(httplib::Server& server) {
        // Runs `f`; a BadField or wisp::Error is a 400 naming the field.
        const auto guarded = [](auto f) {
            return [f](const httplib::Request& req, httplib::Response& res) {
                try {
                    f(req, res);
                } catch (const BadField& e) {
                    send_error(res, 400, e.error, e.field);
                } catch (const Error& e) {
                    send_error(res, 400, e.what(), "motion");
                }
            };
        };
        server.Post("/api/motion/start",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        start_session(body_of(req));
                        std::shared_ptr<MotionSession> m = current();
                        send_json(res, describe(*m));
                    }));
        server.Post("/api/motion/reset",
                    guarded([this](const httplib::Request&, httplib::Response& res) {
                        reset();
                        std::shared_ptr<MotionSession> m = current();
                        send_json(res, describe(*m));
                    }));
        server.Post("/api/motion/stop",
                    guarded([this](const httplib::Request&, httplib::Response& res) {
                        std::shared_ptr<MotionSession> old;
                        {
                            std::lock_guard lock(mutex);
                            old = std::move(session);
                        }
                        send_json(res, {{"stopped", old != nullptr}});
                    }));
        server.Get("/api/motion", guarded([this](const httplib::Request&, httplib::Response& res) {
                       std::shared_ptr<MotionSession> m = current();
                       send_json(res, describe(*m));
                   }));
        server.Post("/api/motion/play",
                    guarded([this](const httplib::Request&, httplib::Response& res) {
                        current()->play();
                        send_json(res, {{"playing", true}});
                    }));
        server.Post("/api/motion/pause",
                    guarded([this](const httplib::Request&, httplib::Response& res) {
                        current()->pause();
                        send_json(res, {{"playing", false}});
                    }));
        server.Post("/api/motion/step",
                    guarded([this](const httplib::Request&, httplib::Response& res) {
                        std::shared_ptr<MotionSession> m = current();
                        if (m->playing()) throw BadField{"playing", "pause before stepping"};
                        m->step();
                        if (!m->error().empty()) throw BadField{"simulation", m->error()};
                        send_json(res, {{"frame", m->frames_published() - 1}});
                    }));
        server.Post(
            "/api/motion/drag",
            guarded([this](const httplib::Request& req, httplib::Response& res) {
                const nlohmann::json j = body_of(req);
                const Vec3f rotate = vec3(j, "rotate", Vec3f::Zero(), kMaxMotionRotate);
                const Vec3f translate = vec3(j, "translate", Vec3f::Zero(), kMaxMotionTranslate);
                current()->drag(rotate, translate);
                send_json(res, {{"rotate", vec_json(rotate)}, {"translate", vec_json(translate)}});
            }));
        server.Post("/api/motion/preset",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        const nlohmann::json j = body_of(req);
                        if (!j.contains("name") || !j["name"].is_string())
                            throw BadField{"name",
                                           "must be a motion preset name (lean, shake, "
                                           "nod, jump, run, still)"};
                        try {
                            current()->play_preset(j["name"].get<std::string>());
                        } catch (const Error& e) {
                            throw BadField{"name", e.what()};
                        }
                        send_json(res, {{"preset", j["name"]}});
                    }));
        // A motion file's JSON as the body (the page's "file…" button), played like a preset.
        server.Post("/api/motion/file",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        try {
                            current()->play_motion_file(req.body, "motion file");
                        } catch (const Error& e) {
                            throw BadField{"motion", e.what()};
                        }
                        send_json(res, {{"motion", "file"}});
                    }));
        server.Post("/api/motion/wind",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        const nlohmann::json j = body_of(req);
                        Vec3f direction = vec3(j, "direction", Vec3f(1, 0, 0), 1e6);
                        const float strength = static_cast<float>(number(j, "strength", 0, 0, 1e5));
                        const float gust = static_cast<float>(number(j, "gust", 0, 0, 1e5));
                        const float frequency =
                            static_cast<float>(number(j, "frequency", 0.5, 0, 100));
                        if (strength > 0 && direction.norm() < 1e-6f)
                            throw BadField{"direction", "must not be zero when strength > 0"};
                        const Vec3f wind = strength > 0 ? Vec3f(direction.normalized() * strength)
                                                        : Vec3f(Vec3f::Zero());
                        std::shared_ptr<MotionSession> m = current();
                        m->set_wind(wind, gust, frequency);
                        {
                            std::lock_guard lock(mutex);
                            if (m->frames_published() > 1) wind_changed_while_playing = true;
                        }
                        send_json(res, {{"wind", vec_json(wind)}});
                    }));
        server.Post("/api/motion/dynamics",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        set_dynamics(body_of(req));
                        send_json(res, {{"applied", "next step"}});
                    }));
        server.Get("/api/motion/strands",
                   guarded([this](const httplib::Request&, httplib::Response& res) {
                       std::shared_ptr<MotionSession> m = current();
                       std::lock_guard lock(mutex);
                       res.set_content(encode_strands(start->rest, m->shown().size()),
                                       "application/octet-stream");
                   }));
        server.Get(
            "/api/motion/frame",
            guarded([this](const httplib::Request& req, httplib::Response& res) {
                std::optional<uint32_t> after;
                if (req.has_param("after")) {
                    const std::string s = req.get_param_value("after");
                    char* end = nullptr;
                    const long long v = std::strtoll(s.c_str(), &end, 10);
                    if (s.empty() || *end || v < -1 || v > 0xffffffffLL)
                        throw BadField{"after",
                                       "must be a frame index (or -1), got '" + excerpt(s) + "'"};
                    if (v >= 0) after = static_cast<uint32_t>(v);
                }
                int wait = 0;
                if (req.has_param("wait")) {
                    const std::string s = req.get_param_value("wait");
                    char* end = nullptr;
                    const long v = std::strtol(s.c_str(), &end, 10);
                    if (s.empty() || *end || v < 0 || v > 1000)
                        throw BadField{"wait", "must be 0 to 1000 ms, got '" + excerpt(s) + "'"};
                    wait = static_cast<int>(v);
                }
                std::shared_ptr<MotionSession> m = current();
                const std::optional<MotionFrame> f = m->frame_after(after, wait);
                if (!f) {
                    res.status = 204;
                    return;
                }
                // The head's and body's poses, so the view poses the mesh with the hair.
                res.set_header("X-Wisp-Head", pose_text(f->head));
                res.set_header("X-Wisp-Body", pose_text(f->body));
                res.set_content(f->bytes, "application/octet-stream");
            }));
        server.Get("/api/motion/stream",
                   guarded([this](const httplib::Request& req, httplib::Response& res) {
                       stream(req, res);
                   }));
        server.Get("/api/motion/tree",
                   guarded([this](const httplib::Request&, httplib::Response& res) {
                       const MotionFrame tree = current()->tree();
                       res.set_content(tree.bytes, "application/octet-stream");
                   }));
        server.Post("/api/motion/record",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        const nlohmann::json j = body_of(req);
                        if (!j.contains("name") || !j["name"].is_string())
                            throw BadField{"name", "must be a file name such as take.json"};
                        const std::string name = j["name"];
                        std::filesystem::path path;
                        try {
                            path = host.file_in_folder(name, {".json"});
                        } catch (const Error& e) {
                            throw BadField{"name", e.what()};
                        }
                        std::shared_ptr<MotionSession> m = current();
                        m->write_recording(path);
                        send_json(res, {{"file", name},
                                        {"frames", m->frames_published()},
                                        {"arguments", m->replay_arguments()}});
                    }));
        server.Post("/api/motion/export",
                    guarded([this](const httplib::Request& req, httplib::Response& res) {
                        send_json(res, export_animation(body_of(req)));
                    }));
        server.Get("/api/motion/export",
                   guarded([this](const httplib::Request&, httplib::Response& res) {
                       send_json(res, {{"exporting", exporting.load()},
                                       {"stage", export_stage.load()},
                                       {"done", export_done.load()},
                                       {"frames", export_frames.load()}});
                   }));
    }
};

MotionRoutes::MotionRoutes(MotionHost host) : impl_(std::make_unique<Impl>()) {
    impl_->host = std::move(host);
}

MotionRoutes::~MotionRoutes() = default;

void MotionRoutes::add_to(httplib::Server& server) {
    impl_->add_to(server);
}

}  // namespace wisp
