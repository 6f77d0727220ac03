#pragma once
// The styling force field Φ (Choe & Ko §3.1, §6.1): the desired flow direction and
// intensity of hair at every point, on a 3D grid read by trilinear interpolation (§3.3).
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <span>

#include "core/grid.hpp"
#include "groom/style.hpp"

namespace wisp {

// Where the head is, for position-dependent fields: the centre and radius of the scalp's
// sphere (head units, ConstraintSpec::head_relative).
struct HeadFrame {
    Vec3f center = Vec3f::Zero();
    float radius = 10.f;
    // Where long hair reaches the shoulders and divides, as a stylist lays it, into a section
    // that falls in front of them and one behind (hair left to land on a shoulder's top slides
    // out over the arm): the neck's axis and radius, the way the face looks (horizontal,
    // unit), the top of the shoulders beside the neck, and the dividing plane's offset along
    // `forward` from the neck (the ears' plane). From the head's landmarks and body
    // (head_frame(const Head&)); shoulder_top NaN when they are not known: hair is not divided.
    Vec3f neck = Vec3f::Zero();
    Vec3f forward = Vec3f::UnitZ();
    float neck_radius = 0.f;
    float shoulder_top = NAN;
    float split = 0.f;
    Vec3f to_space(const Vec3f& head_units) const { return center + radius * head_units; }
};

// The value of one predefined term at p (before its weight):
//   gravity      (0, −1, 0)
//   pulled-back  hair swept over the head toward the nape, along the great circles of the
//                head's sphere (near the point opposite the nape, where they all meet, the
//                one over the crown), turning to gravity as it leaves the head
//   side-part    the same toward the side −side·X (the part on the other side)
//   wind         the term's direction, normalized
//   growth       on the head, the scalp's growth direction (groom/growth.hpp) where p lies,
//                turning to gravity as hair leaves the head; hair in front of the face (below
//                the brows when the front hairline grows a fringe) is carried sideways out
//                of the face; from just above the shoulders' top to below it, hair beside
//                the neck is carried forward or back (HeadFrame::shoulder_top)
Vec3f field_term(const FieldTerm& term, const HeadFrame& head, const GrowthField& growth,
                 const Vec3f& p);

// Reads a field file (the format of docs/style.md "Field files"):
//   wisp-field 1
//   dims NX NY NZ
//   origin X Y Z          (cm, head space)
//   cell C                (cm)
//   NX·NY·NZ lines "FX FY FZ", x fastest, then y, then z
// Throws wisp::Error naming the file and line on any malformed or truncated content.
Grid3<Vec3f> read_field_file(const std::filesystem::path& path);
// The most a field file may hold: 512³ vectors of about 15 characters each.
inline constexpr uint64_t kMaxFieldFileBytes = uint64_t(2) << 30;

class StylingField {
  public:
    StylingField() = default;
    // Samples Σ weight·term over `bounds` with the given cell size.
    StylingField(std::span<const FieldTerm> terms, const HeadFrame& head, const GrowthField& growth,
                 const Box3& bounds, float cell);
    Vec3f operator()(const Vec3f& p) const { return grid_.trilinear(p); }
    const Grid3<Vec3f>& grid() const { return grid_; }

  private:
    Grid3<Vec3f> grid_;
};

}  // namespace wisp
