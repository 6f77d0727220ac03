#include "edit/server.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "groom/style_toml.hpp"

namespace wisp {
namespace {

// One HTTP exchange on loopback with exactly these request bytes; returns the whole
// response ("" if the server closed without one).
std::string http_exchange(int port, const std::string& request) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    EXPECT_GE(fd, 0);
    timeval timeout{10, 0};
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

class EditServerTest : public ::testing::Test {
  protected:
    void SetUp() override {
        Style style = load_preset("default");
        style.wisps = 60;
        style.strands = 600;
        style.points_per_strand = 8;
        server_ = std::make_unique<EditServer>(style, "");
        server_->start();
        port_ = server_->port();
        host_ = "127.0.0.1:" + std::to_string(port_);
    }

    std::string get(const std::string& path, const std::string& extra = "") {
        return http_exchange(port_, "GET " + path + " HTTP/1.1\r\nHost: " + host_ +
                                        "\r\nX-Wisp-Token: " + server_->token() + "\r\n" + extra +
                                        "Connection: close\r\n\r\n");
    }
    std::string post(const std::string& path, const std::string& body,
                     const std::string& extra = "") {
        return http_exchange(port_, "POST " + path + " HTTP/1.1\r\nHost: " + host_ +
                                        "\r\nX-Wisp-Token: " + server_->token() + "\r\n" + extra +
                                        "Content-Type: application/json\r\nContent-Length: " +
                                        std::to_string(body.size()) +
                                        "\r\nConnection: close\r\n\r\n" + body);
    }
    nlohmann::json values() { return nlohmann::json::parse(body_of(get("/api/style")))["values"]; }

