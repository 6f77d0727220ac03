#pragma once
// The head as a field: a signed distance grid around the head mesh, from which the solver
// reads the head's density (Choe & Ko §3.2: 1 inside the head and shoulders, 0 outside) and
// its gradient, and which keeps every hair point out of the head.
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
    // (close_holes), so that its inside is inside everywhere.
    HeadField(const Mesh& mesh, float cell);
    // The node count of the grid the constructor builds for a mesh with these bounds (cm), to
    // check against kMaxGridNodes before building it.
    static double node_count(const Box3& mesh_bounds, float cell);

    // Trilinear signed distance, cm; points outside the grid get a large positive value.
    float sdf(const Vec3f& p) const;
    // The same distance and, in *gradient, the exact gradient of the trilinear interpolant
    // (≈ outward normal; zero outside the grid), for the price of one lookup.
    float sdf(const Vec3f& p, Vec3f* gradient) const;
    // Gradient of the trilinear signed distance (central differences), ≈ outward normal.
    Vec3f gradient(const Vec3f& p) const;
    // Head density: 1 on and inside the surface, falling linearly to 0 at `margin` cm out.
    float density(const Vec3f& p, float margin) const {
        const float d = sdf(p);
        return d <= 0.f ? 1.f : (d >= margin ? 0.f : 1.f - d / margin);
    }
    const Grid3<float>& grid() const { return grid_; }
    bool empty() const { return grid_.size() == 0; }

  private:
    Grid3<float> grid_;
    Box3 box_;
};

}  // namespace wisp
