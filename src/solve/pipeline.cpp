#include "solve/pipeline.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/grid.hpp"
#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "groom/color.hpp"
#include "groom/growth.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace {

// How far member points keep off the head (cm): more than the head field's interpolation
// error near curved skin, so that the exact surface is never crossed. That error grows as
// the skin's radius of curvature shrinks below the field's cell: 0.2 cm was enough for heads
// without small forms, not for the rims of the built-in head's ears (radius ~0.6 cm under
// a 0.75 cm grid, where it reaches ~0.25 cm).
constexpr float kClearance = 0.3f;

}  // namespace

HeadFrame head_frame(const Scalp& scalp) {
    HeadFrame f;
    f.center = scalp.center();
    f.radius = std::max((scalp.crown() - scalp.center()).norm(), 1e-3f);
    return f;
}

HeadFrame head_frame(const Head& head) {
    HeadFrame f = head_frame(*head.scalp);
    if (!head.landmarks || !head.mesh) return f;
    const Landmarks& l = *head.landmarks;
    f.neck = l.neck;
    f.forward = l.forward;
    f.neck_radius = l.neck_radius;
    f.split = (l.center - l.neck).dot(l.forward);
    // The shoulders' top beside the neck: the highest skin below the neck between 1.8 and 2.6
    // neck radii out to either side, within 1.5 radii of the neck's axis front to back (the
    // slope of the trapezius, where hair falling beside the neck lands).
    const Vec3f side = Vec3f::UnitY().cross(l.forward);
    float top = -INFINITY;
    for (const Vec3f& v : head.mesh->vertices) {
        const Vec3f d = v - l.neck;
        const float out = std::abs(d.dot(side)) / l.neck_radius;
        if (d.y() < 0.f && out > 1.8f && out < 2.6f &&
            std::abs(d.dot(l.forward)) < 1.5f * l.neck_radius)
            top = std::max(top, v.y());
    }
    if (std::isfinite(top)) f.shoulder_top = top;
    return f;
}

float head_field_cell(const SolveSpec& spec) {
    return std::min(0.75f, 0.75f * spec.cell);
}

size_t cut_hair(Hair& hair, const Vec3f& normal, float plane, size_t* removed,
                const std::vector<float>* offsets, std::vector<uint8_t>* was_cut) {
    const size_t s_count = hair.strand_count();
    std::vector<uint32_t> keep(s_count, 0);  // points kept per strand (0: removed)
    std::vector<uint8_t> cut(s_count, 0);
    std::vector<Vec3f> tip(s_count);
    std::vector<float> tip_width(s_count);
    parallel_for(
        s_count,
        [&](size_t i) {
            const auto s = hair.strand(i);
            keep[i] = static_cast<uint32_t>(s.size());
            const float offset = offsets ? (*offsets)[i] : plane;
            if (s.empty() || std::isnan(offset)) return;
            keep[i] = 0;
            if (normal.dot(s[0]) > offset) return;
            size_t k = 1;
            while (k < s.size() && normal.dot(s[k]) <= offset)
                ++k;
            keep[i] = static_cast<uint32_t>(k);
            if (k < s.size()) {
                const float a = normal.dot(s[k - 1]) - offset, b = normal.dot(s[k]) - offset;
                const float f = std::clamp(a / (a - b), 0.f, 1.f);
                tip[i] = s[k - 1] + f * (s[k] - s[k - 1]);
                const size_t o = hair.offsets[i];
                tip_width[i] = hair.widths.empty()
                                   ? hair.default_width
                                   : hair.widths[o + k - 1] +
                                         f * (hair.widths[o + k] - hair.widths[o + k - 1]);
                cut[i] = 1;
            }
        },
        1024);
    Hair out;
    out.default_width = hair.default_width;
    out.default_color = hair.default_color;
    size_t shortened = 0, gone = 0;
    if (was_cut) was_cut->clear();
    for (size_t i = 0; i < s_count; ++i) {
        if (keep[i] == 0) {
            ++gone;
            continue;
        }
        if (was_cut) was_cut->push_back(cut[i]);
        const size_t o = hair.offsets[i];
        const size_t n = keep[i];
        out.points.insert(out.points.end(), hair.points.begin() + o, hair.points.begin() + o + n);
        if (!hair.widths.empty())
            out.widths.insert(out.widths.end(), hair.widths.begin() + o,
                              hair.widths.begin() + o + n);
        if (cut[i]) {
            ++shortened;
            out.points.push_back(tip[i]);
            if (!hair.widths.empty()) out.widths.push_back(tip_width[i]);
        }
        out.offsets.push_back(static_cast<uint32_t>(out.points.size()));
        if (!hair.colors.empty()) out.colors.push_back(hair.colors[i]);
        if (!hair.wisp.empty()) out.wisp.push_back(hair.wisp[i]);
        if (!hair.root_uv.empty()) out.root_uv.push_back(hair.root_uv[i]);
        if (!hair.root_normal.empty()) out.root_normal.push_back(hair.root_normal[i]);
        if (!hair.group.empty()) out.group.push_back(hair.group[i]);
    }
    hair = std::move(out);
    if (removed) *removed = gone;
    return shortened;
}

