#include "io/hair_io.hpp"

#include <gtest/gtest.h>

#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

TEST(HairIo, FormatFromExtension) {
    EXPECT_EQ(hair_format_from_path("a/b.usda"), HairFormat::kUsda);
    EXPECT_EQ(hair_format_from_path("x.HAIR"), HairFormat::kHair);
    EXPECT_EQ(hair_format_from_path("x.obj"), HairFormat::kObj);
    EXPECT_EQ(hair_format_from_path("x.ply"), HairFormat::kPly);
    EXPECT_EQ(hair_format_from_path("x.data"), HairFormat::kData);
    EXPECT_EQ(hair_format_from_path("x.rib"), HairFormat::kRib);
    EXPECT_EQ(hair_format_from_path("x.pbrt"), HairFormat::kPbrt);
    EXPECT_EQ(hair_format_from_path("x.npz"), HairFormat::kNpz);
    expect_error([] { hair_format_from_path("x.abc"); },
                 "x.abc: unknown hair file extension \".abc\" (supported: .usda, .hair, .obj, "
                 ".ply, .data; written only: .rib, .pbrt, .npz)");
    expect_error([] { read_hair("x.rib"); }, "x.rib: .rib and .pbrt are scenes wisp writes");
}

TEST(HairIo, EveryWritableFormatRoundTrips) {
    const Hair h = test::random_hair(23, 100);
    for (const char* ext : {".usda", ".hair", ".obj", ".ply"}) {
        SCOPED_TRACE(ext);
        test::TempPath p(ext);
        write_hair(p, h);
        const Hair r = read_hair(p);
        test::expect_same_geometry(h, r);
        const HairFileInfo info = hair_file_info(p);
        EXPECT_EQ(info.strands, h.strand_count());
        EXPECT_EQ(info.points, h.point_count());
        EXPECT_EQ(info.min_points, 2u);
        EXPECT_LE(info.max_points, 40u);
        EXPECT_EQ(info.bounds.lo, h.bounds().lo);
        EXPECT_FALSE(describe(info).empty());
    }
    test::TempPath seg(".obj");
    write_hair(seg, h, HairWriteOptions{.obj_segments = true});
    test::expect_same_geometry(h, read_hair(seg));
    // .data is written as the data set has it: 100 points per strand.
    test::TempPath data(".data");
    write_hair(data, h);
    const Hair d = read_hair(data);
    ASSERT_EQ(d.strand_count(), h.strand_count());
    for (size_t s = 0; s < d.strand_count(); ++s)
        EXPECT_EQ(d.strand_size(s), 100u);
    test::TempPath npz(".npz");
    write_hair(npz, h, HairWriteOptions{.resample_points = 8});
    EXPECT_TRUE(std::filesystem::exists(npz.path()));
    expect_error([&] { read_hair(npz); }, "wisp does not read it");
}

TEST(HairIo, InfoListsUsdPrims) {
    const HairFileInfo info = hair_file_info(WISP_SHARED_DIR "/data/usd/openusd_basicCurves.usda");
    ASSERT_EQ(info.usd_prims.size(), 7u);
    size_t invalid = 0;
    for (const UsdPrimSummary& p : info.usd_prims)
        invalid += !p.problem.empty();
    EXPECT_EQ(invalid, 1u);  // BezierClosedBad
    EXPECT_EQ(info.strands, 6u);
    EXPECT_NE(describe(info).find("INVALID"), std::string::npos);
}

TEST(HairIo, MissingFileNamesIt) {
    expect_error([] { read_hair("/nonexistent/wisp.hair"); },
                 "/nonexistent/wisp.hair: cannot open");
}

}  // namespace
}  // namespace wisp
