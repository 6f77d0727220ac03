#include "edit/wire.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "geometry/skin_normals.hpp"
#include "groom/maps.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"

namespace wisp {

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

std::string encode_strands(const Hair& hair, std::span<const uint32_t> ids, size_t total) {
    std::string out;
    encode_strands(hair, ids, total, out);
    return out;
}

void encode_strands(const Hair& hair, std::span<const uint32_t> ids, size_t total,
                    std::string& out) {
    static_assert(sizeof(Vec3f) == 12, "positions and colours are copied as float32 triples");
    const size_t count = ids.size();
    // Where each strand's points go: the offsets sent, computed once and copied in parallel.
    std::vector<uint32_t> offsets(count + 1, 0);
    for (size_t i = 0; i < count; ++i) {
        if (ids[i] >= hair.strand_count())
            fail("encode_strands: strand ", ids[i], " of ", hair.strand_count());
        offsets[i + 1] = offsets[i] + hair.strand_size(ids[i]);
    }
    const size_t points = offsets[count];
    const uint32_t header[4] = {1, static_cast<uint32_t>(count), static_cast<uint32_t>(points),
                                static_cast<uint32_t>(total)};
    const size_t at_offsets = 8 + sizeof header, at_points = at_offsets + 4 * (count + 1),
                 at_colors = at_points + 12 * points;
    // resize() clears only what the buffer grows by (the rest is written below), and a buffer
    // too small is emptied first so that growing it copies nothing.
    const size_t size = at_colors + 12 * count;
    if (out.capacity() < size) out.clear();
    out.resize(size);
    char* bytes = out.data();
    std::memcpy(bytes, "WISPHAIR", 8);
    std::memcpy(bytes + 8, header, sizeof header);
    std::memcpy(bytes + at_offsets, offsets.data(), 4 * (count + 1));
    parallel_for(
        count,
        [&](size_t i) {
            const uint32_t s = ids[i];
            std::memcpy(bytes + at_points + 12 * size_t(offsets[i]),
                        hair.points.data() + hair.offsets[s], 12 * size_t(hair.strand_size(s)));
            const Vec3f color = hair.color_of(s);
            std::memcpy(bytes + at_colors + 12 * i, color.data(), 12);
        },
        1024);
}

std::string encode_strands(const Hair& hair, size_t limit, size_t total) {
    const size_t n = hair.strand_count();
    const std::vector<uint32_t> order = strand_order(n);
    return encode_strands(hair, std::span<const uint32_t>(order.data(), std::min(limit, n)),
                          total ? total : n);
}

void write_strand_colors(std::span<const Vec3f> colors, std::string& bytes) {
    uint32_t count = 0;
    if (bytes.size() >= 24) std::memcpy(&count, bytes.data() + 12, 4);
    if (bytes.size() < 24 + 4 + 12 * size_t(count) || count != colors.size())
        fail("write_strand_colors: ", colors.size(), " colours for a buffer of ", count,
             " strands");
    if (count)
        std::memcpy(bytes.data() + bytes.size() - 12 * colors.size(), colors.data(),
                    12 * colors.size());
}

std::span<char> begin_frame(uint32_t frame, size_t points, std::string& out) {
    out.resize(20 + 12 * points);
    std::memcpy(out.data(), "WISPFRAM", 8);
    const uint32_t header[3] = {1, frame, static_cast<uint32_t>(points)};
    std::memcpy(out.data() + 8, header, sizeof header);
    return std::span<char>(out.data() + 20, 12 * points);
}

void encode_frame(uint32_t frame, std::span<const Vec3f> points, std::string& out) {
    static_assert(sizeof(Vec3f) == 12, "positions are copied as float32 triples");
    const std::span<char> xyz = begin_frame(frame, points.size(), out);
    if (!points.empty()) std::memcpy(xyz.data(), points.data(), xyz.size());
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
    put_u32(out, 2);
    put_u32(out, static_cast<uint32_t>(mesh.vertices.size()));
    put_u32(out, static_cast<uint32_t>(mesh.faces.size()));
    for (const Vec3f& v : mesh.vertices)
        for (int c = 0; c < 3; ++c)
            put_f32(out, v[c]);
    for (const Vec3f& n : skin_normals(mesh))
        for (int c = 0; c < 3; ++c)
            put_f32(out, n[c]);
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
    nlohmann::json sections = nlohmann::json::array();
    for (const SectionField& f : section_schema())
        sections.push_back({{"section", f.section},
                            {"key", f.key},
                            {"type", field_type_name(f.type)},
                            {"unit", f.unit},
                            {"min", f.lo},
                            {"max", f.hi},
                            {"min_open", f.lo_open},
                            {"soft_min", f.soft_lo},
                            {"soft_max", f.soft_hi},
                            {"doc", f.doc},
                            {"default", f.get_default()}});
    return {{"fields", fields}, {"panels", panels}, {"stages", stages}, {"sections", sections}};
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
