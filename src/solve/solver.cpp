#include "solve/solver.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/parallel.hpp"
#include "core/rng.hpp"

namespace wisp {
namespace {

// How much each Δθ bend must thin the hair's density ahead (the fraction) for the solver to
// bend on (see place()).
constexpr float kProgress = 0.05f;

struct Splat {
    int i[3];
    float f[3];
    bool inside = false;
};

Splat locate(const Grid3<float>& g, const Vec3f& p) {
    Splat s;
    const Vec3f x = (p - g.origin()) / g.cell();
    s.inside = true;
    for (int a = 0; a < 3; ++a) {
        if (!(x[a] >= 0.f) || x[a] > static_cast<float>(g.dims()[a] - 1)) s.inside = false;
        const float c = std::clamp(x[a], 0.f, static_cast<float>(g.dims()[a] - 1));
        s.i[a] = std::min(static_cast<int>(c), g.dims()[a] - 2);
        s.f[a] = c - static_cast<float>(s.i[a]);
    }
    return s;
}

// The trilinear value at p, 0 outside the grid: locate() and Grid3::trilinear's arithmetic
// to the bit, for the lookups of the hair density (several per try of every joint, the
// solve's most frequent operation). Inside the grid, locate()'s clamping changes nothing, so
// a point outside returns at once, and the eight nodes are read by index steps from the
// first rather than by at()'s index arithmetic per node.
inline float sample(const Grid3<float>& g, const Vec3f& p) {
    const Vec3f x = (p - g.origin()) / g.cell();
    const Vec3i& dims = g.dims();
    int i[3];
    float f[3];
    for (int a = 0; a < 3; ++a) {
        if (!(x[a] >= 0.f) || x[a] > static_cast<float>(dims[a] - 1)) return 0.f;
        i[a] = std::min(static_cast<int>(x[a]), dims[a] - 2);
        f[a] = x[a] - static_cast<float>(i[a]);
    }
    // Density grids have at least 2 nodes per axis (grid_nodes), so every step is a node's.
    const size_t dy = static_cast<size_t>(dims[0]), dz = dy * static_cast<size_t>(dims[1]);
    const float* v = g.data().data() + g.index(i[0], i[1], i[2]);
    const float c00 = v[0] * (1 - f[0]) + v[1] * f[0];
    const float c10 = v[dy] * (1 - f[0]) + v[dy + 1] * f[0];
    const float c01 = v[dz] * (1 - f[0]) + v[dz + 1] * f[0];
    const float c11 = v[dz + dy] * (1 - f[0]) + v[dz + dy + 1] * f[0];
    const float c0 = c00 * (1 - f[1]) + c10 * f[1];
    const float c1 = c01 * (1 - f[1]) + c11 * f[1];
    return c0 * (1 - f[2]) + c1 * f[2];
}

// Adds `amount` at p with trilinear weights (the density a wisp segment creates).
void deposit(Grid3<float>& g, const Vec3f& p, float amount) {
    const Splat s = locate(g, p);
    if (!s.inside) return;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const float w = (dx ? s.f[0] : 1 - s.f[0]) * (dy ? s.f[1] : 1 - s.f[1]) *
                                (dz ? s.f[2] : 1 - s.f[2]);
                g.at(s.i[0] + dx, s.i[1] + dy, s.i[2] + dz) += w * amount;
            }
}

// The figures one joint placement adds to SolveStats: integers, so their sums do not depend
// on the order the joints were placed in.
struct Counts {
    size_t joints = 0, bends = 0, collisions = 0, unresolved = 0, projected = 0, constrained = 0,
           contacts = 0;
};

// The grid nodes one joint placement may touch, as inclusive index ranges per axis: every
// node a trilinear read within `radius` cm of x can weigh (locate()'s clamping included).
// A position that is not finite may touch anything.
struct NodeBox {
    int lo[3], hi[3];
};

NodeBox node_box(const Grid3<float>& g, const Vec3f& x, float radius) {
    NodeBox b;
    const bool finite = x.allFinite() && std::isfinite(radius);
    for (int a = 0; a < 3; ++a) {
        const float top = static_cast<float>(g.dims()[a] - 1);
        if (!finite) {
            b.lo[a] = 0;
            b.hi[a] = g.dims()[a] - 1;
            continue;
        }
        const float c = (x[a] - g.origin()[a]) / g.cell(), r = radius / g.cell();
        const float lo = std::clamp(c - r, 0.f, top), hi = std::clamp(c + r, 0.f, top);
        b.lo[a] = std::min(static_cast<int>(lo), g.dims()[a] - 2);
        b.hi[a] = std::min(static_cast<int>(hi), g.dims()[a] - 2) + 1;
    }
    return b;
}

class Solver {
  public:
    Solver(Masters& m, const SolveInput& in, const SolveSpec& spec, Grid3<float>& density)
        : m_(m), in_(in), spec_(spec), rho_(density) {
        const size_t w_count = m.count();
        dir_ = m.direction;
        // The hair leaves the scalp at its protrusion angle, flowing the way the styling
        // field flows along the scalp there (away from the crown where the field runs into
        // or out of the scalp, as gravity does on top of the head).
        for (size_t w = 0; w < w_count; ++w) {
            const Vec3f& n = m.roots[w].normal;
            const Vec3f phi = (*in.field)(m.roots[w].position);
            const Vec3f along = phi - phi.dot(n) * n;
            if (along.norm() < 0.3f * phi.norm() || along.norm() < 1e-4f) continue;
            const float up = std::clamp(dir_[w].dot(n), -1.f, 1.f);
            dir_[w] = (std::sqrt(1.f - up * up) * along.normalized() + up * n).normalized();
        }
        group_of_.assign(w_count, -1);
        for (size_t g = 0; g < in.groups.size(); ++g)
            for (uint32_t w : in.groups[g].wisps)
                if (group_of_[w] < 0) group_of_[w] = static_cast<int>(g);
        active_.assign(in.groups.size(), 0);
        wisp_stage_.assign(w_count, 0);
        bend_ = spec.bend_step * kPi / 180.f;
        inv_cell3_ = 1.f / (rho_.cell() * rho_.cell() * rho_.cell());
        std::fill(rho_.data().begin(), rho_.data().end(), 0.f);
        met_count_.resize(in.groups.size());
        for (size_t g = 0; g < in.groups.size(); ++g)
            met_count_[g].assign(in.groups[g].queue.size(), 0);
        stats_.held_length.assign(w_count, 0.f);
        stats_.wisp_met.assign(w_count, 0);
        following_.assign(w_count, nullptr);
        follow_arc_.assign(w_count, 0.f);
        // Each wisp keeps its own place across a followed trajectory's tube (so a braid's
        // strand or a bun's coil is a bundle as wide as the tube, not a single curve).
        follow_offset_.resize(w_count);
        for (size_t w = 0; w < w_count; ++w) {
            Rng rng(0x7a11, Stream::kMisc, w);
            follow_offset_[w] = (0.8f * std::cbrt(rng.uniform())) * rng.unit_vector();
        }
        nearest_tie_.assign(w_count, 0);
        nearest_tie_distance_.assign(w_count, std::numeric_limits<float>::infinity());
        counts_.assign(w_count, Counts{});
        if (!spec.depth_first) {
            for (int a = 0; a < 3; ++a)
                block_dims_[a] = (rho_.dims()[a] + kBlock - 1) / kBlock;
            const size_t blocks =
                static_cast<size_t>(block_dims_[0]) * block_dims_[1] * block_dims_[2];
            blocks_.assign(blocks, Block{});
            done_ = std::vector<Done>(blocks);
            level_.resize(w_count);
            by_level_.resize(w_count);
        }
    }

