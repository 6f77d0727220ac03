#include "groom/maps.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/noise.hpp"
#include "groom/growth.hpp"

namespace wisp {
namespace {

// How far the nape-short and tapered maps fall toward the nape, at most `depth`: 0 on top,
// rising toward the hairline, most at the back.
float nape_fall(float r, float z, float depth) {
    const float back = smoothstep(-0.3f, 0.6f, -z);
    return depth * smoothstep(0.45f, 0.95f, r) * (0.35f + 0.65f * back);
}

// The sides map: above and behind the ears, judged from the map alone.
float sides_region(float r, float x) {
    return smoothstep(0.55f, 0.85f, r) * smoothstep(0.55f, 0.85f, std::abs(x));
}

// A procedural map from the scalp's polar UV: r in [0,1] from crown to hairline, (x, z) the
// unit direction on the map (x toward the character's left, z toward the front). Maps that
// follow the growth directions' regions take the point's direction from the scalp's centre
// (`dir`) instead, so that they cover the same roots; maps shaped around the ears take how near
// the point lies to one (`ear`, from ear_nearness); the part maps how near it lies to the
// style's part (`part`, from part_nearness).
float procedural(int which, const Vec2f& uv, const Vec3f& dir, float ear, float part) {
    const float du = uv.x() - 0.5f, dv = uv.y() - 0.5f;
    const float r = std::min(1.f, 2.f * std::sqrt(du * du + dv * dv));
    const float len = std::sqrt(du * du + dv * dv);
    const float x = len > 1e-6f ? -du / len : 0.f;  // u grows toward the character's right
    const float z = len > 1e-6f ? dv / len : 0.f;
    switch (which) {
        case 0:  // uniform
            return 1.f;
        case 1: {  // bangs: the forehead sector near the hairline
            const float front = smoothstep(0.55f, 0.8f, z);
            return 1.f - 0.65f * front * smoothstep(0.45f, 0.75f, r);
        }
        case 2:  // nape-short
            return 1.f - nape_fall(r, z, 0.7f);
        case 3:  // crown
            return 1.f - r;
        case 4:  // hairline
            return r;
        case 5:  // front
            return 0.5f + 0.5f * z * r;
        case 6:  // back
            return 0.5f - 0.5f * z * r;
        case 7: {  // side-part: a line from the front hairline back over the left of the crown
            const float line_x = 0.16f;  // in unit-disk coordinates (r·x)
            const float px = r * x, pz = r * z;
            const float d = std::abs(px - line_x);
            return (pz > -0.15f && d < 0.025f) ? 0.15f : 1.f;
        }
        case 8:  // left: the character's left half (x > 0) above 0.5
            return 0.5f + 0.5f * x * r;
        case 9:  // right
            return 0.5f - 0.5f * x * r;
        case 10:  // nape: the low back of the head, by the nape hairline
            return smoothstep(0.55f, 0.85f, r) * smoothstep(0.35f, 0.75f, -z);
        case 11:  // sides: above and behind the ears
            return sides_region(r, x);
        case 12:  // fringe: 0 over the sector that grows a fringe (groom/growth.hpp), 1 elsewhere
            return 1.f - fringe_sector(dir);
        case 13: {  // tapered: a barber's taper: longest on top toward the front, falling
                    // down the back (most) and the sides to 0 around the ears (without
                    // landmarks, taken to be under the sides of the map), with no step
            const float back = smoothstep(-0.3f, 0.6f, -z);
            const float down = 0.85f * smoothstep(0.3f, 0.9f, r) * (0.2f + 0.8f * back);
            const float sides =
                0.75f * smoothstep(0.4f, 0.85f, r) * smoothstep(0.3f, 0.8f, std::abs(x));
            return 1.f - std::max({down, sides, ear >= 0.f ? ear : sides_region(r, x)});
        }
        case 14:  // part
            return part;
        case 15:  // crown-part: a blow-dry lifts the top, not the sides, where hair lies flat
            return std::max(1.f - smoothstep(0.15f, 0.7f, r), part);
    }
    return 1.f;
}

// How near a scalp point lies to the nearer ear: 1 within 0.18 head heights of the ear's
// outermost point (the roots just above, behind and in front of it), falling to 0 at 0.42 (short
// of the crown and the temples); -1 when the head's ears are not known.
float ear_nearness(const Scalp& scalp, const Vec3f& p) {
    const auto& ears = scalp.ears();
    if (!ears || !(ears->head_height > 0.f)) return -1.f;
    const float d = std::min((p - ears->left).norm(), (p - ears->right).norm());
    return 1.f - smoothstep(0.18f * ears->head_height, 0.5f * ears->head_height, d);
}

}  // namespace

const std::vector<std::string>& procedural_map_names() {
    // New names go at the end: the index is the case in procedural().
    static const std::vector<std::string> names = {
        "uniform", "bangs", "nape-short", "crown", "hairline", "front",   "back", "side-part",
        "left",    "right", "nape",       "sides", "fringe",   "tapered", "part", "crown-part"};
    return names;
}

// How far either side of the part line the part maps reach, in head units (about 1.3 cm on
// an adult head): the hair that stands up off a parting before it falls away from it.
constexpr float kPartReach = 0.14f;

MapSampler::MapSampler(const ScalarMap& map, const Scalp& scalp, const GrowthSpec& growth)
    : map_(map), scalp_(&scalp), growth_(growth) {
    if (map.kind == ScalarMap::Kind::kImage) {
        image_ =
            map.pixels ? map.pixels : std::make_shared<const GrayImage>(read_gray_image(map.image));
    } else if (map.kind == ScalarMap::Kind::kProcedural) {
        const auto& names = procedural_map_names();
        const auto it = std::find(names.begin(), names.end(), map.procedural);
        if (it == names.end()) fail("unknown procedural map '", map.procedural, "'");
        procedural_ = static_cast<int>(it - names.begin());
    }
}

// At the temples and down the sideburns (the sides of the head in front of the ears) the
// hairline's ramp is this many times wider: the temples recede and sideburns thin to their
// ends instead of stopping at a line.
constexpr float kTempleRamp = 2.5f;

namespace {

// The temples and the sideburns: the sides of the head in front of the ears, 0 … 1.
float temple_region(const Scalp& scalp, const Vec3f& p) {
    const Vec3f r = scalp_direction(scalp, p);
    return smoothstep(0.55f, 0.8f, std::abs(r.x())) * smoothstep(-0.25f, 0.05f, r.z());
}

// The hairline's noise: fixed, so that it belongs to the head (its positions), not the style.
constexpr uint64_t kHairlineNoise = 0x6861'6972'6c69'6e65;  // "hairline"

}  // namespace

float hairline_edge(const Scalp& scalp, const Vec3f& p, float edge, float irregularity) {
    if (!(irregularity > 0.f)) return edge;
    const float wander = 0.65f * value_noise(kHairlineNoise, p / 1.5f) +
                         0.35f * value_noise(kHairlineNoise + 1, p / 0.6f) +
                         0.5f * temple_region(scalp, p);
    return edge - irregularity * wander;
}

float hairline_edge(const Scalp& scalp, const SurfacePoint& p, float irregularity) {
    return hairline_edge(scalp, p.position, scalp.edge_distance(p), irregularity);
}

float hairline_density(const Scalp& scalp, const Vec3f& p, float edge, const HairlineSpec& spec) {
    if (edge >= kTempleRamp * spec.width + hairline_wander(spec.irregularity)) return 1.f;
    const float inside = hairline_edge(scalp, p, edge, spec.irregularity);
    if (!(spec.width > 0.f)) return inside > 0.f ? 1.f : 0.f;
    return smoothstep(0.f, hairline_ramp(scalp, p, spec.width), inside);
}

float hairline_lie(const Scalp& scalp, const SurfacePoint& root, const HairlineSpec& spec) {
    if (!(spec.width > 0.f)) return 0.f;
    const float inside = hairline_edge(scalp, root, spec.irregularity);
    return spec.lie * (1.f - smoothstep(0.f, 3.f * spec.width, inside));
}

float hairline_ramp(const Scalp& scalp, const Vec3f& p, float width) {
    return width * (1.f + (kTempleRamp - 1.f) * temple_region(scalp, p));
}

float MapSampler::operator()(const SurfacePoint& p) const {
    const float v = value(p);
    if (!hairline_) return v;
    return v * hairline_density(*scalp_, p.position, scalp_->edge_distance(p), *hairline_);
}

float MapSampler::value(const SurfacePoint& p) const {
    switch (map_.kind) {
        case ScalarMap::Kind::kConstant:
            return map_.value;
        case ScalarMap::Kind::kImage:
            return map_.low + (map_.high - map_.low) * image_->sample(p.uv.x(), p.uv.y());
        case ScalarMap::Kind::kProcedural: {
            // Only the fringe and part maps need the direction and only the tapered map the
            // ears (the roots look up the density at every rejection-sampling try).
            const bool part_map = procedural_ == 14 || procedural_ == 15;
            const Vec3f dir = procedural_ == 12 || part_map ? scalp_direction(*scalp_, p.position)
                                                            : Vec3f::UnitY();
            const float ear = procedural_ == 13 ? ear_nearness(*scalp_, p.position) : -1.f;
            const float part = part_map ? part_nearness(growth_, dir, kPartReach) : 0.f;
            return map_.low +
                   (map_.high - map_.low) * procedural(procedural_, p.uv, dir, ear, part);
        }
    }
    return map_.value;
}

}  // namespace wisp
