#include "render/strand_raster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.hpp"

namespace wisp {
namespace {

struct Canvas {
    int size = 64;
    std::vector<float> cover = std::vector<float>(64 * 64, 0.f);
    float total() const {
        float s = 0;
        for (float c : cover)
            s += c;
        return s;
    }
    void draw(float x0, float y0, float w0, float x1, float y1, float w1) {
        rasterize_strand_piece(x0, y0, w0, x1, y1, w1, 0, 0, size, size,
                               [&](int x, int y, float t, float c) {
                                   ASSERT_GE(t, 0.f);
                                   ASSERT_LE(t, 1.f);
                                   ASSERT_GT(c, 0.f);
                                   ASSERT_LE(c, 1.f);
                                   cover[y * size + x] += c;
                               });
    }
};

TEST(StrandRaster, CoverageIsAreaForThinStrandsAtAnyAngle) {
    Rng rng(3);
    for (int i = 0; i < 100; ++i) {
        const float angle = 2.f * kPi * static_cast<float>(rng.uniform_double());
        const float width = 0.05f + 0.9f * static_cast<float>(rng.uniform_double());
        const float len = 20.f;
        const float cx = 32.f + static_cast<float>(rng.uniform_double());
        const float cy = 32.f + static_cast<float>(rng.uniform_double());
        const float dx = 0.5f * len * std::cos(angle), dy = 0.5f * len * std::sin(angle);
        Canvas c;
        c.draw(cx - dx, cy - dy, width, cx + dx, cy + dy, width);
        // Columns are sampled at their centres: the covered length is within a pixel.
        EXPECT_NEAR(c.total(), len * width, 1.2f * width) << "angle " << angle;
    }
}

TEST(StrandRaster, WideStrandsCoverWholePixels) {
    Canvas c;
    c.draw(10.f, 20.f, 4.f, 50.f, 20.f, 4.f);  // rows 18..21 fully, 40 columns
    EXPECT_NEAR(c.total(), 160.f, 1e-3f);
    EXPECT_NEAR(c.cover[19 * 64 + 30], 1.f, 1e-6f);
    EXPECT_EQ(c.cover[17 * 64 + 30], 0.f);
}

TEST(StrandRaster, SplitPiecesNeitherOverlapNorLeaveGaps) {
    Rng rng(5);
    for (int i = 0; i < 50; ++i) {
        auto r = [&] { return 4.f + 56.f * static_cast<float>(rng.uniform_double()); };
        const float x0 = r(), y0 = r(), x1 = r(), y1 = r();
        Canvas whole, split;
        whole.draw(x0, y0, 0.3f, x1, y1, 0.3f);
        const float xm = 0.5f * (x0 + x1), ym = 0.5f * (y0 + y1);
        split.draw(x0, y0, 0.3f, xm, ym, 0.3f);
        split.draw(xm, ym, 0.3f, x1, y1, 0.3f);
        for (size_t k = 0; k < whole.cover.size(); ++k)
            ASSERT_NEAR(whole.cover[k], split.cover[k], 1e-4f);
    }
}

TEST(StrandRaster, ClipRectangleIsRespected) {
    std::vector<int> hits;
    rasterize_strand_piece(-10.f, 5.5f, 0.5f, 100.f, 5.5f, 0.5f, 8, 0, 16, 8,
                           [&](int x, int y, float, float) {
                               EXPECT_GE(x, 8);
                               EXPECT_LT(x, 16);
                               EXPECT_GE(y, 0);
                               EXPECT_LT(y, 8);
                               hits.push_back(x);
                           });
    EXPECT_EQ(hits.size(), 8u);  // one row (the strand is centred on row 5), 8 columns
}

}  // namespace
}  // namespace wisp
