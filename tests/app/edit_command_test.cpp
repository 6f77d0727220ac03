// `wisp schema` and `wisp edit` on the command line (the server itself: tests/edit).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace wisp {
namespace {

// Runs a shell command; returns its exit code and stdout.
std::pair<int, std::string> run(const std::string& command) {
    FILE* pipe = popen(command.c_str(), "r");
    std::string out;
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        out.append(buffer, n);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(EditCommand, SchemaPrintsEveryFieldAsJson) {
    const auto [code, out] = run(std::string(WISP_EXE) + " schema");
    ASSERT_EQ(code, 0);
    const auto j = nlohmann::json::parse(out);
    bool stiffness = false;
    for (const auto& f : j["fields"]) {
        if (f["path"] != "solve.stiffness") continue;
        stiffness = true;
        EXPECT_EQ(f["type"], "number");
        EXPECT_EQ(f["stage"], "solve");
        EXPECT_EQ(f["default"], 1.0);
        EXPECT_EQ(f["max"], 1000.0);
    }
    EXPECT_TRUE(stiffness);
}

TEST(EditCommand, BadInputExitsWithOne) {
    EXPECT_EQ(run(std::string(WISP_EXE) + " edit --preset nosuch 2>/dev/null").first, 1);
    EXPECT_EQ(run(std::string(WISP_EXE) + " edit --port 70000 2>/dev/null").first, 2);
}

}  // namespace
}  // namespace wisp
