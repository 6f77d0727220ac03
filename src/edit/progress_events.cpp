#include "edit/progress_events.hpp"

#include <httplib.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>

#include <nlohmann/json.hpp>

#include "edit/http_util.hpp"

namespace wisp {
namespace {

// How long a stream stays silent before a keep-alive comment (the write timeout is 30 s).
constexpr std::chrono::milliseconds kKeepAlive{10'000};

}  // namespace

ProgressEvents::Task::Task(ProgressEvents& events, std::string name, int total,
                           std::chrono::milliseconds fraction_interval)
    : events_(events),
      name_(std::move(name)),
      fraction_interval_(fraction_interval),
      fractions_([this](float f) { fraction(f); }),
      total_(total),
      uncaught_(std::uncaught_exceptions()) {}

ProgressEvents::Task::~Task() {
    std::lock_guard lock(mutex_);
    if (error_.empty() && std::uncaught_exceptions() > uncaught_) error_ = "failed";
    ProgressEvent e;
    e.task = name_;
    e.step = error_.empty() ? "done" : "failed";
    e.done = error_.empty() ? total_ : done_;
    e.total = total_;
    e.finished = true;
    e.error = error_;
    events_.post(std::move(e));
}

void ProgressEvents::Task::step(std::string name) {
    std::lock_guard lock(mutex_);
    ProgressEvent e;
    e.task = name_;
    e.step = step_ = std::move(name);
    e.done = done_;
    e.total = total_;
    done_ = std::min(done_ + 1, total_);
    fraction_ = 0.f;
    posted_ = std::chrono::steady_clock::now();
    events_.post(std::move(e));
}

void ProgressEvents::Task::fraction(float f) {
    f = std::min(f, 1.f);
    std::lock_guard lock(mutex_);
    // Reports come from several workers, out of order: only a rise counts.
    if (step_.empty() || !(f > fraction_)) return;
    const auto now = std::chrono::steady_clock::now();
    if (f < 1.f && now - posted_ < fraction_interval_) return;
    ProgressEvent e;
    e.task = name_;
    e.step = step_;
    e.done = std::max(done_ - 1, 0);
    e.total = total_;
    e.fraction = f;
    fraction_ = f;
    posted_ = now;
    events_.post(std::move(e));
}

StageProgress ProgressEvents::Task::stages() {
    return [this](Stage stage) { step(stage_name(stage)); };
}

void ProgressEvents::post(ProgressEvent event) {
    {
        std::lock_guard lock(mutex_);
        event.id = ++last_id_;
        kept_.push_back(std::move(event));
        if (kept_.size() > kKept) kept_.pop_front();
    }
    changed_.notify_all();
}

std::deque<ProgressEvent> ProgressEvents::wait(uint64_t seen, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return closed_ || last_id_ > seen; });
    std::deque<ProgressEvent> out;
    if (closed_) return out;
    for (const ProgressEvent& e : kept_)
        if (e.id > seen) out.push_back(e);
    return out;
}

uint64_t ProgressEvents::last_id() const {
    std::lock_guard lock(mutex_);
    return last_id_;
}

void ProgressEvents::close() {
    {
        std::lock_guard lock(mutex_);
        closed_ = true;
    }
    changed_.notify_all();
}

bool ProgressEvents::closed() const {
    std::lock_guard lock(mutex_);
    return closed_;
}

std::string ProgressEvents::frame(const ProgressEvent& e) {
    nlohmann::json data{{"task", e.task},
                        {"step", e.step},
                        {"fraction", std::round(1000.0 * e.fraction) / 1000.0},
                        {"done", e.done},
                        {"total", e.total},
                        {"finished", e.finished}};
    if (!e.error.empty()) data["error"] = e.error;
    // One line of JSON: no newline can end the data field early.
    return "id: " + std::to_string(e.id) + "\nevent: progress\ndata: " +
           data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n\n";
}

void add_progress_route(httplib::Server& server, ProgressEvents& events) {
    server.Get("/api/events", [&events](const httplib::Request&, httplib::Response& res) {
        if (++events.listeners > ProgressEvents::kMaxListeners) {
            --events.listeners;
            return send_error(res, 503, "too many progress streams open");
        }
        // The stream starts from now: a listener sees the runs that start after it opens.
        auto seen = std::make_shared<uint64_t>(events.last_id());
        auto greeted = std::make_shared<bool>(false);
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream",
            [&events, seen, greeted](size_t, httplib::DataSink& sink) {
                if (!*greeted) {
                    *greeted = true;
                    const std::string hello = ": connected\n\n";
                    return sink.write(hello.data(), hello.size());
                }
                if (events.closed()) {
                    sink.done();
                    return true;
                }
                std::string out;
                for (const ProgressEvent& e : events.wait(*seen, kKeepAlive)) {
                    out += ProgressEvents::frame(e);
                    *seen = e.id;
                }
                if (events.closed()) {
                    sink.done();
                    return true;
                }
                if (out.empty()) out = ": keep-alive\n\n";
                return sink.write(out.data(), out.size());
            },
            [&events](bool) { --events.listeners; });
    });
}

}  // namespace wisp
