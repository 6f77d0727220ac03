#pragma once
// Planning and running a dataset (docs/dataset.md). A dataset folder holds
//
//   dataset.json      the run's parameters: samples, seed, the spec's folder, tool version
//   spec.toml         the spec, copied at plan time (the run reads this copy)
//   inputs/           the files the samples read, copied at plan time (the spec's folder is
//                     one of its folders): the dataset moves whole
//   manifest.jsonl    one JSON line per sample: index, seed, base, head, drawn values, hash
//   samples/NNNNNN/   one finished sample (see write_sample), complete.json last
//   samples/NNNNNN.failed  why sample N failed (removed when a later run makes it)
//
// Sample k is a pure function of (spec, k): its files are byte-identical whatever the shard
// layout, job count or thread count, and a run skips finished samples (resume).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/hair.hpp"
#include "dataset/spec.hpp"
#include "geometry/mesh.hpp"
#include "groom/style.hpp"
#include "render/camera.hpp"
#include "render/render.hpp"

namespace wisp {

inline constexpr const char* kDatasetVersion = "0.1.0";

// What sample k draws.
struct SampleDraw {
    uint64_t index = 0;
    uint64_t seed = 0;  // the sample's own seed: every draw below derives from it
    size_t base = 0, head = 0;
    Style style;                       // the base, the head's fields and the drawn values applied
    nlohmann::json values;             // style path -> drawn value, in the spec's order
    std::string values_toml;           // "path = value" lines: what the hash covers
    uint64_t hash = 0;                 // FNV-1a of values_toml, base and head names
    std::vector<double> camera_draws;  // 3 uniform [-1, 1) draws per camera (az, el, dist)
    // The [render] rules' draws, (name, inline TOML value), in the spec's order; also in
    // `values` and `values_toml` as "render.NAME".
    std::vector<std::pair<std::string, std::string>> render_values;
};

// Draws sample k. Throws wisp::Error naming the sample and the rule if a drawn value cannot
// be set (a choice the style's other fields refuse).
SampleDraw draw_sample(const DatasetSpec& spec, uint64_t k);

// The manifest line of a draw.
nlohmann::json manifest_entry(const DatasetSpec& spec, const SampleDraw& draw);

// The picture's options for a draw: the renderer's defaults with the [render] rules' values
// applied (lights turned and scaled, the key's colour temperature, the background, the
// strands' brightness variation, the shading model).
RenderOptions sample_render_options(const SampleDraw& draw);

// The camera of spec.cameras[c] for a sample whose hair and head are given.
Camera sample_camera(const DatasetSpec& spec, const SampleDraw& draw, size_t c, const Hair& hair,
                     const Mesh& head);

// The sample folder's name: k zero-padded to max(6, digits of samples − 1).
std::string sample_name(uint64_t samples, uint64_t k);

// Generates sample k and publishes it as `folder` atomically: every file is written into a
// temporary folder beside it, complete.json (each file's size and CRC-32) last, and the
// folder renamed into place. Files:
//   style.toml            the resolved style: `wisp generate style.toml` makes the same hair
//   hair.<ext>            in each format of spec.output.hair
//   meta.json             index, seeds, base, head, drawn values, counts, version (no times)
//   cameras.json          every camera's intrinsics and extrinsics
//   cameras.npz           the same as arrays: K #C×3×3, world_to_camera #C×4×4 (float64),
//                         image_size #C×2 (int32 width, height), fov_y_degrees #C
//   cam<c>.png, cam<c>_orientation.png, …  per camera, the maps of spec.output.maps
//                         (output_map_table() names them; dataset/targets.hpp says what each holds)
// `times`, if given, receives the stages' wall times in ms (for the run's log). Returns
// false, having made nothing, when another live run on this host holds the sample's claim
// (`.NNNNNN.claim-HOST`, created exclusively while a run makes the sample) or has finished
// the sample since.
bool write_sample(const DatasetSpec& spec, uint64_t k, const std::filesystem::path& folder,
                  std::vector<std::pair<std::string, double>>* times = nullptr);

// `wisp dataset plan`: checks the spec, draws every sample, writes dataset.json, spec.toml
// and manifest.jsonl into `dir` (created; a dir already planned from another spec is an
// error, the same spec again is fine). Returns the number of samples.
uint64_t plan_dataset(const std::filesystem::path& spec_path, const std::filesystem::path& dir);

// Reads a planned dataset's spec (its copy in `dir`).
DatasetSpec load_planned_spec(const std::filesystem::path& dir);

// Which samples a run takes: task `index` of `count` takes k ≡ index (mod count).
struct Slice {
    uint64_t index = 0, count = 1;
};

struct RunOptions {
    Slice slice;
    int jobs = 1;  // samples made at once
    // A finished sample is made again when a file it lists is missing or of another size;
    // with verify, also when a file's CRC-32 differs (which reads every finished file).
    bool verify = false;
    // Told after each sample of the slice (done so far, of total, whether it was skipped).
    std::function<void(uint64_t done, uint64_t total, uint64_t k, bool skipped)> on_sample;
    // Told each made sample's stage times (the run's log; never written into the sample).
    std::function<void(uint64_t k, const std::vector<std::pair<std::string, double>>&)> on_times;
    // Told each failure.
    std::function<void(uint64_t k, const std::string& why)> on_failure;
};

struct RunSummary {
    uint64_t made = 0, skipped = 0, failed = 0;
    uint64_t remade = 0;     // of made: finished before, but found damaged
    uint64_t elsewhere = 0;  // left to another run on this host that was making them
};

// `wisp dataset run`: makes the slice's unfinished samples.
RunSummary run_dataset(const std::filesystem::path& dir, const RunOptions& options);

struct DatasetStatus {
    uint64_t samples = 0, done = 0, failed = 0, pending = 0, corrupt = 0;
    std::vector<uint64_t> missing;      // not done (failed, pending or corrupt), ascending
    std::vector<std::string> problems;  // one line per corrupt or failed sample
};

// `wisp dataset status` (and `verify` with `checksums`: every file's size and CRC-32 checked
// against complete.json).
DatasetStatus dataset_status(const std::filesystem::path& dir, bool checksums);

// "0-3,7,9-12": indices as ranges, for resubmitting an array.
std::string index_ranges(const std::vector<uint64_t>& indices);

struct SlurmOptions {
    int tasks = 1;
    int throttle = 0;       // %K: at most K tasks at once (0: no limit)
    std::string partition;  // -p (empty: the cluster's default)
    std::string time = "";  // --time (empty: the partition's default)
    std::string wisp;       // the wisp executable (absolute)
    int cpus_per_task = 0;  // -c (0: the cluster's default)
};

// The sbatch script of a job array of options.tasks tasks, task i running
// `wisp dataset run DIR --task-id $SLURM_ARRAY_TASK_ID --tasks N`.
std::string slurm_script(const std::filesystem::path& dir, const SlurmOptions& options);

}  // namespace wisp

namespace wisp {

// `wisp dataset pack`: the done samples as WebDataset-style tar shards (POSIX ustar, written
// with libarchive), `samples_per_shard` samples each, in index order, into
// DIR/pack/shard-NNNNNN.tar (atomic). A sample's files are members "<name>.<file>"
// ("000007.cam0.png"), in name order, so WebDataset groups them by the key "000007";
// complete.json is left out. Every member has mode 0644, owner 0 and time 0, so a shard's
// bytes depend only on its samples. Returns the number of shards written.
size_t pack_dataset(const std::filesystem::path& dir, uint64_t samples_per_shard);

}  // namespace wisp
