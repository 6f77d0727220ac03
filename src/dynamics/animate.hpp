#pragma once
// Animating a hairstyle (Bertails et al. 2003): hierarchy → AWT simulation → render strands
// moved with the nodes, frame after frame.
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/hair.hpp"
#include "dynamics/awt.hpp"
#include "dynamics/body.hpp"
#include "dynamics/hierarchy.hpp"
#include "dynamics/motion.hpp"
#include "dynamics/skin.hpp"
#include "geometry/mesh.hpp"
#include "groom/style.hpp"

namespace wisp {

struct AnimateSettings {
    int frames = 48;  // ≥ 1; frame 0 is the rest pose at time 0
    double fps = 24;  // > 0
    bool single_level = false;
    // Per wisp id of the rest hair: the length held rigidly to the head by a tie or a bun
    // (SolveStats::held_length, HierarchyOptions::wisp_held); empty: no ties.
    std::vector<float> wisp_held;
    // Per strand of the rest hair: the length held by ties (held_lengths(), `--tie`); empty:
    // none (HierarchyOptions::strand_held).
    std::vector<float> strand_held;
    // Record the per-frame lists of AnimationStats (active nodes per level, splits, merges):
    // off for a live session that runs without end.
    bool frame_stats = true;
    // Keep the split and merge events of every step of the frame (Animator::frame_events),
    // at most this many per frame (the rest are counted, not kept); 0: none kept.
    size_t frame_events = 0;
};

// A split or merge where it happened: the node's position at the step it happened (cm,
// world).
struct PlacedAwtEvent {
    Vec3f at;
    AwtEvent::Kind kind;
};

struct AnimationStats {
    int levels = 0, sections = 0;
    size_t gcs = 0, nodes = 0, finest_nodes = 0, spheres = 0;
    size_t held_finest_nodes = 0;  // held rigidly to the head by ties (k ≥ 1)
    std::vector<size_t> gcs_per_level;
    bool rigid = true;
    int steps_per_frame = 0;
    double dt = 0;  // s, adjusted so whole steps fill each frame
    size_t steps = 0;
    double hierarchy_ms = 0, bodies_ms = 0, bind_ms = 0;
    double step_ms_mean = 0, step_ms_max = 0;  // simulation only
    double skin_ms_mean = 0;                   // moving the strands, per frame
    uint64_t splits = 0, merges = 0;
    uint64_t pair_tests = 0, hair_contacts = 0, body_contacts = 0;
    double max_kinetic_energy = 0;  // g·cm²/s²
    // Per frame.
    std::vector<std::vector<uint32_t>> active_per_level;
    std::vector<uint32_t> frame_splits, frame_merges;
};

// The hierarchy options of a style's [dynamics] section.
HierarchyOptions hierarchy_options(const DynamicsSpec& spec);

// Fits the body spheres (body.hpp) to `body` and clears them of the rest hierarchy's nodes.
std::vector<Sphere> body_spheres_for(const Mesh& body, const HeadFrame& head,
                                     const Hierarchy& hierarchy);

// Where the character is at a frame.
struct FramePose {
    double time = 0;            // s
    RigidTransform head, body;  // head space → world
};

// One animation, frame by frame: the loop animate() runs, and what the editor's live motion
// steps while the user drives the head (its motion gains keys as it plays: the simulation
// reads the motion at each step's time, live_motion.hpp). Deterministic: the same rest hair,
// motion keys and settings give the same node positions at every frame.
class Animator {
  public:
    // Builds the hierarchy, fits the body spheres and binds the strands (timed in stats()).
    // `rest`, `motion` and what they refer to must outlive the animator. Throws wisp::Error
    // on bad settings.
    Animator(const Hair& rest, const Mesh& body, const HeadFrame& head, const Motion& motion,
             const DynamicsSpec& spec, PrototypeSpec::Kind prototype,
             const AnimateSettings& settings);
    Animator(const Animator&) = delete;  // the simulation refers to the hierarchy
    Animator& operator=(const Animator&) = delete;

    // Moves to the next frame: frame 0 is the rest pose (no step), every later frame runs
    // stats().steps_per_frame steps. Then the nodes are synced for skinning. Throws
    // wisp::Error if the simulation diverges.
    void advance();
    int frame() const { return frame_; }
    // The style's dynamics changed between frames: what AwtSimulation::set_params applies
    // from the next step on (the hierarchy, links, dt and voxel stay). Throws wisp::Error on
    // bad values, nothing changed.
    void set_dynamics(const DynamicsSpec& spec,
                      PrototypeSpec::Kind prototype);  // −1 before the first advance()
    FramePose pose() const;

    // The render strands at the current frame: all of them into `out` (rest's topology), or
    // the strands listed, point after point, into `points` (sized by the caller: the sum of
    // the listed strands' point counts). Parallel over strands; no allocation once the list
    // is known (the binding of the last list is kept, gathered in order: SubsetBinding).
    void skin(Hair& out);
    void skin(std::span<const uint32_t> strands, std::span<Vec3f> points);
    // The same points as float32 x, y, z triples (12 bytes each) into `xyz`: a live frame's
    // bytes (wire.hpp's begin_frame), skinned in place instead of copied.
    void skin(std::span<const uint32_t> strands, std::span<char> xyz);

    const Hierarchy& hierarchy() const { return hierarchy_; }
    const AwtSimulation& simulation() const { return *sim_; }
    // The splits and merges of every step of the last advance(), in step order, at most
    // AnimateSettings::frame_events of them (the first ones); empty when that is 0.
    const std::vector<PlacedAwtEvent>& frame_events() const { return frame_events_; }
    // Totals and means so far.
    AnimationStats stats() const;

  private:
    const Hair& rest_;
    AnimationStats stats_;
    Hierarchy hierarchy_;
    StrandBinding binding_;
    SubsetBinding subset_;  // of the last strands given to skin()
    std::unique_ptr<AwtSimulation> sim_;
    std::vector<Mat3f> rotations_;
    int frame_ = -1;
    bool frame_stats_ = true;
    double step_total_ = 0, skin_total_ = 0;
    int skins_ = 0;
    size_t max_frame_events_ = 0;
    std::vector<PlacedAwtEvent> frame_events_;  // reserved once: no allocation per frame
    uint64_t splits_before_ = 0, merges_before_ = 0;
};

// Runs the animation and calls frame(index, hair, pose) for every frame with the moved
// strands (the rest hair's topology, widths, colors and wisp ids). Deterministic.
AnimationStats animate(const Hair& rest, const Mesh& body, const HeadFrame& head,
                       const Motion& motion, const DynamicsSpec& spec,
                       PrototypeSpec::Kind prototype, const AnimateSettings& settings,
                       const std::function<void(int, const Hair&, const FramePose&)>& frame);

// The figures of a run as `wisp animate --stats` and `wisp.animate(...).stats` give them:
// motion, frames, fps, the rest hair's strands and points, links, hierarchy, body spheres,
// steps, ms per step, splits and merges (in all and per frame), contacts, kinetic energy.
nlohmann::json animation_stats_json(const AnimationStats& stats, const Hair& rest,
                                    const Motion& motion, int frames, double fps);

// The body mesh posed: vertices above the chin follow the head, those below the neck base
// the body, blended linearly in between (the neck bends instead of tearing).
Mesh pose_body(const Mesh& body, const HeadFrame& head, const FramePose& pose);

}  // namespace wisp
