// The command line as users run it: exit codes, atomic outputs, determinism across threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/hair_io.hpp"
#include "io/usda.hpp"

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

// Runs wisp with stderr captured to `err` (a file, not a terminal); returns the exit code.
int run_capturing(const std::string& args, const fs::path& err) {
    const std::string cmd = std::string(WISP_EXE) + " " + args + " >/dev/null 2>" + err.string();
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
    for (const char* ext : {".usda", ".hair", ".npz", ".data"}) {
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

TEST(Cli, PrecisionWritesFewerDigits) {
    Dir d;
    const fs::path exact = d.path / "e.usda", short3 = d.path / "p.usda", c = d.path / "c.usda";
    const std::string gen = "generate --preset short --strands 300 --wisps 30 -q ";
    ASSERT_EQ(run(gen + "-o " + exact.string()), 0);
    ASSERT_EQ(run(gen + "--precision 3 -o " + short3.string()), 0);
    ASSERT_EQ(run("convert " + exact.string() + " " + c.string() + " --precision 3"), 0);
    EXPECT_LT(fs::file_size(short3), fs::file_size(exact) * 3 / 4);
    const wisp::Hair a = wisp::read_hair(exact), b = wisp::read_hair(short3),
                     bc = wisp::read_hair(c);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_TRUE(b.points == bc.points);
    for (size_t i = 0; i < a.points.size(); ++i)
        EXPECT_LE((a.points[i] - b.points[i]).cwiseAbs().maxCoeff(),
                  5e-3f * a.points[i].cwiseAbs().maxCoeff() + 1e-6f);
    EXPECT_EQ(run(gen + "--precision 0 -o " + short3.string()), 2);
    EXPECT_EQ(run(gen + "--precision 10 -o " + short3.string()), 2);
}

TEST(Cli, UpZWritesAZUpLayer) {
    Dir d;
    const fs::path y = d.path / "y.usda", z = d.path / "z.usda", zc = d.path / "zc.usda";
    const std::string gen = "generate --preset short --strands 300 --wisps 30 -q ";
    ASSERT_EQ(run(gen + "-o " + y.string()), 0);
    ASSERT_EQ(run(gen + "--up z -o " + z.string()), 0);
    ASSERT_EQ(run("convert " + y.string() + " " + zc.string() + " --up z"), 0);
    EXPECT_EQ(run(gen + "--up x -o " + z.string()), 2);
    EXPECT_NE(slurp(y).find("upAxis = \"Y\""), std::string::npos);
    EXPECT_NE(slurp(z).find("upAxis = \"Z\""), std::string::npos);
    // The same strands whether generated Z up or converted to it (generate also writes the
    // roots' UVs and groups, which a converted .usda no longer knows).
    const wisp::Hair gz = wisp::read_hair(z), cz = wisp::read_hair(zc);
    EXPECT_TRUE(gz.points == cz.points);
    EXPECT_TRUE(gz.widths == cz.widths);
    EXPECT_TRUE(gz.colors == cz.colors);
    EXPECT_EQ(gz.wisp, cz.wisp);
    EXPECT_NE(slurp(z).find("groom_root_uv"), std::string::npos);
    // Both read back as the same strands in head space.
    const wisp::Hair a = wisp::read_hair(y), b = wisp::read_hair(z);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_TRUE(a.points == b.points);
}

// The export options: guides and the head in the .usda, an even subset of the strands, the
// groups of a braid (Unreal hair groups), and the checks made before the work.
TEST(Cli, ExportOptions) {
    Dir d;
    const fs::path usda = d.path / "b.usda", npz = d.path / "b.npz", half = d.path / "h.hair";
    const std::string gen = "generate --preset braid --strands 600 --wisps 60 -q ";
    ASSERT_EQ(run(gen + "--guides --with-head --export-strands 200 -o " + usda.string() + " -o " +
                  npz.string()),
              0);
    const std::string text = slurp(usda);
    EXPECT_NE(text.find("def BasisCurves \"guides\""), std::string::npos);
    EXPECT_NE(text.find("def Mesh \"head\""), std::string::npos);
    EXPECT_NE(text.find("def GeomSubset \"scalp\""), std::string::npos);
    EXPECT_NE(text.find("float2[] primvars:groom_root_uv"), std::string::npos);
    // The braid's strands fall into its three plaits' groups, 1 to 3.
    const size_t g = text.find("int[] primvars:groom_group_id = [");
    ASSERT_NE(g, std::string::npos);
    const size_t values = g + std::string("int[] primvars:groom_group_id = [").size();
    const std::string ids = text.substr(values, text.find(']', values) - values);
    EXPECT_NE(ids.find('1'), std::string::npos);
    EXPECT_NE(ids.find('3'), std::string::npos);
    // wisp reads the 200 render strands; the 60 guides are the simulation's, not drawn.
    EXPECT_EQ(wisp::read_hair(usda).strand_count(), 200u);
    EXPECT_GT(fs::file_size(npz), 200u * 32 * 12);
    ASSERT_EQ(run("convert " + usda.string() + " " + half.string() + " --export-fraction 0.5"), 0);
    EXPECT_EQ(wisp::read_hair(half).strand_count(), 100u);
    // Mistakes are found before the work.
    EXPECT_EQ(run(gen + "--guides -o " + (d.path / "x.hair").string()), 2);
    EXPECT_EQ(
        run(gen + "--export-strands 5 --export-fraction 0.5 -o " + (d.path / "x.hair").string()),
        2);
    EXPECT_EQ(run(gen + "--resample 1 -o " + (d.path / "x.npz").string()), 2);
    EXPECT_FALSE(fs::exists(d.path / "x.hair"));
}

TEST(Cli, AnimateWritesFramesDeterministically) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style,
          "[roots]\nwisps = 80\nstrands = 800\npoints_per_strand = 12\n"
          "[maps]\nlength = 30\n[dynamics]\nsections = 6\n");
    // Value clips (the default) at 1 and 2 threads: same top layer, same frames.
    const fs::path a = d.path / "a.usda", b = d.path / "two" / "a.usda";
    const std::string common = "animate " + style.string() + " --motion shake --frames 6 -q ";
    ASSERT_EQ(run(common + "--threads 1 -o " + a.string() + " -o " +
                  (d.path / "f_##.hair").string() + " --stats " + (d.path / "s.json").string()),
              0);
    ASSERT_EQ(run(common + "--threads 2 -o " + b.string()), 0);
    EXPECT_EQ(slurp(a), slurp(b));
    for (int f = 0; f < 6; ++f) {
        const std::string name = "a.000" + std::to_string(f) + ".usda";
        EXPECT_EQ(slurp(d.path / name), slurp(d.path / "two" / name)) << name;
    }
    EXPECT_NE(slurp(a).find("asset[] assetPaths = [@./a.0000.usda@, @./a.0001.usda@"),
              std::string::npos);
    EXPECT_NE(slurp(d.path / "a.0005.usda").find("points.timeSamples = {\n            5: ["),
              std::string::npos);
    // The single time-sampled layer on request.
    const fs::path single = d.path / "single.usda";
    ASSERT_EQ(run(common + "--usda single -o " + single.string()), 0);
    const std::string usda = slurp(single);
    EXPECT_NE(usda.find("points.timeSamples"), std::string::npos);
    EXPECT_NE(usda.find("endTimeCode = 5"), std::string::npos);
    EXPECT_FALSE(fs::exists(d.path / "single.0000.usda"));
    // wisp reads the clips' top layer as frame 0, the same strands as the single layer's.
    EXPECT_EQ(wisp::read_hair(a).points, wisp::read_hair(single).points);
    for (int f = 0; f < 6; ++f)
        EXPECT_TRUE(fs::exists(d.path / ("f_0" + std::to_string(f) + ".hair"))) << f;
    const std::string stats = slurp(d.path / "s.json");
    EXPECT_NE(stats.find("\"active_nodes_per_level\""), std::string::npos);
    EXPECT_NE(stats.find("\"ms_per_step\""), std::string::npos);
    // An imported hair file animates too (hierarchy by clustering), and PNG frames render.
    ASSERT_EQ(run("animate " + (d.path / "f_00.hair").string() +
                  " --frames 3 --size 64x64 -q "
                  "--png " +
                  (d.path / "p_####.png").string()),
              0);
    EXPECT_TRUE(fs::exists(d.path / "p_0002.png"));
    // A tie holds the imported strands that pass near it; one that catches none, or has a
    // radius ≤ 0, is a usage error.
    const std::string hair = (d.path / "f_00.hair").string();
    ASSERT_EQ(run("animate " + hair + " --frames 2 -q --tie 0,0,-12,4 --stats " +
                  (d.path / "t.json").string()),
              0);
    const std::string tied = slurp(d.path / "t.json");
    EXPECT_EQ(tied.find("\"held_finest_nodes\": 0"), std::string::npos) << tied;
    EXPECT_EQ(
        run("animate " + hair + " --frames 2 --tie 0,500,0 -o " + (d.path / "t.usda").string()), 2);
    EXPECT_FALSE(fs::exists(d.path / "t.usda"));
    EXPECT_EQ(
        run("animate " + hair + " --frames 2 --tie 0,0,-12,-1 -o " + (d.path / "t.usda").string()),
        2);
}

