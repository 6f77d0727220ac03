#include "groom/style_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "groom/hairdressing.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace detail {
// Defined in presets.cpp, generated from presets/*.toml by embed_presets.cmake.
extern const std::pair<std::string_view, std::string_view> kEmbeddedPresets[];
extern const std::size_t kEmbeddedPresetCount;
}  // namespace detail

namespace {

namespace fs = std::filesystem;

// Bounds that keep a hostile or mistyped file from asking for absurd work or memory.
constexpr int64_t kMaxStrands = 10'000'000;
constexpr int64_t kMaxPointsPerStrand = 1024;
constexpr int64_t kMaxTotalPoints = 320'000'000;  // 10 M strands of 32 points
constexpr size_t kMaxTableValues = 1024;
constexpr size_t kMaxDeviationRadii = 256;
constexpr size_t kMaxPolylinePoints = 10'000;
constexpr std::uintmax_t kMaxFileBytes = 16u << 20;
constexpr size_t kMaxTrajectoryPoints = 10'000;
constexpr size_t kMaxGroups = 1024;  // constraint groups after expansion
constexpr size_t kMaxQueue = 256;    // constraints per group
constexpr size_t kMaxFieldTerms = 64;
constexpr double kMaxCoordinate = 1e4;  // cm or head units
// Messages quote at most this much of a field name, and are at most kMaxMessage long.
constexpr size_t kMaxQuotedField = 200;
constexpr size_t kMaxMessage = 1000;
// "Did you mean" compares with the known names only words up to this long.
constexpr size_t kMaxSuggestedWord = 64;

// The fields of each section; the unknown-key check and its suggestions use these.
const std::vector<std::pair<std::string, std::vector<std::string>>>& schema() {
    static const std::vector<std::pair<std::string, std::vector<std::string>>> sections = {
        {"",
         {"name", "seed", "head", "roots", "maps", "growth", "strand", "prototype", "wisp", "color",
          "solve", "cut", "group", "tie", "braid", "updo", "comb", "dynamics"}},
        {"head", {"obj", "scale", "scalp"}},
        {"head.scalp", {"method", "group", "mask", "front", "side", "back"}},
        {"roots", {"wisps", "strands", "points_per_strand"}},
        {"maps", {"density", "length", "protrusion"}},
        {"growth",
         {"part", "part_offset", "part_length", "front", "whorl", "whorl_turn", "whorl_swirl",
          "map", "map_strength"}},
        {"strand", {"root_width", "tip_width"}},
        {"prototype",
         {"shape", "amplitude", "period", "length", "points", "window", "temperature", "roll"}},
        {"wisp", {"length", "deviation_radius", "fuzziness"}},
        {"color",
         {"preset", "hue", "saturation", "value", "wisp_hue", "wisp_saturation", "wisp_value"}},
        {"solve",
         {"enabled", "stiffness", "threshold", "cell", "full_density", "bend_step", "max_tries",
          "order", "head_margin", "field"}},
        {"cut", {"enabled", "region", "normal", "offset", "head_relative"}},
        {"dynamics", {"levels",           "wisps_per_group", "sub_wisps",       "sections",
                      "strands_per_wisp", "links",           "stiffness",       "stretch",
                      "damping",          "air_drag",        "split_threshold", "merge_velocity",
                      "friction",         "repulsion",       "repulsion_angle", "voxel",
                      "iterations",       "hair_collisions", "body_collisions", "dt",
                      "linear_density"}},
    };
    return sections;
}

const std::vector<std::string>& keys_of(const std::string& section) {
    for (const auto& [name, keys] : schema())
        if (name == section) return keys;
    static const std::vector<std::string> none;
    return none;
}

const std::vector<std::string> kDistributionKeys = {"distribution", "value",  "min",   "max",
                                                    "mean",         "stddev", "values"};
const std::vector<std::string> kMapKeys = {"value", "image", "procedural", "low", "high"};

// The keys of the arrays of tables: solve.field terms, constraint groups and the
// hairdressing operations, which all select wisps with the same keys.
const std::vector<std::string> kFieldKeys = {"kind", "weight", "direction", "side", "file"};
const std::vector<std::string> kSelectionSources = {"select", "region",     "mask",
                                                    "box",    "half_space", "wisps"};
const std::vector<std::string> kSelectionKeys = {
    "select", "region", "mask", "box", "half_space", "wisps", "part", "parts", "head_relative"};
const std::vector<std::string> kConstraintKeys = {
    "kind", "point", "trajectory", "smooth", "radius", "weight", "hold", "head_relative"};

std::vector<std::string> with_selection(std::vector<std::string> keys) {
    keys.insert(keys.end(), kSelectionKeys.begin(), kSelectionKeys.end());
    return keys;
}

const std::vector<std::string> kGroupKeys = with_selection({"name", "constraint"});
const std::vector<std::string> kTieKeys = with_selection({"name", "point", "radius", "weight"});
const std::vector<std::string> kBraidKeys = with_selection(
    {"name", "strands", "start", "axis", "side", "length", "width", "period", "radius", "weight"});
const std::vector<std::string> kUpdoKeys =
    with_selection({"name", "point", "facing", "radius", "bun_radius", "turns", "weight"});
const std::vector<std::string> kCombKeys =
    with_selection({"name", "trajectory", "smooth", "radius", "weight"});

std::string join_path(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

// Case-insensitive edit distance counting a swap of neighbours as one edit (optimal string
// alignment), for "did you mean" suggestions.
size_t edit_distance(std::string_view a, std::string_view b) {
    const auto lower = [](char c) { return std::tolower(static_cast<unsigned char>(c)); };
    const size_t w = b.size() + 1;
    std::vector<size_t> d((a.size() + 1) * w);
    for (size_t i = 0; i <= a.size(); ++i)
        d[i * w] = i;
    for (size_t j = 0; j <= b.size(); ++j)
        d[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
            size_t best = std::min(
                {d[(i - 1) * w + j] + 1, d[i * w + j - 1] + 1, d[(i - 1) * w + j - 1] + cost});
            if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
                lower(a[i - 2]) == lower(b[j - 1]))
                best = std::min(best, d[(i - 2) * w + j - 2] + 1);
            d[i * w + j] = best;
        }
    }
    return d[a.size() * w + b.size()];
}

// The option closest to `word` if it is close enough to be a likely typo. Words much longer
// than any option are no typo of one (and the edit distance is quadratic): none.
std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& options) {
    if (word.size() > kMaxSuggestedWord) return std::nullopt;
    const size_t limit = word.size() <= 4 ? 1 : word.size() <= 8 ? 2 : 3;
    std::optional<std::string> best;
    size_t best_distance = limit + 1;
    for (const auto& option : options) {
        const size_t d = edit_distance(word, option);
        if (d < best_distance) {
            best_distance = d;
            best = option;
        }
    }
    return best;
}

std::string list(const std::vector<std::string>& items, bool quote) {
    std::string out;
    for (size_t i = 0; i < items.size(); ++i) {
        if (i) out += ", ";
        out += quote ? "\"" + items[i] + "\"" : items[i];
    }
    return out;
}

std::string number(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    std::ostringstream out;
    out.precision(7);
    out << v;
    return out.str();
}

// A string as the user would write it in TOML, kept on one line and cut short.
std::string toml_string(std::string_view s) {
    size_t cut = std::min(s.size(), kExcerptBytes);
    while (cut > 0 && cut < s.size() && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80)
        --cut;  // not inside a UTF-8 character
    std::string out;
    for (const char c : s.substr(0, cut)) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    out = "\"" + excerpt(out, SIZE_MAX) + "\"";  // newlines and control characters escaped
    if (cut < s.size()) out += cat("... (", s.size(), " bytes)");
    return out;
}

// What a node holds, for "got ..." in messages.
std::string describe(const toml::node& node) {
    if (const auto* s = node.as_string()) return toml_string(s->get());
    if (const auto* i = node.as_integer()) return std::to_string(i->get());
    if (const auto* f = node.as_floating_point()) return number(f->get());
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (node.is_table()) return "a table";
    if (node.is_array()) return "an array";
    return "a date or time";
}

// An allowed interval for a number; the bound that is violated is the one reported.
struct Range {
    double lo, hi;
    bool lo_open = false;  // lo itself is excluded
};

