// The Motion mode's endpoints (issue 17) on loopback: the security rules, bad values as 400s
// naming the field, frames that move, the tree, and an export whose files `wisp animate`
// reads back into the frames the browser saw, byte for byte.
#include "edit/motion_routes.hpp"

#include <httplib.h>

#include <gtest/gtest.h>

#include <sys/socket.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <thread>

#include <nlohmann/json.hpp>

#include "dynamics/animate.hpp"
#include "edit/server.hpp"
#include "edit/wire.hpp"
#include "groom/style_toml.hpp"
#include "io/hair_io.hpp"

namespace wisp {
namespace {

std::vector<Vec3f> frame_positions(const std::string& bytes) {
    EXPECT_EQ(bytes.substr(0, 8), "WISPFRAM");
    uint32_t points = 0;
    std::memcpy(&points, bytes.data() + 16, 4);
    EXPECT_EQ(bytes.size(), 20 + 12 * size_t(points));
    std::vector<Vec3f> out(points);
    for (size_t i = 0; i < out.size(); ++i)
        std::memcpy(out[i].data(), bytes.data() + 20 + 12 * i, 12);
    return out;
}

uint32_t frame_index(const std::string& bytes) {
    uint32_t f = 0;
    std::memcpy(&f, bytes.data() + 12, 4);
    return f;
}

// Reads GET `path` as a frame stream: its length-prefixed messages, each given to `on` until
// it returns false.
httplib::Result read_stream(httplib::Client& client, const httplib::Headers& headers,
                            const std::string& path,
                            const std::function<bool(const std::string&)>& on) {
    std::string pending;
    return client.Get(path, headers, [&](const char* data, size_t n) {
        pending.append(data, n);
        while (pending.size() >= 4) {
            uint32_t length = 0;
            std::memcpy(&length, pending.data(), 4);
            if (pending.size() < 4 + size_t(length)) break;
            const std::string message = pending.substr(4, length);
            pending.erase(0, 4 + size_t(length));
            if (!on(message)) return false;
        }
        return true;
    });
}

// version, frame, frame bytes, tree bytes, events of a stream message.
std::array<uint32_t, 5> message_header(const std::string& message) {
    EXPECT_EQ(message.substr(0, 8), "WISPMOTN");
    std::array<uint32_t, 5> h{};
    std::memcpy(h.data(), message.data() + 8, 20);
    EXPECT_EQ(message.size(), 124 + size_t(h[2]) + h[3] + 16 * size_t(h[4]));
    return h;
}

class MotionRoutesTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               ("wisp_motion_routes_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        style_ = load_preset("long-straight");
        style_.wisps = 40;
        style_.strands = 400;
        style_.points_per_strand = 10;
        server_ = std::make_unique<EditServer>(style_, dir_);
        server_->start();
        client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
        client_->set_read_timeout(60, 0);
        headers_ = {{"X-Wisp-Token", server_->token()}};
    }
    void TearDown() override {
        server_->stop();
        std::filesystem::remove_all(dir_);
    }

    httplib::Result post(const std::string& path, const std::string& body = "{}") {
        return client_->Post(path, headers_, body, "application/json");
    }
    httplib::Result get(const std::string& path) { return client_->Get(path, headers_); }
    // A 400 whose "field" is `field`.
    void expect_bad(const std::string& path, const std::string& body, const std::string& field) {
        const auto r = post(path, body);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 400) << path << " " << body << ": " << r->body;
        const auto j = nlohmann::json::parse(r->body, nullptr, false);
        EXPECT_EQ(j.value("field", ""), field) << path << " " << body << ": " << r->body;
        EXPECT_FALSE(j.value("error", "").empty());
    }

    std::filesystem::path dir_;
    Style style_;
    std::unique_ptr<EditServer> server_;
    std::unique_ptr<httplib::Client> client_;
    httplib::Headers headers_;
};

