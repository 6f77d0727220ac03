#pragma once
// The camera that .rib and .pbrt scenes get (io/export_camera.hpp): the renderer's
// three-quarter view of the hair on its head, as `wisp generate`, `wisp convert` and
// Python's Hair.write frame it.
#include "core/hair.hpp"
#include "geometry/mesh.hpp"
#include "io/export_camera.hpp"

namespace wisp {

// hair and head in cm, head space.
ExportCamera export_camera(const Hair& hair, const Mesh& head);

}  // namespace wisp