    SolveStats run() {
        const int n = m_.points;
        const size_t w_count = m_.count();
        const auto cancelled = [&] {
            stats_.cancelled = in_.cancel && in_.cancel->cancelled();
            return stats_.cancelled;
        };
        // Progress: after each layer (or each 1/64 of the wisps), on this thread.
        const auto progress = [&](size_t done, size_t total) {
            if (in_.cancel) in_.cancel->progress(done, total);
        };
        if (spec_.depth_first) {
            const size_t every = std::max<size_t>(1, w_count / 64);
            for (size_t w = 0; w < w_count; ++w) {
                if (cancelled()) return stats_;
                for (int j = 0; j + 1 < n; ++j)
                    place(w, j, /*per_wisp_queue=*/true);
                if ((w + 1) % every == 0 || w + 1 == w_count) progress(w + 1, w_count);
            }
        } else {
            for (int j = 0; j + 1 < n; ++j) {
                if (cancelled()) return stats_;
                place_layer(j);
                advance_groups();
                publish(j + 2);
                progress(static_cast<size_t>(j + 1), static_cast<size_t>(n - 1));
            }
        }
        publish(n);
        for (const Counts& c : counts_) {
            stats_.joints += c.joints;
            stats_.bends += c.bends;
            stats_.collisions += c.collisions;
            stats_.unresolved += c.unresolved;
            stats_.projected += c.projected;
            stats_.contacts += c.contacts;
            stats_.constrained += c.constrained;
        }
        if (in_.update_frames)
            parallel_for(
                w_count, [&](size_t w) { update_master(m_, w); }, 64);
        for (size_t w = 0; w < w_count; ++w) {
            // A wisp that a tie pulled but collisions kept from meeting it (the group moved
            // on without it) is tied where it came closest: it lies with the tied hair.
            if (stats_.held_length[w] == 0 && nearest_tie_[w] > 0)
                stats_.held_length[w] = static_cast<float>(nearest_tie_[w]) * m_.segment[w];
        }
        std::vector<size_t> members(in_.groups.size(), 0);
        for (size_t w = 0; w < w_count; ++w)
            if (group_of_[w] >= 0) ++members[group_of_[w]];
        for (size_t g = 0; g < in_.groups.size(); ++g) {
            SolveStats::Group& out = stats_.groups.emplace_back();
            out.name = in_.groups[g].name;
            out.constraints = static_cast<int>(in_.groups[g].queue.size());
            out.completed = spec_.depth_first ? 0 : active_[g];
            // The last wisps meet a constraint at their last joints, too late for the group to
            // move on: it completed a constraint that 95% of its wisps met.
            while (!spec_.depth_first && out.completed < out.constraints && members[g] &&
                   met_count_[g][out.completed] >= 0.95 * double(members[g]))
                ++out.completed;
            out.wisps = members[g];
            for (size_t k = 0; k < met_count_[g].size(); ++k) {
                out.met.push_back(members[g] ? float(met_count_[g][k]) / float(members[g]) : 0.f);
                // Depth-first, each wisp runs its own queue: a constraint is completed when
                // every wisp met it.
                if (spec_.depth_first && met_count_[g][k] == members[g] &&
                    out.completed == static_cast<int>(k))
                    ++out.completed;
            }
        }
        return stats_;
    }

