#include "dataset/spec.hpp"

#include "dataset/targets.hpp"
#include "render/render.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "dataset/toml_value.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"
#include "groom/toml_json.hpp"
#include "render/camera.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

// A spec is a few kilobytes; the style reader allows its files as much.
constexpr uint64_t kMaxSpecBytes = uint64_t(16) << 20;
constexpr size_t kMaxEntries = 10'000;  // bases, heads, rules, cameras, choices each

const std::vector<std::string>& hair_extensions() {
    static const std::vector<std::string> list = {"hair", "usda", "npz", "obj", "ply"};
    return list;
}

class SpecParser {
  public:
    SpecParser(std::string source, fs::path base_dir)
        : source_(std::move(source)), base_dir_(std::move(base_dir)) {}

    DatasetSpec parse(std::string_view text);

  private:
    [[noreturn]] void error(const toml::node* node, const std::string& field,
                            const std::string& why) const {
        const int line = node ? static_cast<int>(node->source().begin.line) : 0;
        if (line > 0) fail(source_, ":", line, ": field '", excerpt(field), "': ", why);
        fail(source_, ": field '", excerpt(field), "': ", why);
    }
    std::string at(const toml::node& node) const {
        return cat(source_, ":", node.source().begin.line);
    }
    void check_keys(const toml::table& table, const std::string& path,
                    const std::vector<std::string_view>& allowed) const;
    double number(const toml::node& node, const std::string& field) const;
    int64_t integer(const toml::node& node, const std::string& field, int64_t lo, int64_t hi) const;
    std::string string(const toml::node& node, const std::string& field) const;
    bool boolean(const toml::node& node, const std::string& field) const;
    const toml::array& array(const toml::node& node, const std::string& field, size_t lo,
                             size_t hi) const;
    double weight(const toml::table& table, const std::string& path) const;

    void read_bases(const toml::table& root, DatasetSpec& spec) const;
    void read_heads(const toml::table& root, DatasetSpec& spec) const;
    void read_distribution(const toml::node& value, const std::string& field_name, VaryRule& rule,
                           bool numeric, const char* kind_name, double lo, double hi,
                           bool lo_open) const;
    void read_vary(const toml::table& root, DatasetSpec& spec) const;
    void read_render(const toml::table& root, DatasetSpec& spec) const;
    void read_output(const toml::table& root, DatasetSpec& spec) const;
    void read_cameras(const toml::table& root, DatasetSpec& spec) const;

    std::string source_;
    fs::path base_dir_;
};

void SpecParser::check_keys(const toml::table& table, const std::string& path,
                            const std::vector<std::string_view>& allowed) const {
    for (const auto& [key, node] : table) {
        if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
        std::string list;
        for (const std::string_view a : allowed)
            list += cat(list.empty() ? "" : ", ", a);
        error(&node, path.empty() ? std::string(key.str()) : path + "." + std::string(key.str()),
              "unknown field (allowed here: " + list + ")");
    }
}

double SpecParser::number(const toml::node& node, const std::string& field) const {
    double v = 0;
    if (const auto* i = node.as_integer())
        v = static_cast<double>(i->get());
    else if (const auto* f = node.as_floating_point())
        v = f->get();
    else
        error(&node, field, "expects a number, got " + toml_value_text(node));
    if (!std::isfinite(v))
        error(&node, field, "expects a finite number, got " + toml_value_text(node));
    return v;
}

int64_t SpecParser::integer(const toml::node& node, const std::string& field, int64_t lo,
                            int64_t hi) const {
    const auto* i = node.as_integer();
    if (!i) error(&node, field, "expects an integer, got " + toml_value_text(node));
    if (i->get() < lo || i->get() > hi)
        error(&node, field, cat("expects an integer in [", lo, ", ", hi, "], got ", i->get()));
    return i->get();
}

std::string SpecParser::string(const toml::node& node, const std::string& field) const {
    const auto* s = node.as_string();
    if (!s || s->get().empty())
        error(&node, field, "expects a non-empty string, got " + toml_value_text(node));
    return s->get();
}

