#pragma once
// The one error type wisp throws at its boundaries (readers, style parser, command line).
// Its message names the input, the location and what was expected versus found.
#include <sstream>
#include <stdexcept>
#include <string>

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

// Throws wisp::Error with the concatenated arguments as its message.
template <typename... Args>
[[noreturn]] void fail(const Args&... args) {
    throw Error(cat(args...));
}

}  // namespace wisp
