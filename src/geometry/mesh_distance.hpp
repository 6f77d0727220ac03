#pragma once
// Inside/outside and signed distance for a triangle mesh, with a BVH. Robust for closed
// meshes and for meshes with small holes or an open boundary (e.g. a head cut at the
// chest): the inside test is the generalized winding number (Jacobson et al. 2013) > 0.5.
//
// The BVH is built once (binned SAH, leaves of up to 4 triangles, flat node array). Closest
// points are exact (Ericson's point-triangle test); the winding number sums exact solid angles
// near the query and the first-order far-field expansion of Barill et al. 2018 ("Fast winding
// numbers for soups and clouds") for BVH nodes further than 2× their radius. Every query is
// const and allocation-free, so any number of threads may query one MeshDistance at once.
// Positions and distances are in the mesh's units (cm in head space).
#include <cstddef>
#include <memory>

#include "geometry/mesh.hpp"

namespace wisp {

class MeshDistance {
  public:
    explicit MeshDistance(const Mesh& mesh);  // keeps a copy of what it needs
    ~MeshDistance();
    MeshDistance(MeshDistance&&) noexcept;
    MeshDistance& operator=(MeshDistance&&) noexcept;

    // Closest point on the surface to p, with the face it lies on.
    Vec3f closest_point(const Vec3f& p, uint32_t* face = nullptr) const;
    float unsigned_distance(const Vec3f& p) const;
    // min(unsigned_distance(p), max_distance), faster far from the surface (narrow bands).
    float unsigned_distance(const Vec3f& p, float max_distance) const;
    // Generalized winding number at p: ≈1 inside, ≈0 outside a closed, outward-oriented
    // (counter-clockwise seen from outside) mesh; fractional near holes.
    float winding_number(const Vec3f& p) const;
    bool inside(const Vec3f& p) const;  // winding_number(p) > 0.5
    // Negative inside, positive outside, in cm.
    float signed_distance(const Vec3f& p) const;
    size_t face_count() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace wisp