  private:
    // SolveInput::joints_final.
    void publish(int joints) const {
        if (!in_.joints_final) return;
        in_.joints_final->store(joints, std::memory_order_release);
        in_.joints_final->notify_all();
    }
    float hair_density(const Vec3f& p) const { return sample(rho_, p); }
    float head_density(const Vec3f& p) const { return in_.head->density(p, spec_.head_margin); }
    // Hair and head density at p, the head's (`head`) already known; `squeeze`: the head's
    // alone (see place()).
    float total_density(const Vec3f& p, float head, bool squeeze) const {
        return squeeze ? head : hair_density(p) + head;
    }
    float total_density(const Vec3f& p, bool squeeze) const {
        return total_density(p, head_density(p), squeeze);
    }
    // A tie or a braid squeezes hair together: inside a point constraint's tolerance sphere,
    // or a trajectory constraint's tolerance tube, hair does not collide with hair (it still
    // collides with the head).
    // `reach` widens the region by what one segment can cover.
    static bool inside_tie(const Constraint& c, const Vec3f& p, float reach) {
        if (c.kind == ConstraintSpec::Kind::kPoint) return (p - c.point).norm() <= c.radius + reach;
        if (c.kind == ConstraintSpec::Kind::kTrajectory)
            return (nearest_on_path(c, p).position - p).norm() <= c.radius + reach;
        return false;
    }
    // The central differences' step, cm.
    float gradient_step() const { return 0.25f * std::min(rho_.cell(), in_.head->grid().cell()); }
    // Gradient of the total density by central differences.
    Vec3f density_gradient(const Vec3f& p, bool squeeze) const {
        const float h = gradient_step();
        Vec3f g;
        for (int a = 0; a < 3; ++a) {
            Vec3f e = Vec3f::Zero();
            e[a] = h;
            g[a] = (total_density(p + e, squeeze) - total_density(p - e, squeeze)) / (2.f * h);
        }
        return g;
    }

