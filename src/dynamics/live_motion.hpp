#pragma once
// Motion made while it plays (issue 17: the editor's Motion mode, where the user drags the
// head or starts a preset and the hair follows live), recorded as an ordinary motion
// (motion.hpp) that `wisp animate --motion` replays to the same frames.
//
// The simulation reads its motion at every step's time (awt.hpp), so the live motion is one
// Motion whose tracks gain keys as frames go by. A key appended to a Catmull-Rom track
// changes the tangent of the key before it, so it reshapes the last two segments: live
// input must only ever reshape time the simulation has not reached, or the replay (which
// has every key from the start) would move the head differently than the live run did.
// drive() keeps that rule, called at every frame boundary t = f·F (F = 1/fps) before the
// frame's steps, with where the head and body should be:
//   - steady, moving: the target becomes a key at t + 2F; the key before the last is then
//     at t + F, so only time after t is reshaped;
//   - starting from a stop (the last two keys equal): a hold key at t (when the last key is
//     older), a second hold at t + F and the target at t + 2F; a key equal to the one before
//     it has a zero tangent (motion.cpp), so the held past stays held;
//   - a target equal to the last key while moving: that key again, one frame later, which
//     makes a stop.
// So the head follows the mouse two frames late (80 ms at 25 fps) and every input is
// recorded at a frame time: the recording is exact.
#include <filesystem>

#include "dynamics/motion.hpp"
#include "groom/head.hpp"

namespace wisp {

class LiveMotion {
  public:
    // Starts still at the rest pose (keys at 0 and F), with the head turning about the neck
    // and the body about the hips, as the presets do. `fps` is the animation's frame rate.
    LiveMotion(const HeadFrame& head, double fps);

    // The motion the simulation reads (it refers to this object; drive() must not run
    // while a step does).
    const Motion& motion() const { return motion_; }
    double frame_interval() const { return interval_; }
    // The frames driven so far (the next drive() must be for this frame).
    int frames() const { return frames_; }

    // Where the head and the body should be at frame `frame`: rotation (degrees) and
    // translation (cm) about this motion's pivots (head_pivot(), body_pivot()); key times
    // are ignored. Throws wisp::Error when a frame is skipped or repeated, or a value is not
    // finite or past the motion file's limits. Once the recording would pass what a motion
    // file may hold (kMaxMotionKeys keys, kMaxMotionTime), the head stops where it is and
    // full() says so.
    void drive(int frame, const MotionKey& head, const MotionKey& body);
    // The same, holding the last target (no new input this frame).
    void hold(int frame);

    // The last target given (what hold() keeps).
    const MotionKey& head_target() const { return motion_.head.keys.back(); }
    const MotionKey& body_target() const { return motion_.body.keys.back(); }
    Vec3f head_pivot() const { return motion_.head.pivot; }
    Vec3f body_pivot() const { return motion_.body.pivot; }

    // Wind and gravity act from the next step on. They are not keyed: a recording replays
    // with the last values set (say so when exporting one where they changed).
    void set_wind(const Vec3f& wind, float gust_amplitude, float gust_frequency);
    bool full() const { return full_; }

    // Writes the recording as a motion file (motion.hpp, cm units), atomically.
    void write(const std::filesystem::path& path) const { write_motion(path, motion_); }

  private:
    void append(double time, const MotionKey& head, const MotionKey& body);

    Motion motion_;
    double interval_;
    int frames_ = 0;
    bool full_ = false;
};

// The checks drive() and set_wind() make (wisp::Error naming the value), for callers that
// take input on another thread than the one that drives.
void check_live_key(const MotionKey& key, const char* what);
void check_wind(const Vec3f& wind, float gust_amplitude, float gust_frequency);

// The pose of `track` at time t as a key about `pivot` instead of the track's own: the same
// rotation, the translation that puts every point where the track puts it.
MotionKey key_about(const MotionTrack& track, double t, const Vec3f& pivot);

}  // namespace wisp