// The support of a distribution and whether it must reach above its low end (lengths).
struct Domain {
    float lo, hi;
    bool positive = false;  // the constant value, or max, must be > lo
};

// How a scalar map's numbers are bounded and what an image or procedural map scales to by
// default.
struct MapRules {
    Range range;
    bool some_positive;  // density: the map may not be zero everywhere
    float low, high;     // default [low, high] of image and procedural maps
};

class Parser {
  public:
    Parser(std::string source, fs::path base_dir)
        : source_(std::move(source)), base_dir_(std::move(base_dir)) {}

    Style parse(std::string_view text);

  private:
    [[noreturn]] void error(const toml::source_region& where, const std::string& field,
                            const std::string& what) const {
        // Field names are keys of the file and `what` may quote values: both are escaped and
        // cut short, so every message is one line of reasonable length.
        const std::string f = excerpt(field, kMaxQuotedField), w = excerpt(what, kMaxMessage);
        if (where.begin.line > 0) fail(source_, ":", where.begin.line, ": field '", f, "': ", w);
        fail(source_, ": field '", f, "': ", w);
    }
    [[noreturn]] void error(const toml::node& node, const std::string& field,
                            const std::string& what) const {
        error(node.source(), field, what);
    }

    // Rejects keys of `table` not in `allowed`, suggesting the likely intended field.
    void check_keys(const toml::table& table, const std::string& path,
                    const std::vector<std::string>& allowed) const;
    // The sub-table `key` of `parent` (null if absent), its keys checked against the schema.
    const toml::table* section(const toml::table* parent, const std::string& path,
                               std::string_view key) const;

    double real(const toml::node& node, const std::string& field, const Range& range) const;
    int64_t integer(const toml::node& node, const std::string& field, int64_t lo, int64_t hi) const;
    std::string string(const toml::node& node, const std::string& field, bool non_empty) const;
    template <typename E>
    E choice(const toml::node& node, const std::string& field,
             const std::vector<std::pair<std::string, E>>& options) const;
    fs::path path(const toml::node& node, const std::string& field) const;
    bool boolean(const toml::node& node, const std::string& field) const;
    // A point or direction [x, y, z] with finite coordinates within ±kMaxCoordinate;
    // `direction`: it must not be the zero vector.
    Vec3f vec3(const toml::node& node, const std::string& field, bool direction) const;
    std::vector<Vec3f> points(const toml::node& node, const std::string& field) const;
    // table[key] as an array of tables ([[key]] or key = [{…}, …]); null if absent.
    const toml::array* tables(const toml::table& parent, const std::string& path,
                              std::string_view key) const;

    // Sets `out` from table[key] if present.
    void opt_real(const toml::table* table, const std::string& path, std::string_view key,
                  float& out, const Range& range) const;
    void opt_int(const toml::table* table, const std::string& path, std::string_view key, int& out,
                 int64_t lo, int64_t hi) const;
    void opt_bool(const toml::table* table, const std::string& path, std::string_view key,
                  bool& out) const;
    void opt_vec3(const toml::table* table, const std::string& path, std::string_view key,
                  Vec3f& out, bool direction) const;

    Distribution distribution(const toml::node& node, const std::string& field,
                              const Distribution& current, const Domain& domain) const;
    ScalarMap map(const toml::node& node, const std::string& field, const MapRules& rules) const;
    std::string procedural_name(const toml::node& node, const std::string& field) const;

    void read_head(const toml::table* root, Style& style) const;
    void read_roots(const toml::table* root, Style& style) const;
    void read_maps(const toml::table* root, Style& style) const;
    void read_growth(const toml::table* root, Style& style) const;
    void read_strand(const toml::table* root, Style& style) const;
    void read_prototype(const toml::table* root, Style& style) const;
    void read_wisp(const toml::table* root, Style& style) const;
    void read_color(const toml::table* root, Style& style) const;
    void read_solve(const toml::table* root, Style& style) const;
    void read_cut(const toml::table* root, Style& style) const;
    void read_dynamics(const toml::table* root, Style& style) const;
    // [[group]], [[tie]], [[braid]], [[updo]] and [[comb]] in file order into style.groups.
    void read_groups(const toml::table* root, Style& style) const;

    FieldTerm field_term(const toml::table& table, const std::string& path) const;
    Selection selection(const toml::table& table, const std::string& path, int wisps,
                        bool with_parts) const;
    ConstraintSpec constraint(const toml::table& table, const std::string& path,
                              bool head_relative) const;
    std::vector<GroupSpec> group(const toml::table& table, const std::string& path,
                                 int wisps) const;
    std::vector<GroupSpec> tie(const toml::table& table, const std::string& path, int wisps) const;
    std::vector<GroupSpec> braid(const toml::table& table, const std::string& path,
                                 int wisps) const;
    std::vector<GroupSpec> updo(const toml::table& table, const std::string& path, int wisps) const;
    std::vector<GroupSpec> comb(const toml::table& table, const std::string& path, int wisps) const;

    std::string source_;
    fs::path base_dir_;
};

void Parser::check_keys(const toml::table& table, const std::string& path,
                        const std::vector<std::string>& allowed) const {
    for (auto&& [key, node] : table) {
        const std::string name(key.str());
        if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
        const std::string field = join_path(path, name);
        // A known field written in the wrong section, else a likely typo of a sibling.
        std::vector<std::string> elsewhere;
        const bool is_section = std::any_of(schema().begin(), schema().end(),
                                            [&](const auto& s) { return s.first == path; });
        for (const auto& [section, keys] : schema())
            for (const auto& k : keys)
                if (is_section && k == name && section != path)
                    elsewhere.push_back(join_path(section, k));
        std::string hint;
        if (!elsewhere.empty()) {
            hint = " (did you mean '" + elsewhere[0] + "'";
            for (size_t i = 1; i < elsewhere.size(); ++i)
                hint += " or '" + elsewhere[i] + "'";
            hint += "?)";
        } else if (const auto near = closest(name, allowed)) {
            hint = " (did you mean '" + join_path(path, *near) + "'?)";
        } else {
            hint = " (expected one of: " + list(allowed, false) + ")";
        }
        const auto& where = key.source().begin.line > 0 ? key.source() : node.source();
        const std::string f = excerpt(field, kMaxQuotedField);
        if (where.begin.line > 0)
            fail(source_, ":", where.begin.line, ": unknown field '", f, "'", hint);
        fail(source_, ": unknown field '", f, "'", hint);
    }
}

const toml::table* Parser::section(const toml::table* parent, const std::string& path,
                                   std::string_view key) const {
    if (!parent) return nullptr;
    const toml::node* node = parent->get(key);
    if (!node) return nullptr;
    const std::string field = join_path(path, key);
    const toml::table* table = node->as_table();
    if (!table) error(*node, field, "must be a table, got " + describe(*node));
    check_keys(*table, field, keys_of(field));
    return table;
}

double Parser::real(const toml::node& node, const std::string& field, const Range& range) const {
    double v;
    if (const auto* f = node.as_floating_point()) {
        v = f->get();
    } else if (const auto* i = node.as_integer()) {
        v = static_cast<double>(i->get());
    } else {
        error(node, field, "must be a number, got " + describe(node));
    }
    if (!std::isfinite(v)) error(node, field, "must be a finite number, got " + number(v));
    if (range.lo_open ? v <= range.lo : v < range.lo)
        error(node, field,
              std::string("must be ") + (range.lo_open ? "> " : "≥ ") + number(range.lo) +
                  ", got " + number(v));
    if (v > range.hi) error(node, field, "must be ≤ " + number(range.hi) + ", got " + number(v));
    return v;
}

int64_t Parser::integer(const toml::node& node, const std::string& field, int64_t lo,
                        int64_t hi) const {
    const auto* i = node.as_integer();
    if (!i) error(node, field, "must be an integer, got " + describe(node));
    const int64_t v = i->get();
    if (v < lo) error(node, field, cat("must be ≥ ", lo, ", got ", v));
    if (v > hi) error(node, field, cat("must be ≤ ", hi, ", got ", v));
    return v;
}

std::string Parser::string(const toml::node& node, const std::string& field, bool non_empty) const {
    const auto* s = node.as_string();
    if (!s) error(node, field, "must be a string, got " + describe(node));
    if (non_empty && s->get().empty()) error(node, field, "must not be empty");
    return s->get();
}

