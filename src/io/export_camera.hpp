#pragma once
// The camera and light that the offline-renderer exporters (rib.hpp, pbrt.hpp) write into
// their scenes, as plain numbers so that io needs nothing from the renderer. From a render
// Camera c: ExportCamera{c.eye, c.eye + c.forward, c.up, c.fov_y_degrees, c.width, c.height}.
#include <cmath>

#include "core/error.hpp"
#include "core/math.hpp"

namespace wisp {

struct ExportCamera {
    Vec3f eye = Vec3f(0, 5, 80);  // cm, head space (Y up, +Z forward)
    Vec3f target = Vec3f(0, 0, 0);
    Vec3f up = Vec3f::UnitY();
    float fov_y_degrees = 30.f;  // full vertical field of view
    int width = 1024, height = 1024;
    // A distant key light: unit direction towards the light (head space) and intensity.
    Vec3f key_direction = Vec3f(-0.5f, 0.7f, 0.5f).normalized();
    float key_intensity = 3.f;
};

// The camera's unit (right, up, forward) basis; throws wisp::Error naming `format` when eye
// and target coincide or up is parallel to the view.
inline void export_camera_basis(const ExportCamera& c, const char* format, Vec3f& right, Vec3f& up,
                                Vec3f& forward) {
    const Vec3f f = c.target - c.eye;
    if (!(f.norm() > 0)) fail(format, " export: camera eye and target coincide");
    forward = f.normalized();
    const Vec3f r = forward.cross(c.up);
    if (!(r.norm() > 1e-6f)) fail(format, " export: camera up is parallel to the view");
    right = r.normalized();
    up = right.cross(forward);
}

// The field of view across the shorter image side, in degrees: what RenderMan's and pbrt's
// perspective cameras take.
inline float shorter_side_fov(const ExportCamera& c) {
    if (c.width >= c.height) return c.fov_y_degrees;
    const float half_y = 0.5f * c.fov_y_degrees * kPi / 180.f;
    return 2.f * std::atan(std::tan(half_y) * c.width / c.height) * 180.f / kPi;
}

}  // namespace wisp
