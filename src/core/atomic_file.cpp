#include "core/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>

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

std::string read_file(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path.string(), ": is a folder, not a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), ": cannot open: ", std::strerror(errno));
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) fail(path.string(), ": read failed");
    return std::move(s).str();
}

}  // namespace wisp