void bevel_ends(Hair& hair, std::span<const uint8_t> turn, float bevel, const Vec3f& center) {
    if (!(bevel > 0.f)) return;
    parallel_for(
        hair.strand_count(),
        [&](size_t i) {
            if (i >= turn.size() || !turn[i]) return;
            const auto s = hair.strand(i);
            if (s.size() < 2) return;
            const Vec3f tip = s.back();
            const Vec3f to_axis(center.x() - tip.x(), 0.f, center.z() - tip.z());
            const float d = to_axis.norm();
            if (!(d > 1e-4f)) return;
            // Inward, and no further than the axis.
            const Vec3f in = to_axis / d;
            const float reach = std::min(bevel, 2.f * d);
            // Arc length back from the tip to each point; the stretch is the last `reach` cm.
            float from_tip = 0.f;
            for (size_t k = s.size() - 1; k > 0; --k) {
                const float t = 1.f - from_tip / reach;
                if (t <= 0.f) break;
                from_tip += (s[k] - s[k - 1]).norm();
                s[k] += (0.5f * reach * t * t) * in;
            }
        },
        1024);
}

namespace {

// Where the plane cuts each strand: `plane` along the normal (cm), then further by the
// point-cut texture, a random depth per wisp (the clump a hairdresser holds between two
// fingers and cuts as one) plus a third of it per strand, so ends neither line up on a
// ruler line nor scatter strand by strand. A fringe cut cuts only the fringe's strands, and
// lower toward its corners, where it meets the side hair: 0.08 head units lower at its
// outer ends (a blunt fringe is cut on a slight curve) and down to 0.35 at the sector's
// edge, graduated into the side hair as a fringe is blended in, not ending in a square
// corner. NaN: the strand is not cut.
std::vector<float> cut_offsets(const Style& style, const Scalp& scalp, float radius,
                               const Hair& hair, float plane) {
    const bool fringe = style.cut.region == CutSpec::Region::kFringe;
    const float texture = style.cut.texture;
    std::vector<float> offsets(hair.strand_count(), plane);
    parallel_for(
        offsets.size(),
        [&](size_t i) {
            const auto s = hair.strand(i);
            if (s.empty()) return;
            float offset = plane;
            if (fringe) {
                const Vec3f r = scalp_direction(scalp, s[0]);
                const float w = fringe_sector(r);
                if (w <= 0.05f) {
                    offsets[i] = std::numeric_limits<float>::quiet_NaN();
                    return;
                }
                const float corner = 1.f - smoothstep(0.05f, 0.8f, w);
                const float side = std::min(std::abs(r.x()) / 0.45f, 1.f);
                offset += radius * (0.35f * corner * corner + 0.08f * side * side);
            }
            if (texture > 0.f) {
                // Keyed by the wisp and by the root's position, which a strand keeps whichever
                // other strands are grown with it (the editor regrows some wisps alone).
                const uint64_t wisp = hair.wisp.empty() ? i : static_cast<uint64_t>(hair.wisp[i]);
                const uint64_t root = (uint64_t{std::bit_cast<uint32_t>(s[0].x())} << 32 |
                                       std::bit_cast<uint32_t>(s[0].y())) ^
                                      mix64(std::bit_cast<uint32_t>(s[0].z()));
                Rng clump(style.seed, Stream::kCut, wisp);
                Rng strand(style.seed, Stream::kCut, mix64(root) | (uint64_t{1} << 63));
                offset += texture * (clump.uniform() + strand.uniform() / 3.f);
            }
            offsets[i] = offset;
        },
        4096);
    return offsets;
}

// Moves point p out along the head's gradient to `clearance` cm from the skin when it is
// closer; true when it moved, and `inside` when it is still inside afterwards.
inline bool push_point(Vec3f& p, const HeadField& head, float clearance, bool& inside) {
    inside = false;
    // Most points examined are clear of the head: the cell test, then the distance alone
    // (the same value the lookup with the gradient gives) rule them out.
    if (head.beyond(p, clearance) || head.sdf(p) >= clearance) return false;
    Vec3f g;
    const float d = head.sdf(p, &g);
    if (d >= clearance) return false;
    if (!(g.norm() > 1e-6f)) return false;
    g.normalize();
    // A few steps: the gradient of a trilinear field is only piecewise exact, and least so
    // at sharp edges (the rim where an open bust is closed). Each lookup gives the distance
    // and the exact gradient of the interpolant together.
    float di = d;
    bool out = false;
    for (int it = 0; it < 6; ++it) {
        if (it > 0) {
            Vec3f g2;
            di = head.sdf(p, &g2);
            if (di >= clearance) {
                out = true;
                break;
            }
            if (g2.norm() > 1e-6f) g = g2.normalized();
        }
        p += (clearance - di + 1e-3f) * g;
    }
    inside = !out && head.sdf(p) < 0.f;
    return true;
}

// Points k1 > k ≥ 1 of strand s, as push_out_of_head examines them (`flags`: its wisp's
// near flags, or null for all).
inline void push_points(std::span<Vec3f> s, const HeadField& head, float clearance,
                        const uint8_t* flags, int n, size_t k0, size_t k1, size_t& moved,
                        size_t& inside) {
    for (size_t k = std::max<size_t>(k0, 1); k < std::min(k1, s.size()); ++k) {
        if (flags && !flags[std::min<size_t>(k, n - 1)] && !flags[k - 1]) continue;
        bool in = false;
        bool pushed = push_point(s[k], head, clearance, in);
        // Two points clear of the skin can still have the segment between them cut through a
        // thin part of the head (an ear's rim, with one point in front of it and the next
        // behind): the deepest of three samples along it comes out by moving the far point,
        // 1/t as far for the sample at t.
        // (The distance is 1-Lipschitz: with both ends half the segment's length off the skin
        // every point between is off it, which the cell test shows for most segments.)
        const float half = 0.5f * (s[k] - s[k - 1]).norm();
        const bool clear = head.beyond(s[k], half) && head.beyond(s[k - 1], half);
        // The deepest of the three samples of the segment from s[k − 1] to b: its distance
        // (0 when none is inside), where (t) and the gradient there.
        const auto deepest_on = [&](const Vec3f& b, float& at, Vec3f& g) {
            float deepest = 0.f;
            for (const float t : {0.25f, 0.5f, 0.75f}) {
                const Vec3f q = s[k - 1] + t * (b - s[k - 1]);
                if (head.beyond(q, 0.f)) continue;
                Vec3f gq;
                const float d = head.sdf(q, &gq);
                if (d < deepest) deepest = d, at = t, g = gq;
            }
            return deepest;
        };
        bool cut = false;
        for (int it = 0; !clear; ++it) {  // 6 steps, then a last look
            float at = 0.f;
            Vec3f g = Vec3f::Zero();
            const float deepest = deepest_on(s[k], at, g);
            cut = deepest < 0.f;
            if (!cut || it == 6 || !(g.norm() > 1e-6f)) break;
            s[k] += (clearance - deepest) / at * g.normalized();
            pushed = true;
            push_point(s[k], head, clearance, in);
        }
        // Caught where the field's gradient leads nowhere (the crease where a bust's cut edge
        // meets the body under it, a thin ear the grid barely resolves): the point goes back
        // along its segment toward the previous one, which is clear, until it and the segment
        // are clear too.
        if ((in || cut) && head.sdf(s[k - 1]) >= 0.f)
            for (const float t : {0.75f, 0.5f, 0.25f, 0.f}) {
                const Vec3f q = s[k - 1] + t * (s[k] - s[k - 1]);
                float at = 0.f;
                Vec3f g;
                if (head.sdf(q) >= 0.f && deepest_on(q, at, g) >= 0.f) {
                    s[k] = q;
                    in = false;
                    pushed = true;
                    break;
                }
            }
        if (pushed) {
            ++moved;
            inside += in;
        }
    }
}

// How far a clump's pull toward its guide can take each wisp's outline (#W, empty without
// clumps): the pull fades out by 3 clump sizes away, and reaches `pull` of the way at most.
std::vector<float> clump_reach(const Style& style, const Scalp& scalp, const Roots& roots) {
    std::vector<float> reach;
    if (!(style.clump.pull > 0.f)) return reach;
    const MapSampler size(style.clump.size, scalp, style.growth);
    reach.resize(roots.masters.size());
    for (size_t w = 0; w < reach.size(); ++w)
        reach[w] = style.clump.pull * 3.f * std::max(size(roots.masters[w]), 0.f);
    return reach;
}

// near[w·n + k] for joints k0 ≤ k < k1 of every master: whether a member point of that
// index can come within kClearance of the skin. A member point lies within its wisp's radius
// of the master point of the same index, moved by its clump at most `clumps[w]` (clump_reach)
// plus the change from its own curl or wave to its guide's (at most the two largest details
// of the band) and `extra` (a bevel's turn), so only joints closer to the head than that (plus
// slack for the grid) can bring members inside.
void near_head(const Style& style, const Roots& roots, const HeadField& head_field,
               const Masters& masters, std::span<const float> clumps, int k0, int k1,
               std::vector<uint8_t>& near, float extra = 0.f) {
    const int n = masters.points;
    const float r0 = deviation_radius(style.wisp.deviation_radius, 0.f);
    near.resize(masters.count() * n);
    float detail = 0.f;
    if (!clumps.empty())
        for (size_t w = 0; w < masters.count(); ++w)
            for (int k = k0; k < k1; ++k)
                detail = std::max(detail, masters.details[w * n + k].norm());
    const float turn = style.clump.pull * 2.f * detail;
    parallel_for(
        masters.count(),
        [&](size_t w) {
            for (int k = k0; k < k1; ++k) {
                const float reach = roots.wisp_radius[w] *
                                        deviation_radius(style.wisp.deviation_radius,
                                                         static_cast<float>(k) / (n - 1)) /
                                        r0 +
                                    kClearance + head_field.grid().cell() + extra +
                                    (clumps.empty() ? 0.f : clumps[w] + turn);
                near[w * n + k] = head_field.sdf(masters.control[w * n + k]) < reach;
            }
        },
        16);
}

}  // namespace

