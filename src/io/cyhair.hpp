#pragma once
// Cem Yuksel's cyHair `.hair` format (cemyuksel.com/research/hairmodels), little-endian:
//
//   header, 128 bytes
//     char     signature[4]   "HAIR"
//     uint32   strand count   #S
//     uint32   point count    #P (all strands)
//     uint32   array flags    bit 0 segments, 1 points, 2 thickness, 3 transparency, 4 color
//     uint32   d_segments     segments per strand when the segments array is absent
//     float    d_thickness    thickness when the thickness array is absent
//     float    d_transparency transparency when the transparency array is absent
//     float    d_color[3]     color when the color array is absent
//     char     info[88]       free text
//   arrays, each present when its flag is set, in this order
//     uint16   segments       #S, points of strand i = segments[i] + 1
//     float    points         #P×3
//     float    thickness      #P
//     float    transparency   #P
//     float    color          #P×3
//
// wisp reads points as centimetres, thickness as per-point widths (diameter, cm) and the
// color of each strand's first point as the strand color; transparency is ignored.
#include <filesystem>
#include <string>
#include <string_view>

#include "core/hair.hpp"

namespace wisp {

// Decodes the bytes of a .hair file; `name` (the file) starts every error message.
// Sizes in the header are checked against bytes.size() before anything is allocated.
Hair decode_cyhair(std::string_view bytes, const std::string& name);
Hair read_cyhair(const std::filesystem::path& path);

// Encodes hair: the segments array only when strands differ in point count, points,
// thickness when hair.widths is set (else d_thickness = default_width) and color when
// hair.colors is set (each strand's color repeated on its points; else d_color =
// default_color). Throws wisp::Error for a strand of 0 or more than 65,536 points.
std::string encode_cyhair(const Hair& hair, const std::string& name = "hair");
void write_cyhair(const std::filesystem::path& path, const Hair& hair);

}  // namespace wisp
