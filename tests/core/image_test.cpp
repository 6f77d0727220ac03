#include "core/image.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

TEST(Image, PngRoundTripAsGray) {
    RgbImage rgb{2, 1, {255, 255, 255, 0, 0, 0}};
    const fs::path p = fs::temp_directory_path() / "wisp_image_test_round_trip.png";
    write_png(p, rgb);
    const GrayImage g = read_gray_image(p);
    fs::remove(p);
    ASSERT_EQ(g.width, 2);
    ASSERT_EQ(g.height, 1);
    EXPECT_NEAR(g.values[0], 1.f, 1e-6f);
    EXPECT_NEAR(g.values[1], 0.f, 1e-6f);
}

// Inputs the fuzzer found (fuzz/corpus/image/, docs/fuzzing.md): each is read or refused with
// wisp::Error, never a crash.
TEST(Image, FuzzFindingsReadOrFailCleanly) {
    for (const char* name : {"empty_idat.png"}) {
        const fs::path p = fs::path(WISP_SOURCE_DIR) / "fuzz/corpus/image" / name;
        ASSERT_TRUE(fs::exists(p)) << p;
        try {
            const GrayImage g = read_gray_image(p);
            EXPECT_EQ(g.values.size(), static_cast<size_t>(g.width) * g.height) << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace wisp
