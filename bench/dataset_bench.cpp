// `wisp dataset`'s speed (issue 19): one sample of the issue's workload, a 20,000-strand
// sample of the `default` preset (solve.stiffness drawn in [0.5, 2]) with 2 pictures at 512²
// (front and three-quarter) and every map (orientation, mask, depth), `.hair` out, written
// and published as `wisp dataset run` does (write_sample). The counter samples_per_min is the
// figure docs/dataset.md reports. BM_DatasetBaseline does the plain work of `wisp generate
// style.toml -o x.hair --png --views front,three-quarter --size 512x512` on the same styles
// (generate, two renders, the hair file and PNGs written) without the maps, so that the two
// give the dataset machinery's overhead per sample. BM_DatasetSamplePictures is the sample
// with pictures only (`maps = ["picture"]`): the same work as the baseline, so the two give
// the machinery's own overhead (the issue's goal: under 5%), and BM_DatasetSample against it
// what the orientation, mask and depth maps cost. All load the head once, as a run does.
// Arg: thread count.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "core/image.hpp"
#include "core/parallel.hpp"
#include "dataset/dataset.hpp"
#include "dataset/spec.hpp"
#include "groom/head.hpp"
#include "io/hair_io.hpp"
#include "render/render.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSpec = R"(
samples = 1000000
seed = 7
[[base]]
preset = "default"
[vary]
"roots.strands" = { choice = [20000] }
"solve.stiffness" = { uniform = [0.5, 2.0] }
[output]
hair = ["hair"]
size = [512, 512]
[[camera]]
view = "front"
[[camera]]
view = "three-quarter"
)";

const DatasetSpec& bench_spec() {
    static const DatasetSpec spec = parse_dataset_spec(kSpec, "dataset_bench", fs::current_path());
    return spec;
}

const DatasetSpec& pictures_spec() {
    std::string text = kSpec;
    const std::string size = "size = [512, 512]\n";
    text.insert(text.find(size) + size.size(), "maps = [\"picture\"]\n");
    static const DatasetSpec spec = parse_dataset_spec(text, "dataset_bench", fs::current_path());
    return spec;
}

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("wisp_dataset_bench_" + std::to_string(getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

// Samples per minute of wall time over the timed iterations (the stages run on TBB's
// workers: the benchmark thread's CPU time says little).
void report(benchmark::State& state, double seconds) {
    state.counters["samples_per_min"] = 60.0 * static_cast<double>(state.iterations()) / seconds;
}

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

void run_samples(benchmark::State& state, const DatasetSpec& spec) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    TempDir dir;
    write_sample(spec, 0, dir.path / "warm");  // the head, loaded once per run
    uint64_t k = 1;
    double seconds = 0;
    for (auto _ : state) {
        const fs::path folder = dir.path / sample_name(spec.samples, k);
        const Clock::time_point start = Clock::now();
        write_sample(spec, k++, folder);
        seconds += since(start);
        state.PauseTiming();
        fs::remove_all(folder);
        state.ResumeTiming();
    }
    report(state, seconds);
}

void BM_DatasetSample(benchmark::State& state) {
    run_samples(state, bench_spec());
}
BENCHMARK(BM_DatasetSample)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DatasetSamplePictures(benchmark::State& state) {
    run_samples(state, pictures_spec());
}
BENCHMARK(BM_DatasetSamplePictures)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DatasetBaseline(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    const DatasetSpec& spec = bench_spec();
    TempDir dir;
    const Head head = load_head(draw_sample(spec, 0).style.head);
    uint64_t k = 1;
    const Clock::time_point start = Clock::now();
    for (auto _ : state) {
        const Style style = draw_sample(spec, k++).style;
        const HairstyleResult r = generate_hairstyle(style, head);
        write_hair(dir.path / "x.hair", r.hair);
        for (const char* view : {"front", "three-quarter"}) {
            RenderOptions options;
            options.width = options.height = 512;
            options.view = view;
            write_png(dir.path / (std::string(view) + ".png"),
                      render(r.hair, head.mesh.get(), options));
        }
    }
    report(state, since(start));
}
BENCHMARK(BM_DatasetBaseline)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace wisp
