#pragma once
// The one description of every style field: its TOML path, type, range, unit, one line of
// documentation, the paper's section, the editor panel it sits in and the first pipeline
// stage it feeds. The TOML reader (style_toml.cpp) checks values against it, `wisp schema`
// and the editor's panels are generated from it, and a test holds docs/style.md to it.
// Defaults are not repeated here: a field's default is its value in a default `Style`
// (style.hpp), read through the field's accessor.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "groom/style.hpp"

namespace wisp {

// How a field is written in TOML (docs/style.md "Value forms").
enum class FieldType {
    kNumber,        // finite number in [lo, hi] (lo excluded when lo_open)
    kInteger,       // integer in [lo, hi]
    kSeed,          // integer in [0, 2⁶³ − 1]
    kBoolean,       //
    kString,        // non-empty when `positive`
    kPath,          // non-empty, relative to the style file
    kChoice,        // one of `choices`
    kPoint,         // [x, y, z], each within [lo, hi]
    kDirection,     // [x, y, z], non-zero
    kMap,           // a scalar map over the scalp (ScalarMap); [lo, hi] bounds its values
    kDistribution,  // a distribution (Distribution) with domain [lo, hi]
    kRadii,         // a number or an array of numbers, each in (lo, hi]
    kPolyline,      // an array of [x, y, z] points
    kFieldTerms,    // [[solve.field]]: an array of tables
    kGroups,        // [[group]], [[tie]], [[braid]], [[updo]], [[comb]]: arrays of tables
};

// The pipeline stages (DESIGN.md), in order. A field feeds the stage it names and, through
// its output, every later one: a change re-runs from there.
enum class Stage : uint8_t {
    kHead,     // the head mesh, scalp and head field
    kRoots,    // §2.3
    kMasters,  // §2.2
    kSolve,    // §3, §4: the styling field, the density grid and the solver
    kMembers,  // §2.1, then the cut and the push out of the head
    kColor,    // §5
    kNone,     // feeds no grooming stage (the name, animation)
};
inline constexpr int kStageCount = 6;  // kHead … kColor

// The largest coordinate or radius (cm or head units) a style may give, the reader's and the
// schema's bound.
inline constexpr double kMaxStyleCoordinate = 1e4;
const char* stage_name(Stage stage);

// A field's storage in Style, for the field types with one place to live.
using FieldRef = std::variant<std::monostate, float*, int*, uint64_t*, bool*, std::string*,
                              std::filesystem::path*, Vec3f*, ScalarMap*, Distribution*,
                              std::vector<float>*, std::vector<Vec3f>*, std::vector<FieldTerm>*>;

struct StyleField {
    std::string_view path;  // TOML path: "solve.stiffness"
    FieldType type;
    Stage stage;             // the first stage the field feeds
    std::string_view panel;  // the editor panel: the paper's modelling step
    std::string_view paper;  // where the paper defines it ("§3.2 eq. (5)"), or ""
    std::string_view unit;   // "cm", "degrees", "radians", "1/s", … or "" (dimensionless)
    // kNumber, kInteger, kPoint: the allowed range; kMap: of its values; kDistribution: its
    // domain; kRadii: of each radius (lo excluded).
    double lo = 0, hi = 0;
    bool lo_open = false;  // kNumber, kMap: lo itself is excluded
    // kString: must not be empty; kMap: a constant must be > lo and low, high not both lo
    // (density); kDistribution: a constant, or max, must be > lo (lengths).
    bool positive = false;
    std::vector<std::string_view> choices;  // kChoice, in the order the docs list them
    std::string_view doc;                   // one line
    FieldRef (*ref)(Style&) = nullptr;      // the storage (not kChoice, kGroups)
    // kChoice: the index in `choices` of the style's value (−1: none, as for color.preset,
    // which sets other fields and is not kept), and setting it.
    int (*get_choice)(const Style&) = nullptr;
    void (*set_choice)(Style&, int) = nullptr;
    float map_low = 0, map_high = 1;  // kMap: [low, high] of image and procedural maps
};

// Every field, section by section in the order docs/style.md lists them. The sections of
// a style are the prefixes of these paths.
std::span<const StyleField> style_schema();

// The field at a TOML path ("solve.stiffness"), or null.
const StyleField* find_style_field(std::string_view path);

// The section part of a path ("solve" for "solve.stiffness", "" for "seed") and the key.
std::string_view field_section(std::string_view path);
std::string_view field_key(std::string_view path);

// The keys a section may hold (fields and sub-sections), in schema order; empty if
// `section` is no section.
const std::vector<std::string>& section_keys(std::string_view section);
// The sections, "" (the top level) first.
const std::vector<std::string>& style_sections();

// A number of a hairdressing section ([[braid]], [[updo]]: "braid", "width") as the reader
// checks it and the editor's tools set it with a slider. The sections are arrays of tables,
// not fields of Style, so their keys are described here rather than in style_schema();
// defaults are those of BraidSpec{} and UpdoSpec{} (groom/hairdressing.hpp). Positions and
// sizes are in head units (the sections' head_relative default).
struct SectionField {
    std::string_view section;         // "braid", "updo"
    std::string_view key;             // "width"
    FieldType type;                   // kNumber or kInteger
    std::string_view unit;            // "head units" or "" (dimensionless)
    double lo = 0, hi = 0;            // the allowed range, as the reader checks it
    bool lo_open = false;             // lo itself is excluded
    double soft_lo = 0, soft_hi = 0;  // the slider's range: where a useful value lies
    std::string_view doc;             // one line
    double (*get_default)() = nullptr;
};

// The numbers of [[braid]] and [[updo]], section by section in docs/style.md's order.
std::span<const SectionField> section_schema();
// The number `key` of `section`, or null.
const SectionField* find_section_field(std::string_view section, std::string_view key);

// The type's name in `wisp schema`, the editor and the Python API ("number", "field_terms", …).
const char* field_type_name(FieldType type);

}  // namespace wisp
