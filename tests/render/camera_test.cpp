#include "render/camera.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace wisp {
namespace {

Box3 test_box() {
    Box3 b;
    b.extend(Vec3f(-10, -25, -12));
    b.extend(Vec3f(11, 14, 13));
    return b;
}

TEST(Camera, NamedViewsFrameEveryCorner) {
    const Box3 box = test_box();
    for (const std::string& view : view_names()) {
        for (auto [w, h] : {std::pair{256, 256}, std::pair{400, 200}, std::pair{150, 300}}) {
            const Camera c = frame_view(view, box, w, h);
            float min_x = 1e9f, max_x = -1e9f, min_y = 1e9f, max_y = -1e9f;
            for (int k = 0; k < 8; ++k) {
                const Vec3f corner((k & 1) ? box.hi.x() : box.lo.x(),
                                   (k & 2) ? box.hi.y() : box.lo.y(),
                                   (k & 4) ? box.hi.z() : box.lo.z());
                const Vec3f q = c.project(corner);
                EXPECT_GT(q.z(), 0.f) << view;
                min_x = std::min(min_x, q.x());
                max_x = std::max(max_x, q.x());
                min_y = std::min(min_y, q.y());
                max_y = std::max(max_y, q.y());
            }
            EXPECT_GE(min_x, 0.f) << view;
            EXPECT_LE(max_x, static_cast<float>(w)) << view;
            EXPECT_GE(min_y, 0.f) << view;
            EXPECT_LE(max_y, static_cast<float>(h)) << view;
            // Tight: the box fills most of the limiting dimension.
            EXPECT_GT(std::max((max_x - min_x) / w, (max_y - min_y) / h), 0.85f) << view;
        }
    }
}

TEST(Camera, ViewsLookFromTheirSide) {
    const Box3 box = test_box();
    EXPECT_GT(frame_view("front", box, 64, 64).eye.z(), box.hi.z());
    EXPECT_LT(frame_view("back", box, 64, 64).eye.z(), box.lo.z());
    EXPECT_GT(frame_view("left", box, 64, 64).eye.x(), box.hi.x());  // the subject's left, +X
    EXPECT_LT(frame_view("right", box, 64, 64).eye.x(), box.lo.x());
    EXPECT_GT(frame_view("top", box, 64, 64).eye.y(), box.hi.y());
    const Camera q = frame_view("three-quarter", box, 64, 64);
    EXPECT_GT(q.eye.x(), 0.f);
    EXPECT_GT(q.eye.z(), 0.f);
    // Front view: +Y is up in the image, the subject's left (+X) on the image's right.
    const Camera f = frame_view("front", box, 64, 64);
    EXPECT_LT(f.project(Vec3f(0, 5, 0)).y(), f.project(Vec3f(0, 0, 0)).y());
    EXPECT_LT(f.project(Vec3f(-5, 0, 0)).x(), f.project(Vec3f(5, 0, 0)).x());
}

TEST(Camera, RayAndProjectAgree) {
    const Camera c = look_at(Vec3f(30, 10, 50), Vec3f(0, 0, 0), Vec3f::UnitY(), 40.f, 320, 200);
    for (float x : {0.5f, 100.f, 319.f})
        for (float y : {0.5f, 77.f, 199.f}) {
            const Vec3f p = c.eye + 37.f * c.ray(x, y);
            const Vec3f q = c.project(p);
            EXPECT_NEAR(q.x(), x, 1e-3f);
            EXPECT_NEAR(q.y(), y, 1e-3f);
        }
    EXPECT_NEAR(c.project(Vec3f::Zero()).x(), 160.f, 1e-3f);
    EXPECT_NEAR(c.project(Vec3f::Zero()).y(), 100.f, 1e-3f);
}

TEST(Camera, BadInputThrows) {
    EXPECT_THROW(frame_view("sideways", test_box(), 64, 64), Error);
    EXPECT_THROW(frame_view("front", Box3{}, 64, 64), Error);
    EXPECT_THROW(look_at(Vec3f::Zero(), Vec3f::Zero(), Vec3f::UnitY(), 30.f, 64, 64), Error);
    EXPECT_THROW(look_at(Vec3f(0, 5, 0), Vec3f::Zero(), Vec3f::UnitY(), 30.f, 64, 64), Error);
    EXPECT_THROW(look_at(Vec3f(0, 0, 5), Vec3f::Zero(), Vec3f::UnitY(), 0.f, 64, 64), Error);
    EXPECT_THROW(look_at(Vec3f(0, 0, 5), Vec3f::Zero(), Vec3f::UnitY(), 30.f, 0, 64), Error);
    try {
        frame_view("sideways", test_box(), 64, 64);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("three-quarter"), std::string::npos);
    }
}

}  // namespace
}  // namespace wisp
