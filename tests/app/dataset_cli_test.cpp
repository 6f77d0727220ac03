// `wisp dataset` as users run it: shards and jobs give byte-identical samples, a sample's
// style regenerates its hair, a killed run leaves no half sample and resumes, bad specs exit 1.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

extern char** environ;

namespace {

namespace fs = std::filesystem;

const fs::path kSpec = fs::path(WISP_SOURCE_DIR) / "tests" / "dataset" / "small.toml";

struct Dir {
    fs::path path;
    Dir() {
        static int counter = 0;
        path = fs::temp_directory_path() / ("wisp_dataset_test_" + std::to_string(::getpid()) +
                                            "_" + std::to_string(counter++));
        fs::create_directories(path);
    }
    ~Dir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

int run(const std::string& args, const fs::path& out = "/dev/null") {
    const std::string cmd = std::string(WISP_EXE) + " " + args + " >" + out.string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Every file under dir (relative path -> bytes).
std::map<std::string, std::string> tree(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
    return files;
}

TEST(DatasetCli, ShardsJobsAndThreadsGiveByteIdenticalSamples) {
    Dir d;
    const fs::path one = d.path / "one", sharded = d.path / "sharded";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + one.string()), 0);
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + sharded.string()), 0);
    EXPECT_EQ(slurp(one / "manifest.jsonl"), slurp(sharded / "manifest.jsonl"));
    ASSERT_EQ(run("dataset run " + one.string() + " --threads 1 --jobs 1"), 0);
    for (int i = 0; i < 3; ++i)
        ASSERT_EQ(run("dataset run " + sharded.string() + " --jobs 2 --shard " + std::to_string(i) +
                      "/3"),
                  0);
    const auto a = tree(one / "samples"), b = tree(sharded / "samples");
    EXPECT_EQ(a.size(), 8u * 15u);  // style, 2 hair, meta, 2 cameras, 4 per camera × 2, complete
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [name, bytes] : a) {
        ASSERT_TRUE(b.count(name)) << name;
        EXPECT_TRUE(bytes == b.at(name)) << name << " differs";
    }
    // Nothing about the run (times, hosts, pids) in a sample's metadata.
    const std::string meta = a.at("000000/meta.json");
    EXPECT_EQ(meta.find("ms"), std::string::npos);
    EXPECT_NE(meta.find("\"values\""), std::string::npos);
    // A rerun skips every finished sample and changes nothing.
    ASSERT_EQ(run("dataset run " + one.string(), d.path / "rerun.txt"), 0);
    EXPECT_NE(slurp(d.path / "rerun.txt").find("0 made, 8 done before"), std::string::npos)
        << slurp(d.path / "rerun.txt");
    EXPECT_EQ(tree(one / "samples"), a);
    ASSERT_EQ(run("dataset verify " + one.string(), d.path / "verify.txt"), 0);
    EXPECT_NE(slurp(d.path / "verify.txt").find("done 8"), std::string::npos);
}

