#include "io/hairsalon.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "core/parallel.hpp"
#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

void put_i32(std::string& s, int32_t v) {
    s.append(reinterpret_cast<const char*>(&v), 4);
}
void put_f32(std::string& s, float v) {
    s.append(reinterpret_cast<const char*>(&v), 4);
}

// Three strands: 3 vertices, a bare root (1 vertex), 2 vertices.
std::string sample_file() {
    std::string s;
    put_i32(s, 3);
    put_i32(s, 3);
    for (float v : {0.f, 1.f, 0.f, 0.f, 0.9f, 0.05f, 0.01f, 0.8f, 0.1f})
        put_f32(s, v);
    put_i32(s, 1);
    for (float v : {0.2f, 1.5f, 0.f})
        put_f32(s, v);
    put_i32(s, 2);
    for (float v : {-0.1f, 1.6f, 0.f, -0.12f, 1.5f, 0.02f})
        put_f32(s, v);
    return s;
}

TEST(HairSalon, ReadsMetresAsCentimetresAndSkipsBareRoots) {
    test::TempPath p(".data");
    test::write_bytes(p, sample_file());
    HairSalonStats stats;
    const Hair h = read_hairsalon(p, &stats);
    EXPECT_EQ(stats.strands_in_file, 3u);
    EXPECT_EQ(stats.bare_roots, 1u);
    ASSERT_EQ(h.strand_count(), 2u);
    EXPECT_EQ(h.strand_size(0), 3u);
    EXPECT_EQ(h.strand_size(1), 2u);
    EXPECT_FLOAT_EQ(h.points[1].y(), 90.f);
    EXPECT_FLOAT_EQ(h.points[4].z(), 2.f);
}

TEST(HairSalon, TruncatedFilesFail) {
    const std::string bytes = sample_file();
    for (size_t cut = 0; cut < bytes.size(); ++cut)
        EXPECT_THROW(decode_hairsalon(std::string_view(bytes).substr(0, cut), "cut.data"), Error)
            << "cut at " << cut;
    expect_error([&] { decode_hairsalon(bytes + "abcd", "t.data"); }, "unexpected bytes");
}

TEST(HairSalon, HostileCountsFail) {
    std::string s;
    put_i32(s, 0x7FFFFFFF);
    expect_error([&] { decode_hairsalon(s, "h.data"); },
                 "h.data: byte 0: header declares 2147483647");
    s.clear();
    put_i32(s, 1);
    put_i32(s, 0x40000000);
    expect_error([&] { decode_hairsalon(s, "v.data"); }, "v.data: byte 8: truncated");
    s.clear();
    put_i32(s, 1);
    put_i32(s, -5);
    expect_error([&] { decode_hairsalon(s, "n.data"); }, "negative vertex count");
    s.clear();
    put_i32(s, 1);
    put_i32(s, 2);
    for (float v : {0.f, 0.f, 0.f, 0.f, std::numeric_limits<float>::infinity(), 0.f})
        put_f32(s, v);
    expect_error([&] { decode_hairsalon(s, "inf.data"); }, "vertex 1 is not finite");
}

// The file is read straight into the arrays, its counts checked against its size: an
// endless file (/dev/zero reports size 0) fails at once instead of being read whole.
TEST(HairSalon, EndlessFileFailsAtOnce) {
    test::TempPath p(".data");
    std::filesystem::create_symlink("/dev/zero", p.path());
    expect_error([&] { read_hairsalon(p); },
                 p.path().string() + ": byte 0: truncated: the strand count needs 4 bytes");
}

// Written as the data set has it: 100 points per strand, metres; read back through the
// reader, every strand keeps its root and tip and lies on wisp's curve.
TEST(HairSalon, WriteRoundTripsThroughTheReader) {
    const Hair h = test::random_hair(21, 200);
    test::TempPath p(".data");
    write_hairsalon(p, h);
    EXPECT_EQ(std::filesystem::file_size(p.path()), 4 + 200u * (4 + 100 * 12));
    HairSalonStats stats;
    const Hair r = read_hairsalon(p, &stats);
    EXPECT_EQ(stats.bare_roots, 0u);
    ASSERT_EQ(r.strand_count(), h.strand_count());
    for (size_t s = 0; s < r.strand_count(); ++s) {
        ASSERT_EQ(r.strand_size(s), 100u);
        EXPECT_LT((r.strand(s).front() - h.strand(s).front()).norm(), 1e-4f) << s;
        EXPECT_LT((r.strand(s).back() - h.strand(s).back()).norm(), 1e-4f) << s;
    }
    // The file holds metres: the first coordinate is the root's x / 100.
    const std::string bytes = test::read_file_text(p);
    float x;
    std::memcpy(&x, bytes.data() + 8, 4);
    EXPECT_EQ(x, h.points[0].x() / 100.f);
    // Any thread count, the same bytes; another point count on request.
    {
        const ThreadLimit one(1);
        EXPECT_EQ(encode_hairsalon(h), bytes);
    }
    EXPECT_EQ(read_hairsalon(p).strand_size(0), 100u);
    const Hair r8 = decode_hairsalon(encode_hairsalon(h, "m", 8), "m");
    EXPECT_EQ(r8.strand_size(3), 8u);
    expect_error([&] { encode_hairsalon(h, "x.data", 1); }, "x.data: points per strand");
}

}  // namespace
}  // namespace wisp