// --guides: each frame holds one guide per wisp, the very strand the full animation moves
// (the same simulation), beside the render strands at rest bound to their guides; both as
// value clips and as one time-sampled layer.
TEST(Cli, AnimateGuidesWritesTheGuidesOnly) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style,
          "[roots]\nwisps = 40\nstrands = 600\npoints_per_strand = 10\n"
          "[maps]\nlength = 25\n[dynamics]\nsections = 5\n");
    const std::string common = "animate " + style.string() + " --motion shake --frames 3 -q ";
    const fs::path full = d.path / "full.usda", g = d.path / "g.usda", gs = d.path / "gs.usda";
    ASSERT_EQ(run(common + "-o " + full.string()), 0);
    ASSERT_EQ(run(common + "--guides -o " + g.string()), 0);
    ASSERT_EQ(run(common + "--guides --usda single -o " + gs.string()), 0);
    EXPECT_EQ(run(common + "--guides -o " + (d.path / "x.hair").string()), 2);
    // --precision as generate and convert take it: the same frames, rounded, in smaller files.
    const fs::path rounded = d.path / "p.usda";
    ASSERT_EQ(run(common + "--precision 3 -o " + rounded.string()), 0);
    EXPECT_LT(fs::file_size(d.path / "p.0002.usda") * 3,
              fs::file_size(d.path / "full.0002.usda") * 2);
    {
        const auto exact = wisp::read_usda_layer(d.path / "full.0002.usda").curves.at(0).points;
        const auto near = wisp::read_usda_layer(d.path / "p.0002.usda").curves.at(0).points;
        ASSERT_EQ(near.size(), exact.size());
        for (size_t i = 0; i < exact.size(); ++i)
            for (int k = 0; k < 3; ++k)
                ASSERT_NEAR(near[i][k], exact[i][k], 0.0051 * std::abs(exact[i][k]) + 1e-6);
    }
    EXPECT_EQ(run(common + "--precision 10 -o " + rounded.string()), 2);

    // The frame layers animate /hair/guides only, and are far smaller.
    const std::string frame2 = slurp(d.path / "g.0002.usda");
    EXPECT_NE(frame2.find("over BasisCurves \"guides\""), std::string::npos);
    EXPECT_EQ(frame2.find("\"strands\""), std::string::npos);
    EXPECT_LT(fs::file_size(d.path / "g.0002.usda") * 5, fs::file_size(d.path / "full.0002.usda"));
    // Guide k of frame 2 is a strand of its wisp in the full animation's frame 2.
    // A clip holds points only: the topology is the top layer's.
    const wisp::UsdaLayer guide_layer = wisp::read_usda_layer(d.path / "g.0002.usda");
    ASSERT_EQ(guide_layer.curves.size(), 1u);
    wisp::Hair full2 = wisp::read_hair(full);
    full2.points = wisp::read_usda_layer(d.path / "full.0002.usda").curves.at(0).points;
    const std::vector<wisp::Vec3f>& gp = guide_layer.curves[0].points;
    // The top layer: render strands at rest (600, read back as the strands) and the guides,
    // flagged and bound (closest guides).
    const wisp::UsdaLayer top = wisp::read_usda_layer(g);
    ASSERT_EQ(top.curves.size(), 2u);
    EXPECT_EQ(top.curves[0].path, "/hair/strands");
    EXPECT_EQ(top.curves[1].path, "/hair/guides");
    EXPECT_TRUE(top.curves[1].guide);
    const size_t W = top.curves[1].counts.size();
    EXPECT_EQ(W, 40u);
    const std::string text = slurp(g);
    EXPECT_NE(text.find("primvars:groom_closest_guides"), std::string::npos);
    EXPECT_NE(text.find("prepend apiSchemas = [\"GroomAPI\"]"), std::string::npos);
    EXPECT_EQ(wisp::read_hair(g).strand_count(), 600u);
    size_t at = 0, found = 0;
    for (size_t k = 0; k < W; ++k) {
        const size_t n = static_cast<size_t>(top.curves[1].counts[k]);
        for (size_t s = 0; s < full2.strand_count(); ++s)
            if (full2.strand_size(s) == n &&
                std::equal(gp.begin() + long(at), gp.begin() + long(at + n),
                           full2.points.begin() + full2.offsets[s])) {
                ++found;
                break;
            }
        at += n;
    }
    EXPECT_EQ(at, gp.size());
    EXPECT_EQ(found, W);
    // The single layer holds the same guides as time samples.
    const std::string single = slurp(gs);
    EXPECT_NE(single.find("def BasisCurves \"guides\""), std::string::npos);
    EXPECT_NE(single.find("point3f[] points.timeSamples"), std::string::npos);
    EXPECT_EQ(wisp::read_hair(gs).points, wisp::read_hair(g).points);
}

