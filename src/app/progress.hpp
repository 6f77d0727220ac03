#pragma once
// Progress of the command line's long tasks (rendering views, animating frames), on stderr:
// on a terminal, one line rewritten in place; otherwise (a log, CI) a plain line per step,
// at most one every few seconds but always the last, so that a long run never looks hung.
#include <chrono>
#include <iosfwd>
#include <string>

namespace wisp {

class Progress {
  public:
    // `task` names what is counted ("view", "frame"); `total` steps. Silent when quiet.
    // `terminal` defaults to whether stderr is a terminal.
    Progress(std::string task, int total, bool quiet);
    Progress(std::string task, int total, bool quiet, bool terminal, std::ostream& out,
             double interval_seconds = 2.0);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Step `done` (1-based) of total finished; `what` says which (a view's name), may be empty.
    void step(int done, const std::string& what = {});

  private:
    std::string task_;
    int total_;
    bool quiet_, terminal_;
    std::ostream& out_;
    double interval_;
    std::chrono::steady_clock::time_point last_;
    bool open_line_ = false;  // a terminal line to end
};

}  // namespace wisp