TEST(DatasetCli, ASamplesStyleRegeneratesItsHair) {
    Dir d;
    const fs::path dir = d.path / "ds";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + dir.string()), 0);
    ASSERT_EQ(run("dataset run " + dir.string() + " --task-id 3 --tasks 4"), 0);
    for (const char* sample : {"000003", "000007"}) {
        const fs::path s = dir / "samples" / sample;
        ASSERT_TRUE(fs::exists(s / "complete.json")) << sample;
        const fs::path again = d.path / (std::string(sample) + ".hair");
        ASSERT_EQ(run("generate " + (s / "style.toml").string() + " -q -o " + again.string()), 0);
        EXPECT_TRUE(slurp(again) == slurp(s / "hair.hair")) << sample;
    }
    ASSERT_EQ(run("dataset status " + dir.string(), d.path / "status.txt"), 0);
    const std::string status = slurp(d.path / "status.txt");
    EXPECT_NE(status.find("done 2\npending 6\nfailed 0"), std::string::npos) << status;
    EXPECT_NE(status.find("missing 0-2,4-6"), std::string::npos) << status;
    // The task index of a job array's environment: Slurm's, with its count.
    const std::string env_run = "SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=4 " +
                                std::string(WISP_EXE) + " dataset run " + dir.string() +
                                " -q >/dev/null 2>&1";
    ASSERT_EQ(std::system(env_run.c_str()), 0);
    EXPECT_TRUE(fs::exists(dir / "samples" / "000001" / "complete.json"));
    EXPECT_TRUE(fs::exists(dir / "samples" / "000005" / "complete.json"));
    EXPECT_FALSE(fs::exists(dir / "samples" / "000000"));
    // pack: the done samples (1, 3, 5, 7) as tar shards of 3 samples that tar lists.
    ASSERT_EQ(run("dataset pack " + dir.string() + " --samples-per-shard 3"), 0);
    ASSERT_TRUE(fs::exists(dir / "pack" / "shard-000001.tar"));
    EXPECT_FALSE(fs::exists(dir / "pack" / "shard-000002.tar"));
    const fs::path listing = d.path / "tar.txt";
    ASSERT_EQ(std::system(("tar -tf " + (dir / "pack" / "shard-000000.tar").string() + " >" +
                           listing.string())
                              .c_str()),
              0);
    const std::string members = slurp(listing);
    EXPECT_NE(members.find("000001.style.toml\n"), std::string::npos) << members;
    EXPECT_NE(members.find("000005.cam1_orientation.png\n"), std::string::npos) << members;
    EXPECT_EQ(members.find("000007."), std::string::npos) << members;
    EXPECT_EQ(members.find("complete.json"), std::string::npos) << members;
    ASSERT_EQ(std::system(("mkdir -p " + (d.path / "x").string() + " && tar -xf " +
                           (dir / "pack" / "shard-000001.tar").string() + " -C " +
                           (d.path / "x").string())
                              .c_str()),
              0);
    EXPECT_TRUE(slurp(d.path / "x" / "000007.hair.hair") ==
                slurp(dir / "samples" / "000007" / "hair.hair"));
    // Deterministic shards: owner 0/0, mode 0644, time 0, members in name order; packing
    // again after the files' times and modes change gives the same bytes.
    ASSERT_EQ(std::system(("tar --numeric-owner --full-time -tvf " +
                           (dir / "pack" / "shard-000000.tar").string() + " >" + listing.string())
                              .c_str()),
              0);
    const std::string verbose = slurp(listing);
    std::istringstream lines(verbose);
    std::string line, previous;
    int count = 0;
    while (std::getline(lines, line)) {
        ++count;
        EXPECT_EQ(line.rfind("-rw-r--r-- 0/0", 0), 0u) << line;
        EXPECT_NE(line.find(" 1970-01-01 00:00:00 "), std::string::npos) << line;
        const std::string member = line.substr(line.rfind(' ') + 1);
        EXPECT_LT(previous, member);
        previous = member;
    }
    EXPECT_EQ(count, 3 * 14) << verbose;  // 3 samples of 14 files (complete.json left out)
    const std::string shard0 = slurp(dir / "pack" / "shard-000000.tar");
    EXPECT_EQ(shard0.size() % 512, 0u);
    ASSERT_EQ(std::system(("touch -d 2020-01-01 " + (dir / "samples" / "000003" / "*").string() +
                           " && chmod 600 " + (dir / "samples" / "000001" / "meta.json").string())
                              .c_str()),
              0);
    ASSERT_EQ(run("dataset pack " + dir.string() + " --samples-per-shard 3"), 0);
    EXPECT_TRUE(slurp(dir / "pack" / "shard-000000.tar") == shard0);
    // verify fails until the dataset is complete, and catches a changed file.
    EXPECT_EQ(run("dataset verify " + dir.string()), 1);
    std::ofstream(dir / "samples" / "000003" / "cam0_mask.png", std::ios::app) << "x";
    ASSERT_EQ(run("dataset verify " + dir.string(), d.path / "verify.txt"), 1);
    EXPECT_NE(slurp(d.path / "verify.txt").find("corrupt 1"), std::string::npos);
}

