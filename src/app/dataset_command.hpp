#pragma once
// `wisp dataset plan | run | status | verify | slurm` (docs/dataset.md), kept beside cli.cpp's
// commands; the work is the dataset library's (dataset/dataset.hpp).
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace wisp {

struct DatasetCommands {
    CLI::App* dataset = nullptr;
    CLI::App *plan = nullptr, *run = nullptr, *status = nullptr, *verify = nullptr,
             *slurm = nullptr, *pack = nullptr;
    std::string spec, dir;
    std::string shard;     // "i/N"
    int64_t task_id = -1;  // --task-id K
    int64_t tasks = 0;     // --tasks N
    int jobs = 1, threads = 0;
    std::string times;  // --times FILE: the run's per-sample stage times as JSON lines
    bool quiet = false;
    bool verify_done = false;  // run --verify
    // slurm
    int throttle = 0, cpus = 0;
    std::string partition, time;
    bool submit = false;
    // pack
    int64_t per_shard = 1000;
};

// Adds `dataset` and its subcommands to `app`, their options bound to `args`.
void add_dataset_commands(CLI::App& app, DatasetCommands& args);

// Runs the dataset subcommand given and returns its exit code; nullopt if none was. Throws
// wisp::Error on bad input and CLI::ValidationError on bad usage, as the other commands do.
std::optional<int> run_dataset_commands(const DatasetCommands& args);

}  // namespace wisp
