#include "solve/styling_field.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace wisp {
namespace {

// A field that sweeps hair over the head toward `pole` (a unit direction from the head's
// centre): along the great circles of the head's sphere, turning to gravity as hair leaves
// the head (beyond 1.6 radii) or passes the pole.
Vec3f swept_toward(const HeadFrame& head, const Vec3f& p, const Vec3f& pole) {
    const Vec3f down(0.f, -1.f, 0.f);
    const Vec3f d = p - head.center;
    const float dist = d.norm();
    if (dist < 1e-4f) return down;
    const Vec3f r = d / dist;
    // Every great circle from the point opposite the pole leads to it; near there, take the
    // one over the top of the head (hair combed back from the forehead goes up and over, not
    // down the face).
    const Vec3f up(0.f, 1.f, 0.f);
    const float opposite = smoothstep(0.8f, 1.f, -r.dot(pole));
    Vec3f along = pole - pole.dot(r) * r + 0.3f * opposite * (up - up.dot(r) * r);
    const float n = along.norm();
    if (n < 1e-4f) return down;
    along /= n;
    // Weight of the sweep: 1 on the head, fading out with distance and past the pole.
    const float near = 1.f - smoothstep(1.15f, 1.6f, dist / head.radius);
    const float before = smoothstep(-0.2f, 0.35f, 1.f - r.dot(pole));
    const float t = near * before;
    return ((1.f - t) * down + t * along).normalized();
}

// Long hair divided at the shoulders: beside the neck, from a little above the shoulders' top
// (so hair is already on its way before it lands) to below it, hair in front of the dividing
// plane is carried forward, over the front of the shoulder onto the chest, and hair behind it
// back, onto the back. Decisively: hair left near the plane, weakly pushed, would stay on the
// shoulder's top and slide out over the arm, so the push is full 2 mm from it.
Vec3f shoulder_section(const HeadFrame& head, const Vec3f& p) {
    if (!std::isfinite(head.shoulder_top) || !(head.neck_radius > 0.f)) return Vec3f::Zero();
    const float h = (p.y() - head.shoulder_top) / head.radius;
    if (h > 1.6f || h < -1.3f) return Vec3f::Zero();
    const Vec3f d = p - head.neck;
    const Vec3f side = Vec3f::UnitY().cross(head.forward);
    const float beside = std::abs(d.dot(side)) / head.neck_radius;
    if (beside < 1.f) return Vec3f::Zero();
    const float f = d.dot(head.forward) - head.split;
    const float weight =
        smoothstep(1.f, 1.5f, beside) * smoothstep(1.6f, 0.9f, h) * smoothstep(-1.3f, -0.7f, h);
    // Where hair lands on the shoulders' top, the push is stronger than the skin's friction
    // holds it back with (μ·g, solve.friction), or it would not divide hair lying there.
    const float push = 0.9f + 0.7f * smoothstep(0.5f, 0.25f, std::abs(h));
    return (push * weight * std::clamp(f / 0.2f, -1.f, 1.f)) * head.forward;
}

// The growth term: the scalp's growth direction at the point of the head's sphere under p,
// handing over to gravity off the head; hair in front of the face (below the brows for a
// fringe) is carried sideways, away from the part, out of the face. Most of the grid lies
// far from the head, where it is gravity alone: each part is skipped outside its region.
Vec3f grown(const HeadFrame& head, const GrowthField& growth, const Vec3f& p) {
    const Vec3f down(0.f, -1.f, 0.f);
    const Vec3f q = (p - head.center) / head.radius;  // head units
    const float dist2 = q.squaredNorm();
    if (dist2 < 1e-8f) return down;
    Vec3f phi = down;
    if (dist2 < 1.6f * 1.6f) {
        const float dist = std::sqrt(dist2);
        const float near = 1.f - smoothstep(1.15f, 1.6f, dist);
        phi = (1.f - near) * down + near * growth(q / dist);
    }
    // Below the skull, hair leaving the head falls as a curtain about as wide as the head
    // instead of closing in on the neck (a V-shaped tail, or seen from behind a mullet's step
    // in from the head's width): close to the head's vertical axis it is carried outward,
    // sideways more than back, stronger than gravity where the neck is narrowest.
    const float axis2 = q.x() * q.x() + q.z() * q.z();
    if (q.y() < -0.2f && axis2 < 1.15f * 1.15f && axis2 > 1e-8f && dist2 > 1.15f * 1.15f) {
        const float axis = std::sqrt(axis2);
        const float off_head = smoothstep(1.15f, 1.6f, std::sqrt(dist2));
        // Down to the shoulders: hair that reaches them rests on them, and carried on outward
        // along their top it would slide out over the arm.
        const float above = std::isfinite(head.shoulder_top)
                                ? smoothstep(0.1f, 0.6f, (p.y() - head.shoulder_top) / head.radius)
                                : 1.f;
        const float curtain = off_head * above * smoothstep(-0.2f, -0.7f, q.y()) *
                              (1.f - smoothstep(0.8f, 1.15f, axis));
        phi += (1.5f * curtain / axis) * Vec3f(2.f * q.x(), 0.f, q.z());
    }
    // A fringe may reach the brows; other hair is cleared from above the hairline down, so
    // that hair leaving the front hairline sideways lies over it rather than across the
    // forehead.
    const bool fringe = growth.spec().front == GrowthSpec::Front::kFringe;
    const float top = fringe ? 0.1f : 0.75f, full = fringe ? -0.15f : 0.45f;
    if (q.z() > 0.1f && q.y() < top && q.y() > -1.9f && std::abs(q.x()) < 0.9f) {
        const float x = q.x() - part_x(growth.spec());
        const float face = smoothstep(0.1f, 0.4f, q.z()) * smoothstep(top, full, q.y()) *
                           smoothstep(-1.9f, -1.4f, q.y()) *
                           (1.f - smoothstep(0.55f, 0.9f, std::abs(q.x())));
        // Held up while it crosses: hair swept from the part over the forehead travels along
        // the hairline and falls at the temple, not diagonally across the eyes. Along the head,
        // not off it: the sideways push has an outward part where the forehead curves back
        // toward the temples, and the hair it carries, lifted at the part and lying on the
        // others, left the head in a straight line, a visor 2-4 cm off the forehead.
        Vec3f across(1.5f * std::clamp(x / 0.03f, -1.f, 1.f), 0.8f, 0.f);
        const float dist = std::sqrt(dist2);
        const Vec3f r = q / dist;
        across -= (std::max(across.dot(r), 0.f) * (1.f - smoothstep(1.15f, 1.6f, dist))) * r;
        phi += face * across;
    }
    // Beside the face, from the temples to the jaw, hair that frames it lies back along the
    // cheek rather than standing forward of it: carried back the further forward it is, so the
    // face's profile stays clear of a full head of hair (curls, volume) seen from the side.
    if (q.z() > 0.15f && q.y() < 0.3f && q.y() > -1.5f && std::abs(q.x()) > 0.5f) {
        const float beside = smoothstep(0.15f, 0.6f, q.z()) * smoothstep(0.3f, 0.f, q.y()) *
                             smoothstep(-1.5f, -1.1f, q.y()) *
                             smoothstep(0.5f, 0.8f, std::abs(q.x()));
        phi -= (0.8f * beside) * Vec3f::UnitZ();
    }
    phi += shoulder_section(head, p);
    return phi;
}

}  // namespace