size_t push_out_of_head(Hair& hair, const HeadField& head, float clearance,
                        const std::vector<uint8_t>* near, int n, size_t* inside) {
    std::atomic<size_t> moved{0}, still_inside{0};
    parallel_for(
        hair.strand_count(),
        [&](size_t i) {
            size_t local = 0, local_inside = 0;
            const uint8_t* flags = near && !hair.wisp.empty()
                                       ? near->data() + static_cast<size_t>(hair.wisp[i]) * n
                                       : nullptr;
            push_points(hair.strand(i), head, clearance, flags, n, 1, SIZE_MAX, local,
                        local_inside);
            moved += local;
            still_inside += local_inside;
        },
        256);
    if (inside) *inside = still_inside;
    return moved;
}

HeadField build_head_field(const Style& style, const Head& head) {
    const float cell = head_field_cell(style.solve);
    const Vec3f span = head.mesh->bounds().size();
    if (const double nodes = HeadField::node_count(head.mesh->bounds(), cell);
        nodes > kMaxGridNodes)
        fail(head.source, ": the head's distance field would have ", nodes,
             " nodes (the head spans ", span.maxCoeff(), " cm, its cell is ", cell,
             " cm from solve.cell = ", style.solve.cell, "), more than ", kMaxGridNodes,
             "; raise solve.cell or check head.scale");
    return HeadField(*head.mesh, cell, head.first_body_face, style.solve.bridge);
}

