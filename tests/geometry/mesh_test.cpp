#include "geometry/mesh.hpp"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace wisp {
namespace {

// A 10 cm cube, counter-clockwise seen from outside, without its bottom (y = 0) face: a cup,
// like a head mesh cut open at the chest.
Mesh open_cube() {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.emplace_back(10.f * (i & 1), 10.f * ((i >> 1) & 1), 10.f * ((i >> 2) & 1));
    const int quads[5][4] = {{2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
        m.faces.emplace_back(q[0], q[1], q[2]);
        m.faces.emplace_back(q[0], q[2], q[3]);
    }
    return m;
}

// Each undirected edge's count of (forward, backward) uses.
std::map<std::pair<int, int>, std::pair<int, int>> edge_uses(const Mesh& m) {
    std::map<std::pair<int, int>, std::pair<int, int>> uses;
    for (const Vec3i& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3];
            auto& u = uses[{std::min(a, b), std::max(a, b)}];
            (a < b ? u.first : u.second) += 1;
        }
    return uses;
}

TEST(Mesh, CloseHolesCapsEachLoopFacingOut) {
    const Mesh cup = open_cube();
    size_t open_edges = 0;
    for (const auto& [edge, u] : edge_uses(cup))
        open_edges += u.first + u.second == 1;
    ASSERT_EQ(open_edges, 4u);

    Mesh closed, caps;
    close_holes(cup, &closed, &caps);
    // Every edge now has one use each way: closed and consistently oriented.
    for (const auto& [edge, u] : edge_uses(closed))
        EXPECT_EQ(u, std::make_pair(1, 1)) << edge.first << "-" << edge.second;
    ASSERT_EQ(closed.faces.size(), cup.faces.size() + 4);
    EXPECT_EQ(caps.faces.size(), 4u);
    // The cap's centre is the bottom's centre, and its faces look down (out of the cube).
    EXPECT_TRUE(closed.vertices.back().isApprox(Vec3f(5, 0, 5)));
    for (size_t f = cup.faces.size(); f < closed.faces.size(); ++f)
        EXPECT_LT(closed.face_normal(f).y(), -0.99f);
    // A closed mesh is left as it is.
    Mesh again;
    close_holes(closed, &again);
    EXPECT_EQ(again.faces.size(), closed.faces.size());
}

}  // namespace
}  // namespace wisp
