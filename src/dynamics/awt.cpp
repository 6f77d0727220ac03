#include "dynamics/awt.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/parallel.hpp"

namespace wisp {
namespace {

using Quat = Eigen::Quaternionf;

constexpr uint8_t kActive = static_cast<uint8_t>(NodeState::kActive);
constexpr uint8_t kSplit = static_cast<uint8_t>(NodeState::kSplit);
constexpr uint8_t kMerged = static_cast<uint8_t>(NodeState::kMerged);

// Relative speeds under this (cm/s) count as "the same velocity" (§4.1: no collision test).
constexpr float kStill = 0.5f;

// A node's total hair–hair friction rate and repulsion stiffness, in units of one contact's
// (α and k_r; interact()).
constexpr float kContactRate = 4.f;

// Calls share(end, w, args...) for a segment's child end with w = s and its parent end with
// w = 1 − s: a contact at s along the segment, split to its nodes by eq. (3).
template <class Sums, class Share, class... Args>
void at_ends(Sums& sums, float s, const Share& share, const Args&... args) {
    share(sums.child, s, args...);
    share(sums.parent, 1 - s, args...);
}

// Contacts a segment makes as the first of a pair (in grid order) before its other pairs are
// skipped. A node's friction and repulsion saturate at kContactRate contacts' worth; in a
// braid or a ponytail, where thousands of segments share a few voxels, the pairs are
// otherwise quadratic in the hair packed there (a shaken braid: 13M contacts a step).
constexpr uint32_t kMaxContacts = 32;

// Grid entries per chunk of the parallel hair–hair tests.
constexpr size_t kChunk = 128;

// Nodes per task of the parallel loops over nodes and GCs. Each writes only its own node's
// data, so they give the same bits at any thread count.
constexpr size_t kGrain = 256;

// Seconds over which the acceleration of the split and merge tests is averaged.
constexpr float kAccelerationTime = 0.05f;

// Merging asks |a|·r under this fraction of the split threshold.
constexpr float kMergeHysteresis = 0.5f;

// Seconds over which a link made by a split or merge relaxes to its rest length.
constexpr float kLinkRelaxTime = 0.1f;

// Seconds over which merged nodes settle back to their styled offsets.
constexpr float kSettleTime = 0.5f;

// A node partly held by a tie (Hierarchy::held, a coarse node over held and free sub-nodes)
// is drawn to its held place with this stiffness (1/s²) and critical damping, times the
// fraction held; a node held whole moves rigidly with the head.
constexpr float kHoldStiffness = 4000.f;

// Closest points of segments p1 + s·d1 and p2 + t·d2, s and t in [0, 1], given a = |d1|² and
// e = |d2|² (Ericson, Real-Time Collision Detection §5.1.9).
void closest_points(const Vec3f& p1, const Vec3f& d1, float a, const Vec3f& p2, const Vec3f& d2,
                    float e, float& s, float& t) {
    const Vec3f r = p1 - p2;
    const float f = d2.dot(r);
    constexpr float eps = 1e-12f;
    if (a <= eps && e <= eps) {
        s = t = 0;
        return;
    }
    if (a <= eps) {
        s = 0;
        t = std::clamp(f / e, 0.f, 1.f);
        return;
    }
    const float c = d1.dot(r);
    if (e <= eps) {
        t = 0;
        s = std::clamp(-c / a, 0.f, 1.f);
        return;
    }
    const float b = d1.dot(d2), denom = a * e - b * b;
    s = denom > eps ? std::clamp((b * f - c * e) / denom, 0.f, 1.f) : 0.f;
    t = (b * s + f) / e;
    if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.f, 1.f);
    } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.f, 1.f);
    }
}

// The same for segments p1q1 and p2q2.
void closest_points(const Vec3f& p1, const Vec3f& q1, const Vec3f& p2, const Vec3f& q2, float& s,
                    float& t) {
    const Vec3f d1 = q1 - p1, d2 = q2 - p2;
    closest_points(p1, d1, d1.squaredNorm(), p2, d2, d2.squaredNorm(), s, t);
}

}  // namespace

AwtParams awt_params(const DynamicsSpec& spec, PrototypeSpec::Kind prototype, bool single_level) {
    AwtParams p;
    switch (spec.links) {
        case DynamicsSpec::Links::kRigid:
            p.rigid = true;
            break;
        case DynamicsSpec::Links::kSoft:
            p.rigid = false;
            break;
        case DynamicsSpec::Links::kAuto:
            p.rigid = prototype != PrototypeSpec::Kind::kCurly &&
                      prototype != PrototypeSpec::Kind::kKinky;
            break;
    }
    p.single_level = single_level;
    p.stiffness = spec.stiffness;
    p.stretch = spec.stretch;
    p.damping = spec.damping;
    p.air_drag = spec.air_drag;
    p.split_threshold = spec.split_threshold * 1e4f;  // m²/s² → cm²/s²
    p.merge_velocity = spec.merge_velocity;
    p.friction = spec.friction;
    p.repulsion = spec.repulsion;
    p.repulsion_angle = spec.repulsion_angle;
    p.voxel = spec.voxel;
    p.iterations = spec.iterations;
    p.hair_collisions = spec.hair_collisions;
    p.body_collisions = spec.body_collisions;
    p.dt = spec.dt;
    if (!(p.dt > 0) || p.dt > 0.05f) fail("dynamics: dt must be in (0, 0.05] s, got ", p.dt);
    if (p.friction * p.dt >= 1)
        fail("dynamics: friction · dt must be under 1 (§4.2), got ", p.friction, " · ", p.dt);
    return p;
}

AwtSimulation::AwtSimulation(const Hierarchy& hierarchy, std::vector<Sphere> spheres,
                             const Motion& motion, const AwtParams& params, double start)
    : h_(&hierarchy),
      spheres_(std::move(spheres)),
      owned_motion_(motion),
      motion_(&owned_motion_),
      params_(params),
      n_(hierarchy.sections),
      time_(start) {
    init();
}

