#include "app/dataset_command.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "app/progress.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "dataset/dataset.hpp"

extern char** environ;

namespace wisp {

namespace {

bool parse_u64(std::string_view text, uint64_t& out) {
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && ptr == text.data() + text.size() && !text.empty();
}

// The slice a run takes: --shard i/N, --task-id K [--tasks N], or the task index of a job
// array's environment (Slurm, Kubernetes indexed jobs, AWS Batch).
Slice run_slice(const DatasetCommands& a, std::string* from) {
    Slice s;
    if (!a.shard.empty()) {
        if (a.task_id >= 0)
            throw CLI::ValidationError("--shard", "give --shard or --task-id, not both");
        const size_t slash = a.shard.find('/');
        if (slash == std::string::npos || !parse_u64(a.shard.substr(0, slash), s.index) ||
            !parse_u64(a.shard.substr(slash + 1), s.count) || s.count == 0 || s.index >= s.count)
            throw CLI::ValidationError(
                "--shard", "expects i/N with 0 ≤ i < N, got '" + excerpt(a.shard) + "'");
        *from = "--shard";
        return s;
    }
    int64_t index = a.task_id;
    *from = "--task-id";
    if (index < 0)
        for (const char* var :
             {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"})
            if (const char* v = std::getenv(var); v && *v) {
                uint64_t parsed = 0;
                if (!parse_u64(v, parsed)) fail(var, " is '", excerpt(v), "', not a task index");
                index = static_cast<int64_t>(parsed);
                *from = var;
                break;
            }
    if (index < 0) {
        if (a.tasks > 0) throw CLI::ValidationError("--tasks", "needs --task-id");
        *from = "";
        return s;  // the whole dataset
    }
    uint64_t count = static_cast<uint64_t>(a.tasks);
    if (count == 0)
        if (const char* v = std::getenv("SLURM_ARRAY_TASK_COUNT"); v && *v) {
            if (!parse_u64(v, count)) fail("SLURM_ARRAY_TASK_COUNT is '", excerpt(v), "'");
        }
    if (count == 0)
        throw CLI::ValidationError(
            "--tasks", "a task index (" + *from + ") needs the task count: give --tasks N");
    if (static_cast<uint64_t>(index) >= count)
        throw CLI::ValidationError(
            *from, cat("task ", index, " of ", count, ": the index must be below the count"));
    s.index = static_cast<uint64_t>(index);
    s.count = count;
    return s;
}

std::string seconds_text(double s) {
    if (!std::isfinite(s) || s < 0) return "?";
    const long t = std::lround(s);
    if (t < 120) return cat(t, " s");
    if (t < 7200) return cat(t / 60, " min ", t % 60, " s");
    return cat(t / 3600, " h ", (t % 3600) / 60, " min");
}

int run_command(const DatasetCommands& a) {
    std::string from;
    RunOptions options;
    options.slice = run_slice(a, &from);
    options.jobs = a.jobs;
    options.verify = a.verify_done;
    const ThreadLimit limit(a.threads);
    if (!a.quiet && !from.empty())
        std::cerr << "wisp: task " << options.slice.index << " of " << options.slice.count << " ("
                  << from << ")\n";
    std::unique_ptr<Progress> progress;
    uint64_t total = 0;
    const auto start = std::chrono::steady_clock::now();
    uint64_t made = 0;
    options.on_sample = [&](uint64_t done, uint64_t all, uint64_t k, bool skipped) {
        if (!progress)
            progress = std::make_unique<Progress>("sample", static_cast<int>(all), a.quiet);
        total = all;
        made += skipped ? 0 : 1;
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double rate = made > 0 ? made / elapsed : 0;
        std::string what = cat("#", k, skipped ? " done before" : "");
        if (rate > 0)
            what += cat(", ", std::lround(rate * 600) / 10.0, " samples/min, ",
                        seconds_text((all - done) / rate), " left");
        progress->step(static_cast<int>(done), what);
    };
    std::ofstream times;
    if (!a.times.empty()) {
        times.open(a.times, std::ios::app);
        if (!times) fail(a.times, ": cannot append to it");
    }
    options.on_times = [&](uint64_t k, const std::vector<std::pair<std::string, double>>& t) {
        if (!times.is_open()) return;
        nlohmann::json ms = nlohmann::json::object();
        for (const auto& [stage, time] : t)
            ms[stage] = ms.value(stage, 0.0) + time;  // per camera stages add up
        const nlohmann::json j = {{"index", k}, {"pid", getpid()}, {"ms", ms}};
        times << j.dump() << '\n' << std::flush;
    };
    options.on_failure = [&](uint64_t k, const std::string& why) {
        std::cerr << "wisp: error: sample " << k << ": " << excerpt(why, 400) << '\n';
    };
    const RunSummary s = run_dataset(a.dir, options);
    progress.reset();
    if (!a.quiet)
        std::cerr
            << "wisp: " << s.made << " made"
            << (s.remade ? cat(" (", s.remade, " of them damaged before)") : std::string()) << ", "
            << s.skipped << " done before, "
            << (s.elsewhere ? cat(s.elsewhere, " left to another run, ") : std::string())
            << s.failed << " failed of " << total << " in this slice ("
            << seconds_text(
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
            << ")\n";
    return s.failed > 0 ? 1 : 0;
}

int status_command(const DatasetCommands& a, bool verify) {
    const DatasetStatus s = dataset_status(a.dir, verify);
    std::cout << "samples " << s.samples << "\ndone " << s.done << "\npending " << s.pending
              << "\nfailed " << s.failed << '\n';
    if (verify) std::cout << "corrupt " << s.corrupt << '\n';
    if (!s.missing.empty()) std::cout << "missing " << index_ranges(s.missing) << '\n';
    for (const std::string& p : s.problems)
        std::cout << "  " << p << '\n';
    if (s.corrupt > 0)
        std::cerr << "wisp: `wisp dataset run " << a.dir
                  << " --verify` makes the damaged samples again\n";
    if (verify) return s.done == s.samples ? 0 : 1;
    return 0;
}

std::string self_executable() {
    std::error_code ec;
    const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("wisp") : p.string();
}

int slurm_command(const DatasetCommands& a) {
    load_planned_spec(a.dir);  // a planned dataset, before anything is written
    SlurmOptions o;
    o.tasks = static_cast<int>(a.tasks);
    o.throttle = a.throttle;
    o.partition = a.partition;
    o.time = a.time;
    o.cpus_per_task = a.cpus;
    o.wisp = self_executable();
    const std::filesystem::path dir(a.dir);
    std::filesystem::create_directories(dir / "slurm");
    const std::filesystem::path script = dir / "slurm" / "array.sbatch";
    write_file_atomic(script, slurm_script(dir, o));
    std::cerr << "wisp: wrote " << script.string() << '\n';
    if (!a.submit) return 0;
    std::vector<std::string> args = {"sbatch", "--parsable", script.string()};
    std::vector<char*> argv;
    for (std::string& s : args)
        argv.push_back(s.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawnp(&pid, "sbatch", nullptr, nullptr, argv.data(), environ) != 0)
        fail("sbatch: cannot run it (is Slurm's client installed?)");
    int status = 0;
    if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fail("sbatch failed to submit ", script.string());
    return 0;
}

}  // namespace

void add_dataset_commands(CLI::App& app, DatasetCommands& a) {
    a.dataset = app.add_subcommand(
        "dataset",
        "Make synthetic hair datasets: plan, run (locally or as a Slurm job array), "
        "status, verify (docs/dataset.md)");
    a.dataset->require_subcommand(1);
    a.plan = a.dataset->add_subcommand(
        "plan", "Check a dataset spec and write the dataset folder's manifest");
    a.plan->add_option("spec", a.spec, "Dataset spec (TOML)")->required()->check(CLI::ExistingFile);
    a.plan->add_option("-o,--output", a.dir, "Dataset folder")->required();

    a.run = a.dataset->add_subcommand(
        "run", "Make the samples of a slice that are not done yet (a rerun resumes)");
    a.run->add_option("dir", a.dir, "Dataset folder (from `wisp dataset plan`)")->required();
    a.run->add_option("--shard", a.shard, "Make samples k with k % N == i");
    a.run
        ->add_option("--task-id", a.task_id,
                     "Task K of --tasks N (default: $SLURM_ARRAY_TASK_ID, "
                     "$JOB_COMPLETION_INDEX or $AWS_BATCH_JOB_ARRAY_INDEX)")
        ->check(CLI::Range(int64_t(0), int64_t(1) << 40));
    a.run->add_option("--tasks", a.tasks, "Number of tasks (default: $SLURM_ARRAY_TASK_COUNT)")
        ->check(CLI::Range(int64_t(1), int64_t(1) << 40));
    a.run->add_option("--jobs", a.jobs, "Samples made at once")->check(CLI::Range(1, 256));
    a.run->add_option("--threads", a.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    a.run->add_option("--times", a.times, "Append each sample's stage times (JSON lines)");
    a.run->add_flag("--verify", a.verify_done,
                    "Check the CRC-32 of every finished sample's files and make the damaged "
                    "ones again (without it, only a missing file or a changed size is caught)");
    a.run->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");

    a.status = a.dataset->add_subcommand("status", "Count done, pending and failed samples");
    a.status->add_option("dir", a.dir, "Dataset folder")->required();
    a.verify = a.dataset->add_subcommand(
        "verify",
        "Check every done sample's files against its checksums; exit 1 unless all "
        "samples are complete");
    a.verify->add_option("dir", a.dir, "Dataset folder")->required();

    a.slurm = a.dataset->add_subcommand(
        "slurm",
        "Write DIR/slurm/array.sbatch: a job array whose tasks run `wisp dataset run "
        "DIR --task-id $SLURM_ARRAY_TASK_ID`");
    a.slurm->add_option("dir", a.dir, "Dataset folder")->required();
    a.slurm->add_option("--tasks", a.tasks, "Array tasks")
        ->required()
        ->check(CLI::Range(1, 1000000));
    a.slurm->add_option("--throttle", a.throttle, "At most K tasks at once")
        ->check(CLI::Range(0, 1000000));
    a.slurm->add_option("--partition", a.partition, "Slurm partition");
    a.slurm->add_option("--time", a.time, "Time limit per task (sbatch --time)");
    a.slurm->add_option("--cpus-per-task", a.cpus, "CPUs per task")->check(CLI::Range(0, 4096));
    a.slurm->add_flag("--submit", a.submit, "Submit it with sbatch");

    a.pack = a.dataset->add_subcommand(
        "pack", "Write the done samples as WebDataset-style tar shards into DIR/pack");
    a.pack->add_option("dir", a.dir, "Dataset folder")->required();
    a.pack->add_option("--samples-per-shard", a.per_shard, "Samples in each tar")
        ->check(CLI::Range(int64_t(1), int64_t(1) << 40))
        ->capture_default_str();
}

std::optional<int> run_dataset_commands(const DatasetCommands& a) {
    if (!a.dataset || !*a.dataset) return std::nullopt;
    if (*a.plan) {
        const uint64_t n = plan_dataset(a.spec, a.dir);
        std::cerr << "wisp: planned " << n << " samples in " << a.dir << '\n';
        return 0;
    }
    if (*a.run) return run_command(a);
    if (*a.status) return status_command(a, false);
    if (*a.verify) return status_command(a, true);
    if (*a.slurm) return slurm_command(a);
    if (*a.pack) {
        const size_t shards = pack_dataset(a.dir, static_cast<uint64_t>(a.per_shard));
        std::cerr << "wisp: wrote " << shards << " tar shard" << (shards == 1 ? "" : "s") << " in "
                  << (std::filesystem::path(a.dir) / "pack").string() << '\n';
        return 0;
    }
    return 2;
}

}  // namespace wisp