bool SpecParser::boolean(const toml::node& node, const std::string& field) const {
    const auto* b = node.as_boolean();
    if (!b) error(&node, field, "expects true or false, got " + toml_value_text(node));
    return b->get();
}

const toml::array& SpecParser::array(const toml::node& node, const std::string& field, size_t lo,
                                     size_t hi) const {
    const auto* a = node.as_array();
    if (!a) error(&node, field, "expects an array, got " + toml_value_text(node));
    if (a->size() < lo || a->size() > hi)
        error(&node, field,
              cat("expects ", lo == hi ? cat(lo) : cat(lo, " to ", hi), " elements, got ",
                  a->size()));
    return *a;
}

double SpecParser::weight(const toml::table& table, const std::string& path) const {
    const toml::node* node = table.get("weight");
    if (!node) return 1;
    const double w = number(*node, path + ".weight");
    if (!(w > 0) || w > 1e12)
        error(node, path + ".weight", cat("expects a weight in (0, 1e12], got ", w));
    return w;
}

void SpecParser::read_bases(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("base");
    if (!node) {
        spec.bases.push_back({"preset:default", load_preset("default"), 1});
        return;
    }
    const toml::array& list = array(*node, "base", 1, kMaxEntries);
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string path = cat("base[", i, "]");
        const toml::table* t = list[i].as_table();
        if (!t) error(&list[i], path, "expects a table ([[base]])");
        check_keys(*t, path, {"preset", "style", "weight"});
        const toml::node* preset = t->get("preset");
        const toml::node* file = t->get("style");
        if (!preset == !file) error(t, path, "give either preset or style");
        BaseStyle base;
        base.weight = weight(*t, path);
        try {
            if (preset) {
                base.name = "preset:" + string(*preset, path + ".preset");
                base.style = load_preset(base.name.substr(7));
            } else {
                base.name = string(*file, path + ".style");
                base.style = load_style(base_dir_ / base.name);
            }
        } catch (const Error& e) {
            error(preset ? preset : file, path + (preset ? ".preset" : ".style"), e.what());
        }
        spec.bases.push_back(std::move(base));
    }
}

void SpecParser::read_heads(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("head");
    if (!node) {
        spec.heads.push_back({"base style's", {}, 1, 0});
        return;
    }
    const toml::array& list = array(*node, "head", 1, kMaxEntries);
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string path = cat("head[", i, "]");
        const toml::table* t = list[i].as_table();
        if (!t) error(&list[i], path, "expects a table ([[head]])");
        HeadChoice head;
        head.line = static_cast<int>(t->source().begin.line);
        head.weight = weight(*t, path);
        head.name = "built-in";
        // Every other key is a field of the style's [head] section, set as the style reader
        // would set it, so a spec's head means what a style's does.
        const std::function<void(const toml::table&, const std::string&)> collect =
            [&](const toml::table& table, const std::string& prefix) {
                for (const auto& [key, value] : table) {
                    const std::string k(key.str());
                    if (prefix.empty() && (k == "weight" || k == "name")) continue;
                    if (prefix.empty() && k == "builtin") {
                        if (!boolean(value, path + ".builtin"))
                            error(&value, path + ".builtin",
                                  "false means nothing: give obj = \"head.obj\" instead");
                        continue;
                    }
                    const std::string field = "head." + prefix + k;
                    if (const toml::table* sub = value.as_table();
                        sub && !find_style_field(field)) {
                        collect(*sub, prefix + k + ".");
                        continue;
                    }
                    head.fields.emplace_back(field, toml_value_text(value));
                    Style probe = spec.bases.front().style;
                    try {
                        set_style_field(probe, field, head.fields.back().second, at(value),
                                        base_dir_);
                    } catch (const Error& e) {
                        fail(e.what());  // names the spec's line and the field
                    }
                    if (field == "head.obj") head.name = value.as_string()->get();
                }
            };
        collect(*t, "");
        if (const toml::node* name = t->get("name")) head.name = string(*name, path + ".name");
        spec.heads.push_back(std::move(head));
    }
}

