#include "solve/constraint.hpp"

#include <algorithm>
#include <cmath>

#include "core/catmull_rom.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "groom/maps.hpp"

namespace wisp {

Constraint resolve_constraint(const ConstraintSpec& spec, const HeadFrame& head) {
    Constraint c;
    c.kind = spec.kind;
    c.weight = spec.weight;
    c.hold = spec.hold;
    c.head_center = head.center;
    c.head_radius = head.radius;
    auto place = [&](const Vec3f& p) { return spec.head_relative ? head.to_space(p) : p; };
    c.radius = spec.head_relative ? spec.radius * head.radius : spec.radius;
    c.point = place(spec.point);
    std::vector<Vec3f> pts;
    for (const Vec3f& p : spec.trajectory)
        pts.push_back(place(p));
    if (spec.smooth && pts.size() >= 2) {
        const int per = 16;
        c.path.resize((pts.size() - 1) * per + 1);
        catmull_rom_sample(pts, per, c.path);
    } else {
        c.path = pts;
    }
    c.arc.assign(c.path.size(), 0.f);
    for (size_t i = 1; i < c.path.size(); ++i)
        c.arc[i] = c.arc[i - 1] + (c.path[i] - c.path[i - 1]).norm();
    if (spec.repeat > 0.f && c.arc.size() >= 2)
        c.repeat_from = c.arc.back() * (1.f - std::min(spec.repeat, 1.f));
    return c;
}

PathPoint nearest_on_path(const Constraint& c, const Vec3f& x, float lo, float hi, float* arc) {
    PathPoint best;
    if (c.path.size() < 2) {
        best.position = c.path.empty() ? c.point : c.path[0];
        best.tangent = Vec3f::UnitY();
        if (arc) *arc = 0.f;
        return best;
    }
    const size_t first = static_cast<size_t>(std::max<ptrdiff_t>(
        std::lower_bound(c.arc.begin(), c.arc.end(), lo) - c.arc.begin() - 1, 0));
    float best_d = INFINITY, best_arc = 0.f;
    const float total = std::max(c.arc.back(), 1e-6f);
    for (size_t i = first; i + 1 < c.path.size() && c.arc[i] <= hi; ++i) {
        const Vec3f a = c.path[i], e = c.path[i + 1] - a;
        const float len2 = e.squaredNorm();
        const float f = len2 > 0.f ? std::clamp((x - a).dot(e) / len2, 0.f, 1.f) : 0.f;
        const Vec3f q = a + f * e;
        const float d = (x - q).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best.position = q;
            best.tangent = len2 > 0.f ? Vec3f(e / std::sqrt(len2)) : Vec3f::UnitY();
            best_arc = c.arc[i] + f * (c.arc[i + 1] - c.arc[i]);
            best.t = best_arc / total;
        }
    }
    if (arc) *arc = best_arc;
    return best;
}

PathPoint point_at_arc(const Constraint& c, float s) {
    PathPoint p;
    if (c.path.size() < 2) {
        p.position = c.path.empty() ? c.point : c.path[0];
        p.tangent = Vec3f::UnitY();
        return p;
    }
    const float total = std::max(c.arc.back(), 1e-6f);
    s = std::clamp(s, 0.f, c.arc.back());
    size_t i = static_cast<size_t>(std::upper_bound(c.arc.begin(), c.arc.end(), s) - c.arc.begin());
    i = std::clamp<size_t>(i, 1, c.path.size() - 1) - 1;
    const float len = c.arc[i + 1] - c.arc[i];
    const float f = len > 0.f ? (s - c.arc[i]) / len : 0.f;
    const Vec3f e = c.path[i + 1] - c.path[i];
    p.position = c.path[i] + f * e;
    p.tangent = e.norm() > 0.f ? Vec3f(e.normalized()) : Vec3f::UnitY();
    p.t = s / total;
    return p;
}

PathPoint nearest_on_path(const Constraint& c, const Vec3f& x) {
    return nearest_on_path(c, x, -INFINITY, INFINITY, nullptr);
}

