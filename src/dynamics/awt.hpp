#pragma once
// The Adaptive Wisp Tree (Bertails et al. 2003 §2.2–§4): animation of a multiresolution
// hierarchy whose nodes split and merge.
//
// State. Node k ≥ 1 of every GC is, at any time, one of
//   active  it is simulated (position, velocity);
//   split   its sub-nodes (or finer ones) govern its cross-section;
//   merged  an active ancestor (super-node, super-super-node …) governs it; it follows that
//           node through its offset vector, rotated with the governing segment (§3.3).
// Partition invariant: along the super-node chain of every finest node k ≥ 1, exactly one
// node is active, those below it are merged and those above are split. Tree invariant: the
// level of the active node never decreases from root to tip (splits go tip to root, merges
// root to tip, §2.2), so the active node at k−1 over an active node at k is itself or an
// ancestor GC: its parent in the AWT. Node 0 (the roots) of every GC moves rigidly with the
// head and is never simulated; the parent of an active node at k = 1 is its own GC's root.
//
// Step (dt), in order:
//   1. roots follow the head's rigid motion (motion.hpp);
//   2. hair–hair interactions (§4.1–§4.2) between active segments whose boxes overlap
//      (broad_phase.hpp) with relative motion: viscous friction k_f = α·m (eq. 1) and, for segments
//      crossing at more than the threshold angle, repulsion (eq. 2), split to the segment's two
//      nodes by eq. (3);
//   3. every active node, root to tip, is integrated implicitly (backward Euler in velocity,
//      with its parent already advanced) under
//        - a shape spring toward its styled place relative to its parent, turned with the
//          head: x_p + R_h·(X_c − X_p), whose reaction acts on the parent (a conservative
//          spring; with the head still, hair stays at the styled shape);
//        - soft links (curly hair): a second spring on the segment's length;
//        - effective gravity g − R_h·R_h0ᵀ·g: the styled shape is the rest shape under the
//          gravity of the first frame (sag-free), and the head's rotation since then turns it;
//        - drag toward the air's velocity (wind), damping relative to the parent's velocity,
//          the interaction forces;
//   4. rigid links (straight hair): `iterations` mass-weighted Gauss–Seidel passes over the
//      link lengths (van Overveld's iterative method), then a last pass root to tip that sets
//      every length exactly;
//   5. body (§4.3): a segment that penetrates a sphere is pushed out by moving its child
//      node, whose velocity becomes the obstacle's;
//   6. velocities from positions; accelerations a = Δv/dt, averaged over 50 ms (a node made
//      by a merge skips its first step: that Δv is the coarse approximation taking over);
//   7. adaptation: splits tip to root (§3.1: |a|·r over the threshold and the child node
//      already split; sub-nodes take the offsets and the velocity of the split node), then
//      merges root to tip (§3.2: sub-nodes of one super-node with the same AWT parent, within
//      its radius, relative speeds under the threshold, the split test false; the super-node
//      takes the centre of mass, the mass-weighted velocity and a radius that fits them).
// Single-level mode keeps every finest node active and never adapts (the paper's baseline).
// The hair–hair tests run in parallel; their sums do not depend on the thread count.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dynamics/body.hpp"
#include "dynamics/broad_phase.hpp"
#include "dynamics/hierarchy.hpp"
#include "dynamics/motion.hpp"
#include "groom/style.hpp"

