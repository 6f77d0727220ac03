// Writing and reading 100,000 strands × 32 points (3.2 M points, the generate benchmarks'
// workload) in each hair format, to and from a file in the system's temporary folder.
// The CPU column is the whole process's (every thread), steadier than wall time on a busy machine.
// Issue 13: the .usda reader within 2× of the .hair reader; issue 15: .usda written in
// < 0.2 s and read in < 0.4 s on 2 cores.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "bench_common.hpp"
#include "core/parallel.hpp"
#include "groom/generate.hpp"
#include "io/hair_io.hpp"
#include "io/usda.hpp"

namespace wisp {
namespace {

const Hair& bench_hair() {
    static const Hair hair = [] {
        const ThreadLimit limit(2);
        return generate(bench_style(), bench_head()).hair;
    }();
    return hair;
}

std::filesystem::path bench_file(const char* extension) {
    return std::filesystem::temp_directory_path() /
           ("wisp_io_bench_" + std::to_string(::getpid()) + "." + extension);
}

// .data is written as USC-HairSalon has it (100 points per strand, so it holds 10 M points);
// .npz resamples to 32 points and is written only.
const char* const kFormats[] = {"hair", "usda", "obj", "ply", "data", "npz"};

void BM_Write(benchmark::State& state) {
    const ThreadLimit limit(2);
    const Hair& hair = bench_hair();
    const std::filesystem::path path = bench_file(kFormats[state.range(0)]);
    for (auto _ : state)
        write_hair(path, hair);
    state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
    state.SetLabel(kFormats[state.range(0)]);
    std::filesystem::remove(path);
}
BENCHMARK(BM_Write)
    ->DenseRange(0, 5)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Read(benchmark::State& state) {
    const ThreadLimit limit(2);
    const std::filesystem::path path = bench_file(kFormats[state.range(0)]);
    write_hair(path, bench_hair());
    for (auto _ : state) {
        Hair hair = read_hair(path);
        benchmark::DoNotOptimize(hair.points.data());
    }
    state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
    state.SetLabel(kFormats[state.range(0)]);
    std::filesystem::remove(path);
}
BENCHMARK(BM_Read)
    ->DenseRange(0, 4)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The .usda text alone, without the disk: formatting (encode_usda) and parsing (parse_usda,
// then the conversion to strands), to tell the CPU's share of BM_Write/BM_Read from the disk's.
void BM_UsdaEncode(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    const Hair& hair = bench_hair();
    size_t bytes = 0;
    for (auto _ : state) {
        std::string text = encode_usda(hair);
        bytes = text.size();
        benchmark::DoNotOptimize(text.data());
    }
    state.counters["MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_UsdaEncode)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_UsdaParse(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    const std::string text = encode_usda(bench_hair());
    for (auto _ : state) {
        Hair hair = hair_from_usda(parse_usda(text, "bench.usda"), "bench.usda");
        benchmark::DoNotOptimize(hair.points.data());
    }
    state.counters["MB"] = static_cast<double>(text.size()) / 1e6;
}
BENCHMARK(BM_UsdaParse)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The animation writers, 3 frames of 100k × 32 (issue 15: 30 frames in < 10 s in all, the
// simulation included): value clips (a layer per frame, the manifest and the top-level
// layer) and the single time-sampled layer. The "ms/frame" counter is wall time per frame.
void BM_AnimationWrite(benchmark::State& state) {
    const ThreadLimit limit(2);
    const Hair& hair = bench_hair();
    constexpr size_t kFrames = 3;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("wisp_anim_bench_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const bool clips = state.range(0) == 0;
    double seconds = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        if (clips) {
            UsdaClipWriter writer(dir / "anim.usda", hair, 24.0, kFrames);
            for (size_t f = 0; f < kFrames; ++f)
                writer.add(hair);
            writer.finish();
        } else {
            UsdaAnimationWriter writer(dir / "anim.usda", hair, 24.0, kFrames);
            for (size_t f = 0; f < kFrames; ++f)
                writer.add(hair);
            writer.finish();
        }
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    state.counters["ms/frame"] = 1e3 * seconds / static_cast<double>(state.iterations() * kFrames);
    state.SetLabel(clips ? "value clips" : "single layer");
    std::filesystem::remove_all(dir);
}
BENCHMARK(BM_AnimationWrite)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace wisp
