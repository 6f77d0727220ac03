#pragma once
// The head as a field: a signed distance grid around the head mesh, from which the solver
// reads the head's density (Choe & Ko §3.2: 1 inside the head and shoulders, 0 outside) and
// its gradient, and which keeps every hair point out of the head.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/grid.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

class HeadField {
  public:
    HeadField() = default;
    // Samples the signed distance of `mesh` (negative inside) on a grid of `cell` cm over its
    // bounding box grown by 3 cells. Near the surface (within 1.5 cells) distances are exact
    // (MeshDistance); further in or out only their sign matters, found by flood-filling the
    // far nodes and classifying each connected region once by its winding number. An open
    // mesh (a head cut at the neck or chest) is first closed by a fan over each hole
    // (close_holes), so that its inside is inside everywhere. With first_body_face below the
    // face count, the faces from it on are a second piece (a body under the head, Head::body)
    // that may overlap the first: each is closed and measured alone and the field is their
    // union.
    //
    // With `bridge` > 0 it also builds bridged(): the same field with the head's creases
    // narrower than 2 × bridge cm closed over.
    HeadField(const Mesh& mesh, float cell, size_t first_body_face = SIZE_MAX, float bridge = 0.f);
    // The node count of the grid the constructor builds for a mesh with these bounds (cm), to
    // check against kMaxGridNodes before building it.
    static double node_count(const Box3& mesh_bounds, float cell);

    // Trilinear signed distance, cm; points outside the grid get a large positive value.
    // Inline: the solver asks it for several points per try of every joint, and the push out
    // of the head for every member point near the skin.
    float sdf(const Vec3f& p) const {
        if (!inside_box(p)) return kOutside;
        return grid_.trilinear(p);
    }
    // The same distance and, in *gradient, the exact gradient of the trilinear interpolant
    // (≈ outward normal; zero outside the grid), for the price of one lookup.
    float sdf(const Vec3f& p, Vec3f* gradient) const {
        if (!inside_box(p)) {
            gradient->setZero();
            return kOutside;
        }
        return grid_.trilinear(p, gradient);
    }
    // Gradient of the trilinear signed distance (central differences), ≈ outward normal.
    Vec3f gradient(const Vec3f& p) const;
    // True only when sdf(p) ≥ `distance` is certain from the cell holding p alone: the
    // smallest distance at its 8 nodes is that far (with a slack far above the rounding of
    // the interpolation). False says nothing. Many of the member points the push out of the
    // head examines are a few cells off the skin: this spares them the trilinear lookup, and
    // every result stays what the lookup gives. (The solver's joints mostly lie within a cell
    // or two of the skin, where the test costs more than it spares.)
    bool beyond(const Vec3f& p, float distance) const {
        if (cell_min_.empty()) return false;
        const Vec3f g = (p - grid_.origin()) / grid_.cell();
        const Vec3i& dims = grid_.dims();
        size_t index = 0, stride = 1;
        for (int a = 0; a < 3; ++a) {
            if (!(g[a] >= 0.f) || g[a] > static_cast<float>(dims[a] - 1)) return false;
            index += stride * static_cast<size_t>(std::min(static_cast<int>(g[a]), dims[a] - 2));
            stride *= static_cast<size_t>(dims[a] - 1);
        }
        return cell_min_[index] >= distance + kBeyondSlack;
    }
    // Head density: 1 on and inside the surface, falling linearly to 0 at `margin` cm out.
    float density(const Vec3f& p, float margin) const {
        const float d = sdf(p);
        return d <= 0.f ? 1.f : (d >= margin ? 0.f : 1.f - d / margin);
    }
    const Grid3<float>& grid() const { return grid_; }
    bool empty() const { return grid_.size() == 0; }
    // The head as a wisp feels it: a wisp is a bundle of hundreds of strands, too stiff and
    // too wide to follow the skin into a crease a few millimetres across, so it lies over the
    // crease behind an ear, and the ear, as hair lies over a finger. This field is a
    // morphological closing of the head by a ball of the bridge radius: the ball, rolled over
    // the skin from outside, cannot enter a crease narrower than its diameter, and the crease
    // counts as inside. The solver routes master strands on it; the members' push out of the
    // head stays on the skin itself. Without a bridge radius it is this field.
    const HeadField& bridged() const { return bridged_ ? *bridged_ : *this; }

  private:
    // cm: more than the rounding of a trilinear lookup of distances of up to a few metres.
    static constexpr float kBeyondSlack = 1e-3f;
    // cm: sdf() outside the grid (and everywhere for an empty field).
    static constexpr float kOutside = 1e6f;
    // False for an empty field and for p outside the grid's box (a NaN coordinate fails both
    // comparisons and counts as inside: the lookup's clamping then decides, as it always did).
    bool inside_box(const Vec3f& p) const {
        if (grid_.size() == 0) return false;
        for (int a = 0; a < 3; ++a)
            if (p[a] < box_.lo[a] || p[a] > box_.hi[a]) return false;
        return true;
    }
    // Fills cell_min_ from grid_.
    void find_cell_minima();
    Grid3<float> grid_;
    Box3 box_;
    std::shared_ptr<const HeadField> bridged_;
    std::vector<float> cell_min_;  // #cells (dims − 1 per axis, x fastest): the smallest
                                   // distance at each cell's 8 nodes, cm
};

}  // namespace wisp
