#pragma once
// TOML text and values shared by every TOML reader (styles, dataset specs) and by what turns
// TOML into JSON and back (the editor's wire, the dataset's manifest and metadata).
#include <string>
#include <string_view>

#include <toml++/toml.h>
#include <nlohmann/json.hpp>

namespace wisp {

// Parses a TOML document. A syntax error throws wisp::Error
// "SOURCE:LINE:COLUMN: TOML syntax error: DESCRIPTION" (on one line, the description cut to
// `max_description` bytes).
toml::table parse_toml(std::string_view text, const std::string& source,
                       size_t max_description = 300);

// A TOML node as JSON: strings, integers, floats, booleans, arrays and tables as themselves;
// dates and times as null.
nlohmann::json toml_to_json(const toml::node& node);

// An inline TOML value ("[1, 2]", "{ procedural = \"crown\" }") as JSON, and JSON as an inline
// TOML value (for set_style_field). Throws wisp::Error naming `field` for JSON TOML cannot
// hold (null, a number that is not finite, nesting deeper than 8).
nlohmann::json toml_value_to_json(const std::string& toml_value);
std::string json_to_toml_value(const nlohmann::json& value, const std::string& field);

}  // namespace wisp