// A rule's distribution ({ uniform = [a, b] }, { normal = [mean, sd], min, max },
// { log_uniform = [a, b] } or { choice = [...] }) into `rule`; a numeric one only when
// `numeric` (else the field is a `kind_name` field), its normal clamped to [lo, hi]. For a
// numeric rule, rule.choices holds the ends a draw can reach, for the caller to try.
void SpecParser::read_distribution(const toml::node& value, const std::string& field_name,
                                   VaryRule& rule, bool numeric, const char* kind_name, double lo,
                                   double hi, bool lo_open) const {
    const toml::table* dist = value.as_table();
    if (!dist || dist->size() == 0)
        error(&value, field_name,
              "expects a distribution: { uniform = [a, b] }, { normal = [mean, sd] }, "
              "{ log_uniform = [a, b] } or { choice = [...] }");
    check_keys(*dist, field_name, {"uniform", "normal", "log_uniform", "choice", "min", "max"});
    int kinds = 0;
    for (const char* k : {"uniform", "normal", "log_uniform", "choice"})
        kinds += dist->get(k) != nullptr;
    if (kinds != 1) error(&value, field_name, "give one of uniform, normal, log_uniform, choice");
    if (const toml::node* c = dist->get("choice")) {
        rule.kind = VaryRule::Kind::kChoice;
        const toml::array& options = array(*c, field_name + ".choice", 1, kMaxEntries);
        for (const toml::node& option : options)
            rule.choices.push_back(toml_value_text(option));
    } else {
        if (!numeric)
            error(&value, field_name,
                  cat("is a ", kind_name, " field: only { choice = [...] } varies it"));
        const char* name = dist->get("uniform")  ? "uniform"
                           : dist->get("normal") ? "normal"
                                                 : "log_uniform";
        rule.kind = dist->get("uniform")  ? VaryRule::Kind::kUniform
                    : dist->get("normal") ? VaryRule::Kind::kNormal
                                          : VaryRule::Kind::kLogUniform;
        const toml::node& ab = *dist->get(name);
        const toml::array& pair = array(ab, field_name + "." + name, 2, 2);
        rule.a = number(pair[0], field_name + "." + name);
        rule.b = number(pair[1], field_name + "." + name);
        if (rule.kind == VaryRule::Kind::kNormal) {
            if (!(rule.b >= 0))
                error(&ab, field_name + ".normal",
                      cat("the standard deviation must be ≥ 0, got ", rule.b));
        } else if (!(rule.a <= rule.b)) {
            error(&ab, field_name + "." + name,
                  cat("expects [a, b] with a ≤ b, got [", rule.a, ", ", rule.b, "]"));
        }
        if (rule.kind == VaryRule::Kind::kLogUniform && !(rule.a > 0))
            error(&ab, field_name + ".log_uniform", cat("expects a > 0, got ", rule.a));
        // A normal's tails are cut at the field's own range unless min or max narrow it.
        rule.lo = lo;
        rule.hi = hi;
        if (lo_open) rule.lo = std::nextafter(rule.lo, INFINITY);
        for (const char* bound : {"min", "max"})
            if (const toml::node* m = dist->get(bound)) {
                if (rule.kind != VaryRule::Kind::kNormal)
                    error(m, field_name + "." + bound, "only a normal distribution is clamped");
                (bound[1] == 'i' ? rule.lo : rule.hi) = number(*m, field_name + "." + bound);
            }
        if (!(rule.lo <= rule.hi))
            error(&value, field_name, cat("min (", rule.lo, ") is above max (", rule.hi, ")"));
        // The ends a draw can reach, tried below like choices.
        if (rule.kind == VaryRule::Kind::kNormal)
            rule.choices = {format_draw(std::clamp(rule.a, rule.lo, rule.hi), rule.integer)};
        else
            rule.choices = {format_draw(rule.a, rule.integer), format_draw(rule.b, rule.integer)};
    }
}