AwtSimulation::AwtSimulation(const Hierarchy& hierarchy, std::vector<Sphere> spheres,
                             const Motion* motion, const AwtParams& params, double start)
    : h_(&hierarchy),
      spheres_(std::move(spheres)),
      motion_(motion),
      params_(params),
      n_(hierarchy.sections),
      time_(start) {
    init();
}

void AwtSimulation::set_params(const AwtParams& params) {
    AwtParams next = params;
    next.rigid = params_.rigid;
    next.single_level = params_.single_level;
    next.voxel = params_.voxel;
    next.dt = params_.dt;
    if (!(next.friction * next.dt < 1))
        fail("dynamics: friction · dt must be under 1 (§4.2), got ", next.friction, " · ", next.dt);
    params_ = next;
    cos_repulsion_ = std::cos(params_.repulsion_angle * kPi / 180.f);
}

void AwtSimulation::init() {
    if (!(params_.dt > 0) || params_.friction * params_.dt >= 1)
        fail("dynamics: friction · dt must be under 1 (§4.2)");
    const Hierarchy& h = *h_;
    const size_t nodes = h.node_count();
    x_.resize(nodes);
    v_.assign(nodes, Vec3f::Zero());
    acc_.assign(nodes, Vec3f::Zero());
    force_.assign(nodes, Vec3f::Zero());
    contact_.assign(nodes, ContactSums{});
    offset_.assign(nodes, Vec3f::Zero());
    x_old_.resize(nodes);
    v_old_.resize(nodes);
    radius_ = h.radius;
    if (h.held.size() != nodes) fail("dynamics: the hierarchy's held fractions are missing");
    state_.assign(nodes, kMerged);
    collided_.assign(nodes, 0);
    merge_step_.assign(nodes, 0);
    parent_.assign(nodes, 0);
    link_length_.assign(nodes, -1.f);
    rotation_.assign(nodes, Quat::Identity());
    cos_repulsion_ = std::cos(params_.repulsion_angle * kPi / 180.f);

    // Voxel: twice the mean finest radius (§4.1's grid; a segment meets its neighbours in
    // its own or the adjacent cells).
    if (params_.voxel > 0) {
        voxel_ = params_.voxel;
    } else {
        double sum = 0;
        size_t count = 0;
        for (uint32_t g = h.finest_begin(); g < h.gc_count(); ++g)
            for (int k = 1; k < n_; ++k, ++count)
                sum += h.radius[h.node(g, k)];
        voxel_ = std::max(0.25f, static_cast<float>(2 * sum / std::max<size_t>(1, count)));
    }

    head_ = motion_->head.at(time_);
    body_ = motion_->body.at(time_);
    head_velocity_ = motion_->head.velocity(time_);
    body_velocity_ = motion_->body.velocity(time_);
    head_rotation_ = Quat(head_.rotation).normalized();
    rest_gravity_ = head_.rotation.transpose() * motion_->gravity;

    const int top = params_.single_level ? h.levels - 1 : 0;
    for (uint32_t g = 0; g < h.gc_count(); ++g)
        for (int k = 0; k < n_; ++k) {
            const uint32_t i = h.node(g, k);
            x_[i] = head_.apply(h.rest[i]);
            rotation_[i] = head_rotation_;
            if (k == 0) continue;
            const int level = h.level[g];
            state_[i] = level == top ? kActive : level < top ? kSplit : kMerged;
            if (h.super[g] >= 0)
                offset_[i] = h.rest[i] - h.rest[h.node(static_cast<uint32_t>(h.super[g]), k)];
        }
    place_roots();
    for (uint32_t g = 0; g < h.gc_count(); ++g)
        for (int k = 1; k < n_; ++k)
            v_[h.node(g, k)] = head_velocity_.at(h.rest[h.node(g, k)]);
    rebuild_active();
}

void AwtSimulation::place_roots() {
    const Hierarchy& h = *h_;
    parallel_for(
        h.gc_count(),
        [&](size_t g) {
            const uint32_t i = h.node(static_cast<uint32_t>(g), 0);
            hold(i);
            rotation_[i] = head_rotation_;
        },
        kGrain);
    world_spheres_ = spheres_;
    for (Sphere& s : world_spheres_)
        s.center = (s.head ? head_ : body_).apply(s.center);
}

void AwtSimulation::hold(uint32_t node) {
    x_[node] = head_.apply(h_->rest[node]);
    v_[node] = head_velocity_.at(h_->rest[node]);
}

std::vector<Sphere> AwtSimulation::world_spheres() const {
    return world_spheres_;
}

Quat AwtSimulation::rest_to_now(const Vec3f& rest, const Vec3f& now) const {
    const Vec3f turned = head_rotation_ * rest;
    if (turned.squaredNorm() < 1e-12f || now.squaredNorm() < 1e-12f) return head_rotation_;
    return (Quat::FromTwoVectors(turned, now) * head_rotation_).normalized();
}

Quat AwtSimulation::segment_rotation(uint32_t child, uint32_t parent_node,
                                     const Vec3f& child_position) const {
    return rest_to_now(h_->rest[child] - h_->rest[parent_node], child_position - x_[parent_node]);
}

uint32_t AwtSimulation::find_parent(uint32_t gc, int k) const {
    const Hierarchy& h = *h_;
    if (k == 1) return h.node(gc, 0);
    uint32_t g = gc;
    while (state_[h.node(g, k - 1)] == kMerged && h.super[g] >= 0)
        g = static_cast<uint32_t>(h.super[g]);
    return h.node(g, k - 1);
}

