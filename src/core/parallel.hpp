#pragma once
// Parallel loops on oneTBB. Bodies write only to their own indices, so results never
// depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <memory>

namespace wisp {

// Calls body(i) for i in [0, n) in parallel, in chunks of at least `grain`.
template <typename Body>
void parallel_for(size_t n, Body&& body, size_t grain = 1) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i)
                              body(i);
                      });
}

// Limits the worker threads for its lifetime (0 = all cores).
class ThreadLimit {
  public:
    explicit ThreadLimit(int threads) {
        if (threads > 0)
            control_ = std::make_unique<tbb::global_control>(
                tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    }

  private:
    std::unique_ptr<tbb::global_control> control_;
};

}  // namespace wisp