template <typename E>
E Parser::choice(const toml::node& node, const std::string& field,
                 const std::vector<std::pair<std::string, E>>& options) const {
    std::vector<std::string> names;
    for (const auto& [name, value] : options)
        names.push_back(name);
    const auto* s = node.as_string();
    if (!s) error(node, field, "must be one of " + list(names, true) + ", got " + describe(node));
    for (const auto& [name, value] : options)
        if (name == s->get()) return value;
    std::string what = "must be one of " + list(names, true) + ", got " + toml_string(s->get());
    if (const auto near = closest(s->get(), names))
        what += " (did you mean " + toml_string(*near) + "?)";
    error(node, field, what);
}

fs::path Parser::path(const toml::node& node, const std::string& field) const {
    const fs::path p = fs::path(string(node, field, true));
    return p.is_relative() && !base_dir_.empty() ? base_dir_ / p : p;
}

void Parser::opt_real(const toml::table* table, const std::string& path, std::string_view key,
                      float& out, const Range& range) const {
    if (!table) return;
    if (const toml::node* node = table->get(key))
        out = static_cast<float>(real(*node, join_path(path, key), range));
}

void Parser::opt_int(const toml::table* table, const std::string& path, std::string_view key,
                     int& out, int64_t lo, int64_t hi) const {
    if (!table) return;
    if (const toml::node* node = table->get(key))
        out = static_cast<int>(integer(*node, join_path(path, key), lo, hi));
}

void Parser::opt_bool(const toml::table* table, const std::string& path, std::string_view key,
                      bool& out) const {
    if (!table) return;
    if (const toml::node* node = table->get(key)) out = boolean(*node, join_path(path, key));
}

void Parser::opt_vec3(const toml::table* table, const std::string& path, std::string_view key,
                      Vec3f& out, bool direction) const {
    if (!table) return;
    if (const toml::node* node = table->get(key))
        out = vec3(*node, join_path(path, key), direction);
}

bool Parser::boolean(const toml::node& node, const std::string& field) const {
    const auto* b = node.as_boolean();
    if (!b) error(node, field, "must be true or false, got " + describe(node));
    return b->get();
}

Vec3f Parser::vec3(const toml::node& node, const std::string& field, bool direction) const {
    const toml::array* xyz = node.as_array();
    if (!xyz || xyz->size() != 3)
        error(node, field,
              std::string("must be ") + (direction ? "a direction" : "a point") +
                  " [x, y, z], got " + describe(node) +
                  (xyz ? cat(" of ", xyz->size(), " values") : std::string()));
    Vec3f v;
    const Range range{-kMaxCoordinate, kMaxCoordinate};
    for (int c = 0; c < 3; ++c)
        v[c] = static_cast<float>(real((*xyz)[c], cat(field, "[", c, "]"), range));
    if (direction && !(v.norm() > 1e-6f))
        error(node, field, "must be a non-zero direction, got [0, 0, 0]");
    return v;
}

std::vector<Vec3f> Parser::points(const toml::node& node, const std::string& field) const {
    const toml::array* array = node.as_array();
    if (!array) error(node, field, "must be an array of [x, y, z] points, got " + describe(node));
    if (array->size() < 2 || array->size() > kMaxTrajectoryPoints)
        error(node, field,
              cat("must hold 2 to ", kMaxTrajectoryPoints, " points, got ", array->size()));
    std::vector<Vec3f> out;
    out.reserve(array->size());
    for (size_t i = 0; i < array->size(); ++i)
        out.push_back(vec3((*array)[i], cat(field, "[", i, "]"), false));
    for (size_t i = 1; i < out.size(); ++i)
        if (out[i] == out[i - 1])
            error((*array)[i], cat(field, "[", i, "]"),
                  "repeats the previous point: a trajectory needs a direction between points");
    return out;
}

const toml::array* Parser::tables(const toml::table& parent, const std::string& path,
                                  std::string_view key) const {
    const toml::node* node = parent.get(key);
    if (!node) return nullptr;
    const std::string field = join_path(path, key);
    if (node->is_table())
        error(*node, field, "must be an array of tables: write [[" + field + "]] for each");
    const toml::array* array = node->as_array();
    if (!array)
        error(*node, field,
              "must be an array of tables ([[" + field + "]]), got " + describe(*node));
    for (size_t i = 0; i < array->size(); ++i)
        if (!(*array)[i].is_table())
            error((*array)[i], cat(field, "[", i, "]"),
                  "must be a table, got " + describe((*array)[i]));
    return array;
}

const char* kind_name(Distribution::Kind kind) {
    switch (kind) {
        case Distribution::Kind::kConstant:
            return "constant";
        case Distribution::Kind::kUniform:
            return "uniform";
        case Distribution::Kind::kNormal:
            return "normal";
        case Distribution::Kind::kTable:
            return "table";
    }
    return "?";
}

std::vector<std::string> distribution_parameters(Distribution::Kind kind) {
    switch (kind) {
        case Distribution::Kind::kConstant:
            return {"value"};
        case Distribution::Kind::kUniform:
            return {"min", "max"};
        case Distribution::Kind::kNormal:
            return {"mean", "stddev", "min", "max"};
        case Distribution::Kind::kTable:
            return {"values", "min", "max"};
    }
    return {};
}

Distribution Parser::distribution(const toml::node& node, const std::string& field,
                                  const Distribution& current, const Domain& domain) const {
    const Range value_range{domain.lo, domain.hi, domain.positive};
    const Range bound_range{domain.lo, domain.hi};
    if (node.is_number()) {
        Distribution d;
        d.kind = Distribution::Kind::kConstant;
        d.value = static_cast<float>(real(node, field, value_range));
        d.min = domain.lo;
        d.max = domain.hi;
        return d;
    }
    const toml::table* table = node.as_table();
    if (!table)
        error(node, field,
              "must be a number or a table such as { distribution = \"normal\", mean = …, "
              "stddev = … }, got " +
                  describe(node));
    check_keys(*table, field, kDistributionKeys);

    // With `distribution`, the table is a whole new distribution; without, it adjusts the
    // parameters of the current one (the default or the color preset).
    Distribution d = current;
    const toml::node* kind_node = table->get("distribution");
    if (kind_node) {
        d = Distribution{};
        d.kind = choice<Distribution::Kind>(*kind_node, field + ".distribution",
                                            {{"constant", Distribution::Kind::kConstant},
                                             {"uniform", Distribution::Kind::kUniform},
                                             {"normal", Distribution::Kind::kNormal},
                                             {"table", Distribution::Kind::kTable}});
        d.min = domain.lo;
        d.max = domain.hi;
    }
    const auto parameters = distribution_parameters(d.kind);
    for (auto&& [key, value] : *table) {
        if (key.str() == "distribution") continue;
        if (std::find(parameters.begin(), parameters.end(), key.str()) == parameters.end())
            error(value, join_path(field, key.str()),
                  std::string("not used by a ") + kind_name(d.kind) + " distribution (it takes " +
                      list(parameters, false) + ")" +
                      (kind_node ? "" : "; set 'distribution' to change the kind"));
    }
    if (kind_node) {
        const std::vector<std::string> required =
            d.kind == Distribution::Kind::kConstant ? std::vector<std::string>{"value"}
            : d.kind == Distribution::Kind::kNormal ? std::vector<std::string>{"mean", "stddev"}
            : d.kind == Distribution::Kind::kTable  ? std::vector<std::string>{"values"}
                                                    : std::vector<std::string>{};
        for (const auto& key : required)
            if (!table->get(key))
                error(*table, join_path(field, key),
                      std::string("required by a ") + kind_name(d.kind) + " distribution");
    }

    const std::string path = field;
    opt_real(table, path, "value", d.value, value_range);
    opt_real(table, path, "min", d.min, bound_range);
    opt_real(table, path, "max", d.max, bound_range);
    opt_real(table, path, "stddev", d.stddev, Range{0, double(domain.hi) - domain.lo});
    opt_real(table, path, "mean", d.mean, bound_range);
    if (const toml::node* values = table->get("values")) {
        const std::string values_field = field + ".values";
        const toml::array* array = values->as_array();
        if (!array)
            error(*values, values_field, "must be an array of numbers, got " + describe(*values));
        if (array->size() < 2 || array->size() > kMaxTableValues)
            error(*values, values_field,
                  cat("must hold 2 to ", kMaxTableValues, " numbers, got ", array->size()));
        d.table.clear();
        double sum = 0;
        for (size_t i = 0; i < array->size(); ++i) {
            const double w = real((*array)[i], cat(values_field, "[", i, "]"), Range{0, 1e9});
            d.table.push_back(static_cast<float>(w));
            sum += w;
        }
        if (sum <= 0) error(*values, values_field, "must not be all zero");
    }

    // Relations between the parameters, reported where the offending value is written.
    const auto where = [&](const char* key) -> const toml::node& {
        const toml::node* n = table->get(key);
        return n ? *n : static_cast<const toml::node&>(*table);
    };
    if (d.kind == Distribution::Kind::kConstant) return d;
    if (d.min > d.max) {
        const char* key = table->get("max") ? "max" : "min";
        error(where(key), field + "." + key,
              cat("min must be ≤ max, got min = ", number(d.min), " and max = ", number(d.max)));
    }
    if (domain.positive && d.max <= domain.lo)
        error(where("max"), field + ".max",
              "must be > " + number(domain.lo) + ", got " + number(d.max));
    if (d.kind == Distribution::Kind::kNormal && (d.mean < d.min || d.mean > d.max))
        error(where("mean"), field + ".mean",
              "must lie within [min, max] = [" + number(d.min) + ", " + number(d.max) + "], got " +
                  number(d.mean));
    return d;
}

