// Issue 16's latency table, server side: the time from a changed value to the bytes the
// editor sends (StageCache::set + update + encode), on the built-in head with 2 threads.
//   change                         strands   goal
//   colour                          20,000   < 10 ms
//   κ (solve onwards): masters      (2,000)  < 20 ms
//   κ: preview                      20,000   < 60 ms
//   a map stroke (roots onwards)    20,000   < 100 ms
//   any change (roots onwards)     100,000   < 400 ms
// Each iteration flips the value between two settings, so every one re-runs its stages.
// Run: build/release/bin/wisp_bench --benchmark_filter=Edit
#include <benchmark/benchmark.h>

#include "bench_common.hpp"
#include "core/parallel.hpp"
#include "edit/stage_cache.hpp"
#include "edit/wire.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

// The default preset (the style an editor session starts from) at `strands`.
Style edit_style(int strands) {
    Style style = load_preset("default");
    style.strands = strands;
    return style;
}

enum class Answer { kStrands, kMasters };

void run(benchmark::State& state, int strands, const char* path, const char* a, const char* b,
         Answer answer) {
    const ThreadLimit limit(2);
    StageCache cache(edit_style(strands));
    cache.update();
    bool flip = false;
    size_t bytes = 0;
    for (auto _ : state) {
        cache.set(path, (flip = !flip) ? a : b);
        const std::string out = answer == Answer::kMasters
                                    ? encode_masters(cache.update_masters())
                                    : encode_strands(cache.update().hair, size_t(strands));
        bytes = out.size();
        benchmark::DoNotOptimize(out.data());
        if (answer == Answer::kMasters) cache.update();  // the preview follows, untimed here
    }
    state.counters["bytes"] = static_cast<double>(bytes);
}

void BM_EditColor20k(benchmark::State& state) {
    run(state, 20000, "color.wisp_hue", "3", "1.5", Answer::kStrands);
}
void BM_EditStiffnessMasters(benchmark::State& state) {
    run(state, 20000, "solve.stiffness", "0.8", "0.6", Answer::kMasters);
}
void BM_EditStiffnessPreview20k(benchmark::State& state) {
    run(state, 20000, "solve.stiffness", "0.8", "0.6", Answer::kStrands);
}
void BM_EditMapStroke20k(benchmark::State& state) {
    run(state, 20000, "maps.density", "{ procedural = \"crown\", low = 0.6, high = 1 }", "1",
        Answer::kStrands);
}
void BM_EditAnyChange100k(benchmark::State& state) {
    run(state, 100000, "maps.density", "{ procedural = \"crown\", low = 0.6, high = 1 }", "1",
        Answer::kStrands);
}
BENCHMARK(BM_EditColor20k)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EditStiffnessMasters)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EditStiffnessPreview20k)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EditMapStroke20k)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EditAnyChange100k)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace wisp
