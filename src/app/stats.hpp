#pragma once
// The figures of a run, written by --stats as JSON.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/hair.hpp"
#include "core/timer.hpp"

namespace wisp {

// Counts and bounding box of a hair: {"strands", "points", "wisps", "bbox": {min, max}}.
nlohmann::json hair_stats(const Hair& hair);

// {"stage": ms, ...} in stage order, plus "total".
nlohmann::json stage_stats(const StageTimes& times);

// Writes the JSON atomically, pretty-printed.
void write_json(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace wisp
