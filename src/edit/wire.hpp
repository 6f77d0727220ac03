#pragma once
// What the editor's server sends the browser: strands and the head as little-endian binary
// arrays, and the style schema as JSON (also `wisp schema`).
#include <bit>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/hair.hpp"
#include "geometry/mesh.hpp"
#include "groom/master.hpp"
#include "groom/style.hpp"
#include "groom/toml_json.hpp"  // toml_value_to_json, json_to_toml_value

namespace wisp {

static_assert(std::endian::native == std::endian::little,
              "the wire format is little-endian: add byte swaps for this machine");

// One number of the wire format appended to `out`.
inline void put_u32(std::string& out, uint32_t v) {
    out.append(reinterpret_cast<const char*>(&v), 4);
}
inline void put_f32(std::string& out, float v) {
    out.append(reinterpret_cast<const char*>(&v), 4);
}

// A permutation of [0, n): strand order[i] is sent i-th, so that any prefix of what is sent
// is a uniform random subset (Fisher–Yates on a fixed stream: the same n, the same order).
std::vector<uint32_t> strand_order(size_t n);

// The strands `ids` (#S', indices into hair's strands) of `hair`, in that order, as:
//   "WISPHAIR"                 8 bytes
//   uint32 version (1), strands sent S', points sent P', strands in all S
//   uint32 offsets[S'+1]       strand i owns points [offsets[i], offsets[i+1])
//   float32 positions[3·P']    cm, head space
//   float32 colors[3·S']       linear RGB in [0, 1]
// every number little-endian. The colours come last, so a colour change rewrites them alone
// (write_strand_colors). `total` is the count written as "strands in all".
std::string encode_strands(const Hair& hair, std::span<const uint32_t> ids, size_t total);
// The same bytes written into `out`, reusing its memory: every byte is written, so a buffer
// that held an answer of about the same size is neither cleared first nor faulted in again
// (a preview's 7.5 MB, on one thread, before the copy that fills it in parallel).
void encode_strands(const Hair& hair, std::span<const uint32_t> ids, size_t total,
                    std::string& out);
// The first min(limit, #S) strands of `hair` in strand_order(#S). `total`, when non-zero, is
// the count written as "strands in all" (a preview's hair holds only the strands it sends).
std::string encode_strands(const Hair& hair, size_t limit, size_t total = 0);
// Overwrites the colours of an encode_strands buffer: colors #S' linear RGB, one per strand it
// holds (the last 12·S' bytes). Throws wisp::Error when `bytes` holds another count.
void write_strand_colors(std::span<const Vec3f> colors, std::string& bytes);

// One frame of the live motion (issue 17) for strands the browser already has from
// encode_strands (the same strands, in the same order): "WISPFRAM", uint32 version (1),
// frame index, points P', then float32 positions[3·P'] (cm, world space), little-endian.
// Reuses `out`'s memory.
void encode_frame(uint32_t frame, std::span<const Vec3f> points, std::string& out);
// The same frame's header written and `out` sized for `points` positions; returns their
// 12·points bytes for the caller to fill (Animator::skin, which skins straight into the
// frame instead of through a copy).
std::span<char> begin_frame(uint32_t frame, size_t points, std::string& out);

// The masters' control polylines in the same layout (colors: a neutral grey).
std::string encode_masters(const Masters& masters);

// The head mesh: "WISPHEAD", uint32 version (2), #V, #F, float32 positions[3·#V] (cm),
// float32 normals[3·#V] (skin_normals: the renderer's, so the editor shows the same skin),
// uint32 triangles[3·#F], uint8 scalp[#F] (1 for scalp faces).
std::string encode_head(const Mesh& mesh, const std::vector<uint8_t>& scalp_faces);

// A scalp map as the painter edits it: "WISPMAP\0", uint32 version (1), width, height,
// kind (0 constant, 1 image file, 2 procedural, 3 painted: held in memory until Save),
// float32 low, high (the map's value is low + t·(high − low)), then uint8 t·255
// [width·height], row 0 the top row of the image (v = 1), pixel (i, j) at scalp UV
// (i / (width − 1), 1 − j / (height − 1)) as GrayImage::sample reads it.
std::string encode_map(const GrayImage& t, uint32_t kind, float low, float high);

// The schema: {"fields": [{path, type, stage, panel, paper, unit, min, max, min_open,
// choices, doc, default}], "stages": [...], "panels": [...], "sections": [{section, key,
// type, unit, min, max, min_open, soft_min, soft_max, doc, default}]}. Defaults are the
// values of Style{} (toml_to_json of style_field_toml); a section's numbers (the tools'
// sliders, section_schema()) those of BraidSpec{} and UpdoSpec{}.
nlohmann::json schema_json();

// The style's value of every field, as JSON keyed by path; file paths relative to
// `base_dir` when they lie under it.
nlohmann::json style_values_json(const Style& style, const std::filesystem::path& base_dir = {});

}  // namespace wisp