TEST(DatasetCli, AKilledRunLeavesNoHalfSampleAndResumes) {
    Dir d;
    const fs::path dir = d.path / "ds", whole = d.path / "whole";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + dir.string()), 0);
    // Kill a run mid-sample several times: at a temporary folder's first sight, and later.
    for (int attempt = 0; attempt < 3; ++attempt) {
        std::vector<std::string> args = {WISP_EXE, "dataset", "run", dir.string(), "--quiet"};
        std::vector<char*> argv;
        for (std::string& a : args)
            argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, WISP_EXE, nullptr, nullptr, argv.data(), environ), 0);
        bool saw_temporary = false;
        for (int i = 0; i < 400 && !saw_temporary; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            std::error_code ec;
            for (const auto& e : fs::directory_iterator(dir / "samples", ec))
                saw_temporary |= e.path().filename().string().find(".tmp-") != std::string::npos;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(150 * attempt));
        kill(pid, SIGKILL);
        int status = 0;
        waitpid(pid, &status, 0);
        // Every folder that looks like a sample is a complete one.
        for (const auto& e : fs::directory_iterator(dir / "samples")) {
            const std::string name = e.path().filename().string();
            if (name[0] == '.') continue;  // a temporary folder: never taken for a sample
            EXPECT_TRUE(fs::exists(e.path() / "complete.json")) << name;
        }
    }
    ASSERT_EQ(run("dataset run " + dir.string()), 0);
    ASSERT_EQ(run("dataset verify " + dir.string()), 0);
    // The killed runs' temporary folders are gone, and the samples equal a clean run's.
    for (const auto& e : fs::directory_iterator(dir / "samples"))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos);
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + whole.string()), 0);
    ASSERT_EQ(run("dataset run " + whole.string()), 0);
    EXPECT_EQ(tree(dir / "samples"), tree(whole / "samples"));
}

TEST(DatasetCli, BadSpecsAndUsage) {
    Dir d;
    const fs::path spec = d.path / "bad.toml";
    std::ofstream(spec) << "samples = 2\n[vary]\n\"solve.stiffness\" = { uniform = [-1, 2] }\n";
    ASSERT_EQ(
        run("dataset plan " + spec.string() + " -o " + (d.path / "x").string(), d.path / "err.txt"),
        1);
    const std::string err = slurp(d.path / "err.txt");
    EXPECT_NE(err.find(spec.string() + ":3: field 'solve.stiffness'"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(d.path / "x" / "dataset.json"));
    EXPECT_EQ(run("dataset run " + (d.path / "nothing").string()), 1);
    const fs::path dir = d.path / "ds";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + dir.string()), 0);
    EXPECT_EQ(run("dataset run " + dir.string() + " --shard 3/3"), 2);
    EXPECT_EQ(run("dataset run " + dir.string() + " --shard x"), 2);
    EXPECT_EQ(run("dataset run " + dir.string() + " --task-id 2"), 2);  // no task count
    // Planning another spec into a planned folder is refused.
    std::ofstream(spec) << "samples = 2\n";
    EXPECT_EQ(run("dataset plan " + spec.string() + " -o " + dir.string()), 1);
    // The sbatch script runs this dataset's tasks.
    ASSERT_EQ(run("dataset slurm " + dir.string() + " --tasks 4 --throttle 2"), 0);
    const std::string script = slurp(dir / "slurm" / "array.sbatch");
    EXPECT_NE(script.find("#SBATCH --array=0-3%2"), std::string::npos) << script;
    // Logs named by the job as well as the task: a resubmitted array keeps the first logs.
    EXPECT_NE(script.find("/slurm/task-%A_%a.log\n"), std::string::npos) << script;
    EXPECT_NE(script.find("--task-id \"$SLURM_ARRAY_TASK_ID\" --tasks 4"), std::string::npos);
}

// A finished sample that is damaged afterwards is made again: by any run when a file is
// missing or changed size, by `run --verify` when only its bytes changed (a CRC mismatch,
// which `verify` reports). The remade files equal the first ones.
TEST(DatasetCli, DamagedSamplesAreMadeAgain) {
    Dir d;
    const fs::path dir = d.path / "ds", err = d.path / "err.txt";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + dir.string()), 0);
    ASSERT_EQ(run("dataset run " + dir.string()), 0);
    const auto before = tree(dir / "samples");
    fs::path sample;
    for (const auto& e : fs::directory_iterator(dir / "samples"))
        if (e.path().filename().string()[0] != '.') sample = std::max(sample, e.path());
    fs::path file;
    for (const auto& e : fs::directory_iterator(sample))
        if (e.path().filename() != "complete.json") file = std::max(file, e.path());
    const std::string bytes = slurp(file);
    ASSERT_FALSE(bytes.empty());

    // Truncated: a plain run sees the size and makes the sample again.
    std::ofstream(file, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    ASSERT_EQ(run("dataset run " + dir.string(), err), 0);
    EXPECT_NE(slurp(err).find("(1 of them damaged before)"), std::string::npos) << slurp(err);
    EXPECT_EQ(tree(dir / "samples"), before);

    // One byte flipped, same size: verify reports it, a plain run keeps it, --verify remakes it.
    std::string flipped = bytes;
    flipped[flipped.size() / 2] ^= 0x20;
    std::ofstream(file, std::ios::binary) << flipped;
    EXPECT_EQ(run("dataset verify " + dir.string(), err), 1);
    ASSERT_EQ(run("dataset run " + dir.string()), 0);
    EXPECT_EQ(slurp(file), flipped);
    ASSERT_EQ(run("dataset run " + dir.string() + " --verify", err), 0);
    EXPECT_EQ(tree(dir / "samples"), before);
    EXPECT_EQ(run("dataset verify " + dir.string()), 0);
}