namespace wisp {

struct AwtParams {
    bool rigid = true;
    bool single_level = false;
    float stiffness = 800.f;         // 1/s²
    float stretch = 3000.f;          // 1/s², soft links
    float damping = 8.f;             // 1/s
    float air_drag = 2.f;            // 1/s
    float split_threshold = 1500.f;  // |a|·r, cm²/s²
    float merge_velocity = 15.f;     // cm/s
    float friction = 20.f;           // α, 1/s
    float repulsion = 1500.f;        // 1/s²
    float repulsion_angle = 30.f;    // degrees
    float voxel = 0.f;               // cm, 0 = automatic
    int iterations = 2;
    bool hair_collisions = true;
    bool body_collisions = true;
    float dt = 0.01f;  // s
};

// The parameters of a style's [dynamics] section (threshold converted from m²/s² to cm²/s²;
// links auto = soft for curly and kinky prototypes). Throws wisp::Error when α·dt ≥ 1.
AwtParams awt_params(const DynamicsSpec& spec, PrototypeSpec::Kind prototype, bool single_level);

enum class NodeState : uint8_t { kActive, kSplit, kMerged };

struct AwtEvent {
    enum class Kind : uint8_t { kSplit, kMerge };
    Kind kind;
    uint32_t node;  // the split node, or the super-node that merged
};

struct AwtStepStats {
    uint32_t splits = 0, merges = 0;
    uint32_t pair_tests = 0;     // cylinder tests (pairs in a voxel with relative motion)
    uint32_t hair_contacts = 0;  // pairs closer than their radii
    uint32_t body_contacts = 0;  // child nodes pushed out of the body
};

class AwtSimulation {
  public:
    // `hierarchy` must outlive the simulation. `spheres` are in head space (body.hpp); the
    // simulation starts at time `start` with the hair at rest in the pose of that time.
    // The motion is copied.
    AwtSimulation(const Hierarchy& hierarchy, std::vector<Sphere> spheres, const Motion& motion,
                  const AwtParams& params, double start = 0);
    // The motion is not copied: it must outlive the simulation, and may gain keys between
    // steps (the editor's live motion, live_motion.hpp).
    AwtSimulation(const Hierarchy& hierarchy, std::vector<Sphere> spheres, const Motion* motion,
                  const AwtParams& params, double start = 0);
    AwtSimulation(const AwtSimulation&) = delete;  // motion_ may point into the object
    AwtSimulation& operator=(const AwtSimulation&) = delete;

    void step();
    // The parameters read at every step, changed between steps (the editor's live controls,
    // issue 17): stiffness, stretch, damping, air_drag, split_threshold, merge_velocity,
    // friction, repulsion, repulsion_angle, iterations, hair_collisions, body_collisions.
    // The others (rigid, single_level, voxel, dt) shaped the state and stay as constructed.
    // Throws wisp::Error when friction·dt ≥ 1 (§4.2), the parameters unchanged.
    void set_params(const AwtParams& params);
    double time() const { return time_; }
    const Hierarchy& hierarchy() const { return *h_; }
    const AwtParams& params() const { return params_; }

    // Positions of every node, world space. Active and root nodes are current after step();
    // call sync() first for the others.
    std::span<const Vec3f> positions() const { return x_; }
    std::span<const Vec3f> velocities() const { return v_; }
    // Places every non-active node (merged: through its offset; split: at its sub-nodes'
    // centre of mass).
    void sync();

    NodeState state(uint32_t node) const { return static_cast<NodeState>(state_[node]); }
    // Active nodes with k ≥ 1, root to tip (by section, then GC).
    const std::vector<uint32_t>& active() const { return active_; }
    uint32_t parent(uint32_t active_node) const { return parent_[active_node]; }
    float radius(uint32_t node) const { return radius_[node]; }
    // The length an active node's link holds: its rest length, except just after a split or
    // merge made the link, when it starts at the current length and relaxes to the rest one.
    float link_length(uint32_t node) const { return link_length_[node]; }
    // Active nodes (k ≥ 1) per hierarchy level.
    std::vector<uint32_t> active_per_level() const;
    const AwtStepStats& last_step() const { return last_; }
    const std::vector<AwtEvent>& last_events() const { return events_; }
    uint64_t total_splits() const { return total_splits_; }
    uint64_t total_merges() const { return total_merges_; }
    // Σ ½·m·|v|² over active nodes, g·cm²/s².
    double kinetic_energy() const;
    double active_mass() const;
    const RigidTransform& head_transform() const { return head_; }
    const RigidTransform& body_transform() const { return body_; }
    // The spheres at the current time, world space.
    std::vector<Sphere> world_spheres() const;
    // Rotation of every finest node (#finest GCs × sections, row by GC): the rest frame to
    // the current one, blended from the segments on either side (roots: the head's). After
    // sync().
    void finest_rotations(std::vector<Mat3f>& out) const;
    // An empty string when the partition and tree invariants hold, else what is wrong.
    std::string check_invariants() const;

