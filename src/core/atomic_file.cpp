#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
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
#include <system_error>
#include <thread>

#include "core/error.hpp"

namespace wisp {
namespace {

// The temporaries open now, for the signal handler: a fixed table (no allocation in the
// handler), each slot free (0), being filled (1) or holding a path (2). A path too long or a
// table full goes unregistered: the file is then only removed on unwinding, as before.
constexpr int kMaxTemporaries = 64;
constexpr size_t kMaxTemporaryPath = 4096;
struct TemporarySlot {
    std::atomic<int> state{0};
    char path[kMaxTemporaryPath];
};
TemporarySlot g_temporaries[kMaxTemporaries];

// File series (FileSeries): a prefix, a suffix, a digit count and how many files exist, so
// the handler rebuilds each name without allocating.
constexpr int kMaxSeries = 8;
constexpr size_t kMaxSeriesSuffix = 64;
struct SeriesSlot {
    std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
    std::atomic<size_t> count{0};
    int digits = 0;
    size_t prefix_size = 0;
    char prefix[kMaxTemporaryPath];
    char suffix[kMaxSeriesSuffix];
};
SeriesSlot g_series[kMaxSeries];

// `<prefix><i zero-padded to digits><suffix>` into out (async-signal-safe); false if too long.
bool series_name(const SeriesSlot& s, size_t i, char* out, size_t cap) {
    char digits[24];
    int n = 0;
    do {
        digits[n++] = static_cast<char>('0' + i % 10);
        i /= 10;
    } while (i > 0 && n < 20);
    while (n < s.digits && n < 20)
        digits[n++] = '0';
    const size_t suffix = std::strlen(s.suffix);
    if (s.prefix_size + static_cast<size_t>(n) + suffix + 1 > cap) return false;
    std::memcpy(out, s.prefix, s.prefix_size);
    for (int k = 0; k < n; ++k)
        out[s.prefix_size + static_cast<size_t>(k)] = digits[n - 1 - k];
    std::memcpy(out + s.prefix_size + static_cast<size_t>(n), s.suffix, suffix + 1);
    return true;
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[std::size(kSignals)];

// Async-signal-safe: unlink, sigaction and raise only.
extern "C" void remove_temporaries(int sig) {
    for (TemporarySlot& slot : g_temporaries)
        if (slot.state.load() == 2) ::unlink(slot.path);
    for (SeriesSlot& series : g_series) {
        if (series.state.load() != 2) continue;
        char name[kMaxTemporaryPath + kMaxSeriesSuffix + 24];
        for (size_t i = 0, n = series.count.load(); i < n; ++i)
            if (series_name(series, i, name, sizeof name)) ::unlink(name);
    }
    for (size_t i = 0; i < std::size(kSignals); ++i)
        if (kSignals[i] == sig) ::sigaction(sig, &g_previous[i], nullptr);
    // Delivered with the previous action (by default: terminate) once this handler returns.
    ::raise(sig);
}

void install_handlers() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (size_t i = 0; i < std::size(kSignals); ++i) {
            struct sigaction action {};
            action.sa_handler = remove_temporaries;
            sigemptyset(&action.sa_mask);
            for (int s : kSignals)
                sigaddset(&action.sa_mask, s);  // one handler at a time
            ::sigaction(kSignals[i], &action, &g_previous[i]);
            // A signal the caller ignores (nohup, a background job) stays ignored.
            if (g_previous[i].sa_handler == SIG_IGN)
                ::sigaction(kSignals[i], &g_previous[i], nullptr);
        }
    });
}

// Returns the slot registered, or -1.
int register_temporary(const std::filesystem::path& path) {
    const std::string& native = path.native();
    if (native.size() >= kMaxTemporaryPath) return -1;
    install_handlers();
    for (int i = 0; i < kMaxTemporaries; ++i) {
        int expected = 0;
        if (g_temporaries[i].state.compare_exchange_strong(expected, 1)) {
            std::memcpy(g_temporaries[i].path, native.c_str(), native.size() + 1);
            g_temporaries[i].state.store(2);
            return i;
        }
    }
    return -1;
}

void unregister_temporary(int slot) {
    if (slot >= 0) g_temporaries[slot].state.store(0);
}

