#include "groom/roots.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "groom/head.hpp"

namespace wisp {
namespace {

const Head& builtin() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

ScalarMap crown(float low) {
    ScalarMap m;
    m.kind = ScalarMap::Kind::kProcedural;
    m.procedural = "crown";
    m.low = low;
    return m;
}

}  // namespace

// Each member root goes to the master nearest to it, ties to the lowest index, exactly as a
// brute-force scan in index order with the same float distances finds it, whatever first
// guess (the labels of the candidates on its face) the search starts from; with and without
// Lloyd iterations (no labels: no guesses).
TEST(Roots, MembersGoToTheExactNearestMaster) {
    const Scalp& scalp = *builtin().scalp;
    const MapSampler density(crown(0.2f), scalp);
    for (const int iterations : {0, 3}) {
        RootParams params;
        params.wisps = 150;
        params.strands = 4000;
        params.lloyd_iterations = iterations;
        params.seed = 23;
        const Roots roots = place_roots(scalp, density, params);
        for (size_t w = 0; w < roots.masters.size(); ++w)
            for (uint32_t j = roots.wisp_offsets[w]; j < roots.wisp_offsets[w + 1]; ++j) {
                const Vec3f& p = roots.members[j].position;
                size_t best = 0;
                for (size_t m = 1; m < roots.masters.size(); ++m)
                    if ((roots.masters[m].position - p).squaredNorm() <
                        (roots.masters[best].position - p).squaredNorm())
                        best = m;
                ASSERT_EQ(w, best) << "member " << j << ", " << iterations << " iterations";
            }
    }
}

}  // namespace wisp