TEST(Cli, AnimateRejectsBadInput) {
    Dir d;
    const fs::path motion = d.path / "m.json";
    write(motion, "{\"format\": \"wisp-motion\", \"version\": 1, \"head\": {\"keys\": [");
    EXPECT_EQ(run("animate --preset short --strands 500 --motion " + motion.string() + " -o " +
                  (d.path / "x.usda").string()),
              1);
    EXPECT_FALSE(fs::exists(d.path / "x.usda"));
    EXPECT_EQ(run("animate --preset short --motion wobble -o " + (d.path / "x.usda").string()), 1);
    EXPECT_EQ(run("animate --preset short --frames 0 -o " + (d.path / "x.usda").string()), 2);
    const fs::path bad = d.path / "bad.toml";
    write(bad, "[dynamics]\nfriction = 500\n");  // α·dt = 5 ≥ 1
    EXPECT_EQ(run("animate " + bad.string() + " -o " + (d.path / "x.usda").string()), 1);
}

TEST(Cli, LongWorkReportsProgressUnlessQuiet) {
    // Not on a terminal (stderr is a file), a contact sheet reports each view on a plain line
    // (throttled to one every few seconds, the first and the last always shown).
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 60\nstrands = 600\npoints_per_strand = 12\n");
    const fs::path hair = d.path / "h.hair", png = d.path / "h.png", err = d.path / "err.txt";
    ASSERT_EQ(run_capturing("generate " + style.string() + " -o " + hair.string() + " --png " +
                                png.string() + " --views front,back,left --size 48x48",
                            err),
              0);
    const std::string log = slurp(err);
    EXPECT_NE(log.find("wisp: rendering view 1/3 (front)\n"), std::string::npos) << log;
    EXPECT_NE(log.find("wisp: rendering view 3/3 (left)\n"), std::string::npos) << log;
    EXPECT_EQ(log.find('\r'), std::string::npos) << "no terminal line rewriting in a log";
    ASSERT_EQ(run_capturing("render " + hair.string() + " -o " + png.string() +
                                " --view front,back --size 48x48 -q",
                            err),
              0);
    EXPECT_EQ(slurp(err), "");
}