Vec3f constraint_force(const Constraint& c, const Vec3f& x) {
    switch (c.kind) {
        case ConstraintSpec::Kind::kPoint: {
            const Vec3f d = c.point - x;
            const float n = d.norm();
            if (!(n > 1e-6f)) return Vec3f::Zero();
            const Vec3f direct = d / n;
            const Vec3f r = x - c.head_center;
            const float dist = r.norm();
            if (!(c.head_radius > 0.f) || dist < 1e-4f) return direct;
            // Far from the tie (seen from the head's centre), along the sphere toward it,
            // hugging the head (its density keeps hair out): drawn in a little, more where it
            // stands out past the tie's shell. Near the tie, straight to it.
            const Vec3f rn = r / dist;
            const Vec3f to_tie = c.point - c.head_center;
            const float shell = to_tie.norm();
            const float angle =
                std::acos(std::clamp(rn.dot(to_tie) / std::max(shell, 1e-6f), -1.f, 1.f));
            const float wrap = smoothstep(0.15f, 0.45f, angle);
            // Every great circle from the point opposite the tie leads to it; near there, the
            // one over the top of the head (hair at the front hairline, gathered at the back,
            // is combed up and over, never down across the face, wherever the hairline lies
            // on the head's sphere).
            const Vec3f up(0.f, 1.f, 0.f);
            const float opposite = smoothstep(0.8f, 1.f, -rn.dot(to_tie) / std::max(shell, 1e-6f));
            const Vec3f along = d - d.dot(rn) * rn + (0.6f * n * opposite) * (up - up.dot(rn) * rn);
            if (wrap <= 0.f || along.norm() < 1e-6f) return direct;
            const float out = std::clamp((dist - shell) / (0.1f * shell), 0.f, 1.f);
            const Vec3f hug = (along.normalized() - (0.2f + 0.5f * out) * rn).normalized();
            return ((1.f - wrap) * direct + wrap * hug).normalized();
        }
        case ConstraintSpec::Kind::kTrajectory: {
            const PathPoint p = nearest_on_path(c, x);
            const Vec3f d = p.position - x;
            const float n = d.norm();
            return n > c.radius ? Vec3f(d / n) : p.tangent;
        }
        case ConstraintSpec::Kind::kDirection: {
            const PathPoint p = nearest_on_path(c, x);
            return (p.position - x).norm() <= c.radius ? p.tangent : Vec3f::Zero();
        }
    }
    return Vec3f::Zero();
}

bool constraint_met(const Constraint& c, const Vec3f& a, const Vec3f& x) {
    switch (c.kind) {
        case ConstraintSpec::Kind::kPoint: {
            const Vec3f e = x - a;
            const float len2 = e.squaredNorm();
            const float f = len2 > 0.f ? std::clamp((c.point - a).dot(e) / len2, 0.f, 1.f) : 0.f;
            return (a + f * e - c.point).norm() <= c.radius;
        }
        case ConstraintSpec::Kind::kTrajectory: {
            const PathPoint p = nearest_on_path(c, x);
            return p.t >= 0.999f && (p.position - x).norm() <= c.radius;
        }
        case ConstraintSpec::Kind::kDirection: {
            const PathPoint p = nearest_on_path(c, x);
            return p.t >= 0.999f || (p.position - x).norm() > c.radius;
        }
    }
    return true;
}

std::vector<uint32_t> select_wisps(const Selection& sel, const std::vector<SurfacePoint>& roots,
                                   const Scalp& scalp, const HeadFrame& head,
                                   const GrowthSpec& growth) {
    std::vector<uint32_t> out;
    std::unique_ptr<MapSampler> region;
    std::unique_ptr<GrayImage> mask;
    if (sel.kind == Selection::Kind::kRegion) {
        ScalarMap map;
        map.kind = ScalarMap::Kind::kProcedural;
        map.procedural = sel.region;
        region = std::make_unique<MapSampler>(map, scalp, growth);
    } else if (sel.kind == Selection::Kind::kMask) {
        mask = std::make_unique<GrayImage>(sel.mask_pixels ? *sel.mask_pixels
                                                           : read_gray_image(sel.mask));
    }
    const Vec3f lo = sel.head_relative ? head.to_space(sel.lo) : sel.lo;
    const Vec3f hi = sel.head_relative ? head.to_space(sel.hi) : sel.hi;
    const Vec3f n = sel.normal.norm() > 0.f ? Vec3f(sel.normal.normalized()) : Vec3f::UnitX();
    const float offset =
        sel.head_relative ? n.dot(head.center) + sel.offset * head.radius : sel.offset;
    for (uint32_t w = 0; w < roots.size(); ++w) {
        const SurfacePoint& r = roots[w];
        bool in = false;
        switch (sel.kind) {
            case Selection::Kind::kAll:
                in = true;
                break;
            case Selection::Kind::kRegion:
                in = (*region)(r) > 0.5f;
                break;
            case Selection::Kind::kMask:
                in = mask->sample(r.uv.x(), r.uv.y()) > 0.5f;
                break;
            case Selection::Kind::kBox:
                in = (r.position.array() >= lo.array()).all() &&
                     (r.position.array() <= hi.array()).all();
                break;
            case Selection::Kind::kHalfSpace:
                in = n.dot(r.position) > offset;
                break;
            case Selection::Kind::kWisps:
                in = std::find(sel.wisps.begin(), sel.wisps.end(), static_cast<int>(w)) !=
                     sel.wisps.end();
                break;
        }
        if (in) out.push_back(w);
    }
    if (sel.parts > 1) {
        std::stable_sort(out.begin(), out.end(), [&](uint32_t a, uint32_t b) {
            return roots[a].position.x() < roots[b].position.x();
        });
        const size_t n_sel = out.size();
        const size_t begin = n_sel * sel.part / sel.parts, end = n_sel * (sel.part + 1) / sel.parts;
        out = std::vector<uint32_t>(out.begin() + begin, out.begin() + end);
        std::sort(out.begin(), out.end());
    }
    return out;
}

}  // namespace wisp
