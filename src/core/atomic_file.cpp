#include "core/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <memory>
#include <mutex>

#include "core/error.hpp"

namespace wisp {

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
    tmp_ = path_;
    tmp_ += cat(".tmp-", ::getpid());
    if (path_.has_parent_path() && !std::filesystem::exists(path_.parent_path())) {
        std::error_code ec;
        std::filesystem::create_directories(path_.parent_path(), ec);
        if (ec) fail(path_.string(), ": cannot create folder: ", ec.message());
    }
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) fail(path_.string(), ": cannot open for writing: ", std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (!committed_) {
        out_.close();
        std::error_code ec;
        std::filesystem::remove(tmp_, ec);
    }
}

void AtomicFile::commit() {
    out_.flush();
    if (!out_) fail(path_.string(), ": write failed");
    out_.close();
    if (out_.fail()) fail(path_.string(), ": write failed on close");
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) fail(path_.string(), ": cannot rename temporary file: ", ec.message());
    committed_ = true;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
    AtomicFile f(path);
    f.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.commit();
}

void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write) {
    AtomicFile f(path);
    write(f.stream());
    f.commit();
}

std::string read_file(const std::filesystem::path& path, const ReadLimits& limits) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path.string(), ": is a folder, not a file");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) fail(path.string(), ": cannot open: ", std::strerror(errno));
    // The size is only a hint for the first allocation: the limits are checked on the bytes.
    uint64_t hint = 0;
    if (std::fseek(f.get(), 0, SEEK_END) == 0) {
        const long size = std::ftell(f.get());
        if (size > 0) hint = static_cast<uint64_t>(size);
        if (std::fseek(f.get(), 0, SEEK_SET) != 0)
            fail(path.string(), ": cannot seek: ", std::strerror(errno));
    }
    const auto too_large = [&] {
        fail(path.string(), ": larger than ", limits.max_bytes, " bytes, the limit for ",
             limits.what, " (docs/formats.md)");
    };
    if (hint > limits.max_bytes) too_large();
    const uint64_t cap = limits.max_bytes + 1;  // one byte more tells a file over the limit
    std::string bytes(
        static_cast<size_t>(std::min<uint64_t>(std::max<uint64_t>(hint + 1, 1 << 16), cap)), '\0');
    size_t got = 0, scanned = 0;  // bytes read; bytes checked for NUL
    bool magic_checked = limits.magic.empty();
    for (;;) {
        if (got == bytes.size()) {
            if (got >= cap) break;
            bytes.resize(static_cast<size_t>(std::min<uint64_t>(uint64_t(got) * 2, cap)));
        }
        const size_t n = std::fread(bytes.data() + got, 1, bytes.size() - got, f.get());
        if (n == 0) break;
        got += n;
        if (!magic_checked && got >= limits.magic.size()) {
            magic_checked = true;
            if (std::string_view(bytes.data(), limits.magic.size()) != limits.magic) break;
        }
        if (limits.text && magic_checked) {
            if (const void* nul = std::memchr(bytes.data() + scanned, '\0', got - scanned))
                fail(path.string(), ": byte ", static_cast<const char*>(nul) - bytes.data(),
                     " is a NUL byte, which ", limits.what, " (text) never holds");
            scanned = got;
        }
    }
    if (std::ferror(f.get())) fail(path.string(), ": read failed: ", std::strerror(errno));
    if (got > limits.max_bytes) too_large();
    bytes.resize(got);
    return bytes;
}

}  // namespace wisp
