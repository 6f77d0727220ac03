#pragma once
// RenderMan RIB scenes of hair, as Choe & Ko 2005 §5 rendered it: every strand a cubic
// Catmull-Rom `Curves` primitive (RiCurves) with per-point widths and its colour.
//
//   Format W H 1 / Projection "perspective" "fov" [F] / Transform [world → camera]
//   WorldBegin
//     LightSource "distantlight" 1 "from" [..] "to" [0 0 0] "intensity" [..]
//     Basis "catmull-rom" 1 "catmull-rom" 1
//     Curves "cubic" [n+2 ...] "nonperiodic" "P" [...] "width" [...] "uniform color Cs" [...]
//   WorldEnd
//
// A strand of n control points is written with n + 2 vertices: the phantom end points
// p0 = 2 p1 − p2 and p(n+1) = 2 pn − p(n−1) of core/catmull_rom.hpp, so the RenderMan curve
// passes through every control point exactly as wisp's pinned spline does (vstep 1: n − 1
// segments). "width" is varying: n values per curve (cm). Strands are grouped into Curves
// calls of at most 10,000. Strands of fewer than 2 points are skipped. Units: centimetres.
// RenderMan's camera space is left-handed (x right, y up, z forward) and its fov spans the
// shorter image side.
#include <filesystem>
#include <string>

#include "core/hair.hpp"
#include "io/export_camera.hpp"

namespace wisp {

std::string encode_rib(const Hair& hair, const ExportCamera& camera,
                       const std::string& image_name = "hair.tif");
// Writes atomically; the image name is the file's stem + ".tif".
void write_rib(const std::filesystem::path& path, const Hair& hair, const ExportCamera& camera);

}  // namespace wisp
