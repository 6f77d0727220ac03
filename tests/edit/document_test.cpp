// The editor's painting and document endpoints (issue 16 items 3 and 6) on loopback: a painted
// map changes the roots where it was painted; Save writes a TOML and its map PNGs that a fresh
// generate turns into the editor's hair byte for byte; Open and autosave read back; and
// hostile requests (bad images, oversize, traversal, wrong types) get a 400 naming the field,
// write nothing outside the folder and leave the style as it was.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.hpp"
#include "edit/server.hpp"
#include "edit/wire.hpp"
#include "groom/head.hpp"
#include "groom/style_toml.hpp"
#include "io/hair_io.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

std::string http_exchange(int port, const std::string& request) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    EXPECT_GE(fd, 0);
    timeval timeout{60, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        close(fd);
        return "";
    }
    for (size_t sent = 0; sent < request.size();) {
        const ssize_t n = send(fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;
        sent += static_cast<size_t>(n);
    }
    std::string response;
    char buffer[65536];
    for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;)
        response.append(buffer, static_cast<size_t>(n));
    close(fd);
    return response;
}

int status_of(const std::string& response) {
    return response.size() > 12 ? std::atoi(response.c_str() + 9) : 0;
}

std::string body_of(const std::string& response) {
    const size_t p = response.find("\r\n\r\n");
    return p == std::string::npos ? "" : response.substr(p + 4);
}

std::string file_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A map image: 1 on the left half of the image (the character's left, +X: scalp UV u < 0.5),
// 0 on the right.
GrayImage left_half(int side) {
    GrayImage g;
    g.width = g.height = side;
    g.values.resize(size_t(side) * side);
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)
            g.values[size_t(j) * side + i] = i < side / 2 ? 1.f : 0.f;
    return g;
}

class EditDocumentTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("wisp_document_test_" + std::to_string(getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "folder");
        folder_ = dir_ / "folder";
        Style style = load_preset("default");
        style.wisps = 60;
        style.strands = 1500;
        style.points_per_strand = 8;
        EditOptions options;
        options.document = "doc.toml";
        server_ = std::make_unique<EditServer>(style, folder_, options);
        server_->start();
        port_ = server_->port();
        host_ = "127.0.0.1:" + std::to_string(port_);
    }
    void TearDown() override {
        server_.reset();
        fs::remove_all(dir_);
    }

    std::string request(const std::string& method, const std::string& path, const std::string& body,
                        const std::string& type) {
        return http_exchange(port_, method + " " + path + " HTTP/1.1\r\nHost: " + host_ +
                                        "\r\nX-Wisp-Token: " + server_->token() +
                                        "\r\nContent-Type: " + type +
                                        "\r\nContent-Length: " + std::to_string(body.size()) +
                                        "\r\nConnection: close\r\n\r\n" + body);
    }
    std::string get(const std::string& path) { return request("GET", path, "", "text/plain"); }
    std::string post(const std::string& path, const nlohmann::json& j) {
        return request("POST", path, j.dump(), "application/json");
    }
    std::string post_map(const std::string& query, const std::string& png) {
        return request("POST", "/api/map?" + query, png, "image/png");
    }
    nlohmann::json json(const std::string& response) {
        return nlohmann::json::parse(body_of(response), nullptr, false);
    }
    // The files of the test's folder and of its parent.
    std::vector<std::string> listing() {
        std::vector<std::string> names;
        for (const auto& e : fs::recursive_directory_iterator(dir_))
            names.push_back(fs::relative(e.path(), dir_).string());
        std::sort(names.begin(), names.end());
        return names;
    }
    // The full hair of the editor, exported as .hair by the server.
    std::string exported(const std::string& name) {
        const std::string r = post("/api/export", {{"name", name}});
        EXPECT_EQ(status_of(r), 200) << r;
        return file_bytes(folder_ / name);
    }

    fs::path dir_, folder_;
    std::unique_ptr<EditServer> server_;
    int port_ = 0;
    std::string host_;
};

