#include "io/io_util.hpp"

#include <cerrno>
#include <cstdio>
#include <memory>

namespace wisp::io_detail {

std::string read_whole_file(const std::filesystem::path& path, const ReadLimits& limits) {
    return read_file(path, limits);
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
