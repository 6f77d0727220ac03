#pragma once
// Inside/outside and signed distance for a triangle mesh, with a BVH. Robust for closed
// meshes and for meshes with small holes or an open boundary (e.g. a head cut at the
// chest): the inside test is the generalized winding number (Jacobson et al. 2013) > 0.5.
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
    bool inside(const Vec3f& p) const;
    // Negative inside, positive outside, in cm.
    float signed_distance(const Vec3f& p) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace wisp