void SpecParser::read_vary(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("vary");
    if (!node) return;
    const toml::table* table = node->as_table();
    if (!table) error(node, "vary", "expects a table ([vary])");
    if (table->size() > kMaxEntries) error(node, "vary", cat("at most ", kMaxEntries, " rules"));
    for (const auto& [key, value] : *table) {
        VaryRule rule;
        rule.path = std::string(key.str());
        rule.line = static_cast<int>(value.source().begin.line);
        const std::string field_name = "vary." + rule.path;
        const StyleField* field = find_style_field(rule.path);
        if (!field) {
            // A dotted key written bare ([vary] roots.strands = ...) arrives as a table.
            if (value.is_table() && !value.as_table()->get("uniform") &&
                !value.as_table()->get("normal") && !value.as_table()->get("log_uniform") &&
                !value.as_table()->get("choice"))
                error(&value, field_name,
                      "is no style field; quote dotted paths: \"" + rule.path + ".KEY\" = {...}");
            error(&value, field_name, "is no style field (see `wisp schema` or docs/style.md)");
        }
        if (field->type == FieldType::kGroups)
            error(&value, field_name, "constraint groups cannot be varied");
        const bool numeric = field->type == FieldType::kNumber ||
                             field->type == FieldType::kInteger || field->type == FieldType::kSeed;
        rule.integer = field->type != FieldType::kNumber;
        read_distribution(value, field_name, rule, numeric,
                          field->type == FieldType::kChoice ? "choice" : "non-numeric",
                          field->type == FieldType::kSeed ? 0 : field->lo,
                          field->type == FieldType::kSeed ? 9.2e18 : field->hi, field->lo_open);
        // Every option (or end) must be a value the field takes on every base style.
        for (const BaseStyle& base : spec.bases)
            for (const std::string& option : rule.choices) {
                Style probe = base.style;
                try {
                    apply_draw(probe, rule.path, option, cat(source_, ":", rule.line), base_dir_);
                } catch (const Error& e) {
                    fail(e.what(), spec.bases.size() > 1 ? " (base " + base.name + ")" : "");
                }
            }
        if (rule.kind != VaryRule::Kind::kChoice) rule.choices.clear();
        spec.vary.push_back(std::move(rule));
    }
    // toml++ iterates a table in key order; the file's order reads better in the manifest.
    std::stable_sort(spec.vary.begin(), spec.vary.end(),
                     [](const VaryRule& x, const VaryRule& y) { return x.line < y.line; });
}

void SpecParser::read_render(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("render");
    if (!node) return;
    const toml::table* table = node->as_table();
    if (!table) error(node, "render", "expects a table ([render])");
    const auto& fields = render_field_table();
    for (const auto& [key, value] : *table) {
        VaryRule rule;
        rule.path = std::string(key.str());
        rule.line = static_cast<int>(value.source().begin.line);
        const std::string field_name = "render." + rule.path;
        const auto it = std::find_if(fields.begin(), fields.end(),
                                     [&](const RenderField& f) { return rule.path == f.name; });
        if (it == fields.end()) {
            std::string names;
            for (const RenderField& f : fields)
                names += cat(names.empty() ? "" : ", ", f.name);
            error(&value, field_name, "is no picture parameter (" + names + ")");
        }
        const bool shading = rule.path == "shading";
        read_distribution(value, field_name, rule, !shading, "choice", it->lo, it->hi, false);
        for (const std::string& option : rule.choices) {
            const toml::table parsed = toml::parse("v = " + option);
            if (shading) {
                const auto name = parsed["v"].value<std::string>();
                const auto& names = shading_names();
                if (!name || std::find(names.begin(), names.end(), *name) == names.end())
                    error(&value, field_name,
                          cat("a choice of \"hair\", \"fiber\", \"kajiya-kay\", got ",
                              excerpt(option)));
                continue;
            }
            const auto x = parsed["v"].value<double>();
            if (!x || !(*x >= it->lo && *x <= it->hi))
                error(&value, field_name,
                      cat("takes numbers in [", it->lo, ", ", it->hi, "], got ", excerpt(option)));
        }
        if (rule.kind != VaryRule::Kind::kChoice) rule.choices.clear();
        spec.render.push_back(std::move(rule));
    }
    std::stable_sort(spec.render.begin(), spec.render.end(),
                     [](const VaryRule& x, const VaryRule& y) { return x.line < y.line; });
}