    // The constraint that currently acts on wisp w, or null. A wisp that met a constraint
    // goes on to the next at once (hair gathered at a tie is braided or wound on from there);
    // breadth-first, the group also carries on the wisps that lag when it moves on.
    size_t stage(size_t w, bool per_wisp_queue) const {
        const int g = group_of_[w];
        return per_wisp_queue ? wisp_stage_[w]
                              : std::max<size_t>(wisp_stage_[w], static_cast<size_t>(active_[g]));
    }
    const Constraint* active_constraint(size_t w, bool per_wisp_queue) const {
        const int g = group_of_[w];
        if (g < 0) return nullptr;
        const auto& queue = in_.groups[g].queue;
        const size_t k = stage(w, per_wisp_queue);
        return k < queue.size() ? &queue[k] : nullptr;
    }

    // A trajectory with w = 1 is followed, as hands lay hair along a braid or round a bun:
    // once wisp w is within the tube, each joint advances its place on the path by a segment
    // (a bun's trajectory winds on over its last turn). Returns the direction to take, or
    // false while the wisp has not reached the tube. `end` tells it reached the path's end.
    bool follow(size_t w, const Constraint& c, const Vec3f& x, float s, Vec3f& q, bool& end) {
        end = false;
        if (following_[w] != &c) {
            float arc = 0.f;
            const PathPoint p = nearest_on_path(c, x, -INFINITY, INFINITY, &arc);
            if ((p.position - x).norm() > c.radius + s) return false;
            following_[w] = &c;
            follow_arc_[w] = arc;
        }
        const float total = c.arc.empty() ? 0.f : c.arc.back();
        float target = follow_arc_[w] + s;
        if (target >= total) {
            if (c.repeat_from >= 0.f && total - c.repeat_from > s)
                target = c.repeat_from + std::fmod(target - c.repeat_from, total - c.repeat_from);
            else
                end = true;
        }
        const PathPoint p = point_at_arc(c, target);
        const Vec3f& o = follow_offset_[w];
        const Vec3f goal = p.position + c.radius * (o - o.dot(p.tangent) * p.tangent);
        const Vec3f v = goal - x;
        q = v.norm() > 1e-6f ? Vec3f(v.normalized()) : p.tangent;
        follow_arc_[w] = std::min(target, total);
        return true;
    }