TEST_F(MotionRoutesTest, RefusesWithoutTokenAndBadValuesNameTheirField) {
    // The token and Host rules hold for the motion routes as for every /api/ path.
    auto r = client_->Post("/api/motion/start", "{}", "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403);
    r = client_->Post("/api/motion/play",
                      {{"X-Wisp-Token", server_->token()}, {"Origin", "http://evil.example"}}, "{}",
                      "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403);

    expect_bad("/api/motion/play", "{}", "session");  // not started
    expect_bad("/api/motion/start", R"({"fps": 0})", "fps");
    expect_bad("/api/motion/start", R"({"strands": -3})", "strands");
    expect_bad("/api/motion/start", R"({"single_level": "yes"})", "single_level");
    expect_bad("/api/motion/start", "[1]", "body");
    ASSERT_EQ(post("/api/motion/start", R"({"strands": 100})")->status, 200);
    expect_bad("/api/motion/drag", R"({"rotate": [1, 2]})", "rotate");
    expect_bad("/api/motion/drag", R"({"rotate": [1, 2, "x"]})", "rotate");
    expect_bad("/api/motion/drag", R"({"translate": [1e300, 0, 0]})", "translate");
    expect_bad("/api/motion/drag", "not json", "body");
    expect_bad("/api/motion/preset", R"({"name": "moonwalk"})", "name");
    expect_bad("/api/motion/preset", R"({"name": 3})", "name");
    expect_bad("/api/motion/wind", R"({"strength": -1})", "strength");
    expect_bad("/api/motion/wind", R"({"strength": 100, "direction": [0, 0, 0]})", "direction");
    expect_bad("/api/motion/wind", R"({"frequency": 1000})", "frequency");
    expect_bad("/api/motion/record", R"({"name": "../x.json"})", "name");
    expect_bad("/api/motion/record", R"({"name": "x.toml"})", "name");
    expect_bad("/api/motion/export", R"({"name": "/tmp/x.usda"})", "name");
    expect_bad("/api/motion/export", R"({"name": "x.npz"})", "name");
    expect_bad("/api/motion/dynamics", R"({"path": "dynamics.levels", "value": 2})",
               "dynamics.levels");  // shapes the tree: not live
    expect_bad("/api/motion/dynamics", R"({"path": "dynamics.stiffness", "value": -1})",
               "dynamics.stiffness");
    expect_bad("/api/motion/dynamics", R"({"path": "dynamics.friction", "value": 500})",
               "dynamics.friction");
    expect_bad("/api/motion/dynamics", R"({"value": 1})", "path");
    EXPECT_EQ(
        post("/api/motion/dynamics", R"({"path": "dynamics.stiffness", "value": 400})")->status,
        200);
    r = get("/api/motion/frame?after=abc");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);
    r = get("/api/motion/frame?after=0&wait=99999");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);
    // Paused: nothing past frame 0.
    r = get("/api/motion/frame?after=0&wait=50");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 204);
    // Still serving, still at rest.
    const auto state = nlohmann::json::parse(get("/api/motion")->body);
    EXPECT_EQ(state["frame"], 0);
    EXPECT_EQ(state["error"], "");
}

TEST_F(MotionRoutesTest, AMotionFilePlaysLikeAPresetAndABadOneNamesItsField) {
    ASSERT_EQ(post("/api/motion/start", R"({"strands": 100})")->status, 200);
    auto r = get("/api/motion/frame");
    ASSERT_EQ(r->status, 200);
    const std::vector<Vec3f> rest = frame_positions(r->body);
    // docs/motion.md's file: the head turns 30° about the neck by 0.4 s.
    const std::string file = R"({"format": "wisp-motion", "version": 1, "units": "head",
        "head": {"pivot": [0, -1.2, 0], "keys": [{"t": 0.0}, {"t": 0.4, "rotate": [0, 30, 0]}]},
        "body": {"keys": []}, "duration": 1.0})";
    r = post("/api/motion/file", file);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    for (int i = 1; i <= 12; ++i)
        ASSERT_EQ(post("/api/motion/step")->status, 200);
    r = get("/api/motion/frame?after=11&wait=1000");
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_GT((frame_positions(r->body)[0] - rest[0]).norm(), 0.5f);  // the roots turned

    expect_bad("/api/motion/file", "{\"format\": \"wisp-motion\"", "motion");  // truncated
    expect_bad("/api/motion/file", R"({"format": "wisp-motion", "version": 1, "units": "head",
        "head": {"keys": [{"t": 0.0, "rotate": [0, NaN, 0]}]}})",
               "motion");
    expect_bad("/api/motion/file", R"({"format": "wisp-motion", "version": 1, "units": "head",
        "head": {"keys": [{"t": 1.0}, {"t": 0.5}]}})",
               "motion");  // keys out of order
}

