#pragma once
// The scalp: the hair-bearing faces of a head mesh, with area-uniform sampling and the
// scalp UV map in which density, length and protrusion maps are given.
//
// Scalp UV is the azimuthal equidistant ("polar") map of the cap about the vertical through
// center(): for a point p, with d = p - center(),
//     θ = angle between d and +Y = atan2(√(dx² + dz²), dy)        (polar angle, radians)
//     r = 0.5 · min(θ / θmax, 1)       θmax = the largest θ over the scalp's vertices
//     u = 0.5 − r · dx / √(dx² + dz²),  v = 0.5 + r · dz / √(dx² + dz²)
// so the crown maps to (0.5, 0.5), the lowest hairline point to the unit disk's rim (radius
// 0.5 about the centre), the front of the head (+Z) toward v = 1 (the top row of an image) and
// the character's left (+X) toward u = 0 (the left of an image). A user's map PNG is thus the
// top view of the head seen from above with the face up: what a hairdresser standing behind
// the chair sees. Points beyond θmax clamp to the rim.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/rng.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

// How the scalp faces are chosen (DESIGN: scalp regions).
struct ScalpSpec {
    enum class Kind { kGroup, kMask, kHairline };
    Kind kind = Kind::kGroup;
    std::string group = "scalp";  // kGroup: a face group or material with this name
    std::filesystem::path mask;   // kMask: grayscale image in the mesh's UV space;
                                  // faces whose UV centroid samples > 0.5 are scalp
    // kHairline: the cap above a hairline given as depths below the top of the head in cm,
    // interpolated around the head by azimuth. The back is the nape hairline, about the level
    // of the ear lobes on an adult head (the built-in head's is 18 cm below its crown).
    float hairline_front = 6.5f;
    float hairline_side = 10.f;
    float hairline_back = 18.f;
};

struct SurfacePoint {
    uint32_t face = 0;  // index into the head mesh's faces
    Vec2f bary{0, 0};   // barycentric coordinates (of vertices 1 and 2; vertex 0 gets 1-x-y)
    Vec3f position = Vec3f::Zero();
    Vec3f normal = Vec3f::UnitY();  // interpolated smooth surface normal, unit
    Vec2f uv{0.5f, 0.5f};           // scalp UV
};

class Scalp {
  public:
    // Selects the scalp of `mesh` (kept by reference: it must outlive the Scalp). `source`
    // names the mesh in error messages. Throws wisp::Error naming the source and the
    // selection if the scalp is empty, a group is unknown, or a mask needs UVs the mesh lacks.
    //  kGroup     faces whose group or material is spec.group;
    //  kMask      faces whose UV centroid samples spec.mask (v = 0 at the image's bottom) > 0.5;
    //  kHairline  on the connected piece of largest area (so helper shells, eyes and teeth of
    //             full-body meshes are skipped), the faces above top - depth(azimuth) whose
    //             centroid lies within the cranium's horizontal extent (measured 0.5-8 cm below
    //             the top, grown 8%) and whose normal faces away from the head and not down,
    //             connected to the topmost one. Depth blends front → side → back smoothly.
    // Only the first head_faces faces may be scalp (a body appended after the head never
    // grows hair; the hairline's "largest piece" is the head's).
    Scalp(const Mesh& mesh, const ScalpSpec& spec, const std::string& source,
          size_t head_faces = SIZE_MAX);

    const Mesh& mesh() const { return *mesh_; }
    const std::vector<uint32_t>& faces() const { return faces_; }  // sorted, face indices
    float area() const { return area_; }                           // cm²
    // The crown: where the vertical through center() leaves the scalp (UV (0.5, 0.5)).
    const Vec3f& crown() const { return crown_; }
    // Centre of the least-squares sphere through the scalp's vertices (the cranium's centre);
    // a flat patch falls back to below its bounding box centre.
    const Vec3f& center() const { return center_; }

    // An area-uniform random point on the scalp: a face by the area CDF, then uniform
    // barycentrics (3 draws from rng; deterministic for a given stream).
    SurfacePoint sample(Rng& rng) const;
    // The slot in faces() that sample() picks for a uniform u in [0, 1): the first whose
    // cumulative area (a fraction of area()) exceeds u.
    size_t face_slot(float u) const;
    // #faces: the cumulative area of faces()[0 .. i] as a fraction of area() (the last is 1).
    const std::vector<float>& cumulative_area() const { return cdf_; }
    // The surface point on scalp face f at barycentric (b1, b2).
    SurfacePoint point_on(uint32_t face, const Vec2f& bary) const;
    // Scalp UV of a point on (or near) the scalp.
    Vec2f uv_of(const Vec3f& p) const;
    // θmax of the polar map (radians): the polar angle that reaches the UV disk's rim. With
    // center() it inverts uv_of on directions (the editor paints maps through it).
    float max_polar_angle() const { return max_polar_angle_; }

    // How far a point on the scalp lies from the scalp's edge, the hairline, in cm: its face's
    // vertices' distances to the nearest edge (within 0.1 cm), interpolated. An edge is where a
    // scalp face meets a face that is not scalp or none (vertices at one position are one, so
    // UV seams are no edge); a scalp without one gives kNoEdge.
    float edge_distance(const SurfacePoint& p) const;
    // The same at point q on (or near) scalp face f.
    float edge_distance(uint32_t face, const Vec3f& q) const;
    static constexpr float kNoEdge = 1e6f;

    // The ears as the head's landmarks place them (find_landmarks), so that maps can shape hair
    // around them on any head: their outermost points and the head's height, chin to crown.
    struct Ears {
        Vec3f left = Vec3f::Zero(), right = Vec3f::Zero();
        float head_height = 0.f;
    };
    void set_ears(const Ears& ears) { ears_ = ears; }
    // Empty when the head's landmarks were not found.
    const std::optional<Ears>& ears() const { return ears_; }

  private:
    const Mesh* mesh_;
    std::vector<uint32_t> faces_;
    std::vector<float> cdf_;             // #faces cumulative area, for sampling
    std::vector<uint32_t> guide_;        // #faces+1: face_slot(b / #faces), where its search starts
    std::vector<Vec3f> vertex_normals_;  // #V smooth normals of the whole mesh
    std::vector<float> edge_distance_;   // #V: edge_distance at the scalp's vertices
    float area_ = 0.f;
    Vec3f crown_ = Vec3f::Zero(), center_ = Vec3f::Zero();
    float max_polar_angle_ = 1.f;
    std::optional<Ears> ears_;
};

}  // namespace wisp
