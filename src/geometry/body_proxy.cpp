#include "geometry/body_proxy.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/builtin_head.hpp"

namespace wisp {
namespace {

// The built-in head, whose torso the proxy is: its height from chin to crown, its chin and the
// point of its neck's axis that the proxy centres under the mesh's neck (cm, its space).
constexpr float kBuiltinHeight = 22.8f;
constexpr float kBuiltinChinY = -10.3f;
constexpr float kBuiltinNeckZ = -2.f;

}  // namespace

Mesh fit_body_proxy(const Landmarks& head, const Mesh* mesh) {
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
    // A bust's own shoulders, where it has them, may be broader or deeper than the built-in
    // figure's at this head size: the proxy is widened (never narrowed) to hold them, so their
    // cut edge does not stand out of it. Measured in the face's frame across the shoulders,
    // a little above where the mesh ends (or 0.45 heights below the chin).
    Vec3f stretch = Vec3f::Ones();
    if (mesh) {
        const float level =
            std::max(head.chin.y() - 0.45f * head.height, mesh->bounds().lo.y() + 1.5f * s);
        if (level < head.chin.y() - 0.3f * head.height) {
            const auto extent = [&](const std::vector<Vec3f>& points, bool builtin) {
                Vec3f lo = Vec3f::Constant(INFINITY), hi = Vec3f::Constant(-INFINITY);
                for (const Vec3f& v : points) {
                    // Across (character's left) and forward in the face's frame: the built-in
                    // torso faces +Z already, the mesh turns by the yaw.
                    const Vec3f d = builtin ? Vec3f(s * (v - a)) : Vec3f(v - t);
                    if (std::abs(d.y() + t.y() - level) > 1.f * s) continue;
                    const Vec3f f =
                        builtin ? Vec3f(d.x(), 0.f, d.z())
                                : Vec3f(c * d.x() - sn * d.z(), 0.f, sn * d.x() + c * d.z());
                    lo = lo.cwiseMin(f);
                    hi = hi.cwiseMax(f);
                }
                return Vec3f(hi - lo);
            };
            const Vec3f theirs = extent(mesh->vertices, false), ours = extent(torso.vertices, true);
            for (int axis : {0, 2})
                if (ours[axis] > 0.f && std::isfinite(theirs[axis]))
                    stretch[axis] = std::clamp(1.02f * theirs[axis] / ours[axis], 1.f, 1.4f);
        }
    }
    for (Vec3f& v : torso.vertices) {
        const Vec3f q = s * (v - a).cwiseProduct(stretch);
        v = t + Vec3f(c * q.x() + sn * q.z(), q.y(), -sn * q.x() + c * q.z());
    }
    torso.group_names = {kBodyProxyGroup};
    torso.face_group.assign(torso.faces.size(), 0);
    return torso;
}

}  // namespace wisp
