#include "dataset/toml_value.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "groom/style_toml.hpp"

namespace wisp {

namespace {

std::string shortest(double v) {
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
    std::string s(buffer, r.ptr);
    // TOML floats need a fraction or an exponent: "2" would read as an integer.
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

}  // namespace

std::string toml_value_text(const toml::node& node) {
    if (const auto* s = node.as_string()) return toml_quote(s->get());
    if (const auto* i = node.as_integer()) return std::to_string(i->get());
    if (const auto* f = node.as_floating_point()) {
        const double v = f->get();
        if (std::isnan(v)) return "nan";
        if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
        return shortest(v);
    }
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* a = node.as_array()) {
        std::string out = "[";
        for (size_t i = 0; i < a->size(); ++i)
            out += (i ? ", " : "") + toml_value_text((*a)[i]);
        return out + "]";
    }
    if (const auto* t = node.as_table()) {
        std::string out = "{ ";
        bool first = true;
        for (const auto& [key, value] : *t) {
            out += (first ? "" : ", ") + toml_quote(key.str()) + " = " + toml_value_text(value);
            first = false;
        }
        return out + (first ? "}" : " }");
    }
    return "\"(a date or time)\"";
}

std::string format_draw(double value, bool integer) {
    if (integer) return std::to_string(static_cast<int64_t>(std::llround(value)));
    const float f = static_cast<float>(value);
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, f);
    std::string s(buffer, r.ptr);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

}  // namespace wisp
