#include "render/camera.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace wisp {

Camera look_at(const Vec3f& eye, const Vec3f& target, const Vec3f& up, float fov_y_degrees,
               int width, int height) {
    if (width <= 0 || height <= 0) fail("camera: image size ", width, "x", height, " is empty");
    if (!(fov_y_degrees > 0.f && fov_y_degrees < 180.f))
        fail("camera: fov ", fov_y_degrees, " degrees is outside (0, 180)");
    const Vec3f view = target - eye;
    if (!(view.norm() > 1e-6f)) fail("camera: eye and target coincide");
    Camera c;
    c.eye = eye;
    c.forward = view.normalized();
    const Vec3f r = c.forward.cross(up);
    if (!(r.norm() > 1e-6f * std::max(1.f, up.norm())))
        fail("camera: up vector is parallel to the viewing direction");
    c.right = r.normalized();
    c.up = c.right.cross(c.forward);
    c.fov_y_degrees = fov_y_degrees;
    c.width = width;
    c.height = height;
    c.focal_pixels = 0.5f * height / std::tan(0.5f * fov_y_degrees * kPi / 180.f);
    return c;
}

const std::vector<std::string>& view_names() {
    static const std::vector<std::string> names = {"front", "back",          "left",
                                                   "right", "three-quarter", "top"};
    return names;
}

namespace {

// Unit vector from the target towards the eye, and the up vector, of a named view.
bool view_direction(const std::string& view, Vec3f& dir, Vec3f& up) {
    up = Vec3f::UnitY();
    if (view == "front") {
        dir = Vec3f::UnitZ();
    } else if (view == "back") {
        dir = -Vec3f::UnitZ();
    } else if (view == "left") {
        dir = Vec3f::UnitX();
    } else if (view == "right") {
        dir = -Vec3f::UnitX();
    } else if (view == "three-quarter" || view == "three_quarter") {
        const float el = 15.f * kPi / 180.f;
        dir = Vec3f(std::cos(el) * std::sqrt(0.5f), std::sin(el), std::cos(el) * std::sqrt(0.5f));
    } else if (view == "top") {
        dir = Vec3f::UnitY();
        up = Vec3f::UnitZ();  // the face towards the top of the image
    } else {
        return false;
    }
    return true;
}

}  // namespace

Camera frame_view(const std::string& view, const Box3& bounds, int width, int height,
                  float fov_y_degrees) {
    Vec3f dir, up;
    if (!view_direction(view, dir, up)) {
        std::string list;
        for (const std::string& n : view_names())
            list += (list.empty() ? "" : ", ") + n;
        fail("view '", view, "' is unknown (views: ", list, ")");
    }
    if (bounds.empty()) fail("view '", view, "': nothing to frame (empty bounds)");
    const Vec3f centre = bounds.center();
    // Place the eye on the line through the centre at the distance where every corner of
    // the box projects inside the frame shrunk by a 4% margin: a corner at lateral offset
    // a and depth offset b (towards the eye) needs distance ≥ b + |a| / tan(half-fov).
    Camera c = look_at(centre + dir, centre, up, fov_y_degrees, width, height);
    const float tan_y = 0.96f * 0.5f * height / c.focal_pixels;
    const float tan_x = 0.96f * 0.5f * width / c.focal_pixels;
    float distance = 1e-3f;
    for (int k = 0; k < 8; ++k) {
        const Vec3f d = bounds.corner(k) - centre;
        const float b = d.dot(dir);
        distance = std::max(distance, b + std::abs(d.dot(c.right)) / tan_x);
        distance = std::max(distance, b + std::abs(d.dot(c.up)) / tan_y);
    }
    return look_at(centre + distance * dir, centre, up, fov_y_degrees, width, height);
}

}  // namespace wisp