TEST(Cli, RenderGivesTheSamePictureAtAnyThreadCount) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 60\nstrands = 600\npoints_per_strand = 12\n");
    const fs::path hair = d.path / "h.hair", a = d.path / "a.png", b = d.path / "b.png";
    ASSERT_EQ(run("generate " + style.string() + " -q -o " + hair.string()), 0);
    ASSERT_EQ(run("render " + hair.string() + " -o " + a.string() + " --size 64x64 --threads 1"),
              0);
    ASSERT_EQ(run("render " + hair.string() + " -o " + b.string() + " --size 64x64 --threads 2"),
              0);
    EXPECT_EQ(slurp(a), slurp(b));
    EXPECT_GT(fs::file_size(a), 100u);
    EXPECT_EQ(run("render " + hair.string() + " -o " + a.string() + " --threads -1"), 2);
}

TEST(Cli, RenderRimLightScalesAndTurnsOff) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 60\nstrands = 600\npoints_per_strand = 12\n");
    const fs::path hair = d.path / "h.hair", a = d.path / "a.png", b = d.path / "b.png";
    ASSERT_EQ(run("generate " + style.string() + " -q -o " + hair.string()), 0);
    const std::string common = "render " + hair.string() + " --size 64x64 -q --view back -o ";
    ASSERT_EQ(run(common + a.string()), 0);
    ASSERT_EQ(run(common + b.string() + " --rim 0"), 0);
    EXPECT_NE(slurp(a), slurp(b));  // the default rig has a rim light
    ASSERT_EQ(run(common + b.string() + " --rim 1"), 0);
    EXPECT_EQ(slurp(a), slurp(b));
    EXPECT_EQ(run(common + b.string() + " --rim -1"), 2);
}