// Roots (first points) on the character's left (x > 0) and right.
std::pair<int, int> roots_by_side(const std::string& wire) {
    uint32_t header[4];
    std::memcpy(header, wire.data() + 8, sizeof header);
    const uint32_t strands = header[1];
    std::vector<uint32_t> offsets(strands + 1);
    std::memcpy(offsets.data(), wire.data() + 24, 4 * offsets.size());
    const char* positions = wire.data() + 24 + 4 * offsets.size();
    int left = 0, right = 0;
    for (uint32_t s = 0; s < strands; ++s) {
        float x;
        std::memcpy(&x, positions + 12 * size_t(offsets[s]), 4);
        (x > 0 ? left : right) += 1;
    }
    return {left, right};
}

TEST_F(EditDocumentTest, APaintedDensityMapGrowsHairWhereItWasPainted) {
    const auto [left0, right0] = roots_by_side(body_of(get("/api/hair")));
    EXPECT_GT(left0, 400);
    EXPECT_GT(right0, 400);
    // The painter's image of the default (constant) density: all 1.
    const std::string map = body_of(get("/api/map?field=maps.density"));
    ASSERT_EQ(map.substr(0, 7), "WISPMAP");
    uint32_t header[4];
    std::memcpy(header, map.data() + 8, sizeof header);
    EXPECT_EQ(header[1], 256u);
    EXPECT_EQ(header[3], 0u);  // constant
    EXPECT_EQ(static_cast<unsigned char>(map[32 + 100]), 255);

    const std::string r =
        post_map("field=maps.density&low=0&high=1", encode_gray_png(left_half(64)));
    ASSERT_EQ(status_of(r), 200) << r;
    EXPECT_EQ(json(r)["value"]["image"], "doc.density.png");
    const auto [left, right] = roots_by_side(body_of(get("/api/hair")));
    // The right half was painted 0: only roots by the parting, where the bilinear lookup
    // still sees the left half, grow there.
    EXPECT_GT(left, 0.9 * (left + right)) << left << " left, " << right << " right";
    // The map reads back as painted (kind 3, held until Save), at its own size.
    const std::string back = body_of(get("/api/map?field=maps.density"));
    std::memcpy(header, back.data() + 8, sizeof header);
    EXPECT_EQ(header[0], 1u);
    EXPECT_EQ(header[1], 64u);
    EXPECT_EQ(header[3], 3u);
    EXPECT_EQ(static_cast<unsigned char>(back[32]), 255);
    EXPECT_EQ(static_cast<unsigned char>(back[32 + 63]), 0);
    // Changing its high keeps the painting (its file does not exist yet).
    const std::string high =
        post("/api/set", {{"path", "maps.density"},
                          {"value", {{"image", "doc.density.png"}, {"low", 0}, {"high", 2}}}});
    EXPECT_EQ(status_of(high), 200) << high;
    EXPECT_EQ(status_of(get("/api/hair?strands=10")), 200);
}

TEST_F(EditDocumentTest, SaveWritesATomlAndMapsThatGenerateTurnsIntoTheSameHair) {
    ASSERT_EQ(status_of(post_map("field=maps.density", encode_gray_png(left_half(32)))), 200);
    GrayImage ramp = left_half(48);
    for (size_t i = 0; i < ramp.values.size(); ++i)
        ramp.values[i] = float(i % 48) / 47.f;
    ASSERT_EQ(status_of(post_map("field=maps.length&low=5&high=30", encode_gray_png(ramp))), 200);
    const std::string r = post("/api/save", {{"name", "mine.toml"}});
    ASSERT_EQ(status_of(r), 200) << r;
    EXPECT_EQ(json(r)["files"],
              nlohmann::json({"mine.density.png", "mine.length.png", "mine.toml"}));
    const std::string toml = file_bytes(folder_ / "mine.toml");
    EXPECT_NE(toml.find("image = \"mine.density.png\""), std::string::npos) << toml;
    EXPECT_NE(toml.find("image = \"mine.length.png\""), std::string::npos) << toml;

    // What the CLI does with the saved file: load_style, generate, write.
    const Style saved = load_style(folder_ / "mine.toml");
    const Head head = load_head(saved.head);
    write_hair(folder_ / "cli.hair", generate_hairstyle(saved, head).hair);
    EXPECT_EQ(file_bytes(folder_ / "cli.hair"), exported("editor.hair"));

    // Open gives the saved style back after another one was loaded.
    ASSERT_EQ(status_of(post("/api/preset", {{"name", "short"}})), 200);
    EXPECT_NE(exported("short.hair"), file_bytes(folder_ / "cli.hair"));
    const std::string o = post("/api/open", {{"name", "mine.toml"}});
    ASSERT_EQ(status_of(o), 200) << o;
    EXPECT_EQ(json(o)["document"], "mine.toml");
    EXPECT_EQ(exported("opened.hair"), file_bytes(folder_ / "cli.hair"));
    // A map opened from a file paints on from its pixels.
    const std::string m = body_of(get("/api/map?field=maps.length"));
    uint32_t header[4];
    std::memcpy(header, m.data() + 8, sizeof header);
    EXPECT_EQ(header[1], 48u);
    EXPECT_EQ(header[3], 1u);  // an image file
}

