#pragma once
// The camera and light that the offline-renderer exporters (rib.hpp, pbrt.hpp) write into
// their scenes, as plain numbers so that io needs nothing from the renderer. From a render
// Camera c: ExportCamera{c.eye, c.eye + c.forward, c.up, c.fov_y_degrees, c.width, c.height}.
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

}  // namespace wisp
