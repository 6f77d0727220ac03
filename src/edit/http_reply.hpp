#pragma once
// The editor's JSON replies: a body, and an error as {"error": message, "field": name} with
// both quoted safely (excerpt). motion_routes.cpp uses these; server.cpp still has its own
// copy, left there while other branches edit the lines around it (merge it after them).
#include <httplib.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace wisp {

inline void send_json(httplib::Response& res, const nlohmann::json& j, int status = 200) {
    res.status = status;
    res.set_content(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                    "application/json");
}

inline void send_error(httplib::Response& res, int status, const std::string& message,
                       const std::string& field = {}) {
    nlohmann::json j{{"error", excerpt(message, 1000)}};
    if (!field.empty()) j["field"] = excerpt(field, 200);
    send_json(res, j, status);
}

}  // namespace wisp
