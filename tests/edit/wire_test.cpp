// The binary layouts the editor sends to the browser (src/edit/wire.hpp).
#include "edit/wire.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace wisp {
namespace {

uint32_t u32_at(const std::string& bytes, size_t at) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

TEST(Wire, FrameIsHeaderThenPositionsAndReusesItsBuffer) {
    const std::vector<Vec3f> points{{1.5f, -2.f, 3.25f}, {0.f, 1e-3f, -7.f}};
    std::string bytes;
    encode_frame(42, points, bytes);
    ASSERT_EQ(bytes.size(), 20u + 24u);
    EXPECT_EQ(bytes.substr(0, 8), "WISPFRAM");
    EXPECT_EQ(u32_at(bytes, 8), 1u);
    EXPECT_EQ(u32_at(bytes, 12), 42u);
    EXPECT_EQ(u32_at(bytes, 16), 2u);
    float z;
    std::memcpy(&z, bytes.data() + 20 + 5 * 4, 4);
    EXPECT_EQ(z, -7.f);
    const char* memory = bytes.data();
    encode_frame(43, std::span<const Vec3f>(points).first(1), bytes);
    EXPECT_EQ(bytes.size(), 32u);
    EXPECT_EQ(bytes.data(), memory);  // a smaller frame reuses the memory
    EXPECT_EQ(u32_at(bytes, 16), 1u);
}

}  // namespace
}  // namespace wisp