    // Places joint j + 1 of wisp w. Of the state other wisps share, it reads the hair density
    // only at points within s + gradient_step() of joint j (the segment's end and middle
    // for unit directions, and the gradient's samples around them) and adds to it only
    // within s/2 of joint j (its middle): place_layer() relies on this.
    void place(size_t w, int j, bool per_wisp_queue) {
        const int n = m_.points;
        const size_t base = w * static_cast<size_t>(n);
        const Vec3f x = m_.outline[base + j];
        const float s = m_.segment[w];
        Counts& counts = counts_[w];
        const Vec3f q0 = dir_[w];  // zero joint angle: continue the previous segment

        Vec3f phi = (*in_.field)(x);
        const Constraint* c = active_constraint(w, per_wisp_queue);
        Vec3f followed;
        bool at_end = false;
        const bool following = c && c->kind == ConstraintSpec::Kind::kTrajectory &&
                               c->weight >= 0.99f && follow(w, *c, x, s, followed, at_end);
        if (c) {
            phi = constrained_field(phi, constraint_force(*c, x), c->weight);
            ++counts.constrained;
        }
        // Shrinkwrap: hair near the skin is pulled in along its normal (only in choosing the
        // direction: on the skin it slides as without, not held by a harder press).
        Vec3f drawn = phi;
        if (!c && spec_.wrap > 0.f) {
            Vec3f n;
            const float d = in_.head->sdf(x, &n);
            const float nn = n.norm();
            if (d < spec_.wrap && nn > 1e-6f)
                drawn -= (phi.norm() * (1.f - smoothstep(0.f, spec_.wrap, d)) / nn) * n;
        }
        Vec3f q = following ? followed : best_direction(drawn, q0, spec_.stiffness);
        if (!c && !in_.root_hold.empty()) {
            const float hold = in_.root_hold[w];
            const float h = 1.f - smoothstep(0.f, hold, static_cast<float>(j) * s);
            if (h > 0.f) q = ((1.f - h) * q + h * q0).normalized();
        }
        if (!following) {
            // On the skin, the segment slides along it instead of bending away by eq. (6)'s
            // steps, which crinkled hair lying on the shoulders into zigzags. A constraint's
            // pull (a hand gathering hair) is not held back by friction.
            Vec3f n;
            const float d_end = in_.head->sdf(x + s * q, &n);
            const float nn = n.norm();
            if (d_end < spec_.head_margin && nn > 1e-6f) {
                const float d_x = in_.head->sdf(x);
                const float lift = (spec_.head_margin - d_x) / s;
                q = slide_direction(phi, q0, n / nn, spec_.stiffness, c ? 0.f : spec_.friction,
                                    lift);
                ++counts.contacts;
            }
        }
        // Decided once per joint, at the joint: nearest_on_path is not cheap.
        // A tie with w = 1 pulls hair in like a hand gathering it: while it acts, and within
        // reach of a trajectory's tube, hair passes through hair.
        const bool squeeze = c && (c->weight >= 0.99f || inside_tie(*c, x, s));

        // Eq. (6) with the segment's own density ρ_Δ: its strands over its cross-section.
        const float r = std::max(in_.wisp_radius[w] * in_.radius_profile[j], 0.25f * rho_.cell());
        const float rho_delta =
            static_cast<float>(in_.wisp_strands[w]) / (kPi * r * r * spec_.full_density);
        int tries = 0;
        bool collided = false;
        Vec3f best_q = q;
        float best_density = INFINITY, last_worst = INFINITY;
        for (; !following;) {
            const Vec3f end = x + s * q, mid = x + 0.5f * s * q;
            const float head_end = head_density(end), head_mid = head_density(mid);
            const float d_end = total_density(end, head_end, squeeze),
                        d_mid = total_density(mid, head_mid, squeeze);
            const float worst = std::max(d_end, d_mid);
            if (worst < best_density) {
                best_density = worst;
                best_q = q;
            }
            if (worst + rho_delta <= spec_.threshold) break;
            collided = true;
            // Among hair alone (the head is always escaped), a bend that no longer thins the
            // density ahead by kProgress means the hair around is packed as far as it goes:
            // bending on would only splay the wisp sideways (at a small τ, into a lampshade).
            const bool packed = tries > 0 && worst > (1.f - kProgress) * last_worst &&
                                head_end == 0.f && head_mid == 0.f;
            last_worst = worst;
            if (tries >= spec_.max_tries || packed) {
                // Still colliding: keep the least dense direction tried.
                ++counts.unresolved;
                q = best_q;
                break;
            }
            const Vec3f g = density_gradient(d_end >= d_mid ? end : mid, squeeze);
            const float gn = g.norm();
            if (!(gn > 1e-8f)) break;
            const Vec3f away = -g / gn;
            Vec3f axis = q.cross(away);
            if (axis.norm() < 1e-6f) {
                if (q.dot(away) > 0.f) break;  // already heading down the gradient
                axis = any_perpendicular(q);
            }
            q = (Eigen::AngleAxisf(bend_, axis.normalized()) * q).normalized();
            ++tries;
            ++counts.bends;
        }
        if (collided) ++counts.collisions;
        // Whatever the density says, a joint never ends inside the head.
        const float clearance = 0.5f * spec_.head_margin;
        const Vec3f end = x + s * q;
        const float d = in_.head->sdf(end);
        if (d < clearance) {
            const Vec3f g = in_.head->gradient(end);
            if (g.norm() > 1e-6f) {
                const Vec3f target = end + (clearance - d) * g.normalized();
                const Vec3f v = target - x;
                if (v.norm() > 1e-6f) {
                    q = v.normalized();
                    ++counts.projected;
                }
            }
        }

        m_.outline[base + j + 1] = x + s * q;
        dir_[w] = q;
        const float reached = static_cast<float>(j + 1) * s;  // arc length to the new joint
        if (c && c->hold) {
            const Vec3f& b = m_.outline[base + j + 1];
            if (c->kind == ConstraintSpec::Kind::kTrajectory) {
                // A holding trajectory (a bun) holds the wisp as far as it follows it, met
                // or not: hair too short to finish the spiral is pinned all the same.
                if ((nearest_on_path(*c, b).position - b).norm() <= c->radius + s)
                    stats_.held_length[w] = reached;
            } else if (c->kind == ConstraintSpec::Kind::kPoint) {
                const float d = (b - c->point).norm();
                if (d < nearest_tie_distance_[w]) {
                    nearest_tie_distance_[w] = d;
                    nearest_tie_[w] = j + 1;
                }
            }
        }
        ++counts.joints;
        // Algorithm 1: updateDensityField() with this segment's strands.
        deposit(rho_, x + 0.5f * s * q,
                static_cast<float>(in_.wisp_strands[w]) * s / spec_.full_density * inv_cell3_);

        // A followed trajectory is met at its end; a bun's, which winds on, when the wisp ends
        // in it.
        const bool met = following ? at_end || (c->repeat_from >= 0.f && j + 2 == n)
                                   : c && constraint_met(*c, x, m_.outline[base + j + 1]);
        if (met) {
            if (c->hold) stats_.held_length[w] = reached;
            const size_t k = static_cast<size_t>(c - in_.groups[group_of_[w]].queue.data());
            std::atomic_ref<size_t>(met_count_[group_of_[w]][k])
                .fetch_add(1, std::memory_order_relaxed);
            ++stats_.wisp_met[w];
            wisp_stage_[w] = static_cast<uint32_t>(k + 1);
        }
    }