void AwtSimulation::rebuild_active() {
    const Hierarchy& h = *h_;
    active_.clear();
    section_begin_.assign(n_ + 1, 0);
    for (int k = 1; k < n_; ++k) {
        section_begin_[k] = active_.size();
        for (uint32_t g = 0; g < h.gc_count(); ++g) {
            const uint32_t i = h.node(g, k);
            if (state_[i] != kActive) continue;
            active_.push_back(i);
            const uint32_t p = find_parent(g, k);
            // A new link starts at its current length and relaxes to its rest length, so a
            // split or merge never snaps nodes (and never turns a snap into velocity).
            if (p != parent_[i] || link_length_[i] < 0) link_length_[i] = (x_[i] - x_[p]).norm();
            parent_[i] = p;
        }
    }
    section_begin_[n_] = active_.size();
}

template <class Body>
void AwtSimulation::for_active(Body&& body) const {
    parallel_for(
        active_.size(), [&](size_t a) { body(active_[a]); }, kGrain);
}

template <class Body>
void AwtSimulation::for_section(int k, Body&& body) const {
    const size_t begin = section_begin_[k];
    parallel_for(
        section_begin_[k + 1] - begin, [&](size_t a) { body(active_[begin + a]); }, kGrain);
}

void AwtSimulation::step() {
    const float dt = params_.dt;
    last_ = AwtStepStats{};
    events_.clear();
    time_ += dt;
    head_ = motion_->head.at(time_);
    body_ = motion_->body.at(time_);
    const RigidVelocity head_velocity_old = head_velocity_;
    head_velocity_ = motion_->head.velocity(time_);
    body_velocity_ = motion_->body.velocity(time_);
    head_rotation_ = Quat(head_.rotation).normalized();
    const double inv_dt = 1.0 / dt;
    head_acceleration_.turn = (head_velocity_.turn - head_velocity_old.turn) * inv_dt;
    head_acceleration_.linear = (head_velocity_.linear - head_velocity_old.linear) * inv_dt;
    head_acceleration_.pivot = head_velocity_.pivot;

    for_active([&](uint32_t i) {
        x_old_[i] = x_[i];
        v_old_[i] = v_[i];
    });
    // Interactions are computed on the state at the start of the step.
    if (params_.hair_collisions) interact();
    place_roots();
    integrate();
    if (!params_.single_level) {
        adapt();
        settle_merged();
    }
}

void AwtSimulation::settle_merged() {
    // §3.2 freezes merged nodes relative to their super-node; wisp lets them settle back to
    // their styled place over kSettleTime, so with the head still the hair rests at its
    // styled shape once the tree has merged back (rather than keeping the deformation of the
    // moment of the merge).
    const Hierarchy& h = *h_;
    const float relax = std::min(1.f, params_.dt / kSettleTime);
    const uint32_t first = h.level_begin[1];
    parallel_for(
        h.gc_count() - first,
        [&](size_t e) {
            const uint32_t g = first + static_cast<uint32_t>(e);
            const uint32_t up = static_cast<uint32_t>(h.super[g]);
            for (int k = 1; k < n_; ++k) {
                const uint32_t i = h.node(g, k);
                if (state_[i] != kMerged) continue;
                offset_[i] += relax * ((h.rest[i] - h.rest[h.node(up, k)]) - offset_[i]);
            }
        },
        kGrain);
}