TEST_F(MotionRoutesTest, StepsDragsDrawsTheTreeAndExportsWhatWisAnimateReplays) {
    auto r = post("/api/motion/start", R"({"strands": 150, "fps": 25})");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const auto started = nlohmann::json::parse(r->body);
    EXPECT_EQ(started["shown"], 150);
    EXPECT_EQ(started["frame"], 0);
    EXPECT_GE(started["levels"].get<int>(), 2);

    r = get("/api/motion/strands");
    ASSERT_EQ(r->status, 200);
    ASSERT_EQ(r->body.substr(0, 8), "WISPHAIR");
    uint32_t header[4];
    std::memcpy(header, r->body.data() + 8, sizeof header);
    EXPECT_EQ(header[1], 150u);
    EXPECT_EQ(header[2], started["points"].get<uint32_t>());

    std::vector<std::string> seen;
    r = get("/api/motion/frame");
    ASSERT_EQ(r->status, 200);
    seen.push_back(r->body);
    EXPECT_TRUE(r->has_header("X-Wisp-Head"));
    const std::vector<Vec3f> rest = frame_positions(r->body);
    ASSERT_EQ(rest.size(), header[2]);

    // The head turned and moved by "mouse" drags, a frame at a time.
    ASSERT_EQ(post("/api/motion/wind", R"({"direction": [1, 0, 0], "strength": 50})")->status, 200);
    for (int i = 1; i <= 6; ++i) {
        ASSERT_EQ(
            post("/api/motion/drag",
                 nlohmann::json{{"rotate", {0, 8 * i, 0}}, {"translate", {0, 0, 0.5 * i}}}.dump())
                ->status,
            200);
        r = post("/api/motion/step");
        ASSERT_EQ(r->status, 200) << r->body;
        r = get("/api/motion/frame?after=" + std::to_string(i - 1) + "&wait=1000");
        ASSERT_EQ(r->status, 200);
        EXPECT_EQ(frame_index(r->body), uint32_t(i));
        seen.push_back(r->body);
    }
    // The roots moved with the head (the first point of the first strand is a root).
    EXPECT_GT((frame_positions(seen.back())[0] - rest[0]).norm(), 0.5f);

    // A preset played in real time; the client polls and skips what it is too slow for.
    ASSERT_EQ(post("/api/motion/preset", R"({"name": "shake"})")->status, 200);
    ASSERT_EQ(post("/api/motion/play")->status, 200);
    expect_bad("/api/motion/step", "{}", "playing");
    uint32_t last = frame_index(seen.back());
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
    while (std::chrono::steady_clock::now() < end) {
        r = get("/api/motion/frame?after=" + std::to_string(last) + "&wait=200");
        ASSERT_TRUE(r);
        if (r->status != 200) continue;
        last = frame_index(r->body);
        seen.push_back(r->body);
    }
    ASSERT_EQ(post("/api/motion/pause")->status, 200);
    EXPECT_GT(seen.size(), 9u);
    EXPECT_NE(frame_positions(seen.back()), frame_positions(seen[seen.size() - 2]));

    // The tree: active nodes with their parents, levels and per-level counts.
    r = get("/api/motion/tree");
    ASSERT_EQ(r->status, 200);
    ASSERT_EQ(r->body.substr(0, 8), "WISPTREE");
    uint32_t tree[5];
    std::memcpy(tree, r->body.data() + 8, sizeof tree);
    const uint32_t nodes = tree[2], levels = tree[3], events = tree[4];
    EXPECT_GT(nodes, 0u);
    EXPECT_EQ(levels, started["levels"].get<uint32_t>());
    EXPECT_EQ(r->body.size(), 28 + 32 * size_t(nodes) + 4 * levels + 16 * size_t(events));
    uint32_t counted = 0;
    for (uint32_t l = 0; l < levels; ++l) {
        uint32_t c;
        std::memcpy(&c, r->body.data() + 28 + 32 * size_t(nodes) + 4 * l, 4);
        counted += c;
    }
    EXPECT_EQ(counted, nodes);

    // Export: the style, the recording and the frames of the whole hair.
    r = post("/api/motion/export", R"({"name": "take.hair"})");
    ASSERT_EQ(r->status, 200) << r->body;
    const auto exported = nlohmann::json::parse(r->body);
    const int frames = exported["frames"];
    EXPECT_GE(frames, int(last) + 1);
    EXPECT_NE(exported["command"].get<std::string>().find("--frames " + std::to_string(frames)),
              std::string::npos);
    EXPECT_FALSE(exported.contains("warning"));  // the wind was set before frame 1
    ASSERT_TRUE(std::filesystem::exists(dir_ / "take.style.toml"));
    ASSERT_TRUE(std::filesystem::exists(dir_ / "take.motion.json"));

    // What `wisp animate take.style.toml --motion take.motion.json --fps 25 --frames N` does.
    const Style style = load_style(dir_ / "take.style.toml");
    const Head head = load_head(style.head);
    const HeadFrame frame = head_frame(*head.scalp);
    const HairstyleResult generated = generate_hairstyle(style, head);
    const Motion motion = read_motion(dir_ / "take.motion.json", frame);
    AnimateSettings settings;
    settings.frames = frames;
    settings.fps = 25;
    settings.wisp_held = generated.solve.held_length;
    const std::vector<uint32_t> order = strand_order(generated.hair.strand_count());
    size_t compared = 0;
    animate(generated.hair, *head.mesh, frame, motion, style.dynamics, style.prototype.kind,
            settings, [&](int f, const Hair& moved, const FramePose&) {
                char name[32];
                std::snprintf(name, sizeof name, "take_%04d.hair", f);
                const Hair file = read_hair(dir_ / name);
                ASSERT_EQ(file.points.size(), moved.points.size());
                ASSERT_EQ(std::memcmp(file.points.data(), moved.points.data(),
                                      moved.points.size() * sizeof(Vec3f)),
                          0)
                    << name;
                for (const std::string& bytes : seen) {
                    if (frame_index(bytes) != uint32_t(f)) continue;
                    const std::vector<Vec3f> got = frame_positions(bytes);
                    size_t at = 0;
                    for (size_t i = 0; i < 150; ++i)
                        for (const Vec3f& p : moved.strand(order[i]))
                            ASSERT_EQ(std::memcmp(&got[at++], &p, 12), 0)
                                << "frame " << f << " strand " << order[i];
                    ++compared;
                }
            });
    EXPECT_EQ(compared, seen.size());

    // Reset: back to the rest pose at frame 0.
    r = post("/api/motion/reset");
    ASSERT_EQ(r->status, 200);
    r = get("/api/motion/frame");
    EXPECT_EQ(frame_index(r->body), 0u);
    EXPECT_EQ(frame_positions(r->body), rest);
    EXPECT_EQ(post("/api/motion/stop")->status, 200);
    expect_bad("/api/motion/play", "{}", "session");
}