    // Breadth-first layer j: joint j + 1 of every wisp, with the result of placing them one
    // after another in id order. Each placement reads and writes the density grid only near
    // its wisp's joint j (place()), and each wisp's other state is its own, so a placement
    // need only wait for the earlier ones whose writes its reads or writes could meet and
    // those whose reads its writes could meet (over blocks of kBlock³ nodes, a conservative
    // test). Per block, the solve counts the placements that read it and those that write it
    // (a writer also reads): a placement starts once the counts of finished ones reach those
    // registered before it in id order. Every pair that could interact then does so in id
    // order, as the serial solve does, so the grid and masters are the same bytes at any
    // thread count. Placements are taken in an order where all that one waits for come
    // before it (by level, its longest chain of waits), so the lanes never deadlock.
    void place_layer(int j) {
        const size_t w_count = m_.count();
        const int lanes = std::min<int>(tbb::this_task_arena::max_concurrency(),
                                        static_cast<int>(tbb::global_control::active_value(
                                            tbb::global_control::max_allowed_parallelism)));
        const bool by_level = in_.schedule == SolveInput::Schedule::kByLevel;
        if (!(by_level || (in_.schedule == SolveInput::Schedule::kConcurrent && lanes > 1))) {
            for (size_t w = 0; w < w_count; ++w)
                place(w, j, false);
            return;
        }
        const size_t n = static_cast<size_t>(m_.points);
        // Reads reach s + the gradient step, writes s/2; the slack covers rounding in the
        // positions place() computes (|q| = 1 to a few ulps).
        const float h = gradient_step(), slack = 0.01f * rho_.cell();
        wait_start_.resize(w_count + 1);
        waits_.clear();
        int top = 0;
        for (size_t w = 0; w < w_count; ++w) {
            wait_start_[w] = waits_.size();
            const Vec3f& x = m_.outline[w * n + j];
            const float s = m_.segment[w];
            const NodeBox reads = node_box(rho_, x, s + h + slack);
            const NodeBox writes = node_box(rho_, x, 0.5f * s + slack);
            int level = 0;
            // The write box lies inside the read box: a read block's earlier writers cover
            // write after write.
            visit_blocks(reads, [&](size_t b) {
                Block& k = blocks_[b];
                level = std::max(level, k.write_level + 1);
                waits_.push_back({static_cast<uint32_t>(b), false, k.writes});
            });
            visit_blocks(writes, [&](size_t b) {
                Block& k = blocks_[b];
                level = std::max(level, k.read_level + 1);
                waits_.push_back({static_cast<uint32_t>(b), true, k.reads});
            });
            visit_blocks(reads, [&](size_t b) {
                Block& k = blocks_[b];
                ++k.reads;
                k.read_level = std::max(k.read_level, level);
            });
            visit_blocks(writes, [&](size_t b) {
                Block& k = blocks_[b];
                ++k.writes;
                k.write_level = std::max(k.write_level, level);
            });
            level_[w] = level;
            top = std::max(top, level);
        }
        wait_start_[w_count] = waits_.size();
        // Levels are per layer: clear them where this layer set them.
        for (const Wait& wt : waits_) {
            blocks_[wt.block].read_level = -1;
            blocks_[wt.block].write_level = -1;
        }
        // The wisps by level, in id order within one (a counting sort).
        level_start_.assign(static_cast<size_t>(top) + 2, 0);
        for (size_t w = 0; w < w_count; ++w)
            ++level_start_[level_[w] + 1];
        for (size_t l = 1; l < level_start_.size(); ++l)
            level_start_[l] += level_start_[l - 1];
        for (size_t w = 0; w < w_count; ++w)
            by_level_[level_start_[level_[w]]++] = static_cast<uint32_t>(w);

        std::atomic<size_t> next{0};
        const auto lane = [&] {
            for (size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < w_count;) {
                const uint32_t w = by_level_[i];
                for (size_t k = wait_start_[w]; k < wait_start_[w + 1]; ++k) {
                    const Wait& wt = waits_[k];
                    const std::atomic<int>& done =
                        wt.readers ? done_[wt.block].reads : done_[wt.block].writes;
                    for (int spin = 0; done.load(std::memory_order_acquire) < wt.count; ++spin)
                        if (spin >= 64) std::this_thread::yield();
                }
                place(w, j, false);
                // Reads of the read box, then writes of the write box (the read box's first
                // entries, the write box's after them in waits_): released together with the
                // placement's writes.
                for (size_t k = wait_start_[w]; k < wait_start_[w + 1]; ++k) {
                    const Wait& wt = waits_[k];
                    (wt.readers ? done_[wt.block].writes : done_[wt.block].reads)
                        .fetch_add(1, std::memory_order_release);
                }
            }
        };
        if (lanes > 1)
            tbb::parallel_for(0, lanes, [&](int) { lane(); });
        else
            lane();
    }

