#pragma once
// Pinhole cameras for the renderer: named views framed on a bounding box, or an explicit
// eye/target/fov. Head space is centimetres, Y up, the face looking along +Z, so the
// subject's left is +X.
#include <string>
#include <vector>

#include "core/math.hpp"

namespace wisp {

struct Camera {
    Vec3f eye = Vec3f(0, 0, 100);     // cm, head space
    Vec3f right = Vec3f::UnitX();     // unit; image x grows along it
    Vec3f up = Vec3f::UnitY();        // unit; image y grows against it (row 0 is the top)
    Vec3f forward = -Vec3f::UnitZ();  // unit viewing direction
    float fov_y_degrees = 30.f;       // full vertical field of view
    int width = 512, height = 512;    // pixels
    float focal_pixels = 955.f;       // (height / 2) / tan(fov_y / 2)

    // (x, y, depth): x, y in pixels with pixel (i, j) covering [i, i+1) × [j, j+1), row 0 at
    // the top; depth is the distance along `forward` in cm (≤ 0 behind the eye).
    Vec3f project(const Vec3f& p) const {
        const Vec3f d = p - eye;
        const float z = d.dot(forward);
        const float s = focal_pixels / z;
        return {0.5f * width + d.dot(right) * s, 0.5f * height - d.dot(up) * s, z};
    }
    // Unit direction of the ray through image point (x, y) in pixels.
    Vec3f ray(float x, float y) const {
        return (forward * focal_pixels + right * (x - 0.5f * width) - up * (y - 0.5f * height))
            .normalized();
    }
};

// A camera at `eye` looking at `target`, with `up` (need not be orthogonal to the view)
// and a vertical field of view in degrees. Throws wisp::Error if eye == target, up is
// parallel to the view, the fov is outside (0, 180) or the size is not positive.
Camera look_at(const Vec3f& eye, const Vec3f& target, const Vec3f& up, float fov_y_degrees,
               int width, int height);

// The named views: "front" (camera on +Z), "back" (−Z), "left" (the subject's left, +X),
// "right" (−X), "three-quarter" (front-left, 45° round and 15° above), "top" (+Y, face
// towards the top of the image).
const std::vector<std::string>& view_names();

// A camera of the named view whose picture holds all of `bounds` (cm, head space) with a
// small margin, looking at its centre. Throws wisp::Error naming the view and listing
// view_names() if the name is unknown, or if bounds is empty.
Camera frame_view(const std::string& view, const Box3& bounds, int width, int height,
                  float fov_y_degrees = 30.f);

}  // namespace wisp
