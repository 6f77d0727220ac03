#include "io/ply.hpp"

#include <gtest/gtest.h>

#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

TEST(Ply, RoundTripIsBitExact) {
    for (bool extras : {true, false}) {
        Hair h = test::random_hair(13, 300, 0, extras, extras, extras);
        h.default_width = 0.0321f;
        h.default_color = Vec3f(0.9f, 0.1f, 0.3f);
        test::TempPath p(".ply");
        write_ply(p, h);
        const Hair r = read_ply(p);
        test::expect_same_geometry(h, r);
        ASSERT_EQ(r.widths.size(), h.widths.size());
        test::expect_same_widths(h, r);
        ASSERT_EQ(r.colors.size(), h.colors.size());
        test::expect_same_colors(h, r);
        EXPECT_EQ(r.wisp, h.wisp);
        EXPECT_EQ(r.default_width, h.default_width);
    }
}

TEST(Ply, HeaderLayout) {
    Hair h;
    h.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, 1, 0}, {0, 2, 0}});
    h.widths = {0.1f, 0.1f, 0.05f};
    const std::string bytes = encode_ply(h);
    const std::string header = bytes.substr(0, bytes.find("end_header"));
    for (const char* line :
         {"format binary_little_endian 1.0", "element vertex 3", "property float width",
          "element edge 2", "property int vertex1", "property int vertex2", "element strand 1",
          "property int vertex_count"})
        EXPECT_NE(header.find(line), std::string::npos) << line;
}

TEST(Ply, ReadsAsciiAndEdgesOnly) {
    // No strand element: strands come from chaining edges. Faces (lists) are read past.
    const char* text =
        "ply\nformat ascii 1.0\ncomment from another tool\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\n"
        "element face 1\nproperty list uchar int vertex_indices\n"
        "element edge 3\nproperty int vertex1\nproperty int vertex2\n"
        "end_header\n"
        "0 0 0 255\n0 1 0 0\n0 2 0 0\n5 0 0 1\n5 1 0 1\n"
        "3 0 1 2\n"
        "0 1\n1 2\n3 4\n";
    const Hair h = decode_ply(text, "a.ply");
    ASSERT_EQ(h.strand_count(), 2u);
    EXPECT_EQ(h.strand_size(0), 3u);
    EXPECT_EQ(h.strand(1)[1], Vec3f(5, 1, 0));
}

TEST(Ply, ReadsBigEndian) {
    std::string s =
        "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nelement strand 1\nproperty uchar vertex_count\n"
        "end_header\n";
    auto put_be = [&](float v) {
        uint32_t u;
        std::memcpy(&u, &v, 4);
        for (int k = 3; k >= 0; --k)
            s += char((u >> (8 * k)) & 0xFF);
    };
    for (float v : {1.f, 2.f, 3.f, 4.f, 5.f, 6.5f})
        put_be(v);
    s += char(2);
    const Hair h = decode_ply(s, "be.ply");
    ASSERT_EQ(h.strand_count(), 1u);
    EXPECT_EQ(h.points[1], Vec3f(4, 5, 6.5f));
}

TEST(Ply, TruncatedAndHostileFilesFail) {
    const std::string bytes = encode_ply(test::random_hair(17, 12, 0));
    for (size_t cut = 0; cut < bytes.size(); ++cut)
        EXPECT_THROW(decode_ply(std::string_view(bytes).substr(0, cut), "cut.ply"), Error)
            << "cut at " << cut;
    expect_error(
        [] {
            decode_ply(
                "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                "property float x\nproperty float y\nproperty float z\nend_header\n",
                "h.ply");
        },
        "h.ply: byte 124: element vertex declares 4000000000 records");
    expect_error(
        [] {
            decode_ply(
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nelement strand 1\nproperty int vertex_count\nend_header\n"
                "0 0\n0\n",
                "s.ply");
        },
        "s.ply:12: file ends before vertex_count");
    expect_error(
        [] {
            decode_ply(
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nelement strand 1\nproperty int vertex_count\nend_header\n"
                "0 0 x\n1\n",
                "x.ply");
        },
        "x.ply:10: `x` is not a number (z)");
    expect_error([] { decode_ply("plx\n", "n.ply"); }, "n.ply:1: not a PLY file");
    expect_error(
        [] {
            decode_ply(
                "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                "property float z\nelement strand 1\nproperty int vertex_count\nend_header\n"
                "0 0 0\n1 1 1\n5\n",
                "c.ply");
        },
        "c.ply: strand 0 has vertex_count 5");
    expect_error(
        [] {
            decode_ply(
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nelement strand 1\nproperty int vertex_count\nend_header\n"
                "0 inf 0\n1\n",
                "i.ply");
        },
        "i.ply: vertex 0 is not finite");
}

// What a header quotes is escaped and cut short: a terminal escape sequence in a file must
// not reach the terminal, nor a megabyte word the log.
TEST(Ply, MessagesEscapeAndShortenWhatTheyQuote) {
    expect_error([] { decode_ply("ply\n\x1b[2J\x1b]0;pwned\x07 x\n", "e.ply"); },
                 "e.ply:2: unknown header line `\\x1b[2J\\x1b]0;pwned\\x07`");
    try {
        decode_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty " +
                       std::string(1 << 20, 'f') + " x\nend_header\n",
                   "big.ply");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_LT(m.size(), 200u);
        EXPECT_NE(m.find("big.ply:4: unknown property type `ffff"), std::string::npos) << m;
        EXPECT_NE(m.find("... (1048576 bytes)`"), std::string::npos) << m;
    }
}

// Doubles that become integers or floats are range-checked before the conversion.
TEST(Ply, OutOfRangeDoublesFail) {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property double z\nelement strand 1\nproperty double vertex_count\n";
    expect_error([&] { decode_ply(head + "end_header\n0 0 0\n1 1 1\n1e300\n", "v.ply"); },
                 "v.ply: strand 0 has vertex_count 1e+300, which runs past the 2 vertices");
    expect_error([&] { decode_ply(head + "end_header\n0 0 0\n1 1 1\nnan\n", "n.ply"); },
                 "n.ply: strand 0 has vertex_count nan");
    expect_error(
        [&] {
            decode_ply(head + "property double wisp_id\nend_header\n0 0 0\n1 1 1\n2 nan\n",
                       "w.ply");
        },
        "w.ply: strand 0 has wisp_id nan, which is not a whole number");
    expect_error(
        [&] {
            decode_ply(head + "property double wisp_id\nend_header\n0 0 0\n1 1 1\n2 3e9\n",
                       "b.ply");
        },
        "b.ply: strand 0 has wisp_id 3e+09");
    expect_error([&] { decode_ply(head + "end_header\n0 0 1e300\n1 1 1\n2\n", "z.ply"); },
                 "z.ply: vertex 0 is not finite or farther than 100000 cm");
    const Hair h = decode_ply(
        head + "property double wisp_id\nend_header\n0 0 0\n1 1 99999\n2 -7\n", "ok.ply");
    EXPECT_EQ(h.wisp[0], -7);
}

}  // namespace
}  // namespace wisp
