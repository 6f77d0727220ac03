#pragma once
// The one error type wisp throws at its boundaries (readers, style parser, command line).
// Its message names the input, the location and what was expected versus found.
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace wisp {

class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Concatenates its arguments with operator<< (GCC 12 has no <format>).
template <typename... Args>
std::string cat(const Args&... args) {
    std::ostringstream out;
    (out << ... << args);
    return out.str();
}

// How many bytes of an input value a message quotes (excerpt's default).
inline constexpr size_t kExcerptBytes = 64;

// `s` made safe to quote in a one-line message: control characters (newlines, terminal
// escape sequences, C1 controls) and bytes that are not UTF-8 are escaped (\n, \x1b,
// \u009b), and a value longer than max_bytes is cut there and followed by
// "... (N bytes)". Readers and the style parser pass every quoted input value through it.
std::string excerpt(std::string_view s, size_t max_bytes = kExcerptBytes);

// Throws wisp::Error with the concatenated arguments as its message.
template <typename... Args>
[[noreturn]] void fail(const Args&... args) {
    throw Error(cat(args...));
}

}  // namespace wisp