Vec3f field_term(const FieldTerm& term, const HeadFrame& head, const GrowthField& growth,
                 const Vec3f& p) {
    const Vec3f down(0.f, -1.f, 0.f);
    switch (term.kind) {
        case FieldTerm::Kind::kGrowth:
            return grown(head, growth, p);
        case FieldTerm::Kind::kGravity:
            return down;
        case FieldTerm::Kind::kPulledBack: {
            // Toward a point behind and below the head that moves sideways with p: each side's
            // hair is swept back on its own side and falls as a curtain about as wide as the
            // head. Toward one point, the great circles would gather all of it at the nape into
            // a tail.
            const Vec3f d = p - head.center;
            const float across = d.x() / std::max(d.norm(), 1e-4f);
            return swept_toward(head, p, Vec3f(0.9f * across, -0.55f, -1.f).normalized());
        }
        case FieldTerm::Kind::kSidePart:
            return swept_toward(head, p, Vec3f(-term.side, -0.45f, 0.15f).normalized());
        case FieldTerm::Kind::kWind:
            return term.direction.norm() > 0.f ? Vec3f(term.direction.normalized()) : Vec3f::Zero();
        case FieldTerm::Kind::kFile:
            return Vec3f::Zero();  // sampled from its grid by StylingField
    }
    return Vec3f::Zero();
}