std::string Parser::procedural_name(const toml::node& node, const std::string& field) const {
    const std::string name = string(node, field, true);
    const auto& names = procedural_map_names();
    if (std::find(names.begin(), names.end(), name) != names.end()) return name;
    std::string what =
        "unknown procedural map " + toml_string(name) + "; the names are " + list(names, true);
    if (const auto near = closest(name, names))
        what += " (did you mean " + toml_string(*near) + "?)";
    error(node, field, what);
}

ScalarMap Parser::map(const toml::node& node, const std::string& field,
                      const MapRules& rules) const {
    ScalarMap m;
    m.low = rules.low;
    m.high = rules.high;
    if (node.is_number()) {
        m.kind = ScalarMap::Kind::kConstant;
        m.value = static_cast<float>(
            real(node, field, rules.some_positive ? Range{0, rules.range.hi, true} : rules.range));
        return m;
    }
    if (node.is_string()) {
        m.kind = ScalarMap::Kind::kProcedural;
        m.procedural = procedural_name(node, field);
        return m;
    }
    const toml::table* table = node.as_table();
    if (!table)
        error(node, field,
              "must be a number, a procedural map name or a table such as { image = \"map.png\", "
              "low = …, high = … }, got " +
                  describe(node));
    check_keys(*table, field, kMapKeys);
    std::vector<std::string> sources;
    for (const char* key : {"value", "image", "procedural"})
        if (table->get(key)) sources.push_back(key);
    if (sources.empty()) error(*table, field, "needs one of value, image or procedural");
    if (sources.size() > 1)
        error(*table->get(sources[1]), join_path(field, sources[1]),
              "cannot be combined with '" + sources[0] + "': give one of value, image, procedural");
    if (const toml::node* value = table->get("value")) {
        for (const char* key : {"low", "high"})
            if (const toml::node* n = table->get(key))
                error(*n, join_path(field, key), "only applies to image and procedural maps");
        m.kind = ScalarMap::Kind::kConstant;
        m.value = static_cast<float>(
            real(*value, field + ".value",
                 rules.some_positive ? Range{0, rules.range.hi, true} : rules.range));
        return m;
    }
    if (const toml::node* image = table->get("image")) {
        m.kind = ScalarMap::Kind::kImage;
        m.image = path(*image, field + ".image");
    } else {
        m.kind = ScalarMap::Kind::kProcedural;
        m.procedural = procedural_name(*table->get("procedural"), field + ".procedural");
    }
    opt_real(table, field, "low", m.low, rules.range);
    opt_real(table, field, "high", m.high, rules.range);
    if (rules.some_positive && std::max(m.low, m.high) <= 0)
        error(*table, field, "low and high must not both be 0 (no hair would grow)");
    return m;
}

void Parser::read_head(const toml::table* root, Style& style) const {
    const toml::table* head = section(root, "", "head");
    if (!head) return;
    if (const toml::node* obj = head->get("obj")) style.head.obj = path(*obj, "head.obj");
    opt_real(head, "head", "scale", style.head.scale, Range{0, 1e6, true});

    const toml::table* scalp = section(head, "head", "scalp");
    if (!scalp) return;
    ScalpSpec& spec = style.head.scalp;
    // Which method each key belongs to; the method is inferred from the keys when not named.
    const std::vector<std::pair<std::string, ScalpSpec::Kind>> owners = {
        {"group", ScalpSpec::Kind::kGroup},
        {"mask", ScalpSpec::Kind::kMask},
        {"front", ScalpSpec::Kind::kHairline},
        {"side", ScalpSpec::Kind::kHairline},
        {"back", ScalpSpec::Kind::kHairline}};
    const std::vector<std::pair<std::string, ScalpSpec::Kind>> methods = {
        {"group", ScalpSpec::Kind::kGroup},
        {"mask", ScalpSpec::Kind::kMask},
        {"hairline", ScalpSpec::Kind::kHairline}};
    const auto method_name = [&](ScalpSpec::Kind kind) {
        for (const auto& [name, k] : methods)
            if (k == kind) return name;
        return std::string();
    };
    std::optional<ScalpSpec::Kind> kind;
    std::string decided_by;
    if (const toml::node* method = scalp->get("method")) {
        kind = choice(*method, "head.scalp.method", methods);
        decided_by = "method = " + toml_string(method_name(*kind));
    }
    for (const auto& [key, owner] : owners) {
        const toml::node* node = scalp->get(key);
        if (!node) continue;
        if (!kind) {
            kind = owner;
            decided_by = "'head.scalp." + key + "'";
        } else if (*kind != owner) {
            error(*node, "head.scalp." + key,
                  "belongs to method = " + toml_string(method_name(owner)) + ", but " + decided_by +
                      " selects method " + toml_string(method_name(*kind)));
        }
    }
    if (kind) spec.kind = *kind;
    if (const toml::node* group = scalp->get("group"))
        spec.group = string(*group, "head.scalp.group", true);
    if (const toml::node* mask = scalp->get("mask")) spec.mask = path(*mask, "head.scalp.mask");
    if (spec.kind == ScalpSpec::Kind::kMask && spec.mask.empty())
        error(*scalp, "head.scalp.mask", "required by method = \"mask\"");
    const Range depth{0, 50, true};
    opt_real(scalp, "head.scalp", "front", spec.hairline_front, depth);
    opt_real(scalp, "head.scalp", "side", spec.hairline_side, depth);
    opt_real(scalp, "head.scalp", "back", spec.hairline_back, depth);
}

void Parser::read_roots(const toml::table* root, Style& style) const {
    const toml::table* roots = section(root, "", "roots");
    if (!roots) return;
    opt_int(roots, "roots", "wisps", style.wisps, 1, kMaxStrands);
    opt_int(roots, "roots", "strands", style.strands, 1, kMaxStrands);
    opt_int(roots, "roots", "points_per_strand", style.points_per_strand, 4, kMaxPointsPerStrand);
    if (style.wisps > style.strands) {
        if (const toml::node* wisps = roots->get("wisps"))
            error(*wisps, "roots.wisps",
                  cat("must be ≤ roots.strands (", style.strands, "), got ", style.wisps));
        error(*roots->get("strands"), "roots.strands",
              cat("must be ≥ roots.wisps (", style.wisps, "), got ", style.strands));
    }
    const int64_t total = int64_t(style.strands) * style.points_per_strand;
    if (total > kMaxTotalPoints) {
        const toml::node* node = roots->get("points_per_strand");
        const bool per_strand = node != nullptr;
        if (!node) node = roots->get("strands");
        error(*node, per_strand ? "roots.points_per_strand" : "roots.strands",
              cat("strands × points_per_strand must be ≤ ", kMaxTotalPoints, ", got ",
                  style.strands, " × ", style.points_per_strand, " = ", total));
    }
}

