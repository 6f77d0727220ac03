#pragma once
// Progress of the editor's long runs (issue 16: server-sent events for progress): a
// full-density update, a preview, the final picture, an export. The route running one posts a
// step as each of its stages starts, and the fraction of a long stage done as it runs (the
// solve's layers, the members' wisps: CancelToken::progress); GET /api/events streams them to
// the page as text/event-stream (cpp-httplib's chunked content provider), which shows a
// progress bar.
//
//   GET /api/events     text/event-stream: first ": connected", then for each step
//                       `id: N` / `event: progress` / `data: {"task": "export", "step":
//                       "solve", "fraction": 0.4, "done": 3, "total": 8, "finished":
//                       false}` (fraction: of the step, 0 as it starts), and a
//                       ": keep-alive" comment when nothing happened for a while. The same
//                       Host, Origin and token checks as every /api/ route (the token as
//                       ?token=, since EventSource sends no headers); at most kMaxListeners
//                       streams at once (503 beyond: each holds one of the server's threads).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "core/cancel.hpp"
#include "edit/stage_cache.hpp"

namespace httplib {
class Server;
}

namespace wisp {

struct ProgressEvent {
    uint64_t id = 0;   // 1, 2, … in the order posted
    std::string task;  // "update", "render", "export"
    std::string step;  // the stage starting ("solve"), or the task's own last step ("write")
    int done = 0;      // steps done before this one, of `total`
    int total = 0;
    float fraction = 0.f;   // of this step, done so far: 0 as it starts, up to 1
    bool finished = false;  // the task ended (done == total, or failed with `error`)
    std::string error;
};

class ProgressEvents {
  public:
    static constexpr int kMaxListeners = 4;
    // Events a listener that fell behind can still catch up on.
    static constexpr size_t kKept = 64;
    // A step's fraction is posted at most this often (and always when it reaches 1).
    static constexpr std::chrono::milliseconds kFractionInterval{50};

    // A task of `total` steps (its stages and its own) reporting through `post`.
    class Task {
      public:
        Task(ProgressEvents& events, std::string name, int total,
             std::chrono::milliseconds fraction_interval = kFractionInterval);
        ~Task();  // finished (failed when fail() was called or an exception ends it)
        Task(const Task&) = delete;
        Task& operator=(const Task&) = delete;
        // The next step starts.
        void step(std::string name);
        void fail(std::string error) { error_ = std::move(error); }
        // A StageCache progress callback: each stage that runs is a step.
        StageProgress stages();
        // The running step's fraction done (a CancelToken's report, called from any thread):
        // posted when it rose, at most every `fraction_interval`, and when it reaches 1.
        const FractionReport* fractions() const { return &fractions_; }

      private:
        void fraction(float f);

        ProgressEvents& events_;
        std::string name_;
        std::chrono::milliseconds fraction_interval_;
        FractionReport fractions_;
        std::mutex mutex_;  // guards what follows: fractions come from the workers
        int done_ = 0, total_ = 0;
        std::string step_;                              // the running step
        float fraction_ = 0.f;                          // its fraction last posted
        std::chrono::steady_clock::time_point posted_;  // when
        std::string error_;
        int uncaught_ = 0;  // exceptions in flight when it started: more at the end, it failed
    };

    void post(ProgressEvent event);  // its id is set here
    // The events after `seen`, waiting up to `timeout` for one; empty on timeout or close.
    std::deque<ProgressEvent> wait(uint64_t seen, std::chrono::milliseconds timeout);
    uint64_t last_id() const;
    // Wakes every listener for good (the server stops).
    void close();
    bool closed() const;

    // The text/event-stream frame of an event.
    static std::string frame(const ProgressEvent& event);

    std::atomic<int> listeners{0};

  private:
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<ProgressEvent> kept_;
    uint64_t last_id_ = 0;
    bool closed_ = false;
};

// GET /api/events (the server's pre-routing checks guard it as every /api/ path).
void add_progress_route(httplib::Server& server, ProgressEvents& events);

}  // namespace wisp