void AwtSimulation::interact() {
    const Hierarchy& h = *h_;
    // Broad phase (broad_phase.hpp): the active segments' boxes on a hierarchical grid.
    const size_t count = active_.size();
    boxes_.resize(count);
    parallel_for(
        count,
        [&](size_t s) {
            const uint32_t c = active_[s], p = parent_[c];
            contact_[c] = ContactSums{};
            const Vec3f r = Vec3f::Constant(radius_[c]);
            const Vec3f lo = x_[c].cwiseMin(x_[p]) - r, hi = x_[c].cwiseMax(x_[p]) + r;
            boxes_[s].lo = {lo.x(), lo.y(), lo.z(), 0.f};
            boxes_[s].hi = {hi.x(), hi.y(), hi.z(), 0.f};
        },
        kGrain);
    grid_.build(boxes_, voxel_);
    // The segments in grid order, with everything the tests read, so that they read memory in
    // sequence; forces gather per segment end and are added to the nodes afterwards.
    const std::span<const uint32_t> order = grid_.order();
    segments_.resize(order.size());
    sums_.resize(order.size());
    parallel_for(
        order.size(),
        [&](size_t e) {
            sums_[e] = SegmentSums{};
            const uint32_t c = active_[order[e]], p = parent_[c];
            Segment& g = segments_[e];
            g.xp = x_[p];
            g.axis = x_[c] - x_[p];
            g.length2 = g.axis.squaredNorm();
            g.vp = v_[p];
            g.vc = v_[c];
            g.velocity = 0.5f * (v_[c] + v_[p]);
            g.middle = 0.5f * (x_[c] + x_[p]);
            g.reach = 0.5f * (x_[c] - x_[p]).norm() + radius_[c];
            g.radius = radius_[c];
            g.mass = h.mass[c];
            g.child = c;
            g.parent = p;
            // §4.1: only pairs with relative motion are tested; two segments both slower than
            // half the threshold cannot have it.
            g.moving = g.velocity.squaredNorm() >= 0.25f * kStill * kStill;
        },
        kGrain);
    const float alpha = params_.friction, kr = params_.repulsion;
    // The tests run in parallel over fixed chunks of the grid, each listing its contacts; the
    // contacts then act in chunk order, so the sums never depend on the thread count.
    const size_t chunks = std::max<size_t>(1, (order.size() + kChunk - 1) / kChunk);
    if (contacts_.size() < chunks) contacts_.resize(chunks);
    const float cos2 = cos_repulsion_ * cos_repulsion_;
    parallel_for(chunks, [&](size_t chunk) {
        ChunkContacts& out = contacts_[chunk];
        out.list.clear();
        out.tests = 0;
        size_t current = SIZE_MAX;
        uint32_t found = 0;  // contacts of segment `current`, as the first of the pair
        grid_.for_each_overlap(chunk * kChunk, (chunk + 1) * kChunk, [&](size_t ia, size_t ib) {
            if (ia != current) {
                current = ia;
                found = 0;
            }
            const Segment& a = segments_[ia];
            const Segment& b = segments_[ib];
            if (!a.moving && !b.moving) return true;
            if ((a.velocity - b.velocity).squaredNorm() < kStill * kStill) return true;
            if (a.parent == b.child || b.parent == a.child || a.parent == b.parent)
                return true;  // neighbours in the tree
            // Bounding spheres first: segments whose spheres are apart cannot touch.
            const float reach = a.reach + b.reach;
            if ((a.middle - b.middle).squaredNorm() >= reach * reach) return true;
            ++out.tests;
            float s, t;
            closest_points(a.xp, a.axis, a.length2, b.xp, b.axis, b.length2, s, t);
            const Vec3f d = (a.xp + s * a.axis) - (b.xp + t * b.axis);
            const float r = a.radius + b.radius;
            const float dist2 = d.squaredNorm();
            if (dist2 >= r * r) return true;
            Contact contact{static_cast<uint32_t>(ia), static_cast<uint32_t>(ib), s, t, 0.f};
            const float la2 = a.length2, lb2 = b.length2;
            const float dot = a.axis.dot(b.axis);
            if (la2 > 0 && lb2 > 0 && dist2 > 1e-12f && dot * dot < cos2 * la2 * lb2) {
                // Eq. (2), but never against the styled shape: segments that overlap at rest
                // (neighbouring sub-wisps, layers) repel only when closer than there.
                const uint32_t pa = a.parent, ca = a.child, pb = b.parent, cb = b.child;
                float rs, rt;
                closest_points(h.rest[pa], h.rest[ca], h.rest[pb], h.rest[cb], rs, rt);
                const float at_rest = ((h.rest[pa] + rs * (h.rest[ca] - h.rest[pa])) -
                                       (h.rest[pb] + rt * (h.rest[cb] - h.rest[pb])))
                                          .norm();
                const float reach = std::min(r, at_rest);
                const float dist = std::sqrt(dist2);
                if (dist < reach) contact.push = (reach - dist) / dist;
            }
            out.list.push_back(contact);
            // Enough contacts saturate the node's caps (below): the rest of a dense bundle
            // would only cost time, quadratic in the hair packed in one place.
            return ++found < kMaxContacts;
        });
    });
    for (size_t chunk = 0; chunk < chunks; ++chunk) {
        last_.pair_tests += contacts_[chunk].tests;
        last_.hair_contacts += static_cast<uint32_t>(contacts_[chunk].list.size());
        for (const Contact& contact : contacts_[chunk].list) {
            const Segment& a = segments_[contact.a];
            const Segment& b = segments_[contact.b];
            SegmentSums& fa = sums_[contact.a];
            SegmentSums& fb = sums_[contact.b];
            const float s = contact.s, t = contact.t;
            const float m = std::min(a.mass, b.mass);
            const float k = alpha * m;
            const Vec3f v1 = a.vp + s * (a.vc - a.vp);
            const Vec3f v2 = b.vp + t * (b.vc - b.vp);
            // Eq. (1), k_f = α·m, split to the nodes by eq. (3): P = u·N_p + (1 − u)·N_c with
            // u = 1 − s (s runs parent → child). It is integrated implicitly (each node is
            // drawn toward the other segment's velocity), so many contacts on one node never
            // reverse its relative motion.
            const auto rub = [&](ContactSums& end, float w, const Vec3f& other) {
                end.drag += w * k;
                end.friction += w * k * other;
            };
            at_ends(fa, s, rub, v2);
            at_ends(fb, t, rub, v1);
            if (contact.push == 0) continue;
            const float k_r = kr * m;
            const Vec3f d = (a.xp + s * a.axis) - (b.xp + t * b.axis);
            const Vec3f f = k_r * contact.push * d;
            // The repulsion, with its stiffness and Σ k_r·v_other for its implicit integration
            // relative to the other segment's motion (integrate()), along the contact normal
            // only: the implicit response resists approach, not sliding (that is friction's
            // business).
            const Mat3f nn = (k_r / d.squaredNorm()) * (d * d.transpose());
            const auto push = [&](ContactSums& end, float w, const Vec3f& force,
                                  const Vec3f& other) {
                end.force += w * force;
                end.stiffness += w * k_r;
                end.normal += w * nn;
                end.pushed_with += w * (nn * other);
            };
            at_ends(fa, s, push, f, v2);
            at_ends(fb, t, push, Vec3f(-f), v1);
        }
    }
    // Roots are not simulated: what falls on them is dropped.
    for (size_t e = 0; e < segments_.size(); ++e) {
        contact_[segments_[e].child].add(sums_[e].child);
        const uint32_t p = segments_[e].parent;
        if (h.section_of(p) != 0) contact_[p].add(sums_[e].parent);
    }
    // A node's friction rate Σk_f/m is at most kContactRate·α, and its repulsion stiffness
    // Σk_r/m at most kContactRate·k_r: it is drawn toward the mean velocity of the hair it
    // touches, and pushed out of it, at rates that do not grow with the number of segments
    // touching it. Eq. (1)'s k_f = α·m makes one contact independent of the level of its
    // nodes (§4.2); this makes a node's response independent of how finely the hair around
    // it is split too. Uncapped, a node in dense hair (hundreds of contacts at the finest
    // level) locked to its neighbours, and the hair set like a jelly in whatever shape a
    // motion left it; and summed repulsions flung it.
    for_active([&](uint32_t i) {
        ContactSums& n = contact_[i];
        const float friction_cap = kContactRate * alpha * h.mass[i];
        if (n.drag > friction_cap) {
            n.friction *= friction_cap / n.drag;
            n.drag = friction_cap;
        }
        const float repulsion_cap = kContactRate * kr * h.mass[i];
        if (n.stiffness > repulsion_cap) {
            const float scale = repulsion_cap / n.stiffness;
            n.force *= scale;
            n.pushed_with *= scale;
            n.normal *= scale;
            n.stiffness = repulsion_cap;
        }
        force_[i] = n.force + n.friction;
    });
}

