// The editor's Motion export with pictures (issue 17): the PNG frames the server renders are
// the ones `wisp animate --png` writes for the same session, byte for byte, the MP4 is made
// beside them, and an MP4 without ffmpeg on PATH is refused up front, naming the field.
// Eigen before httplib.h: the <resolv.h> it includes defines _res, a name Eigen uses.
#include "edit/server.hpp"

#include <httplib.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "groom/style_toml.hpp"
#include "io/frame_files.hpp"

namespace wisp {
namespace {

std::string bytes_of(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
    for (size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size())
        text.replace(at, from.size(), to);
    return text;
}

TEST(MotionExport, PngFramesAreTheOnesWispAnimateWrites) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("wisp_motion_export_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    Style style = load_preset("long-straight");
    style.wisps = 40;
    style.strands = 400;
    style.points_per_strand = 10;
    EditServer server(style, dir);
    server.start();
    httplib::Client client("127.0.0.1", server.port());
    client.set_read_timeout(300, 0);
    const httplib::Headers headers{{"X-Wisp-Token", server.token()}};
    const auto post = [&](const std::string& path, const std::string& body) {
        return client.Post(path, headers, body, "application/json");
    };
    ASSERT_EQ(post("/api/motion/start", R"({"strands": 100})")->status, 200);
    for (int i = 1; i <= 4; ++i) {
        ASSERT_EQ(
            post("/api/motion/drag", nlohmann::json{{"rotate", {0, 10 * i, 0}}}.dump())->status,
            200);
        ASSERT_EQ(post("/api/motion/step", "{}")->status, 200);
    }

    auto r = post("/api/motion/export", R"({"name": "take.hair", "png": true, "mp4": true})");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const auto exported = nlohmann::json::parse(r->body);
    const int frames = exported["frames"];
    EXPECT_EQ(frames, 5);
    const std::string command = exported["command"];
    EXPECT_NE(command.find("--png 'take_####.png'"), std::string::npos) << command;
    EXPECT_NE(command.find("--mp4 'take.mp4'"), std::string::npos) << command;
    EXPECT_GT(std::filesystem::file_size(dir / "take.mp4"), 0u);
    r = client.Get("/api/motion/export", headers);
    ASSERT_TRUE(r);
    EXPECT_EQ(nlohmann::json::parse(r->body)["exporting"], false);

    // The command the export gives, run with its own output names.
    std::string cli = command.substr(std::string("wisp ").size());
    cli = replaced(cli, "'take.hair'", "'cli.hair'");
    cli = replaced(cli, "'take_####.png'", "'cli_####.png'");
    cli = replaced(cli, "'take.mp4'", "'cli.mp4'");
    ASSERT_EQ(std::system(("cd '" + dir.string() + "' && " + WISP_EXE + " " + cli + " -q").c_str()),
              0)
        << cli;
    for (int f = 0; f < frames; ++f) {
        const std::string png = bytes_of(dir / numbered("take_####.png", f));
        ASSERT_FALSE(png.empty()) << f;
        EXPECT_TRUE(png == bytes_of(dir / numbered("cli_####.png", f)))
            << numbered("take_####.png", f) << " differs from wisp animate's";
    }
    EXPECT_GT(std::filesystem::file_size(dir / "cli.mp4"), 0u);

    // No ffmpeg: refused before any work, naming the field.
    const std::string path = std::getenv("PATH");
    setenv("PATH", "/nonexistent", 1);
    r = post("/api/motion/export", R"({"name": "again.hair", "mp4": true})");
    setenv("PATH", path.c_str(), 1);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);
    const auto refused = nlohmann::json::parse(r->body);
    EXPECT_EQ(refused["field"], "mp4");
    EXPECT_NE(refused["error"].get<std::string>().find("ffmpeg"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "again.motion.json"));
    r = post("/api/motion/export", R"({"name": "again.hair", "png": "yes"})");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);

    server.stop();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace wisp
