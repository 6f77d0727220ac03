#pragma once
// USD text layers (`.usda`) with BasisCurves prims.
//
// Writer: one layer, `defaultPrim = "hair"`, upAxis "Y" (or "Z", UsdaWriteOptions),
// metersPerUnit 0.01 (wisp's centimetres), `def Xform "hair"` holding `def BasisCurves
// "strands"` with the GroomAPI schema applied (Unreal's USD importer reads it as a groom,
// with primvars:groom_group_id 0 and primvars:groom_color per strand): type "cubic",
// basis "catmullRom", wrap "pinned" (the pinned Catmull-Rom spline passes through the
// end points, exactly wisp's spline, core/catmull_rom.hpp), curveVertexCounts, points,
// per-vertex widths, per-strand primvars:displayColor (or one constant color) and
// per-strand primvars:wisp_id when known; extent. Floats are written in their shortest
// form that reads back bit-exact.
//
// Reader: a tokenizer and parser for the usda text that BasisCurves layers use: nested
// def/over/class prims with `( ... )` metadata, attributes with custom/uniform
// qualifiers and any value type, `.timeSamples = { time: value, ... }`, `None`
// (blocked) values, `.connect`, relationships, list-ops, variantSets (skipped), strings
// ("...", '...', """..."""), asset and path literals, `#`, `//` and `/* */` comments
// anywhere (also inside arrays). Value of an attribute: the default value when one is
// authored and not blocked, else the earliest time sample (else none).
#include <array>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/hair.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

// One BasisCurves prim as authored (no unit or axis conversion). Unauthored tokens take
// the schema fallbacks: type "cubic", basis "bezier", wrap "nonperiodic".
struct UsdCurves {
    std::string path;  // prim path, e.g. "/World/curve"
    size_t line = 0;   // line of the prim's `def` in the file
    std::string type = "cubic", basis = "bezier", wrap = "nonperiodic";
    std::vector<int> counts;                  // curveVertexCounts  #C
    std::vector<Vec3f> points;                // points             #P (should be sum of counts)
    std::vector<float> widths;                // widths, as authored (size depends on interpolation)
    std::string widths_interpolation;         // as authored, "" when not
    std::vector<Vec3f> display_color;         // primvars:displayColor (indices applied)
    std::string display_color_interpolation;  // as authored, "" when not
    std::vector<int32_t> wisp_id;             // primvars:wisp_id
    std::string wisp_id_interpolation;
    bool has_normals = false;  // ribbons: normals are read past, not kept
    bool guide = false;        // primvars:groom_guide is 1 on every curve (Unreal's guides)
};

// One explicit set of USD value clips, authored on prim `prim` as
// `clips = { dictionary <name> = { ... } }` (the clips API's metadata, as written).
struct UsdClipSet {
    std::string prim;  // prim path holding the metadata, e.g. "/hair"
    std::string name;  // clip set, e.g. "default"
    size_t line = 0;
    std::vector<std::string> asset_paths;       // assetPaths, as authored
    std::vector<std::array<double, 2>> active;  // active: (stage time, asset index)
    std::vector<std::array<double, 2>> times;   // times: (stage time, clip time)
    std::string prim_path;                      // primPath: `prim` inside each clip
    std::string manifest, template_asset_path;  // as authored, "" when not
};

// Layer metadata wisp uses, the BasisCurves prims in file order and the value clip sets.
struct UsdaLayer {
    std::string up_axis = "Y";      // "Y" or "Z"; USD's fallback when unauthored is Y
    double meters_per_unit = 0.01;  // USD's fallback (centimetres)
    double time_codes_per_second = 24.0;
    double start_time_code = 0;  // startTimeCode (0 when unauthored)
    std::vector<UsdCurves> curves;
    std::vector<UsdClipSet> clip_sets;
};

// Parses usda text; `name` (the file) starts every error message ("name:line:col: ...").
// Every BasisCurves prim is returned, valid or not (see usd_curves_problem).
UsdaLayer parse_usda(std::string_view text, const std::string& name);
UsdaLayer read_usda_layer(const std::filesystem::path& path);
std::vector<UsdCurves> read_usda_curves(const std::filesystem::path& path);

// Segments of curve `curve` under USD's rules: linear nonperiodic n-1, periodic n;
// cubic bezier nonperiodic (n-4)/3+1, periodic n/3; bspline and catmullRom nonperiodic
// n-3, periodic n, pinned n-1; pinned bezier and pinned linear behave as nonperiodic.
// 0 for a curve below its minimum vertex count.
size_t usd_segment_count(const UsdCurves& c, size_t curve);
// Data sizes for the four interpolations: constant 1, uniform #C, varying sum of
// segments+1 (periodic: segments), vertex sum of counts.
size_t usd_interpolation_size(const UsdCurves& c, std::string_view interpolation);
// The interpolation a primvar of n values has ("constant", "uniform", "varying",
// "vertex", checked in that order), or "" when none fits.
std::string usd_interpolation_for_size(const UsdCurves& c, size_t n);
// Why the prim cannot be read as strands ("curve 3 has 1 vertex, ..."), or "" if it can.
std::string usd_curves_problem(const UsdCurves& c);