void Parser::read_maps(const toml::table* root, Style& style) const {
    const toml::table* maps = section(root, "", "maps");
    if (!maps) return;
    if (const toml::node* n = maps->get("density"))
        style.density = map(*n, "maps.density", {Range{0, 1e6}, true, 0.f, 1.f});
    if (const toml::node* n = maps->get("length"))
        style.length = map(*n, "maps.length", {Range{0, 500, true}, false, 1.f, 25.f});
    if (const toml::node* n = maps->get("protrusion"))
        style.protrusion = map(*n, "maps.protrusion", {Range{0, 1}, false, 0.f, 1.f});
}

void Parser::read_growth(const toml::table* root, Style& style) const {
    const toml::table* growth = section(root, "", "growth");
    if (!growth) return;
    GrowthSpec& spec = style.growth;
    float side = 1.f;
    if (const toml::node* n = growth->get("part")) {
        using Part = GrowthSpec::Part;
        const int part =
            choice<int>(*n, "growth.part", {{"none", 0}, {"centre", 1}, {"left", 2}, {"right", 3}});
        spec.part = part == 0 ? Part::kNone : part == 1 ? Part::kCentre : Part::kSide;
        side = part == 3 ? -1.f : 1.f;
    }
    opt_real(growth, "growth", "part_offset", spec.part_offset, Range{0, 0.8, true});
    spec.part_offset = side * std::abs(spec.part_offset);
    opt_real(growth, "growth", "part_length", spec.part_length, Range{0, 3, true});
    if (const toml::node* n = growth->get("front"))
        spec.front = choice<GrowthSpec::Front>(*n, "growth.front",
                                               {{"sides", GrowthSpec::Front::kSides},
                                                {"back", GrowthSpec::Front::kBack},
                                                {"fringe", GrowthSpec::Front::kFringe}});
    opt_vec3(growth, "growth", "whorl", spec.whorl, true);
    if (const toml::node* n = growth->get("whorl_turn"))
        spec.whorl_turn = choice<float>(*n, "growth.whorl_turn",
                                        {{"clockwise", 1.f}, {"counter-clockwise", -1.f}});
    opt_real(growth, "growth", "whorl_swirl", spec.whorl_swirl, Range{0, 2});
    if (const toml::node* n = growth->get("map")) spec.map = path(*n, "growth.map");
    opt_real(growth, "growth", "map_strength", spec.map_strength, Range{0, 1});
}

void Parser::read_strand(const toml::table* root, Style& style) const {
    const toml::table* strand = section(root, "", "strand");
    opt_real(strand, "strand", "root_width", style.root_width, Range{0, 1, true});
    opt_real(strand, "strand", "tip_width", style.tip_width, Range{0, 1, true});
}

void Parser::read_prototype(const toml::table* root, Style& style) const {
    const toml::table* prototype = section(root, "", "prototype");
    if (!prototype) return;
    PrototypeSpec& spec = style.prototype;
    const toml::node* points = prototype->get("points");
    if (const toml::node* shape = prototype->get("shape")) {
        spec.kind = choice<PrototypeSpec::Kind>(*shape, "prototype.shape",
                                                {{"straight", PrototypeSpec::Kind::kStraight},
                                                 {"wavy", PrototypeSpec::Kind::kWavy},
                                                 {"curly", PrototypeSpec::Kind::kCurly},
                                                 {"kinky", PrototypeSpec::Kind::kKinky},
                                                 {"polyline", PrototypeSpec::Kind::kPolyline}});
        if (points && spec.kind != PrototypeSpec::Kind::kPolyline)
            error(*points, "prototype.points",
                  "only used with shape = \"polyline\", but shape is " + describe(*shape));
    } else if (points) {
        spec.kind = PrototypeSpec::Kind::kPolyline;
    }
    opt_real(prototype, "prototype", "amplitude", spec.amplitude, Range{0, 100});
    opt_real(prototype, "prototype", "period", spec.period, Range{0, 1000, true});
    opt_real(prototype, "prototype", "length", spec.length, Range{0, 1000, true});
    opt_int(prototype, "prototype", "window", spec.window, 1, 256);
    opt_real(prototype, "prototype", "temperature", spec.temperature, Range{0, 100});
    opt_real(prototype, "prototype", "roll", spec.roll, Range{0, 3.1416});
    if (spec.kind != PrototypeSpec::Kind::kPolyline) return;
    if (!points) error(*prototype, "prototype.points", "required by shape = \"polyline\"");
    const toml::array* array = points->as_array();
    if (!array)
        error(*points, "prototype.points",
              "must be an array of [x, y, z] points, got " + describe(*points));
    if (array->size() < 4 || array->size() > kMaxPolylinePoints)
        error(*points, "prototype.points",
              cat("must hold 4 to ", kMaxPolylinePoints, " points, got ", array->size()));
    spec.polyline.clear();
    for (size_t i = 0; i < array->size(); ++i) {
        const std::string field = cat("prototype.points[", i, "]");
        const toml::node& p = (*array)[i];
        const toml::array* xyz = p.as_array();
        if (!xyz || xyz->size() != 3)
            error(p, field, "must be a point [x, y, z] in cm, got " + describe(p));
        Vec3f v;
        for (int c = 0; c < 3; ++c)
            v[c] = static_cast<float>(real((*xyz)[c], cat(field, "[", c, "]"), Range{-1e4, 1e4}));
        spec.polyline.push_back(v);
    }
    if (spec.window >= int(spec.polyline.size()))
        error(prototype->get("window") ? *prototype->get("window") : *points, "prototype.window",
              cat("must be < the number of prototype points (", spec.polyline.size(), "), got ",
                  spec.window));
}

void Parser::read_wisp(const toml::table* root, Style& style) const {
    const toml::table* wisp = section(root, "", "wisp");
    if (!wisp) return;
    WispSpec& spec = style.wisp;
    if (const toml::node* n = wisp->get("length"))
        spec.length = distribution(*n, "wisp.length", spec.length, Domain{0, 1, true});
    if (const toml::node* n = wisp->get("deviation_radius")) {
        const std::string field = "wisp.deviation_radius";
        const Range range{0, 100, true};
        spec.deviation_radius.clear();
        if (n->is_number()) {
            spec.deviation_radius.push_back(static_cast<float>(real(*n, field, range)));
        } else if (const toml::array* array = n->as_array()) {
            if (array->empty() || array->size() > kMaxDeviationRadii)
                error(*n, field,
                      cat("must hold 1 to ", kMaxDeviationRadii, " numbers, got ", array->size()));
            for (size_t i = 0; i < array->size(); ++i)
                spec.deviation_radius.push_back(
                    static_cast<float>(real((*array)[i], cat(field, "[", i, "]"), range)));
        } else {
            error(*n, field, "must be a number or an array of numbers, got " + describe(*n));
        }
    }
    opt_real(wisp, "wisp", "fuzziness", spec.fuzziness, Range{0, 10});
}

// Realistic natural colors (HSV means and spreads, per-strand and per-wisp), the starting
// point that explicit color fields then adjust.
struct ColorPreset {
    const char* name;
    float hue, hue_sd, saturation, saturation_sd, value, value_sd;
    float wisp_hue, wisp_saturation, wisp_value;
};

const std::vector<ColorPreset>& color_presets() {
    static const std::vector<ColorPreset> presets = {
        {"black", 25, 3, 0.30f, 0.05f, 0.08f, 0.02f, 2, 0.03f, 0.01f},
        {"dark-brown", 25, 2, 0.50f, 0.05f, 0.17f, 0.03f, 1.5f, 0.03f, 0.02f},
        {"brown", 28, 2, 0.55f, 0.04f, 0.30f, 0.04f, 1.5f, 0.03f, 0.03f},
        {"auburn", 16, 2, 0.65f, 0.05f, 0.33f, 0.04f, 1.5f, 0.03f, 0.03f},
        {"red", 12, 2, 0.75f, 0.05f, 0.45f, 0.05f, 1.5f, 0.04f, 0.03f},
        {"blonde", 40, 2, 0.45f, 0.05f, 0.72f, 0.05f, 2, 0.04f, 0.04f},
        {"platinum", 45, 3, 0.12f, 0.03f, 0.88f, 0.03f, 2, 0.02f, 0.02f},
        {"gray", 30, 5, 0.06f, 0.03f, 0.60f, 0.12f, 3, 0.02f, 0.05f},
    };
    return presets;
}