// Two runs started at once on one folder share its samples (each leaves to the other what
// the other is making) instead of each making all of them, and the samples equal one run's.
TEST(DatasetCli, TwoRunsOnOneFolderShareItsSamples) {
    Dir d;
    const fs::path dir = d.path / "ds", whole = d.path / "whole";
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + dir.string()), 0);
    const std::string both = "(" + std::string(WISP_EXE) + " dataset run " + dir.string() +
                             " --threads 1 2>" + (d.path / "a.txt").string() + " & " +
                             std::string(WISP_EXE) + " dataset run " + dir.string() +
                             " --threads 1 2>" + (d.path / "b.txt").string() + "; wait)";
    ASSERT_EQ(std::system(both.c_str()), 0);
    const auto made = [&](const fs::path& log) {
        const std::string text = slurp(log);
        const size_t at = text.rfind("wisp: ");
        return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + 6);
    };
    const int a = made(d.path / "a.txt"), b = made(d.path / "b.txt");
    ASSERT_GE(a, 0) << slurp(d.path / "a.txt");
    ASSERT_GE(b, 0) << slurp(d.path / "b.txt");
    // 8 samples, each made once (without sharing, both made all 8).
    EXPECT_EQ(a + b, 8) << slurp(d.path / "a.txt") << slurp(d.path / "b.txt");
    EXPECT_EQ(run("dataset verify " + dir.string()), 0);
    ASSERT_EQ(run("dataset plan " + kSpec.string() + " -o " + whole.string()), 0);
    ASSERT_EQ(run("dataset run " + whole.string()), 0);
    EXPECT_EQ(tree(dir / "samples"), tree(whole / "samples"));
}

// A head no sample could load fails the plan, naming its [[head]] line, before any sample
// (or a Slurm array of them) is made: a missing file, an endless one, a mesh without the
// scalp group the head names.
TEST(DatasetCli, PlanLoadsEveryHeadItCanDraw) {
    Dir d;
    const fs::path tri = d.path / "tri.obj", err = d.path / "err.txt";
    std::ofstream(tri) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::pair<std::string, std::string> heads[] = {
        {"obj = \"" + (d.path / "none.obj").string() + "\"", "none.obj: cannot open"},
        {"obj = \"/dev/zero\"", "/dev/zero: byte 0 is a NUL byte"},
        {"obj = \"" + tri.string() + "\"\nscalp = { method = \"group\", group = \"top\" }",
         "no face group or material named 'top'"},
    };
    for (const auto& [fields, says] : heads) {
        const fs::path spec = d.path / "spec.toml", dir = d.path / "ds";
        std::ofstream(spec) << "samples = 2\n[[head]]\nname = \"mine\"\n" << fields << "\n";
        EXPECT_EQ(run("dataset plan " + spec.string() + " -o " + dir.string(), err), 1) << fields;
        const std::string said = slurp(err);
        EXPECT_NE(said.find(spec.string() + ":2: head 'mine'"), std::string::npos) << said;
        EXPECT_NE(said.find(says), std::string::npos) << said;
        EXPECT_FALSE(fs::exists(dir / "dataset.json"));
    }
}

