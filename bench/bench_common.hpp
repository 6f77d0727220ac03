#pragma once
// What the benchmarks share: the issues' reference workload and the built-in head.
#include "groom/head.hpp"
#include "groom/style.hpp"

namespace wisp {

// 100,000 full-length strands of 32 control points in 2,000 wavy wisps.
inline Style bench_style() {
    Style style;
    style.wisps = 2000;
    style.strands = 100000;
    style.points_per_strand = 32;
    // Full-length members, so that every strand has exactly 32 control points.
    style.wisp.length = Distribution{Distribution::Kind::kConstant, 1.f};
    style.prototype.kind = PrototypeSpec::Kind::kWavy;
    // Clumps as the default preset has them: every preset gathers its members.
    style.clump.pull = 0.8f;
    style.clump.shape = 1.2f;
    style.clump.sub_pull = 0.6f;
    return style;
}

inline const Head& bench_head() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

}  // namespace wisp
