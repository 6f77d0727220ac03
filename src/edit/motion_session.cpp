#include "edit/motion_session.hpp"

#include <chrono>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "edit/wire.hpp"

namespace wisp {

namespace {

template <class T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // the wire is little-endian, as this machine
    out.append(bytes, sizeof(T));
}

void put_event(std::string& out, const PlacedAwtEvent& e) {
    for (int c = 0; c < 3; ++c)
        put<float>(out, e.at[c]);
    put<float>(out, e.kind == AwtEvent::Kind::kSplit ? 0.f : 1.f);
}

void put_pose(std::string& out, const RigidTransform& t) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            put<float>(out, t.rotation(r, c));
    for (int c = 0; c < 3; ++c)
        put<float>(out, t.translation[c]);
}

}  // namespace

void encode_tree(uint32_t frame, const AwtSimulation& sim, std::span<const PlacedAwtEvent> events,
                 std::string& out) {
    const Hierarchy& h = sim.hierarchy();
    const std::vector<uint32_t>& active = sim.active();
    const std::span<const Vec3f> x = sim.positions();
    const std::vector<uint32_t> per_level = sim.active_per_level();
    out.clear();
    out.reserve(28 + active.size() * 32 + per_level.size() * 4 + events.size() * 16);
    out += "WISPTREE";
    put<uint32_t>(out, 2);  // 2: the events of every step of the frame, not the last step's
    put<uint32_t>(out, frame);
    put<uint32_t>(out, static_cast<uint32_t>(active.size()));
    put<uint32_t>(out, static_cast<uint32_t>(per_level.size()));
    put<uint32_t>(out, static_cast<uint32_t>(events.size()));
    for (const uint32_t n : active)
        for (int c = 0; c < 3; ++c)
            put<float>(out, x[n][c]);
    for (const uint32_t n : active)
        for (int c = 0; c < 3; ++c)
            put<float>(out, x[sim.parent(n)][c]);
    for (const uint32_t n : active)
        put<float>(out, sim.radius(n));
    for (const uint32_t n : active)
        put<uint32_t>(out, h.level[h.gc_of(n)]);
    for (const uint32_t count : per_level)
        put<uint32_t>(out, count);
    for (const PlacedAwtEvent& e : events)
        put_event(out, e);
}

MotionSession::MotionSession(const Hair& rest, const Mesh& body, const HeadFrame& head,
                             const DynamicsSpec& dynamics, PrototypeSpec::Kind prototype,
                             MotionSessionSettings settings)
    : head_(head),
      rest_(rest),
      body_(body),
      live_(head, settings.fps),
      interval_(1.0 / settings.fps),
      prototype_(prototype),
      single_level_(settings.single_level) {
    AnimateSettings animate;
    animate.fps = settings.fps;
    animate.single_level = settings.single_level;
    animate.wisp_held = std::move(settings.wisp_held);
    animate.frame_stats = false;
    animate.frame_events = kMotionEventsKept;
    animator_ = std::make_unique<Animator>(rest_, body_, head_, live_.motion(), dynamics, prototype,
                                           animate);
    dt_ = animator_->stats().dt;
    const std::vector<uint32_t> order = strand_order(rest_.strand_count());
    shown_.assign(order.begin(), order.begin() + static_cast<ptrdiff_t>(std::min(
                                                     settings.shown_strands, order.size())));
    for (uint32_t s : shown_)
        shown_points_ += rest_.strand_size(s);
    // Frame 0: the rest pose.
    animator_->advance();
    animator_->skin(shown_, begin_frame(0, shown_points_, frame_.bytes));
    frame_.head = animator_->pose().head;
    frame_.body = animator_->pose().body;
    active_per_level_ = animator_->simulation().active_per_level();
    stats_ = animator_->stats();
    events_.resize(kMotionEventsKept);
    thread_ = std::thread([this] { run(); });
}

MotionSession::~MotionSession() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    changed_.notify_all();
    thread_.join();
}

void MotionSession::play() {
    std::lock_guard lock(mutex_);
    playing_ = true;
    changed_.notify_all();
}

void MotionSession::pause() {
    std::unique_lock lock(mutex_);
    playing_ = false;
    changed_.notify_all();
    // A frame being computed is published before this returns: paused, the frame count and
    // the recording stay as they are (an export reads both).
    changed_.wait(lock, [&] { return !advancing_ || stop_; });
}

bool MotionSession::playing() const {
    std::lock_guard lock(mutex_);
    return playing_;
}

