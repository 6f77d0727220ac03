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
    return c;
}

PathPoint nearest_on_path(const Constraint& c, const Vec3f& x) {
    PathPoint best;
    if (c.path.size() < 2) {
        best.position = c.path.empty() ? c.point : c.path[0];
        best.tangent = Vec3f::UnitY();
        return best;
    }
    float best_d = INFINITY;
    const float total = std::max(c.arc.back(), 1e-6f);
    for (size_t i = 0; i + 1 < c.path.size(); ++i) {
        const Vec3f a = c.path[i], e = c.path[i + 1] - a;
        const float len2 = e.squaredNorm();
        const float f = len2 > 0.f ? std::clamp((x - a).dot(e) / len2, 0.f, 1.f) : 0.f;
        const Vec3f q = a + f * e;
        const float d = (x - q).squaredNorm();
        if (d < best_d) {
            best_d = d;
            best.position = q;
            best.tangent = len2 > 0.f ? Vec3f(e / std::sqrt(len2)) : Vec3f::UnitY();
            best.t = (c.arc[i] + f * (c.arc[i + 1] - c.arc[i])) / total;
        }
    }
    return best;
}

Vec3f constraint_force(const Constraint& c, const Vec3f& x) {
    switch (c.kind) {
        case ConstraintSpec::Kind::kPoint: {
            const Vec3f d = c.point - x;
            const float n = d.norm();
            return n > 1e-6f ? Vec3f(d / n) : Vec3f::Zero();
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
                                   const Scalp& scalp, const HeadFrame& head) {
    std::vector<uint32_t> out;
    std::unique_ptr<MapSampler> region;
    std::unique_ptr<GrayImage> mask;
    if (sel.kind == Selection::Kind::kRegion) {
        ScalarMap map;
        map.kind = ScalarMap::Kind::kProcedural;
        map.procedural = sel.region;
        region = std::make_unique<MapSampler>(map, scalp);
    } else if (sel.kind == Selection::Kind::kMask) {
        mask = std::make_unique<GrayImage>(read_gray_image(sel.mask));
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
