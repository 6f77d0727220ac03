#include "io/float_text.hpp"

#include <bit>
#include <cstdint>
#include <cstring>

#include <dragonbox/dragonbox.h>

namespace wisp::io_detail {
namespace {

// 8 ASCII digits of x < 10^8, the most significant first in memory (little-endian): the two
// halves of 4 digits, then pairs, then digits are split in the lanes of one 64-bit word
// (x·10486 >> 20 is x/100 for x < 10^4, x·103 >> 10 is x/10 for x < 100), so no digit costs a
// division or a loop iteration.
uint64_t eight_digits(uint32_t x) {
    const uint64_t hi = x / 10000, lo = x % 10000;
    uint64_t v = hi | (lo << 32);
    const uint64_t hundreds = ((v * 10486) >> 20) & 0x0000007F0000007Full;
    v = hundreds | ((v - hundreds * 100) << 16);
    const uint64_t tens = ((v * 103) >> 10) & 0x000F000F000F000Full;
    v = tens | ((v - tens * 10) << 8);
    return v + 0x3030303030303030ull;
}

constexpr uint32_t kPow10[10] = {1,      10,      100,      1000,      10000,
                                 100000, 1000000, 10000000, 100000000, 1000000000};

// Decimal digits of m > 0 (bit width · log10 2, corrected by one comparison).
int digit_count(uint32_t m) {
    const int n = ((std::bit_width(m) * 1233) >> 12) + 1;
    return n - (m < kPow10[n - 1]);
}

constexpr char kTwoDigits[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

}  // namespace

char* put_shortest(char* p, float v) {
    const uint32_t bits = std::bit_cast<uint32_t>(v);
    const uint32_t magnitude = bits & 0x7fffffffu;
    *p = '-';
    p += bits >> 31;
    if (magnitude == 0 || magnitude >= 0x7f800000u) [[unlikely]] {
        if (magnitude == 0) {
            *p = '0';
            return p + 1;
        }
        std::memcpy(p, magnitude == 0x7f800000u ? "inf" : "nan", 3);
        return p + 3;
    }
    // v = ±m·10^e with the fewest digits, the nearest to v of those (ties to an even m).
    const auto decimal = jkj::dragonbox::to_decimal(std::bit_cast<float>(magnitude),
                                                    jkj::dragonbox::policy::sign::ignore);
    const uint32_t m = decimal.significand;  // < 10^9, no trailing zeros
    const int e = decimal.exponent;
    const int n = digit_count(m);

    // m's n digits at s, in a buffer long enough for the 16-byte copies below.
    char digits[48] = {};
    digits[16] = static_cast<char>('0' + m / 100000000);
    const uint64_t low = eight_digits(m % 100000000);
    std::memcpy(digits + 17, &low, 8);
    const char* s = digits + 25 - n;

    // Most values (all of hair's coordinates in centimetres but the tiny ones) have the point
    // inside their digits: "12.34567".
    if (e < 0 && n + e > 0) [[likely]] {
        const int whole = n + e;
        std::memcpy(p, s, 16);
        std::memcpy(p + whole + 1, s + whole, 16);
        p[whole] = '.';
        return p + n + 1;
    }
    // Fixed notation when it is no longer than scientific (libstdc++'s bounds on e, the same
    // comparison of the two lengths): "0.00123" is, "0.0001" ("1e-04") and "1000000" ("1e+06")
    // are not.
    const int lower = n == 1 ? -3 : -(n + 3), upper = n == 1 ? 4 : 5;
    if (e >= lower && e <= upper) {
        if (e < 0) {
            std::memcpy(p, "0.000000", 8);
            p += 2 - e - n;
            std::memcpy(p, s, 16);
            return p + n;
        }
        // A whole number, written exactly as printf("%.0f") would (it is below 10^15, and the
        // float is an integer: its shortest decimal is one, within half an ulp), not as its
        // shortest digits followed by zeros: 123456792, not 123456790.
        uint64_t x = static_cast<uint64_t>(std::bit_cast<float>(magnitude));
        int k = 1;
        for (uint64_t t = x; t >= 10; t /= 10)
            ++k;
        char* end = p + k;
        do {
            *--end = static_cast<char>('0' + x % 10);
            x /= 10;
        } while (x);
        return p + k;
    }
    // Scientific: "1e+10", "1.1754944e-38", "1e-45".
    *p++ = s[0];
    if (n > 1) {
        *p = '.';
        std::memcpy(p + 1, s + 1, 16);
        p += n;
    }
    int exponent = e + n - 1;
    *p++ = 'e';
    *p++ = exponent < 0 ? '-' : '+';
    if (exponent < 0) exponent = -exponent;  // at most 45: two digits
    std::memcpy(p, kTwoDigits + 2 * exponent, 2);
    return p + 2;
}

}  // namespace wisp::io_detail
