#pragma once
// A cooperative cancel token for long stages (the editor's stage cache, issue 16: "the
// newest request wins, stale work is cancelled"). Loops poll cancelled() at coarse steps (a
// layer of joints, a wisp) and return early; the caller then publishes nothing from the run.
// Polling is one relaxed atomic load: cheap enough for every wisp of a parallel loop.
//
// The same coarse steps report how far the stage has come (issue 16: the progress bar moves
// inside a long stage): progress(done, total) passes done/total to the token's report, when
// it has one. Loops call it at a few dozen places per stage (a breadth-first layer of the
// solve on the calling thread; every 1/32 of the members' wisps, from whichever worker
// finished it), so the report may be called from several threads at once and out of order;
// it keeps the largest fraction and throttles (ProgressEvents::Task::fractions).
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace wisp {

// A stage's fraction done, in (0, 1].
using FractionReport = std::function<void(float fraction)>;

class CancelToken {
  public:
    // Never cancelled (what the command line and the library's own callers pass).
    CancelToken() = default;
    // Never cancelled, with a progress report (`report` must outlive the token's use).
    explicit CancelToken(const FractionReport* report) : report_(report) {}
    // Cancelled as soon as `newest` no longer equals `ticket`: a request holds the ticket it
    // drew from a counter, and every newer request bumps the counter.
    CancelToken(const std::atomic<uint64_t>& newest, uint64_t ticket,
                const FractionReport* report = nullptr)
        : newest_(&newest), ticket_(ticket), report_(report) {}

    bool cancelled() const {
        return newest_ && newest_->load(std::memory_order_relaxed) != ticket_;
    }

    // The running stage has done `done` of `total` steps, as a fraction of [lo, hi] of it
    // (part()). Nothing without a report or with total 0.
    void progress(size_t done, size_t total) const {
        if (report_ && *report_ && total > 0)
            (*report_)(lo_ + (hi_ - lo_) * static_cast<float>(done) / static_cast<float>(total));
    }
    // Whether progress() reports anything (a loop can skip counting when not).
    bool reports() const { return report_ && *report_; }
    // The same token for a part of a stage: its progress(done, total) covers the fraction
    // [lo, hi] of the stage's (a stage of two loops reports each as a part).
    CancelToken part(float lo, float hi) const {
        CancelToken t = *this;
        t.lo_ = lo_ + (hi_ - lo_) * lo;
        t.hi_ = lo_ + (hi_ - lo_) * hi;
        return t;
    }

    // The same token without its progress report (work beside a stage that reports its own).
    CancelToken quiet() const {
        CancelToken t = *this;
        t.report_ = nullptr;
        return t;
    }

  private:
    const std::atomic<uint64_t>* newest_ = nullptr;
    uint64_t ticket_ = 0;
    const FractionReport* report_ = nullptr;
    float lo_ = 0.f, hi_ = 1.f;
};

// Counts the steps of a parallel loop and reports every `total / parts` of them (a relaxed
// atomic add per step; the report runs on the worker that completed the share).
class ProgressCounter {
  public:
    ProgressCounter(const CancelToken& token, size_t total, size_t parts = 32)
        : token_(token), total_(total), every_(total / parts > 0 ? total / parts : 1) {}
    void step() {
        if (!token_.reports()) return;
        const size_t done = done_.fetch_add(1, std::memory_order_relaxed) + 1;
        if (done % every_ == 0 || done == total_) token_.progress(done, total_);
    }

  private:
    const CancelToken& token_;
    size_t total_, every_;
    std::atomic<size_t> done_{0};
};

}  // namespace wisp