// Strands of every BasisCurves prim of the layer, converted to centimetres and Y up.
// Pinned catmullRom curves keep their control points; linear curves keep their points;
// bezier, bspline and non-pinned catmullRom curves are sampled `samples_per_segment`
// times per segment; periodic curves are closed (first point repeated at the end).
// Widths of any interpolation become per-point widths; displayColor becomes per-strand
// colors (the first value of a curve for vertex/varying). Throws wisp::Error naming the
// file and prim if any prim is invalid.
Hair hair_from_usda(const UsdaLayer& layer, const std::string& name, int samples_per_segment = 8);
Hair read_usda(const std::filesystem::path& path);

struct UsdaWriteOptions {
    // Z up for Z-up pipelines: points (and extent) turned (x, y, z) -> (x, -z, y), so +Y
    // becomes +Z and the face looks along -Y; upAxis "Z". read_usda turns it back exactly.
    bool z_up = false;
    // Guide strands (the masters, one per wisp), written as a second BasisCurves prim
    // "/hair/guides" flagged primvars:groom_guide = 1; render strand s is driven by guide
    // hair.wisp[s] (Unreal's groom_closest_guides, weight 1), so the hair needs wisp ids below
    // the guide count. GroomAPI then moves to the Xform "/hair", so that Unreal imports both
    // prims as one groom. Null: no guides.
    const Hair* guides = nullptr;
    // A head mesh written as `def Mesh "head"` beside "/hair" (same units and up axis), its
    // scalp faces (`head_scalp`, indices into head->faces) as a GeomSubset "scalp". Null: none.
    const Mesh* head = nullptr;
    std::span<const uint32_t> head_scalp;
    // Significant digits of the strands' floats (points, widths, colors, root UVs), 1 … 9,
    // trading exactness for size; 0 (the default): the shortest form that reads back
    // bit-exact. A value v is then written as the nearest decimal of `precision` digits,
    // within half a unit of its last digit (|error| <= 0.5·10^(1−precision)·|v|, rounded to
    // float); the extent, written exact, is grown to hold every rounded point.
    int precision = 0;
};
// The largest UsdaWriteOptions::precision (9 digits always read back exactly).
inline constexpr int kMaxUsdaPrecision = 9;

// The usda layer described above. Throws for a strand of fewer than 2 points (a pinned
// cubic curve needs 2).
std::string encode_usda(const Hair& hair, const std::string& name = "hair",
                        const UsdaWriteOptions& options = {});
void write_usda(const std::filesystem::path& path, const Hair& hair,
                const UsdaWriteOptions& options = {});

// Animation: frames share their topology (offsets); frame i is time code i, at `fps`
// time codes per second. points and extent are time-sampled; counts, widths, colors and
// wisp ids come from frame 0.
std::string encode_usda_animation(const std::vector<Hair>& frames, double fps,
                                  const std::string& name = "hair");
void write_usda_animation(const std::filesystem::path& path, const std::vector<Hair>& frames,
                          double fps);

// The same file written frame by frame, so a long animation never holds every frame in
// memory: add() each of the `frames` frames in order, then finish() commits the file (until
// then it is a temporary beside the target; destroying the writer unfinished removes it).
class UsdaAnimationWriter {
  public:
    // Guides mode (`wisp animate --guides`), with `strands`: the frames are guide strands,
    // animated as the prim "/hair/guides" (primvars:groom_guide = 1), and `strands` the
    // render strands at rest, written once as "/hair/strands" with what rebuilds them from
    // the guides: strand s follows guide strands.wisp[s] (groom_closest_guides, weight 1),
    // its rest points and root UV (UsdaWriteOptions::guides' layout, GroomAPI on "/hair").
    // `precision`: significant digits of the strands' floats, as UsdaWriteOptions::precision
    // (0: the shortest exact form); each frame's extent holds its rounded points.
    UsdaAnimationWriter(const std::filesystem::path& path, const Hair& first, double fps,
                        size_t frames, const Hair* strands = nullptr, int precision = 0);
    ~UsdaAnimationWriter();
    void add(const Hair& frame);
    void finish();

  private:
    struct Impl;
    std::filesystem::path path_;
    std::unique_ptr<Impl> impl_;
};

// Animation as USD value clips, so a long animation is written frame by frame and loads
// lazily: frame i goes to its own layer `<stem>.<iiii>.usda` beside `path` (points and
// extent at time code i under `over "hair" { over BasisCurves "strands" }`) as add() gets it;
// finish() writes `<stem>.manifest.usda` (the animated attributes, declared) and the small
// top-level layer at `path`: the topology, widths and colors of frame 0 with `points` and
// `extent` declared, and on /hair the metadata `clips = { dictionary default = { active,
// assetPaths, manifestAssetPath, primPath, times } }` (frame i active from time code i,
// clip time i). Each file is written atomically; destroying the writer unfinished, or
// SIGINT/SIGTERM/SIGHUP, removes the frames already written.
class UsdaClipWriter {
  public:
    // `strands`: guides mode, and `precision`, as UsdaAnimationWriter's (the clips animate
    // "/hair/guides").
    UsdaClipWriter(const std::filesystem::path& path, const Hair& first, double fps, size_t frames,
                   const Hair* strands = nullptr, int precision = 0);
    ~UsdaClipWriter();
    void add(const Hair& frame);
    void finish();
    // The file frame `i` of an animation of `frames` frames written to `path` goes to.
    static std::filesystem::path frame_path(const std::filesystem::path& path, size_t i,
                                            size_t frames);

  private:
    struct Impl;
    std::filesystem::path path_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace wisp
