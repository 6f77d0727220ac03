// Issue target: generating 100,000 strands of 32 control points with 2,000 wisps on the
// built-in head in under 0.25 s with 2 threads. Run: build/release/bin/wisp_bench
#include <benchmark/benchmark.h>

#include "bench_common.hpp"
#include "core/parallel.hpp"
#include "groom/generate.hpp"

namespace wisp {
namespace {

void BM_Generate100k(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    const Style style = bench_style();
    const Head& head = bench_head();
    size_t points = 0;
    for (auto _ : state) {
        GenerateResult r = generate(style, head);
        points = r.hair.point_count();
        benchmark::DoNotOptimize(r.hair.points.data());
    }
    state.counters["points"] = static_cast<double>(points);
    state.counters["strands/s"] = benchmark::Counter(static_cast<double>(style.strands),
                                                     benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Generate100k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The stages alone, to see where the time goes.
void BM_Stage(benchmark::State& state) {
    const ThreadLimit limit(2);
    const Style style = bench_style();
    const Head& head = bench_head();
    const Roots roots = grow_roots(style, head);
    const Masters masters = synthesize_masters(style, head, roots);
    for (auto _ : state) {
        switch (state.range(0)) {
            case 0:
                benchmark::DoNotOptimize(grow_roots(style, head).members.data());
                break;
            case 1:
                benchmark::DoNotOptimize(synthesize_masters(style, head, roots).control.data());
                break;
            case 2:
                benchmark::DoNotOptimize(grow_members(style, masters, roots).points.data());
                break;
        }
    }
    state.SetLabel(state.range(0) == 0 ? "roots" : state.range(0) == 1 ? "masters" : "members");
}
BENCHMARK(BM_Stage)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BuiltinHead(benchmark::State& state) {
    for (auto _ : state)
        benchmark::DoNotOptimize(load_head(HeadSpec{}).mesh->vertices.data());
}
BENCHMARK(BM_BuiltinHead)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace wisp
