#include "edit/wire.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "groom/maps.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the wire format is little-endian: add byte swaps for this machine");

void put_u32(std::string& out, uint32_t v) {
    out.append(reinterpret_cast<const char*>(&v), 4);
}
void put_f32(std::string& out, float v) {
    out.append(reinterpret_cast<const char*>(&v), 4);
}

nlohmann::json node_to_json(const toml::node& node) {
    if (const auto* s = node.as_string()) return s->get();
    if (const auto* i = node.as_integer()) return i->get();
    if (const auto* f = node.as_floating_point()) return f->get();
    if (const auto* b = node.as_boolean()) return b->get();
    if (const auto* a = node.as_array()) {
        nlohmann::json out = nlohmann::json::array();
        for (const toml::node& e : *a)
            out.push_back(node_to_json(e));
        return out;
    }
    if (const auto* t = node.as_table()) {
        nlohmann::json out = nlohmann::json::object();
        for (auto&& [k, v] : *t)
            out[std::string(k.str())] = node_to_json(v);
        return out;
    }
    return nullptr;
}

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
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "%.17g", d);
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

std::vector<uint32_t> strand_order(size_t n) {
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i)
        order[i] = static_cast<uint32_t>(i);
    Rng rng(0x5eed, Stream::kMisc, 0xed17);
    for (size_t i = n; i > 1; --i) {
        const size_t j = static_cast<size_t>(rng.next() % i);  // bias below 2⁻⁴⁰
        std::swap(order[i - 1], order[j]);
    }
    return order;
}

std::string encode_strands(const Hair& hair, size_t limit, size_t all) {
    const size_t total = hair.strand_count();
    const size_t count = std::min(limit, total);
    const std::vector<uint32_t> order = strand_order(total);
    size_t points = 0;
    for (size_t i = 0; i < count; ++i)
        points += hair.strand_size(order[i]);
    std::string out;
    out.reserve(24 + 4 * (count + 1) + 12 * points + 12 * count);
    out += "WISPHAIR";
    put_u32(out, 1);
    put_u32(out, static_cast<uint32_t>(count));
    put_u32(out, static_cast<uint32_t>(points));
    put_u32(out, static_cast<uint32_t>(all ? all : total));
    uint32_t offset = 0;
    put_u32(out, 0);
    for (size_t i = 0; i < count; ++i) {
        offset += hair.strand_size(order[i]);
        put_u32(out, offset);
    }
    for (size_t i = 0; i < count; ++i)
        for (const Vec3f& p : hair.strand(order[i]))
            for (int c = 0; c < 3; ++c)
                put_f32(out, p[c]);
    for (size_t i = 0; i < count; ++i) {
        const Vec3f color = hair.color_of(order[i]);
        for (int c = 0; c < 3; ++c)
            put_f32(out, color[c]);
    }
    return out;
}

void encode_frame(uint32_t frame, std::span<const Vec3f> points, std::string& out) {
    static_assert(sizeof(Vec3f) == 12, "positions are copied as float32 triples");
    out.resize(20 + 12 * points.size());
    std::memcpy(out.data(), "WISPFRAM", 8);
    const uint32_t header[3] = {1, frame, static_cast<uint32_t>(points.size())};
    std::memcpy(out.data() + 8, header, sizeof header);
    if (!points.empty()) std::memcpy(out.data() + 20, points.data(), 12 * points.size());
}

std::string encode_masters(const Masters& masters) {
    Hair hair;
    hair.points = masters.control;
    hair.offsets.resize(masters.count() + 1);
    for (size_t w = 0; w <= masters.count(); ++w)
        hair.offsets[w] = static_cast<uint32_t>(w * masters.points);
    hair.colors.assign(masters.count(), Vec3f(0.55f, 0.55f, 0.6f));
    return encode_strands(hair, masters.count());
}

std::string encode_head(const Mesh& mesh, const std::vector<uint8_t>& scalp_faces) {
    std::string out = "WISPHEAD";
    put_u32(out, 1);
    put_u32(out, static_cast<uint32_t>(mesh.vertices.size()));
    put_u32(out, static_cast<uint32_t>(mesh.faces.size()));
    for (const Vec3f& v : mesh.vertices)
        for (int c = 0; c < 3; ++c)
            put_f32(out, v[c]);
    for (const Vec3i& f : mesh.faces)
        for (int c = 0; c < 3; ++c)
            put_u32(out, static_cast<uint32_t>(f[c]));
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        out += static_cast<char>(f < scalp_faces.size() ? scalp_faces[f] : 0);
    return out;
}

std::string encode_map(const GrayImage& t, uint32_t kind, float low, float high) {
    std::string out("WISPMAP\0", 8);
    put_u32(out, 1);
    put_u32(out, static_cast<uint32_t>(t.width));
    put_u32(out, static_cast<uint32_t>(t.height));
    put_u32(out, kind);
    put_f32(out, low);
    put_f32(out, high);
    for (const float v : t.values)
        out += static_cast<char>(std::lround((v > 0.f ? std::min(v, 1.f) : 0.f) * 255.f));
    return out;
}

nlohmann::json toml_value_to_json(const std::string& toml_value) {
    const toml::table t = toml::parse("value = " + toml_value);
    return node_to_json(*t.get("value"));
}

std::string json_to_toml_value(const nlohmann::json& value, const std::string& field) {
    std::string out;
    to_toml(value, field, 0, out);
    return out;
}

nlohmann::json schema_json() {
    const Style defaults;
    nlohmann::json fields = nlohmann::json::array();
    nlohmann::json panels = nlohmann::json::array();
    for (const StyleField& f : style_schema()) {
        nlohmann::json j;
        j["path"] = f.path;
        j["type"] = field_type_name(f.type);
        j["stage"] = stage_name(f.stage);
        j["panel"] = f.panel;
        j["paper"] = f.paper;
        j["unit"] = f.unit;
        j["doc"] = f.doc;
        if (f.type == FieldType::kNumber || f.type == FieldType::kInteger ||
            f.type == FieldType::kMap || f.type == FieldType::kDistribution ||
            f.type == FieldType::kRadii || f.type == FieldType::kPoint) {
            j["min"] = f.lo;
            j["max"] = f.hi;
            j["min_open"] = f.lo_open;
        }
        if (f.type == FieldType::kChoice) j["choices"] = f.choices;
        if (f.type == FieldType::kMap) {  // the map control's procedural names and its ramp
            j["procedural"] = procedural_map_names();
            j["map_low"] = f.map_low;
            j["map_high"] = f.map_high;
        }
        const std::string text = style_field_toml(defaults, f);
        j["default"] = text.empty() ? nlohmann::json() : toml_value_to_json(text);
        fields.push_back(std::move(j));
        if (std::find(panels.begin(), panels.end(), f.panel) == panels.end())
            panels.push_back(f.panel);
    }
    nlohmann::json stages = nlohmann::json::array();
    for (int s = 0; s <= kStageCount; ++s)
        stages.push_back(stage_name(Stage(s)));
    return {{"fields", fields}, {"panels", panels}, {"stages", stages}};
}

nlohmann::json style_values_json(const Style& style, const std::filesystem::path& base_dir) {
    nlohmann::json values = nlohmann::json::object();
    for (const StyleField& f : style_schema()) {
        const std::string text = style_field_toml(style, f, base_dir);
        values[std::string(f.path)] = text.empty() ? nlohmann::json() : toml_value_to_json(text);
    }
    return values;
}

}  // namespace wisp