TEST(Cli, UsageErrorsQuoteArgumentsEscaped) {
    // CLI11's own messages quote the arguments it did not expect: a terminal escape sequence
    // among them is shown escaped, not sent to the user's terminal.
    Dir d;
    const fs::path err = d.path / "err.txt";
    EXPECT_EQ(run_capturing("presets '\x1b]0;owned\x07'", err), 2);
    const std::string msg = slurp(err);
    EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
    EXPECT_NE(msg.find("\\x1b]0;owned"), std::string::npos) << msg;
    EXPECT_NE(msg.find("usage error"), std::string::npos) << msg;
}

// Issue 14: hostile inputs fail with exit 1 and one escaped line naming the file and what is
// wrong; never a crash, a hang or memory running out.
TEST(Cli, HostileInputsFailWithOneLineNamingTheFile) {
    Dir d;
    const fs::path err = d.path / "err.txt";
    const auto expect_failure = [&](const std::string& args, const std::string& says) {
        EXPECT_EQ(run_capturing(args, err), 1) << args;
        const std::string msg = slurp(err);
        EXPECT_NE(msg.find(says), std::string::npos) << args << "\n" << msg.substr(0, 300);
        EXPECT_EQ(msg.find('\x1b'), std::string::npos) << args;
        EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 1) << args << "\n" << msg;
    };
    // Tuples without their numbers once crashed every command reading them.
    const fs::path empty = d.path / "empty.usda";
    write(empty,
          "#usda 1.0\ndef BasisCurves \"C\" {\n    int[] curveVertexCounts = [4]\n"
          "    point3f[] points = [((),(),()), ((),(),()), ((),(),()), ((),(),())]\n}\n");
    const std::string x = (d.path / "x").string();
    const std::pair<std::string, std::string> commands[] = {{"info", ""},
                                                            {"info --json", ""},
                                                            {"convert", x + ".hair"},
                                                            {"render", "-q -o " + x + ".png"},
                                                            {"animate", "-q -o " + x + ".usda"}};
    for (const auto& [command, rest] : commands)
        expect_failure(command + " " + empty.string() + " " + rest,
                       "empty.usda:4:26: values nested too deeply");
    // A terminal escape sequence in a header is quoted escaped.
    const fs::path ply = d.path / "esc.ply";
    write(ply, "ply\n\x1b]0;owned\x07\x1b[2J x\n");
    expect_failure("info " + ply.string(), "esc.ply:2: unknown header line `\\x1b]0;owned\\x07");
    // Far-off strands (2e8 cm) once kept `render` busy for minutes.
    const fs::path far = d.path / "far.obj";
    write(far, "v 0 0 0\nv 0 1 0\nv 0 2e8 0\nl 1 2 3\n");
    expect_failure("render -q -o " + (d.path / "far.png").string() + " " + far.string(),
                   "far.obj: point 2 (strand 0, its point 2) is at (0, 2e+08, 0)");
    // Endless files are not read until memory runs out.
    const fs::path zero_usda = d.path / "zero.usda", zero_toml = d.path / "zero.toml";
    fs::create_symlink("/dev/zero", zero_usda);
    fs::create_symlink("/dev/zero", zero_toml);
    expect_failure("convert " + zero_usda.string() + " " + (d.path / "x.hair").string(),
                   "zero.usda:1:1: not a usda text layer");
    expect_failure("generate " + zero_toml.string() + " -o " + (d.path / "x.hair").string(),
                   "zero.toml: byte 0 is a NUL byte, which a style file (text) never holds");
    expect_failure("animate --preset short --strands 300 --motion /dev/zero -o " +
                       (d.path / "x.usda").string(),
                   "/dev/zero: byte 0 is a NUL byte, which a motion file (text) never holds");
    const fs::path head_zero = d.path / "hz.toml";
    write(head_zero, "[head]\nobj = \"/dev/zero\"\n");
    expect_failure("generate " + head_zero.string() + " -o " + (d.path / "x.hair").string(),
                   "/dev/zero: byte 0 is a NUL byte, which a head OBJ file (text) never holds");
    // What fails once the style is read names the style.
    const fs::path huge = d.path / "huge.toml";
    write(huge, "name = \"huge\"\n[maps]\nlength = 400\n");
    expect_failure(
        "generate -q " + huge.string() + " --strands 500 -o " + (d.path / "x.hair").string(),
        "huge.toml: the solver's grid would span");
    EXPECT_FALSE(fs::exists(d.path / "x.hair"));
}

