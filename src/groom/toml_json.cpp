#include "groom/toml_json.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

void to_toml(const nlohmann::json& v, const std::string& field, int depth, std::string& out) {
    if (depth > 8) fail("field '", excerpt(field), "': the value nests deeper than 8 levels");
    switch (v.type()) {
        case nlohmann::json::value_t::boolean:
            out += v.get<bool>() ? "true" : "false";
            return;
        case nlohmann::json::value_t::number_integer:
            out += std::to_string(v.get<int64_t>());
            return;
        case nlohmann::json::value_t::number_unsigned:
            out += std::to_string(v.get<uint64_t>());
            return;
        case nlohmann::json::value_t::number_float: {
            const double d = v.get<double>();
            if (!std::isfinite(d)) fail("field '", excerpt(field), "': must be a finite number");
            // The shortest text that reads back to the same double (0.55, not
            // 0.55000000000000004): what a user wrote comes back as written on Save.
            char buffer[32];
            const auto end = std::to_chars(buffer, buffer + sizeof buffer - 1, d).ptr;
            *end = '\0';
            out += buffer;
            // TOML needs a fraction or exponent for a float; 2.0 prints as "2".
            if (!std::strpbrk(buffer, ".eEn")) out += ".0";
            return;
        }
        case nlohmann::json::value_t::string:
            out += toml_quote(v.get<std::string>());
            return;
        case nlohmann::json::value_t::array: {
            out += "[";
            bool first = true;
            for (const auto& e : v) {
                if (!first) out += ", ";
                first = false;
                to_toml(e, field, depth + 1, out);
            }
            out += "]";
            return;
        }
        case nlohmann::json::value_t::object: {
            out += "{ ";
            bool first = true;
            for (const auto& [k, e] : v.items()) {
                if (!first) out += ", ";
                first = false;
                out += toml_quote(k) + " = ";
                to_toml(e, field, depth + 1, out);
            }
            out += " }";
            return;
        }
        default:
            fail("field '", excerpt(field), "': a value is required, got null");
    }
}

}  // namespace

toml::table parse_toml(std::string_view text, const std::string& source, size_t max_description) {
    try {
        return toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        std::string description(e.description());
        std::replace(description.begin(), description.end(), '\n', ' ');
        fail(source, ":", e.source().begin.line, ":", e.source().begin.column,
             ": TOML syntax error: ", excerpt(description, max_description));
    }
}

nlohmann::json toml_to_json(const toml::node& node) {
    if (const auto* s = node.as_string()) return s->get();
    if (const auto* i = node.as_integer()) return i->get();
    if (const auto* f = node.as_floating_point()) return f->get();
    if (const auto* b = node.as_boolean()) return b->get();
    if (const auto* a = node.as_array()) {
        nlohmann::json out = nlohmann::json::array();
        for (const toml::node& e : *a)
            out.push_back(toml_to_json(e));
        return out;
    }
    if (const auto* t = node.as_table()) {
        nlohmann::json out = nlohmann::json::object();
        for (auto&& [k, v] : *t)
            out[std::string(k.str())] = toml_to_json(v);
        return out;
    }
    return nullptr;
}

nlohmann::json toml_value_to_json(const std::string& toml_value) {
    const toml::table t = toml::parse("value = " + toml_value);
    return toml_to_json(*t.get("value"));
}

std::string json_to_toml_value(const nlohmann::json& value, const std::string& field) {
    std::string out;
    to_toml(value, field, 0, out);
    return out;
}

}  // namespace wisp