// A style file's braid and updo (the presets' text, opened): the constraints' reply lists
// them as a [[braid]] and an [[updo]] with the file's values, not as the groups they expand
// into; Save writes them back as such, the saved file generates the editor's hair, and Open
// and Save again give the same bytes.
TEST_F(EditDocumentTest, AnOpenedBraidAndUpdoListAsWrittenAndSaveTheSameBytesAgain) {
    for (const std::string kind : {"braid", "updo"}) {
        SCOPED_TRACE(kind);
        std::string text(preset_text(kind));
        // Fewer wisps and strands: the line `KEY = …` of [roots] set to `KEY = value`.
        const auto set_line = [&](const std::string& key, const std::string& value) {
            const size_t at = text.find("\n" + key + " = ") + 1;
            text.replace(at, text.find('\n', at) - at, key + " = " + value);
        };
        set_line("wisps", "60");
        set_line("strands", "1500");
        { std::ofstream(folder_ / (kind + ".toml")) << text; }
        const std::string o = post("/api/open", {{"name", kind + ".toml"}});
        ASSERT_EQ(status_of(o), 200) << o;
        const nlohmann::json sections = json(get("/api/constraints"))["sections"];
        ASSERT_EQ(sections.size(), 1u) << sections;
        EXPECT_EQ(sections[0]["section"], kind);
        EXPECT_EQ(sections[0]["weight"], 1.0);
        EXPECT_EQ(sections[0].contains("constraint"), false);

        ASSERT_EQ(status_of(post("/api/save", {{"name", "saved.toml"}})), 200);
        const std::string saved = file_bytes(folder_ / "saved.toml");
        EXPECT_NE(saved.find("\n[[" + kind + "]]\n"), std::string::npos) << saved;
        EXPECT_EQ(saved.find("[[group]]"), std::string::npos) << saved;
        EXPECT_NE(saved.find(kind == "braid" ? "\nperiod = 0.55\n" : "\nbun_radius = 0.38\n"),
                  std::string::npos)
            << saved;
        const Style read = load_style(folder_ / "saved.toml");
        write_hair(folder_ / "cli.hair", generate_hairstyle(read, load_head(read.head)).hair);
        EXPECT_EQ(file_bytes(folder_ / "cli.hair"), exported("editor.hair"));

        ASSERT_EQ(status_of(post("/api/open", {{"name", "saved.toml"}})), 200);
        ASSERT_EQ(status_of(post("/api/save", {{"name", "again.toml"}})), 200);
        EXPECT_EQ(file_bytes(folder_ / "again.toml"), saved);
    }
}