void AwtSimulation::integrate() {
    const Hierarchy& h = *h_;
    const float dt = params_.dt;
    const Vec3f gravity = motion_->gravity - head_rotation_ * rest_gravity_;
    const Vec3f air = params_.air_drag * motion_->wind_at(time_);
    const float ks = params_.rigid ? 0.f : params_.stretch;
    const float kb = params_.stiffness;
    const float kt = kb + ks;
    const float denom = 1 + dt * (params_.damping + params_.air_drag) + dt * dt * kt;
    const bool forces = params_.hair_collisions;  // interact() has set force_ and contact_
    const float relax = std::min(1.f, dt / kLinkRelaxTime);
    for_active([&](uint32_t c) {
        link_length_[c] += relax * ((h.rest[c] - h.rest[parent_[c]]).norm() - link_length_[c]);
    });
    // The shape spring pulls each child toward x_p + R_h·(X_c − X_p) (its styled place
    // relative to its parent, turned with the head) and pulls the parent back by as much
    // (explicitly, from the start of the step), so it is a conservative spring between the
    // two and the tree cannot pump energy into itself.
    if (!forces) for_active([&](uint32_t c) { force_[c].setZero(); });
    for (uint32_t c : active_) {
        const uint32_t p = parent_[c];
        if (h.section_of(p) == 0) continue;
        const Vec3f target = x_old_[p] + head_rotation_ * (h.rest[c] - h.rest[p]);
        force_[p] -= h.mass[c] * kb * (target - x_old_[c]);
    }
    const float hold_damping = 2 * std::sqrt(kHoldStiffness);
    // Root to tip: every parent is advanced before its children; the nodes of one section
    // depend only on the previous one's.
    for (int k = 1; k < n_; ++k)
        for_section(k, [&](uint32_t c) {
            const uint32_t p = parent_[c];
            const float held = h.held[c];
            if (held >= 1) {
                hold(c);  // tied: rigid with the head, like the roots
                return;
            }
            const Vec3f rest = h.rest[c] - h.rest[p];
            const Vec3f bend_target = x_[p] + head_rotation_ * rest;
            Vec3f target = bend_target;
            if (ks > 0) {
                const Vec3f along = x_[c] - x_[p];
                const float len = along.norm();
                const Vec3f stretch_target =
                    len > 1e-6f ? Vec3f(x_[p] + link_length_[c] / len * along) : bend_target;
                target = (kb * bend_target + ks * stretch_target) / kt;
            }
            Vec3f a = gravity + air + params_.damping * v_[p];
            // force_ holds the shape springs' reactions, the repulsions and Σ k_f·v_other; the
            // contact sums' drag is Σ k_f (friction, implicit). The repulsions are implicit too,
            // along their normals and in the motion relative to the segments pushing (Σ k_r·n·nᵀ
            // and Σ k_r·n·nᵀ·v_other). So a node pressed by many
            // segments moves out of them by at most its penetration in a step instead of being
            // flung, and hair moving as one (a running character's) is not slowed.
            const ContactSums& n = contact_[c];
            a += (force_[c] + dt * n.pushed_with) / h.mass[c];
            float d = denom + dt * n.drag / h.mass[c];
            Vec3f rhs = v_[c] + dt * (kt * (target - x_[c]) + a);
            if (held > 0) {
                // Partly tied: an implicit spring to the held place, damped toward its velocity.
                const float k = held * kHoldStiffness, damping = held * hold_damping;
                d += dt * damping + dt * dt * k;
                rhs += dt * (k * (head_.apply(h.rest[c]) - x_[c]) +
                             damping * head_velocity_.at(h.rest[c]));
            }
            const Vec3f v =
                n.stiffness > 0
                    ? Vec3f((d * Mat3f::Identity() + (dt * dt / h.mass[c]) * n.normal).inverse() *
                            rhs)
                    : Vec3f(rhs / d);
            x_[c] += dt * v;
            v_[c] = v;
        });
    if (params_.rigid) {
        // van Overveld's iterative constraint method: mass-weighted passes over the links.
        for (int it = 0; it < params_.iterations; ++it)
            for (uint32_t c : active_) {
                const uint32_t p = parent_[c];
                const float rest = link_length_[c];
                const Vec3f d = x_[c] - x_[p];
                const float len = d.norm();
                if (len < 1e-6f) continue;
                // Roots and tied nodes do not give.
                const float wc = h.held[c] >= 1 ? 0.f : 1.f / h.mass[c];
                const float wp = h.held[p] >= 1 ? 0.f : 1.f / h.mass[p];
                if (wc + wp == 0) continue;
                const Vec3f correction = (len - rest) / (len * (wc + wp)) * d;
                x_[c] -= wc * correction;
                x_[p] += wp * correction;
            }
    }
    // Last pass, root to tip: exact lengths (rigid), then the body; section by section, as
    // above. The contacts are counted after it (collide_body counts none here).
    for (int k = 1; k < n_; ++k)
        for_section(k, [&](uint32_t c) {
            const uint32_t p = parent_[c];
            collided_[c] = 0;
            if (h.held[c] >= 1) return;
            const float rest = link_length_[c];
            // Alternate the link length and the body, ending with the body: the child slides
            // over the obstacle at its link's length (rigid) instead of being shoved off it.
            for (int round = 0; round < 4; ++round) {
                if (params_.rigid) {
                    const Vec3f d = x_[c] - x_[p];
                    const float len = d.norm();
                    if (len > 1e-6f) x_[c] = x_[p] + rest / len * d;
                }
                if (!params_.body_collisions || !collide_body(c, p)) break;
            }
        });
    for (uint32_t c : active_)
        last_.body_contacts += collided_[c];
    const float inv_dt = 1.f / dt;
    for_active([&](uint32_t c) {
        if (!collided_[c] && h.held[c] < 1) v_[c] = (x_[c] - x_old_[c]) * inv_dt;
        // The split test (§3.1) reads the node's acceleration in the world or relative to the
        // head's motion, whichever is smaller: hair riding the head rigidly does not deform
        // however the head accelerates (a lean's 45° swing about the hips accelerates all of
        // it at 3 m/s², which kept the coarse nodes of long hair split through the whole
        // lean), and hair that hangs while the head turns under it barely accelerates in the
        // world. It is averaged over kAccelerationTime (an exponential moving average), not
        // one step's Δv/dt: a single step's jolt (a node meeting the hair or the body, a
        // merged node meeting the neighbours its wider radius now touches) is not motion to
        // resolve. One step's Δv/dt split 70% of merged nodes again within 0.1 s, and the tree
        // churned.
        //
        // The first step of a node made by a merge does not count at all: its Δv is the coarse
        // approximation taking over, not motion. The super-node starts at its sub-nodes' centre
        // of mass with their mean velocity and a radius that fits them, and that state is not
        // one its own link, shape spring and contacts shaped: its link and spring meet a
        // configuration they did not make, its wider cylinder touches neighbours its sub-nodes
        // did not, its centre may lie in a body sphere (the centre of points on a convex
        // surface lies inside it). The first step jolts it by a few cm/s, as §4.1 says of the
        // coarse geometry ("new, undesired motion towards a slightly different rest state");
        // averaged in, that jolt read 2–3 times the split threshold on coarse nodes of long
        // hair, which split at the next step and merged again, 10 to 27 times a second, on
        // hair at rest. The node keeps the acceleration its sub-nodes carried (try_merge) and
        // measures its own from the next step, which §3.2's third condition (no merge that
        // would split right away) assumes.
        //
        // A node the body stopped this step lies on it and moves with it (its velocity is the
        // obstacle's): it does not deform, and its Δv is the contact's jolt, the free step's
        // velocity against the obstacle's, step after step while long hair lies on the back
        // or the shoulders. It counts as no acceleration, so hair resting on the body settles
        // into the coarse level instead of splitting and merging there many times a second.
        if (merge_step_[c]) {
            merge_step_[c] = 0;
        } else {
            Vec3f a = Vec3f::Zero();
            if (!collided_[c]) {
                const Vec3f world = (v_[c] - v_old_[c]) * inv_dt;
                const Vec3f relative = world - head_acceleration_.at(head_.to_local(x_[c]));
                a = relative.squaredNorm() < world.squaredNorm() ? relative : world;
            }
            acc_[c] += std::min(1.f, dt / kAccelerationTime) * (a - acc_[c]);
        }
        rotation_[c] = segment_rotation(c, parent_[c], x_[c]);
    });
}