void SpecParser::read_output(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("output");
    if (!node) return;
    const toml::table* t = node->as_table();
    if (!t) error(node, "output", "expects a table ([output])");
    check_keys(*t, "output",
               {"hair", "resample", "size", "maps", "volume", "volume_box", "scalp_texture"});
    OutputSpec& o = spec.output;
    if (const toml::node* h = t->get("hair")) {
        o.hair.clear();
        for (const toml::node& e : array(*h, "output.hair", 0, 5)) {
            const std::string ext = string(e, "output.hair");
            const auto& list = hair_extensions();
            if (std::find(list.begin(), list.end(), ext) == list.end())
                error(&e, "output.hair",
                      "unknown format '" + excerpt(ext) + "' (hair, usda, npz, obj, ply)");
            if (std::find(o.hair.begin(), o.hair.end(), ext) != o.hair.end())
                error(&e, "output.hair", "'" + ext + "' given twice");
            o.hair.push_back(ext);
        }
    }
    if (const toml::node* r = t->get("resample"))
        o.resample = static_cast<int>(integer(*r, "output.resample", 2, 4096));
    if (const toml::node* s = t->get("size")) {
        const toml::array& wh = array(*s, "output.size", 2, 2);
        o.width = static_cast<int>(integer(wh[0], "output.size", 8, 8192));
        o.height = static_cast<int>(integer(wh[1], "output.size", 8, 8192));
    }
    if (const toml::node* st = t->get("scalp_texture")) {
        const toml::array& sp = array(*st, "output.scalp_texture", 2, 2);
        o.scalp_texture = static_cast<int>(integer(sp[0], "output.scalp_texture", 4, 1024));
        o.scalp_points = static_cast<int>(integer(sp[1], "output.scalp_texture", 2, 1024));
        if (static_cast<size_t>(o.scalp_texture) * o.scalp_texture * o.scalp_points >
            (size_t{1} << 26))
            error(st, "output.scalp_texture",
                  cat(o.scalp_texture, "² texels of ", o.scalp_points,
                      " points: 2^26 points at most (256² of 1024, 1024² of 64)"));
    }
    if (const toml::node* v = t->get("volume")) {
        const toml::array& xyz = array(*v, "output.volume", 3, 3);
        for (int i = 0; i < 3; ++i)
            o.volume[i] = static_cast<int>(integer(xyz[i], "output.volume", 1, 1024));
        const size_t voxels = static_cast<size_t>(o.volume.x()) * o.volume.y() * o.volume.z();
        if (voxels > kMaxVolumeVoxels)
            error(v, "output.volume",
                  cat(voxels, " voxels: at most ", kMaxVolumeVoxels, " (256 x 256 x 256)"));
    }
    if (const toml::node* b = t->get("volume_box")) {
        const toml::array& corners = array(*b, "output.volume_box", 2, 2);
        Vec3f c[2];
        for (int k = 0; k < 2; ++k) {
            const toml::array& xyz = array(corners[k], "output.volume_box", 3, 3);
            for (int i = 0; i < 3; ++i) {
                const double x = number(xyz[i], "output.volume_box");
                if (!(std::abs(x) <= 100))
                    error(&xyz[i], "output.volume_box", "a corner in head units, within ±100");
                c[k][i] = static_cast<float>(x);
            }
        }
        if (!(c[0].array() < c[1].array()).all())
            error(b, "output.volume_box",
                  "[low corner, high corner]: the first below the second on every axis");
        o.volume_lo = c[0];
        o.volume_hi = c[1];
    }
    if (const toml::node* m = t->get("maps")) {
        const auto& table = output_map_table();
        o.maps = 0;
        for (const toml::node& e : array(*m, "output.maps", 0, table.size())) {
            const std::string name = string(e, "output.maps");
            const OutputMapInfo* map = find_output_map(name);
            if (!map)
                error(&e, "output.maps",
                      "unknown map '" + excerpt(name) + "' (" + output_map_names() + ")");
            o.maps |= 1u << static_cast<int>(map->map);
        }
    }
}