GroupSelection select_groups(const Style& style, const Head& head, const Roots& roots) {
    const HeadFrame frame = head_frame(*head.scalp);
    GroupSelection out;
    out.selected.resize(style.groups.size());
    out.wisp_group.assign(roots.masters.size(), 0);
    for (size_t g = style.groups.size(); g-- > 0;) {
        out.selected[g] = select_wisps(style.groups[g].selection, roots.masters, *head.scalp, frame,
                                       style.growth);
        for (uint32_t w : out.selected[g])
            out.wisp_group[w] = static_cast<int32_t>(g + 1);
    }
    return out;
}

Box3 solve_bounds(const Style& style, const Head& head, const Roots& roots,
                  const Masters& masters) {
    // The grid spans everywhere the hair can reach: the head, grown by the longest master.
    float longest = 0.f;
    for (size_t w = 0; w < masters.count(); ++w)
        longest = std::max(longest, masters.segment[w] * (masters.points - 1));
    Box3 bounds = head.mesh->bounds();
    Box3 reach;
    for (const SurfacePoint& p : roots.masters)
        reach.extend(p.position);
    reach.lo -= Vec3f::Constant(longest);
    reach.hi += Vec3f::Constant(longest);
    bounds.extend(reach);
    if (const double nodes = grid_nodes(bounds.size(), style.solve.cell); nodes > kMaxGridNodes)
        fail("the solver's grid would span ", bounds.size().x(), " × ", bounds.size().y(), " × ",
             bounds.size().z(), " cm (the head and ", longest,
             " cm of hair around it) at solve.cell = ", style.solve.cell, " cm: ", nodes,
             " nodes, more than ", kMaxGridNodes,
             "; shorten the hair (maps.length, wisp.length) or raise solve.cell");
    return bounds;
}