void Parser::read_color(const toml::table* root, Style& style) const {
    const toml::table* color = section(root, "", "color");
    if (!color) return;
    ColorSpec& spec = style.color;
    if (const toml::node* preset = color->get("preset")) {
        std::vector<std::pair<std::string, const ColorPreset*>> options;
        for (const auto& p : color_presets())
            options.emplace_back(p.name, &p);
        const ColorPreset& p = *choice(*preset, "color.preset", options);
        const auto normal = [](float mean, float sd, float hi) {
            Distribution d;
            d.kind = Distribution::Kind::kNormal;
            d.mean = mean;
            d.stddev = sd;
            d.min = 0;
            d.max = hi;
            return d;
        };
        spec.hue = normal(p.hue, p.hue_sd, 360);
        spec.saturation = normal(p.saturation, p.saturation_sd, 1);
        spec.value = normal(p.value, p.value_sd, 1);
        spec.wisp_hue = p.wisp_hue;
        spec.wisp_saturation = p.wisp_saturation;
        spec.wisp_value = p.wisp_value;
    }
    if (const toml::node* n = color->get("hue"))
        spec.hue = distribution(*n, "color.hue", spec.hue, Domain{0, 360});
    if (const toml::node* n = color->get("saturation"))
        spec.saturation = distribution(*n, "color.saturation", spec.saturation, Domain{0, 1});
    if (const toml::node* n = color->get("value"))
        spec.value = distribution(*n, "color.value", spec.value, Domain{0, 1});
    opt_real(color, "color", "wisp_hue", spec.wisp_hue, Range{0, 180});
    opt_real(color, "color", "wisp_saturation", spec.wisp_saturation, Range{0, 1});
    opt_real(color, "color", "wisp_value", spec.wisp_value, Range{0, 1});
}

void Parser::read_solve(const toml::table* root, Style& style) const {
    const toml::table* solve = section(root, "", "solve");
    if (!solve) return;
    SolveSpec& spec = style.solve;
    opt_bool(solve, "solve", "enabled", spec.enabled);
    opt_real(solve, "solve", "stiffness", spec.stiffness, Range{0, 1000});
    opt_real(solve, "solve", "threshold", spec.threshold, Range{0, 1, true});
    opt_real(solve, "solve", "cell", spec.cell, Range{0.2, 10});
    opt_real(solve, "solve", "full_density", spec.full_density, Range{0, 1e9, true});
    opt_real(solve, "solve", "bend_step", spec.bend_step, Range{0, 45, true});
    opt_int(solve, "solve", "max_tries", spec.max_tries, 0, 1000);
    opt_real(solve, "solve", "head_margin", spec.head_margin, Range{0, 10});
    if (const toml::node* order = solve->get("order"))
        spec.depth_first =
            choice<bool>(*order, "solve.order", {{"breadth-first", false}, {"depth-first", true}});
    if (const toml::array* terms = tables(*solve, "solve", "field")) {
        if (terms->size() > kMaxFieldTerms)
            error(*solve->get("field"), "solve.field",
                  cat("must hold at most ", kMaxFieldTerms, " terms, got ", terms->size()));
        spec.field.clear();
        for (size_t i = 0; i < terms->size(); ++i) {
            const std::string path = cat("solve.field[", i, "]");
            const toml::table& term = *(*terms)[i].as_table();
            check_keys(term, path, kFieldKeys);
            spec.field.push_back(field_term(term, path));
        }
    }
}

FieldTerm Parser::field_term(const toml::table& table, const std::string& path) const {
    using Kind = FieldTerm::Kind;
    const std::vector<std::pair<std::string, Kind>> kinds = {
        {"gravity", Kind::kGravity},    {"pulled-back", Kind::kPulledBack},
        {"side-part", Kind::kSidePart}, {"wind", Kind::kWind},
        {"file", Kind::kFile},          {"growth", Kind::kGrowth}};
    const toml::node* kind = table.get("kind");
    if (!kind)
        error(table, path + ".kind",
              "required: one of \"gravity\", \"pulled-back\", \"side-part\", \"wind\", \"file\", "
              "\"growth\"");
    FieldTerm term;
    term.kind = choice(*kind, path + ".kind", kinds);
    // Each kind's own parameter, rejected with the others so a misplaced key is not ignored.
    const std::vector<std::pair<std::string, Kind>> owners = {
        {"direction", Kind::kWind}, {"side", Kind::kSidePart}, {"file", Kind::kFile}};
    for (const auto& [key, owner] : owners) {
        const toml::node* node = table.get(key);
        if (!node || owner == term.kind) continue;
        std::string owner_name;
        for (const auto& [name, k] : kinds)
            if (k == owner) owner_name = name;
        error(*node, join_path(path, key),
              "only used with kind = " + toml_string(owner_name) + ", but kind is " +
                  describe(*kind));
    }
    opt_real(&table, path, "weight", term.weight, Range{-1000, 1000});
    opt_vec3(&table, path, "direction", term.direction, true);
    if (const toml::node* side = table.get("side"))
        term.side = choice<float>(*side, path + ".side", {{"left", 1.f}, {"right", -1.f}});
    if (const toml::node* file = table.get("file")) term.file = this->path(*file, path + ".file");
    if (term.kind == Kind::kFile && term.file.empty())
        error(table, path + ".file", "required by kind = \"file\"");
    return term;
}

void Parser::read_cut(const toml::table* root, Style& style) const {
    const toml::table* cut = section(root, "", "cut");
    if (!cut) return;
    CutSpec& spec = style.cut;
    spec.enabled = true;
    opt_bool(cut, "cut", "enabled", spec.enabled);
    if (const toml::node* n = cut->get("region"))
        spec.region = choice<CutSpec::Region>(
            *n, "cut.region",
            {{"all", CutSpec::Region::kAll}, {"fringe", CutSpec::Region::kFringe}});
    opt_vec3(cut, "cut", "normal", spec.normal, true);
    opt_real(cut, "cut", "offset", spec.offset, Range{-kMaxCoordinate, kMaxCoordinate});
    opt_bool(cut, "cut", "head_relative", spec.head_relative);
}

void Parser::read_dynamics(const toml::table* root, Style& style) const {
    const toml::table* dyn = section(root, "", "dynamics");
    if (!dyn) return;
    DynamicsSpec& spec = style.dynamics;
    const std::string d = "dynamics";
    opt_int(dyn, d, "levels", spec.levels, 2, 4);
    opt_int(dyn, d, "wisps_per_group", spec.wisps_per_group, 2, 64);
    opt_int(dyn, d, "sub_wisps", spec.sub_wisps, 2, 16);
    opt_int(dyn, d, "sections", spec.sections, 3, 64);
    opt_int(dyn, d, "strands_per_wisp", spec.strands_per_wisp, 1, kMaxStrands);
    if (const toml::node* links = dyn->get("links"))
        spec.links = choice<DynamicsSpec::Links>(*links, "dynamics.links",
                                                 {{"auto", DynamicsSpec::Links::kAuto},
                                                  {"rigid", DynamicsSpec::Links::kRigid},
                                                  {"soft", DynamicsSpec::Links::kSoft}});
    opt_real(dyn, d, "stiffness", spec.stiffness, Range{0, 1e5});
    opt_real(dyn, d, "stretch", spec.stretch, Range{0, 1e6});
    opt_real(dyn, d, "damping", spec.damping, Range{0, 1000});
    opt_real(dyn, d, "air_drag", spec.air_drag, Range{0, 1000});
    opt_real(dyn, d, "split_threshold", spec.split_threshold, Range{0, 1e3, true});
    opt_real(dyn, d, "merge_velocity", spec.merge_velocity, Range{0, 1e5, true});
    opt_real(dyn, d, "friction", spec.friction, Range{0, 1e4});
    opt_real(dyn, d, "repulsion", spec.repulsion, Range{0, 1e6});
    opt_real(dyn, d, "repulsion_angle", spec.repulsion_angle, Range{0, 90});
    opt_real(dyn, d, "voxel", spec.voxel, Range{0, 100});
    opt_int(dyn, d, "iterations", spec.iterations, 0, 100);
    opt_bool(dyn, d, "hair_collisions", spec.hair_collisions);
    opt_bool(dyn, d, "body_collisions", spec.body_collisions);
    opt_real(dyn, d, "dt", spec.dt, Range{0, 0.05, true});
    opt_real(dyn, d, "linear_density", spec.linear_density, Range{0, 1, true});
    if (spec.friction * spec.dt >= 1)
        error(*dyn, "dynamics.friction",
              cat("friction · dt must be under 1 (§4.2: friction must not reverse the relative "
                  "motion), got ",
                  spec.friction, " · ", spec.dt, " = ", spec.friction * spec.dt));
}