TEST(Cli, GridsSizedByTheInputAreCheckedBeforeAllocation) {
    Dir d;
    const fs::path err = d.path / "err.txt", out = d.path / "x.hair";
    // A 56-byte field file declaring a 512³ grid.
    const fs::path field = d.path / "f.field", fstyle = d.path / "f.toml";
    write(field, "wisp-field 1\ndims 512 512 512\norigin 0 0 0\ncell 1\n0 0 0\n");
    write(fstyle,
          "[roots]\nwisps = 20\nstrands = 200\n[[solve.field]]\nkind = \"file\"\nfile = \"" +
              field.string() + "\"\n");
    EXPECT_EQ(run_capturing("generate " + fstyle.string() + " -o " + out.string(), err), 1);
    EXPECT_NE(slurp(err).find("f.field:4: dims 512 512 512 declare 134217728 vectors"),
              std::string::npos)
        << slurp(err);
    // 500 cm hair at 1 cm cells: a 10⁹-node solver grid.
    const fs::path lstyle = d.path / "l.toml";
    write(lstyle, "[roots]\nwisps = 20\nstrands = 200\n[maps]\nlength = 500\n[solve]\ncell = 1\n");
    EXPECT_EQ(run_capturing("generate " + lstyle.string() + " -o " + out.string(), err), 1);
    EXPECT_NE(slurp(err).find("or raise solve.cell"), std::string::npos) << slurp(err);
    // The built-in head at 30× its size.
    const fs::path head = d.path / "head.obj", hstyle = d.path / "h.toml";
    ASSERT_EQ(run("head -o " + head.string()), 0);
    write(hstyle, "[roots]\nwisps = 20\nstrands = 200\n[head]\nobj = \"" + head.string() +
                      "\"\nscale = 30\n");
    EXPECT_EQ(run_capturing("generate " + hstyle.string() + " -o " + out.string(), err), 1);
    EXPECT_NE(slurp(err).find("head.obj: the head spans"), std::string::npos) << slurp(err);
    EXPECT_NE(slurp(err).find("after head.scale = 30"), std::string::npos) << slurp(err);
    EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, InfoJsonReplacesBytesThatAreNotUtf8) {
    Dir d;
    const fs::path style = d.path / "s.toml";
    write(style, "[roots]\nwisps = 20\nstrands = 100\npoints_per_strand = 6\n");
    const fs::path hair = d.path / "caf\xe9.usda", out = d.path / "out.json";
    ASSERT_EQ(run("generate " + style.string() + " -q -o '" + hair.string() + "'"), 0);
    const std::string info =
        std::string(WISP_EXE) + " info --json '" + hair.string() + "' >" + out.string();
    ASSERT_EQ(std::system(info.c_str()), 0);
    const std::string json = slurp(out);
    EXPECT_NE(json.find("caf\xef\xbf\xbd.usda"), std::string::npos) << json;  // U+FFFD
    // A prim name that is not UTF-8 is named escaped.
    const fs::path bad = d.path / "bad.usda", err = d.path / "err.txt";
    write(bad, "#usda 1.0\ndef BasisCurves \"h\xff\" {\n}\n");
    EXPECT_EQ(run_capturing("info --json " + bad.string(), err), 1);
    EXPECT_NE(slurp(err).find("bad.usda:2:17: prim name \"h\\xff\" holds control characters"),
              std::string::npos)
        << slurp(err);
}

// Usage errors are found before any work: no output is written, no temporary folder left.
TEST(Cli, OutputsGoIntoNewRelativeFolders) {
    // The README's first command writes into out/, which a fresh clone does not have: the
    // check before the work must accept a folder the writer will create in the current one.
    Dir d;
    const std::string cmd = "cd " + d.path.string() + " && " + std::string(WISP_EXE) +
                            " generate --preset short --strands 200 -o new/sub/a.hair -q";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    EXPECT_TRUE(fs::exists(d.path / "new/sub/a.hair"));
}