void SpecParser::read_cameras(const toml::table& root, DatasetSpec& spec) const {
    const toml::node* node = root.get("camera");
    if (!node) {
        spec.cameras.push_back({});
        return;
    }
    const toml::array& list = array(*node, "camera", 0, 64);
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string path = cat("camera[", i, "]");
        const toml::table* t = list[i].as_table();
        if (!t) error(&list[i], path, "expects a table ([[camera]])");
        check_keys(*t, path, {"view", "frame", "azimuth", "elevation", "distance", "fov"});
        CameraSpec c;
        if (const toml::node* f = t->get("frame")) {
            const std::string frame = string(*f, path + ".frame");
            if (frame != "head" && frame != "hair")
                error(f, path + ".frame",
                      "\"head\" (hair and head) or \"hair\" (the hair alone), got \"" +
                          excerpt(frame) + "\"");
            c.hair_only = frame == "hair";
        }
        if (const toml::node* v = t->get("view")) {
            c.view = string(*v, path + ".view");
            if (c.view == "three_quarter") c.view = "three-quarter";
            const auto& names = view_names();
            if (std::find(names.begin(), names.end(), c.view) == names.end())
                error(v, path + ".view",
                      "unknown view '" + excerpt(c.view) +
                          "' (front, back, left, right, three-quarter, top)");
        }
        const auto bounded = [&](const char* key, double hi, double& out) {
            if (const toml::node* n = t->get(key)) {
                out = number(*n, path + "." + key);
                if (out < 0 || out > hi)
                    error(n, path + "." + key, cat("expects a number in [0, ", hi, "], got ", out));
            }
        };
        bounded("azimuth", 180, c.azimuth);
        bounded("elevation", 80, c.elevation);
        bounded("distance", 0.9, c.distance);
        if (const toml::node* n = t->get("fov")) {
            c.fov_y_degrees = number(*n, path + ".fov");
            if (!(c.fov_y_degrees > 1 && c.fov_y_degrees < 170))
                error(n, path + ".fov", cat("expects degrees in (1, 170), got ", c.fov_y_degrees));
        }
        spec.cameras.push_back(c);
    }
}

DatasetSpec SpecParser::parse(std::string_view text) {
    const toml::table root = parse_toml(text, source_);
    check_keys(
        root, "",
        {"samples", "seed", "sampling", "base", "head", "vary", "render", "output", "camera"});
    DatasetSpec spec;
    spec.source = source_;
    spec.base_dir = base_dir_;
    const toml::node* samples = root.get("samples");
    if (!samples) fail(source_, ": field 'samples': required (how many samples to make)");
    spec.samples = static_cast<uint64_t>(integer(*samples, "samples", 1, kMaxSamples));
    if (const toml::node* sampling = root.get("sampling")) {
        const std::string how = string(*sampling, "sampling");
        using S = DatasetSpec::Sampling;
        if (how == "weighted")
            spec.sampling = S::kWeighted;
        else if (how == "stratified")
            spec.sampling = S::kStratified;
        else if (how == "grid")
            spec.sampling = S::kGrid;
        else
            error(sampling, "sampling",
                  "one of \"weighted\", \"stratified\", \"grid\", got \"" + excerpt(how) + "\"");
    }
    if (const toml::node* seed = root.get("seed"))
        spec.seed = static_cast<uint64_t>(integer(*seed, "seed", 0, INT64_MAX));
    read_bases(root, spec);
    read_heads(root, spec);
    read_vary(root, spec);
    read_render(root, spec);
    read_output(root, spec);
    read_cameras(root, spec);
    return spec;
}

}  // namespace

