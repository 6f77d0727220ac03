#include "core/error.hpp"

#include <gtest/gtest.h>

namespace wisp {

TEST(Excerpt, EscapesControlCharactersAndBytesThatAreNotUtf8) {
    EXPECT_EQ(excerpt("plain text"), "plain text");
    EXPECT_EQ(excerpt("a\nb\tc\rd"), "a\\nb\\tc\\rd");
    EXPECT_EQ(excerpt("\x1b[31mred\x1b[0m"), "\\x1b[31mred\\x1b[0m");
    EXPECT_EQ(excerpt(std::string_view("nul\0!", 5)), "nul\\x00!");
    EXPECT_EQ(excerpt("\x7f"), "\\x7f");
    EXPECT_EQ(excerpt("caf\xc3\xa9 \xe2\x89\xa5 \xf0\x9f\x92\x87"), "café ≥ 💇");
    EXPECT_EQ(excerpt("\xc2\x9b"
                      "2J"),
              "\\u009b2J");  // C1 CSI
    EXPECT_EQ(excerpt("bad \xff\xc3 \xed\xa0\x80"), "bad \\xff\\xc3 \\xed\\xa0\\x80");
}

TEST(Excerpt, CutsLongValues) {
    const std::string big(15'000'000, 'k');
    const std::string e = excerpt(big);
    EXPECT_EQ(e, std::string(kExcerptBytes, 'k') + "... (15000000 bytes)");
    EXPECT_EQ(excerpt("abcdef", 3), "abc... (6 bytes)");
    EXPECT_EQ(excerpt("abc", 3), "abc");
    // A multi-byte character is never split.
    EXPECT_EQ(excerpt("ab\xc3\xa9z", 3), "ab\xc3\xa9... (5 bytes)");
}

}  // namespace wisp
