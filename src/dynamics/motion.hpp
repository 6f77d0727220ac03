#pragma once
// Head and body motion for the animation (Bertails et al. 2003 §5: leaning, shaking,
// nodding, jumping, running), as keyframed rigid transforms.
//
// A track is a list of keys (time in s, Euler rotation in degrees, translation in cm) about
// a pivot. Between keys each rotation angle and translation component follows a Catmull-Rom
// spline in time: the cubic Hermite segment between keys i and i+1 with tangents
// m[i] = (p[i+1] − p[i−1]) / (t[i+1] − t[i−1]), which allows unevenly spaced keys, and
// m = 0 at the first and last keys (clamped ends). So velocities are continuous and
// accelerations finite: the AWT splits where hair accelerates, and a piecewise-linear track
// would give it spikes at every key. Before the first key and after the last, the track
// holds its end pose with zero velocity, which the clamped ends meet continuously.
//
// A transform maps head space (the space the hairstyle was made in) to world space:
//   world = translation + pivot + R · (p − pivot),   R = Ry(yaw) · Rx(pitch) · Rz(roll)
// with rotate = (pitch about X, yaw about Y, roll about Z) in degrees, right-handed: pitch > 0
// tips the face (+Z) down, yaw > 0 turns the face toward +X, roll > 0 tilts the crown (+Y)
// toward −X.
//
// The JSON file (format "wisp-motion", version 1) is documented in docs/motion.md:
//   {"format": "wisp-motion", "version": 1,
//    "head": {"pivot": [x, y, z], "keys": [{"t": 0, "rotate": [0, 0, 0],
//                                             "translate": [0, 0, 0]}, ...]},
//    "body": {...same...}            (optional: without it the body moves with the head)
//    "gravity": [0, -981, 0],        (optional, cm/s²)
//    "wind": [0, 0, 0],              (optional, cm/s, air velocity)
//    "gust": {"amplitude": 0, "frequency": 0.5}   (optional: wind speed varies by
//                                                   amplitude·sin(2π f t), cm/s)
//    "duration": 4.0}                (optional, s: default the last key's time)
// Pivots and translations are in head units when "units": "head" (the default: a unit is
// the head's radius, pivots relative to the head's centre) or in cm when "units": "cm".
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.hpp"
#include "solve/styling_field.hpp"  // HeadFrame

namespace wisp {

struct RigidTransform {
    Mat3f rotation = Mat3f::Identity();
    Vec3f translation = Vec3f::Zero();
    Vec3f apply(const Vec3f& p) const { return rotation * p + translation; }
    Vec3f apply_vector(const Vec3f& v) const { return rotation * v; }
    // The inverse: the head-space point that apply() takes to world point p.
    Vec3f to_local(const Vec3f& p) const { return rotation.transpose() * (p - translation); }
};

// The velocity field of a rigid motion at one instant (cm/s): v(p) = linear + turn·(p − pivot)
// for the point at head-space p, turn being dR/dt.
struct RigidVelocity {
    Mat3d turn = Mat3d::Zero();
    Vec3d linear = Vec3d::Zero();
    Vec3f pivot = Vec3f::Zero();
    Vec3f at(const Vec3f& p) const {
        return (linear + turn * (p - pivot).cast<double>()).cast<float>();
    }
};

struct MotionKey {
    double time = 0;                  // s
    Vec3f rotate = Vec3f::Zero();     // degrees: pitch (X), yaw (Y), roll (Z)
    Vec3f translate = Vec3f::Zero();  // cm (already converted from head units)
};

struct MotionTrack {
    Vec3f pivot = Vec3f::Zero();  // cm, head space
    std::vector<MotionKey> keys;  // sorted by time, strictly increasing; may be empty (still)

    RigidTransform at(double t) const;
    // The interpolated channels at time t (rotation angles and translation about `pivot`),
    // as a key at that time.
    MotionKey key_at(double t) const;
    // Velocity of the point that sits at head-space p, at time t (cm/s): the analytic time
    // derivative of at(t).apply(p).
    Vec3f velocity(const Vec3f& p, double t) const { return velocity(t).at(p); }
    // The velocity field at time t, for the velocities of many points.
    RigidVelocity velocity(double t) const;
};

struct Motion {
    std::string name;  // preset name or file path, for messages and stats
    MotionTrack head;  // moves the scalp and the hair roots
    MotionTrack body;  // moves neck and shoulders (a file without "body": a copy of
                       // head; presets that move only the head: empty, the body still)
    Vec3f gravity = Vec3f(0, -981.f, 0);  // cm/s²
    Vec3f wind = Vec3f::Zero();           // cm/s, air velocity
    float gust_amplitude = 0;             // cm/s
    float gust_frequency = 0.5f;          // Hz
    double duration = 0;                  // s

    // Air velocity at time t: wind scaled by (1 + gust_amplitude·sin(2π f t)/|wind|) along
    // the wind direction (no gust without wind).
    Vec3f wind_at(double t) const;
};

// Limits read_motion enforces (per track; times and duration in s, rotations in degrees,
// translations and pivots in cm after unit conversion).
inline constexpr size_t kMaxMotionKeys = 100000;
inline constexpr double kMaxMotionTime = 3600;
inline constexpr double kMaxMotionRotate = 3600;
inline constexpr double kMaxMotionTranslate = 1e5;
// The most a motion file may hold (4 tracks of kMaxMotionKeys keys fit in it).
inline constexpr uint64_t kMaxMotionFileBytes = uint64_t(64) << 20;

// The pivots the presets turn about: the neck (the head's nods and shakes) and the hips
// (leaning, running).
Vec3f neck_pivot(const HeadFrame& head);
Vec3f hips_pivot(const HeadFrame& head);

// The preset names: lean, shake, nod, jump, run, still.
std::vector<std::string> motion_preset_names();

// A preset scaled to the head (pivots at the neck or hips in head units). Throws
// wisp::Error listing the names for an unknown one.
Motion motion_preset(std::string_view name, const HeadFrame& head);

// Reads the JSON file above. Throws wisp::Error naming the file and the field on any
// malformed, truncated, non-finite or out-of-range content (keys out of order, unknown
// fields, wrong types, more than 100,000 keys, times beyond 1 hour).
Motion read_motion(const std::filesystem::path& path, const HeadFrame& head);

// The same from the file's text already in memory (an editor upload); `source` names it in
// messages.
Motion parse_motion(const std::string& text, const std::string& source, const HeadFrame& head);

// A preset name or a file path: presets first, then the file.
Motion load_motion(const std::string& preset_or_path, const HeadFrame& head);

// Writes a motion as the JSON above (in cm units), atomically.
void write_motion(const std::filesystem::path& path, const Motion& motion);

}  // namespace wisp