// A planned dataset carries what its samples read (the base style file, the head mesh a
// [[head]] names, the style's map image, by the paths the spec and the style give relative to
// themselves): moved elsewhere with the originals gone, it runs and makes the bytes it makes
// where it was planned, and a sample's style names its files relative to itself.
TEST(DatasetCli, APlannedDatasetMovesWhole) {
    Dir d;
    const fs::path project = d.path / "project";
    for (const char* sub : {"specs", "styles", "heads", "maps"})
        fs::create_directories(project / sub);
    fs::copy_file(fs::path(WISP_SOURCE_DIR) /
                      "../shared/data/heads/makehuman/"
                      "makehuman_hm08_head_neck_shoulders.obj",
                  project / "heads" / "mh.obj");
    // A 4×4 grey TGA (uncompressed, 8 bits): a map image without an image library.
    std::string tga(18, '\0');
    tga[2] = 3;
    tga[12] = tga[14] = 4;
    tga[16] = 8;
    for (int i = 0; i < 16; ++i)
        tga += static_cast<char>(64 + 12 * i);
    std::ofstream(project / "maps" / "density.tga", std::ios::binary) << tga;
    std::ofstream(project / "styles" / "mine.toml")
        << "[roots]\nwisps = 100\nstrands = 800\n[maps]\n"
           "density = { image = \"../maps/density.tga\" }\n";
    std::ofstream(project / "specs" / "spec.toml")
        << "samples = 2\nseed = 5\n[[base]]\nstyle = \"../styles/mine.toml\"\n"
           "[[head]]\nname = \"mh\"\nobj = \"../heads/mh.obj\"\nscale = 10\n"
           "scalp = { method = \"hairline\" }\n"
           "[output]\nhair = [\"hair\"]\nsize = [32, 32]\n";
    const fs::path planned = d.path / "planned", err = d.path / "err.txt";
    ASSERT_EQ(run("dataset plan " + (project / "specs" / "spec.toml").string() + " -o " +
                      planned.string(),
                  err),
              0)
        << slurp(err);
    EXPECT_TRUE(fs::exists(planned / "inputs" / "heads" / "mh.obj"));
    EXPECT_TRUE(fs::exists(planned / "inputs" / "maps" / "density.tga"));
    EXPECT_TRUE(fs::exists(planned / "inputs" / "styles" / "mine.toml"));
    // Made where it was planned, and moved elsewhere with the project gone.
    const fs::path here = d.path / "here";
    fs::copy(planned, here, fs::copy_options::recursive);
    ASSERT_EQ(run("dataset run " + here.string(), err), 0) << slurp(err);
    const fs::path moved = d.path / "elsewhere" / "ds";
    fs::create_directories(moved.parent_path());
    fs::rename(planned, moved);
    fs::remove_all(project);
    ASSERT_EQ(run("dataset run " + moved.string(), err), 0) << slurp(err);
    EXPECT_EQ(tree(moved / "samples"), tree(here / "samples"));
    const std::string style = slurp(moved / "samples" / "000000" / "style.toml");
    EXPECT_NE(style.find("\"../../inputs/heads/mh.obj\""), std::string::npos) << style;
    EXPECT_EQ(style.find(d.path.string()), std::string::npos) << style;
    const fs::path again = d.path / "again.hair";
    ASSERT_EQ(run("generate " + (moved / "samples" / "000000" / "style.toml").string() + " -q -o " +
                      again.string(),
                  err),
              0)
        << slurp(err);
    EXPECT_TRUE(slurp(again) == slurp(moved / "samples" / "000000" / "hair.hair"));
}

