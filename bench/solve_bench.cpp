// Issue 3 targets: solving 2,000 wisps of 32 joints with collisions on the built-in head in
// under 100 ms with 2 threads, and the whole generate of 100,000 strands under 0.35 s.
#include <benchmark/benchmark.h>

#include "bench_common.hpp"
#include "core/parallel.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

const HeadField& builtin_field() {
    static const HeadField field = build_head_field(bench_style(), bench_head());
    return field;
}

// The solver alone (Algorithm 1 with the styling field), masters re-synthesized outside the
// timing each iteration. Threads, then the field: 0 the default (growth and gravity), 1
// gravity alone (the workload of the figures before the growth field, Fig. 9's).
void BM_Solve2000Wisps(benchmark::State& state) {
    const ThreadLimit limit(static_cast<int>(state.range(0)));
    Style style = bench_style();
    if (state.range(1) == 1) style.solve.field = {FieldTerm{}};
    const Head& head = bench_head();
    const HeadField& field = builtin_field();
    const Roots roots = grow_roots(style, head);
    const Masters fresh = synthesize_masters(style, head, roots);
    const HeadFrame frame = head_frame(*head.scalp);
    Box3 bounds = head.mesh->bounds();
    bounds.lo -= Vec3f::Constant(25.f);
    bounds.hi += Vec3f::Constant(25.f);
    SolveStats stats;
    for (auto _ : state) {
        state.PauseTiming();
        Masters m = fresh;
        state.ResumeTiming();
        const StylingField phi(style.solve.field, frame, GrowthField(style.growth, *head.scalp),
                               bounds, style.solve.cell);
        Grid3<float> density(phi.grid().origin(), phi.grid().cell(), phi.grid().dims());
        SolveInput in;
        in.field = &phi;
        in.head = &field.bridged();
        for (size_t w = 0; w < m.count(); ++w)
            in.wisp_strands.push_back(
                static_cast<int>(roots.wisp_offsets[w + 1] - roots.wisp_offsets[w]));
        in.wisp_radius = roots.wisp_radius;
        in.radius_profile.assign(m.points, 1.f);
        stats = solve_masters(m, in, style.solve, density);
        benchmark::DoNotOptimize(m.outline.data());
    }
    state.counters["joints"] = static_cast<double>(stats.joints);
    state.counters["collision_iterations"] = static_cast<double>(stats.bends);
}
BENCHMARK(BM_Solve2000Wisps)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "gravity"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The whole pipeline (roots → color) for 100,000 strands, with the head's field built once
// per head (as the editor keeps it) and, second, built in the run as the command line does.
void BM_GenerateSolved100k(benchmark::State& state) {
    const ThreadLimit limit(2);
    const Style style = bench_style();
    const Head& head = bench_head();
    const bool cached = state.range(0) == 1;
    for (auto _ : state) {
        HairstyleResult r = generate_hairstyle(style, head, cached ? &builtin_field() : nullptr);
        benchmark::DoNotOptimize(r.hair.points.data());
    }
    state.SetLabel(cached ? "head field cached" : "head field built");
}
BENCHMARK(BM_GenerateSolved100k)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_HeadField(benchmark::State& state) {
    const ThreadLimit limit(2);
    for (auto _ : state) {
        const HeadField f = build_head_field(bench_style(), bench_head());
        benchmark::DoNotOptimize(f.grid().data().data());
    }
}
BENCHMARK(BM_HeadField)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace wisp
