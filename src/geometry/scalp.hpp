#pragma once
// The scalp: the hair-bearing faces of a head mesh, with area-uniform sampling and the
// scalp UV map in which density, length and protrusion maps are given.
//
// Scalp UV is a polar map of the cap seen from above: the crown (the scalp point furthest
// along +Y... see scalp.cpp for the exact definition) maps to (0.5, 0.5); the distance from
// the centre grows with the angle from the crown direction, reaching 0.5 at the lowest
// hairline point; the front of the head (+Z) is toward v = 1 (the top of an image), the
// character's left (+X) toward u = 1. A user's map PNG is therefore a top view of the head.
#include <filesystem>
#include <string>
#include <vector>

#include "core/rng.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

// How the scalp faces are chosen (DESIGN: scalp regions).
struct ScalpSpec {
    enum class Kind { kGroup, kMask, kHairline };
    Kind kind = Kind::kGroup;
    std::string group = "scalp";        // kGroup: a face group or material with this name
    std::filesystem::path mask;         // kMask: grayscale image in the mesh's UV space;
                                        // faces whose UV centroid samples > 0.5 are scalp
    // kHairline: the cap above a hairline given as depths below the top of the head in cm,
    // interpolated around the head by azimuth.
    float hairline_front = 6.5f;
    float hairline_side = 10.f;
    float hairline_back = 14.f;
};

struct SurfacePoint {
    uint32_t face = 0;   // index into the head mesh's faces
    Vec2f bary{0, 0};    // barycentric coordinates (of vertices 1 and 2; vertex 0 gets 1-x-y)
    Vec3f position = Vec3f::Zero();
    Vec3f normal = Vec3f::UnitY();  // interpolated smooth surface normal, unit
    Vec2f uv{0.5f, 0.5f};           // scalp UV
};

class Scalp {
public:
    // Selects the scalp of `mesh` (kept by reference: it must outlive the Scalp). `source`
    // names the mesh in error messages. Throws wisp::Error if the scalp is empty.
    Scalp(const Mesh& mesh, const ScalpSpec& spec, const std::string& source);

    const Mesh& mesh() const { return *mesh_; }
    const std::vector<uint32_t>& faces() const { return faces_; }
    float area() const { return area_; }  // cm²
    // Crown point and the up direction of the cap (unit), used by procedural maps.
    const Vec3f& crown() const { return crown_; }
    const Vec3f& center() const { return center_; }  // centre of the head's cap sphere fit

    // An area-uniform random point on the scalp.
    SurfacePoint sample(Rng& rng) const;
    // The surface point on scalp face f at barycentric (b1, b2).
    SurfacePoint point_on(uint32_t face, const Vec2f& bary) const;
    // Scalp UV of a point on (or near) the scalp.
    Vec2f uv_of(const Vec3f& p) const;

private:
    const Mesh* mesh_;
    std::vector<uint32_t> faces_;
    std::vector<float> cdf_;             // #faces cumulative area, for sampling
    std::vector<Vec3f> vertex_normals_;  // #V smooth normals of the whole mesh
    float area_ = 0.f;
    Vec3f crown_ = Vec3f::Zero(), center_ = Vec3f::Zero();
    float max_polar_angle_ = 1.f;
};

}  // namespace wisp
