#pragma once
// The growth direction of hair on the scalp: the tangent direction in which hair leaves the
// skin, as real scalps have it. Hair grows away from a crown whorl, turning about it in the
// whorl's sense; a parting splits the hair on the top of the head to either side of its line;
// at the front hairline hair runs to the sides (past the temples), back, or forward as a
// fringe; at the temples and nape it runs down.
//
// Positions are unit directions from the centre of the scalp's fitted sphere (the head
// frame of solve/styling_field.hpp), in head space: Y up, +Z forward, +X the subject's left.
// The styling field's "growth" term carries the same directions off the scalp, so the
// hair's flow over the head continues what its roots start.
#include <filesystem>
#include <memory>
#include <vector>

#include "core/math.hpp"

namespace wisp {

class Scalp;
struct GrayImage;

struct GrowthSpec {
    enum class Part { kNone, kCentre, kSide };
    enum class Front { kSides, kBack, kFringe };
    Part part = Part::kCentre;
    // kSide: the part's distance from the midline, in head units along x; positive on the
    // subject's left (+X, hair swept to the right), negative on the right. Ignored for kCentre.
    float part_offset = 0.3f;
    // How far the part runs back from the front hairline over the top: up to the whorl at 1,
    // on down the back beyond (2.5 reaches the nape). In (0, 3].
    float part_length = 1.f;
    // Front hairline hair: to the sides of the face past the temples (the part's sides; with
    // no part, either side of the midline), back over the head, or forward as a fringe.
    Front front = Front::kSides;
    // The crown whorl: a direction from the head centre (normalized on use), and its sense
    // seen from above: +1 clockwise (most people), −1 counter-clockwise.
    Vec3f whorl = Vec3f(0.f, 0.93f, -0.37f);
    float whorl_turn = 1.f;
    float whorl_swirl = 1.5f;  // how strongly hair turns about the whorl near it, in [0, 2]
    // A growth-direction map (empty: none): an image in scalp UV (the top view of the head,
    // face up, as the scalar maps) whose red and green give the direction hair grows in that
    // view, 2·(R, G) − 1 toward the image's right and top. Neutral grey (0.5, 0.5, within 0.025)
    // leaves the directions above; a stronger colour takes over from them, fully at |2·(R, G) − 1|
    // ≥ 0.5, times `map_strength` in [0, 1]. A direction pointing away from the image centre runs
    // down the head from the crown; one around it, around the head.
    std::filesystem::path map;
    float map_strength = 1.f;
};

// The growth direction at unit direction r from the head centre: a unit vector tangent to the
// sphere at r (⟂ r). Without the map.
Vec3f growth_direction(const GrowthSpec& spec, const Vec3f& r);

// The unit direction of p from the scalp's centre (+Y at the centre itself): where
// growth_direction, fringe_sector and the growth field are evaluated.
Vec3f scalp_direction(const Scalp& scalp, const Vec3f& p);

// The growth directions of a style on a scalp: growth_direction() with the growth map, if
// any, loaded once. Cheap to copy.
class GrowthField {
  public:
    // Loads spec.map (throws wisp::Error naming it if unreadable). `scalp` gives the UV of
    // a direction and must outlive the field when there is a map.
    GrowthField(const GrowthSpec& spec, const Scalp& scalp);

    const GrowthSpec& spec() const { return spec_; }
    // The growth direction at unit direction r from the scalp's centre.
    Vec3f operator()(const Vec3f& r) const;

  private:
    GrowthSpec spec_;
    const Scalp* scalp_ = nullptr;
    std::shared_ptr<const std::vector<GrayImage>> map_;  // red, green
};

// How much unit direction r lies in the fringe sector, the front of the top of the head whose
// hair grows forward over the forehead when front = kFringe: 1 across the forehead between
// the temples, falling to 0 at the temples and toward the crown. The fringe map and a fringe
// cut ([cut] region = "fringe") use the same sector.
float fringe_sector(const Vec3f& r);

// The part line's x (head units) at the front of the head, signed; 0 for a centre part.
float part_x(const GrowthSpec& spec);

// Whether unit direction r lies within `half_width` (head units) of the part line, which runs
// from the front hairline over the top (part_length). False when there is no part.
bool on_part(const GrowthSpec& spec, const Vec3f& r, float half_width);

// How near unit direction r lies to the part line, over the part's run: 1 on it, falling
// smoothly to 0 at `reach` (head units) to either side. 0 everywhere when there is no part.
float part_nearness(const GrowthSpec& spec, const Vec3f& r, float reach);

}  // namespace wisp