// A client reading the stream slowly gets the newest frame each time it is ready: the frame
// numbers increase with gaps, and the simulation runs on at its own rate.
TEST_F(MotionRoutesTest, AStreamSkipsFramesForASlowReaderAndNeverSlowsTheSimulation) {
    // All 400 strands: 48 KB a frame, so TCP holds a frame or two in flight, not dozens.
    ASSERT_EQ(post("/api/motion/start", R"({"fps": 50})")->status, 200);
    ASSERT_EQ(post("/api/motion/preset", R"({"name": "shake"})")->status, 200);
    ASSERT_EQ(post("/api/motion/play")->status, 200);
    httplib::Client slow("127.0.0.1", server_->port());
    slow.set_read_timeout(60, 0);
    slow.set_socket_options([](socket_t sock) {
        const int size = 16384;
        setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    });
    std::vector<uint32_t> frames;
    read_stream(slow, headers_, "/api/motion/stream", [&](const std::string& message) {
        const std::array<uint32_t, 5> h = message_header(message);
        EXPECT_EQ(h[3], 0u);  // no tree asked for
        EXPECT_EQ(frame_index(message.substr(124, h[2])), h[1]);
        frames.push_back(h[1]);
        std::this_thread::sleep_for(std::chrono::milliseconds(120));
        return frames.size() < 12;
    });
    const uint32_t published = nlohmann::json::parse(get("/api/motion")->body)["frame"];
    ASSERT_EQ(frames.size(), 12u);
    size_t gaps = 0;
    for (size_t i = 1; i < frames.size(); ++i) {
        EXPECT_GT(frames[i], frames[i - 1]);
        gaps += frames[i] > frames[i - 1] + 1;
    }
    EXPECT_GE(gaps, 5u) << "frames " << ::testing::PrintToString(frames);
    // The simulation did not wait for the reader: it published several frames per frame read.
    EXPECT_GT(published, 3 * frames.size()) << "frames " << ::testing::PrintToString(frames);
    ASSERT_EQ(post("/api/motion/pause")->status, 200);

    auto r = get("/api/motion/stream?tree=2");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);
    r = client_->Get("/api/motion/stream");  // no token
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403);
}

