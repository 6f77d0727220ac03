#include "geometry/body_proxy.hpp"

#include <cmath>

#include "geometry/builtin_head.hpp"

namespace wisp {
namespace {

// The built-in head, whose torso the proxy is: its height from chin to crown, its chin and the
// point of its neck's axis that the proxy centres under the mesh's neck (cm, its space).
constexpr float kBuiltinHeight = 22.8f;
constexpr float kBuiltinChinY = -10.3f;
constexpr float kBuiltinNeckZ = -2.f;

}  // namespace

Mesh fit_body_proxy(const Landmarks& head) {
    const float s = head.height / kBuiltinHeight;
    // The neck column goes up into the mesh's neck, 2 head-scaled cm above where the mesh
    // ends, or to the narrowest section if that is higher, never above 1 cm under the chin;
    // thinner than the narrowest section, it stays inside the neck everywhere between.
    const float bottom = std::isfinite(head.neck_bottom) ? head.neck_bottom : head.neck.y();
    const float top = std::min(std::max(head.neck.y(), bottom + 2.f * s), head.chin.y() - 1.f * s);
    const auto to_builtin_y = [&](float y) { return kBuiltinChinY + (y - head.chin.y()) / s; };
    // The radius is the circle's of the section's area: necks are wider than deep, so 0.8 of
    // it stays inside front and back.
    Mesh torso = builtin_torso_mesh(to_builtin_y(top), 0.8f * head.neck_radius / s);

    // p = T + s·R·(q − A): A the built-in's chin level on its neck's axis, T the mesh's chin
    // level on its neck's centre; R turns +Z to the face's direction about +Y.
    const float yaw = std::atan2(head.forward.x(), head.forward.z());
    const float c = std::cos(yaw), sn = std::sin(yaw);
    const Vec3f a(0.f, kBuiltinChinY, kBuiltinNeckZ);
    const Vec3f t(head.neck.x(), head.chin.y(), head.neck.z());
    for (Vec3f& v : torso.vertices) {
        const Vec3f q = s * (v - a);
        v = t + Vec3f(c * q.x() + sn * q.z(), q.y(), -sn * q.x() + c * q.z());
    }
    torso.group_names = {kBodyProxyGroup};
    torso.face_group.assign(torso.faces.size(), 0);
    return torso;
}

}  // namespace wisp
