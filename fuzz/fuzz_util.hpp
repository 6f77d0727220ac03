#pragma once
// Helpers shared by the libFuzzer harnesses (fuzz/*_fuzz.cpp, docs/fuzzing.md): a scratch file
// for readers that take only a path, and the checks every harness makes of what a reader
// returns. A reader may throw wisp::Error; anything else escapes to libFuzzer, which reports
// it, and so does a broken invariant (abort).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/hair.hpp"

namespace wisp::fuzz {

inline std::string_view as_text(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// A file named for this process in /dev/shm (memory, so no disk writes per input), or in the
// temporary folder where there is none; rewritten for every input, removed at exit.
class ScratchFile {
  public:
    explicit ScratchFile(std::string_view extension) {
        const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm")
                                              ? std::filesystem::path("/dev/shm")
                                              : std::filesystem::temp_directory_path();
        path_ = dir / ("wisp_fuzz_" + std::to_string(::getpid()) + std::string(extension));
    }
    ~ScratchFile() {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
    }
    ScratchFile(const ScratchFile&) = delete;
    ScratchFile& operator=(const ScratchFile&) = delete;

    const std::filesystem::path& write(const uint8_t* data, size_t size) {
        std::FILE* f = std::fopen(path_.c_str(), "wb");
        if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
            std::perror(path_.c_str());
            std::abort();  // the harness cannot run, not a finding in the reader
        }
        return path_;
    }

  private:
    std::filesystem::path path_;
};

// A reader broke a promise its header makes: report it as a crash.
[[noreturn]] inline void broken(std::string_view what) {
    std::fprintf(stderr, "wisp fuzz: %.*s\n", static_cast<int>(what.size()), what.data());
    std::abort();
}

// read(), or nothing if it threw wisp::Error (the documented way to refuse an input).
template <typename Read>
auto attempt(Read&& read) -> std::optional<decltype(read())> {
    try {
        return read();
    } catch (const Error&) {
        return std::nullopt;
    }
}

// Readers return hair that passes Hair::validate (finite, in range, consistent arrays).
inline void check_valid(const Hair& hair) {
    try {
        hair.validate("the hair a reader returned");
    } catch (const Error& e) {
        broken(e.what());
    }
}

inline bool same_hair(const Hair& a, const Hair& b) {
    return a.offsets == b.offsets && a.points == b.points && a.widths == b.widths &&
           a.colors == b.colors && a.wisp == b.wisp && a.default_width == b.default_width &&
           a.default_color == b.default_color;
}

// The in-memory decoder and the file reader of one format must agree: both refuse the input,
// or both return the same hair.
inline void check_same(const std::optional<Hair>& from_memory,
                       const std::optional<Hair>& from_file) {
    if (from_memory.has_value() != from_file.has_value())
        broken(from_memory ? "the file reader refused what the decoder read"
                           : "the decoder refused what the file reader read");
    if (from_memory && !same_hair(*from_memory, *from_file))
        broken("the decoder and the file reader returned different hair");
}

}  // namespace wisp::fuzz
