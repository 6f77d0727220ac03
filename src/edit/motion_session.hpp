#pragma once
// The editor's Motion mode (issue 17): the current style's hair as the rest shape, the
// Adaptive Wisp Tree stepping in its own thread at a fixed time step, and the newest frame of
// the shown strands ready for the browser.
//
// The simulation thread runs frame after frame at the animation's frame rate (never faster
// than real time; slower when a frame costs more than its interval). At every frame boundary
// it takes the newest input: a drag target, a preset playing, or nothing (the head holds).
// Input therefore lands on a frame the thread chooses, but it is recorded there
// (LiveMotion), so the recording replayed by `wisp animate --motion` gives the frames the
// browser saw, byte for byte. A slow client is given the newest frame and skips the others;
// the simulation never waits for it.
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "dynamics/animate.hpp"
#include "dynamics/live_motion.hpp"

namespace wisp {

struct MotionSessionSettings {
    double fps = 25;
    size_t shown_strands = 20000;  // the first ones in strand_order (wire.hpp)
    // Passed to the Animator (held lengths of ties).
    std::vector<float> wisp_held;
    bool single_level = false;
};

struct MotionFrame {
    uint32_t index = 0;
    std::string bytes;  // encode_frame
    // Head space → world at this frame, of the head and the body (the view poses the mesh as
    // pose_body does).
    RigidTransform head, body;
    // The session's splits and merges numbered from 0 (every step's): this frame's end here.
    uint64_t events_end = 0;
};

// One message of the frame stream (GET /api/motion/stream), little-endian, every part a
// multiple of 4 bytes:
//   uint32 length                  the bytes that follow
//   "WISPMOTN"                     8 bytes
//   uint32 version (1), frame index, frame bytes F, tree bytes T, events E
//   float32 head[12], body[12]     head space → world: rotation row by row, translation cm
//   frame[F]                       encode_frame
//   tree[T]                        encode_tree of the same frame (T = 0 unless asked for)
//   float32 events[4·E]            every step's splits and merges since the stream's last
//                                  message (frames skipped included, the newest
//                                  kMotionEventsKept at most): x, y, z (cm, world), kind (0
//                                  split, 1 merge)
constexpr size_t kMotionEventsKept = 4096;

// The active part of the Adaptive Wisp Tree for the tree view (Bertails et al. Fig. 4):
//   "WISPTREE"                 8 bytes
//   uint32 version (1), frame index, active nodes N, levels L, events E
//   float32 positions[3·N]     cm, world: each active node (k ≥ 1), root to tip
//   float32 parents[3·N]       cm, world: its AWT parent (a root node for k = 1): segment ends
//   float32 radius[N]          cm, the node's cross-section radius
//   uint32 level[N]            0 = coarsest
//   uint32 per_level[L]        active nodes per level (AwtSimulation::active_per_level)
//   float32 events[4·E]        `events`: the splits and merges of every step of the frame
//                              (Animator::frame_events): x, y, z (cm, world), kind (0 split,
//                              1 merge)
// little-endian. Call after sim.sync(). Reuses `out`'s memory.
void encode_tree(uint32_t frame, const AwtSimulation& sim, std::span<const PlacedAwtEvent> events,
                 std::string& out);

class MotionSession {
  public:
    // Copies what it needs; builds the hierarchy (may take a moment; throws wisp::Error on
    // bad dynamics parameters). Starts paused at frame 0, the rest pose, already published.
    MotionSession(const Hair& rest, const Mesh& body, const HeadFrame& head,
                  const DynamicsSpec& dynamics, PrototypeSpec::Kind prototype,
                  MotionSessionSettings settings);
    ~MotionSession();  // stops the thread
    MotionSession(const MotionSession&) = delete;
    MotionSession& operator=(const MotionSession&) = delete;

    void play();
    // Returns once a frame being computed is published: nothing changes while paused.
    void pause();
    bool playing() const;
    // One frame while paused; returns once it is published.
    void step();

