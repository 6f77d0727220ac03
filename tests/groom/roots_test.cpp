#include "groom/roots.hpp"

#include <gtest/gtest.h>

#include <string>
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

// Proposals drawn beforehand (once per head in the editor) give the roots place_roots draws
// itself, bit for bit, under maps that accept most first tries, reject many (zero at the
// crown) or none; proposals drawn for another seed or count are not used.
TEST(Roots, ProposalsDrawnBeforehandGiveTheSameRoots) {
    const Scalp& scalp = *builtin().scalp;
    RootParams params;
    params.wisps = 150;
    params.strands = 5000;
    params.seed = 9;
    const RootProposals proposals = root_proposals(scalp, params);
    RootParams other = params;
    other.seed = 10;
    const RootProposals others = root_proposals(scalp, other);
    EXPECT_TRUE(proposals.fit(params));
    EXPECT_FALSE(others.fit(params));
    ScalarMap hairline = crown(0.f);
    hairline.procedural = "hairline";
    const auto bytes = [](const auto& v) {
        return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
    };
    for (const ScalarMap& map : {crown(0.6f), crown(0.f), hairline, ScalarMap{}}) {
        const MapSampler density(map, scalp);
        const Roots a = place_roots(scalp, density, params);
        for (const RootProposals* p : {&proposals, &others}) {
            const Roots b = place_roots(scalp, density, params, nullptr, p);
            EXPECT_TRUE(bytes(a.masters) == bytes(b.masters)) << map.procedural;
            EXPECT_TRUE(bytes(a.members) == bytes(b.members)) << map.procedural;
            EXPECT_EQ(a.wisp_offsets, b.wisp_offsets);
            EXPECT_EQ(a.wisp_radius, b.wisp_radius);
        }
    }
}

}  // namespace wisp
