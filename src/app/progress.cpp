#include "app/progress.hpp"

#include <unistd.h>

#include <iostream>
#include <utility>

namespace wisp {

Progress::Progress(std::string task, int total, bool quiet)
    : Progress(std::move(task), total, quiet, isatty(STDERR_FILENO) != 0, std::cerr) {}

Progress::Progress(std::string task, int total, bool quiet, bool terminal, std::ostream& out,
                   double interval_seconds)
    : task_(std::move(task)),
      total_(total),
      quiet_(quiet || total <= 1),
      terminal_(terminal),
      out_(out),
      interval_(interval_seconds),
      last_(std::chrono::steady_clock::now() - std::chrono::hours(1)) {}  // the first step shows

Progress::~Progress() {
    if (open_line_) out_ << '\n' << std::flush;
}

void Progress::step(int done, const std::string& what) {
    if (quiet_) return;
    const std::string line = "wisp: " + task_ + " " + std::to_string(done) + "/" +
                             std::to_string(total_) + (what.empty() ? "" : " (" + what + ")");
    if (terminal_) {
        out_ << "\r" << line << "\x1b[K" << std::flush;
        open_line_ = done < total_;
        if (!open_line_) out_ << '\n' << std::flush;
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && std::chrono::duration<double>(now - last_).count() < interval_) return;
    last_ = now;
    out_ << line << '\n' << std::flush;
}

}  // namespace wisp
