#pragma once
// Outputs are written to a temporary file beside the target and renamed over it on
// commit(), so an interrupted run never leaves a truncated file behind. Open temporaries
// are registered: SIGINT, SIGTERM and SIGHUP remove them before the process dies.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>

namespace wisp {

class AtomicFile {
  public:
    // Opens `<path>.tmp-<pid>` for binary writing; throws wisp::Error if it cannot.
    explicit AtomicFile(std::filesystem::path path);
    ~AtomicFile();  // removes the temporary file unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return out_; }
    // Flushes, checks for write errors, and renames onto the target.
    void commit();

  private:
    std::filesystem::path path_, tmp_;
    std::ofstream out_;
    bool committed_ = false;
    int slot_ = -1;  // in the table of temporaries the signal handler removes
};

// Writes `bytes` to path atomically.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Calls write(stream) on an AtomicFile for path, then commits.
void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write);

// What a reader accepts of a file, checked while it reads, not from the file's size (endless
// files such as /dev/zero or a pipe report 0): at most max_bytes; for text formats no NUL
// byte; and, when magic is given, reading stops at the first byte that differs from it and
// returns what was read, so that the format's parser reports it. docs/formats.md lists
// each format's limit.
struct ReadLimits {
    uint64_t max_bytes = uint64_t(4) << 30;
    std::string_view what = "a file";  // "a style file": named in the messages
    bool text = false;
    std::string_view magic = {};
};

// Reads a whole file within `limits`; throws wisp::Error naming the file if it cannot, or if
// the file breaks a limit.
std::string read_file(const std::filesystem::path& path, const ReadLimits& limits = {});

}  // namespace wisp