    // Calls f(block index) for every block a node box touches.
    template <typename F>
    void visit_blocks(const NodeBox& box, F&& f) const {
        for (int z = box.lo[2] / kBlock; z <= box.hi[2] / kBlock; ++z)
            for (int y = box.lo[1] / kBlock; y <= box.hi[1] / kBlock; ++y)
                for (int x = box.lo[0] / kBlock; x <= box.hi[0] / kBlock; ++x)
                    f((static_cast<size_t>(z) * block_dims_[1] + y) * block_dims_[0] + x);
    }

    // §4: a group moves to its next constraint once all its wisps met the active one. A
    // few wisps that collisions keep from ever meeting it must not hold the rest forever:
    // the group also moves on when 80% have met it and no more did over the last 3 joints.
    void advance_groups() {
        stalled_.resize(in_.groups.size(), 0);
        last_met_.resize(in_.groups.size(), 0);
        for (size_t g = 0; g < in_.groups.size(); ++g) {
            const SolverGroup& group = in_.groups[g];
            if (active_[g] >= static_cast<int>(group.queue.size())) continue;
            size_t members = 0, met = 0;
            for (uint32_t w : group.wisps)
                if (group_of_[w] == static_cast<int>(g)) {
                    ++members;
                    met += wisp_stage_[w] > static_cast<uint32_t>(active_[g]);
                }
            stalled_[g] = met == last_met_[g] ? stalled_[g] + 1 : 0;
            last_met_[g] = met;
            const bool all = met == members;
            const bool enough = met >= 0.8 * static_cast<double>(members) && stalled_[g] >= 3;
            if (!all && !enough) continue;
            ++active_[g];
            stalled_[g] = 0;
            last_met_[g] = 0;
        }
    }

