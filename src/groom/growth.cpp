#include "groom/growth.hpp"

#include <algorithm>
#include <cmath>

#include "core/image.hpp"
#include "geometry/scalp.hpp"

namespace wisp {
namespace {

Vec3f tangent(const Vec3f& v, const Vec3f& r) {
    return v - v.dot(r) * r;
}

Vec3f lerp(const Vec3f& a, const Vec3f& b, float t) {
    return (1.f - t) * a + t * b;
}

// The angle of r about the X axis from the front (+Z) over the top (+Y) toward the back, in
// [−π/2, 3π/2): the part line's parameter.
float over_the_top(const Vec3f& r) {
    float a = std::atan2(r.y(), r.z());
    if (a < -0.5f * kPi) a += 2.f * kPi;
    return a;
}

// Where the part runs: from the front hairline (20° above the front) over the top, to the
// whorl at part_length 1 and on down the back beyond.
constexpr float kPartStart = 0.35f;
float part_end(const GrowthSpec& spec) {
    const Vec3f w = unit_or(spec.whorl, Vec3f::UnitY());
    return kPartStart + spec.part_length * (over_the_top(w) - kPartStart);
}

// Where along its run (the angle over the top) the part closes: gradually over its last
// third, so that it runs out in the hair short of the whorl rather than meeting it in a
// second parting.
float part_closing(const GrowthSpec& spec) {
    return kPartStart + 0.65f * (part_end(spec) - kPartStart);
}

}  // namespace

float fringe_sector(const Vec3f& r) {
    return smoothstep(-0.3f, -0.05f, r.z()) * (1.f - smoothstep(0.36f, 0.48f, std::abs(r.x())));
}

float part_x(const GrowthSpec& spec) {
    return spec.part == GrowthSpec::Part::kSide ? spec.part_offset : 0.f;
}

bool on_part(const GrowthSpec& spec, const Vec3f& r, float half_width) {
    if (spec.part == GrowthSpec::Part::kNone) return false;
    const float a = over_the_top(r);
    return a > kPartStart - 0.15f && a < part_end(spec) &&
           std::abs(r.x() - part_x(spec)) < half_width;
}

float part_nearness(const GrowthSpec& spec, const Vec3f& r, float reach) {
    if (spec.part == GrowthSpec::Part::kNone || !(reach > 0.f)) return 0.f;
    const float a = over_the_top(r);
    // Fades in over the front hairline's first few degrees and out as the part closes.
    const float along = smoothstep(kPartStart - 0.15f, kPartStart + 0.05f, a) *
                        (1.f - smoothstep(part_closing(spec), part_end(spec), a));
    return along * (1.f - smoothstep(0.f, reach, std::abs(r.x() - part_x(spec))));
}

Vec3f growth_direction(const GrowthSpec& spec, const Vec3f& r) {
    const Vec3f w = unit_or(spec.whorl, Vec3f::UnitY());
    // Away from the whorl along great circles, turning about it near it (clockwise seen from
    // above is a rotation about −w).
    Vec3f away =
        unit_or(tangent(r - w, r), unit_or(tangent(-Vec3f::UnitZ(), r), any_perpendicular(r)));
    const float from_whorl = std::acos(std::clamp(r.dot(w), -1.f, 1.f));
    const float swirl =
        std::clamp(spec.whorl_swirl, 0.f, 2.f) * (1.f - smoothstep(0.25f, 0.9f, from_whorl));
    Vec3f d = away - (spec.whorl_turn * swirl) * w.cross(away);

    // Which side of the part (or of the midline) r lies on, softly across a narrow band.
    const float sigma = std::clamp((r.x() - part_x(spec)) / 0.08f, -1.f, 1.f);
    // The part: on top of the head ahead of the whorl, hair runs away from the part line.
    if (spec.part != GrowthSpec::Part::kNone) {
        const float a = over_the_top(r);
        const float p = smoothstep(kPartStart - 0.3f, kPartStart, a) *
                        (1.f - smoothstep(part_closing(spec), part_end(spec) + 0.2f, a)) *
                        smoothstep(0.15f, 0.45f, from_whorl);
        d = lerp(d, Vec3f(sigma, 0.f, -0.25f), p);
    }
    // The front hairline: to the sides past the temples, back over the head, or forward.
    const Vec3f sides(
        spec.part == GrowthSpec::Part::kNone ? std::clamp(r.x() / 0.12f, -1.f, 1.f) : sigma, -0.2f,
        -0.5f);
    const Vec3f front = spec.front == GrowthSpec::Front::kBack
                            ? Vec3f(0.25f * std::clamp(r.x() / 0.2f, -1.f, 1.f), 0.f, -1.f)
                            : sides;
    // Hair combed back runs back over all of the top ahead of the whorl, or it would meet
    // the whorl's forward growth in a seam that reads as a parting.
    float front_reach = smoothstep(0.2f, 0.65f, r.z());
    if (spec.front == GrowthSpec::Front::kBack)
        front_reach = std::max(
            front_reach, smoothstep(-0.3f, 0.1f, r.z()) * smoothstep(0.15f, 0.45f, from_whorl));
    d = lerp(d, front, front_reach);
    // A fringe grows forward over the forehead, fanning out a little toward the temples.
    if (spec.front == GrowthSpec::Front::kFringe)
        d = lerp(d, Vec3f(0.25f * r.x(), -0.8f, 0.8f), fringe_sector(r));
    // Low on the sides and at the nape hair grows down, a little outward (so it does not
    // close in on the nape) and, in front of the ears, a little back.
    const float h = std::hypot(r.x(), r.z());
    const Vec3f outward = h > 1e-4f ? Vec3f(r.x() / h, 0.f, r.z() / h) : Vec3f::Zero();
    const Vec3f low =
        -Vec3f::UnitY() + 0.3f * outward - 0.4f * std::max(r.z(), 0.f) * Vec3f::UnitZ();
    d = lerp(d, low, 0.7f * smoothstep(0.15f, -0.35f, r.y()));
    return unit_or(tangent(d, r), away);
}

Vec3f scalp_direction(const Scalp& scalp, const Vec3f& p) {
    return unit_or(Vec3f(p - scalp.center()), Vec3f::UnitY());
}

GrowthField::GrowthField(const GrowthSpec& spec, const Scalp& scalp) : spec_(spec), scalp_(&scalp) {
    if (!spec.map.empty()) {
        auto planes = read_image_planes(spec.map, 3);
        planes.resize(2);
        map_ = std::make_shared<const std::vector<GrayImage>>(std::move(planes));
    }
}

Vec3f GrowthField::operator()(const Vec3f& r) const {
    const Vec3f base = growth_direction(spec_, r);
    if (!map_ || !(spec_.map_strength > 0.f)) return base;
    const Vec2f uv = scalp_->uv_of(scalp_->center() + r);
    const float mu = 2.f * (*map_)[0].sample(uv.x(), uv.y()) - 1.f;
    const float mv = 2.f * (*map_)[1].sample(uv.x(), uv.y()) - 1.f;
    const float s = std::min(spec_.map_strength, 1.f) * smoothstep(0.05f, 0.5f, std::hypot(mu, mv));
    if (!(s > 0.f)) return base;
    // The map's direction as a horizontal direction of the top view: the image's right is the
    // subject's right (−X), its top the front (+Z). Its part away from the crown runs down the
    // sphere, its part around the crown around it.
    const Vec3f flat(-mu, 0.f, mv);
    const float h = std::hypot(r.x(), r.z());
    Vec3f d = flat;
    if (h > 1e-3f) {
        const Vec3f radial(r.x() / h, 0.f, r.z() / h);
        const float away = flat.dot(radial);
        d = away * unit_or(tangent(-Vec3f::UnitY(), r), radial) + (flat - away * radial);
    }
    d = unit_or(tangent(d, r), base);
    return unit_or(tangent(lerp(base, d, s), r), base);
}

}  // namespace wisp