// How far past a body sphere's surface collide_body() leaves a node (cm).
constexpr float kBodyMargin = 2e-3f;

bool AwtSimulation::collide_body(uint32_t c, uint32_t p) {
    bool any = false;
    // The child end must leave every sphere; so must the child half of the segment (the
    // parent half is its own parent segment's business, and roots sit on the scalp). A few
    // rounds: leaving one sphere may enter an overlapping one.
    for (int round = 0; round < 8; ++round) {
        bool moved = false;
        const Vec3f a = x_[p];
        // The child half of the segment lies within `reach` of its child end.
        float reach = 0.5f * (x_[c] - a).norm();
        for (const Sphere& sphere : world_spheres_) {
            const Vec3f b = x_[c];
            const float near = sphere.radius + reach;
            if ((b - sphere.center).squaredNorm() >= near * near) continue;
            const Vec3f ab = b - a;
            const float len2 = ab.squaredNorm();
            const float t =
                len2 > 1e-12f ? std::clamp((sphere.center - a).dot(ab) / len2, 0.5f, 1.f) : 1.f;
            const Vec3f d = a + t * ab - sphere.center;
            const float dist = d.norm();
            if (dist >= sphere.radius) continue;
            // Moving the child by δ moves the point at t by t·δ.
            Vec3f normal = dist > 1e-6f ? Vec3f(d / dist) : Vec3f(b - sphere.center);
            if (normal.squaredNorm() < 1e-12f) normal = Vec3f::UnitY();
            normal.normalize();
            // A little past the surface: in the crease between two overlapping spheres, leaving
            // each exactly for its surface lands inside the other by less each round without
            // ever leaving both.
            const float out = sphere.radius + kBodyMargin;
            Vec3f to = b + (out - dist) / t * normal;
            const Vec3f e = to - sphere.center;
            if (e.norm() < out) to = sphere.center + out * e.normalized();
            x_[c] = to;
            reach = 0.5f * (to - a).norm();
            moved = any = true;
            collided_[c] = 1;
            // Static friction: the node takes the obstacle's velocity (§4.3).
            const RigidTransform& pose = sphere.head ? head_ : body_;
            v_[c] = (sphere.head ? head_velocity_ : body_velocity_).at(pose.to_local(x_[c]));
        }
        if (!moved) return any;
    }
    // Still moving after every round: caught where spheres meet at a sharp crease, each push
    // out of one landing in another. Leave them all along one line instead, the deepest
    // sphere's normal, to the farthest of their surfaces on it (a few steps at most: every
    // step leaves the spheres it was in for good).
    for (int step = 0; step < 8; ++step) {
        const Sphere* deepest = nullptr;
        float depth = 0.f;
        for (const Sphere& sphere : world_spheres_) {
            const float d = sphere.radius - (x_[c] - sphere.center).norm();
            if (d > depth) depth = d, deepest = &sphere;
        }
        if (!deepest) break;
        Vec3f n = x_[c] - deepest->center;
        n = n.squaredNorm() > 1e-12f ? Vec3f(n.normalized()) : Vec3f::UnitY();
        float t = 0.f;  // the farthest exit along n: |x + t·n − c| = r, larger root
        for (const Sphere& sphere : world_spheres_) {
            const Vec3f e = x_[c] - sphere.center;
            const float b = e.dot(n), q = e.squaredNorm() - sphere.radius * sphere.radius;
            if (q < 0.f) t = std::max(t, -b + std::sqrt(b * b - q));
        }
        x_[c] += (t + kBodyMargin) * n;
    }
    return any;
}

