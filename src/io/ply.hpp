#pragma once
// Hair strands as PLY. The writer's layout (binary_little_endian 1.0):
//
//   comment wisp default_width <w>          used when there is no `width` property
//   comment wisp default_color <r> <g> <b>  used when the strand element has no color
//   element vertex #P                       every control point, strand after strand
//     property float x, y, z                centimetres, Y up
//     property float width                  diameter in cm (only when hair.widths is set)
//   element edge #P-#S                      one per segment, so tools that read PLY edges
//     property int vertex1, vertex2         (Blender: loose edges, Houdini) see polylines
//   element strand #S                       the strand table wisp reads back
//     property int vertex_count             points of the strand
//     property float red, green, blue       linear RGB (only when hair.colors is set)
//     property int wisp_id                  (only when hair.wisp is set)
//
// The reader takes ascii, binary_little_endian and binary_big_endian files with any
// elements and property types. Strands come from the `strand` element when present, else
// from chaining consecutive `edge` records that continue each other (a→b, b→c, ...).
#include <filesystem>
#include <string>
#include <string_view>

#include "core/hair.hpp"

namespace wisp {

Hair decode_ply(std::string_view bytes, const std::string& name);
Hair read_ply(const std::filesystem::path& path);

std::string encode_ply(const Hair& hair, const std::string& name = "hair");
void write_ply(const std::filesystem::path& path, const Hair& hair);

}  // namespace wisp
