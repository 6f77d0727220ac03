// Issue target: generating 100,000 strands of 32 control points with 2,000 wisps on the
// built-in head in under 0.25 s with 2 threads. Run: build/release/bin/wisp_bench
#include <benchmark/benchmark.h>

#include <optional>
#include "bench_common.hpp"
#include "core/parallel.hpp"

#include "groom/generate.hpp"
#include "groom/roots.hpp"
#include "groom/style_toml.hpp"

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
                benchmark::DoNotOptimize(
                    grow_members(style, *head.scalp, masters, roots).points.data());
                break;
        }
    }
    state.SetLabel(state.range(0) == 0 ? "roots" : state.range(0) == 1 ? "masters" : "members");
}
BENCHMARK(BM_Stage)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The roots stage of a map stroke (issue 16): the default preset with the crown density map
// the editor benchmark paints (arg 0) or the constant map it paints back (arg 1), the scalp's
// surface built once as the editor's stage cache does; with the map-independent proposals
// drawn once too (proposals:1) or not. Arg: threads.
void BM_Roots(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(1)));
    Style style = load_preset("default");
    if (state.range(0) == 0) {
        style.density.kind = ScalarMap::Kind::kProcedural;
        style.density.procedural = "crown";
        style.density.low = 0.6f;
        style.density.high = 1.f;
    }
    const Head head = load_head(style.head);
    const MeshDistance surface = scalp_surface(*head.scalp);
    // grow_roots' parameters.
    RootParams params;
    params.wisps = style.wisps;
    params.strands = style.strands;
    params.seed = style.seed;
    std::optional<RootProposals> proposals;
    if (state.range(2) == 1) proposals.emplace(root_proposals(*head.scalp, params));
    const MapSampler density(style.density, *head.scalp);
    for (auto _ : state)
        benchmark::DoNotOptimize(
            place_roots(*head.scalp, density, params, &surface, proposals ? &*proposals : nullptr)
                .members.data());
    state.SetLabel(state.range(0) == 0 ? "crown" : "constant");
}
BENCHMARK(BM_Roots)
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 1}})
    ->ArgNames({"map", "threads", "proposals"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The masters' details alone (issue 16's critical path beside the solve): the default
// preset's outlines and prototype made once, then synthesize_master_details as the editor
// calls it (frames left to the solve), on 1 thread.
void BM_MasterDetails(benchmark::State& state) {
    const ThreadLimit limit(1);
    const Style style = load_preset("default");
    const Head head = load_head(style.head);
    const Roots roots = grow_roots(style, head);
    Masters masters = master_outlines(style, head, roots);
    const MasterPrototype prototype = master_prototype(style, masters);
    for (auto _ : state) {
        synthesize_master_details(style, prototype, masters, false);
        benchmark::DoNotOptimize(masters.details.data());
    }
    state.counters["masters"] = static_cast<double>(masters.count());
}
BENCHMARK(BM_MasterDetails)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void BM_BuiltinHead(benchmark::State& state) {
    for (auto _ : state)
        benchmark::DoNotOptimize(load_head(HeadSpec{}).mesh->vertices.data());
}
BENCHMARK(BM_BuiltinHead)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace wisp
