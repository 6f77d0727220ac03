#pragma once
// Reading styles from TOML (docs/style.md is the field-by-field reference) and the
// presets shipped inside the binary.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "groom/style.hpp"

namespace wisp {

// Parses a style. `source` names it in errors ("ponytail.toml", "preset 'curly'"); relative
// paths inside (images, OBJ heads) resolve against `base_dir`. Unknown fields, wrong types,
// out-of-range values and NaN throw wisp::Error naming source, line, field and the allowed
// range. An empty text is a valid style (all defaults).
Style parse_style(std::string_view toml_text, const std::string& source,
                  const std::filesystem::path& base_dir = {});

// A TOML basic string of s: quotes, backslashes and control characters escaped.
std::string toml_quote(std::string_view s);

// Reads and parses a style file.
Style load_style(const std::filesystem::path& path);

// The names of the shipped presets, sorted.
std::vector<std::string> preset_names();
// The TOML text of a shipped preset; throws wisp::Error listing the names if unknown.
std::string_view preset_text(const std::string& name);
// Parses a shipped preset.
Style load_preset(const std::string& name);

struct StyleField;

// The value of one schema field of `style` as an inline TOML value ("0.5", "[0, 1, 0]",
// "{ procedural = \"crown\", low = 0, high = 1 }"), which parse_style reads back to the same
// value; file paths are written relative to `base_dir` when they lie under it. Empty for a
// field with nothing to write (an empty path, color.preset, the constraint groups).
std::string style_field_toml(const Style& style, const StyleField& field,
                             const std::filesystem::path& base_dir = {});

// Calls `f` on each path of a file the style reads when hair is grown from it (the head and
// body meshes, map and mask images, field files), in the schema's order; `f` may change it.
void for_each_style_file(Style& style, const std::function<void(std::filesystem::path&)>& f);
// Those files, once each: what a style needs beside it.
std::vector<std::filesystem::path> style_files(const Style& style);

// The whole style as a TOML file that parse_style (with the same base_dir) reads back to the
// same Style: every field whose value differs from the default, section by section, then
// the constraint groups as [[group]] entries (the hairdressing sections written out as the
// groups they expand into).
std::string style_to_toml(const Style& style, const std::filesystem::path& base_dir = {});

// Constraint groups as [[group]] entries that parse_style reads back to the same groups.
std::string groups_to_toml(const std::vector<GroupSpec>& groups,
                           const std::filesystem::path& base_dir = {});

// Sets the field at `path` ("solve.stiffness") from an inline TOML value with the reader's
// checks and messages, then the checks between the fields of its section: on error, throws
// wisp::Error "SOURCE: field 'PATH': REASON" and leaves `style` unchanged. The editor and
// the Python API set fields through this.
void set_style_field(Style& style, std::string_view path, std::string_view toml_value,
                     const std::string& source, const std::filesystem::path& base_dir = {});

}  // namespace wisp