    // The head dragged to a pose about the neck (head_pivot(); rotation in degrees,
    // translation in cm); the body moves with the head's translation only. Cancels a preset.
    void drag(const Vec3f& rotate, const Vec3f& translate);
    // Plays a motion preset from the next frame (its poses, taken about this session's
    // pivots; a head dragged away goes to the preset's first pose within two frames), then
    // holds its last pose. Throws wisp::Error for an unknown name.
    void play_preset(const std::string& name);
    // Plays a motion file's text (docs/animate.md's JSON, as `wisp animate --motion` reads it)
    // the same way: its head and body tracks about this session's pivots, and its wind when
    // it has one. Throws wisp::Error naming `source` and the field for a malformed file.
    void play_motion_file(const std::string& text, const std::string& source);
    void set_wind(const Vec3f& wind, float gust_amplitude = 0, float gust_frequency = 0.5f);
    // The style's dynamics changed: applied at the next frame boundary (Animator::
    // set_dynamics: the parameters read at every step; the hierarchy's, links, dt and voxel
    // stay as the session started). Throws wisp::Error for values the simulation refuses
    // (friction · dt ≥ 1). Like wind, it is not keyed: a recording replays with the last ones.
    void set_dynamics(const DynamicsSpec& dynamics);

    // The newest published frame if its index is past `after` (or any frame when `after` is
    // empty), waiting up to `wait_ms` for one.
    std::optional<MotionFrame> frame_after(std::optional<uint32_t> after, int wait_ms) const;
    // The frame stream's next message (the format above) into `out`: the newest frame if its
    // index is past `after` (any frame when empty), waiting up to `wait_ms` for one; with its
    // tree when `tree` (call tree() once first), and the events numbered from `events_from`
    // on, which moves past them. False when no frame came. The newest frame only: a slow
    // stream skips frames, never queues them.
    bool stream_message(std::optional<uint32_t> after, bool tree, int wait_ms,
                        uint64_t& events_from, std::string& out) const;
    uint32_t frames_published() const;
    // The splits and merges published so far (MotionFrame::events_end of the newest frame).
    uint64_t events_published() const;
    // An error that stopped the simulation (it diverged), or empty.
    std::string error() const;
    // Active nodes per level and split/merge counts of the newest frame.
    std::vector<uint32_t> active_per_level() const;
    AnimationStats stats() const;

    // The Adaptive Wisp Tree of the newest frame (encode_tree), for the tree view (Fig. 4).
    // The first call turns it on: from then on every frame encodes its tree too (a few
    // hundred to a few thousand active nodes, well under a millisecond). Waits for a frame
    // being computed to finish.
    MotionFrame tree();

    // The recording so far as a motion file; and the `wisp animate` command line that replays
    // it (frames and fps).
    void write_recording(const std::filesystem::path& path) const;
    std::string replay_arguments() const;

    Vec3f head_pivot() const { return live_.head_pivot(); }
    const std::vector<uint32_t>& shown() const { return shown_; }

  private:
    void run();
    void advance_locked(std::unique_lock<std::mutex>& lock);
    void play(Motion motion);

    HeadFrame head_;
    Hair rest_;
    Mesh body_;
    LiveMotion live_;
    std::unique_ptr<Animator> animator_;
    std::vector<uint32_t> shown_;
    size_t shown_points_ = 0;  // the shown strands' points
    double interval_;

    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    bool playing_ = false, stop_ = false;
    // The thread is inside advance_locked() with the lock released: the animator is its.
    bool advancing_ = false;
    bool tree_wanted_ = false;
    MotionFrame tree_;
    int steps_requested_ = 0;
    // Input for the next frame boundary.
    std::optional<MotionKey> drag_head_, drag_body_;
    std::optional<Motion> preset_;
    int preset_start_ = 0;
    struct Wind {
        Vec3f wind;
        float amplitude, frequency;
    };
    std::optional<Wind> pending_wind_;
    std::optional<DynamicsSpec> pending_dynamics_;
    PrototypeSpec::Kind prototype_;
    bool single_level_;
    double dt_;  // the simulation's step, s
    MotionFrame frame_;
    // The newest kMotionEventsKept events, event n at n % kMotionEventsKept (frame_.events_end
    // of them so far).
    std::vector<PlacedAwtEvent> events_;
    std::string spare_;  // the frame before, its memory reused for the next
    std::vector<uint32_t> active_per_level_;
    AnimationStats stats_;
    std::string error_;
    std::thread thread_;
};

}  // namespace wisp
