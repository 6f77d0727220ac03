#include "solve/coverage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace {

// The head rasterized orthographically: per cell, the depth (along forward) of the nearest
// surface and the face there (-1: none).
class DepthGrid {
  public:
    DepthGrid(const Mesh& mesh, const OrthoView& view) : view_(view) {
        float u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
        for (const Vec3f& p : mesh.vertices) {
            u0 = std::min(u0, p.dot(view.right));
            u1 = std::max(u1, p.dot(view.right));
            v0 = std::min(v0, p.dot(view.up));
            v1 = std::max(v1, p.dot(view.up));
        }
        u0_ = u0 - view.cell;
        v0_ = v0 - view.cell;
        nu_ = static_cast<int>(std::ceil((u1 - u0_) / view.cell)) + 2;
        nv_ = static_cast<int>(std::ceil((v1 - v0_) / view.cell)) + 2;
        depth_.assign(static_cast<size_t>(nu_) * nv_, INFINITY);
        face_.assign(depth_.size(), -1);
        for (size_t f = 0; f < mesh.faces.size(); ++f) {
            Vec3f q[3];
            for (int k = 0; k < 3; ++k) {
                const Vec3f& p = mesh.vertices[mesh.faces[f][k]];
                q[k] = Vec3f((p.dot(view.right) - u0_) / view.cell - 0.5f,
                             (p.dot(view.up) - v0_) / view.cell - 0.5f, p.dot(view.forward));
            }
            const float area = (q[1].x() - q[0].x()) * (q[2].y() - q[0].y()) -
                               (q[2].x() - q[0].x()) * (q[1].y() - q[0].y());
            if (std::abs(area) < 1e-12f) continue;
            const int i0 =
                std::max(0, static_cast<int>(std::ceil(std::min({q[0].x(), q[1].x(), q[2].x()}))));
            const int i1 = std::min(
                nu_ - 1, static_cast<int>(std::floor(std::max({q[0].x(), q[1].x(), q[2].x()}))));
            const int j0 =
                std::max(0, static_cast<int>(std::ceil(std::min({q[0].y(), q[1].y(), q[2].y()}))));
            const int j1 = std::min(
                nv_ - 1, static_cast<int>(std::floor(std::max({q[0].y(), q[1].y(), q[2].y()}))));
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    const float x = float(i), y = float(j);
                    const float b1 = ((x - q[0].x()) * (q[2].y() - q[0].y()) -
                                      (q[2].x() - q[0].x()) * (y - q[0].y())) /
                                     area;
                    const float b2 = ((q[1].x() - q[0].x()) * (y - q[0].y()) -
                                      (x - q[0].x()) * (q[1].y() - q[0].y())) /
                                     area;
                    const float b0 = 1.f - b1 - b2;
                    if (b0 < 0.f || b1 < 0.f || b2 < 0.f) continue;
                    const float d = b0 * q[0].z() + b1 * q[1].z() + b2 * q[2].z();
                    const size_t c = static_cast<size_t>(j) * nu_ + i;
                    if (d < depth_[c]) {
                        depth_[c] = d;
                        face_[c] = static_cast<int32_t>(f);
                    }
                }
        }
    }

    size_t size() const { return depth_.size(); }
    int32_t face(size_t c) const { return face_[c]; }
    float depth(size_t c) const { return depth_[c]; }
    // The surface point seen at cell c (its centre at the surface's depth).
    Vec3f point(size_t c) const {
        const float u = u0_ + (float(c % nu_) + 0.5f) * view_.cell;
        const float v = v0_ + (float(c / nu_) + 0.5f) * view_.cell;
        return u * view_.right + v * view_.up + depth_[c] * view_.forward;
    }
    // Marks the cells that hair covers (flags #size()): where the projected area of the
    // strands on or in front of the surface (width × length seen across the view, each
    // strand's width times `width_scale`) makes the cell at least half opaque,
    // 1 − exp(−area / cell area) ≥ 0.5, as thin hair over skin looks.
    void mark_hair(const Hair& hair, float width_scale, std::vector<uint8_t>& covered) const {
        std::vector<float> area(depth_.size(), 0.f);
        const float step = 0.5f * view_.cell;
        auto deposit = [&](const Vec3f& p, float a) {
            const float x = (p.dot(view_.right) - u0_) / view_.cell;
            const float y = (p.dot(view_.up) - v0_) / view_.cell;
            if (!(x >= 0.f && y >= 0.f && x < float(nu_) && y < float(nv_))) return;
            const size_t c = static_cast<size_t>(y) * nu_ + static_cast<size_t>(x);
            if (p.dot(view_.forward) <= depth_[c] + view_.tolerance) area[c] += a;
        };
        for (size_t s = 0; s < hair.strand_count(); ++s) {
            const auto pts = hair.strand(s);
            const size_t o = hair.offsets[s];
            for (size_t k = 1; k < pts.size(); ++k) {
                const Vec3f d = pts[k] - pts[k - 1];
                const float across = std::hypot(d.dot(view_.right), d.dot(view_.up));
                const int n = std::clamp(static_cast<int>(std::ceil(across / step)), 1, 4096);
                const float width =
                    0.5f * (hair.width_at(o + k - 1) + hair.width_at(o + k)) * width_scale;
                const float a = width * across / float(n);
                for (int i = 0; i < n; ++i)
                    deposit(pts[k - 1] + ((float(i) + 0.5f) / float(n)) * d, a);
            }
        }
        const float half_opaque = std::log(2.f) * view_.cell * view_.cell;
        covered.resize(depth_.size());
        for (size_t c = 0; c < area.size(); ++c)
            covered[c] = area[c] >= half_opaque;
    }

  private:
    OrthoView view_;
    float u0_ = 0.f, v0_ = 0.f;
    int nu_ = 0, nv_ = 0;
    std::vector<float> depth_;
    std::vector<int32_t> face_;
};

