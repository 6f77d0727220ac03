#include "geometry/builtin_head.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/parallel.hpp"

namespace wisp {
namespace {

// ---- The implicit head: a smooth union of ellipsoids, capsules and a few shaped parts.
// Values are approximate signed distances in cm (negative inside), accurate near the surface.

float smin(float a, float b, float k) {  // polynomial smooth minimum, blend width k
    const float h = std::max(k - std::abs(a - b), 0.f) / k;
    return std::min(a, b) - h * h * k * 0.25f;
}
float smax(float a, float b, float k) {
    return -smin(-a, -b, k);
}
// Ellipsoid bound (Quilez): exact on the surface, good nearby.
float ellipsoid(const Vec3f& p, const Vec3f& c, const Vec3f& r) {
    const Vec3f q = p - c;
    const float k0 = q.cwiseQuotient(r).norm();
    const float k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
    return k1 > 1e-12f ? k0 * (k0 - 1.f) / k1 : -r.minCoeff();
}
float ellipse(const Vec2f& q, const Vec2f& r) {  // the same in the plane
    const float k0 = q.cwiseQuotient(r).norm();
    const float k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
    return k1 > 1e-12f ? k0 * (k0 - 1.f) / k1 : -r.minCoeff();
}

// A capsule whose radius goes from ra at a to rb at b (linearly along the axis).
float cone_capsule(const Vec3f& p, const Vec3f& a, const Vec3f& b, float ra, float rb) {
    const Vec3f pa = p - a, ba = b - a;
    const float h = std::clamp(pa.dot(ba) / ba.squaredNorm(), 0.f, 1.f);
    return (pa - h * ba).norm() - (ra + (rb - ra) * h);
}

// The cranium: a superellipsoid, squarer than an ellipsoid in the horizontal section (the
// forehead is broad and the sides flat), with its own radius on each side of the centre.
// Distance estimate (g - 1) / |∇g| of the implicit g = 1 surface.
float cranium(const Vec3f& p) {
    const Vec3f c(0.f, 3.0f, -0.7f);
    const Vec3f q = p - c;
    const float taper = 1.f - 0.08f * smoothstep(-2.f, 9.f, q.z());  // narrower at the brow
    const float rx = 7.55f * taper;
    const float ry = q.y() > 0.f ? 9.5f : 8.0f;
    const float rz = q.z() > 0.f ? 9.55f : 9.1f;
    const float ax = std::abs(q.x()) / rx, az = std::abs(q.z()) / rz, ay = q.y() / ry;
    // The horizontal section: |x/rx|^n + |z/rz|^n = 1, n = 3 in front, 2 (an ellipse) behind;
    // big_h = h^(2/n) is the squared horizontal "radius", dh = ∂big_h/∂a / (2a) per axis.
    float big_h, dhx, dhz;
    if (q.z() > 0.f) {
        const float h = ax * ax * ax + az * az * az;
        const float cb = std::cbrt(h);
        big_h = cb * cb;
        const float s = cb > 1e-6f ? 1.f / cb : 0.f;  // h^(2/3 - 1)
        dhx = s * ax;
        dhz = s * az;
    } else {
        big_h = ax * ax + az * az;
        dhx = dhz = 1.f;
    }
    const float g = std::sqrt(big_h + ay * ay);
    // ∇g = (dhx·ax/rx, ay/ry, dhz·az/rz) / g.
    const float gx = dhx * ax / rx, gy = ay / ry, gz = dhz * az / rz;
    const float grad = std::sqrt(gx * gx + gy * gy + gz * gz);
    return grad > 1e-9f ? g * (g - 1.f) / grad : -8.f;
}

// ---- The ear: a flattened shell in its own plane, facing out and a little forward, its
// front edge sunk into the side of the head and its back edge standing off it; a rolled rim
// (the helix) around the top and back, a bowl inside the rim, a lobe and a tragus. Solid
// everywhere (no holes), so the surface stays genus 0.
struct EarFrame {
    Vec3f origin;
    Vec3f n, a, b;  // out of the ear's face, up its long axis, forward across it
};
EarFrame make_ear_frame() {
    const float yaw = 0.6f;    // radians the face turns forward from +X (the back stands off)
    const float tilt = 0.26f;  // radians the long axis leans back at the top
    EarFrame f;
    f.origin = Vec3f(7.55f, 0.35f, -1.45f);
    f.n = Vec3f(std::cos(yaw), 0.f, std::sin(yaw));
    const Vec3f up(0.f, std::cos(tilt), -std::sin(tilt));
    f.a = (up - up.dot(f.n) * f.n).normalized();
    f.b = f.n.cross(f.a);  // forward-ish
    return f;
}
const EarFrame kEar = make_ear_frame();
const Vec3f kEarCentre = kEar.origin;  // for bounds and the scalp's ear test
constexpr float kEarRadius = 3.8f;

// The ear's outline in its plane: an egg 6.2 cm tall and 3.5 cm across, narrower at the lobe.
float ear_outline(float b, float a) {
    const float narrow = 1.f - 0.22f * smoothstep(0.5f, -3.f, a);
    return ellipse(Vec2f(b / narrow, a), Vec2f(1.75f, 3.1f));
}

float ear(const Vec3f& m) {
    const Vec3f q = m - kEar.origin;
    const float n = q.dot(kEar.n), a = q.dot(kEar.a), b = q.dot(kEar.b);
    const float outline = ear_outline(b, a);
    auto at = [&](const Vec3f& c, const Vec3f& r) { return ellipsoid(Vec3f(b, a, n), c, r); };
    // The plate: 1.5 cm thick (the outline extruded to 0.4 cm, its edges rounded by 0.55 cm),
    // thick as a mannequin's, so that hair collisions, which see the head through a 0.75 cm
    // grid, see it.
    const float inner = outline + 0.55f, slab = std::abs(n + 0.15f) - 0.2f;
    const float plate = std::hypot(std::max(inner, 0.f), std::max(slab, 0.f)) +
                        std::min(std::max(inner, slab), 0.f) - 0.55f;
    // The helix: a broad roll just inside the outline, raised on the outer face (its top flat
    // enough for the collision grid, radius ~1.2 cm across), lower at the front where the ear
    // meets the head.
    const float rise = 0.45f - 0.15f * smoothstep(-0.2f, 1.4f, b) * smoothstep(-1.f, 1.5f, a) -
                       0.15f * smoothstep(0.5f, -1.5f, a);
    const float rim = ellipse(Vec2f(outline + 0.75f, n - 0.55f), Vec2f(0.75f, rise));
    float d = smin(plate, rim, 0.3f);
    // The lobe, fuller and rounder at the bottom, and the back of the ear's root, which fills
    // the narrow of the fold between the ear and the head.
    d = smin(d, at({0.15f, -2.55f, -0.1f}, {0.95f, 0.8f, 0.7f}), 0.4f);
    d = smin(d, at({0.7f, -0.6f, -1.f}, {1.1f, 2.1f, 0.8f}), 0.8f);
    // The bowl inside the rim (scapha and concha), deepest near the ear canal; its floor stays
    // 1.2 cm thick.
    d = smax(d, -at({0.05f, 0.15f, 1.f}, {1.1f, 2.2f, 0.62f}), 0.6f);
    d = smax(d, -at({0.45f, -0.6f, 0.95f}, {0.75f, 0.85f, 0.55f}), 0.5f);
    // The tragus: a small flap in front of the concha.
    d = smin(d, at({1.35f, -0.75f, 0.55f}, {0.45f, 0.55f, 0.45f}), 0.25f);
    return d;
}

const Vec3f kMouthCentre(0.f, -5.1f, 8.8f), kNoseTip(0.f, -1.8f, 10.3f);

// ---- The lips, in coordinates that wrap around the dental arch: s is the arc length along
// the arch from the midline (cm), t the distance out of it, y the height.
Vec3f arch_coordinates(const Vec3f& p) {
    constexpr float kArchRadius = 5.0f, kArchZ = 4.45f;  // the arch's front is at z = 9.45
    const float dz = p.z() - kArchZ;
    const float rho = std::hypot(p.x(), dz);
    return {kArchRadius * std::atan2(p.x(), dz), p.y(), rho - kArchRadius};
}

float lips(const Vec3f& p) {
    const Vec3f q = arch_coordinates(p);
    const float s = std::abs(q.x()), y = q.y(), t = q.z();
    // Each lip is, at arc length s, an ellipse in the (y, t) section between its edge and the
    // line of the mouth, thinning and sinking toward the corners (s = 2.7 cm).
    const float w = std::clamp(s / 2.7f, 0.f, 1.f), w2 = w * w;
    const float mouth = -4.95f + 0.1f * w2;  // the line between the lips, rising a little
    // The upper edge: a Cupid's bow, two peaks 0.55 cm either side of the middle.
    const float bow =
        0.1f * std::exp(-(s - 0.55f) * (s - 0.55f) / 0.1f) - 0.06f * smoothstep(0.45f, 0.f, s);
    const float top = -4.2f + bow - 0.45f * w2;
    const float bottom = -5.95f + 0.6f * w2;  // the lower edge
    auto lip = [&](float y0, float y1, float depth, float forward) {
        const float d = ellipse(Vec2f(y - 0.5f * (y0 + y1), t - forward),
                                Vec2f(0.5f * (y1 - y0), depth * (1.f - 0.5f * w2)));
        return smax(d, s - 2.7f, 0.5f);
    };
    const float upper = lip(top, mouth, 0.4f, -0.25f - 0.25f * w2);
    const float lower = lip(mouth, bottom, 0.45f, -0.35f - 0.3f * w2);
    return smin(upper, lower, 0.35f);
}

// ---- The eyes: a ball in each socket, the lids a layer over it that leaves an almond-shaped
// opening. The lids are a height over the ball (no overhang), rising smoothly from the
// opening's edge, so the mesh's 0.35 cm cells can hold them: thin, sharp lids would come out
// of the grid as torn slivers.
const Vec3f kEyeCentre(3.15f, 1.3f, 6.8f);  // right eye mirrored; pupils 6.3 cm apart
constexpr float kEyeRadius = 1.15f;

float eye_and_lids(const Vec3f& m) {
    const Vec3f q = m - kEyeCentre;
    const float r = q.norm();
    // The opening: an almond 2.8 cm wide and 1.05 cm tall whose edges are arcs through the
    // corners (the outer corner a little higher).
    const float x = q.x(), y = q.y() - 0.06f * q.x();
    constexpr float kHalfWidth = 1.4f, kTop = 0.5f, kBottom = 0.55f;
    auto arc = [](float half_width, float height) {  // radius of the arc through the corners
        return (half_width * half_width + height * height) / (2.f * height);
    };
    const float ru = arc(kHalfWidth, kTop), rl = arc(kHalfWidth, kBottom);
    // > 0 inside the almond's upper arc (under the upper lid's edge), likewise the lower.
    const float under_upper = ru - std::hypot(x, y - (kTop - ru));
    const float over_lower = rl - std::hypot(x, y + (kBottom - rl));
    // The upper lid stands 0.32 cm off the ball, the lower 0.22 cm, each reached 0.4 cm from
    // the edge; a fold runs along the upper lid 0.7 cm above its edge.
    const float upper = 0.32f * smoothstep(-0.05f, 0.4f, -under_upper) -
                        0.07f * std::exp(-(under_upper + 0.75f) * (under_upper + 0.75f) / 0.06f);
    const float lower = 0.22f * smoothstep(-0.05f, 0.4f, -over_lower);
    return r - kEyeRadius - std::max(upper, lower);
}

// ---- The whole figure, in head space: origin between the ears at ear-canal height, Y up, +Z
// forward, cm. Each part is blended in only where it can change the result: a part whose
// bounding sphere is further than the blend width from the current value is skipped, which
// keeps the field cheap away from its own parts (the union is exact there, smin(a, b, k) = a for
// b >= a + k).
struct Blend {
    float d = 1e3f;
    // Blends part() (bounded by the sphere (c, radius)) into d with width k, or removes it.
    template <typename Part>
    void add(const Vec3f& q, const Vec3f& c, float radius, float k, Part&& part) {
        const float reach = radius + d + k + 0.5f;
        if (d > 1e2f || (q - c).squaredNorm() < reach * reach) d = smin(d, part(), k);
    }
    template <typename Part>
    void carve(const Vec3f& q, const Vec3f& c, float radius, float k, Part&& part) {
        const float reach = radius + k - d + 0.5f;
        if (reach > 0.f && (q - c).squaredNorm() < reach * reach) d = smax(d, -part(), k);
    }
    void add_ellipsoid(const Vec3f& q, const Vec3f& c, const Vec3f& r, float k) {
        add(q, c, r.maxCoeff(), k, [&] { return ellipsoid(q, c, r); });
    }
    void carve_ellipsoid(const Vec3f& q, const Vec3f& c, const Vec3f& r, float k) {
        carve(q, c, r.maxCoeff(), k, [&] { return ellipsoid(q, c, r); });
    }
    void add_capsule(const Vec3f& q, const Vec3f& a, const Vec3f& b, float ra, float rb, float k) {
        add(q, 0.5f * (a + b), 0.5f * (b - a).norm() + std::max(ra, rb), k,
            [&] { return cone_capsule(q, a, b, ra, rb); });
    }
};

// The figure ends in a flat cut through the top of the hips, as a display mannequin does.
constexpr float kBodyBottom = -62.f;  // cm

// The torso below the neck, to the waist: the shoulder girdle (collarbones, shoulder blades,
// trapezius, deltoids), the rib cage with chest and back muscles, the waist and the top of the
// hips, and the arms hanging beside it, the upper arms to the elbows and the forearms down to
// the cut, a hand's breadth from the waist. Proportions of an adult whose head (chin to
// crown, 22.8 cm) is an eighth of their height: the nipples two heads below the crown, the
// waist and the elbows three.
void add_torso(Blend& b, const Vec3f& p, const Vec3f& m) {
    // The rib cage, narrowing to the waist, and the top of the hips.
    b.add_ellipsoid(p, {0.f, -33.5f, -0.8f}, {13.6f, 15.5f, 9.8f}, 5.f);
    b.add_ellipsoid(p, {0.f, -51.5f, -0.2f}, {12.4f, 10.5f, 9.0f}, 6.f);
    b.add_ellipsoid(p, {0.f, -64.f, -0.8f}, {14.6f, 8.5f, 10.2f}, 6.f);
    // The shoulder girdle, chest and back muscles.
    b.add_ellipsoid(p, {0.f, -23.5f, -1.3f}, {17.f, 4.8f, 7.0f}, 4.f);
    b.add_ellipsoid(m, {5.8f, -27.f, 4.6f}, {6.2f, 4.2f, 4.6f}, 3.f);
    b.add_ellipsoid(m, {6.5f, -27.5f, -5.6f}, {6.0f, 7.0f, 4.5f}, 3.f);
    // Shoulders: the trapezius sloping from the neck to the point of the shoulder, the deltoid
    // rounding it; the collarbones.
    b.add_capsule(m, {2.5f, -15.5f, -3.2f}, {16.f, -21.6f, -2.2f}, 3.4f, 2.6f, 3.f);
    b.add_ellipsoid(m, {16.4f, -24.4f, -1.2f}, {4.0f, 4.6f, 4.6f}, 4.f);
    b.add_capsule(m, {1.7f, -20.4f, 4.3f}, {15.2f, -21.4f, -0.6f}, 0.75f, 0.75f, 1.5f);
    // The arms: the upper arm from under the deltoid to the elbow, out a little from the
    // waist, then the forearm turning forward.
    b.add_capsule(m, {16.9f, -25.f, -1.3f}, {18.4f, -51.f, -2.4f}, 4.1f, 3.2f, 2.5f);
    b.add_capsule(m, {18.4f, -51.f, -2.4f}, {18.f, -66.f, 2.2f}, 3.1f, 2.7f, 1.2f);
    b.d = smax(b.d, kBodyBottom - p.y(), 1.2f);
}

float head_field(const Vec3f& p) {
    const Vec3f m(std::abs(p.x()), p.y(), p.z());  // mirror: the head is symmetric in x
    Blend b;

    // -- The big forms first, so that the small ones are skipped wherever they cannot matter.
    // Cranium and the back of the skull.
    b.add(p, {0.f, 3.f, -0.7f}, 10.f, 2.f, [&] { return cranium(p); });
    b.add_ellipsoid(p, {0.f, 1.8f, -4.6f}, {6.3f, 6.8f, 4.8f}, 2.f);

    // -- Face: the mass of the face from the brow to the jaw, full in the cheeks, cut below by
    // the plane through the angles of the jaw and the bottom of the chin, so the jaw line
    // shows above the neck.
    b.add(p, {0.f, -2.2f, 2.8f}, 7.3f, 2.f, [&] {
        const float under_jaw = -(0.899f * (p.y() + 10.1f) + 0.437f * (p.z() - 7.f));
        return smax(ellipsoid(p, {0.f, -2.2f, 2.8f}, {6.3f, 7.3f, 6.2f}), under_jaw, 1.f);
    });
    // -- Neck: an oval column leaning forward, the sternocleidomastoid muscles running from
    // behind the ears to the top of the breastbone.
    b.add(p, {0.f, -12.f, -1.6f}, 13.f, 2.5f, [&] {
        const Vec3f s(p.x(), p.y(), p.z() * 0.92f);
        return cone_capsule(s, {0.f, -19.f, -2.8f * 0.92f}, {0.f, -5.f, -0.6f * 0.92f}, 5.6f, 4.9f);
    });
    b.add_capsule(m, {4.9f, -3.4f, -2.6f}, {1.5f, -19.0f, 4.0f}, 1.2f, 0.9f, 1.6f);

    add_torso(b, p, m);

    // -- The forms of the face: cheekbones, the jaw (ramus, body, chin), the cheeks filling the
    // hollow between them, the muzzle around the mouth, brow ridges.
    b.add_ellipsoid(m, {4.7f, -0.3f, 5.2f}, {1.9f, 1.3f, 2.0f}, 1.5f);
    b.add_capsule(m, {4.9f, -6.8f, -0.3f}, {5.4f, -2.0f, -0.6f}, 0.95f, 0.95f, 1.5f);
    b.add_capsule(m, {4.9f, -6.9f, -0.3f}, {1.9f, -9.1f, 6.4f}, 0.9f, 0.85f, 1.8f);
    b.add_ellipsoid(p, {0.f, -8.3f, 7.6f}, {2.2f, 1.6f, 1.5f}, 1.5f);
    b.add_ellipsoid(m, {4.2f, -3.6f, 3.6f}, {1.9f, 3.2f, 3.2f}, 2.2f);
    b.add_ellipsoid(p, {0.f, -4.7f, 5.5f}, {3.6f, 2.6f, 3.5f}, 1.5f);
    b.add_ellipsoid(m, {2.6f, 3.3f, 7.7f}, {2.4f, 0.9f, 1.4f}, 1.2f);

    // -- Eye sockets, then the eyes in them.
    b.carve_ellipsoid(m, {3.2f, 1.6f, 8.3f}, {1.6f, 1.0f, 1.0f}, 1.2f);
    b.add(m, kEyeCentre, kEyeRadius + 0.7f, 0.3f, [&] { return eye_and_lids(m); });

    // -- Nose: bridge from the root between the eyes to the tip, its sides, the wings of the
    // nostrils and the column under the tip.
    b.add_capsule(p, {0.f, 2.3f, 8.35f}, {0.f, -1.35f, 10.5f}, 0.45f, 0.7f, 0.8f);
    b.add_ellipsoid(p, {0.f, -0.9f, 9.3f}, {1.2f, 1.9f, 1.1f}, 0.8f);
    b.add_ellipsoid(p, {0.f, -1.65f, 10.55f}, {0.8f, 0.75f, 0.85f}, 0.6f);
    b.add_ellipsoid(m, {1.15f, -2.1f, 9.5f}, {0.6f, 0.55f, 0.8f}, 0.6f);
    b.add_capsule(p, {0.f, -2.1f, 10.6f}, {0.f, -2.75f, 9.65f}, 0.35f, 0.35f, 0.4f);

    // -- Mouth.
    b.add(p, kMouthCentre, 3.4f, 0.35f, [&] { return lips(p); });

    // -- Ears.
    b.add(m, kEarCentre, kEarRadius, 0.9f, [&] { return ear(m); });
    return b.d;
}

template <typename Field>
Vec3f field_gradient(const Field& field, const Vec3f& p, float f0) {
    constexpr float h = 0.02f;
    return Vec3f(field(p + Vec3f(h, 0, 0)) - f0, field(p + Vec3f(0, h, 0)) - f0,
                 field(p + Vec3f(0, 0, h)) - f0) /
           h;
}

// ---- Marching tetrahedra on the Freudenthal (Kuhn) split of a rectilinear grid: every cell is
// cut into six tetrahedra along its main diagonal, consistently across neighbours, so the
// piecewise linear zero set is a closed 2-manifold whenever no node value is exactly zero (no
// table ambiguities, unlike marching cubes); where the surface leaves the grid it is cut open
// along the grid's side.
//
// Two grids: a fine one over the head down to the neck, a coarse one over the bust up to just
// below it, so the small forms of the face and ears get a fine cell without spending one on the
// chest. The neck leaves each grid through one flat side, and a strip of triangles joins the two
// rims (join_rims).

constexpr float kHeadCell = 0.35f, kBodyCell = 0.8f;     // cm
constexpr float kSeamHead = -11.2f, kSeamBody = -11.8f;  // y of the rims, under the chin

struct Grid {
    std::vector<float> x, y, z;  // node coordinates, cm; x symmetric about 0
    Vec3f node(int i, int j, int k) const { return {x[i], y[j], z[k]}; }
};

// Nodes from lo by step until past hi.
std::vector<float> axis(float lo, float hi, float step) {
    std::vector<float> a;
    for (int i = 0; lo + step * (i - 1) < hi; ++i)
        a.push_back(lo + step * i);
    return a;
}
// Nodes symmetric about 0 (x_i = -x_{n-1-i} exactly), covering [-half, half].
std::vector<float> symmetric_axis(float half, float step) {
    const int n = static_cast<int>(std::ceil(half / step));
    std::vector<float> a;
    for (int i = -n; i <= n; ++i)
        a.push_back(step * i);
    return a;
}

Grid head_grid() {
    Grid g;
    g.x = symmetric_axis(10.6f, kHeadCell);
    g.y = axis(kSeamHead, 13.4f, kHeadCell);  // the first layer is the rim's plane
    g.z = axis(-11.6f, 12.4f, kHeadCell);
    return g;
}
Grid body_grid() {
    Grid g;
    g.x = symmetric_axis(23.5f, kBodyCell);
    g.y = axis(kBodyBottom - 1.5f, kSeamBody, kBodyCell);
    // The last layer is the rim's plane: shift the axis so it ends exactly there.
    const float shift = kSeamBody - g.y.back();
    for (float& y : g.y)
        y += shift;
    g.z = axis(-13.5f, 12.5f, kBodyCell);
    return g;
}

// Corner c of a cube: bit 0 = +x, bit 1 = +y, bit 2 = +z. Tetrahedra 0-a-b-7.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

// The field at every node, index (k·ny + j)·nx + i. Only the half x >= 0 is evaluated (the
// field is symmetric, so is the grid) and the other mirrored. Blocks of kBlock³ cells whose
// centre is far from the surface (by a safe bound on the field's slope) give their nodes the
// centre's value, which has the right sign and never makes a crossing; the other nodes are
// evaluated one by one.
template <typename Field>
std::vector<float> node_values(const Grid& g, const Field& field) {
    const int nx = static_cast<int>(g.x.size()), ny = static_cast<int>(g.y.size()),
              nz = static_cast<int>(g.z.size());
    const int i0 = nx / 2;  // the first node with x >= 0
    const int hx = nx - i0;
    constexpr int kBlock = 4;
    auto block_count = [](int n) { return (n - 2) / kBlock + 1; };
    const int bx = block_count(hx), by = block_count(ny), bz = block_count(nz);
    std::vector<float> block_value(static_cast<size_t>(bx) * by * bz);
    std::vector<char> block_far(block_value.size());
    parallel_for(static_cast<size_t>(bz), [&](size_t kb) {
        for (int jb = 0; jb < by; ++jb)
            for (int ib = 0; ib < bx; ++ib) {
                const int k0 = static_cast<int>(kb) * kBlock, j0 = jb * kBlock, ia = ib * kBlock;
                const Vec3f lo = g.node(i0 + ia, j0, k0);
                const Vec3f hi =
                    g.node(i0 + std::min(ia + kBlock, hx - 1), std::min(j0 + kBlock, ny - 1),
                           std::min(k0 + kBlock, nz - 1));
                const float f = field(0.5f * (lo + hi));
                const size_t b = (kb * by + jb) * bx + ib;
                block_value[b] = f;
                // The field's slope stays under ~1.5 (tapers and warps stretch distances); the
                // margin covers the parts head_field skips.
                block_far[b] = std::abs(f) > 0.75f * (hi - lo).norm() + 0.6f;
            }
    });
    // The blocks a node touches along an axis: one, or two on a block boundary.
    auto blocks = [](int i, int count) {
        const int b = std::min(i / kBlock, count - 1);
        return std::pair<int, int>(i % kBlock == 0 && i > 0 ? i / kBlock - 1 : b, b);
    };
    std::vector<float> value(static_cast<size_t>(nx) * ny * nz);
    parallel_for(static_cast<size_t>(nz), [&](size_t k) {
        const auto [kb0, kb1] = blocks(static_cast<int>(k), bz);
        for (int j = 0; j < ny; ++j) {
            const auto [jb0, jb1] = blocks(j, by);
            float* row = &value[(k * ny + j) * nx];
            for (int ih = 0; ih < hx; ++ih) {
                const auto [ib0, ib1] = blocks(ih, bx);
                bool far = true;
                float f = 0.f;
                for (int kb = kb0; kb <= kb1 && far; ++kb)
                    for (int jb = jb0; jb <= jb1 && far; ++jb)
                        for (int ib = ib0; ib <= ib1 && far; ++ib) {
                            const size_t b = (static_cast<size_t>(kb) * by + jb) * bx + ib;
                            far = block_far[b];
                            f = block_value[b];
                        }
                if (!far) f = field(g.node(i0 + ih, j, static_cast<int>(k)));
                if (f == 0.f) f = 1e-6f;  // keep the zero set off the nodes
                row[i0 + ih] = f;
                row[nx - 1 - (i0 + ih)] = f;
            }
        }
    });
    return value;
}

// The zero set of the field over grid g, open where it leaves the grid.
template <typename Field>
Mesh march(const Grid& g, const Field& field) {
    const int nx = static_cast<int>(g.x.size()), ny = static_cast<int>(g.y.size()),
              nz = static_cast<int>(g.z.size());
    const size_t nodes = static_cast<size_t>(nx) * ny * nz;
    const std::vector<float> value = node_values(g, field);
    auto position = [&](size_t n) {
        return g.node(static_cast<int>(n % nx), static_cast<int>((n / nx) % ny),
                      static_cast<int>(n / (static_cast<size_t>(nx) * ny)));
    };

    Mesh mesh;
    std::vector<int32_t> edge_vertex(nodes * 7, -1);  // (node, direction bits - 1) -> vertex
    const size_t corner_offset[8] = {0,
                                     1,
                                     static_cast<size_t>(nx),
                                     static_cast<size_t>(nx) + 1,
                                     static_cast<size_t>(nx) * ny,
                                     static_cast<size_t>(nx) * ny + 1,
                                     static_cast<size_t>(nx) * ny + nx,
                                     static_cast<size_t>(nx) * ny + nx + 1};
    auto edge_point = [&](size_t base, int cu, int cv) -> int32_t {
        // cu ⊂ cv bitwise, so the edge runs from node base+off[cu] in direction cv ^ cu.
        const size_t a = base + corner_offset[cu], b = base + corner_offset[cv];
        int32_t& slot = edge_vertex[a * 7 + (cv ^ cu) - 1];
        if (slot < 0) {
            const float fa = value[a], fb = value[b];
            const float t = fa / (fa - fb);
            slot = static_cast<int32_t>(mesh.vertices.size());
            mesh.vertices.push_back(position(a) + t * (position(b) - position(a)));
        }
        return slot;
    };
    auto emit = [&](int32_t a, int32_t b, int32_t c, const Vec3f& outward) {
        const Vec3f n =
            (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
        if (n.dot(outward) >= 0.f)
            mesh.faces.emplace_back(a, b, c);
        else
            mesh.faces.emplace_back(a, c, b);
    };

    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i) {
                const size_t base = (static_cast<size_t>(k) * ny + j) * nx + i;
                float v[8];
                int inside = 0;
                for (int c = 0; c < 8; ++c) {
                    v[c] = value[base + corner_offset[c]];
                    inside += v[c] < 0.f;
                }
                if (inside == 0 || inside == 8) continue;
                const Vec3f lo = g.node(i, j, k), size = g.node(i + 1, j + 1, k + 1) - lo;
                auto corner_pos = [&](int c) {
                    return Vec3f(lo + Vec3f(c & 1, (c >> 1) & 1, (c >> 2) & 1).cwiseProduct(size));
                };
                for (const auto& tet : kTets) {
                    int in[4], out[4], ni = 0, no = 0;
                    for (int c : tet)
                        (v[c] < 0.f ? in[ni++] : out[no++]) = c;
                    if (ni == 0 || ni == 4) continue;
                    Vec3f cin = Vec3f::Zero(), cout = Vec3f::Zero();
                    for (int q = 0; q < ni; ++q)
                        cin += corner_pos(in[q]) / ni;
                    for (int q = 0; q < no; ++q)
                        cout += corner_pos(out[q]) / no;
                    const Vec3f outward = cout - cin;
                    auto ep = [&](int c0, int c1) {
                        return c0 < c1 ? edge_point(base, c0, c1) : edge_point(base, c1, c0);
                    };
                    if (ni == 1 || no == 1) {
                        const int apex = ni == 1 ? in[0] : out[0];
                        const int* rest = ni == 1 ? out : in;
                        emit(ep(apex, rest[0]), ep(apex, rest[1]), ep(apex, rest[2]), outward);
                    } else {  // a quad across the tetrahedron: in0-out0, in0-out1, in1-out1,
                              // in1-out0
                        const int32_t q0 = ep(in[0], out[0]), q1 = ep(in[0], out[1]),
                                      q2 = ep(in[1], out[1]), q3 = ep(in[1], out[0]);
                        emit(q0, q1, q2, outward);
                        emit(q0, q2, q3, outward);
                    }
                }
            }
    return mesh;
}

// The rim of an open mesh on the plane y = y0 (its vertices there lie on it exactly), as the
// vertex loop that follows the faces' boundary edges. Empty unless it is a single loop.
std::vector<int32_t> rim(const Mesh& mesh, float y0) {
    std::vector<int32_t> after(mesh.vertices.size(), -1);
    size_t edges = 0;
    for (const Vec3i& t : mesh.faces)
        for (int e = 0; e < 3; ++e)
            if (mesh.vertices[t[e]].y() == y0 && mesh.vertices[t[(e + 1) % 3]].y() == y0) {
                after[t[e]] = t[(e + 1) % 3];
                ++edges;
            }
    std::vector<int32_t> loop;
    int32_t start = -1;
    for (size_t v = 0; v < after.size() && start < 0; ++v)
        if (after[v] >= 0) start = static_cast<int32_t>(v);
    for (int32_t v = start; v >= 0 && loop.size() <= edges;) {
        loop.push_back(v);
        v = after[v];
        if (v == start) break;
    }
    if (loop.size() != edges) loop.clear();
    return loop;
}

// Appends `lower` to `upper` and joins their rims (upper's at y = kSeamHead, lower's at
// kSeamBody, both around the neck) with a strip of triangles, in order of the angle around the
// neck's axis, oriented to match both. Each rim must be one loop around the neck, and the two
// must run opposite ways, as they do when only the neck crosses the seam (the built-in head's
// tests check the result is closed and of genus 0); otherwise the rims stay open.
void join_rims(Mesh& upper, const Mesh& lower) {
    std::vector<int32_t> a = rim(upper, kSeamHead), b = rim(lower, kSeamBody);
    if (a.size() < 3 || b.size() < 3) return;
    const int32_t offset = static_cast<int32_t>(upper.vertices.size());
    upper.vertices.insert(upper.vertices.end(), lower.vertices.begin(), lower.vertices.end());
    for (const Vec3i& t : lower.faces)
        upper.faces.push_back(t + Vec3i::Constant(offset));
    for (int32_t& v : b)
        v += offset;

    const Vec3f axis(0.f, 0.f, -1.5f);
    auto angle = [&](int32_t v) {
        const Vec3f& p = upper.vertices[v];
        return std::atan2(p.x() - axis.x(), p.z() - axis.z());
    };
    // Each rim in order of increasing angle from its lowest, and whether its boundary edges run
    // that way.
    auto order = [&](std::vector<int32_t>& loop) {
        double turn = 0;
        for (size_t i = 0; i < loop.size(); ++i) {
            float d = angle(loop[(i + 1) % loop.size()]) - angle(loop[i]);
            d -= 2.f * kPi * std::round(d / (2.f * kPi));
            turn += d;
        }
        const bool forward = turn > 0;
        if (!forward) std::reverse(loop.begin(), loop.end());
        size_t lowest = 0;
        for (size_t i = 1; i < loop.size(); ++i)
            if (angle(loop[i]) < angle(loop[lowest])) lowest = i;
        std::rotate(loop.begin(), loop.begin() + lowest, loop.end());
        return forward;
    };
    const bool a_forward = order(a), b_forward = order(b);
    if (a_forward == b_forward) return;
    const size_t na = a.size(), nb = b.size();
    auto unwrapped = [&](const std::vector<int32_t>& loop, size_t i) {
        float t = angle(loop[i % loop.size()]);
        if (i > 0 && t < angle(loop[0])) t += 2.f * kPi;
        return i >= loop.size() ? angle(loop[0]) + 2.f * kPi : t;
    };
    size_t i = 0, j = 0;
    while (i < na || j < nb) {
        const bool advance_a = j == nb || (i < na && unwrapped(a, i + 1) < unwrapped(b, j + 1));
        if (advance_a) {
            const int32_t p = a[i % na], q = a[(i + 1) % na], r = b[j % nb];
            upper.faces.push_back(a_forward ? Vec3i(q, p, r) : Vec3i(p, q, r));
            ++i;
        } else {
            const int32_t p = b[j % nb], q = b[(j + 1) % nb], r = a[i % na];
            upper.faces.push_back(b_forward ? Vec3i(q, p, r) : Vec3i(p, q, r));
            ++j;
        }
    }
}

Mesh polygonize() {
    Mesh mesh = march(head_grid(), head_field);
    join_rims(mesh, march(body_grid(), head_field));
    return mesh;
}

// Collapses edges shorter than max_length(midpoint), roughly shortest first, each into its
// midpoint, wherever that keeps the mesh a closed, oriented 2-manifold of the same genus, the
// surface nearly flat there and no triangle turned over: the endpoints must share exactly the
// two neighbours opposite the edge (the link condition) and neither of those may be left with
// fewer than three triangles. Marching tetrahedra leaves many tiny edges where the surface
// passes close to a grid node; removing them evens out the triangles and saves most of them.
// Deterministic: `passes` passes over the faces in memory order, each with a longer limit.
constexpr int kMaxValence = 16;         // triangles around a vertex; more are never made
constexpr float kFlatCos = 0.85f;       // a fan within ~30° of its mean normal is flat
constexpr float kFlatMinArea = 0.004f;  // cm², twice the area of a triangle whose normal counts
template <typename MaxLength>
void collapse_short_edges(Mesh& mesh, MaxLength&& max_length, int passes) {
    const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
    // The triangles around each vertex, kMaxValence slots a vertex; a vertex with more (rare in
    // marching tetrahedra output) is never collapsed.
    std::vector<int32_t> ring_faces(nv * kMaxValence), valence(nv, 0);
    std::vector<char> face_dead(nf, 0), vertex_dead(nv, 0), frozen(nv, 0);
    for (size_t f = 0; f < nf; ++f)
        for (int c = 0; c < 3; ++c) {
            const int v = mesh.faces[f][c];
            if (valence[v] < kMaxValence)
                ring_faces[v * kMaxValence + valence[v]] = static_cast<int32_t>(f);
            else
                frozen[v] = 1;
            ++valence[v];
        }
    auto contains = [](const Vec3i& t, int w) { return t[0] == w || t[1] == w || t[2] == w; };
    auto remove_face = [&](int w, int32_t f) {
        int32_t* r = &ring_faces[w * kMaxValence];
        for (int i = 0; i < valence[w]; ++i)
            if (r[i] == f) {
                r[i] = r[--valence[w]];
                return;
            }
    };

    auto try_collapse = [&](int u, int v) {
        if (frozen[u] || frozen[v]) return false;
        const int nu = valence[u], nvv = valence[v];
        if (nu + nvv - 4 > kMaxValence) return false;
        const int32_t* fu = &ring_faces[u * kMaxValence];
        const int32_t* fv = &ring_faces[v * kMaxValence];
        // The faces on the edge, their opposite corners, and the link condition.
        int shared = 0, opposite[2] = {-1, -1};
        int32_t shared_face[2] = {-1, -1};
        for (int i = 0; i < nu; ++i) {
            const Vec3i& t = mesh.faces[fu[i]];
            if (!contains(t, v)) continue;
            if (shared == 2) return false;
            for (int c = 0; c < 3; ++c)
                if (t[c] != u && t[c] != v) opposite[shared] = t[c];
            shared_face[shared++] = fu[i];
        }
        if (shared != 2 || opposite[0] == opposite[1]) return false;
        if (valence[opposite[0]] <= 3 || valence[opposite[1]] <= 3) return false;
        // Neighbours, each once: the corner after the vertex in each of its faces.
        auto after = [&](int w, int32_t f) {
            const Vec3i& t = mesh.faces[f];
            return t[0] == w ? t[1] : (t[1] == w ? t[2] : t[0]);
        };
        int32_t rv[kMaxValence];
        for (int j = 0; j < nvv; ++j)
            rv[j] = after(v, fv[j]);
        int common = 0;
        for (int i = 0; i < nu; ++i) {
            const int w = after(u, fu[i]);
            for (int j = 0; j < nvv; ++j)
                common += w == rv[j];
        }
        if (common != 2) return false;

        // Only where the surface is nearly flat (the fan's triangles within ~30° of their mean
        // normal; slivers too small to have a reliable normal do not count), so the detail of
        // lips, nostrils, lids and ears keeps its triangles; and no triangle may turn over.
        const Vec3f p = 0.5f * (mesh.vertices[u] + mesh.vertices[v]);
        std::array<Vec3f, 2 * kMaxValence> before, after_move;
        Vec3f mean = Vec3f::Zero();
        int n = 0;
        auto gather = [&](const int32_t* fw, int count) {
            for (int i = 0; i < count; ++i) {
                const Vec3i& t = mesh.faces[fw[i]];
                Vec3f c[3];
                for (int k = 0; k < 3; ++k)
                    c[k] = mesh.vertices[t[k]];
                before[n] = (c[1] - c[0]).cross(c[2] - c[0]);
                mean += before[n];
                if (contains(t, u) && contains(t, v)) {
                    after_move[n] = before[n];  // removed: no constraint
                    ++n;
                    continue;
                }
                for (int k = 0; k < 3; ++k)
                    if (t[k] == u || t[k] == v) c[k] = p;
                after_move[n++] = (c[1] - c[0]).cross(c[2] - c[0]);
            }
        };
        gather(fu, nu);
        gather(fv, nvv);
        // Compared squared, without roots: x·y >= c |x| |y| as x·y >= 0 and (x·y)² >= c² |x|² |y|².
        const float mean2 = mean.squaredNorm();
        for (int i = 0; i < n; ++i) {
            const float b2 = before[i].squaredNorm(), a2 = after_move[i].squaredNorm();
            const float bm = before[i].dot(mean), ab = after_move[i].dot(before[i]);
            if (b2 > kFlatMinArea * kFlatMinArea &&
                (bm < 0.f || bm * bm < kFlatCos * kFlatCos * b2 * mean2))
                return false;
            // Nor turn away from the fan's mean normal (an estimate of the surface's), so that
            // collapses in a row cannot fold the surface a little at a time.
            const float am = after_move[i].dot(mean);
            if (a2 < 1e-10f || ab < 0.f || ab * ab < 0.25f * a2 * b2 || am < 0.f ||
                am * am < 0.5f * a2 * mean2)
                return false;
        }

        // u merges into v: the two faces on the edge go, u's others move to v.
        for (int s = 0; s < 2; ++s) {
            face_dead[shared_face[s]] = 1;
            remove_face(opposite[s], shared_face[s]);
        }
        int32_t merged[kMaxValence];
        int count = 0;
        for (int j = 0; j < nvv; ++j)
            if (fv[j] != shared_face[0] && fv[j] != shared_face[1]) merged[count++] = fv[j];
        for (int i = 0; i < nu; ++i) {
            const int32_t f = fu[i];
            if (f == shared_face[0] || f == shared_face[1]) continue;
            Vec3i& t = mesh.faces[f];
            for (int c = 0; c < 3; ++c)
                if (t[c] == u) t[c] = v;
            merged[count++] = f;
        }
        std::copy(merged, merged + count, &ring_faces[v * kMaxValence]);
        valence[v] = count;
        valence[u] = 0;
        vertex_dead[u] = 1;
        mesh.vertices[v] = p;
        return true;
    };

    // The halves x < 0 and x > 0 in parallel, then what is left along the midline. A face is
    // on one side if its corners are (collapses never move a vertex across x = 0, nor a face
    // off its side); a collapse within a half touches only faces of that side, so the halves
    // share nothing, and the result does not depend on the thread count.
    std::vector<int8_t> side(nf);
    std::vector<char> border(nv, 0);  // has a face on both sides
    for (size_t f = 0; f < nf; ++f) {
        const Vec3i& t = mesh.faces[f];
        int neg = 0, pos = 0;
        for (int c = 0; c < 3; ++c)
            (mesh.vertices[t[c]].x() < 0.f ? neg : pos) += 1;
        side[f] = pos == 0 ? -1 : (neg == 0 ? 1 : 0);
        if (side[f] == 0)
            for (int c = 0; c < 3; ++c)
                border[t[c]] = 1;
    }
    // The side of each vertex whose faces are all on it (0 for the others); it never changes:
    // only a collapse within a side gives a vertex more faces.
    std::vector<int8_t> vertex_side(nv, 0);
    for (size_t v = 0; v < nv; ++v)
        if (!border[v] && valence[v] > 0) vertex_side[v] = side[ring_faces[v * kMaxValence]];
    auto sweep = [&](float fraction, int8_t s) {
        for (size_t f = 0; f < nf; ++f) {
            if (s != 0 && side[f] != s) continue;
            for (int e = 0; e < 3 && !face_dead[f]; ++e) {
                const int a = mesh.faces[f][e], b = mesh.faces[f][(e + 1) % 3];
                if (a > b) continue;  // each edge once: the neighbour has it as (b, a)
                if (s == 0 ? !(border[a] || border[b])
                           : (vertex_side[a] != s || vertex_side[b] != s))
                    continue;
                const Vec3f pa = mesh.vertices[a], pb = mesh.vertices[b];
                const float limit = fraction * max_length(0.5f * (pa + pb));
                if ((pb - pa).squaredNorm() >= limit * limit) continue;
                try_collapse(a, b);
            }
        }
    };
    for (int pass = 1; pass <= passes; ++pass) {
        const float fraction = static_cast<float>(pass) / passes;
        parallel_for(2, [&](size_t h) { sweep(fraction, h == 0 ? -1 : 1); });
        sweep(fraction, 0);
    }

    // Compact.
    std::vector<int32_t> index(nv, -1);
    std::vector<Vec3f> vertices;
    for (size_t v = 0; v < nv; ++v)
        if (!vertex_dead[v]) {
            index[v] = static_cast<int32_t>(vertices.size());
            vertices.push_back(mesh.vertices[v]);
        }
    std::vector<Vec3i> faces;
    for (size_t f = 0; f < nf; ++f)
        if (!face_dead[f]) {
            const Vec3i& t = mesh.faces[f];
            faces.emplace_back(index[t[0]], index[t[1]], index[t[2]]);
        }
    mesh.vertices.swap(vertices);
    mesh.faces.swap(faces);
}

// Tangential Laplacian smoothing with projection onto the implicit surface: each vertex moves
// halfway to its neighbours' centroid within its tangent plane (the field's gradient gives the
// normal) and a Newton step takes it onto the zero set. Evens out the triangles of marching
// tetrahedra without changing the connectivity; moving only along the surface keeps vertices
// from being pulled across creases (the lips, the lids) and projected onto the wrong side.
template <typename Field, typename Moves>
void relax(Mesh& mesh, const Field& field, int iterations, Moves&& moves) {
    const size_t nv = mesh.vertices.size();
    // Vertex neighbours in CSR form from the (directed) triangle edges; each undirected edge
    // appears once per direction in a closed manifold, so neighbours are listed once.
    const VertexLists neighbours = vertex_edges(mesh);
    const std::vector<uint32_t>& start = neighbours.first;
    const std::vector<uint32_t>& adj = neighbours.items;

    // Which vertices move is decided once, from where they start. A vertex that stays and has
    // no neighbour that moves only sits in triangles that stay as they are: it needs no field.
    std::vector<uint8_t> moving(nv), touched(nv);
    parallel_for(
        nv, [&](size_t v) { moving[v] = moves(mesh.vertices[v]) ? 1 : 0; }, 1024);
    parallel_for(
        nv,
        [&](size_t v) {
            bool t = moving[v] != 0;
            for (uint32_t a = start[v]; a < start[v + 1] && !t; ++a)
                t = moving[adj[a]] != 0;
            touched[v] = t ? 1 : 0;
        },
        1024);

    // The gradient is taken once: the later steps are short, and it changes little over them.
    std::vector<Vec3f> next(nv), gradient(nv, Vec3f::Zero()), normal(nv, Vec3f::Zero());
    for (int it = 0; it < iterations; ++it) {
        parallel_for(
            nv,
            [&](size_t v) {
                const Vec3f x = mesh.vertices[v];
                if (!touched[v]) {
                    next[v] = x;
                    return;
                }
                Vec3f c = Vec3f::Zero();
                for (uint32_t a = start[v]; a < start[v + 1]; ++a)
                    c += mesh.vertices[adj[a]];
                const uint32_t n = start[v + 1] - start[v];
                const float f = field(x);
                if (it == 0) {
                    gradient[v] = field_gradient(field, x, f);
                    const float len = gradient[v].norm();
                    normal[v] = len > 0.f ? Vec3f(gradient[v] / len) : Vec3f::Zero();
                }
                const Vec3f& g = gradient[v];
                const float g2 = g.squaredNorm();
                if (n == 0 || g2 < 1e-8f || !moving[v]) {
                    next[v] = x;
                    return;
                }
                const Vec3f lap = c / static_cast<float>(n) - x;
                next[v] = x + 0.5f * (lap - (lap.dot(g) / g2) * g) - (f / g2) * g;
            },
            256);
        // Where a triangle would turn over, against its old self or against the surface (the
        // field's gradient at its corners) — neighbours moving at once can fold a thin one —
        // its corners stay where they were, until none does.
        for (int round = 0; round < 8; ++round) {
            size_t kept = 0;
            for (const Vec3i& t : mesh.faces) {
                const Vec3f before = (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                                         .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
                const Vec3f after = (next[t[1]] - next[t[0]]).cross(next[t[2]] - next[t[0]]);
                const Vec3f surface = normal[t[0]] + normal[t[1]] + normal[t[2]];
                if (after.dot(before) > 0.f && after.dot(surface) > 0.f) continue;
                for (int k = 0; k < 3; ++k)
                    if (next[t[k]] != mesh.vertices[t[k]]) {
                        next[t[k]] = mesh.vertices[t[k]];
                        ++kept;
                    }
            }
            if (kept == 0) break;
        }
        mesh.vertices.swap(next);
    }
}

// Splits every edge longer than max_length(midpoint) at its midpoint, pulled onto the
// implicit surface by Newton steps along the field's gradient, and each triangle into two,
// three or four to match its split edges (conforming: a split edge is split in both of its
// triangles), `passes` times. Marching on a 0.35 cm grid cannot hold forms a few cells across
// (the lids, the nostrils); the refined patch can, and only it pays for the extra triangles.
// Keeps the mesh closed, oriented and of the same genus. Deterministic: edges are numbered in
// face order.
template <typename Field, typename MaxLength>
void refine(Mesh& mesh, const Field& field, MaxLength&& max_length, int passes) {
    for (int pass = 0; pass < passes; ++pass) {
        const size_t nf = mesh.faces.size();
        // The midpoint vertex of each split edge, keyed by its endpoints (lower index first).
        std::vector<std::array<int32_t, 3>> splits;  // a, b, new vertex
        auto find = [&](int32_t a, int32_t b) {
            if (a > b) std::swap(a, b);
            const auto it =
                std::lower_bound(splits.begin(), splits.end(), std::array<int32_t, 3>{a, b, -1},
                                 [](const auto& x, const auto& y) {
                                     return x[0] != y[0] ? x[0] < y[0] : x[1] < y[1];
                                 });
            return it != splits.end() && (*it)[0] == a && (*it)[1] == b ? (*it)[2] : -1;
        };
        for (size_t f = 0; f < nf; ++f)
            for (int e = 0; e < 3; ++e) {
                const int32_t a = mesh.faces[f][e], b = mesh.faces[f][(e + 1) % 3];
                const Vec3f pa = mesh.vertices[a], pb = mesh.vertices[b];
                const float limit = max_length(0.5f * (pa + pb));
                if ((pb - pa).squaredNorm() > limit * limit)
                    splits.push_back({std::min(a, b), std::max(a, b), -1});
            }
        if (splits.empty()) return;
        std::sort(splits.begin(), splits.end());
        splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
        const size_t nv = mesh.vertices.size();
        mesh.vertices.resize(nv + splits.size());
        parallel_for(
            splits.size(),
            [&](size_t i) {
                auto& s = splits[i];
                Vec3f x = 0.5f * (mesh.vertices[s[0]] + mesh.vertices[s[1]]);
                const float reach = 0.5f * (mesh.vertices[s[1]] - mesh.vertices[s[0]]).norm();
                const Vec3f start = x;
                for (int it = 0; it < 4; ++it) {
                    const float f = field(x);
                    const Vec3f g = field_gradient(field, x, f);
                    const float g2 = g.squaredNorm();
                    if (g2 < 1e-8f) break;
                    x -= (f / g2) * g;
                }
                // A step that leaves the edge's neighbourhood found another sheet: keep the
                // midpoint.
                if ((x - start).norm() > reach) x = start;
                s[2] = static_cast<int32_t>(nv + i);
                mesh.vertices[nv + i] = x;
            },
            64);
        std::vector<Vec3i> faces;
        faces.reserve(nf * 2);
        for (size_t f = 0; f < nf; ++f) {
            const Vec3i t = mesh.faces[f];
            int32_t m[3];
            int count = 0;
            for (int e = 0; e < 3; ++e)
                count += (m[e] = find(t[e], t[(e + 1) % 3])) >= 0;
            if (count == 0) {
                faces.push_back(t);
                continue;
            }
            // Rotate so that the first split edge follows a run of split edges from corner 0:
            // edge e joins corners e and e + 1, its midpoint m[e].
            int r = 0;
            while (m[r] < 0 || (count < 3 && m[(r + 2) % 3] >= 0))
                ++r;
            const int32_t c0 = t[r], c1 = t[(r + 1) % 3], c2 = t[(r + 2) % 3];
            const int32_t m0 = m[r], m1 = m[(r + 1) % 3], m2 = m[(r + 2) % 3];
            if (count == 1) {
                faces.emplace_back(c0, m0, c2);
                faces.emplace_back(m0, c1, c2);
            } else if (count == 2) {
                faces.emplace_back(c0, m0, c2);
                faces.emplace_back(m0, c1, m1);
                faces.emplace_back(m0, m1, c2);
            } else {
                faces.emplace_back(c0, m0, m2);
                faces.emplace_back(m0, c1, m1);
                faces.emplace_back(m2, m1, c2);
                faces.emplace_back(m0, m1, m2);
            }
        }
        mesh.faces.swap(faces);
    }
}

bool everywhere(const Vec3f&) {
    return true;
}
// The eyes, the nose's tip and wings and the lips: forms a few millimetres across, which the
// mesh is refined for and only there relaxed again, so the rest of the figure stays as it was.
bool near_face_detail(const Vec3f& p) {
    const Vec3f m(std::abs(p.x()), p.y(), p.z());
    return (m - kEyeCentre).norm() < kEyeRadius + 1.f || (p - kMouthCentre).norm() < 3.f ||
           (p - kNoseTip).norm() < 2.f;
}

// The hairline of the built-in head: the height (y, cm) of the hairline at azimuth phi around
// the head (0 = front, ±π = back), as a periodic smooth curve through key points. It dips at the
// sideburns, rises over the ears and falls to the nape.
float hairline_height(float phi) {
    struct Key {
        float deg, y;
    };
    static constexpr Key kKeys[] = {{0.f, 6.2f},    {22.f, 6.0f},   {38.f, 5.4f},   {50.f, 4.6f},
                                    {58.f, 2.0f},   {63.f, 0.3f},   {72.f, 0.0f},   {77.f, 1.5f},
                                    {82.f, 4.4f},   {100.f, 4.7f},  {110.f, 4.2f},  {118.f, 2.0f},
                                    {126.f, -1.0f}, {140.f, -3.6f}, {160.f, -5.0f}, {180.f, -5.4f}};
    const float a = std::min(std::abs(phi) * 180.f / kPi, 180.f);
    for (size_t i = 0; i + 1 < std::size(kKeys); ++i) {
        if (a <= kKeys[i + 1].deg) {
            const float t = (a - kKeys[i].deg) / (kKeys[i + 1].deg - kKeys[i].deg);
            const float s = t * t * (3.f - 2.f * t);
            return kKeys[i].y + (kKeys[i + 1].y - kKeys[i].y) * s;
        }
    }
    return kKeys[std::size(kKeys) - 1].y;
}

// The torso alone under a neck column that rises from inside the shoulders to a flat top at
// y = neck_top, of radius neck_radius there (the body proxy: a user's neck goes on into it).
float torso_field(const Vec3f& p, float neck_top, float neck_radius) {
    const Vec3f m(std::abs(p.x()), p.y(), p.z());
    Blend b;
    const Vec3f bottom(0.f, -19.f, -2.8f), top(0.f, neck_top, -2.f);
    b.add(p, 0.5f * (bottom + top), 0.5f * (top - bottom).norm() + 6.f, 2.5f, [&] {
        return smax(cone_capsule(p, bottom, top, 5.6f, neck_radius), p.y() - neck_top, 0.4f);
    });
    add_torso(b, p, m);
    return b.d;
}

Vec3f lerp(const Vec3f& a, const Vec3f& b, float t) {
    return a + t * (b - a);
}

// The albedo at a vertex of the face: the skin's, except on the eyes (white, an iris and a
// pupil looking straight ahead, a dark lash line along the upper lid) and the lips. Shape
// alone cannot make a face read at a glance: eyes the colour of skin look blind.
Vec3f face_color(const Vec3f& p) {
    const Vec3f m(std::abs(p.x()), p.y(), p.z());
    Vec3f c = kSkinAlbedo;
    const Vec3f q = m - kEyeCentre;
    const float r = q.norm();
    if (r < kEyeRadius + 0.6f && q.z() > 0.f) {
        const float angle = std::acos(std::clamp(q.z() / r, -1.f, 1.f));  // from the gaze
        const Vec3f sclera(0.52f, 0.47f, 0.43f), iris(0.09f, 0.045f, 0.022f),
            limbus(0.03f, 0.018f, 0.012f), pupil(0.008f, 0.008f, 0.008f);
        Vec3f eye = lerp(limbus, sclera, smoothstep(0.5f, 0.58f, angle));
        eye = lerp(iris, eye, smoothstep(0.4f, 0.5f, angle));
        eye = lerp(pupil, eye, smoothstep(0.16f, 0.22f, angle));
        const float height = r - kEyeRadius;  // off the ball: 0 in the opening, the lids above
        // The lash line: the first 1.5 mm of the upper lid's rise off the ball.
        const float lash =
            (1.f - smoothstep(0.06f, 0.22f, height)) * smoothstep(0.f, 0.3f, q.y() - 0.06f * q.x());
        c = lerp(c, Vec3f(0.08f, 0.05f, 0.035f), 0.6f * lash);
        c = lerp(c, eye, 1.f - smoothstep(0.04f, 0.1f, height));
    }
    const float lip = lips(p);
    if (lip < 0.3f)
        c = lerp(c, Vec3f(0.46f, 0.22f, 0.19f), 0.7f * (1.f - smoothstep(0.02f, 0.2f, lip)));
    return c;
}

std::vector<Vec3f> face_colors(const Mesh& mesh) {
    std::vector<Vec3f> colors(mesh.vertices.size());
    parallel_for(
        mesh.vertices.size(), [&](size_t v) { colors[v] = face_color(mesh.vertices[v]); }, 4096);
    return colors;
}

}  // namespace

Mesh builtin_torso_mesh(float neck_top, float neck_radius) {
    neck_top = std::clamp(neck_top, -16.f, -6.f);
    neck_radius = std::clamp(neck_radius, 2.f, 8.f);
    const auto field = [&](const Vec3f& p) { return torso_field(p, neck_top, neck_radius); };
    Grid g = body_grid();
    g.y = axis(kBodyBottom - 1.5f, neck_top + 2.f * kBodyCell, kBodyCell);
    Mesh mesh = march(g, field);
    collapse_short_edges(
        mesh, [](const Vec3f&) { return 0.7f; }, 2);
    relax(mesh, field, 2, everywhere);
    return mesh;
}

Mesh builtin_head_mesh() {
    Mesh mesh = polygonize();
    // Slivers everywhere; on the bust, whose forms are broad, edges up to 0.7 cm.
    collapse_short_edges(
        mesh, [](const Vec3f& p) { return 0.2f + 0.5f * smoothstep(-10.f, -14.f, p.y()); }, 2);
    relax(mesh, head_field, 2, everywhere);
    // The eyes and their lids on edges of 2 mm at most, the lips and nostrils on 2.5 mm.
    refine(
        mesh, head_field,
        [](const Vec3f& p) {
            const Vec3f m(std::abs(p.x()), p.y(), p.z());
            if ((m - kEyeCentre).norm() < kEyeRadius + 0.8f) return 0.2f;
            return near_face_detail(p) ? 0.25f : 1e3f;
        },
        3);
    relax(mesh, head_field, 2, near_face_detail);

    mesh.colors = face_colors(mesh);

    // Groups: the scalp is above the hairline and off the ears.
    mesh.group_names = {"scalp", "body"};
    mesh.face_group.resize(mesh.faces.size());
    const Vec3f axis(0.f, 0.f,
                     -0.7f);  // the vertical axis of the cranium passes (x, z) = (0, -0.7)
    parallel_for(
        mesh.faces.size(),
        [&](size_t f) {
            const Vec3i& t = mesh.faces[f];
            const Vec3f c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.f;
            const float phi = std::atan2(c.x() - axis.x(), c.z() - axis.z());
            const Vec3f m(std::abs(c.x()), c.y(), c.z());
            const bool on_ear = (m - kEarCentre).norm() < kEarRadius + 1.f && ear(m) < 0.4f;
            const bool scalp = c.y() > hairline_height(phi) && !on_ear && c.y() > -8.f;
            mesh.face_group[f] = scalp ? 0 : 1;
        },
        1024);

    // UVs: the polar map around the cranium centre (crown at (0.5, 0.5), front toward v = 1,
    // +X toward u = 1, radius = polar angle / π · 0.5), one UV per vertex.
    const Vec3f centre(0.f, 3.f, -0.7f);
    mesh.uvs.resize(mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        const Vec3f d = mesh.vertices[v] - centre;
        const float h = std::hypot(d.x(), d.z());
        const float r = 0.5f * std::atan2(h, d.y()) / kPi;
        mesh.uvs[v] = h > 1e-6f ? Vec2f(0.5f + r * d.x() / h, 0.5f + r * d.z() / h)
                                : Vec2f(0.5f, d.y() > 0 ? 0.5f : 1.f);
    }
    mesh.face_uvs = mesh.faces;
    // The few faces around the map's pole (straight down, under the chest) span every azimuth,
    // so their UV centroid would land near the crown; they get one UV on the rim instead.
    const int pole = static_cast<int>(mesh.uvs.size());
    mesh.uvs.emplace_back(0.5f, 0.f);
    const Vec2f mid(0.5f, 0.5f);
    for (Vec3i& t : mesh.face_uvs) {
        const Vec2f c = (mesh.uvs[t[0]] + mesh.uvs[t[1]] + mesh.uvs[t[2]]) / 3.f;
        float r = INFINITY;
        for (int k = 0; k < 3; ++k)
            r = std::min(r, (mesh.uvs[t[k]] - mid).norm());
        if ((c - mid).norm() < 0.5f * r) t = Vec3i::Constant(pole);
    }
    return mesh;
}

}  // namespace wisp