StylingField styling_field(const Style& style, const Head& head, const Box3& bounds) {
    return StylingField(style.solve.field, head_frame(head), GrowthField(style.growth, *head.scalp),
                        bounds, style.solve.cell);
}

SolveStats solve_stage(const Style& style, const Head& head, const HeadField& head_field,
                       const Roots& roots, const GroupSelection& groups, Masters& masters,
                       StageTimes* times, const StylingField* kept, const CancelToken& cancel,
                       bool update_frames, std::atomic<int>* joints_final) {
    Stopwatch watch;
    const HeadFrame frame = head_frame(*head.scalp);
    StylingField own;
    if (!kept) own = styling_field(style, head, solve_bounds(style, head, roots, masters));
    const StylingField& field = kept ? *kept : own;
    Grid3<float> density(field.grid().origin(), field.grid().cell(), field.grid().dims());
    if (times) times->emplace_back("field", watch.ms());
    watch = Stopwatch();

    SolveInput in;
    in.field = &field;
    in.head = &head_field.bridged();
    for (size_t gi = 0; gi < style.groups.size(); ++gi) {
        const GroupSpec& g = style.groups[gi];
        SolverGroup sg;
        sg.name = g.name;
        sg.wisps = groups.selected[gi];
        for (const ConstraintSpec& c : g.queue)
            sg.queue.push_back(resolve_constraint(c, frame));
        in.groups.push_back(std::move(sg));
    }
    const size_t w_count = masters.count();
    in.wisp_strands.resize(w_count);
    for (size_t w = 0; w < w_count; ++w)
        in.wisp_strands[w] = static_cast<int>(roots.wisp_offsets[w + 1] - roots.wisp_offsets[w]);
    in.wisp_radius = roots.wisp_radius;
    const int n = masters.points;
    in.radius_profile.resize(n);
    const float r0 = deviation_radius(style.wisp.deviation_radius, 0.f);
    for (int k = 0; k < n; ++k)
        in.radius_profile[k] =
            deviation_radius(style.wisp.deviation_radius, static_cast<float>(k) / (n - 1)) / r0;
    // Root lift, as a blow-dry gives it: the lifted root leaves the scalp steeper (rising by
    // at least lift / (lift + kLiftBend) along the normal, 30° off the scalp for 1.5 cm) and
    // is held straight until it stands `lift` cm off the scalp's sphere, where the hair is
    // let fall. A root left at its flat growth angle would need a long straight run to rise
    // (5 cm for 1.5 cm on an adult head) and stood out as a ledge.
    if (style.lift.kind != ScalarMap::Kind::kConstant || style.lift.value > 0.f) {
        constexpr float kLiftBend = 1.5f;  // cm
        const MapSampler lift_map(style.lift, *head.scalp, style.growth);
        in.root_hold.resize(w_count);
        for (size_t w = 0; w < w_count; ++w) {
            const SurfacePoint& root = masters.roots[w];
            // Not at the hairline, where roots lie low: a lifted root there stands up out of
            // the face's frame and the hair it holds arcs over the rest as a stray loop.
            const float lift = std::max(lift_map(root), 0.f) *
                               (1.f - hairline_lie(*head.scalp, root, style.hairline));
            in.root_hold[w] = 0.f;
            if (!(lift > 0.f)) continue;
            Vec3f& dir = masters.direction[w];
            float rise = std::clamp(dir.dot(root.normal), -1.f, 1.f);
            const float steep = lift / (lift + kLiftBend);
            const Vec3f along = dir - rise * root.normal;
            if (rise < steep && along.norm() > 1e-4f) {
                rise = steep;
                dir = (std::sqrt(1.f - rise * rise) * along.normalized() + rise * root.normal)
                          .normalized();
            }
            // The run of a straight segment leaving a sphere of radius R at this rise that ends
            // `lift` above it. The hold eases off from the root over twice the run, so it
            // holds the hair about half of that way and bends it over gradually: eased off
            // over only its second half, each wisp bent at one knee, and the knees of a lifted
            // top, evenly spaced, caught the light as rows of scales.
            const float radius = (root.position - head.scalp->center()).norm();
            const float rr = radius * std::max(rise, 0.f);
            const float run = std::sqrt(rr * rr + lift * (2.f * radius + lift)) - rr;
            const float length = masters.segment[w] * static_cast<float>(n - 1);
            in.root_hold[w] = std::min(2.f * run, 0.6f * length);
        }
    }
    in.cancel = &cancel;
    in.update_frames = update_frames;
    in.joints_final = joints_final;
    SolveStats stats = solve_masters(masters, in, style.solve, density);
    if (times) times->emplace_back("solve", watch.ms());
    return stats;
}