// The cells of `view` where the head's surface is seen at a point `in_window` accepts, and of
// those the ones hair covers.
template <class Window>
Coverage window_coverage(const Hair& hair, const Mesh& head, const OrthoView& view,
                         float width_scale, Window in_window) {
    const DepthGrid grid(head, view);
    std::vector<uint8_t> covered;
    grid.mark_hair(hair, width_scale, covered);
    Coverage c;
    for (size_t i = 0; i < grid.size(); ++i) {
        if (grid.face(i) < 0 || !in_window(grid.point(i))) continue;
        ++c.cells;
        c.covered += covered[i];
    }
    return c;
}

}  // namespace

OrthoView ortho_view(const std::string& name, float cell) {
    OrthoView v;
    v.cell = cell;
    if (name == "front") {
        v.forward = -Vec3f::UnitZ();
        v.right = Vec3f::UnitX();
    } else if (name == "back") {
        v.forward = Vec3f::UnitZ();
        v.right = -Vec3f::UnitX();
    } else if (name == "left") {
        v.forward = -Vec3f::UnitX();
        v.right = -Vec3f::UnitZ();
    } else if (name == "right") {
        v.forward = Vec3f::UnitX();
        v.right = Vec3f::UnitZ();
    } else if (name == "top") {
        v.forward = -Vec3f::UnitY();
        v.right = Vec3f::UnitX();
        v.up = Vec3f::UnitZ();
    } else {
        fail("unknown coverage view '", name, "' (front, back, left, right, top)");
    }
    return v;
}

Coverage face_coverage(const Hair& hair, const Mesh& head, float eye_y, float chin_y,
                       float half_width, float cell, float width_scale) {
    return window_coverage(hair, head, ortho_view("front", cell), width_scale, [&](const Vec3f& p) {
        return std::abs(p.x()) <= half_width && p.y() <= eye_y && p.y() >= chin_y;
    });
}

Coverage profile_coverage(const Hair& hair, const Mesh& head, const std::string& side, float eye_y,
                          float chin_y, float eye_z, float cell, float width_scale) {
    return window_coverage(hair, head, ortho_view(side, cell), width_scale, [&](const Vec3f& p) {
        return p.z() >= eye_z && p.y() <= eye_y && p.y() >= chin_y;
    });
}

Coverage scalp_coverage(const Hair& hair, const Scalp& scalp, const OrthoView& view,
                        const std::function<bool(const Vec3f&)>& exclude, float width_scale,
                        const HairlineSpec* hairline) {
    const Mesh& mesh = scalp.mesh();
    std::vector<uint8_t> is_scalp(mesh.faces.size(), 0);
    for (uint32_t f : scalp.faces())
        is_scalp[f] = 1;
    const DepthGrid grid(mesh, view);
    std::vector<uint8_t> covered;
    grid.mark_hair(hair, width_scale, covered);
    Coverage c;
    for (size_t i = 0; i < grid.size(); ++i) {
        const int32_t f = grid.face(i);
        if (f < 0 || !is_scalp[f]) continue;
        if (exclude && exclude(grid.point(i))) continue;
        if (hairline &&
            hairline_density(scalp, grid.point(i),
                             scalp.edge_distance(static_cast<uint32_t>(f), grid.point(i)),
                             *hairline) < 1.f)
            continue;
        ++c.cells;
        c.covered += covered[i];
    }
    return c;
}

FaceLandmarks face_landmarks(const Head& found) {
    if (found.landmarks) {
        const Landmarks& m = *found.landmarks;
        FaceLandmarks l;
        l.nose_tip = m.nose_tip;
        l.eye_y = 0.5f * (m.eye_left.y() + m.eye_right.y());
        l.chin_y = m.chin.y();
        l.eye_z = 0.5f * (m.eye_left.z() + m.eye_right.z());
        return l;
    }
    const Mesh& head = *found.mesh;
    const Scalp& scalp = *found.scalp;
    // The nose tip: the most forward vertex near the midline between 8 and 25 cm below the
    // crown (the face of any adult head; the chest of a bust lies lower or further back).
    const float crown = scalp.crown().y();
    FaceLandmarks l;
    float best = -INFINITY;
    for (const Vec3f& p : head.vertices)
        if (std::abs(p.x() - scalp.center().x()) < 3.f && p.y() < crown - 8.f &&
            p.y() > crown - 25.f && p.z() > best) {
            best = p.z();
            l.nose_tip = p;
        }
    if (!std::isfinite(best)) fail("face landmarks: no vertex where a nose would be");
    // Human proportions, as fractions of the nose tip's height h below the crown: the eye
    // line 0.24·h above the nose tip, the chin 0.53·h below it (11 cm and 22 cm below the
    // crown for h = 14.5 cm), the eyes 0.17·h behind it.
    const float h = crown - l.nose_tip.y();
    l.eye_y = l.nose_tip.y() + 0.24f * h;
    l.chin_y = l.nose_tip.y() - 0.53f * h;
    l.eye_z = l.nose_tip.z() - 0.17f * h;  // the eyes 2.5 cm behind the nose tip
    return l;
}

}  // namespace wisp
