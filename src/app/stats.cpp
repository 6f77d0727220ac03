#include "app/stats.hpp"

#include <unordered_set>

#include "core/atomic_file.hpp"

namespace wisp {

nlohmann::json hair_stats(const Hair& hair) {
    nlohmann::json j;
    j["strands"] = hair.strand_count();
    j["points"] = hair.point_count();
    std::unordered_set<int32_t> wisps(hair.wisp.begin(), hair.wisp.end());
    wisps.erase(-1);
    j["wisps"] = wisps.size();
    const Box3 box = hair.bounds();
    if (!box.empty()) {
        j["bbox"] = {{"min", {box.lo.x(), box.lo.y(), box.lo.z()}},
                     {"max", {box.hi.x(), box.hi.y(), box.hi.z()}},
                     {"units", "cm"}};
    }
    return j;
}

nlohmann::json stage_stats(const StageTimes& times) {
    nlohmann::json j = nlohmann::json::object();
    double total = 0;
    for (const auto& [name, ms] : times) {
        j[name] = ms;
        total += ms;
    }
    j["total"] = total;
    return j;
}

void write_json(const std::filesystem::path& path, const nlohmann::json& json) {
    write_file_atomic(path,
                      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace wisp
