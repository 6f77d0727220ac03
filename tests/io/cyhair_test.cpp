#include "io/cyhair.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

TEST(CyHair, RoundTripIsBitExact) {
    for (uint32_t n : {0u, 25u}) {  // varying point counts (segments array), then uniform
        const Hair h = test::random_hair(7 + n, 300, n);
        test::TempPath p(".hair");
        write_cyhair(p, h);
        const Hair r = read_cyhair(p);
        test::expect_same_geometry(h, r);
        EXPECT_TRUE(test::same_bits(h.widths.data(), r.widths.data(), 4 * h.widths.size()));
        test::expect_same_colors(h, r);
        EXPECT_TRUE(r.wisp.empty());  // cyHair has no wisp ids
    }
}

TEST(CyHair, WritesSegmentsOnlyWhenStrandsDiffer) {
    const Hair uniform = test::random_hair(1, 10, 5, false, false, false);
    const std::string a = encode_cyhair(uniform);
    uint32_t flags, d_segments;
    std::memcpy(&flags, a.data() + 12, 4);
    std::memcpy(&d_segments, a.data() + 16, 4);
    EXPECT_EQ(flags, 2u);  // points only
    EXPECT_EQ(d_segments, 4u);
    EXPECT_EQ(a.size(), 128u + 10 * 5 * 12);
    const Hair varying = test::random_hair(1, 10, 0, true, true, false);
    const std::string b = encode_cyhair(varying);
    std::memcpy(&flags, b.data() + 12, 4);
    EXPECT_EQ(flags, 1u | 2u | 4u | 16u);
}

TEST(CyHair, DefaultsStandInForAbsentArrays) {
    Hair h = test::random_hair(3, 20, 8, false, false, false);
    h.default_width = 0.0125f;
    h.default_color = Vec3f(0.5f, 0.25f, 0.125f);
    const Hair r = decode_cyhair(encode_cyhair(h), "mem.hair");
    EXPECT_TRUE(r.widths.empty());
    EXPECT_TRUE(r.colors.empty());
    EXPECT_EQ(r.default_width, 0.0125f);
    EXPECT_EQ(r.default_color, h.default_color);
    test::expect_same_geometry(h, r);
}

TEST(CyHair, TruncatedFilesFail) {
    const std::string bytes = encode_cyhair(test::random_hair(11, 40));
    for (size_t cut = 0; cut < bytes.size(); cut += cut < 300 ? 1 : 37) {
        EXPECT_THROW(decode_cyhair(std::string_view(bytes).substr(0, cut), "cut.hair"), Error)
            << "cut at " << cut;
    }
    expect_error([&] { decode_cyhair(bytes + "x", "long.hair"); }, "long.hair: byte");
}

TEST(CyHair, HostileHeaderDoesNotAllocate) {
    std::string bytes(128, '\0');
    std::memcpy(bytes.data(), "HAIR", 4);
    const uint32_t strands = 1u << 31, points = 0xFFFFFFFFu, flags = 0x1F;
    std::memcpy(bytes.data() + 4, &strands, 4);
    std::memcpy(bytes.data() + 8, &points, 4);
    std::memcpy(bytes.data() + 12, &flags, 4);
    expect_error([&] { decode_cyhair(bytes, "hostile.hair"); },
                 "hostile.hair: byte 128: header declares 2147483648 strands");
    // Without a segments array d_segments must explain the point count.
    const uint32_t two = 2, pts = 2;
    std::memcpy(bytes.data() + 12, &two, 4);
    std::memcpy(bytes.data() + 4, &strands, 4);
    std::memcpy(bytes.data() + 8, &pts, 4);
    bytes.resize(128 + 24);
    expect_error([&] { decode_cyhair(bytes, "h.hair"); }, "d_segments");
}

TEST(CyHair, InconsistentOrBadValuesFail) {
    Hair h = test::random_hair(5, 4, 0, false, false, false);
    std::string bytes = encode_cyhair(h);
    expect_error([&] { decode_cyhair("HAIX" + bytes.substr(4), "sig.hair"); }, "HAIR signature");
    // Segments claiming more points than the header.
    std::string bad = bytes;
    const uint16_t big = 1000;
    std::memcpy(bad.data() + 128, &big, 2);
    expect_error([&] { decode_cyhair(bad, "seg.hair"); },
                 "seg.hair: byte 128: strand 0 ends at point");
    // A NaN coordinate.
    bad = bytes;
    const float nan = std::nanf("");
    std::memcpy(bad.data() + 128 + 2 * 4 + 12 * 2 + 4, &nan, 4);
    expect_error([&] { decode_cyhair(bad, "nan.hair"); }, "point 2 is not finite");
    // A coordinate 1e20 cm away (once crashed `wisp animate`).
    bad = bytes;
    const float far = 1e20f;
    std::memcpy(bad.data() + 128 + 2 * 4 + 12 * 2 + 4, &far, 4);
    expect_error([&] { decode_cyhair(bad, "far.hair"); }, "far.hair: point 2 (strand ");
    expect_error([&] { decode_cyhair(bad, "far.hair"); }, "farther than 100000 cm");
    // No points array.
    bad = bytes;
    const uint32_t seg_only = 1;
    std::memcpy(bad.data() + 12, &seg_only, 4);
    expect_error([&] { decode_cyhair(bad, "nopts.hair"); }, "no points array");
}

TEST(CyHair, StrandTooLongForUint16SegmentsFails) {
    Hair h;
    h.add_strand(std::vector<Vec3f>(65537, Vec3f::Zero()));
    expect_error([&] { encode_cyhair(h, "long.hair"); }, "long.hair: strand 0 has 65537 points");
    Hair ok;
    ok.add_strand(std::vector<Vec3f>(65536, Vec3f::Ones()));
    ok.add_strand(std::vector<Vec3f>(3, Vec3f::Ones()));
    EXPECT_EQ(decode_cyhair(encode_cyhair(ok), "ok.hair").strand_size(0), 65536u);
}

TEST(CyHair, RoundTrips100kStrandsOf32Points) {
    // Speed is measured by bench/io_bench; this checks the format holds a groom of a
    // realistic size exactly.
    const Hair h = test::random_hair(42, 100000, 32);
    test::TempPath p(".hair");
    write_cyhair(p, h);
    test::expect_same_geometry(h, read_cyhair(p));
}

}  // namespace
}  // namespace wisp
