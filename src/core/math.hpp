#pragma once
// Small math types on Eigen. Units across wisp: centimetres and seconds, head space is
// Y up, +Z forward (the face looks along +Z).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wisp {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;
using Vec3i = Eigen::Vector3i;
using Mat3f = Eigen::Matrix3f;
using Mat3d = Eigen::Matrix3d;

inline constexpr float kPi = 3.14159265358979323846f;

// An orthonormal frame: columns are tangent t, normal n and binormal b (b = t × n).
// Local coordinates (x, y, z) map to world as x·t + y·n + z·b.
struct Frame {
    Vec3f t = Vec3f::UnitX();
    Vec3f n = Vec3f::UnitY();
    Vec3f b = Vec3f::UnitZ();

    Vec3f to_world(const Vec3f& local) const {
        return local.x() * t + local.y() * n + local.z() * b;
    }
    Vec3f to_local(const Vec3f& world) const { return {world.dot(t), world.dot(n), world.dot(b)}; }
};

// Hermite step from 0 at e0 to 1 at e1 (e1 < e0 steps down), clamped.
inline float smoothstep(float e0, float e1, float x) {
    const float t = std::clamp((x - e0) / (e1 - e0), 0.f, 1.f);
    return t * t * (3.f - 2.f * t);
}

// v / |v|, or `fallback` when |v| is not above min_norm or not finite.
inline Vec3f unit_or(const Vec3f& v, const Vec3f& fallback, float min_norm = 1e-6f) {
    const float n = v.norm();
    return n > min_norm && std::isfinite(n) ? Vec3f(v / n) : fallback;
}

// A unit vector perpendicular to the unit vector v, chosen deterministically.
inline Vec3f any_perpendicular(const Vec3f& v) {
    const Vec3f a = std::abs(v.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY();
    return v.cross(a).normalized();
}

// The frame with tangent t (unit) whose normal is the part of `reference` orthogonal to t,
// or any perpendicular when reference is (nearly) parallel to t.
inline Frame frame_from(const Vec3f& t, const Vec3f& reference) {
    Frame f;
    f.t = t;
    Vec3f n = reference - reference.dot(t) * t;
    const float len = n.norm();
    f.n = len > 1e-6f ? Vec3f(n / len) : any_perpendicular(t);
    f.b = f.t.cross(f.n);
    return f;
}

// Rotation-minimizing transport of frame f onto the new unit tangent t (double reflection
// reduced to the single rotation taking f.t to t).
inline Frame transport(const Frame& f, const Vec3f& t) {
    const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(f.t, t);
    Frame g;
    g.t = t;
    g.n = (q * f.n).normalized();
    g.n = (g.n - g.n.dot(t) * t).normalized();
    g.b = t.cross(g.n);
    return g;
}

// Axis-aligned bounding box.
struct Box3 {
    Vec3f lo = Vec3f::Constant(INFINITY);
    Vec3f hi = Vec3f::Constant(-INFINITY);
    void extend(const Vec3f& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    void extend(const Box3& b) {
        lo = lo.cwiseMin(b.lo);
        hi = hi.cwiseMax(b.hi);
    }
    bool empty() const { return !(lo.x() <= hi.x()); }
    Vec3f size() const { return hi - lo; }
    Vec3f center() const { return 0.5f * (lo + hi); }
    // Corner k in [0, 8): bit 0 picks hi.x, bit 1 hi.y, bit 2 hi.z.
    Vec3f corner(int k) const {
        return Vec3f((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                     (k & 4) ? hi.z() : lo.z());
    }
};

}  // namespace wisp