namespace {

bool cuts(const Style& style) {
    return style.cut.enabled && style.cut.normal.norm() > 0.f;
}

}  // namespace

MemberBands::MemberBands(const Style& style, const HeadField& head_field, const Scalp& scalp,
                         const Roots& roots, std::span<const int32_t> wisp_group, int points,
                         std::span<const uint32_t> only)
    : style_(style),
      head_field_(head_field),
      scalp_(scalp),
      roots_(roots),
      points_(points),
      growth_(style, scalp, roots, points, wisp_group, only),
      clump_reach_(clump_reach(style, scalp, roots)) {
    Hair& hair = growth_.hair();
    hair.group.resize(hair.strand_count());
    for (size_t j = 0; j < hair.strand_count(); ++j)
        hair.group[j] = wisp_group[static_cast<size_t>(hair.wisp[j])];
}

void MemberBands::grow(const Masters& masters, int k0, int k1, const CancelToken& cancel) {
    growth_.grow(masters, k0, k1, cancel);
}

void MemberBands::push(const Masters& masters, int k0, int k1) {
    // Bevelled ends move in by up to half the bevel.
    near_head(style_, roots_, head_field_, masters, clump_reach_, k0, k1, near_,
              cuts(style_) ? 0.5f * style_.cut.bevel : 0.f);
    Hair& hair = growth_.hair();
    const int n = masters.points;
    std::atomic<size_t> moved{0}, inside{0};
    parallel_for(
        hair.strand_count(),
        [&](size_t i) {
            size_t local = 0, local_inside = 0;
            // The points no band after this one reads (the last whole point waits for the tip
            // interpolated from it).
            const size_t from = static_cast<size_t>(growth_.settled(i, k0));
            const size_t to = static_cast<size_t>(growth_.settled(i, k1));
            push_points(hair.strand(i), head_field_, kClearance,
                        near_.data() + static_cast<size_t>(hair.wisp[i]) * n, n, from, to, local,
                        local_inside);
            moved += local;
            inside += local_inside;
        },
        256);
    result_.points_pushed += moved;
    result_.points_inside_head += inside;
}