TEST(Cli, ArgumentsAreCheckedBeforeTheWork) {
    Dir d;
    const std::string out = (d.path / "a.hair").string();
    const std::string gen = "generate --preset default -o " + out + " ";
    // Refused before the work starts: the only thing said is the error (the work's first line
    // names the wisps and strands, its last the files written), and no file appears. Told by
    // what the run says, not by how long it took, so a loaded machine cannot fail it.
    const fs::path err = d.path / "err.txt";
    const auto quick = [&](const std::string& args, int code) {
        EXPECT_EQ(run_capturing(args, err), code) << args;
        const std::string said = slurp(err);
        EXPECT_EQ(said.find(" strands"), std::string::npos) << args << "\n" << said;
        EXPECT_EQ(said.find("frame"), std::string::npos) << args << "\n" << said;
        EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << args << "\n" << said;
        EXPECT_FALSE(fs::exists(out)) << args;
    };
    const std::string png = " --png " + (d.path / "p.png").string();
    quick(gen + png + " --size 5x5", 2);
    quick(gen + png + " --eye 1,2", 2);
    quick(gen + png + " --eye 0,0,50 --target 0,0,50", 2);
    quick(gen + png + " --background red", 2);
    quick(gen + png + " --views front,sideways", 2);
    write(d.path / "file", "");
    quick(gen + "--stats " + (d.path / "file" / "s.json").string(), 1);
    quick(gen + "-o " + (d.path / "x.unknown").string(), 1);
    quick("animate --preset short -o " + (d.path / "x.usda").string() + " --size 5x5", 2);
    quick("animate --preset short --mp4 " + (d.path / "x.mp4").string() + " --size 5x5", 2);
    quick("animate --preset short --mp4 " + (d.path / "x.mp4").string() + " --view sideways", 2);
    quick("render " + out + " -o " + (d.path / "r.png").string() + " --size 5x5", 2);
}