// Each open stream holds one of the server's threads: a third is refused with a 503 while two
// are open, and a stream the client closed frees its place.
TEST_F(MotionRoutesTest, AtMostTwoStreamsAreOpenAndAClosedOneFreesItsPlace) {
    ASSERT_EQ(post("/api/motion/start", R"({"strands": 100})")->status, 200);
    ASSERT_EQ(post("/api/motion/play")->status, 200);
    std::atomic<bool> stop_first{false};
    std::atomic<int> open{0};
    const auto reader = [&](bool first) {
        return std::thread([&, first] {
            httplib::Client c("127.0.0.1", server_->port());
            c.set_read_timeout(60, 0);
            bool counted = false;
            read_stream(c, headers_, "/api/motion/stream", [&](const std::string&) {
                if (!counted) ++open, counted = true;
                return !(first ? stop_first.load() : open.load() >= 4);
            });
        });
    };
    std::thread a = reader(true), b = reader(false);
    const auto wait_for = [&](auto done) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        bool ok = false;
        while (!(ok = done()) && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return ok;
    };
    ASSERT_TRUE(wait_for([&] { return open.load() == 2; }));
    auto r = get("/api/motion/stream");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 503);
    EXPECT_NE(r->body.find("too many motion streams"), std::string::npos) << r->body;
    stop_first = true;
    a.join();
    // The server notices the closed connection at its next write and frees the place.
    int status = 0;
    EXPECT_TRUE(wait_for([&] {
        httplib::Client c("127.0.0.1", server_->port());
        c.set_read_timeout(60, 0);
        bool got = false;
        const auto res = read_stream(c, headers_, "/api/motion/stream", [&](const std::string&) {
            got = true;
            return false;
        });
        status = res ? res->status : 0;
        if (got) ++open;
        return got;
    })) << "last status "
        << status;
    open = 4;  // lets the second reader go
    b.join();
    ASSERT_EQ(post("/api/motion/pause")->status, 200);
}

// Ctrl-C (the server stopping) with a stream open: the stream ends and stop() returns at
// once, not when the client goes.
TEST_F(MotionRoutesTest, StoppingTheServerEndsAnOpenStreamPromptly) {
    ASSERT_EQ(post("/api/motion/start", R"({"strands": 100})")->status, 200);
    ASSERT_EQ(post("/api/motion/play")->status, 200);
    std::atomic<int> messages{0};
    std::thread reader([&] {
        httplib::Client c("127.0.0.1", server_->port());
        c.set_read_timeout(60, 0);
        read_stream(c, headers_, "/api/motion/stream?tree=1", [&](const std::string& message) {
            const std::array<uint32_t, 5> h = message_header(message);
            EXPECT_EQ(message.substr(124 + h[2], 8), "WISPTREE");
            ++messages;
            return true;
        });
    });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (messages < 3 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_GE(messages.load(), 3);
    const auto start = std::chrono::steady_clock::now();
    server_->stop();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    reader.join();
    // A stream waits at most 0.1 s for a frame between httplib's checks; 5 s is a wide margin
    // for a loaded machine, and far under the 30 s write timeout a stuck stream would take.
    EXPECT_LT(seconds, 5.0);
}

}  // namespace
}  // namespace wisp
