// The binary layouts the editor sends to the browser (src/edit/wire.hpp).
#include "edit/wire.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/error.hpp"

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

// begin_frame writes encode_frame's header and leaves the positions to its caller.
TEST(Wire, BeginFrameIsEncodeFrameWithThePositionsLeftToFill) {
    const std::vector<Vec3f> points{{1.5f, -2.f, 3.25f}, {0.f, 1e-3f, -7.f}};
    std::string encoded, begun;
    encode_frame(7, points, encoded);
    const std::span<char> xyz = begin_frame(7, points.size(), begun);
    ASSERT_EQ(xyz.size(), 24u);
    EXPECT_EQ(xyz.data(), begun.data() + 20);
    std::memcpy(xyz.data(), points.data(), xyz.size());
    EXPECT_EQ(begun, encoded);
}

// Strands by index, in the order given; the colours last, rewritten alone.
TEST(Wire, StrandsAreSentInTheOrderGivenWithTheirColoursLast) {
    Hair hair;
    hair.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, 1, 0}});
    hair.add_strand(std::vector<Vec3f>{{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
    hair.colors = {{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f}};
    const std::vector<uint32_t> ids{1};
    std::string bytes = encode_strands(hair, ids, 7);
    ASSERT_EQ(bytes.size(), 24u + 8u + 36u + 12u);
    EXPECT_EQ(bytes.substr(0, 8), "WISPHAIR");
    EXPECT_EQ(u32_at(bytes, 12), 1u);  // strands sent
    EXPECT_EQ(u32_at(bytes, 16), 3u);  // points sent
    EXPECT_EQ(u32_at(bytes, 20), 7u);  // strands in all
    EXPECT_EQ(u32_at(bytes, 28), 3u);  // offsets: 0, 3
    float v[3];
    std::memcpy(v, bytes.data() + 32 + 2 * 12, 12);
    EXPECT_EQ(Vec3f(v[0], v[1], v[2]), Vec3f(1, 2, 0));
    std::memcpy(v, bytes.data() + 68, 12);
    EXPECT_EQ(Vec3f(v[0], v[1], v[2]), hair.colors[1]);
    const std::vector<Vec3f> red{{1, 0, 0}};
    write_strand_colors(red, bytes);
    std::memcpy(v, bytes.data() + 68, 12);
    EXPECT_EQ(Vec3f(v[0], v[1], v[2]), red[0]);
    EXPECT_THROW(write_strand_colors(hair.colors, bytes), Error);  // two colours, one strand
    // The shuffled prefix is the same bytes as its ids.
    const std::vector<uint32_t> order = strand_order(2);
    EXPECT_EQ(encode_strands(hair, 2), encode_strands(hair, order, 2));
    EXPECT_THROW(encode_strands(hair, std::vector<uint32_t>{2}, 2), Error);
}

// Encoding into a buffer that held other bytes, larger, smaller or the same size, writes every
// byte: the result is the fresh encoding's, and a buffer large enough keeps its memory.
TEST(Wire, EncodingIntoAUsedBufferGivesTheFreshBytes) {
    Hair hair;
    hair.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, 1, 0}});
    hair.add_strand(std::vector<Vec3f>{{1, 0, 0}, {1, 1, 0}, {1, 2, 0}});
    hair.add_strand(std::vector<Vec3f>{{2, 0, 0}, {2, 1, 0}, {2, 2, 0}, {2, 3, 0}});
    hair.colors = {{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f}, {0.7f, 0.8f, 0.9f}};
    const std::vector<std::vector<uint32_t>> asks{{2, 0, 1}, {1}, {0, 2}, {2, 1, 0}, {}};
    for (const std::string& used : {std::string(), std::string(200, '\xff'), std::string(3, '\x55'),
                                    std::string(80, '\x7f')}) {
        for (const auto& ids : asks) {
            std::string out = used;
            encode_strands(hair, ids, 9, out);
            EXPECT_EQ(out, encode_strands(hair, ids, 9)) << used.size() << " " << ids.size();
        }
    }
    std::string out(500, '\xff');
    const char* memory = out.data();
    encode_strands(hair, asks[0], 3, out);
    EXPECT_EQ(out.data(), memory);
    EXPECT_EQ(out, encode_strands(hair, asks[0], 3));
}

}  // namespace
}  // namespace wisp