Grid3<Vec3f> read_field_file(const std::filesystem::path& path) {
    const std::string text = read_file(path, {kMaxFieldFileBytes, "a field file", true});
    const std::string name = path.string();
    size_t pos = 0;
    int line = 0;
    auto next_line = [&](std::string_view& out) {
        while (pos < text.size()) {
            const size_t end = std::min(text.find('\n', pos), text.size());
            out = std::string_view(text).substr(pos, end - pos);
            pos = end + 1;
            ++line;
            const size_t hash = out.find('#');
            if (hash != std::string_view::npos) out = out.substr(0, hash);
            while (!out.empty() && std::isspace(static_cast<unsigned char>(out.back())))
                out.remove_suffix(1);
            while (!out.empty() && std::isspace(static_cast<unsigned char>(out.front())))
                out.remove_prefix(1);
            if (!out.empty()) return true;
        }
        return false;
    };
    auto numbers = [&](std::string_view s, float* out, int count) {
        const char* p = s.data();
        const char* end = s.data() + s.size();
        for (int i = 0; i < count; ++i) {
            while (p < end && *p == ' ')
                ++p;
            const auto [q, ec] = std::from_chars(p, end, out[i]);
            if (ec != std::errc() || !std::isfinite(out[i]))
                fail(name, ":", line, ": expected ", count, " finite numbers, got '", excerpt(s),
                     "'");
            p = q;
        }
        while (p < end && *p == ' ')
            ++p;
        if (p != end)
            fail(name, ":", line, ": unexpected text after ", count, " numbers: '", excerpt(s),
                 "'");
    };
    auto keyword = [&](std::string_view key, float* out, int count) {
        std::string_view l;
        if (!next_line(l)) fail(name, ": truncated: expected '", key, "'");
        if (l.substr(0, key.size()) != key)
            fail(name, ":", line, ": expected '", key, "', got '", excerpt(l), "'");
        numbers(l.substr(key.size()), out, count);
    };
    std::string_view l;
    if (!next_line(l) || l != "wisp-field 1")
        fail(name, ":", line, ": not a wisp field file (the first line must be 'wisp-field 1')");
    float dims_f[3], origin[3], cell;
    keyword("dims", dims_f, 3);
    for (float v : dims_f)
        if (v < 2 || v > 512 || v != std::floor(v))
            fail(name, ":", line, ": dims must be whole numbers in [2, 512]");
    keyword("origin", origin, 3);
    keyword("cell", &cell, 1);
    if (!(cell > 0.f)) fail(name, ":", line, ": cell must be > 0");
    const Vec3i dims(static_cast<int>(dims_f[0]), static_cast<int>(dims_f[1]),
                     static_cast<int>(dims_f[2]));
    // Each vector takes a line of at least 6 bytes ("0 0 0\n"): a truncated file or a
    // hostile header fails here, before the grid is allocated.
    const uint64_t vectors = uint64_t(dims.x()) * dims.y() * dims.z();
    const uint64_t left = pos < text.size() ? text.size() - pos : 0;
    if (vectors * 6 > left + 1)
        fail(name, ":", line, ": dims ", dims.x(), " ", dims.y(), " ", dims.z(), " declare ",
             vectors, " vectors, which need at least ", vectors * 6, " bytes, but only ", left,
             " are left");
    Grid3<Vec3f> grid(Vec3f(origin[0], origin[1], origin[2]), cell, dims, Vec3f::Zero());
    for (size_t i = 0; i < grid.size(); ++i) {
        if (!next_line(l)) fail(name, ": truncated: expected ", grid.size(), " vectors, got ", i);
        float v[3];
        numbers(l, v, 3);
        grid.data()[i] = Vec3f(v[0], v[1], v[2]);
    }
    if (next_line(l)) fail(name, ":", line, ": more vectors than dims give (", grid.size(), ")");
    return grid;
}

StylingField::StylingField(std::span<const FieldTerm> terms, const HeadFrame& head,
                           const GrowthField& growth, const Box3& bounds, float cell) {
    Vec3i dims;
    for (int a = 0; a < 3; ++a)
        dims[a] = std::max(2, static_cast<int>(std::ceil(bounds.size()[a] / cell)) + 1);
    grid_ = Grid3<Vec3f>(bounds.lo, cell, dims, Vec3f::Zero());
    std::vector<std::unique_ptr<Grid3<Vec3f>>> files(terms.size());
    for (size_t t = 0; t < terms.size(); ++t)
        if (terms[t].kind == FieldTerm::Kind::kFile)
            files[t] = std::make_unique<Grid3<Vec3f>>(read_field_file(terms[t].file));
    parallel_for(
        grid_.size(),
        [&](size_t i) {
            const int x = static_cast<int>(i % dims.x());
            const int y = static_cast<int>((i / dims.x()) % dims.y());
            const int z = static_cast<int>(i / (static_cast<size_t>(dims.x()) * dims.y()));
            const Vec3f p = grid_.node(x, y, z);
            Vec3f phi = Vec3f::Zero();
            for (size_t t = 0; t < terms.size(); ++t) {
                const Vec3f v =
                    files[t] ? files[t]->trilinear(p) : field_term(terms[t], head, growth, p);
                phi += terms[t].weight * v;
            }
            grid_.data()[i] = phi;
        },
        4096);
}

}  // namespace wisp
