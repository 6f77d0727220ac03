#pragma once
// Helpers shared by the io readers and writers: fast whole-file reads, bounds-checked
// little-endian binary reads, and shortest round-trip number formatting (put_shortest for
// floats, std::to_chars otherwise, std::from_chars: no iostream per value). Internal to src/io.
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/math.hpp"
#include "io/float_text.hpp"

namespace wisp::io_detail {

static_assert(std::endian::native == std::endian::little,
              "the binary readers and writers copy little-endian arrays directly");

// The most a hair file read whole (.usda, .obj, .ply) may hold: 2 GiB, about
// 20 million strands of 32 points in .usda (docs/formats.md).
inline constexpr uint64_t kMaxHairFileBytes = uint64_t(2) << 30;

// Reads a whole file within `limits` (core/atomic_file.hpp); throws wisp::Error naming the
// file.
std::string read_whole_file(const std::filesystem::path& path, const ReadLimits& limits = {});

// A whole file's bytes within `limits`, as read_whole_file gives them, but mapped read-only
// when the file is a regular, non-empty one: no zero-filled buffer, no copy out of the page
// cache, its pages mapped in one go (MAP_POPULATE). Anything else (a pipe, /dev/zero, a
// file the system cannot map) is read whole. The bytes stay valid while the object lives.
// A file truncated by another process while mapped would fault on the lost pages: wisp reads
// its own outputs, written atomically (a new file renamed over the old, never truncated).
class FileBytes {
  public:
    FileBytes(const std::filesystem::path& path, const ReadLimits& limits);
    ~FileBytes();
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;
    std::string_view view() const { return view_; }

  private:
    std::string owned_;
    void* map_ = nullptr;
    size_t map_size_ = 0;
    std::string_view view_;
};

// Lower-case extension of path, with its dot (".usda"), or "".
std::string lower_extension(const std::filesystem::path& path);

// Sequential, bounds-checked reads from a byte buffer. Every failure throws wisp::Error
// "<name>: byte <offset>: <what>".
class ByteReader {
  public:
    ByteReader(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

    size_t offset() const { return pos_; }
    size_t size() const { return bytes_.size(); }
    size_t remaining() const { return bytes_.size() - pos_; }
    const std::string& name() const { return name_; }

    // Throws unless n more bytes are available; `what` names what is being read.
    void require(uint64_t n, std::string_view what) const {
        if (n > remaining())
            fail(name_, ": byte ", pos_, ": truncated: ", what, " needs ", n, " bytes, only ",
                 remaining(), " left");
    }
    template <typename T>
    T read(std::string_view what) {
        static_assert(std::is_trivially_copyable_v<T>);
        require(sizeof(T), what);
        T v;
        std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }
    void read_bytes(void* dst, size_t n, std::string_view what) {
        require(n, what);
        if (n) std::memcpy(dst, bytes_.data() + pos_, n);
        pos_ += n;
    }
    void skip(size_t n, std::string_view what) {
        require(n, what);
        pos_ += n;
    }
    std::string_view view(size_t n, std::string_view what) {
        require(n, what);
        std::string_view v = bytes_.substr(pos_, n);
        pos_ += n;
        return v;
    }
    template <typename... Args>
    [[noreturn]] void fail_at(size_t offset, const Args&... args) const {
        fail(name_, ": byte ", offset, ": ", args...);
    }

  private:
    std::string_view bytes_;
    std::string name_;
    size_t pos_ = 0;
};

// The ByteReader interface on an open file, reading straight into the caller's arrays
// (no whole-file buffer). The size is taken once at open.
class FileReader {
  public:
    explicit FileReader(const std::filesystem::path& path);
    ~FileReader();
    FileReader(const FileReader&) = delete;
    FileReader& operator=(const FileReader&) = delete;

    size_t offset() const { return pos_; }
    size_t size() const { return size_; }
    size_t remaining() const { return size_ - pos_; }
    const std::string& name() const { return name_; }
    void require(uint64_t n, std::string_view what) const {
        if (n > remaining())
            fail(name_, ": byte ", pos_, ": truncated: ", what, " needs ", n, " bytes, only ",
                 remaining(), " left");
    }
    void read_bytes(void* dst, size_t n, std::string_view what);
    void skip(size_t n, std::string_view what);
    template <typename... Args>
    [[noreturn]] void fail_at(size_t offset, const Args&... args) const {
        fail(name_, ": byte ", offset, ": ", args...);
    }

  private:
    std::FILE* f_ = nullptr;
    std::string name_;
    size_t size_ = 0, pos_ = 0;
};

// Appends the shortest decimal form that reads back to exactly v (std::to_chars' bytes).
inline void append_number(std::string& out, float v) {
    char buf[kShortestFloatRoom];
    out.append(buf, put_shortest(buf, v));
}
inline void append_number(std::string& out, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}
template <typename I>
requires std::is_integral_v<I>
inline void append_number(std::string& out, I v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

// Appends "x y z", each number in its shortest exact form.
inline void append_vec(std::string& out, const Vec3f& v) {
    append_number(out, v.x());
    out += ' ';
    append_number(out, v.y());
    out += ' ';
    append_number(out, v.z());
}

// Parses all of s as a number (a leading '+' is accepted); false if s is not one.
template <typename T>
bool parse_number(std::string_view s, T& v) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

}  // namespace wisp::io_detail
