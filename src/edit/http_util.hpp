#pragma once
// The editor server's small HTTP helpers, shared by its route files (server.cpp,
// routes_features.cpp): JSON answers, 400s naming the field, and file names that stay
// inside the style's folder.
#include <httplib.h>

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace wisp {

void send_json(httplib::Response& res, const nlohmann::json& j, int status = 200);
// {"error": message, "field": field} (field left out when empty), with `status`.
void send_error(httplib::Response& res, int status, const std::string& message,
                const std::string& field = {});

// `name` as a file of the style's folder `dir`: a plain file name (letters, digits, '.', '-',
// '_', ' '; not hidden, no separators, so nothing outside the folder), at most 128 bytes,
// ending in one of `extensions`. Throws wisp::Error saying what is wrong.
std::filesystem::path file_in_folder(const std::filesystem::path& dir, const std::string& name,
                                     std::initializer_list<std::string_view> extensions);

// "stem" of "stem.toml".
std::string stem_of(const std::string& toml_name);

// A finite number from a query parameter (`fallback` when absent), or throws naming it.
float query_number(const httplib::Request& req, const char* name, float fallback);

}  // namespace wisp