// The error sweep: each command's ways to fail on what a user gives it, each refused with
// one line that names the input (file, and line or field where there is one) and what is
// wrong, exit 1 for a bad input and 2 for a bad argument, and no output file left.
TEST(Cli, EveryCommandsErrorsNameTheirInput) {
    Dir d;
    const fs::path err = d.path / "err.txt";
    const auto in = [&](const std::string& name, const std::string& text) {
        write(d.path / name, text);
        return (d.path / name).string();
    };
    const std::string ok = in("ok.toml", "name = \"s\"\n[roots]\nwisps = 30\nstrands = 300\n");
    const std::string hair = (d.path / "ok.hair").string();
    ASSERT_EQ(run("generate -q " + ok + " -o " + hair), 0);
    const std::string trunc = in("trunc.hair", slurp(hair).substr(0, 300));
    const std::string tri = in("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string bad_obj = in("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    const std::string bad_png = in("bad.png", "not a png\n");
    const std::string x = (d.path / "x").string();
    struct Case {
        std::string args;
        int code;
        std::string says;
    };
    const Case cases[] = {
        // generate: the style, its head, its maps, the outputs.
        {"generate " + in("syntax.toml", "[roots\n") + " -o " + x + ".hair", 1,
         "syntax.toml:1:7: TOML syntax error"},
        {"generate " + in("unknown.toml", "[roots]\nwispz = 3\n") + " -o " + x + ".hair", 1,
         "unknown.toml:2: unknown field 'roots.wispz' (did you mean 'roots.wisps'?)"},
        {"generate " + in("range.toml", "[roots]\nwisps = -3\n") + " -o " + x + ".hair", 1,
         "range.toml:2: field 'roots.wisps': must be ≥ 1, got -3"},
        {"generate --preset nosuch -o " + x + ".hair", 1, "unknown preset 'nosuch'"},
        {"generate " + (d.path / "missing.toml").string() + " -o " + x + ".hair", 2,
         "missing.toml"},
        {"generate -q " + ok + " --head " + bad_obj + " -o " + x + ".hair", 1,
         "ok.toml: " + bad_obj + ":3: vertex index 9 is out of range"},
        {"generate -q " + in("head.toml", "[head]\nobj = \"" + bad_obj + "\"\n") + " -o " + x +
             ".hair",
         1, "head.toml: " + bad_obj + ":3: vertex index 9"},
        {"generate -q " + ok + " --head " + tri + " --scalp group:nosuch -o " + x + ".hair", 1,
         "tri.obj: scalp by group: no face group or material named 'nosuch'"},
        {"generate -q " + ok + " --scalp mask:" + bad_png + " -o " + x + ".hair", 1,
         "bad.png: not a readable image"},
        {"generate -q " + ok + " --scalp mask:" + x + ".none -o " + x + ".hair", 2,
         "x.none is not a file"},
        {"generate -q " + ok + " -o " + x + ".xyz", 1, "x.xyz: unknown hair file extension"},
        {"generate -q " + ok + " -o " + x + ".hair --png " + x + ".jpg", 2,
         "--png: writes PNG pictures: give a name ending in .png, got '" + x + ".jpg'"},
        {"generate -q " + ok + " -o /proc/wisp/x.hair", 1, "/proc/wisp/x.hair: cannot"},
        // render, convert, info: the hair file, the head, the output.
        {"render -q " + x + ".hair -o " + x + ".png", 1, "x.hair: cannot open"},
        {"render -q " + trunc + " -o " + x + ".png", 1,
         "trunc.hair: byte 300: header declares 300 strands"},
        {"render -q " + hair + " --head " + bad_obj + " -o " + x + ".png", 1,
         "bad.obj:3: vertex index 9"},
        {"render -q " + hair + " -o " + x + ".xyz", 2,
         "--output: writes PNG pictures: give a name ending in .png"},
        {"convert " + hair + " " + x + ".xyz", 1, "x.xyz: unknown hair file extension"},
        {"convert " + trunc + " " + x + ".ply", 1, "trunc.hair: byte 300"},
        {"info " + in("junk.hair", "HAIR\x01"), 1, "junk.hair: byte"},
        // animate: the style or hair, the motion, the outputs.
        {"animate -q " + ok + " --frames 2 --motion " +
             in("syntax.json", "{\"format\": \"wisp-motion\", ") + " -o " + x + ".usda",
         1, "syntax.json"},
        {"animate -q " + ok + " --frames 2 --motion " + in("field.json", "{\"frames\": 3}") +
             " -o " + x + ".usda",
         1, "field.json: frames: unknown field"},
        {"animate -q " + ok + " --frames 2 --motion dance -o " + x + ".usda", 1,
         "dance: neither a motion preset (lean, shake, nod, jump, run, still) nor a motion "
         "file"},
        {"animate -q " + trunc + " --frames 2 -o " + x + ".usda", 1, "trunc.hair: byte 300"},
        {"animate -q " + ok + " --frames 2 -o " + x + ".xyz", 1,
         x + ".xyz: unknown hair file extension"},
        {"animate -q " + ok + " --frames 2 --png " + x + "_####.jpg", 2,
         "--png: writes PNG pictures"},
        {"animate -q " + in("ahead.toml", "[head]\nobj = \"" + bad_obj + "\"\n") +
             " --frames 2 -o " + x + ".usda",
         1, "ahead.toml: " + bad_obj + ":3"},
        // dataset: the spec and the folder.
        {"dataset plan " + in("spec.toml", "samples = [") + " -o " + x + "_ds", 1,
         "spec.toml:1:12: TOML syntax error"},
        {"dataset plan " + in("spec2.toml", "[dataset]\n") + " -o " + x + "_ds", 1,
         "spec2.toml:1: field 'dataset': unknown field"},
        {"dataset verify " + d.path.string(), 1, d.path.string() + ": no dataset.json"},
        {"dataset run " + d.path.string(), 1, d.path.string() + ": no dataset.json"},
        // edit: the style it starts from.
        {"edit " + (d.path / "syntax.toml").string(), 1, "syntax.toml:1:7: TOML syntax error"},
        // head: the output.
        {"head -o /proc/wisp/h.obj", 1, "/proc/wisp/h.obj: cannot"},
    };
    for (const Case& c : cases) {
        EXPECT_EQ(run_capturing(c.args, err), c.code) << c.args;
        const std::string said = slurp(err);
        EXPECT_NE(said.find(c.says), std::string::npos) << c.args << "\n" << said;
        // One line, and for some usage errors CLI11's hint to --help.
        const size_t hint = said.find("\nRun with --help for more information.\n");
        EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), hint == std::string::npos ? 1 : 2)
            << c.args << "\n"
            << said;
        EXPECT_FALSE(fs::exists(x + ".hair") || fs::exists(x + ".usda") || fs::exists(x + ".png") ||
                     fs::exists(x + "_ds"))
            << c.args;
    }
}