MembersResult MemberBands::finish(bool cut) {
    result_.hair = std::move(growth_.hair());
    if (!cut || !cuts(style_)) return std::move(result_);
    Hair& hair = result_.hair;
    const HeadFrame frame = head_frame(scalp_);
    const Vec3f normal = style_.cut.normal.normalized();
    const float offset = style_.cut.head_relative
                             ? normal.dot(frame.center) + style_.cut.offset * frame.radius
                             : style_.cut.offset;
    // Out of the head first (the bands did it), then the cut: cut first, a tip the plane
    // leaves inside the jaw would be pushed down its underside, hanging below the cut line
    // down the neck.
    std::vector<float> offsets;  // per strand: where the plane cuts it (NaN: not at all)
    if (style_.cut.region == CutSpec::Region::kFringe || style_.cut.texture > 0.f)
        offsets = cut_offsets(style_, scalp_, frame.radius, hair, offset);
    std::vector<uint8_t> was_cut;
    result_.strands_cut = cut_hair(hair, normal, offset, &result_.strands_removed,
                                   offsets.empty() ? nullptr : &offsets, &was_cut);
    bevel_ends(hair, was_cut, style_.cut.bevel, frame.center);
    // Again for the new tips and the bevelled ends (the rest are out already: quick); what
    // is still inside is counted after this push.
    result_.points_inside_head = 0;
    result_.points_pushed += push_out_of_head(hair, head_field_, kClearance, &near_, points_,
                                              &result_.points_inside_head);
    return std::move(result_);
}

bool follow_solve(Masters& masters, const std::atomic<int>& joints_final, MemberBands* bands,
                  const CancelToken& cancel) {
    // Each band takes every joint the solve has made final since the last (at least 2, so
    // that a band's loops are worth their start-up): a follower that lags catches up in one
    // pass, and what is left when the solve ends runs on both cores. Any split gives the same
    // bytes.
    constexpr int kLeast = 2;
    const int n = masters.points;
    // Frame k reads the outline to joint k + 1 (update_master): with `joints` final, the
    // frames below joints − 1 (every one once the solve finished).
    const auto ready = [n](int joints) { return joints >= n ? n : joints - 1; };
    for (int k0 = 0; k0 < n;) {
        int joints = joints_final.load(std::memory_order_acquire);
        while (joints >= 0 && ready(joints) < std::min(n, k0 + kLeast)) {
            joints_final.wait(joints, std::memory_order_acquire);
            joints = joints_final.load(std::memory_order_acquire);
        }
        if (joints < 0 || cancel.cancelled()) return false;
        const int k1 = ready(joints);
        parallel_for(
            masters.count(), [&](size_t w) { update_master(masters, w, k0, k1); }, 64);
        if (bands) {
            bands->grow(masters, k0, k1, cancel);
            if (cancel.cancelled()) return false;
            bands->push(masters, k0, k1);
        }
        k0 = k1;
    }
    return true;
}