// Every map the spec can ask for is written per camera, one file each, and an unknown name
// is refused with the names there are.
TEST(DatasetCli, EveryMapIsAnOption) {
    Dir d;
    const fs::path spec = d.path / "spec.toml", dir = d.path / "ds", err = d.path / "err.txt";
    const char* maps =
        "\"picture\", \"orientation\", \"mask\", \"depth\", \"strand\", "
        "\"confidence\", \"matte\", \"strand_id\", \"depth_hairstep\"";
    std::ofstream(spec) << "samples = 1\n[[base]]\npreset = \"short\"\n[vary]\n"
                           "\"roots.strands\" = { choice = [1500] }\n"
                           "\"roots.wisps\" = { choice = [150] }\n"
                           "[output]\nsize = [48, 40]\nvolume = [16, 24, 16]\n"
                           "scalp_texture = [32, 8]\nmaps = ["
                        << maps << "]\n";
    ASSERT_EQ(run("dataset plan " + spec.string() + " -o " + dir.string(), err), 0) << slurp(err);
    ASSERT_EQ(run("dataset run " + dir.string(), err), 0) << slurp(err);
    const fs::path s = dir / "samples" / "000000";
    for (const char* f :
         {"cam0.png", "cam0_orientation.png", "cam0_mask.png", "cam0_depth.npy", "cam0_strand.png",
          "cam0_confidence.npy", "cam0_matte.png", "cam0_strand_id.npy", "cam0_depth_hairstep.npy"})
        EXPECT_TRUE(fs::exists(s / f)) << f;
    // The volume: occupancy and orientation, z-major, and its box.
    const std::string volume = slurp(s / "volume.npz");
    for (const char* part : {"occupancy.npy", "orientation.npy", "box.npy",
                             "'shape': (16, 24, 16, 3)", "'shape': (16, 24, 16)"})
        EXPECT_NE(volume.find(part), std::string::npos) << part;
    const std::string scalp = slurp(s / "scalp.npz");
    for (const char* part : {"mask.npy", "strand.npy", "offsets.npy", "roots.npy", "normals.npy",
                             "'shape': (32, 32, 8, 3)"})
        EXPECT_NE(scalp.find(part), std::string::npos) << part;
    // The arrays' headers: the picture's shape, as float32 or int32.
    EXPECT_NE(slurp(s / "cam0_strand_id.npy").find("'descr': '<i4'"), std::string::npos);
    EXPECT_NE(slurp(s / "cam0_confidence.npy").find("'shape': (40, 48)"), std::string::npos);
    // Only what was asked for: a spec with one map writes that one.
    std::ofstream(spec) << "samples = 1\n[[base]]\npreset = \"short\"\n[vary]\n"
                           "\"roots.strands\" = { choice = [1500] }\n"
                           "\"roots.wisps\" = { choice = [150] }\n"
                           "[output]\nsize = [48, 40]\nmaps = [\"strand\"]\n";
    const fs::path one = d.path / "one";
    ASSERT_EQ(run("dataset plan " + spec.string() + " -o " + one.string(), err), 0) << slurp(err);
    ASSERT_EQ(run("dataset run " + one.string(), err), 0) << slurp(err);
    EXPECT_TRUE(fs::exists(one / "samples" / "000000" / "cam0_strand.png"));
    EXPECT_FALSE(fs::exists(one / "samples" / "000000" / "cam0.png"));
    EXPECT_FALSE(fs::exists(one / "samples" / "000000" / "cam0_mask.png"));
    std::ofstream(spec) << "samples = 1\n[output]\nvolume = [512, 512, 512]\n";
    EXPECT_EQ(run("dataset plan " + spec.string() + " -o " + (d.path / "big").string(), err), 1);
    EXPECT_NE(slurp(err).find("134217728 voxels: at most 16777216"), std::string::npos)
        << slurp(err);
    std::ofstream(spec) << "samples = 1\n[output]\nmaps = [\"normals\"]\n";
    EXPECT_EQ(run("dataset plan " + spec.string() + " -o " + (d.path / "bad").string(), err), 1);
    EXPECT_NE(slurp(err).find("unknown map 'normals' (picture, orientation, mask, depth, strand, "
                              "confidence, matte, strand_id, depth_hairstep)"),
              std::string::npos)
        << slurp(err);
}

// `wisp compare` as a user runs it: identical files score 1, a file against another seed of the
// style less, --json has the same numbers, and a missing file is an error that names it.
TEST(DatasetCli, CompareTwoHairFiles) {
    Dir d;
    const fs::path a = d.path / "a.hair", b = d.path / "b.hair", out = d.path / "out.txt";
    ASSERT_EQ(run("generate --preset short --strands 2000 --wisps 200 -q -o " + a.string()), 0);
    ASSERT_EQ(
        run("generate --preset short --strands 2000 --wisps 200 --seed 9 -q -o " + b.string()), 0);
    ASSERT_EQ(run("compare " + a.string() + " " + a.string() + " --size 64", out), 0);
    EXPECT_NE(slurp(out).find("2 mm, 20°: 1.000 / 1.000 / 1.000"), std::string::npos) << slurp(out);
    EXPECT_NE(slurp(out).find("silhouette IoU 1.0000"), std::string::npos) << slurp(out);
    ASSERT_EQ(run("compare " + a.string() + " " + b.string() + " --size 64 --json", out), 0);
    const std::string json = slurp(out);
    EXPECT_NE(json.find("\"occupancy_iou\""), std::string::npos) << json;
    EXPECT_EQ(json.find("\"f1\": 1.0"), std::string::npos) << json;
    EXPECT_EQ(run("compare " + a.string() + " " + (d.path / "none.hair").string(), out), 1);
    EXPECT_NE(slurp(out).find("none.hair"), std::string::npos) << slurp(out);
    EXPECT_EQ(run("compare " + a.string() + " " + b.string() + " --views sideways", out), 2);
    EXPECT_NE(slurp(out).find("unknown view 'sideways'"), std::string::npos) << slurp(out);
}

}  // namespace