TEST_F(EditDocumentTest, AutosaveWritesASidecarThatReadsBackToTheSameHair) {
    ASSERT_EQ(status_of(post_map("field=maps.protrusion", encode_gray_png(left_half(16)))), 200);
    const std::string r = post("/api/autosave", nlohmann::json::object());
    ASSERT_EQ(status_of(r), 200) << r;
    EXPECT_EQ(json(r)["document"], "doc.toml");  // the document keeps its name
    ASSERT_TRUE(fs::exists(folder_ / "doc.autosave.toml"));
    ASSERT_TRUE(fs::exists(folder_ / "doc.autosave.protrusion.png"));
    const Style autosaved = load_style(folder_ / "doc.autosave.toml");
    const Head head = load_head(autosaved.head);
    write_hair(folder_ / "cli.hair", generate_hairstyle(autosaved, head).hair);
    EXPECT_EQ(file_bytes(folder_ / "cli.hair"), exported("editor.hair"));
    // Nothing but the folder's own files were written.
    for (const std::string& name : listing())
        EXPECT_EQ(name.rfind("folder", 0), 0u) << name;
}

// The Export menu is built from GET /api/export: every format it lists, Export writes.
TEST_F(EditDocumentTest, EveryFormatTheExportMenuListsIsWritten) {
    const std::string r = get("/api/export");
    ASSERT_EQ(status_of(r), 200) << r;
    const auto formats = nlohmann::json::parse(body_of(r))["formats"];
    EXPECT_EQ(formats.size(), 6u);
    for (const auto& ext : formats) {
        const std::string name = "menu" + ext.get<std::string>();
        EXPECT_FALSE(exported(name).empty()) << name;
    }
}

// A realistic head is over the 1 MiB every other route allows: the MakeHuman base mesh
// (1.7 MB, decimetres) uploads as a head, while the same bytes sent to another route, or a
// head over its own 64 MiB, are refused before they are read.
TEST_F(EditDocumentTest, AHeadOverTheBodyLimitUploadsButOnlyAsAHead) {
    const fs::path obj = WISP_SHARED_DIR "/data/heads/makehuman/makehuman_hm08_base.obj";
    if (!fs::exists(obj)) GTEST_SKIP() << obj << " not present";
    const std::string bytes = file_bytes(obj);
    ASSERT_GT(bytes.size(), size_t(1) << 20);
    EXPECT_EQ(status_of(request("POST", "/api/map?field=maps.density", bytes, "image/png")), 413);
    const std::string r = request("POST", "/api/head?name=makehuman.obj&scale=10&method=hairline",
                                  bytes, "text/plain");
    ASSERT_EQ(status_of(r), 200) << r.substr(0, 400);
    EXPECT_EQ(file_bytes(folder_ / "makehuman.obj"), bytes);
    EXPECT_EQ(json(r)["values"]["head.obj"], "makehuman.obj");
    EXPECT_EQ(status_of(get("/api/hair?strands=100")), 200);
    // Over the head's limit: refused from the declared length, nothing written.
    const std::string huge =
        http_exchange(port_, "POST /api/head?name=huge.obj HTTP/1.1\r\nHost: " + host_ +
                                 "\r\nX-Wisp-Token: " + server_->token() +
                                 "\r\nContent-Length: " + std::to_string((size_t(64) << 20) + 1) +
                                 "\r\nConnection: close\r\n\r\nv 0 0 0\n");
    EXPECT_EQ(status_of(huge), 413) << huge;
    EXPECT_FALSE(fs::exists(folder_ / "huge.obj"));
    // A body of undeclared length is refused.
    const std::string chunked = http_exchange(
        port_,
        "POST /api/set HTTP/1.1\r\nHost: " + host_ + "\r\nX-Wisp-Token: " + server_->token() +
            "\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n2\r\n{}\r\n0\r\n\r\n");
    EXPECT_EQ(status_of(chunked), 411) << chunked;
}

