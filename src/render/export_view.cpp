#include "render/export_view.hpp"

#include "render/render.hpp"

namespace wisp {

ExportCamera export_camera(const Hair& hair, const Mesh& head) {
    RenderOptions options;
    const Camera c = render_camera(hair, &head, options);
    ExportCamera e;
    e.eye = c.eye;
    e.target = c.eye + c.forward;
    e.up = c.up;
    e.fov_y_degrees = c.fov_y_degrees;
    e.width = c.width;
    e.height = c.height;
    return e;
}

}  // namespace wisp
