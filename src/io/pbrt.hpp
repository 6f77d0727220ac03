#pragma once
// pbrt-v4 scenes of hair: a camera, a film, lights, the hair material and one curve shape
// per strand, which pbrt-v4 loads as is (`pbrt scene.pbrt`).
//
//   LookAt ex ey ez  tx ty tz  ux uy uz
//   Camera "perspective" "float fov" [F]
//   Film "rgb" "integer xresolution" [W] "integer yresolution" [H] "string filename" "..exr"
//   Sampler "zsobol" "integer pixelsamples" [64]
//   Integrator "volpath" "integer maxdepth" [30]
//   WorldBegin
//   LightSource "distant" "point3 from" [..] "point3 to" [0 0 0] "float scale" [..]
//   LightSource "infinite" "rgb L" [..]
//   AttributeBegin
//     Material "hair" "rgb reflectance" [r g b]     (when the colour changes)
//     Shape "curve" "string type" "cylinder" "string basis" "bezier" "integer degree" [3]
//           "point3 P" [3(n-1)+1 points] "float width0" [w_root] "float width1" [w_tip]
//   AttributeEnd
//
// pbrt-v4 curves are piecewise cubic Bézier (3k + 1 control points for k segments), so each
// Catmull-Rom segment p0 p1 p2 p3 (phantom ends as in core/catmull_rom.hpp) is converted
// exactly: b0 = p1, b1 = p1 + (p2 − p0)/6, b2 = p2 − (p3 − p1)/6, b3 = p2, consecutive
// segments sharing b3/b0. Widths are the strand's first and last per-point widths (pbrt
// interpolates linearly between them). The hair material's "reflectance" is the strand
// colour (pbrt-v4 inverts it to an absorption coefficient). Units: centimetres; pbrt's
// camera looks along +z with the fov of the shorter image side, which LookAt and the fov
// below account for. Strands of fewer than 2 points are skipped.
#include <filesystem>
#include <string>

#include "core/hair.hpp"
#include "io/export_camera.hpp"

namespace wisp {

std::string encode_pbrt(const Hair& hair, const ExportCamera& camera,
                        const std::string& image_name = "hair.exr");
// Writes atomically; the image name is the file's stem + ".exr".
void write_pbrt(const std::filesystem::path& path, const Hair& hair, const ExportCamera& camera);

}  // namespace wisp
