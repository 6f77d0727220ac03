#include "groom/style_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "groom/hairdressing.hpp"
#include "groom/maps.hpp"
#include "groom/style_schema.hpp"
#include "groom/toml_json.hpp"

namespace wisp {
namespace detail {
// Defined in presets.cpp, generated from presets/*.toml by embed_presets.cmake.
extern const std::pair<std::string_view, std::string_view> kEmbeddedPresets[];
extern const std::size_t kEmbeddedPresetCount;
}  // namespace detail

namespace {

namespace fs = std::filesystem;

// Bounds that keep a hostile or mistyped file from asking for absurd work or memory.
constexpr int64_t kMaxTotalPoints = 320'000'000;  // 10 M strands of 32 points
constexpr size_t kMaxTableValues = 1024;
constexpr size_t kMaxDeviationRadii = 256;
constexpr size_t kMaxPolylinePoints = 10'000;
constexpr std::uintmax_t kMaxFileBytes = 16u << 20;
constexpr size_t kMaxTrajectoryPoints = 10'000;
constexpr size_t kMaxGroups = 1024;  // constraint groups after expansion
constexpr size_t kMaxQueue = 256;    // constraints per group
constexpr size_t kMaxFieldTerms = 64;
// Messages quote at most this much of a field name, and are at most kMaxMessage long.
constexpr size_t kMaxQuotedField = 200;
constexpr size_t kMaxMessage = 1000;
// "Did you mean" compares with the known names only words up to this long.
constexpr size_t kMaxSuggestedWord = 64;

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

// A hairdressing section's number as the schema describes it (section_schema()).
const SectionField& section_field(std::string_view section, std::string_view key) {
    const SectionField* f = find_section_field(section, key);
    if (!f) fail("no schema entry for ", section, ".", key);  // a bug: the schema lists them
    return *f;
}

Range section_range(std::string_view section, std::string_view key) {
    const SectionField& f = section_field(section, key);
    return Range{f.lo, f.hi, f.lo_open};
}

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

using SectionTables = std::vector<std::pair<std::string, const toml::table*>>;
const toml::table* find_table(const SectionTables& tables, const std::string& name) {
    for (const auto& [n, t] : tables)
        if (n == name) return t;
    return nullptr;
}

class Parser {
  public:
    Parser(std::string source, fs::path base_dir, bool lines = true)
        : source_(std::move(source)), base_dir_(std::move(base_dir)), lines_(lines) {}

    Style parse(std::string_view text);
    // set_style_field: one field from a node, then its section's checks.
    void set(Style& style, const StyleField& field, const toml::node& node) const;

