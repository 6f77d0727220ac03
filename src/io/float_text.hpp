#pragma once
// The shortest text of a float that reads back to exactly the same float: the characters
// std::to_chars(first, last, v) writes (C++17 [charconv.to.chars]: the fewest significant
// digits that round-trip, the nearest such decimal, in fixed or scientific notation,
// whichever is shorter, fixed on a tie; libstdc++ writes fixed whole numbers exactly), in
// about two thirds of its time. The text formats are bound by float formatting (a usda of
// 100,000 strands × 32 points holds 12.8 M floats; docs/formats.md).
//
// The digits come from Dragonbox (J. Jeon, "Dragonbox: A New Floating-Point Binary-to-Decimal
// Conversion Algorithm", 2020; Debian's libdragonbox-dev), which gives the same shortest,
// nearest digits as Ryu, the algorithm behind libstdc++'s to_chars; the layout writes them with
// fixed-size copies instead of a loop per digit. tests/io/float_text_test.cpp compares the
// bytes with std::to_chars on a stride of all 2^32 bit patterns (every one with
// WISP_FLOAT_TEXT_EXHAUSTIVE=1).
#include <cstddef>

namespace wisp::io_detail {

// The text is at most 15 characters ("-1.1754944e-38"), but put_shortest may write scratch
// bytes after it, up to this many bytes from `p` in all: give it that much room (the next
// text written overwrites the scratch).
inline constexpr size_t kShortestFloatRoom = 32;

// Writes v's shortest round-trip text at p and returns its end: "0.1", "-12.5", "1e+10",
// "1.1754944e-38", "-0", "inf", "-nan", exactly as std::to_chars(p, p + 15, v).
char* put_shortest(char* p, float v);

}  // namespace wisp::io_detail
