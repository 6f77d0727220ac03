#pragma once
// Outputs are written to a temporary file beside the target and renamed over it on
// commit(), so an interrupted run never leaves a truncated file behind. Open temporaries
// are registered: SIGINT, SIGTERM and SIGHUP remove them before the process dies.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
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
    // Writes n bytes at `offset` of the file (pwrite: no shared file position, so blocks may
    // be written in any order and from any thread). Throws wisp::Error naming the file if it
    // cannot. For writers that compute where each block goes; do not mix with stream().
    void write_at(const char* data, size_t n, uint64_t offset);
    // Flushes, checks for write errors, and renames onto the target.
    void commit();

  private:
    std::filesystem::path path_, tmp_;
    std::ofstream out_;
    int fd_ = -1;  // write_at's descriptor of the temporary, opened by the constructor
    bool committed_ = false;
    int slot_ = -1;  // in the table of temporaries the signal handler removes
};

// Numbered files written one after another (an animation's frames, `<prefix><i><suffix>`
// with i zero-padded to `digits`), removed together unless kept: by the destructor, and by
// the signal handler above on SIGINT, SIGTERM and SIGHUP, so an interrupted run leaves none
// of them behind. Write each file with an AtomicFile at path(i), then call added(i).
class FileSeries {
  public:
    FileSeries(std::string prefix, std::string suffix, int digits);
    ~FileSeries();  // removes files 0 .. count-1 unless kept
    FileSeries(const FileSeries&) = delete;
    FileSeries& operator=(const FileSeries&) = delete;

    std::filesystem::path path(size_t i) const;
    void added(size_t i);  // files 0 .. i exist now
    void keep();           // the series is complete: nothing is removed

  private:
    std::string prefix_, suffix_;
    int digits_;
    size_t count_ = 0;
    bool kept_ = false;
    int slot_ = -1;
};

// Writes `bytes` to path atomically.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Calls write(stream) on an AtomicFile for path, then commits.
void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write);

// What a reader accepts of a file, checked while it reads, not from the file's size (endless
// files such as /dev/zero or a pipe report 0): at most max_bytes; for text formats no NUL
// byte, but for NUL padding that ends the file (kMaxNulPadding); and, when magic is given,
// reading stops at the first byte that differs from it and returns what was read, so that
// the format's parser reports it. docs/formats.md lists each format's limit.
struct ReadLimits {
    uint64_t max_bytes = uint64_t(4) << 30;
    std::string_view what = "a file";  // "a style file": named in the messages
    bool text = false;
    std::string_view magic = {};
};

// Text that exporters pad with NUL bytes to a block (three.js's LeePerrySmith.obj ends in
// one) is read as the text before them, as Blender and three.js read it: up to this many
// bytes of padding, after some text. Any other NUL (at byte 0, followed by text, or more
// padding than this, as /dev/zero is) makes a text file fail at the NUL.
constexpr uint64_t kMaxNulPadding = 65536;

// For a text file's bytes [0, size) read so far, `nul` its first NUL byte (or npos, looked
// for from `from`): fails naming `path` unless [nul, size) may be padding. Returns the first
// NUL's position (npos: none yet), which the next call takes as `nul`.
size_t check_nul_padding(const std::filesystem::path& path, const ReadLimits& limits,
                         std::string_view bytes, size_t from, size_t nul);

// Reads a whole file within `limits`; throws wisp::Error naming the file if it cannot, or if
// the file breaks a limit.
std::string read_file(const std::filesystem::path& path, const ReadLimits& limits = {});

}  // namespace wisp