  private:
    void place_roots();
    // Places a node rigidly with the head (roots, tied nodes): its rest place and velocity.
    void hold(uint32_t node);
    void interact();
    void integrate();
    // True when it moved the child; sets collided_[child], counts nothing (callers do: it
    // runs in parallel in integrate()).
    bool collide_body(uint32_t child, uint32_t parent_node);
    // collide_body(), counting a first contact in last_.body_contacts.
    void collide_counted(uint32_t child, uint32_t parent_node);
    // body(node) for every active node, or those of section k, in parallel.
    template <class Body>
    void for_active(Body&& body) const;
    template <class Body>
    void for_section(int k, Body&& body) const;
    void adapt();
    void split(uint32_t node);
    bool try_merge(uint32_t gc, int k);
    void rebuild_active();
    uint32_t find_parent(uint32_t gc, int k) const;
    Eigen::Quaternionf segment_rotation(uint32_t child, uint32_t parent_node,
                                        const Vec3f& child_position) const;
    // The rotation taking the head-space rest vector `rest` to `now` (the head's rotation
    // composed with the shortest arc).
    Eigen::Quaternionf rest_to_now(const Vec3f& rest, const Vec3f& now) const;
    void rebase_subtree(uint32_t node, const Eigen::Quaternionf& change);
    void settle_merged();
    void init();  // the constructors' work once the members are set

    const Hierarchy* h_;
    std::vector<Sphere> spheres_;
    Motion owned_motion_;
    const Motion* motion_;
    AwtParams params_;
    int n_;
    double time_;
    RigidTransform head_, body_;
    RigidVelocity head_velocity_, body_velocity_;  // at time_
    // The head's acceleration field over the last step, in the same form (linear + turn·(p −
    // pivot) for the point at head-space p): what hair moving rigidly with the head would do.
    RigidVelocity head_acceleration_;
    Eigen::Quaternionf head_rotation_;
    Vec3f rest_gravity_;  // gravity of the first frame, head space
    float voxel_;
    float cos_repulsion_;

    std::vector<Vec3f> x_, v_, acc_, force_, offset_, x_old_, v_old_;
    std::vector<float> radius_, link_length_;
    std::vector<uint8_t> state_, collided_;
    // 1 for a node made by a merge at the last adapt(), until its first step (integrate()).
    std::vector<uint8_t> merge_step_;
    std::vector<uint32_t> parent_;
    std::vector<Eigen::Quaternionf> rotation_;  // segment rotation of active nodes
    std::vector<uint32_t> active_;
    std::vector<size_t> section_begin_;  // #sections+1: section k's nodes in active_
    std::vector<uint32_t> governor_;     // sync(): the active node governing each merged node
    std::vector<Sphere> world_spheres_;
    // Hair–hair interactions (interact()): the active segments' boxes, and their data in the
    // grid's order.
    struct Segment {
        Vec3f xp, axis;  // parent node, and child − parent
        float length2;   // |axis|²
        Vec3f vp, vc;    // parent and child node
        Vec3f velocity;  // mean of the two nodes'
        Vec3f middle;    // bounding sphere: centre and radius
        float reach;
        float radius, mass;  // the child node's
        uint32_t child, parent;
        bool moving;
    };
    // Hair–hair contact sums at a node, or at one end of a segment.
    struct ContactSums {
        Vec3f force = Vec3f::Zero();        // repulsion
        Vec3f friction = Vec3f::Zero();     // Σ k_f·v_other
        Vec3f pushed_with = Vec3f::Zero();  // Σ k_r·n·nᵀ·v_other
        float drag = 0;                     // Σ k_f
        float stiffness = 0;                // Σ k_r
        Mat3f normal = Mat3f::Zero();       // Σ k_r·n·nᵀ
        void add(const ContactSums& o) {
            force += o.force;
            friction += o.friction;
            pushed_with += o.pushed_with;
            drag += o.drag;
            stiffness += o.stiffness;
            normal += o.normal;
        }
    };
    // What the contacts gather at a segment's two ends (kept apart from Segment, which the
    // tests read, so that the tests' data stays compact).
    struct SegmentSums {
        ContactSums child, parent;
    };
    struct Contact {
        uint32_t a, b;  // positions in grid order
        float s, t;     // closest points along a and b, parent → child
        float push;     // repulsion (r − d)/d, 0 when none
    };
    struct ChunkContacts {
        std::vector<Contact> list;
        uint32_t tests = 0;
    };
    BoxGrid grid_;
    std::vector<ChunkContacts> contacts_;
    std::vector<Box4> boxes_;
    std::vector<Segment> segments_;
    std::vector<SegmentSums> sums_;
    std::vector<ContactSums> contact_;  // per node, after the caps
    std::vector<AwtEvent> events_;
    AwtStepStats last_;
    uint64_t total_splits_ = 0, total_merges_ = 0;
};

}  // namespace wisp
