#pragma once
// Hair strands as OBJ polylines: `v x y z` vertices (centimetres) and `l` lines of
// 1-based vertex indices. OBJ carries positions only: widths, colors and wisp ids are not
// written and read back as absent.
#include <filesystem>
#include <string>
#include <string_view>

#include "core/hair.hpp"

namespace wisp {

// Reads `v` and `l` statements; `l` accepts negative (relative) indices and `v/vt`
// pairs. Consecutive 2-point `l` lines that continue each other (the next starts where
// the last ended) are joined back into one strand, so both writer forms read back.
// `vt`, `vn`, `f`, `g`, `o`, `s`, `usemtl`, `mtllib`, comments and unknown statements
// are ignored. Errors name "<name>:<line>".
Hair decode_obj_curves(std::string_view text, const std::string& name);
Hair read_obj_curves(const std::filesystem::path& path);

// One `l` per strand, or with `segments` one `l a b` per segment (Blender's OBJ importer
// keeps only the first two points of a longer `l`). A 1-point strand is written `l a`.
std::string encode_obj_curves(const Hair& hair, bool segments, const std::string& name = "hair");
void write_obj_curves(const std::filesystem::path& path, const Hair& hair, bool segments);

}  // namespace wisp
