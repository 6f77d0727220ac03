#include "dynamics/broad_phase.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/rng.hpp"

namespace wisp {
namespace {

Box4 box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
    Box4 b;
    b.lo << lo, 0.f;
    b.hi << hi, 0.f;
    return b;
}

// Boxes like hair segments: mostly small, some a few cells wide, a few much wider, packed
// into a head-sized region so that many overlap.
std::vector<Box4> random_boxes(uint64_t seed, int count, float region) {
    Rng rng(seed);
    std::vector<Box4> boxes;
    for (int i = 0; i < count; ++i) {
        const float scale = i % 17 == 0 ? 12.f : i % 5 == 0 ? 3.f : 0.8f;
        Eigen::Vector3f centre, half;
        for (int a = 0; a < 3; ++a) {
            centre[a] = rng.uniform(-region, region);
            half[a] = rng.uniform(0.f, scale);
        }
        boxes.push_back(box(centre - half, centre + half));
    }
    return boxes;
}

using Pairs = std::vector<std::pair<uint32_t, uint32_t>>;

Pairs grid_pairs(const BoxGrid& grid) {
    Pairs pairs;
    const auto order = grid.order();
    grid.for_each_overlap([&](size_t a, size_t b) {
        pairs.emplace_back(std::min(order[a], order[b]), std::max(order[a], order[b]));
    });
    return pairs;
}

Pairs brute_force(const std::vector<Box4>& boxes) {
    Pairs pairs;
    for (uint32_t a = 0; a < boxes.size(); ++a)
        for (uint32_t b = a + 1; b < boxes.size(); ++b)
            if (boxes_overlap(boxes[a], boxes[b])) pairs.emplace_back(a, b);
    return pairs;
}

TEST(BroadPhase, FindsEveryOverlappingPairExactlyOnce) {
    for (uint64_t seed : {1, 2, 3}) {
        for (float cell : {0.25f, 1.f, 4.f}) {
            const std::vector<Box4> boxes = random_boxes(seed, 600, 15.f);
            BoxGrid grid;
            grid.build(boxes, cell);
            ASSERT_EQ(grid.order().size(), boxes.size());
            Pairs found = grid_pairs(grid);
            const size_t visits = found.size();
            std::sort(found.begin(), found.end());
            found.erase(std::unique(found.begin(), found.end()), found.end());
            EXPECT_EQ(found.size(), visits) << "a pair was visited twice";
            const Pairs expected = brute_force(boxes);
            EXPECT_GT(expected.size(), 1000u);
            EXPECT_EQ(found, expected) << "seed " << seed << ", cell " << cell;
        }
    }
}

TEST(BroadPhase, BoxesOnCellBoundariesAndTouching) {
    // Boxes exactly one cell wide, centred on cell boundaries, touching face to face.
    std::vector<Box4> boxes;
    for (int i = 0; i < 6; ++i)
        boxes.push_back(
            box(Eigen::Vector3f(i - 0.5f, -0.5f, -0.5f), Eigen::Vector3f(i + 0.5f, 0.5f, 0.5f)));
    BoxGrid grid;
    grid.build(boxes, 1.f);
    Pairs found = grid_pairs(grid);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, brute_force(boxes));
    EXPECT_EQ(found.size(), 5u);
}

TEST(BroadPhase, LeavesOutBoxesThatAreNotFiniteOrFarAway) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<Box4> boxes = {
        box(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 1, 1)),
        box(Eigen::Vector3f(0.5f, 0.5f, 0.5f), Eigen::Vector3f(2, 2, 2)),
        box(Eigen::Vector3f(nan, 0, 0), Eigen::Vector3f(1, 1, 1)),
        box(Eigen::Vector3f(-inf, -inf, -inf), Eigen::Vector3f(inf, inf, inf)),
        box(Eigen::Vector3f(1e9f, 1e9f, 1e9f), Eigen::Vector3f(1e9f + 1, 1e9f + 1, 1e9f + 1)),
    };
    BoxGrid grid;
    grid.build(boxes, 0.5f);
    EXPECT_EQ(grid.order().size(), 2u);
    EXPECT_EQ(grid_pairs(grid), (Pairs{{0, 1}}));
}

// A visit returning false ends the pairs of its first box: each box then has at most as many
// pairs as it allowed, all of them real, and the boxes after it still get theirs.
TEST(BroadPhase, AVisitCanEndItsFirstBoxsPairs) {
    const std::vector<Box4> boxes = random_boxes(7, 600, 10.f);
    BoxGrid grid;
    grid.build(boxes, 1.f);
    const Pairs all = grid_pairs(grid);
    const size_t kLimit = 3;
    std::vector<size_t> all_per_box(boxes.size(), 0), kept_per_box(boxes.size(), 0);
    grid.for_each_overlap([&](size_t a, size_t) { ++all_per_box[a]; });
    Pairs kept;
    size_t current = SIZE_MAX, count = 0;
    grid.for_each_overlap([&](size_t a, size_t b) -> bool {
        EXPECT_TRUE(a == current || current == SIZE_MAX || a > current) << "a's pairs in a row";
        if (a != current) {
            current = a;
            count = 0;
        }
        ++kept_per_box[a];
        const auto order = grid.order();
        kept.emplace_back(std::min(order[a], order[b]), std::max(order[a], order[b]));
        return ++count < kLimit;
    });
    std::sort(kept.begin(), kept.end());
    Pairs expected = all;
    std::sort(expected.begin(), expected.end());
    EXPECT_TRUE(std::includes(expected.begin(), expected.end(), kept.begin(), kept.end()));
    size_t capped = 0;
    for (size_t a = 0; a < boxes.size(); ++a) {
        EXPECT_EQ(kept_per_box[a], std::min(all_per_box[a], kLimit)) << "box " << a;
        capped += all_per_box[a] > kLimit;
    }
    EXPECT_GT(capped, 10u) << "too few boxes with more pairs than the limit to test it";
}

TEST(BroadPhase, OrderDependsOnlyOnTheBoxes) {
    const std::vector<Box4> boxes = random_boxes(7, 300, 10.f);
    BoxGrid a, b;
    a.build(boxes, 1.f);
    b.build(random_boxes(99, 50, 3.f), 0.3f);  // reused with other boxes first
    b.build(boxes, 1.f);
    EXPECT_EQ(grid_pairs(a), grid_pairs(b));
}

}  // namespace
}  // namespace wisp
