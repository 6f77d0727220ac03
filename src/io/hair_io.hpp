#pragma once
// Hair files in and out, by extension. Each format has its own header with the byte or
// text layout it reads and writes (cyhair.hpp, usda.hpp, obj_curves.hpp, ply.hpp,
// hairsalon.hpp); docs/formats.md describes them for users.
//
// Every reader throws wisp::Error with a one-line message naming the file, the location
// (byte offset or line) and what is wrong; every writer writes atomically (a temporary
// file renamed over the target).
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/hair.hpp"
#include "core/math.hpp"
#include "geometry/mesh.hpp"
#include "io/export_camera.hpp"

namespace wisp {

enum class HairFormat { kUsda, kHair, kObj, kPly, kData, kRib, kPbrt, kNpz };

// "usda", "hair", "obj", "ply", "data", "rib", "pbrt", "npz" (the last three are write-only:
// scenes for RenderMan and pbrt-v4, and numpy arrays).
const char* hair_format_name(HairFormat format);

// The format of path's extension (case-insensitive): .usda, .hair, .obj, .ply, .data, .rib,
// .pbrt, .npz.
// Throws wisp::Error naming the path and listing the supported extensions.
HairFormat hair_format_from_path(const std::filesystem::path& path);

// Reads any supported format (a .usda layer: every BasisCurves prim, see read_usda).
Hair read_hair(const std::filesystem::path& path);

struct HairWriteOptions {
    bool obj_segments = false;  // .obj: one `l a b` per segment instead of one `l` per strand
    bool usda_z_up = false;     // .usda: Z up, (x, y, z) -> (x, -z, y) (UsdaWriteOptions)
    int usda_precision = 0;     // .usda: significant digits, 0 = exact (UsdaWriteOptions)
    ExportCamera camera;        // .rib, .pbrt: the scene's camera
    // .usda: guide strands and a head mesh with its scalp faces (UsdaWriteOptions).
    const Hair* usda_guides = nullptr;
    const Mesh* usda_head = nullptr;
    std::span<const uint32_t> usda_head_scalp;
    // .npz and .data: points per strand after resampling; 0 = the format's own (.npz 32,
    // .data 100, the USC-HairSalon data set's).
    int resample_points = 0;
};

// Writes any format by its extension.
void write_hair(const std::filesystem::path& path, const Hair& hair,
                const HairWriteOptions& options = {});

// One BasisCurves prim of a .usda file, as `wisp info` lists it.
struct UsdPrimSummary {
    std::string path, type, basis, wrap;
    size_t curves = 0, points = 0, segments = 0;
    std::string widths_interpolation;  // as authored or inferred from the size; "" if none
    bool has_colors = false;
    std::string problem;  // why the prim cannot be read as strands, "" if it can
};

// What `wisp info` prints about a hair file.
struct HairFileInfo {
    std::filesystem::path path;
    HairFormat format = HairFormat::kHair;
    uint64_t file_bytes = 0;
    size_t strands = 0, points = 0;         // of the Hair that read_hair returns
    size_t min_points = 0, max_points = 0;  // per strand
    double mean_points = 0;
    Box3 bounds;  // centimetres
    bool has_widths = false, has_colors = false, has_wisp_ids = false;
    float min_width = 0, max_width = 0;  // cm, of the widths array or the default width
    size_t skipped_strands = 0;          // .data: bare roots (0 or 1 vertex) skipped
    // .usda: every BasisCurves prim. When one is invalid the strand figures above count
    // the control points of the valid prims only.
    std::vector<UsdPrimSummary> usd_prims;
};

// Reads the file and summarizes it; an invalid .usda prim is reported in its summary
// rather than thrown.
HairFileInfo hair_file_info(const std::filesystem::path& path);

// A short multi-line human-readable report of info.
std::string describe(const HairFileInfo& info);

}  // namespace wisp