void AwtSimulation::collide_counted(uint32_t c, uint32_t p) {
    const uint8_t before = collided_[c];
    collide_body(c, p);
    if (!before && collided_[c]) ++last_.body_contacts;
}

void AwtSimulation::adapt() {
    const Hierarchy& h = *h_;
    const float threshold = params_.split_threshold;
    const uint32_t finest = h.finest_begin();
    // Splits, tip to root: the active list is ordered by section.
    size_t end = active_.size();
    for (int k = n_ - 1; k >= 1; --k) {
        size_t begin = end;
        while (begin > 0 && h.section_of(active_[begin - 1]) == k)
            --begin;
        for (size_t i = begin; i < end; ++i) {
            const uint32_t c = active_[i];
            const uint32_t g = h.gc_of(c);
            // A tied node moves with the head: there is nothing to resolve.
            if (g >= finest || state_[c] != kActive || h.held[c] >= 1) continue;
            if (acc_[c].norm() * radius_[c] <= threshold) continue;
            if (k < n_ - 1 && state_[h.node(g, k + 1)] != kSplit) continue;
            split(c);
        }
        end = begin;
    }
    // Merges, root to tip; finer levels first so a merge can cascade up within a step.
    for (int k = 1; k < n_; ++k)
        for (int l = h.levels - 2; l >= 0; --l)
            for (uint32_t g = h.level_begin[l]; g < h.level_begin[l + 1]; ++g)
                if (state_[h.node(g, k)] == kSplit) try_merge(g, k);
    if (last_.splits || last_.merges) rebuild_active();
}

void AwtSimulation::rebase_subtree(uint32_t node, const Quat& change) {
    const Hierarchy& h = *h_;
    const uint32_t g = h.gc_of(node);
    const int k = h.section_of(node);
    for (uint32_t s = h.child_begin[g]; s < h.child_begin[g] + h.child_count[g]; ++s) {
        const uint32_t i = h.node(s, k);
        offset_[i] = change * offset_[i];
        rebase_subtree(i, change);
    }
}

void AwtSimulation::split(uint32_t c) {
    const Hierarchy& h = *h_;
    const uint32_t g = h.gc_of(c);
    const int k = h.section_of(c);
    const uint32_t p = parent_[c];
    const Quat q = rotation_[c];
    state_[c] = kSplit;
    for (uint32_t s = h.child_begin[g]; s < h.child_begin[g] + h.child_count[g]; ++s) {
        const uint32_t i = h.node(s, k);
        state_[i] = kActive;
        if (h.held[i] >= 1) {
            hold(i);
        } else {
            x_[i] = x_[c] + q * offset_[i];
            v_[i] = v_[c];
        }
        acc_[i] = acc_[c];
        radius_[i] = h.radius[i];
        parent_[i] = k == 1 ? h.node(s, 0) : p;
        link_length_[i] = (x_[i] - x_[parent_[i]]).norm();
        rotation_[i] = segment_rotation(i, parent_[i], x_[i]);
        // Finer nodes keep their places: their offsets move to the new segment's frame.
        rebase_subtree(i, rotation_[i].conjugate() * q);
        if (params_.body_collisions) collide_counted(i, p);
    }
    events_.push_back({AwtEvent::Kind::kSplit, c});
    ++last_.splits;
    ++total_splits_;
}

bool AwtSimulation::try_merge(uint32_t g, int k) {
    const Hierarchy& h = *h_;
    const uint32_t node = h.node(g, k);
    // Same AWT parent: the node above must not be split (the active node there is g or an
    // ancestor, shared by every sub-node).
    if (k > 1 && state_[h.node(g, k - 1)] == kSplit) return false;
    const uint32_t first = h.child_begin[g], last = first + h.child_count[g];
    double m = 0;
    Vec3d xs = Vec3d::Zero(), vs = Vec3d::Zero(), as = Vec3d::Zero();
    for (uint32_t s = first; s < last; ++s) {
        const uint32_t i = h.node(s, k);
        if (state_[i] != kActive) return false;
        const double mi = h.mass[i];
        m += mi;
        xs += mi * x_[i].cast<double>();
        vs += mi * v_[i].cast<double>();
        as += mi * acc_[i].cast<double>();
    }
    const Vec3f centre = (xs / m).cast<float>(), velocity = (vs / m).cast<float>();
    const Vec3f acceleration = (as / m).cast<float>();
    const float rest_radius = h.radius[node];
    // The split test must be false (§3.2), with a margin so a merged node does not split
    // again at the next step's noise.
    if (acceleration.norm() * rest_radius > kMergeHysteresis * params_.split_threshold)
        return false;
    float fit = 0;
    for (uint32_t s = first; s < last; ++s) {
        const uint32_t i = h.node(s, k);
        const float d = (x_[i] - centre).norm();
        if (d > rest_radius) return false;
        if ((v_[i] - velocity).norm() >= params_.merge_velocity) return false;
        fit = std::max(fit, d + radius_[i]);
    }
    const uint32_t p = find_parent(g, k);
    state_[node] = kActive;
    merge_step_[node] = 1;
    x_[node] = centre;
    v_[node] = velocity;
    acc_[node] = acceleration;
    radius_[node] = std::max(fit, 0.05f);
    parent_[node] = p;
    link_length_[node] = (centre - x_[p]).norm();
    rotation_[node] = segment_rotation(node, p, centre);
    const Quat inverse = rotation_[node].conjugate();
    for (uint32_t s = first; s < last; ++s) {
        const uint32_t i = h.node(s, k);
        state_[i] = kMerged;
        merge_step_[i] = 0;  // merged again before its first step: it starts afresh if split
        // Frozen relative to the super-node from now on (§3.2), in its segment's frame;
        // finer nodes move from the sub-node's frame to it.
        offset_[i] = inverse * (x_[i] - centre);
        rebase_subtree(i, inverse * rotation_[i]);
    }
    if (params_.body_collisions) collide_counted(node, p);
    events_.push_back({AwtEvent::Kind::kMerge, node});
    ++last_.merges;
    ++total_merges_;
    return true;
}