    std::unique_ptr<EditServer> server_;
    int port_ = 0;
    std::string host_;
};

TEST_F(EditServerTest, ListensOnLoopbackWithATokenInItsUrl) {
    EXPECT_GT(port_, 0);
    EXPECT_EQ(server_->token().size(), 32u);
    EXPECT_EQ(server_->url(),
              "http://127.0.0.1:" + std::to_string(port_) + "/?token=" + server_->token());
    const std::string r = get("/api/schema");
    ASSERT_EQ(status_of(r), 200) << r;
    const auto schema = nlohmann::json::parse(body_of(r));
    EXPECT_GT(schema["fields"].size(), 80u);
    EXPECT_EQ(schema["fields"][0]["path"], "name");
    // The page itself needs no token (it holds no data); the API does.
    EXPECT_EQ(status_of(http_exchange(
                  port_, "GET / HTTP/1.1\r\nHost: " + host_ + "\r\nConnection: close\r\n\r\n")),
              200);
}

TEST_F(EditServerTest, RefusesForeignHostsOriginsAndMissingTokens) {
    const std::string token = server_->token();
    const auto raw = [&](const std::string& headers) {
        return status_of(http_exchange(
            port_, "GET /api/style HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n"));
    };
    EXPECT_EQ(raw("Host: " + host_ + "\r\nX-Wisp-Token: " + token + "\r\n"), 200);
    EXPECT_EQ(
        raw("Host: localhost:" + std::to_string(port_) + "\r\nX-Wisp-Token: " + token + "\r\n"),
        200);
    // DNS rebinding: another site's name resolved to 127.0.0.1.
    EXPECT_EQ(
        raw("Host: evil.example:" + std::to_string(port_) + "\r\nX-Wisp-Token: " + token + "\r\n"),
        403);
    EXPECT_EQ(raw("X-Wisp-Token: " + token + "\r\n"), 403);  // no Host at all
    EXPECT_EQ(raw("Host: " + host_ + "\r\nOrigin: http://evil.example\r\nX-Wisp-Token: " + token +
                  "\r\n"),
              403);
    EXPECT_EQ(raw("Host: " + host_ + "\r\nOrigin: http://" + host_ + "\r\nX-Wisp-Token: " + token +
                  "\r\n"),
              200);
    EXPECT_EQ(raw("Host: " + host_ + "\r\n"), 403);  // no token
    EXPECT_EQ(raw("Host: " + host_ + "\r\nX-Wisp-Token: " + std::string(32, '0') + "\r\n"), 403);
    EXPECT_EQ(status_of(http_exchange(port_, "GET /api/style?token=" + token +
                                                 " HTTP/1.1\r\nHost: " + host_ +
                                                 "\r\nConnection: close\r\n\r\n")),
              200);
}

TEST_F(EditServerTest, BadValuesAre400sNamingTheFieldAndReason) {
    std::string r = post("/api/set", R"({"path": "wisp.fuzziness", "value": -1})");
    ASSERT_EQ(status_of(r), 400) << r;
    auto j = nlohmann::json::parse(body_of(r));
    EXPECT_EQ(j["field"], "wisp.fuzziness");
    EXPECT_EQ(j["error"], "value: field 'wisp.fuzziness': must be ≥ 0, got -1");
    ASSERT_EQ(status_of(get("/api/hair?strands=0")), 200);  // every stage up to date
    r = post("/api/set", R"({"path": "solve.stiffness", "value": 0.5})");
    ASSERT_EQ(status_of(r), 200) << r;
    j = nlohmann::json::parse(body_of(r));
    EXPECT_EQ(j["stale"], "solve");
    EXPECT_EQ(j["value"], 0.5);
    EXPECT_EQ(values()["solve.stiffness"], 0.5);
    // Maps and choices as JSON.
    EXPECT_EQ(status_of(post("/api/set", R"({"path": "maps.length",
        "value": {"procedural": "crown", "low": 5, "high": 30}})")),
              200);
    EXPECT_EQ(values()["maps.length"]["procedural"], "crown");
}

TEST_F(EditServerTest, SendsShuffledStrandsAsLittleEndianArrays) {
    const std::string r = get("/api/hair?strands=100");
    ASSERT_EQ(status_of(r), 200);
    const std::string b = body_of(r);
    ASSERT_GE(b.size(), 24u);
    EXPECT_EQ(b.substr(0, 8), "WISPHAIR");
    uint32_t header[4];
    std::memcpy(header, b.data() + 8, sizeof header);
    EXPECT_EQ(header[0], 1u);
    EXPECT_EQ(header[1], 100u);
    EXPECT_EQ(header[3], 600u);
    const uint32_t strands = header[1], points = header[2];
    EXPECT_EQ(b.size(), 24 + 4 * (strands + 1) + 12 * points + 12 * strands);
    uint32_t last;
    std::memcpy(&last, b.data() + 24 + 4 * strands, 4);
    EXPECT_EQ(last, points);
    const std::string head = body_of(get("/api/head"));
    EXPECT_EQ(head.substr(0, 8), "WISPHEAD");
    uint32_t head_header[3];  // version, #V, #F
    ASSERT_GE(head.size(), 20u);
    std::memcpy(head_header, head.data() + 8, sizeof head_header);
    EXPECT_EQ(head_header[0], 2u);
    const size_t nv = head_header[1], nf = head_header[2];
    ASSERT_EQ(head.size(), 20 + 24 * nv + 13 * nf);
    for (size_t v = 0; v < nv; v += 97) {  // the skin normals, after the positions: unit
        float n[3];
        std::memcpy(n, head.data() + 20 + 12 * nv + 12 * v, sizeof n);
        EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.f, 1e-4f) << v;
    }
    const std::string masters = body_of(get("/api/masters"));
    EXPECT_EQ(masters.substr(0, 8), "WISPHAIR");
    std::memcpy(header, masters.data() + 8, sizeof header);
    EXPECT_EQ(header[1], 60u);
}

// A bounded sweep of hostile requests: each gets a 4xx, the server keeps answering and the
// style is what it was.
TEST_F(EditServerTest, SurvivesAHostileSweepWithItsStateIntact) {
    const nlohmann::json before = values();
    const std::string big(2 << 20, 'x');
    const std::vector<std::pair<std::string, std::string>> bodies = {
        {"/api/set", ""},
        {"/api/set", "not json"},
        {"/api/set", "[1, 2]"},
        {"/api/set", R"({"value": 1})"},
        {"/api/set", R"({"path": 7, "value": 1})"},
        {"/api/set", R"({"path": "roots.wisps"})"},
        {"/api/set", R"({"path": "roots.wisps", "value": null})"},
        {"/api/set", R"({"path": "roots.wisps", "value": 1e300})"},
        {"/api/set", R"({"path": "roots.wisps", "value": 2.5})"},
        {"/api/set", R"({"path": "roots.strands", "value": 99999999999})"},
        {"/api/set", R"({"path": "roots.wisps\u0000\u001b[2J", "value": 1})"},
        {"/api/set", R"({"path": "group", "value": {}})"},
        {"/api/set", R"({"path": "maps.length", "value": [[[[[[[[[[[1]]]]]]]]]]]})"},
        {"/api/set", R"({"path": "maps.length", "value": {"image": ""}})"},
        {"/api/set", R"({"path": "prototype.points", "value": "\n[x]\ny = 1"})"},
        {"/api/set", R"({"path": "solve.cell", "value": "1\nroots.wisps = 5"})"},
        {"/api/preset", R"({"name": "../../etc/passwd"})"},
        {"/api/preset", R"({"name": 3})"},
        {"/api/set", big},
    };
    for (const auto& [path, body] : bodies) {
        const int status = status_of(post(path, body));
        EXPECT_GE(status, 400) << path << " " << body.substr(0, 80);
        EXPECT_LT(status, 500) << path << " " << body.substr(0, 80);
    }
    for (const char* path :
         {"/api/hair?strands=-1", "/api/hair?strands=x", "/api/hair?strands=99999999999999999999",
          "/api/nothing", "/../../etc/passwd", "/%2e%2e/etc/passwd"}) {
        const int status = status_of(get(path));
        EXPECT_GE(status, 400) << path;
        EXPECT_LT(status, 500) << path;
    }
    EXPECT_EQ(http_exchange(port_, "garbage\r\n\r\n").substr(0, 12).find("200"), std::string::npos);
    EXPECT_EQ(values(), before);
    EXPECT_EQ(status_of(get("/api/hair?strands=10")), 200);
}

// The braid and updo tools' wire: the schema's section numbers (the sliders' ranges and
// defaults), a placed braid's and updo's expanded paths in the constraints' reply, and a bad
// value of either a 400 naming the field, the sections unchanged.
TEST_F(EditServerTest, BraidAndUpdoSendTheirPathsAndBadValuesNameTheField) {
    const auto schema = nlohmann::json::parse(body_of(get("/api/schema")));
    const auto number = [&](const std::string& section, const std::string& key) {
        for (const auto& f : schema["sections"])
            if (f["section"] == section && f["key"] == key) return f;
        return nlohmann::json();
    };
    EXPECT_EQ(number("braid", "width")["default"], 0.35f);
    EXPECT_EQ(number("braid", "width")["unit"], "head units");
    EXPECT_EQ(number("braid", "strands")["max"], 16);
    EXPECT_EQ(number("updo", "turns")["soft_max"], 6);

    const std::string placed = R"({"sections": [
        {"section": "braid", "strands": 3, "start": [0, -0.35, -1.15], "width": 0.4},
        {"section": "updo", "point": [0, 0.55, -1.05], "bun_radius": 0.25}]})";
    std::string r = post("/api/constraints", placed);
    ASSERT_EQ(status_of(r), 200) << r;
    auto j = nlohmann::json::parse(body_of(r));
    ASSERT_EQ(j["paths"].size(), 2u);
    EXPECT_EQ(j["paths"][0].size(), 3u);  // one per strand
    EXPECT_EQ(j["paths"][1].size(), 1u);  // the spiral
    EXPECT_GT(j["paths"][0][0]["points"].size(), 16u);
    EXPECT_EQ(nlohmann::json::parse(body_of(get("/api/constraints")))["paths"], j["paths"]);

    const std::vector<std::pair<std::string, std::string>> bad = {
        {R"({"section": "braid", "strands": 2})", "braid[0].strands"},
        {R"({"section": "braid", "width": 0})", "braid[0].width"},
        {R"({"section": "braid", "period": -1})", "braid[0].period"},
        {R"({"section": "braid", "weight": 1.5})", "braid[0].weight"},
        {R"({"section": "braid", "axis": [1, 0, 0], "side": [1, 0, 0]})", "braid[0].side"},
        {R"({"section": "braid", "start": [0, 1]})", "braid[0].start"},
        {R"({"section": "updo", "turns": 60})", "updo[0].turns"},
        {R"({"section": "updo", "bun_radius": -0.1})", "updo[0].bun_radius"},
        {R"({"section": "updo", "facing": [0, 0, 0]})", "updo[0].facing"},
    };
    for (const auto& [section, field] : bad) {
        r = post("/api/constraints", R"({"sections": [)" + section + "]}");
        ASSERT_EQ(status_of(r), 400) << section << ": " << r;
        EXPECT_EQ(nlohmann::json::parse(body_of(r))["field"], field) << section;
    }
    EXPECT_EQ(nlohmann::json::parse(body_of(get("/api/constraints")))["sections"],
              nlohmann::json::parse(placed)["sections"]);
}