void apply_draw(Style& style, const std::string& path, const std::string& toml_value,
                const std::string& source, const std::filesystem::path& base_dir) {
    if (path == "roots.strands") {
        int64_t n = 0;
        const auto [ptr, ec] =
            std::from_chars(toml_value.data(), toml_value.data() + toml_value.size(), n);
        if (ec == std::errc() && ptr == toml_value.data() + toml_value.size() && n >= 1 &&
            n < style.wisps) {
            Style out = style;
            out.wisps = static_cast<int>(n);
            set_style_field(out, path, toml_value, source, base_dir);
            style = std::move(out);
            return;
        }
    }
    set_style_field(style, path, toml_value, source, base_dir);
}

DatasetSpec parse_dataset_spec(std::string_view toml_text, const std::string& source,
                               const std::filesystem::path& base_dir) {
    return SpecParser(source, base_dir).parse(toml_text);
}

const std::vector<RenderField>& render_field_table() {
    static const std::vector<RenderField> table{
        {"key_azimuth", -180, 180, 0, "degrees",
         "the key light turned about the camera's up axis (positive: toward the right)"},
        {"key_elevation", -80, 80, 0, "degrees",
         "the key light turned about the camera's right axis (positive: from higher up)"},
        {"key_intensity", 0, 10, 1, "factor", "the key light's strength"},
        {"key_temperature", 1500, 15000, 6500, "kelvin",
         "the key light's colour: a black body's at this temperature (6500: daylight white, "
         "2700: a warm lamp), at the key's own luminance"},
        {"fill_intensity", 0, 10, 1, "factor", "the fill light's strength"},
        {"rim_intensity", 0, 10, 1, "factor", "the rim (back) light's strength; 0 turns it off"},
        {"ambient_intensity", 0, 10, 1, "factor", "the ambient light's strength"},
        {"background_value", 0, 1, 0.31, "linear", "the background's brightness (HSV value)"},
        {"background_saturation", 0, 1, 0.032, "", "the background's saturation (HSV)"},
        {"background_hue", 0, 360, 240, "degrees", "the background's hue (HSV)"},
        {"strand_brightness", 0, 1, 0.3, "",
         "how much each strand's brightness varies from the next (± this, uniform)"},
        {"shading", 0, 0, 0, "choice", "the shading model: \"hair\", \"fiber\" or \"kajiya-kay\""},
    };
    return table;
}

const std::vector<OutputMapInfo>& output_map_table() {
    using M = OutputMap;
    static const std::vector<OutputMapInfo> table{
        {M::kPicture, "picture", ".png", true},
        {M::kOrientation, "orientation", "_orientation.png", true},
        {M::kMask, "mask", "_mask.png", true},
        {M::kDepth, "depth", "_depth.npy", true},
        {M::kStrand, "strand", "_strand.png", false},
        {M::kConfidence, "confidence", "_confidence.npy", false},
        {M::kMatte, "matte", "_matte.png", false},
        {M::kStrandId, "strand_id", "_strand_id.npy", false},
        {M::kDepthHairstep, "depth_hairstep", "_depth_hairstep.npy", false},
    };
    return table;
}

const OutputMapInfo* find_output_map(const std::string& name, bool maps_only) {
    for (const OutputMapInfo& m : output_map_table())
        if (name == m.name && !(maps_only && m.map == OutputMap::kPicture)) return &m;
    return nullptr;
}

std::string output_map_names(bool maps_only) {
    std::string names;
    for (const OutputMapInfo& m : output_map_table())
        if (!(maps_only && m.map == OutputMap::kPicture))
            names += cat(names.empty() ? "" : ", ", m.name);
    return names;
}

DatasetSpec load_dataset_spec(const std::filesystem::path& path,
                              const std::filesystem::path& base_dir) {
    ReadLimits limits;
    limits.max_bytes = kMaxSpecBytes;
    limits.what = "a dataset spec";
    limits.text = true;
    const std::string text = read_file(path, limits);
    return parse_dataset_spec(text, path.string(),
                              base_dir.empty() ? fs::absolute(path).parent_path() : base_dir);
}

}  // namespace wisp
