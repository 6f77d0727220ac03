#pragma once
// The dataset spec (docs/dataset.md): a TOML file that says how many samples to make, from
// which base styles and heads, which style fields to vary and how, what to write per sample
// and from which cameras. Sample k is a pure function of (spec, k): its stream derives from
// the spec's seed and k, and each varied field draws from its own stream (seeded by the
// sample's seed and a hash of the field's path), so that adding a rule does not change the
// values the others draw.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "groom/style.hpp"

namespace wisp {

// One `[vary]` rule: a distribution over the style field at `path` (a style TOML path,
// "solve.stiffness"), applied with set_style_field.
struct VaryRule {
    enum class Kind { kUniform, kNormal, kLogUniform, kChoice };
    std::string path;
    Kind kind = Kind::kUniform;
    double a = 0, b = 0;               // uniform, log-uniform: [a, b]; normal: mean a, stddev b
    double lo = 0, hi = 0;             // normal: values are clamped to [lo, hi]
    bool integer = false;              // the field holds an integer: draws are rounded
    std::vector<std::string> choices;  // choice: the options as inline TOML values
    int line = 0;                      // in the spec file, for messages
};

// A picture parameter a `[render]` rule draws per sample (domain randomisation): its name,
// range and meaning. `shading` takes a choice of the renderer's models; the rest are numbers.
struct RenderField {
    const char* name;
    double lo, hi;     // the range a draw is clamped to (a normal's tails) and checked against
    double fallback;   // its value when no rule draws it (the renderer's own)
    const char* unit;  // for the docs
    const char* doc;
};
const std::vector<RenderField>& render_field_table();

// One `[[base]]`: a shipped preset or a style file, picked with probability weight / Σ.
struct BaseStyle {
    std::string name;  // "preset:short" or the style file's path as the spec gives it
    Style style;
    double weight = 1;
};

// One `[[head]]`: `head.*` style fields (inline TOML values) set on the sample's style, picked
// with probability weight / Σ. No fields: the base style's own head (by default the built-in).
struct HeadChoice {
    std::string name;                                         // "built-in" or the OBJ path
    std::vector<std::pair<std::string, std::string>> fields;  // (style path, TOML value)
    double weight = 1;
    int line = 0;
};

// One `[[camera]]`: a named view framed on the hair and head as `wisp render --view` frames
// it, turned about the framed box's centre by a uniform draw in ±azimuth degrees (about the
// Y axis) and ±elevation degrees, and moved by a factor in 1 ± distance.
struct CameraSpec {
    std::string view = "front";
    // What the view frames: "head", the hair and the head down to below the hair (as `wisp
    // render --view`), or "hair", the hair alone, centred and filling 95% of the picture's
    // tighter side after the turn's jitter (a hair-centred crop, as HairStep's and
    // NeuralHaircut's inputs are cut; the distance's jitter does not apply).
    bool hair_only = false;
    double azimuth = 0, elevation = 0, distance = 0;
    double fov_y_degrees = 30;
};

// The pictures and maps a sample can write per camera (dataset/targets.hpp says what each
// holds), by their names in `output.maps`.
enum class OutputMap {
    kPicture,
    kOrientation,
    kMask,
    kDepth,
    kStrand,
    kConfidence,
    kMatte,
    kStrandId,
    kDepthHairstep
};
struct OutputMapInfo {
    OutputMap map;
    const char* name;    // in output.maps
    const char* suffix;  // the file: cam<c><suffix>
    bool by_default;     // written when output.maps is not given
};
const std::vector<OutputMapInfo>& output_map_table();
// The map of that name, or null; with maps_only, the picture is not one.
const OutputMapInfo* find_output_map(const std::string& name, bool maps_only = false);
// Their names, comma-separated, for messages (the picture's too unless maps_only).
std::string output_map_names(bool maps_only = false);

// `[output]`: what each sample writes.
struct OutputSpec {
    std::vector<std::string> hair = {"hair"};  // extensions: hair, usda, npz, obj, ply
    int resample = 32;                         // .npz points per strand
    int width = 256, height = 256;             // pictures and maps, pixels
    uint32_t maps = default_maps();            // bit i: output_map_table()[i]
    // volume.npz (dataset/targets.hpp hair_volume): voxels along x, y, z (0: none), over the
    // box [volume_lo, volume_hi] in head units (p ↦ c + R·p of the scalp's sphere).
    Vec3i volume = Vec3i::Zero();
    Vec3f volume_lo{-2.5f, -5.f, -2.5f}, volume_hi{2.5f, 2.f, 2.5f};
    // scalp.npz (dataset/targets.hpp scalp_texture): texels a side (0: none), points per strand.
    int scalp_texture = 0, scalp_points = 32;
    bool has(OutputMap m) const { return maps >> static_cast<int>(m) & 1u; }
    static uint32_t default_maps() {
        uint32_t bits = 0;
        for (const OutputMapInfo& m : output_map_table())
            if (m.by_default) bits |= 1u << static_cast<int>(m.map);
        return bits;
    }
};

struct DatasetSpec {
    std::string source;              // names the spec in messages
    std::filesystem::path base_dir;  // relative paths in the spec resolve against it
    uint64_t samples = 1;
    uint64_t seed = 0;
    // How samples pick their base and head: kWeighted, each independently at random by the
    // weights; kStratified, by the weights but evenly over every run of samples (sample k at
    // the k-th point of the R2 low-discrepancy sequence, Roberts 2018: base and head each
    // within a few samples of their share in any first n samples, where independent draws
    // stray by about √n, and the pairs spread evenly);
    // kGrid, every (base, head) pair in turn, weights aside.
    enum class Sampling { kWeighted, kStratified, kGrid };
    Sampling sampling = Sampling::kWeighted;
    std::vector<BaseStyle> bases;   // at least one (default: the preset "default")
    std::vector<HeadChoice> heads;  // at least one (default: the base style's head)
    std::vector<VaryRule> vary;     // in the order of the file
    std::vector<VaryRule> render;   // [render]: path = a render_field_table() name
    std::vector<CameraSpec> cameras;
    OutputSpec output;
};

// Sets one drawn value (inline TOML) on a style with set_style_field. As `wisp generate
// --strands` does, a strand count below the style's wisp count lowers the wisp count to it
// (the issue's own example varies roots.strands of a preset with 3000 wisps).
void apply_draw(Style& style, const std::string& path, const std::string& toml_value,
                const std::string& source, const std::filesystem::path& base_dir);

// The most samples a dataset may have (sample folders are numbered with up to 9 digits).
inline constexpr uint64_t kMaxSamples = 1'000'000'000;

// Parses a spec. Every mistake throws wisp::Error "SOURCE:LINE: field 'F': REASON": unknown
// keys, wrong types, empty or negative weights, distributions whose ends or options the
// field does not accept (each is tried on every base style), unknown formats and views.
DatasetSpec parse_dataset_spec(std::string_view toml_text, const std::string& source,
                               const std::filesystem::path& base_dir);
// Reads (within the style reader's limits) and parses a spec file; relative paths resolve
// against `base_dir`, by default the file's folder.
DatasetSpec load_dataset_spec(const std::filesystem::path& path,
                              const std::filesystem::path& base_dir = {});

}  // namespace wisp
