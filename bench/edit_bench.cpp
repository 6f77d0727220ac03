// Issue 16's latency table, server side: the time from a changed value to the bytes the
// editor sends, on the stage cache as the server drives it (src/edit/server.cpp), for the
// default preset (100,000 strands, 2,000 wisps) on the built-in head with 2 threads.
//   change                         sent                      goal
//   colour                          20,000 strands           < 10 ms
//   κ (solve onwards): masters      667 of 2,000 masters     < 20 ms (a coarse solve while
//                                   (all 2,000, exact: the    the slider moves)
//                                   MastersExact row)
//   κ: preview                      20,000 strands           < 60 ms
//   a map stroke (roots onwards)    20,000 strands           < 100 ms
//   any change (roots onwards)     100,000 strands           < 400 ms
// A moving slider asks for 20,000 strands (GET /api/hair?strands=20000: hair_bytes, which
// grows or colours only the strands it sends); its release asks for all of them. Each
// iteration flips the value between two settings, so every one re-runs its stages, and
// then, untimed, brings the whole hair up to date, as the release that follows a drag does.
// Time is wall time; CPU is the process's CPU time over all threads (the work done, which
// a loaded machine does not inflate). The rows with progress:1 report it as the server does
// (a ProgressEvents task: each stage, and the solve's layers and the members' wisps inside
// them), to show that costs nothing measurable against progress:0.
// Counters roots_ms … encode_ms: each stage's wall time per iteration, as the stage cache
// timed it (field_ms is the solve's styling field, inside solve_ms; members_ms and color_ms
// are a preview's subset where only that was grown, after the solve: a preview's members
// that grew beside the solve, band by band as its layers made the joints final, are inside
// solve_ms, and members_ms is what was left after it), so a report can say where the time went.
// Run: build/release/bin/wisp_bench --benchmark_filter=Edit
#include <benchmark/benchmark.h>

#include <array>
#include <cstring>
#include <memory>
#include <optional>

#include "bench_common.hpp"
#include "core/parallel.hpp"
#include "edit/progress_events.hpp"
#include "edit/stage_cache.hpp"
#include "edit/wire.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

enum class Answer { kMasters, kMastersExact, kPreview, kAll };

constexpr size_t kPreviewStrands = 20000;  // web/src/main.js previewStrands

void run(benchmark::State& state, const char* path, const char* a, const char* b, Answer answer,
         bool progress = false) {
    const ThreadLimit limit(2);
    StageCache cache(load_preset("default"));
    cache.update();
    bool flip = false;
    size_t bytes = 0, strands = 0;
    // Per-stage wall ms, summed over the iterations (the stages this answer ran; the styling
    // field is part of the solve, the preview's members and colour those of a subset).
    double roots_ms = 0., masters_ms = 0., solve_ms = 0., field_ms = 0., members_ms = 0.,
           color_ms = 0., encode_ms = 0.;
    ProgressEvents events;
    for (auto _ : state) {
        cache.set(path, (flip = !flip) ? a : b);
        std::optional<ProgressEvents::Task> task;
        if (progress) task.emplace(events, "update", kStageCount);
        const CancelToken token(task ? task->fractions() : nullptr);
        const Stage stale = cache.stale();
        const std::array<int, kStageCount> runs = cache.runs();
        const StageProgress stages = task ? task->stages() : StageProgress{};
        std::string out;
        std::shared_ptr<const std::string> sent;
        switch (answer) {
            case Answer::kMasters: {  // GET /api/masters?preview=1
                const Masters& m = *cache.update_masters_preview();
                out = encode_masters(m);
                strands = m.count();
                break;
            }
            case Answer::kMastersExact:  // GET /api/masters
                out = encode_masters(cache.update_masters());
                strands = cache.update_masters().count();
                break;
            case Answer::kPreview:  // GET /api/hair?strands=20000
                sent = cache.hair_bytes(kPreviewStrands, token, stages);
                break;
            case Answer::kAll:  // GET /api/hair
                sent = cache.hair_bytes(SIZE_MAX, token, stages);
                break;
        }
        if (sent) {
            uint32_t count = 0;
            std::memcpy(&count, sent->data() + 12, 4);
            strands = count;
        }
        bytes = sent ? sent->size() : out.size();
        const auto ran = [&](Stage s) { return cache.runs()[int(s)] != runs[int(s)]; };
        const auto ms = [&](Stage s) { return ran(s) ? cache.last_ms()[int(s)] : 0.; };
        roots_ms += ms(Stage::kRoots);
        masters_ms += ms(Stage::kMasters);
        solve_ms += ms(Stage::kSolve);
        if (ran(Stage::kSolve)) field_ms += cache.field_ms();
        if (answer == Answer::kPreview && stale <= Stage::kMembers && !ran(Stage::kMembers)) {
            members_ms += cache.preview_members_ms();
            color_ms += cache.preview_color_ms();
        } else {
            members_ms += ms(Stage::kMembers);
            color_ms += ms(Stage::kColor);
        }
        if (sent) encode_ms += cache.encode_ms();
        benchmark::DoNotOptimize(sent ? sent->data() : out.data());
        sent.reset();
        task.reset();
        state.PauseTiming();
        cache.update();
        state.ResumeTiming();
    }
    state.counters["bytes"] = static_cast<double>(bytes);
    state.counters["strands"] = static_cast<double>(strands);
    const auto per_iteration = [&](const char* name, double total) {
        if (total > 0.) state.counters[name] = total / static_cast<double>(state.iterations());
    };
    per_iteration("roots_ms", roots_ms);
    per_iteration("masters_ms", masters_ms);
    per_iteration("solve_ms", solve_ms);
    per_iteration("field_ms", field_ms);
    per_iteration("members_ms", members_ms);
    per_iteration("color_ms", color_ms);
    per_iteration("encode_ms", encode_ms);
}

void BM_EditColor20k(benchmark::State& state) {
    run(state, "color.wisp_hue", "3", "1.5", Answer::kPreview);
}
void BM_EditStiffnessMasters(benchmark::State& state) {
    run(state, "solve.stiffness", "0.8", "0.6", Answer::kMasters);
}
void BM_EditStiffnessMastersExact(benchmark::State& state) {
    run(state, "solve.stiffness", "0.8", "0.6", Answer::kMastersExact);
}
void BM_EditStiffnessPreview20k(benchmark::State& state) {
    run(state, "solve.stiffness", "0.8", "0.6", Answer::kPreview, state.range(0) == 1);
}
void BM_EditMapStroke20k(benchmark::State& state) {
    run(state, "maps.density", "{ procedural = \"crown\", low = 0.6, high = 1 }", "1",
        Answer::kPreview);
}
void BM_EditAnyChange100k(benchmark::State& state) {
    run(state, "maps.density", "{ procedural = \"crown\", low = 0.6, high = 1 }", "1", Answer::kAll,
        state.range(0) == 1);
}
BENCHMARK(BM_EditColor20k)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_EditStiffnessMasters)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_EditStiffnessMastersExact)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_EditStiffnessPreview20k)
    ->ArgName("progress")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_EditMapStroke20k)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_EditAnyChange100k)
    ->ArgName("progress")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace wisp
