#pragma once
// A cooperative cancel token for long stages (the editor's stage cache, issue 16: "the
// newest request wins, stale work is cancelled"). Loops poll cancelled() at coarse steps (a
// layer of joints, a wisp) and return early; the caller then publishes nothing from the run.
// Polling is one relaxed atomic load: cheap enough for every wisp of a parallel loop.
#include <atomic>
#include <cstdint>

namespace wisp {

class CancelToken {
  public:
    // Never cancelled (what the command line and the library's own callers pass).
    CancelToken() = default;
    // Cancelled as soon as `newest` no longer equals `ticket`: a request holds the ticket it
    // drew from a counter, and every newer request bumps the counter.
    CancelToken(const std::atomic<uint64_t>& newest, uint64_t ticket)
        : newest_(&newest), ticket_(ticket) {}

    bool cancelled() const {
        return newest_ && newest_->load(std::memory_order_relaxed) != ticket_;
    }

  private:
    const std::atomic<uint64_t>* newest_ = nullptr;
    uint64_t ticket_ = 0;
};

}  // namespace wisp
