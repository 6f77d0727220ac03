#pragma once
// Values of the dataset spec as inline TOML text, the form set_style_field takes: a choice's
// options as the spec wrote them, and drawn numbers written so that they read back exactly.
#include <string>

#include <toml++/toml.h>

namespace wisp {

// A TOML node as an inline value: strings quoted, numbers in their shortest exact form,
// arrays and tables inline ("[1, 2]", "{ procedural = \"crown\" }").
std::string toml_value_text(const toml::node& node);

// A drawn number as TOML: an integer (rounded to nearest) when `integer`, else the shortest
// text that reads back to the same float (style fields are floats).
std::string format_draw(double value, bool integer);

}  // namespace wisp
