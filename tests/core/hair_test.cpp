#include "core/hair.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/rng.hpp"

namespace wisp {
namespace {

// Three strands of 2, 3 and 4 points with every optional array filled.
Hair full_hair() {
    Hair h;
    for (int s = 0; s < 3; ++s) {
        std::vector<Vec3f> pts;
        for (int k = 0; k < s + 2; ++k)
            pts.emplace_back(float(s), float(k), 0.f);
        h.add_strand(pts);
        h.colors.emplace_back(0.1f * s, 0.2f, 0.3f);
        h.wisp.push_back(s * 10);
        h.root_uv.emplace_back(0.25f * s, 0.5f);
        h.root_normal.emplace_back(0.f, 1.f, 0.f);
        h.group.push_back(s % 2);
    }
    for (size_t i = 0; i < h.point_count(); ++i)
        h.widths.push_back(0.01f * float(i + 1));
    h.default_width = 0.02f;
    return h;
}

TEST(Hair, ValidateChecksTheRootArrays) {
    Hair h = full_hair();
    EXPECT_NO_THROW(h.validate("h"));
    Hair a = h;
    a.root_uv.pop_back();
    EXPECT_THROW(a.validate("h"), Error);
    Hair b = h;
    b.root_normal[1].x() = std::nanf("");
    EXPECT_THROW(b.validate("h"), Error);
    Hair c = h;
    c.group[2] = -1;
    try {
        c.validate("file.x");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("file.x: group 2 is -1"), std::string::npos)
            << e.what();
    }
}

// bounds() and max_width() reduce chunks on all cores: on random hair spanning several
// chunks, they equal a serial scan exactly, at 1 and 2 threads; no points is an empty box.
TEST(Hair, BoundsAndMaxWidthEqualASerialScanAtAnyThreadCount) {
    EXPECT_TRUE(Hair{}.bounds().empty());
    EXPECT_EQ(Hair{}.max_width(), Hair{}.default_width);
    Hair h;
    Rng rng(7);
    std::vector<Vec3f> pts(33);
    for (int s = 0; s < 9001; ++s) {  // 297,033 points: 5 chunks, the last not whole
        for (Vec3f& p : pts)
            p = Vec3f(rng.uniform(-30.f, 20.f), rng.uniform(-5.f, 40.f), rng.uniform(-25.f, 25.f));
        h.add_strand(pts);
    }
    EXPECT_EQ(h.max_width(), h.default_width);
    for (size_t i = 0; i < h.point_count(); ++i)
        h.widths.push_back(rng.uniform(0.f, 0.01f));
    Box3 serial;
    for (const Vec3f& p : h.points)
        serial.extend(p);
    const float widest = *std::max_element(h.widths.begin(), h.widths.end());
    for (int threads : {1, 2}) {
        const ThreadLimit limit(threads);
        const Box3 b = h.bounds();
        EXPECT_EQ(b.lo, serial.lo) << threads << " threads";
        EXPECT_EQ(b.hi, serial.hi) << threads << " threads";
        EXPECT_EQ(h.max_width(), widest) << threads << " threads";
    }
}

TEST(Hair, SelectStrandsCarriesEveryArray) {
    const Hair h = full_hair();
    const std::vector<uint32_t> keep{2, 0};
    const Hair s = select_strands(h, keep);
    ASSERT_NO_THROW(s.validate("s"));
    ASSERT_EQ(s.strand_count(), 2u);
    EXPECT_EQ(s.strand_size(0), 4u);
    EXPECT_EQ(s.strand_size(1), 2u);
    EXPECT_EQ(s.strand(0)[3], h.strand(2)[3]);
    EXPECT_EQ(s.widths[0], h.widths[h.offsets[2]]);
    EXPECT_EQ(s.colors[0], h.colors[2]);
    EXPECT_EQ(s.wisp[1], 0);
    EXPECT_EQ(s.root_uv[0], h.root_uv[2]);
    EXPECT_EQ(s.group[0], 0);
    EXPECT_EQ(s.default_width, 0.02f);
    const std::vector<uint32_t> bad{3};
    EXPECT_THROW(select_strands(h, bad), Error);
}

TEST(Hair, EvenSubsetIsSpreadAndDeterministic) {
    EXPECT_EQ(even_subset(10, 5), (std::vector<uint32_t>{1, 3, 5, 7, 9}));
    EXPECT_EQ(even_subset(3, 10), (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_TRUE(even_subset(0, 4).empty());
    const auto big = even_subset(100000, 1000);
    ASSERT_EQ(big.size(), 1000u);
    for (size_t k = 1; k < big.size(); ++k)
        EXPECT_EQ(big[k] - big[k - 1], 100u);
}

}  // namespace
}  // namespace wisp