void AwtSimulation::sync() {
    const Hierarchy& h = *h_;
    // Level by level, each in parallel over its GCs: a node reads only coarser nodes (merged)
    // or finer ones (split), never its own level's.
    const auto for_level = [&](int l, const auto& body) {
        const uint32_t first = h.level_begin[l];
        parallel_for(
            h.level_size(l), [&](size_t e) { body(first + static_cast<uint32_t>(e)); }, kGrain / 4);
    };
    // Merged nodes, coarse to fine: from their super-node through the governing rotation.
    std::vector<uint32_t>& governor = governor_;
    governor.resize(h.node_count());
    for (int l = 0; l < h.levels; ++l)
        for_level(l, [&](uint32_t g) {
            for (int k = 1; k < n_; ++k) {
                const uint32_t i = h.node(g, k);
                if (state_[i] == kActive) {
                    governor[i] = i;
                } else if (state_[i] == kMerged) {
                    const uint32_t up = h.node(static_cast<uint32_t>(h.super[g]), k);
                    governor[i] = governor[up];
                    if (h.held[i] >= 1) {
                        hold(i);  // tied, under a node only partly tied: rigid with the head
                    } else {
                        x_[i] = x_[up] + rotation_[governor[i]] * offset_[i];
                        v_[i] = v_[governor[i]];
                    }
                }
            }
        });
    // Split nodes, fine to coarse: their sub-nodes' centre of mass.
    for (int l = h.levels; l-- > 0;)
        for_level(l, [&](uint32_t g) {
            for (int k = 1; k < n_; ++k) {
                const uint32_t i = h.node(g, k);
                if (state_[i] != kSplit) continue;
                Vec3f xs = Vec3f::Zero(), vs = Vec3f::Zero();
                for (uint32_t s = h.child_begin[g]; s < h.child_begin[g] + h.child_count[g]; ++s) {
                    xs += h.mass[h.node(s, k)] * x_[h.node(s, k)];
                    vs += h.mass[h.node(s, k)] * v_[h.node(s, k)];
                }
                x_[i] = xs / h.mass[i];
                v_[i] = vs / h.mass[i];
            }
        });
}

std::vector<uint32_t> AwtSimulation::active_per_level() const {
    std::vector<uint32_t> counts(h_->levels, 0);
    for (uint32_t i : active_)
        ++counts[h_->level[h_->gc_of(i)]];
    return counts;
}

double AwtSimulation::kinetic_energy() const {
    double e = 0;
    for (uint32_t i : active_)
        e += 0.5 * h_->mass[i] * v_[i].squaredNorm();
    return e;
}

double AwtSimulation::active_mass() const {
    double m = 0;
    for (uint32_t i : active_)
        m += h_->mass[i];
    return m;
}

void AwtSimulation::finest_rotations(std::vector<Mat3f>& out) const {
    const Hierarchy& h = *h_;
    const uint32_t first = h.finest_begin();
    const size_t count = h.gc_count() - first;
    out.resize(count * n_);
    const auto segment = [&](uint32_t g, int k) {
        const uint32_t c = h.node(g, k), p = h.node(g, k - 1);
        return rest_to_now(h.rest[c] - h.rest[p], x_[c] - x_[p]);
    };
    // Every GC writes its own rows: parallel, the same at any thread count.
    parallel_for(
        count,
        [&](size_t f) {
            const uint32_t g = first + static_cast<uint32_t>(f);
            out[f * n_] = head_rotation_.toRotationMatrix();
            Quat next = n_ > 1 ? segment(g, 1) : head_rotation_;
            for (int k = 1; k < n_; ++k) {
                Quat q = next;
                if (k + 1 < n_) {
                    next = segment(g, k + 1);
                    Quat flipped = next;
                    if (q.dot(flipped) < 0) flipped.coeffs() = -flipped.coeffs();
                    q.coeffs() = q.coeffs() + flipped.coeffs();
                    q.normalize();
                }
                out[f * n_ + k] = q.toRotationMatrix();
            }
        },
        64);
}

std::string AwtSimulation::check_invariants() const {
    const Hierarchy& h = *h_;
    const uint32_t finest = h.finest_begin();
    for (uint32_t f = finest; f < h.gc_count(); ++f) {
        int previous_level = 0;
        for (int k = 1; k < n_; ++k) {
            // Walk up from the finest node: merged*, active, split*.
            uint32_t g = f;
            int active = 0, active_level = -1;
            bool above_active = false;
            while (true) {
                const uint8_t s = state_[h.node(g, k)];
                if (s == kActive) {
                    ++active;
                    active_level = h.level[g];
                    above_active = true;
                } else if (s == kMerged && above_active) {
                    return cat("node ", h.node(g, k), " is merged above the active node");
                } else if (s == kSplit && !above_active) {
                    return cat("node ", h.node(g, k), " is split below the active node");
                }
                if (h.super[g] < 0) break;
                g = static_cast<uint32_t>(h.super[g]);
            }
            if (active != 1)
                return cat("finest GC ", f, " section ", k, " has ", active, " active nodes");
            if (active_level < previous_level)
                return cat("finest GC ", f, ": the active level decreases at section ", k);
            previous_level = active_level;
        }
    }
    return {};
}

}  // namespace wisp
