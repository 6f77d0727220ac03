// The renderer on the scene: 100,000 strands of 32 control points on the built-in
// head, 1024×1024, with shadows. Target: under 1 s with 2 threads. The hair is synthesized
// (tests/render/synthetic_hair.hpp: long strands falling from a spherical cap) so that the
// figure does not move when the groom changes. Arg: thread count.
#include <benchmark/benchmark.h>

#include "../tests/render/synthetic_hair.hpp"
#include "core/parallel.hpp"
#include "geometry/builtin_head.hpp"
#include "render/render.hpp"

namespace {

const wisp::Hair& bench_hair() {
    static const wisp::Hair hair = [] {
        wisp::test::SyntheticHairSpec spec;
        spec.strands = 100000;
        spec.points = 32;
        return wisp::test::synthetic_hair(spec);
    }();
    return hair;
}

const wisp::Mesh& bench_head() {
    static const wisp::Mesh head = wisp::builtin_head_mesh();
    return head;
}

void run(benchmark::State& state, bool shadows, const char* view, bool rim = true,
         wisp::RenderOptions::Shading shading = wisp::RenderOptions{}.shading) {
    const wisp::Hair& hair = bench_hair();
    const wisp::Mesh& head = bench_head();
    wisp::ThreadLimit limit(static_cast<int>(state.range(0)));
    wisp::RenderOptions options;
    options.width = options.height = 1024;
    options.shadows = shadows;
    options.view = view;
    if (!rim) options.rim.color = wisp::Vec3f::Zero();
    options.shading = shading;
    wisp::RenderStats stats;
    std::vector<double> stage_ms;
    for (auto _ : state) {
        wisp::RgbImage image = wisp::render(hair, &head, options, &stats);
        benchmark::DoNotOptimize(image.rgb.data());
        stage_ms.resize(stats.stages.size(), 0.0);
        for (size_t i = 0; i < stats.stages.size(); ++i)
            stage_ms[i] += stats.stages[i].second;
    }
    for (size_t i = 0; i < stats.stages.size(); ++i)
        state.counters[stats.stages[i].first + "_ms"] =
            stage_ms[i] / static_cast<double>(state.iterations());
    state.counters["pieces"] = static_cast<double>(stats.pieces);
    state.counters["hidden_pieces"] = static_cast<double>(stats.hidden_pieces);
    state.counters["fragments"] = static_cast<double>(stats.fragments);
}

void BM_Render100kShadows(benchmark::State& state) {
    run(state, true, "three-quarter");
}
// Without the rim light (and its shadow maps): what the rim costs.
void BM_Render100kShadowsNoRim(benchmark::State& state) {
    run(state, true, "three-quarter", false);
}
// The fibre model (R, TT, TRT and dual scattering from tables) in place of the lobes.
void BM_Render100kFiber(benchmark::State& state) {
    run(state, true, "three-quarter", true, wisp::RenderOptions::Shading::kFiber);
}
void BM_Render100kNoShadows(benchmark::State& state) {
    run(state, false, "three-quarter");
}
void BM_Render100kBack(benchmark::State& state) {
    run(state, true, "back");
}

}  // namespace

BENCHMARK(BM_Render100kShadows)->Arg(2)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Render100kShadowsNoRim)->Arg(2)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Render100kFiber)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Render100kNoShadows)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Render100kBack)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