TEST_F(EditDocumentTest, HostileRequestsGetA400AndChangeNothing) {
    ASSERT_EQ(status_of(get("/api/hair?strands=1")), 200);  // nothing stale from here on
    const std::string style_before = body_of(get("/api/style"));
    const std::vector<std::string> files_before = listing();
    const std::string good = encode_gray_png(left_half(8));
    const auto expect_400 = [&](const std::string& response, const std::string& field) {
        EXPECT_EQ(status_of(response), 400) << response;
        EXPECT_EQ(json(response)["field"], field) << response;
        EXPECT_FALSE(json(response)["error"].get<std::string>().empty());
    };
    // The field: missing, unknown, not a map, not a string.
    expect_400(post_map("", good), "field");
    expect_400(post_map("field=maps.nope", good), "field");
    expect_400(post_map("field=solve.stiffness", good), "field");
    expect_400(get("/api/map?field=roots.strands"), "field");
    expect_400(get("/api/map"), "field");
    // Bad image data: not an image, a truncated PNG, an empty body, JSON.
    expect_400(post_map("field=maps.density", "not a png at all"), "body");
    expect_400(post_map("field=maps.density", good.substr(0, good.size() / 2)), "body");
    expect_400(post_map("field=maps.density", ""), "body");
    expect_400(post_map("field=maps.density", R"({"image": "x.png"})"), "body");
    // Sizes: too small, too large (a small file of a large image), over the body limit.
    GrayImage tiny;
    tiny.width = tiny.height = 1;
    tiny.values = {1.f};
    expect_400(post_map("field=maps.density", encode_gray_png(tiny)), "body");
    GrayImage wide;
    wide.width = 2048;
    wide.height = 2;
    wide.values.assign(4096, 0.5f);
    expect_400(post_map("field=maps.density", encode_gray_png(wide)), "body");
    EXPECT_EQ(status_of(post_map("field=maps.density", std::string(2 << 20, 'x'))), 413);
    // low and high: not numbers, not finite, out of the reader's range.
    expect_400(post_map("field=maps.density&low=abc", good), "maps.density.low");
    expect_400(post_map("field=maps.density&high=nan", good), "maps.density.high");
    expect_400(post_map("field=maps.density&high=1e99", good), "maps.density.high");
    expect_400(post_map("field=maps.density&low=-1&high=1", good), "maps.density");
    expect_400(post_map("field=maps.length&low=0&high=0", good), "maps.length");

    // File names: traversal, absolute, folders, hidden, other extensions, wrong types.
    for (const nlohmann::json& name :
         {nlohmann::json("../escape.toml"), nlohmann::json("/tmp/escape.toml"),
          nlohmann::json("sub/escape.toml"), nlohmann::json(".hidden.toml"),
          nlohmann::json("escape.txt"), nlohmann::json(""),
          nlohmann::json(std::string(200, 'a') + ".toml"), nlohmann::json("a\\b.toml"),
          nlohmann::json(std::string("nul\0.toml", 9)), nlohmann::json("..toml"), nlohmann::json(5),
          nlohmann::json::array(), nlohmann::json(nullptr)}) {
        expect_400(post("/api/save", {{"name", name}}), "name");
        expect_400(post("/api/open", {{"name", name}}), "name");
    }
    expect_400(post("/api/open", nlohmann::json::object()), "name");
    expect_400(post("/api/open", {{"name", "missing.toml"}}), "name");
    for (const char* name : {"../x.hair", "x.exe", "x.toml", "x.hair/"})
        expect_400(post("/api/export", {{"name", name}}), "name");
    EXPECT_EQ(status_of(request("POST", "/api/save", "[1, 2]", "application/json")), 400);
    EXPECT_EQ(status_of(request("POST", "/api/open", "{", "application/json")), 400);
    // A style file of the folder that is not valid TOML, or names a missing map.
    std::ofstream(folder_ / "broken.toml") << "[maps\ndensity = ";
    std::ofstream(folder_ / "nomap.toml") << "[maps]\ndensity = { image = \"gone.png\" }\n";
    expect_400(post("/api/open", {{"name", "broken.toml"}}), "name");
    expect_400(post("/api/open", {{"name", "nomap.toml"}}), "name");
    fs::remove(folder_ / "broken.toml");
    fs::remove(folder_ / "nomap.toml");

    // The server still answers, with the same style, and wrote no file.
    EXPECT_EQ(status_of(get("/api/hair?strands=5")), 200);
    EXPECT_EQ(body_of(get("/api/style")), style_before);
    EXPECT_EQ(listing(), files_before);
}

}  // namespace
}  // namespace wisp
