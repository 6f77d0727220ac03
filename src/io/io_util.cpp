#include "io/io_util.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <memory>

namespace wisp::io_detail {

std::string read_whole_file(const std::filesystem::path& path, const ReadLimits& limits) {
    return read_file(path, limits);
}

FileBytes::FileBytes(const std::filesystem::path& path, const ReadLimits& limits) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat st {};
    if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        static_cast<uint64_t>(st.st_size) <= limits.max_bytes) {
        map_size_ = static_cast<size_t>(st.st_size);
        map_ = ::mmap(nullptr, map_size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
        if (map_ == MAP_FAILED) map_ = nullptr;
    }
    if (fd >= 0) ::close(fd);
    if (!map_) {
        // Not mappable, or over the limit: read_file reads it or reports why it cannot.
        owned_ = read_file(path, limits);
        view_ = owned_;
        return;
    }
    ::madvise(map_, map_size_, MADV_SEQUENTIAL);
    view_ = std::string_view(static_cast<const char*>(map_), map_size_);
    // read_file's check: text holds no NUL byte but for padding at its end, which is cut off
    // (a file that does not start with the magic is left to its parser, which reports its
    // first line).
    if (limits.text && (limits.magic.empty() || view_.starts_with(limits.magic))) {
        size_t nul = std::string_view::npos;
        try {
            nul = check_nul_padding(path, limits, view_, 0, nul);
        } catch (...) {
            ::munmap(map_, map_size_);
            map_ = nullptr;
            throw;
        }
        if (nul != std::string_view::npos) view_ = view_.substr(0, nul);
    }
}

FileBytes::~FileBytes() {
    if (map_) ::munmap(map_, map_size_);
}

FileReader::FileReader(const std::filesystem::path& path) : name_(path.string()) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(name_, ": is a folder, not a file");
    f_ = std::fopen(path.c_str(), "rb");
    if (!f_) fail(name_, ": cannot open: ", std::strerror(errno));
    if (std::fseek(f_, 0, SEEK_END) != 0) fail(name_, ": cannot seek: ", std::strerror(errno));
    const long size = std::ftell(f_);
    if (size < 0 || std::fseek(f_, 0, SEEK_SET) != 0)
        fail(name_, ": cannot seek: ", std::strerror(errno));
    size_ = static_cast<size_t>(size);
}

FileReader::~FileReader() {
    if (f_) std::fclose(f_);
}

void FileReader::read_bytes(void* dst, size_t n, std::string_view what) {
    require(n, what);
    if (n && std::fread(dst, 1, n, f_) != n)
        fail(name_, ": byte ", pos_, ": read failed for ", what, ": ",
             std::ferror(f_) ? std::strerror(errno) : "the file shrank");
    pos_ += n;
}

void FileReader::skip(size_t n, std::string_view what) {
    require(n, what);
    if (std::fseek(f_, static_cast<long>(pos_ + n), SEEK_SET) != 0)
        fail(name_, ": byte ", pos_, ": cannot seek past ", what);
    pos_ += n;
}

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace wisp::io_detail