    Masters& m_;
    const SolveInput& in_;
    const SolveSpec& spec_;
    Grid3<float>& rho_;
    std::vector<Vec3f> dir_;
    std::vector<int> group_of_;
    std::vector<int> active_;
    std::vector<uint32_t> wisp_stage_;
    // The joint of each wisp closest to a holding point constraint that was acting on it
    // (0: none), and its distance.
    std::vector<int> nearest_tie_;
    std::vector<float> nearest_tie_distance_;
    std::vector<int> stalled_;
    std::vector<const Constraint*> following_;    // per wisp: the trajectory it follows
    std::vector<float> follow_arc_;               // per wisp: its arc length along it, cm
    std::vector<Vec3f> follow_offset_;            // per wisp: its place across the tube
    std::vector<std::vector<size_t>> met_count_;  // per group, per constraint: wisps that met it
    std::vector<size_t> last_met_;
    std::vector<Counts> counts_;  // per wisp
    // place_layer's schedule, per block of kBlock³ density nodes: the placements registered
    // to read and to write it (over the whole solve) and the highest level among this
    // layer's; the placements that finished reading and writing it; per wisp its level and
    // what it waits for (waits_[wait_start_[w] …]); the wisps by level.
    static constexpr int kBlock = 2;
    struct Block {
        int reads = 0, writes = 0;
        int read_level = -1, write_level = -1;
    };
    struct Done {
        std::atomic<int> reads{0}, writes{0};
    };
    struct Wait {
        uint32_t block;
        bool readers;  // true: for `count` finished reads, false: finished writes
        int count;
    };
    int block_dims_[3] = {0, 0, 0};
    std::vector<Block> blocks_;
    std::vector<Done> done_;
    std::vector<Wait> waits_;
    std::vector<size_t> wait_start_, level_start_;
    std::vector<int> level_;
    std::vector<uint32_t> by_level_;
    float bend_ = 0.f, inv_cell3_ = 1.f;
    SolveStats stats_;
};

}  // namespace

SolveStats solve_masters(Masters& masters, const SolveInput& in, const SolveSpec& spec,
                         Grid3<float>& density) {
    Solver solver(masters, in, spec, density);
    return solver.run();
}

}  // namespace wisp