Selection Parser::selection(const toml::table& table, const std::string& path, int wisps,
                            bool with_parts) const {
    Selection s;
    std::vector<std::string> given;
    for (const auto& key : kSelectionSources)
        if (table.get(key)) given.push_back(key);
    if (given.size() > 1)
        error(*table.get(given[1]), join_path(path, given[1]),
              "cannot be combined with '" + given[0] + "': a group selects by one of " +
                  list(kSelectionSources, false));
    if (const toml::node* node = table.get("select")) {
        s.kind = choice<Selection::Kind>(*node, path + ".select", {{"all", Selection::Kind::kAll}});
    } else if (const toml::node* node = table.get("region")) {
        s.kind = Selection::Kind::kRegion;
        s.region = procedural_name(*node, path + ".region");
    } else if (const toml::node* node = table.get("mask")) {
        s.kind = Selection::Kind::kMask;
        s.mask = this->path(*node, path + ".mask");
    } else if (const toml::node* node = table.get("box")) {
        const std::string field = path + ".box";
        const toml::table* box = node->as_table();
        if (!box)
            error(*node, field,
                  "must be a table { min = [x, y, z], max = [x, y, z] }, got " + describe(*node));
        check_keys(*box, field, {"min", "max"});
        for (const char* key : {"min", "max"})
            if (!box->get(key)) error(*box, join_path(field, key), "required");
        s.kind = Selection::Kind::kBox;
        s.lo = vec3(*box->get("min"), field + ".min", false);
        s.hi = vec3(*box->get("max"), field + ".max", false);
        for (int c = 0; c < 3; ++c)
            if (s.hi[c] < s.lo[c])
                error(*box->get("max"), field + ".max",
                      cat("must be ≥ min in every coordinate, got max[", c, "] = ", number(s.hi[c]),
                          " < min[", c, "] = ", number(s.lo[c])));
    } else if (const toml::node* node = table.get("half_space")) {
        const std::string field = path + ".half_space";
        const toml::table* half = node->as_table();
        if (!half)
            error(*node, field,
                  "must be a table { normal = [x, y, z], offset = … }, got " + describe(*node));
        check_keys(*half, field, {"normal", "offset"});
        if (!half->get("normal")) error(*half, field + ".normal", "required");
        s.kind = Selection::Kind::kHalfSpace;
        s.normal = vec3(*half->get("normal"), field + ".normal", true);
        opt_real(half, field, "offset", s.offset, Range{-kMaxCoordinate, kMaxCoordinate});
    } else if (const toml::node* node = table.get("wisps")) {
        const std::string field = path + ".wisps";
        const toml::array* ids = node->as_array();
        if (!ids) error(*node, field, "must be an array of wisp ids, got " + describe(*node));
        if (ids->empty() || ids->size() > size_t(wisps))
            error(*node, field,
                  cat("must hold 1 to roots.wisps (", wisps, ") ids, got ", ids->size()));
        s.kind = Selection::Kind::kWisps;
        for (size_t i = 0; i < ids->size(); ++i) {
            const std::string id_field = cat(field, "[", i, "]");
            const int64_t id = integer((*ids)[i], id_field, 0, std::numeric_limits<int>::max());
            if (id >= wisps)
                error((*ids)[i], id_field,
                      cat("must be < roots.wisps (", wisps, "), got ", id,
                          " (wisp ids count from 0)"));
            if (std::find(s.wisps.begin(), s.wisps.end(), int(id)) != s.wisps.end())
                error((*ids)[i], id_field, cat("lists wisp ", id, " twice"));
            s.wisps.push_back(int(id));
        }
    }
    opt_bool(&table, path, "head_relative", s.head_relative);
    if (!with_parts) {
        for (const char* key : {"part", "parts"})
            if (const toml::node* node = table.get(key))
                error(*node, join_path(path, key),
                      "is set by the braid: its selection is split into `strands` parts");
        return s;
    }
    opt_int(&table, path, "parts", s.parts, 1, int64_t(kMaxGroups));
    if (const toml::node* node = table.get("part")) {
        s.part = static_cast<int>(integer(*node, path + ".part", 0, kMaxGroups));
        if (s.part >= s.parts)
            error(*node, path + ".part",
                  cat("must be < parts (", s.parts, "), got ", s.part, " (parts count from 0)"));
    } else if (table.get("parts")) {
        error(*table.get("parts"), path + ".part",
              "required with 'parts': which of the parts (0 to parts − 1) the group keeps");
    }
    return s;
}

ConstraintSpec Parser::constraint(const toml::table& table, const std::string& path,
                                  bool head_relative) const {
    using Kind = ConstraintSpec::Kind;
    const toml::node* kind = table.get("kind");
    if (!kind)
        error(table, path + ".kind", "required: one of \"point\", \"trajectory\", \"direction\"");
    ConstraintSpec c;
    c.kind = choice<Kind>(*kind, path + ".kind",
                          {{"point", Kind::kPoint},
                           {"trajectory", Kind::kTrajectory},
                           {"direction", Kind::kDirection}});
    c.head_relative = head_relative;
    opt_bool(&table, path, "head_relative", c.head_relative);
    const bool is_point = c.kind == Kind::kPoint;
    for (const char* key : {"trajectory", "smooth"})
        if (const toml::node* node = table.get(key); node && is_point)
            error(*node, join_path(path, key),
                  "only used with kind = \"trajectory\" or \"direction\", but kind is \"point\"");
    if (const toml::node* node = table.get("point"); node && !is_point)
        error(*node, path + ".point",
              "only used with kind = \"point\", but kind is " + describe(*kind));
    if (is_point) {
        if (!table.get("point")) error(table, path + ".point", "required by kind = \"point\"");
        c.point = vec3(*table.get("point"), path + ".point", false);
    } else {
        if (!table.get("trajectory"))
            error(table, path + ".trajectory", "required by kind = " + describe(*kind));
        c.trajectory = points(*table.get("trajectory"), path + ".trajectory");
        opt_bool(&table, path, "smooth", c.smooth);
    }
    // Tolerance radii hug the target; a direction's influence radius reaches further.
    const float unit = c.head_relative ? 1.f : 10.f;
    c.radius = (c.kind == Kind::kDirection ? 0.4f : 0.1f) * unit;
    opt_real(&table, path, "radius", c.radius, Range{0, kMaxCoordinate, true});
    opt_real(&table, path, "weight", c.weight, Range{0, 1});
    c.hold = is_point;
    opt_bool(&table, path, "hold", c.hold);
    return c;
}

// The group's name: `name` if given, else the section's path ("tie[1]"); a braid's groups
// add " strand i". head_relative, read with the selection, applies to the constraints too.
void finish_groups(std::vector<GroupSpec>& groups, const std::string& name) {
    for (size_t i = 0; i < groups.size(); ++i) {
        groups[i].name = groups.size() > 1 ? cat(name, " strand ", i) : name;
        for (ConstraintSpec& c : groups[i].queue)
            c.head_relative = groups[i].selection.head_relative;
    }
}

std::vector<GroupSpec> Parser::group(const toml::table& table, const std::string& path,
                                     int wisps) const {
    check_keys(table, path, kGroupKeys);
    GroupSpec g;
    g.name = path;
    if (const toml::node* name = table.get("name")) g.name = string(*name, path + ".name", true);
    g.selection = selection(table, path, wisps, true);
    const toml::array* queue = tables(table, path, "constraint");
    if (!queue || queue->empty())
        error(queue ? *table.get("constraint") : static_cast<const toml::node&>(table),
              path + ".constraint",
              "required: at least one [[group.constraint]] (the group's constraint queue)");
    if (queue->size() > kMaxQueue)
        error(*table.get("constraint"), path + ".constraint",
              cat("must hold at most ", kMaxQueue, " constraints, got ", queue->size()));
    for (size_t i = 0; i < queue->size(); ++i) {
        const std::string cpath = cat(path, ".constraint[", i, "]");
        const toml::table& c = *(*queue)[i].as_table();
        check_keys(c, cpath, kConstraintKeys);
        g.queue.push_back(constraint(c, cpath, g.selection.head_relative));
    }
    return {std::move(g)};
}