  private:
    [[noreturn]] void error(const toml::source_region& where, const std::string& field,
                            const std::string& what) const {
        // Field names are keys of the file and `what` may quote values: both are escaped and
        // cut short, so every message is one line of reasonable length.
        const std::string f = excerpt(field, kMaxQuotedField), w = excerpt(what, kMaxMessage);
        if (lines_ && where.begin.line > 0)
            fail(source_, ":", where.begin.line, ": field '", f, "': ", w);
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
    // A point or direction [x, y, z] with finite coordinates within ±kMaxStyleCoordinate;
    // `direction`: it must not be the zero vector.
    Vec3f vec3(const toml::node& node, const std::string& field, bool direction) const;
    std::vector<Vec3f> points(const toml::node& node, const std::string& field) const;
    // table[key] as an array of tables ([[key]] or key = [{…}, …]); null if absent.
    const toml::array* tables(const toml::table& parent, const std::string& path,
                              std::string_view key) const;
    const toml::array* as_tables(const toml::node& node, const std::string& field) const;

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

    // Sets one field of the schema from its node, checked against the field's type and range.
    void read_field(const StyleField& field, const toml::node& node, Style& style) const;
    // The fields of every section in schema order, with the checks between them.
    void read_sections(const toml::table& root, Style& style) const;
    using Given = std::function<const toml::node*(std::string_view key)>;
    void section_pre(const std::string& section, const Given& given, Style& style) const;
    void section_post(const std::string& section, const Given& given, const toml::node& where,
                      Style& style) const;
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
    bool lines_ = true;  // messages give the file's line
};

void Parser::check_keys(const toml::table& table, const std::string& path,
                        const std::vector<std::string>& allowed) const {
    for (auto&& [key, node] : table) {
        const std::string name(key.str());
        if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
        const std::string field = join_path(path, name);
        // A known field written in the wrong section, else a likely typo of a sibling.
        std::vector<std::string> elsewhere;
        const auto& sections = style_sections();
        const bool is_section = std::find(sections.begin(), sections.end(), path) != sections.end();
        for (const std::string& section : sections)
            for (const auto& k : section_keys(section))
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
    check_keys(*table, field, section_keys(field));
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
    const Range range{-kMaxStyleCoordinate, kMaxStyleCoordinate};
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
    return node ? as_tables(*node, join_path(path, key)) : nullptr;
}

const toml::array* Parser::as_tables(const toml::node& n, const std::string& field) const {
    const toml::node* node = &n;
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

// Realistic natural colors (HSV means and spreads, per-strand and per-wisp), the starting
// point that explicit color fields then adjust; in the order of color.preset's choices.
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

void apply_color_preset(const ColorPreset& p, ColorSpec& spec) {
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

void Parser::read_field(const StyleField& f, const toml::node& node, Style& style) const {
    const std::string field(f.path);
    const FieldRef ref = f.ref ? f.ref(style) : FieldRef{};
    const Range range{f.lo, f.hi, f.lo_open};
    switch (f.type) {
        case FieldType::kNumber: {
            float& out = *std::get<float*>(ref);
            const float v = static_cast<float>(real(node, field, range));
            // A side part's sign says which side it is on, and growth.part sets it.
            out = f.path == "growth.part_offset" ? std::copysign(v, out) : v;
            return;
        }
        case FieldType::kInteger:
            *std::get<int*>(ref) =
                static_cast<int>(integer(node, field, int64_t(f.lo), int64_t(f.hi)));
            return;
        case FieldType::kSeed:
            *std::get<uint64_t*>(ref) =
                static_cast<uint64_t>(integer(node, field, 0, std::numeric_limits<int64_t>::max()));
            return;
        case FieldType::kBoolean:
            *std::get<bool*>(ref) = boolean(node, field);
            return;
        case FieldType::kString:
            *std::get<std::string*>(ref) = string(node, field, f.positive);
            return;
        case FieldType::kPath:
            *std::get<fs::path*>(ref) = path(node, field);
            return;
        case FieldType::kChoice: {
            std::vector<std::pair<std::string, int>> options;
            for (size_t i = 0; i < f.choices.size(); ++i)
                options.emplace_back(std::string(f.choices[i]), int(i));
            const int i = choice(node, field, options);
            if (f.path == "color.preset")
                apply_color_preset(color_presets()[i], style.color);
            else
                f.set_choice(style, i);
            return;
        }
        case FieldType::kPoint:
        case FieldType::kDirection:
            *std::get<Vec3f*>(ref) = vec3(node, field, f.type == FieldType::kDirection);
            return;
        case FieldType::kMap:
            *std::get<ScalarMap*>(ref) =
                map(node, field, MapRules{range, f.positive, f.map_low, f.map_high});
            return;
        case FieldType::kDistribution: {
            Distribution& out = *std::get<Distribution*>(ref);
            out = distribution(node, field, out, Domain{float(f.lo), float(f.hi), f.positive});
            return;
        }
        case FieldType::kRadii: {
            std::vector<float>& out = *std::get<std::vector<float>*>(ref);
            const Range each{f.lo, f.hi, true};
            out.clear();
            if (node.is_number()) {
                out.push_back(static_cast<float>(real(node, field, each)));
            } else if (const toml::array* array = node.as_array()) {
                if (array->empty() || array->size() > kMaxDeviationRadii)
                    error(node, field,
                          cat("must hold 1 to ", kMaxDeviationRadii, " numbers, got ",
                              array->size()));
                for (size_t i = 0; i < array->size(); ++i)
                    out.push_back(
                        static_cast<float>(real((*array)[i], cat(field, "[", i, "]"), each)));
            } else {
                error(node, field,
                      "must be a number or an array of numbers, got " + describe(node));
            }
            return;
        }
        case FieldType::kPolyline: {
            std::vector<Vec3f>& out = *std::get<std::vector<Vec3f>*>(ref);
            const toml::array* array = node.as_array();
            if (!array)
                error(node, field, "must be an array of [x, y, z] points, got " + describe(node));
            if (array->size() < 4 || array->size() > kMaxPolylinePoints)
                error(node, field,
                      cat("must hold 4 to ", kMaxPolylinePoints, " points, got ", array->size()));
            out.clear();
            for (size_t i = 0; i < array->size(); ++i) {
                const std::string point = cat(field, "[", i, "]");
                const toml::node& p = (*array)[i];
                const toml::array* xyz = p.as_array();
                if (!xyz || xyz->size() != 3)
                    error(p, point, "must be a point [x, y, z] in cm, got " + describe(p));
                Vec3f v;
                for (int c = 0; c < 3; ++c)
                    v[c] = static_cast<float>(real((*xyz)[c], cat(point, "[", c, "]"), range));
                out.push_back(v);
            }
            return;
        }
        case FieldType::kFieldTerms: {
            std::vector<FieldTerm>& out = *std::get<std::vector<FieldTerm>*>(ref);
            const toml::array* terms = as_tables(node, field);
            if (terms->size() > kMaxFieldTerms)
                error(node, field,
                      cat("must hold at most ", kMaxFieldTerms, " terms, got ", terms->size()));
            out.clear();
            for (size_t i = 0; i < terms->size(); ++i) {
                const std::string term_path = cat(field, "[", i, "]");
                const toml::table& term = *(*terms)[i].as_table();
                check_keys(term, term_path, kFieldKeys);
                out.push_back(field_term(term, term_path));
            }
            return;
        }
        case FieldType::kGroups:
            return;  // read_groups, in file order
    }
}

// Relations between the fields of a section, checked before (pre) and after (post) its
// fields are read. `given(key)` is the node of a key the input sets (null if it does not):
// a message points at the value the user wrote.
void Parser::section_pre(const std::string& section, const Given& given, Style& style) const {
    if (section == "head.scalp") {
        // Which method each key belongs to; the method is inferred from the keys when not
        // named.
        using Kind = ScalpSpec::Kind;
        const std::vector<std::pair<std::string, Kind>> owners = {{"group", Kind::kGroup},
                                                                  {"mask", Kind::kMask},
                                                                  {"front", Kind::kHairline},
                                                                  {"side", Kind::kHairline},
                                                                  {"back", Kind::kHairline}};
        const auto& methods = find_style_field("head.scalp.method")->choices;
        const auto method_name = [&](Kind kind) { return std::string(methods[int(kind)]); };
        std::optional<Kind> kind;
        std::string decided_by;
        if (const toml::node* method = given("method")) {
            read_field(*find_style_field("head.scalp.method"), *method, style);
            kind = style.head.scalp.kind;
            decided_by = "method = " + toml_string(method_name(*kind));
        }
        for (const auto& [key, owner] : owners) {
            const toml::node* node = given(key);
            if (!node) continue;
            if (!kind) {
                kind = owner;
                decided_by = "'head.scalp." + key + "'";
            } else if (*kind != owner) {
                error(*node, "head.scalp." + key,
                      "belongs to method = " + toml_string(method_name(owner)) + ", but " +
                          decided_by + " selects method " + toml_string(method_name(*kind)));
            }
        }
        if (kind) style.head.scalp.kind = *kind;
    } else if (section == "body") {
        // A body mesh given alone says which method it is for.
        if (given("obj") && !given("method")) style.head.body.kind = BodySpec::Kind::kObj;
    } else if (section == "prototype") {
        const toml::node* points = given("points");
        if (const toml::node* shape = given("shape")) {
            read_field(*find_style_field("prototype.shape"), *shape, style);
            if (points && style.prototype.kind != PrototypeSpec::Kind::kPolyline)
                error(*points, "prototype.points",
                      "only used with shape = \"polyline\", but shape is " + describe(*shape));
        } else if (points) {
            style.prototype.kind = PrototypeSpec::Kind::kPolyline;
        }
    } else if (section == "cut") {
        style.cut.enabled = true;  // the section being present turns the cut on
    }
}

void Parser::section_post(const std::string& section, const Given& given, const toml::node& where,
                          Style& style) const {
    // The node to blame for a relation between keys: the first of them the input gives.
    const auto blame = [&](std::initializer_list<const char*> keys) -> std::string {
        for (const char* key : keys)
            if (given(key)) return key;
        return *keys.begin();
    };
    const auto at = [&](const std::string& key) -> const toml::node& {
        const toml::node* node = given(key);
        return node ? *node : where;
    };
    if (section == "head.scalp") {
        if (style.head.scalp.kind == ScalpSpec::Kind::kMask && style.head.scalp.mask.empty())
            error(where, "head.scalp.mask", "required by method = \"mask\"");
    } else if (section == "body") {
        if (style.head.body.kind == BodySpec::Kind::kObj && style.head.body.obj.empty())
            error(where, "body.obj", "required by method = \"obj\"");
    } else if (section == "roots") {
        if (style.wisps > style.strands) {
            if (given("wisps"))
                error(at("wisps"), "roots.wisps",
                      cat("must be ≤ roots.strands (", style.strands, "), got ", style.wisps));
            error(at("strands"), "roots.strands",
                  cat("must be ≥ roots.wisps (", style.wisps, "), got ", style.strands));
        }
        const int64_t total = int64_t(style.strands) * style.points_per_strand;
        if (total > kMaxTotalPoints) {
            const std::string key = blame({"points_per_strand", "strands"});
            error(at(key), "roots." + key,
                  cat("strands × points_per_strand must be ≤ ", kMaxTotalPoints, ", got ",
                      style.strands, " × ", style.points_per_strand, " = ", total));
        }
    } else if (section == "prototype") {
        const PrototypeSpec& spec = style.prototype;
        if (spec.kind != PrototypeSpec::Kind::kPolyline) return;
        if (spec.polyline.empty())
            error(where, "prototype.points", "required by shape = \"polyline\"");
        if (spec.window >= int(spec.polyline.size()))
            error(at(blame({"window", "points"})), "prototype.window",
                  cat("must be < the number of prototype points (", spec.polyline.size(), "), got ",
                      spec.window));
    } else if (section == "dynamics") {
        const DynamicsSpec& spec = style.dynamics;
        if (spec.friction * spec.dt >= 1)
            error(where, "dynamics.friction",
                  cat("friction · dt must be under 1 (§4.2: friction must not reverse the "
                      "relative motion), got ",
                      spec.friction, " · ", spec.dt, " = ", spec.friction * spec.dt));
    }
}

void Parser::read_sections(const toml::table& root, Style& style) const {
    // The table of each section the file has (null: absent), found as the schema's order
    // reaches it: a section's parent comes before it.
    std::vector<std::pair<std::string, const toml::table*>> tables = {{"", &root}};
    const auto table_of = [&](const std::string& name) -> const toml::table* {
        for (const auto& [n, t] : tables)
            if (n == name) return t;
        const std::string parent(field_section(name));
        const toml::table* t = section(find_table(tables, parent), parent, field_key(name));
        tables.emplace_back(name, t);
        return t;
    };
    const auto& schema = style_schema();
    for (size_t i = 0; i < schema.size();) {
        const std::string name(field_section(schema[i].path));
        size_t end = i;
        while (end < schema.size() && field_section(schema[end].path) == name)
            ++end;
        const toml::table* table = table_of(name);
        if (table) {
            const Given given = [table](std::string_view key) { return table->get(key); };
            section_pre(name, given, style);
            for (; i < end; ++i)
                if (const toml::node* node = table->get(field_key(schema[i].path)))
                    if (!(name == "head.scalp" && field_key(schema[i].path) == "method") &&
                        !(name == "prototype" && field_key(schema[i].path) == "shape"))
                        read_field(schema[i], *node, style);  // (pre read those two)
            section_post(name, given, *table, style);
        }
        i = end;
    }
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
        opt_real(half, field, "offset", s.offset, Range{-kMaxStyleCoordinate, kMaxStyleCoordinate});
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
    opt_real(&table, path, "radius", c.radius, Range{0, kMaxStyleCoordinate, true});
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
    opt_real(&table, path, "radius", spec.radius, Range{0, kMaxStyleCoordinate, true});
    opt_real(&table, path, "weight", spec.weight, Range{0, 1});
    return tie_groups(spec);
}

std::vector<GroupSpec> Parser::braid(const toml::table& table, const std::string& path,
                                     int wisps) const {
    check_keys(table, path, kBraidKeys);
    BraidSpec spec;
    spec.selection = selection(table, path, wisps, false);
    const SectionField& strands = section_field("braid", "strands");
    opt_int(&table, path, "strands", spec.strands, int64_t(strands.lo), int64_t(strands.hi));
    opt_vec3(&table, path, "start", spec.start, false);
    opt_vec3(&table, path, "axis", spec.axis, true);
    opt_vec3(&table, path, "side", spec.side, true);
    opt_real(&table, path, "length", spec.length, section_range("braid", "length"));
    opt_real(&table, path, "width", spec.width, section_range("braid", "width"));
    opt_real(&table, path, "period", spec.period, section_range("braid", "period"));
    opt_real(&table, path, "radius", spec.radius, section_range("braid", "radius"));
    opt_real(&table, path, "weight", spec.weight, section_range("braid", "weight"));
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
    opt_vec3(&table, path, "point", spec.point, false);
    opt_vec3(&table, path, "facing", spec.facing, true);
    opt_real(&table, path, "radius", spec.radius, section_range("updo", "radius"));
    opt_real(&table, path, "bun_radius", spec.bun_radius, section_range("updo", "bun_radius"));
    opt_real(&table, path, "turns", spec.turns, section_range("updo", "turns"));
    opt_real(&table, path, "weight", spec.weight, section_range("updo", "weight"));
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
    opt_real(&table, path, "radius", spec.radius, Range{0, kMaxStyleCoordinate, true});
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
        std::string kind;
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
            entries.push_back(
                {table->source().begin.line, key, cat(key, "[", i, "]"), reader, table});
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
        style.sections.push_back({e.kind, toml_to_json(*e.table).dump()});
    }
}

Style Parser::parse(std::string_view text) {
    const toml::table root = parse_toml(text, source_, kMaxMessage);
    check_keys(root, "", section_keys(""));

    Style style;
    read_sections(root, style);
    read_groups(&root, style);  // after [roots]: wisp ids are checked against roots.wisps
    return style;
}

}  // namespace

void Parser::set(Style& style, const StyleField& field, const toml::node& node) const {
    if (field.type == FieldType::kGroups)
        fail(source_, ": field '", field.path, "': constraint groups are not set one by one");
    const std::string section(field_section(field.path));
    const std::string_view key = field_key(field.path);
    const Given given = [&](std::string_view k) { return k == key ? &node : nullptr; };
    Style out = style;
    // A [cut] section in a file turns the cut on; setting one of its fields does not.
    if (section != "cut") section_pre(section, given, out);
    // The scalp method and the prototype shape are read by the section's pre-checks.
    if (field.path != "head.scalp.method" && field.path != "prototype.shape")
        read_field(field, node, out);
    section_post(section, given, node, out);
    style = std::move(out);
}

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

std::string toml_quote(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7f) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04x", u);
            out += buffer;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

namespace {

// The shortest decimal that reads back to the same float.
std::string toml_number(float v) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
}

std::string toml_path(const fs::path& p, const fs::path& base_dir) {
    if (!base_dir.empty()) {
        const fs::path relative = p.lexically_relative(base_dir);
        if (!relative.empty() && *relative.begin() != "..") return toml_quote(relative.string());
    }
    return toml_quote(p.string());
}

std::string toml_vec3(const Vec3f& v) {
    return "[" + toml_number(v.x()) + ", " + toml_number(v.y()) + ", " + toml_number(v.z()) + "]";
}

std::string toml_points(const std::vector<Vec3f>& points) {
    std::string out = "[";
    for (size_t i = 0; i < points.size(); ++i)
        out += (i ? ", " : "") + toml_vec3(points[i]);
    return out + "]";
}

std::string toml_distribution(const Distribution& d) {
    const std::string range = ", min = " + toml_number(d.min) + ", max = " + toml_number(d.max);
    switch (d.kind) {
        case Distribution::Kind::kConstant:
            return "{ distribution = \"constant\", value = " + toml_number(d.value) + " }";
        case Distribution::Kind::kUniform:
            return "{ distribution = \"uniform\"" + range + " }";
        case Distribution::Kind::kNormal:
            return "{ distribution = \"normal\", mean = " + toml_number(d.mean) +
                   ", stddev = " + toml_number(d.stddev) + range + " }";
        case Distribution::Kind::kTable: {
            std::string values;
            for (size_t i = 0; i < d.table.size(); ++i)
                values += (i ? ", " : "") + toml_number(d.table[i]);
            return "{ distribution = \"table\", values = [" + values + "]" + range + " }";
        }
    }
    return {};
}

std::string toml_map(const ScalarMap& m, const fs::path& base_dir) {
    const std::string scale = ", low = " + toml_number(m.low) + ", high = " + toml_number(m.high);
    switch (m.kind) {
        case ScalarMap::Kind::kConstant:
            return toml_number(m.value);
        case ScalarMap::Kind::kImage:
            return "{ image = " + toml_path(m.image, base_dir) + scale + " }";
        case ScalarMap::Kind::kProcedural:
            return "{ procedural = " + toml_quote(m.procedural) + scale + " }";
    }
    return {};
}

std::string toml_field_terms(const std::vector<FieldTerm>& terms, const fs::path& base_dir) {
    static const char* const kKinds[] = {"gravity", "pulled-back", "side-part",
                                         "wind",    "file",        "growth"};
    std::string out = "[";
    for (size_t i = 0; i < terms.size(); ++i) {
        const FieldTerm& t = terms[i];
        out += std::string(i ? ", " : "") + "{ kind = \"" + kKinds[int(t.kind)] +
               "\", weight = " + toml_number(t.weight);
        if (t.kind == FieldTerm::Kind::kWind) out += ", direction = " + toml_vec3(t.direction);
        if (t.kind == FieldTerm::Kind::kSidePart)
            out += std::string(", side = ") + (t.side < 0 ? "\"right\"" : "\"left\"");
        if (t.kind == FieldTerm::Kind::kFile) out += ", file = " + toml_path(t.file, base_dir);
        out += " }";
    }
    return out + "]";
}

}  // namespace

std::string groups_to_toml(const std::vector<GroupSpec>& groups, const fs::path& base_dir) {
    std::string out;
    for (const GroupSpec& g : groups) {
        const Selection& s = g.selection;
        out += "\n[[group]]\nname = " + toml_quote(g.name) + "\n";
        switch (s.kind) {
            case Selection::Kind::kAll:
                break;
            case Selection::Kind::kRegion:
                out += "region = " + toml_quote(s.region) + "\n";
                break;
            case Selection::Kind::kMask:
                out += "mask = " + toml_path(s.mask, base_dir) + "\n";
                break;
            case Selection::Kind::kBox:
                out += "box = { min = " + toml_vec3(s.lo) + ", max = " + toml_vec3(s.hi) + " }\n";
                break;
            case Selection::Kind::kHalfSpace:
                out += "half_space = { normal = " + toml_vec3(s.normal) +
                       ", offset = " + toml_number(s.offset) + " }\n";
                break;
            case Selection::Kind::kWisps: {
                out += "wisps = [";
                for (size_t i = 0; i < s.wisps.size(); ++i)
                    out += (i ? ", " : "") + std::to_string(s.wisps[i]);
                out += "]\n";
                break;
            }
        }
        out += std::string("head_relative = ") + (s.head_relative ? "true" : "false") + "\n";
        if (s.parts != 1) out += cat("part = ", s.part, "\nparts = ", s.parts, "\n");
        for (const ConstraintSpec& c : g.queue) {
            out += "[[group.constraint]]\n";
            if (c.kind == ConstraintSpec::Kind::kPoint) {
                out += "kind = \"point\"\npoint = " + toml_vec3(c.point) + "\n";
            } else {
                out += std::string("kind = ") +
                       (c.kind == ConstraintSpec::Kind::kTrajectory ? "\"trajectory\""
                                                                    : "\"direction\"") +
                       "\ntrajectory = " + toml_points(c.trajectory) +
                       "\nsmooth = " + (c.smooth ? "true" : "false") + "\n";
            }
            out += "radius = " + toml_number(c.radius) + "\nweight = " + toml_number(c.weight) +
                   "\nhold = " + (c.hold ? "true" : "false") +
                   "\nhead_relative = " + (c.head_relative ? "true" : "false") + "\n";
        }
    }
    return out;
}

std::string style_field_toml(const Style& style, const StyleField& field,
                             const fs::path& base_dir) {
    // The accessors hand out mutable storage; nothing is written through it here.
    Style& s = const_cast<Style&>(style);
    const FieldRef ref = field.ref ? field.ref(s) : FieldRef{};
    switch (field.type) {
        case FieldType::kNumber: {
            const float v = *std::get<float*>(ref);
            return toml_number(field.path == "growth.part_offset" ? std::abs(v) : v);
        }
        case FieldType::kInteger:
            return std::to_string(*std::get<int*>(ref));
        case FieldType::kSeed:
            return std::to_string(*std::get<uint64_t*>(ref));
        case FieldType::kBoolean:
            return *std::get<bool*>(ref) ? "true" : "false";
        case FieldType::kString:
            return toml_quote(*std::get<std::string*>(ref));
        case FieldType::kPath: {
            const fs::path& p = *std::get<fs::path*>(ref);
            return p.empty() ? std::string() : toml_path(p, base_dir);
        }
        case FieldType::kChoice: {
            const int i = field.get_choice(style);
            return i < 0 ? std::string() : toml_quote(field.choices[i]);
        }
        case FieldType::kPoint:
        case FieldType::kDirection:
            return toml_vec3(*std::get<Vec3f*>(ref));
        case FieldType::kMap:
            return toml_map(*std::get<ScalarMap*>(ref), base_dir);
        case FieldType::kDistribution:
            return toml_distribution(*std::get<Distribution*>(ref));
        case FieldType::kRadii: {
            const auto& radii = *std::get<std::vector<float>*>(ref);
            std::string out = "[";
            for (size_t i = 0; i < radii.size(); ++i)
                out += (i ? ", " : "") + toml_number(radii[i]);
            return out + "]";
        }
        case FieldType::kPolyline:
            return style.prototype.kind == PrototypeSpec::Kind::kPolyline
                       ? toml_points(*std::get<std::vector<Vec3f>*>(ref))
                       : std::string();
        case FieldType::kFieldTerms:
            return toml_field_terms(*std::get<std::vector<FieldTerm>*>(ref), base_dir);
        case FieldType::kGroups:
            return {};
    }
    return {};
}

void for_each_style_file(Style& style, const std::function<void(fs::path&)>& f) {
    auto visit = [&](fs::path& p) {
        if (!p.empty()) f(p);
    };
    for (const StyleField& field : style_schema()) {
        const FieldRef ref = field.ref ? field.ref(style) : FieldRef{};
        switch (field.type) {
            case FieldType::kPath:
                // A path its method does not read (a mask kept beside another scalp) is not
                // a file the style reads.
                if ((field.path == "head.scalp.mask" &&
                     style.head.scalp.kind != ScalpSpec::Kind::kMask) ||
                    (field.path == "body.obj" && style.head.body.kind != BodySpec::Kind::kObj))
                    break;
                visit(*std::get<fs::path*>(ref));
                break;
            case FieldType::kMap: {
                ScalarMap& m = *std::get<ScalarMap*>(ref);
                if (m.kind == ScalarMap::Kind::kImage) visit(m.image);
                break;
            }
            case FieldType::kFieldTerms:
                for (FieldTerm& t : *std::get<std::vector<FieldTerm>*>(ref))
                    if (t.kind == FieldTerm::Kind::kFile) visit(t.file);
                break;
            default:
                break;
        }
    }
    for (GroupSpec& g : style.groups)
        if (g.selection.kind == Selection::Kind::kMask) visit(g.selection.mask);
}

std::vector<fs::path> style_files(const Style& style) {
    std::vector<fs::path> files;
    // Nothing is changed: the visitor only reads.
    for_each_style_file(const_cast<Style&>(style), [&](fs::path& p) {
        if (std::find(files.begin(), files.end(), p) == files.end()) files.push_back(p);
    });
    return files;
}

std::string style_to_toml(const Style& style, const fs::path& base_dir) {
    static const Style defaults;
    const auto changed = [&](const StyleField& field) {
        return style_field_toml(style, field, base_dir) != style_field_toml(defaults, field);
    };
    // A [cut] section turns the cut on when read, so a written one says whether it cuts.
    bool cut_changed = false;
    for (const StyleField& field : style_schema())
        cut_changed |= field_section(field.path) == "cut" && changed(field);
    std::string out = "# written by wisp (docs/style.md)\n";
    std::string section = "";
    for (const StyleField& field : style_schema()) {
        const std::string text = style_field_toml(style, field, base_dir);
        if (text.empty()) continue;
        const bool always = field.path == "cut.enabled" && cut_changed;
        // The scalp's keys select its method when read: only the method's own are written.
        using Scalp = ScalpSpec::Kind;
        const Scalp scalp = style.head.scalp.kind;
        if ((field.path == "head.scalp.group" && scalp != Scalp::kGroup) ||
            (field.path == "head.scalp.mask" && scalp != Scalp::kMask) ||
            (field_section(field.path) == "head.scalp" && field.path != "head.scalp.method" &&
             field.path != "head.scalp.group" && field.path != "head.scalp.mask" &&
             scalp != Scalp::kHairline))
            continue;
        if (!always && !changed(field)) continue;
        const std::string_view s = field_section(field.path);
        if (s != section) {
            section = std::string(s);
            out += "\n[" + section + "]\n";
        }
        out += std::string(field_key(field.path)) + " = " + text + "\n";
    }
    return out + groups_to_toml(style.groups, base_dir);
}

void set_style_field(Style& style, std::string_view path, std::string_view toml_value,
                     const std::string& source, const fs::path& base_dir) {
    const StyleField* field = find_style_field(path);
    if (!field) {
        std::vector<std::string> paths;
        for (const StyleField& f : style_schema())
            paths.emplace_back(f.path);
        std::string hint;
        if (const auto near = closest(path, paths)) hint = " (did you mean '" + *near + "'?)";
        fail(source, ": unknown field '", excerpt(path, kMaxQuotedField), "'", hint);
    }
    if (toml_value.size() > kMaxFileBytes)
        fail(source, ": field '", path, "': the value is ", toml_value.size(), " bytes, more than ",
             kMaxFileBytes);
    toml::table table;
    try {
        table = toml::parse("value = " + std::string(toml_value), source);
    } catch (const toml::parse_error& e) {
        std::string description(e.description());
        std::replace(description.begin(), description.end(), '\n', ' ');
        fail(source, ": field '", path, "': not a TOML value: ", excerpt(description, kMaxMessage));
    }
    // One value: "1\nroots.wisps = 5" is not a value of one field.
    if (table.size() != 1 || !table.get("value"))
        fail(source, ": field '", path, "': not a single TOML value");
    Parser(source, base_dir, false).set(style, *field, *table.get("value"));
}

}  // namespace wisp