void MotionSession::step() {
    std::unique_lock lock(mutex_);
    if (playing_ || !error_.empty()) return;
    const uint32_t target = frame_.index + 1;
    ++steps_requested_;
    changed_.notify_all();
    changed_.wait(lock, [&] { return stop_ || frame_.index >= target || !error_.empty(); });
}

void MotionSession::drag(const Vec3f& rotate, const Vec3f& translate) {
    MotionKey head, body;
    head.rotate = rotate;
    head.translate = translate;
    body.translate = translate;
    // Checked here, so a bad value is the caller's error and not the simulation thread's.
    check_live_key(head, "head");
    std::lock_guard lock(mutex_);
    drag_head_ = head;
    drag_body_ = body;
    preset_.reset();
}

void MotionSession::play_preset(const std::string& name) {
    play(motion_preset(name, head_));
}

void MotionSession::play_motion_file(const std::string& text, const std::string& source) {
    play(parse_motion(text, source, head_));
}

void MotionSession::play(Motion motion) {
    if (motion.wind != Vec3f::Zero() || motion.gust_amplitude != 0)
        set_wind(motion.wind, motion.gust_amplitude, motion.gust_frequency);
    std::lock_guard lock(mutex_);
    preset_ = std::move(motion);
    preset_start_ = -1;  // set at the next frame boundary
    drag_head_.reset();
    drag_body_.reset();
}

void MotionSession::set_wind(const Vec3f& wind, float gust_amplitude, float gust_frequency) {
    check_wind(wind, gust_amplitude, gust_frequency);
    std::lock_guard lock(mutex_);
    // The thread applies it at the next frame boundary (the motion is its own).
    pending_wind_ = Wind{wind, gust_amplitude, gust_frequency};
}

void MotionSession::set_dynamics(const DynamicsSpec& dynamics) {
    // The checks the thread's set_params would make, here, so a bad value is the caller's.
    const AwtParams p = awt_params(dynamics, prototype_, single_level_);
    if (!(p.friction * dt_ < 1))
        fail("dynamics: friction · dt must be under 1 (§4.2), got ", p.friction, " · ", dt_);
    std::lock_guard lock(mutex_);
    pending_dynamics_ = dynamics;
}

std::optional<MotionFrame> MotionSession::frame_after(std::optional<uint32_t> after,
                                                      int wait_ms) const {
    std::unique_lock lock(mutex_);
    const auto ready = [&] { return !after || frame_.index > *after || stop_; };
    if (!changed_.wait_for(lock, std::chrono::milliseconds(std::max(0, wait_ms)), ready) ||
        (after && frame_.index <= *after))
        return std::nullopt;
    return frame_;
}

bool MotionSession::stream_message(std::optional<uint32_t> after, bool tree, int wait_ms,
                                   uint64_t& events_from, std::string& out) const {
    std::unique_lock lock(mutex_);
    const auto ready = [&] { return !after || frame_.index > *after || stop_; };
    if (!changed_.wait_for(lock, std::chrono::milliseconds(std::max(0, wait_ms)), ready) ||
        (after && frame_.index <= *after))
        return false;
    const uint64_t end = frame_.events_end;
    const uint64_t first =
        std::max(std::min(events_from, end), end - std::min<uint64_t>(end, kMotionEventsKept));
    const std::string_view tree_bytes =
        tree && tree_.index == frame_.index ? std::string_view(tree_.bytes) : std::string_view();
    out.clear();
    put<uint32_t>(out, 0);  // the length, below
    out += "WISPMOTN";
    put<uint32_t>(out, 1);
    put<uint32_t>(out, frame_.index);
    put<uint32_t>(out, static_cast<uint32_t>(frame_.bytes.size()));
    put<uint32_t>(out, static_cast<uint32_t>(tree_bytes.size()));
    put<uint32_t>(out, static_cast<uint32_t>(end - first));
    put_pose(out, frame_.head);
    put_pose(out, frame_.body);
    out += frame_.bytes;
    out += tree_bytes;
    for (uint64_t n = first; n < end; ++n)
        put_event(out, events_[n % kMotionEventsKept]);
    const auto length = static_cast<uint32_t>(out.size() - 4);
    std::memcpy(out.data(), &length, 4);
    events_from = end;
    return true;
}

uint32_t MotionSession::frames_published() const {
    std::lock_guard lock(mutex_);
    return frame_.index + 1;
}

uint64_t MotionSession::events_published() const {
    std::lock_guard lock(mutex_);
    return frame_.events_end;
}

std::string MotionSession::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

