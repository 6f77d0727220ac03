#include "io/float_text.hpp"

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <string_view>

namespace wisp {
namespace {

using io_detail::kShortestFloatRoom;
using io_detail::put_shortest;

std::string shortest(float v) {
    char buf[kShortestFloatRoom];
    return std::string(buf, put_shortest(buf, v));
}

std::string reference(float v) {
    char buf[64];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

// put_shortest(v) must be the bytes of std::to_chars(v); on a mismatch, the bit pattern and
// both texts (the first few only, counted beyond that).
struct Mismatches {
    uint64_t checked = 0, count = 0;
    std::string first;
    void add(const Mismatches& o) {
        checked += o.checked;
        count += o.count;
        if (first.size() < 400) first += o.first;
    }
};

void check(uint32_t bits, Mismatches& m) {
    const float v = std::bit_cast<float>(bits);
    char got[kShortestFloatRoom], want[64];
    char* got_end = put_shortest(got, v);
    char* want_end = std::to_chars(want, want + sizeof want, v).ptr;
    ++m.checked;
    if (std::string_view(got, size_t(got_end - got)) !=
        std::string_view(want, size_t(want_end - want))) {
        if (++m.count <= 8) {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%08x", bits);
            m.first += std::string("\n  0x") + hex + ": " + std::string(got, got_end) +
                       " (to_chars " + std::string(want, want_end) + ")";
        }
    }
}

// Bit patterns lo, lo + stride, ... below 2^32, in parallel.
Mismatches check_strided(uint64_t stride, uint64_t offset = 0) {
    const uint64_t n = ((uint64_t(1) << 32) - offset + stride - 1) / stride;
    return tbb::parallel_reduce(
        tbb::blocked_range<uint64_t>(0, n, 1 << 16), Mismatches{},
        [&](const tbb::blocked_range<uint64_t>& r, Mismatches m) {
            for (uint64_t i = r.begin(); i < r.end(); ++i)
                check(static_cast<uint32_t>(offset + i * stride), m);
            return m;
        },
        [](Mismatches a, const Mismatches& b) {
            a.add(b);
            return a;
        });
}

TEST(FloatText, SpecialValues) {
    EXPECT_EQ(shortest(0.f), "0");
    EXPECT_EQ(shortest(-0.f), "-0");
    EXPECT_EQ(shortest(std::numeric_limits<float>::infinity()), "inf");
    EXPECT_EQ(shortest(-std::numeric_limits<float>::infinity()), "-inf");
    EXPECT_EQ(shortest(std::numeric_limits<float>::quiet_NaN()), "nan");
    EXPECT_EQ(shortest(-std::numeric_limits<float>::quiet_NaN()), "-nan");
    EXPECT_EQ(shortest(std::bit_cast<float>(0x7f800001u)),
              reference(std::bit_cast<float>(0x7f800001u)));
}

// Every layout: the point inside the digits, leading zeros, whole numbers written exactly,
// and scientific notation where it is shorter.
TEST(FloatText, Layouts) {
    EXPECT_EQ(shortest(12.5f), "12.5");
    EXPECT_EQ(shortest(-0.1f), "-0.1");
    EXPECT_EQ(shortest(0.00123f), "0.00123");
    EXPECT_EQ(shortest(0.0001f), "1e-04");
    EXPECT_EQ(shortest(1.f), "1");
    EXPECT_EQ(shortest(10000.f), "10000");  // as long as "1e+04": fixed
    EXPECT_EQ(shortest(100000.f), "1e+05");
    EXPECT_EQ(shortest(120000.f), "120000");        // as long as "1.2e+05"
    EXPECT_EQ(shortest(123456790.f), "123456792");  // the float's exact value
    EXPECT_EQ(shortest(1e10f), "1e+10");
    EXPECT_EQ(shortest(std::numeric_limits<float>::max()), "3.4028235e+38");
    EXPECT_EQ(shortest(std::numeric_limits<float>::min()), "1.1754944e-38");
    EXPECT_EQ(shortest(std::numeric_limits<float>::denorm_min()), "1e-45");
    EXPECT_EQ(shortest(-1.1754942e-38f), "-1.1754942e-38");
}

// The text is never longer than 15 characters and stays inside kShortestFloatRoom; it reads
// back to the same bits.
TEST(FloatText, RoundTripsWithinItsRoom) {
    std::mt19937 rng(15);
    for (int i = 0; i < 200000; ++i) {
        const uint32_t bits = rng();
        const float v = std::bit_cast<float>(bits);
        if (!std::isfinite(v)) continue;
        char buf[kShortestFloatRoom + 16];
        std::memset(buf, '#', sizeof buf);
        const char* end = put_shortest(buf, v);
        ASSERT_LE(end - buf, 15);
        for (size_t k = kShortestFloatRoom; k < sizeof buf; ++k)
            ASSERT_EQ(buf[k], '#') << "wrote past its room for bits " << bits;
        float back = 0;
        ASSERT_EQ(std::from_chars(buf, end, back).ec, std::errc());
        ASSERT_EQ(std::bit_cast<uint32_t>(back), bits) << std::string_view(buf, size_t(end - buf));
    }
}

// Where the layout or the digits change: each power of ten and its neighbouring floats, the
// powers of two (a narrower interval below them), every binade's first and last floats, and
// the whole numbers around 2^24 and 10^n.
TEST(FloatText, BoundariesMatchToChars) {
    Mismatches m;
    for (int k = -45; k <= 38; ++k) {
        const float p = static_cast<float>(std::pow(10.0, k));
        const uint32_t b = std::bit_cast<uint32_t>(p);
        for (uint32_t d = 0; d < 64; ++d)
            for (uint32_t sign : {0u, 0x80000000u}) {
                check((b + d) | sign, m);
                if (b >= d) check((b - d) | sign, m);
            }
    }
    for (uint32_t exponent = 0; exponent < 255; ++exponent)
        for (uint32_t mantissa : {0u, 1u, 2u, 0x7ffffeu, 0x7fffffu})
            check((exponent << 23) | mantissa, m);
    for (uint32_t x = 0; x < 100000; ++x) {
        check(std::bit_cast<uint32_t>(float(16777216 - 50000 + int(x))), m);
        check(std::bit_cast<uint32_t>(float(x)), m);
    }
    EXPECT_EQ(m.count, 0u) << m.count << " of " << m.checked << " differ:" << m.first;
}

// A stride through all 2^32 bit patterns (a prime, so every exponent and sign and many
// mantissa endings are met): about 4 million floats. WISP_FLOAT_TEXT_EXHAUSTIVE=1 checks all
// 2^32 instead (a few minutes on 2 cores).
TEST(FloatText, MatchesToCharsOverAllBitPatterns) {
    const char* env = std::getenv("WISP_FLOAT_TEXT_EXHAUSTIVE");
    const bool exhaustive = env && std::string(env) == "1";
    const Mismatches m = exhaustive ? check_strided(1) : check_strided(1021, 7);
    std::printf("[ perf ] float text: %llu bit patterns compared with std::to_chars%s\n",
                static_cast<unsigned long long>(m.checked), exhaustive ? " (all)" : "");
    EXPECT_EQ(m.count, 0u) << m.count << " of " << m.checked << " differ:" << m.first;
    EXPECT_EQ(m.checked, exhaustive ? uint64_t(1) << 32 : ((uint64_t(1) << 32) - 7 + 1020) / 1021);
}

}  // namespace
}  // namespace wisp
