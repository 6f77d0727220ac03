#include "io/hairsalon.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace wisp