std::vector<uint32_t> MotionSession::active_per_level() const {
    std::lock_guard lock(mutex_);
    return active_per_level_;
}

AnimationStats MotionSession::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

MotionFrame MotionSession::tree() {
    std::unique_lock lock(mutex_);
    if (!tree_wanted_) {
        // The animator is the thread's while it advances; between frames it is idle.
        changed_.wait(lock, [&] { return !advancing_ || stop_; });
        tree_wanted_ = true;
        tree_.index = frame_.index;
        encode_tree(frame_.index, animator_->simulation(), animator_->frame_events(), tree_.bytes);
    }
    return tree_;
}

void MotionSession::write_recording(const std::filesystem::path& path) const {
    std::lock_guard lock(mutex_);  // the thread appends keys only under the lock
    live_.write(path);
}

std::string MotionSession::replay_arguments() const {
    std::lock_guard lock(mutex_);
    std::string args = "--fps ";
    args += std::to_string(static_cast<int>(std::lround(1 / interval_)));
    args += " --frames ";
    args += std::to_string(frame_.index + 1);
    return args;
}

void MotionSession::advance_locked(std::unique_lock<std::mutex>& lock) {
    // At the boundary before frame f + 1 (time f·F): this frame's input.
    const int f = live_.frames();
    if (pending_wind_) {
        live_.set_wind(pending_wind_->wind, pending_wind_->amplitude, pending_wind_->frequency);
        pending_wind_.reset();
    }
    if (preset_) {
        if (preset_start_ < 0) preset_start_ = f;
        const double t = (f - preset_start_) * interval_;
        live_.drive(f, key_about(preset_->head, t, live_.head_pivot()),
                    key_about(preset_->body, t, live_.body_pivot()));
        if (t > preset_->duration) preset_.reset();
    } else if (drag_head_) {
        live_.drive(f, *drag_head_, *drag_body_);
    } else {
        live_.hold(f);
    }
    const bool tree = tree_wanted_;
    std::optional<DynamicsSpec> dynamics;
    dynamics.swap(pending_dynamics_);
    advancing_ = true;
    lock.unlock();
    std::string error;
    std::string bytes, tree_bytes;
    RigidTransform head, body;
    std::vector<uint32_t> active;
    AnimationStats stats;
    try {
        if (dynamics) animator_->set_dynamics(*dynamics, prototype_);
        animator_->advance();
        bytes.swap(spare_);
        animator_->skin(
            shown_, begin_frame(static_cast<uint32_t>(animator_->frame()), shown_points_, bytes));
        active = animator_->simulation().active_per_level();
        stats = animator_->stats();
        const FramePose pose = animator_->pose();
        head = pose.head;
        body = pose.body;
        if (tree)
            encode_tree(static_cast<uint32_t>(animator_->frame()), animator_->simulation(),
                        animator_->frame_events(), tree_bytes);
    } catch (const Error& e) {
        error = e.what();
    }
    lock.lock();
    advancing_ = false;
    if (!error.empty()) {
        error_ = error;
        playing_ = false;
    } else {
        spare_.swap(frame_.bytes);
        frame_.bytes.swap(bytes);
        frame_.index = static_cast<uint32_t>(animator_->frame());
        frame_.head = head;
        frame_.body = body;
        active_per_level_ = std::move(active);
        stats_ = std::move(stats);
        // The animator is idle until this thread advances it again.
        for (const PlacedAwtEvent& e : animator_->frame_events())
            events_[frame_.events_end++ % kMotionEventsKept] = e;
        if (tree) {
            tree_.index = frame_.index;
            tree_.bytes.swap(tree_bytes);
        }
    }
    changed_.notify_all();
}

void MotionSession::run() {
    using Clock = std::chrono::steady_clock;
    const auto interval =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_));
    std::unique_lock lock(mutex_);
    auto next = Clock::now();
    while (!stop_) {
        changed_.wait(lock, [&] { return stop_ || playing_ || steps_requested_ > 0; });
        if (stop_) break;
        if (!error_.empty()) {
            playing_ = false;
            steps_requested_ = 0;
            changed_.notify_all();
            continue;
        }
        const bool stepping = !playing_;
        if (stepping) --steps_requested_;
        advance_locked(lock);
        if (stepping) continue;
        // Real time at most: the next frame one interval after this one started, or now
        // when this one took longer.
        next = std::max(next + interval, Clock::now() - interval);
        changed_.wait_until(lock, next, [&] { return stop_ || !playing_; });
        if (!playing_) next = Clock::now();
    }
}

}  // namespace wisp
