#pragma once
// Wall-clock timing of named stages, reported in --stats.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace wisp {

class Stopwatch {
  public:
    Stopwatch() : start_(std::chrono::steady_clock::now()) {}
    double ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
    }

  private:
    std::chrono::steady_clock::time_point start_;
};

// Ordered (stage name, milliseconds) pairs.
using StageTimes = std::vector<std::pair<std::string, double>>;

}  // namespace wisp