// GET /api/events streams the progress of a long run as server-sent events: a picture
// rendered while the stream is open shows as its stages and its own step, then finished;
// without the token the stream is refused; stopping the server ends the stream.
TEST_F(EditServerTest, ProgressArrivesAsServerSentEvents) {
    EXPECT_EQ(status_of(http_exchange(port_, "GET /api/events HTTP/1.1\r\nHost: " + host_ +
                                                 "\r\nConnection: close\r\n\r\n")),
              403);
    ASSERT_EQ(status_of(post("/api/set", R"({"path": "solve.stiffness", "value": 0.4})")), 200);
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_GE(fd, 0);
    timeval timeout{30, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port_));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    const std::string request =
        "GET /api/events?token=" + server_->token() + " HTTP/1.1\r\nHost: " + host_ + "\r\n\r\n";
    ASSERT_EQ(send(fd, request.data(), request.size(), MSG_NOSIGNAL), ssize_t(request.size()));
    std::string stream;
    const auto read_until = [&](const std::string& what, size_t from = 0) {
        char buffer[4096];
        while (stream.find(what, from) == std::string::npos) {
            const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
            if (n <= 0) return false;
            stream.append(buffer, static_cast<size_t>(n));
        }
        return true;
    };
    ASSERT_TRUE(read_until(": connected")) << stream;
    EXPECT_NE(stream.find("text/event-stream"), std::string::npos) << stream;
    const std::string picture = post(
        "/api/render", R"({"eye": [0, 10, 80], "target": [0, 5, 0], "width": 16, "height": 16})");
    ASSERT_EQ(status_of(picture), 200) << picture.substr(0, 300);
    ASSERT_TRUE(read_until(R"("finished":true)")) << stream;
    for (const char* step : {R"("step":"solve")", R"("step":"color")", R"("step":"render")"})
        EXPECT_NE(stream.find(step), std::string::npos) << step << " in " << stream;
    EXPECT_NE(stream.find("event: progress\ndata: {"), std::string::npos) << stream;
    EXPECT_NE(stream.find(R"("task":"render")"), std::string::npos) << stream;
    // A preview after κ moved reports too, with the solve's fraction done up to 1.
    const size_t seen = stream.size();
    ASSERT_EQ(status_of(post("/api/set", R"({"path": "solve.stiffness", "value": 0.5})")), 200);
    ASSERT_EQ(status_of(get("/api/hair?strands=10")), 200);
    ASSERT_TRUE(read_until(R"("finished":true)", seen)) << stream;
    const std::string preview = stream.substr(seen);
    EXPECT_NE(preview.find(R"("task":"preview")"), std::string::npos) << preview;
    EXPECT_NE(preview.find(R"("fraction":1.0,"step":"solve")"), std::string::npos) << preview;
    EXPECT_NE(preview.find(R"("step":"members")"), std::string::npos) << preview;
    server_->stop();  // ends the stream rather than waiting on it
    char rest[4096];
    while (recv(fd, rest, sizeof rest, 0) > 0) {
    }
    close(fd);
}

TEST(EditServer, StopsAndFreesItsPort) {
    Style style = load_preset("short");
    style.wisps = 10;
    style.strands = 100;
    int port = 0;
    {
        EditServer server(style, "");
        server.start();
        port = server.port();
        server.stop();
        server.stop();  // twice is fine
    }
    EXPECT_EQ(http_exchange(port, "GET / HTTP/1.1\r\nHost: x\r\n\r\n"), "");
    EditOptions options;
    options.port = port;  // free again
    EditServer again(style, "", options);
    EXPECT_NO_THROW(again.start());
    EXPECT_EQ(again.port(), port);
}

}  // namespace
}  // namespace wisp