// Puts the file `from` in place of `to`, atomically. Over an existing file the two names are
// exchanged (renameat2's RENAME_EXCHANGE) and the old file, now at `from`, is unlinked:
// rename(2) over an existing file on ext4 also starts writing the new file back inside the
// call (auto_da_alloc, a guard for programs that replace files without fsync; wisp does not
// promise durability on power loss), 120–310 ms for a 174 MB .usda on a loaded machine. The
// old file's pages are freed when its last descriptor closes (15–20 ms for the same): a
// descriptor held across the unlink is closed on a thread of its own, so that work overlaps
// whatever comes next (at exit, the kernel closes it). Where exchange is not supported, or
// `to` is not a regular file, a plain rename (which fails on a folder, as it should).
void replace_file(const std::filesystem::path& from, const std::filesystem::path& to) {
    struct stat target {};
    if (::lstat(to.c_str(), &target) == 0 && S_ISREG(target.st_mode)) {
        const int old = ::open(to.c_str(), O_PATH | O_NOFOLLOW | O_CLOEXEC);
        if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) == 0) {
            ::unlink(from.c_str());
            if (old < 0) return;
            try {
                std::thread([old] { ::close(old); }).detach();
            } catch (const std::system_error&) {  // no thread to be had: close it here
                ::close(old);
            }
            return;
        }
        if (old >= 0) ::close(old);
    }
    std::error_code ec;
    std::filesystem::rename(from, to, ec);
    if (ec) fail(to.string(), ": cannot rename temporary file: ", ec.message());
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
    tmp_ = path_;
    tmp_ += cat(".tmp-", ::getpid());
    if (path_.has_parent_path() && !std::filesystem::exists(path_.parent_path())) {
        std::error_code ec;
        std::filesystem::create_directories(path_.parent_path(), ec);
        if (ec) fail(path_.string(), ": cannot create folder: ", ec.message());
    }
    slot_ = register_temporary(tmp_);  // before the file exists: a signal never misses it
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (out_) fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CLOEXEC);
    if (!out_ || fd_ < 0) {
        const int error = errno;
        if (out_) {
            out_.close();
            std::error_code ec;
            std::filesystem::remove(tmp_, ec);
        }
        unregister_temporary(slot_);
        fail(path_.string(), ": cannot open for writing: ", std::strerror(error));
    }
}

AtomicFile::~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) {
        out_.close();
        std::error_code ec;
        std::filesystem::remove(tmp_, ec);
    }
    unregister_temporary(slot_);
}

void AtomicFile::write_at(const char* data, size_t n, uint64_t offset) {
    while (n > 0) {
        const ssize_t wrote = ::pwrite(fd_, data, n, static_cast<off_t>(offset));
        if (wrote < 0 && errno == EINTR) continue;
        if (wrote <= 0)
            fail(path_.string(), ": write failed at byte ", offset, ": ",
                 wrote < 0 ? std::strerror(errno) : "no byte written");
        data += wrote;
        n -= static_cast<size_t>(wrote);
        offset += static_cast<uint64_t>(wrote);
    }
}

void AtomicFile::commit() {
    out_.flush();
    if (!out_) fail(path_.string(), ": write failed");
    out_.close();
    if (out_.fail()) fail(path_.string(), ": write failed on close");
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(path_.string(), ": write failed on close: ", std::strerror(errno));
    replace_file(tmp_, path_);
    committed_ = true;
    unregister_temporary(slot_);
    slot_ = -1;
}

FileSeries::FileSeries(std::string prefix, std::string suffix, int digits)
    : prefix_(std::move(prefix)), suffix_(std::move(suffix)), digits_(digits) {
    if (prefix_.size() >= kMaxTemporaryPath || suffix_.size() >= kMaxSeriesSuffix) return;
    install_handlers();
    for (int i = 0; i < kMaxSeries; ++i) {
        int expected = 0;
        if (g_series[i].state.compare_exchange_strong(expected, 1)) {
            SeriesSlot& s = g_series[i];
            s.count.store(0);
            s.digits = digits_;
            s.prefix_size = prefix_.size();
            std::memcpy(s.prefix, prefix_.data(), prefix_.size());
            std::memcpy(s.suffix, suffix_.c_str(), suffix_.size() + 1);
            s.state.store(2);
            slot_ = i;
            return;
        }
    }
}

FileSeries::~FileSeries() {
    if (slot_ >= 0) g_series[slot_].state.store(0);
    if (kept_) return;
    for (size_t i = 0; i < count_; ++i) {
        std::error_code ec;
        std::filesystem::remove(path(i), ec);
    }
}

std::filesystem::path FileSeries::path(size_t i) const {
    std::string n = std::to_string(i);
    if (n.size() < static_cast<size_t>(digits_))
        n.insert(0, static_cast<size_t>(digits_) - n.size(), '0');
    return prefix_ + n + suffix_;
}

void FileSeries::added(size_t i) {
    count_ = std::max(count_, i + 1);
    if (slot_ >= 0) g_series[slot_].count.store(count_);
}

void FileSeries::keep() {
    kept_ = true;
    if (slot_ >= 0) g_series[slot_].state.store(0);
    slot_ = -1;
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
    size_t got = 0, scanned = 0;          // bytes read; bytes checked for NUL
    size_t nul = std::string_view::npos;  // the first NUL: where the text ends
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
            nul =
                check_nul_padding(path, limits, std::string_view(bytes.data(), got), scanned, nul);
            scanned = got;
        }
    }
    if (std::ferror(f.get())) fail(path.string(), ": read failed: ", std::strerror(errno));
    if (got > limits.max_bytes) too_large();
    bytes.resize(nul != std::string_view::npos ? nul : got);
    return bytes;
}

size_t check_nul_padding(const std::filesystem::path& path, const ReadLimits& limits,
                         std::string_view bytes, size_t from, size_t nul) {
    if (nul == std::string_view::npos) {
        nul = bytes.find('\0', from);
        if (nul == std::string_view::npos) return nul;
        from = nul;
    }
    const bool padding = nul > 0 && bytes.size() - nul <= kMaxNulPadding &&
                         std::all_of(bytes.begin() + static_cast<std::ptrdiff_t>(from), bytes.end(),
                                     [](char c) { return c == '\0'; });
    if (!padding)
        fail(path.string(), ": byte ", nul, " is a NUL byte, which ", limits.what,
             " (text) never holds");
    return nul;
}

}  // namespace wisp