MembersResult members_stage(const Style& style, const Head& head, const HeadField& head_field,
                            const Roots& roots, const Masters& masters,
                            std::span<const int32_t> wisp_group, StageTimes* times,
                            std::span<const uint32_t> only, const CancelToken& cancel) {
    Stopwatch watch;
    const auto lap = [&](const char* stage) {
        if (times) times->emplace_back(stage, watch.ms());
        watch = Stopwatch();
    };
    const int n = masters.points;
    // One band: all of the growth (about half of the stage), then the push out of the head
    // and the cut.
    MemberBands bands(style, head_field, *head.scalp, roots, wisp_group, n, only);
    bands.grow(masters, 0, n, cancel.part(0.f, 0.5f));
    if (cancel.cancelled()) return bands.finish(false);
    lap("members");
    bands.push(masters, 0, n);
    lap("collide");
    MembersResult r = bands.finish();
    if (cuts(style)) lap("cut");
    cancel.progress(1, 1);
    return r;
}

void color_stage(const Style& style, Hair& hair, std::span<const uint32_t> ids) {
    hair.colors.resize(hair.strand_count());
    color_strands(style.color, style.seed, hair.wisp, hair.colors, ids);
}

HairstyleResult generate_hairstyle(const Style& style, const Head& head,
                                   const HeadField* head_field) {
    HairstyleResult r;
    Stopwatch watch;
    auto lap = [&](const char* stage) {
        r.times.emplace_back(stage, watch.ms());
        watch = Stopwatch();
    };
    const Roots roots = grow_roots(style, head);
    lap("roots");
    r.masters = synthesize_masters(style, head, roots);
    lap("masters");

    HeadField own;
    if (!head_field) {
        own = build_head_field(style, head);
        head_field = &own;
        lap("head field");
    }
    // The wisps of each constraint group; a wisp belongs to the first group that selects it
    // (the solver's rule), which is also the group its strands export with (Hair::group).
    GroupSelection groups = select_groups(style, head, roots);
    if (style.solve.enabled)
        r.solve = solve_stage(style, head, *head_field, roots, groups, r.masters, &r.times);
    MembersResult members =
        members_stage(style, head, *head_field, roots, r.masters, groups.wisp_group, &r.times);
    r.wisp_group = std::move(groups.wisp_group);
    r.hair = std::move(members.hair);
    r.points_pushed = members.points_pushed;
    r.points_inside_head = members.points_inside_head;
    r.strands_cut = members.strands_cut;
    r.strands_removed = members.strands_removed;
    watch = Stopwatch();
    color_stage(style, r.hair);
    lap("color");
    return r;
}

nlohmann::json solve_stats_json(const SolveStats& solve, const SolveSpec& spec) {
    nlohmann::json j = {{"enabled", spec.enabled},
                        {"order", spec.depth_first ? "depth-first" : "breadth-first"},
                        {"joints", solve.joints},
                        {"collision_iterations", solve.bends},
                        {"colliding_joints", solve.collisions},
                        {"unresolved_joints", solve.unresolved},
                        {"contact_joints", solve.contacts},
                        {"projected_joints", solve.projected},
                        {"constrained_joints", solve.constrained}};
    nlohmann::json groups = nlohmann::json::array();
    for (const SolveStats::Group& g : solve.groups)
        groups.push_back({{"name", g.name},
                          {"constraints", g.constraints},
                          {"completed", g.completed},
                          {"wisps", g.wisps},
                          {"met", g.met}});
    j["groups"] = std::move(groups);
    return j;
}

}  // namespace wisp