std::vector<GroupSpec> Parser::tie(const toml::table& table, const std::string& path,
                                   int wisps) const {
    check_keys(table, path, kTieKeys);
    TieSpec spec;
    spec.selection = selection(table, path, wisps, true);
    opt_vec3(&table, path, "point", spec.point, false);
    opt_real(&table, path, "radius", spec.radius, Range{0, kMaxCoordinate, true});
    opt_real(&table, path, "weight", spec.weight, Range{0, 1});
    return tie_groups(spec);
}

std::vector<GroupSpec> Parser::braid(const toml::table& table, const std::string& path,
                                     int wisps) const {
    check_keys(table, path, kBraidKeys);
    BraidSpec spec;
    spec.selection = selection(table, path, wisps, false);
    opt_int(&table, path, "strands", spec.strands, 3, 16);
    opt_vec3(&table, path, "start", spec.start, false);
    opt_vec3(&table, path, "axis", spec.axis, true);
    opt_vec3(&table, path, "side", spec.side, true);
    const Range positive{0, kMaxCoordinate, true};
    opt_real(&table, path, "length", spec.length, positive);
    opt_real(&table, path, "width", spec.width, positive);
    opt_real(&table, path, "period", spec.period, positive);
    opt_real(&table, path, "radius", spec.radius, positive);
    opt_real(&table, path, "weight", spec.weight, Range{0, 1});
    const float sine = spec.axis.normalized().cross(spec.side.normalized()).norm();
    if (sine < 0.05f) {
        const toml::node* node = table.get("side") ? table.get("side") : table.get("axis");
        error(node ? *node : static_cast<const toml::node&>(table),
              path + (table.get("side") ? ".side" : ".axis"),
              "side must point across the braid's axis, but side and axis are (nearly) parallel");
    }
    if (spec.length / spec.period > 1000)
        error(table.get("period") ? *table.get("period") : *table.get("length"),
              path + (table.get("period") ? ".period" : ".length"),
              cat("length / period must be ≤ 1000 crossing cycles, got ",
                  number(spec.length / spec.period)));
    return braid_groups(spec);
}

std::vector<GroupSpec> Parser::updo(const toml::table& table, const std::string& path,
                                    int wisps) const {
    check_keys(table, path, kUpdoKeys);
    UpdoSpec spec;
    spec.selection = selection(table, path, wisps, true);
    const Range positive{0, kMaxCoordinate, true};
    opt_vec3(&table, path, "point", spec.point, false);
    opt_vec3(&table, path, "facing", spec.facing, true);
    opt_real(&table, path, "radius", spec.radius, positive);
    opt_real(&table, path, "bun_radius", spec.bun_radius, positive);
    opt_real(&table, path, "turns", spec.turns, Range{0, 50, true});
    opt_real(&table, path, "weight", spec.weight, Range{0, 1});
    return updo_groups(spec);
}

std::vector<GroupSpec> Parser::comb(const toml::table& table, const std::string& path,
                                    int wisps) const {
    check_keys(table, path, kCombKeys);
    CombSpec spec;
    spec.selection = selection(table, path, wisps, true);
    const toml::node* trajectory = table.get("trajectory");
    if (!trajectory) error(table, path + ".trajectory", "required: the comb's path, ≥ 2 points");
    spec.trajectory = points(*trajectory, path + ".trajectory");
    opt_bool(&table, path, "smooth", spec.smooth);
    opt_real(&table, path, "radius", spec.radius, Range{0, kMaxCoordinate, true});
    opt_real(&table, path, "weight", spec.weight, Range{0, 1});
    return comb_groups(spec);
}

void Parser::read_groups(const toml::table* root, Style& style) const {
    using Reader =
        std::vector<GroupSpec> (Parser::*)(const toml::table&, const std::string&, int) const;
    const std::vector<std::pair<std::string, Reader>> kinds = {{"group", &Parser::group},
                                                               {"tie", &Parser::tie},
                                                               {"braid", &Parser::braid},
                                                               {"updo", &Parser::updo},
                                                               {"comb", &Parser::comb}};
    // toml++ keeps a table's keys sorted, not in file order; the headers' lines restore it,
    // so groups queue in the order they are written.
    struct Entry {
        uint32_t line;
        std::string path;
        Reader reader;
        const toml::table* table;
    };
    std::vector<Entry> entries;
    for (const auto& [key, reader] : kinds) {
        const toml::array* array = tables(*root, "", key);
        if (!array) continue;
        for (size_t i = 0; i < array->size(); ++i) {
            const toml::table* table = (*array)[i].as_table();
            entries.push_back({table->source().begin.line, cat(key, "[", i, "]"), reader, table});
        }
    }
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.line < b.line; });
    for (const Entry& e : entries) {
        std::vector<GroupSpec> groups = (this->*e.reader)(*e.table, e.path, style.wisps);
        std::string name = e.path;
        if (const toml::node* n = e.table->get("name")) name = string(*n, e.path + ".name", true);
        if (e.reader != &Parser::group) finish_groups(groups, name);
        if (style.groups.size() + groups.size() > kMaxGroups)
            error(*e.table, e.path,
                  cat("too many constraint groups: at most ", kMaxGroups, " in all"));
        for (GroupSpec& g : groups)
            style.groups.push_back(std::move(g));
    }
}

Style Parser::parse(std::string_view text) {
    toml::table root;
    try {
        root = toml::parse(text, source_);
    } catch (const toml::parse_error& e) {
        std::string description(e.description());
        std::replace(description.begin(), description.end(), '\n', ' ');
        fail(source_, ":", e.source().begin.line, ":", e.source().begin.column,
             ": TOML syntax error: ", excerpt(description, kMaxMessage));
    }
    check_keys(root, "", keys_of(""));

    Style style;
    if (const toml::node* name = root.get("name")) style.name = string(*name, "name", false);
    if (const toml::node* seed = root.get("seed"))
        style.seed =
            static_cast<uint64_t>(integer(*seed, "seed", 0, std::numeric_limits<int64_t>::max()));
    read_head(&root, style);
    read_roots(&root, style);
    read_maps(&root, style);
    read_growth(&root, style);
    read_strand(&root, style);
    read_prototype(&root, style);
    read_wisp(&root, style);
    read_color(&root, style);
    read_solve(&root, style);
    read_cut(&root, style);
    read_dynamics(&root, style);
    read_groups(&root, style);  // after [roots]: wisp ids are checked against roots.wisps
    return style;
}

}  // namespace

Style parse_style(std::string_view toml_text, const std::string& source,
                  const std::filesystem::path& base_dir) {
    return Parser(source, base_dir).parse(toml_text);
}

Style load_style(const std::filesystem::path& path) {
    const std::string source = path.string();
    std::error_code ec;
    if (fs::is_directory(path, ec)) fail(source, ": is a directory, not a style file");
    // Checked while reading: an endless file (/dev/zero, a pipe) reports size 0.
    const std::string text = read_file(path, {kMaxFileBytes, "a style file", true});
    Style style = parse_style(text, source, path.parent_path());
    if (style.name.empty()) style.name = path.stem().string();
    return style;
}

std::vector<std::string> preset_names() {
    std::vector<std::string> names;
    for (size_t i = 0; i < detail::kEmbeddedPresetCount; ++i)
        names.emplace_back(detail::kEmbeddedPresets[i].first);
    std::sort(names.begin(), names.end());
    return names;
}

std::string_view preset_text(const std::string& name) {
    for (size_t i = 0; i < detail::kEmbeddedPresetCount; ++i)
        if (detail::kEmbeddedPresets[i].first == name) return detail::kEmbeddedPresets[i].second;
    const auto names = preset_names();
    std::string hint;
    if (const auto near = closest(name, names)) hint = " (did you mean '" + *near + "'?)";
    fail("unknown preset '", name, "'", hint, "; the presets are: ", list(names, false));
}

Style load_preset(const std::string& name) {
    Style style = parse_style(preset_text(name), "preset '" + name + "'");
    if (style.name.empty()) style.name = name;
    return style;
}

}  // namespace wisp
