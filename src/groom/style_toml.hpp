#pragma once
// Reading styles from TOML (docs/style.md is the field-by-field reference) and the
// presets shipped inside the binary.
#include <filesystem>
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

// Reads and parses a style file.
Style load_style(const std::filesystem::path& path);

// The names of the shipped presets, sorted.
std::vector<std::string> preset_names();
// The TOML text of a shipped preset; throws wisp::Error listing the names if unknown.
std::string_view preset_text(const std::string& name);
// Parses a shipped preset.
Style load_preset(const std::string& name);

}  // namespace wisp
