#pragma once
// Master strands (Choe & Ko §2.2): an outline, a chain of equal-length segments joined by
// 3-DOF joints, plus details, displacements of the control points from the joint centres
// expressed in each segment's local frame, so that rotating joints carries the details.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "geometry/scalp.hpp"
#include "groom/style.hpp"

namespace wisp {

struct Masters {
    int points = 0;  // n control points (= joints) per master, the same for every master
    std::vector<SurfacePoint> roots;  // #W
    std::vector<float> segment;       // #W outline segment length, cm (length / (n-1))
    std::vector<Vec3f> direction;     // #W protrusion direction at the root, unit
    std::vector<Frame> root_frame;    // #W frame of the first segment at zero joint angles
    std::vector<Vec3f> outline;       // #W·n joint centres c_i, cm, head space
    std::vector<Vec3f> details;       // #W·n δ_i in the local frame of segment i
    std::vector<Frame> frames;        // #W·n frame of the segment at each joint (the last
                                      // joint takes the last segment's)
    std::vector<Vec3f> control;       // #W·n control points p_i = c_i + F_i δ_i

    size_t count() const { return roots.size(); }
    std::span<const Vec3f> strand(size_t w) const {
        return {control.data() + w * points, static_cast<size_t>(points)};
    }
};

// The protrusion direction (§2.3) at a scalp point: protrusion 0 lies along the scalp in the
// growth direction `flow` (groom/growth.hpp; made tangent to the surface here); 1 is the
// surface normal; in between the angle from the surface is protrusion·90°.
Vec3f protrusion_direction(const SurfacePoint& root, const Vec3f& flow, float protrusion);

// Recomputes frames (transported along the outline from root_frame) and control points of
// master w from its outline and details. Call after the outline changes.
void update_master(Masters& m, size_t w);
// The same for joints i0 ≤ i < i1 only, given those before i0 (the frame transports on from
// joint i0 − 1's): it reads the outline up to joint min(i1, n − 1), so the masters' frames and
// control points can follow the solve's layers (any split gives update_master's, to the bit).
void update_master(Masters& m, size_t w, int i0, int i1);

}  // namespace wisp
