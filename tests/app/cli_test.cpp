// The command line as users run it: exit codes, atomic outputs, determinism across threads.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

struct Dir {
    fs::path path;
    Dir() {
        path = fs::temp_directory_path() /
               ("wisp_cli_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
        fs::create_directories(path);
    }
    ~Dir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    static int& counter() {
        static int c = 0;
        return c;
    }
};

int run(const std::string& args) {
    const std::string cmd = std::string(WISP_EXE) + " " + args + " >/dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

}  // namespace

TEST(Cli, SameSeedGivesByteIdenticalFilesAtOneAndTwoThreads) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 150\nstrands = 3000\npoints_per_strand = 16\n");
    for (const char* ext : {".usda", ".hair"}) {
        const fs::path a = d.path / (std::string("a") + ext), b = d.path / (std::string("b") + ext);
        ASSERT_EQ(run("generate " + style.string() + " --seed 9 --threads 1 -q -o " + a.string()),
                  0);
        ASSERT_EQ(run("generate " + style.string() + " --seed 9 --threads 2 -q -o " + b.string()),
                  0);
        EXPECT_EQ(slurp(a), slurp(b)) << ext;
        EXPECT_GT(fs::file_size(a), 1000u);
    }
}

TEST(Cli, ExitCodes) {
    Dir d;
    EXPECT_EQ(run("generate --preset nope -o " + (d.path / "x.hair").string()), 1);
    EXPECT_EQ(run("frobnicate"), 2);
    EXPECT_EQ(run("generate --preset default --seed banana -o " + (d.path / "x.hair").string()), 2);
    const fs::path bad = d.path / "bad.toml";
    write(bad, "[wisp]\nfuzziness = nan\n");
    EXPECT_EQ(run("generate " + bad.string() + " -o " + (d.path / "x.hair").string()), 1);
    const fs::path trunc = d.path / "t.hair";
    write(trunc, "HAIR\x05");
    EXPECT_EQ(run("info " + trunc.string()), 1);
    EXPECT_EQ(run("convert " + trunc.string() + " " + (d.path / "y.usda").string()), 1);
    EXPECT_FALSE(fs::exists(d.path / "y.usda"));
    EXPECT_FALSE(fs::exists(d.path / "x.hair"));
}

TEST(Cli, FailedRunLeavesTheExistingOutputIntact) {
    Dir d;
    const fs::path out = d.path / "keep.hair";
    write(out, "precious");
    const fs::path bad = d.path / "bad.toml";
    write(bad, "[roots]\nwisps = -3\n");
    EXPECT_EQ(run("generate " + bad.string() + " -o " + out.string()), 1);
    EXPECT_EQ(slurp(out), "precious");
}

TEST(Cli, HeadAndRoundTrip) {
    Dir d;
    const fs::path head = d.path / "head.obj";
    ASSERT_EQ(run("head -o " + head.string()), 0);
    EXPECT_NE(slurp(head).find("g scalp"), std::string::npos);
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 50\nstrands = 500\npoints_per_strand = 8\n[head]\nobj = \"" +
                     head.string() + "\"\n");
    const fs::path hair = d.path / "h.hair", usda = d.path / "h.usda", back = d.path / "b.hair";
    ASSERT_EQ(run("generate " + style.string() + " -q -o " + hair.string()), 0);
    ASSERT_EQ(run("convert " + hair.string() + " " + usda.string()), 0);
    ASSERT_EQ(run("convert " + usda.string() + " " + back.string()), 0);
    EXPECT_EQ(run("info " + back.string()), 0);
}
