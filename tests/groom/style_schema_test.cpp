#include "groom/style_schema.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

std::string error_of_set(Style& style, std::string_view path, std::string_view value) {
    try {
        set_style_field(style, path, value, "editor");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// Two styles agree in every field of the schema (the TOML text of equal floats is equal)
// and in their constraint groups.
void expect_same_fields(const Style& a, const Style& b, const std::string& what) {
    SCOPED_TRACE(what);
    for (const StyleField& f : style_schema())
        EXPECT_EQ(style_field_toml(a, f), style_field_toml(b, f)) << f.path;
    EXPECT_EQ(a.groups.size(), b.groups.size());
    EXPECT_EQ(style_to_toml(a), style_to_toml(b));
}

TEST(StyleSchema, PathsAreUniqueAndSectionsKnowTheirKeys) {
    std::set<std::string_view> paths;
    for (const StyleField& f : style_schema()) {
        EXPECT_TRUE(paths.insert(f.path).second) << f.path;
        EXPECT_FALSE(f.doc.empty()) << f.path;
        EXPECT_FALSE(f.panel.empty()) << f.path;
        const auto& keys = section_keys(field_section(f.path));
        EXPECT_NE(std::find(keys.begin(), keys.end(), field_key(f.path)), keys.end()) << f.path;
        if (f.type == FieldType::kChoice) {
            EXPECT_FALSE(f.choices.empty()) << f.path;
            EXPECT_NE(f.get_choice, nullptr) << f.path;
        } else if (f.type != FieldType::kGroups) {
            EXPECT_NE(f.ref, nullptr) << f.path;
        }
        if (f.type == FieldType::kNumber || f.type == FieldType::kInteger) {
            EXPECT_LT(f.lo, f.hi) << f.path;
        }
        EXPECT_EQ(find_style_field(f.path), &f);
    }
    EXPECT_EQ(find_style_field("solve.stiffnes"), nullptr);
    EXPECT_EQ(style_sections().front(), "");
    const auto& top = section_keys("");
    EXPECT_NE(std::find(top.begin(), top.end(), "head"), top.end());
    EXPECT_NE(std::find(top.begin(), top.end(), "braid"), top.end());
    EXPECT_EQ(section_keys("head.scalp").size(), 6u);
}

// The defaults come from Style{}: each one is inside its own range, and setting a field to
// its default text changes nothing.
TEST(StyleSchema, DefaultsLieInTheirRangesAndReadBack) {
    const Style defaults;
    for (const StyleField& f : style_schema()) {
        Style s;
        const std::string text = style_field_toml(defaults, f);
        if (f.type == FieldType::kNumber) {
            const double v = std::stod(text);
            EXPECT_TRUE(f.lo_open ? v > f.lo : v >= f.lo) << f.path << " = " << text;
            EXPECT_LE(v, f.hi) << f.path;
        }
        if (f.type == FieldType::kInteger) {
            EXPECT_GE(std::stod(text), f.lo) << f.path;
            EXPECT_LE(std::stod(text), f.hi) << f.path;
        }
        if (text.empty() || f.type == FieldType::kGroups) continue;
        EXPECT_EQ(error_of_set(s, f.path, text), "") << f.path << " = " << text;
        // The hairline depths select their method, as they do in a file.
        if (f.path == "head.scalp.front" || f.path == "head.scalp.side" ||
            f.path == "head.scalp.back") {
            EXPECT_EQ(s.head.scalp.kind, ScalpSpec::Kind::kHairline) << f.path;
            s.head.scalp.kind = defaults.head.scalp.kind;
        }
        expect_same_fields(s, defaults, std::string(f.path));
    }
}

TEST(StyleSchema, StagesFollowThePipeline) {
    EXPECT_EQ(find_style_field("color.hue")->stage, Stage::kColor);
    EXPECT_EQ(find_style_field("solve.stiffness")->stage, Stage::kSolve);
    EXPECT_EQ(find_style_field("solve.threshold")->stage, Stage::kSolve);
    EXPECT_EQ(find_style_field("maps.density")->stage, Stage::kRoots);
    EXPECT_EQ(find_style_field("maps.length")->stage, Stage::kMasters);
    EXPECT_EQ(find_style_field("wisp.fuzziness")->stage, Stage::kMembers);
    EXPECT_EQ(find_style_field("head.obj")->stage, Stage::kHead);
    EXPECT_EQ(find_style_field("dynamics.dt")->stage, Stage::kNone);
    EXPECT_STREQ(stage_name(Stage::kSolve), "solve");
}

TEST(StyleSchema, SetFieldChecksLikeTheReaderAndKeepsTheStyleOnError) {
    Style s;
    EXPECT_EQ(error_of_set(s, "solve.stiffness", "2.5"), "");
    EXPECT_EQ(s.solve.stiffness, 2.5f);
    EXPECT_EQ(error_of_set(s, "wisp.fuzziness", "-1"),
              "editor: field 'wisp.fuzziness': must be ≥ 0, got -1");
    EXPECT_EQ(s.wisp.fuzziness, Style{}.wisp.fuzziness);
    EXPECT_EQ(error_of_set(s, "prototype.shape", "\"curley\""),
              "editor: field 'prototype.shape': must be one of \"straight\", \"wavy\", \"curly\", "
              "\"kinky\", \"polyline\", got \"curley\" (did you mean \"curly\"?)");
    EXPECT_EQ(error_of_set(s, "solve.stifness", "1"),
              "editor: unknown field 'solve.stifness' (did you mean 'solve.stiffness'?)");
    // The checks between a section's fields run too, naming the field that was set.
    EXPECT_EQ(error_of_set(s, "roots.wisps", "200000"),
              "editor: field 'roots.wisps': must be ≤ roots.strands (100000), got 200000");
    EXPECT_EQ(s.wisps, 2000);
    EXPECT_EQ(error_of_set(s, "roots.strands", "10"),
              "editor: field 'roots.strands': must be ≥ roots.wisps (2000), got 10");
    EXPECT_EQ(error_of_set(s, "dynamics.dt", "0.05"),
              "editor: field 'dynamics.friction': friction · dt must be under 1 (§4.2: friction "
              "must not reverse the relative motion), got 20 · 0.05 = 1");
    // One value, not a document.
    EXPECT_NE(error_of_set(s, "roots.wisps", "5\nroots.strands = 5").find("not a single"),
              std::string::npos);
    EXPECT_NE(error_of_set(s, "roots.wisps", "[").find("not a TOML value"), std::string::npos);
    EXPECT_NE(error_of_set(s, "group", "{}").find("not set one by one"), std::string::npos);
    // Choices whose value lives in more than one place: a right part is a negative offset.
    EXPECT_EQ(error_of_set(s, "growth.part", "\"right\""), "");
    EXPECT_EQ(error_of_set(s, "growth.part_offset", "0.5"), "");
    EXPECT_EQ(s.growth.part_offset, -0.5f);
    EXPECT_EQ(style_field_toml(s, *find_style_field("growth.part")), "\"right\"");
    EXPECT_EQ(style_field_toml(s, *find_style_field("growth.part_offset")), "0.5");
    // A preset sets the colour fields it names.
    EXPECT_EQ(error_of_set(s, "color.preset", "\"blonde\""), "");
    EXPECT_EQ(s.color.value.mean, 0.72f);
    // Maps and distributions take every form the file takes.
    EXPECT_EQ(error_of_set(s, "maps.length", "{ procedural = \"crown\", low = 5, high = 30 }"), "");
    EXPECT_EQ(s.length.kind, ScalarMap::Kind::kProcedural);
    EXPECT_EQ(error_of_set(s, "color.hue", "{ mean = 20 }"), "");
    EXPECT_EQ(s.color.hue.mean, 20.f);
    EXPECT_EQ(s.color.hue.stddev, 2.f);  // blonde's, kept
}

// Save then open: every preset written by style_to_toml reads back to the same style.
TEST(StyleSchema, EveryPresetRoundTripsThroughTheWriter) {
    for (const std::string& name : preset_names()) {
        const Style a = load_preset(name);
        const std::string text = style_to_toml(a);
        Style b;
        ASSERT_NO_THROW(b = parse_style(text, "written " + name)) << text;
        expect_same_fields(a, b, name);
        ASSERT_EQ(a.groups.size(), b.groups.size());
        for (size_t g = 0; g < a.groups.size(); ++g) {
            EXPECT_EQ(a.groups[g].name, b.groups[g].name);
            ASSERT_EQ(a.groups[g].queue.size(), b.groups[g].queue.size());
            for (size_t c = 0; c < a.groups[g].queue.size(); ++c) {
                const ConstraintSpec &x = a.groups[g].queue[c], &y = b.groups[g].queue[c];
                EXPECT_EQ(x.kind, y.kind);
                EXPECT_EQ(x.point, y.point);
                EXPECT_EQ(x.trajectory, y.trajectory);
                EXPECT_EQ(x.radius, y.radius);
                EXPECT_EQ(x.weight, y.weight);
                EXPECT_EQ(x.hold, y.hold);
                EXPECT_EQ(x.head_relative, y.head_relative);
            }
            EXPECT_EQ(a.groups[g].selection.kind, b.groups[g].selection.kind);
            EXPECT_EQ(a.groups[g].selection.region, b.groups[g].selection.region);
            EXPECT_EQ(a.groups[g].selection.part, b.groups[g].selection.part);
            EXPECT_EQ(a.groups[g].selection.parts, b.groups[g].selection.parts);
        }
    }
    // A default style writes no field at all; a cut that is off but moved says so.
    EXPECT_EQ(style_to_toml(Style{}), "# written by wisp (docs/style.md)\n");
    Style cut;
    cut.cut.offset = 2.f;
    const Style back = parse_style(style_to_toml(cut), "cut");
    EXPECT_FALSE(back.cut.enabled);
    EXPECT_EQ(back.cut.offset, 2.f);
}

// Paths under the style's folder are written relative to it.
TEST(StyleSchema, PathsAreWrittenRelativeToTheStyleFolder) {
    const Style a = parse_style(
        "[maps]\nlength = { image = \"maps/len.png\", low = 5, high = 30 }\n"
        "[growth]\nmap = \"/elsewhere/g.png\"\n",
        "t.toml", "/styles");
    const std::string text = style_to_toml(a, "/styles");
    EXPECT_NE(text.find("image = \"maps/len.png\""), std::string::npos) << text;
    EXPECT_NE(text.find("map = \"/elsewhere/g.png\""), std::string::npos) << text;
    expect_same_fields(parse_style(text, "t", "/styles"), a, "relative");
}

// --- docs/style.md and docs/animate.md agree with the schema ---------------------------

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The rows of the field tables of a reference document: section → key → cells. A section
// is named by a heading "### `[name]`" (or "## `[dynamics]` fields"); a row's first cell
// names one or more keys in backticks.
using Rows = std::map<std::string, std::map<std::string, std::vector<std::string>>>;

Rows field_rows(const std::string& text, Rows rows = {}) {
    std::istringstream in(text);
    std::string line, section = "?";
    bool top = false, field_table = false;
    while (std::getline(in, line)) {
        if (line.rfind("#", 0) == 0) {
            const size_t a = line.find("`["), b = line.find("]`");
            top = line.find("Top level") != std::string::npos;
            section = top                                 ? ""
                      : (a != std::string::npos && b > a) ? line.substr(a + 2, b - a - 2)
                                                          : "?";
            if (section.rfind("[", 0) == 0) section = "?";  // [[group]] and the like
            continue;
        }
        // Only tables whose header begins "| field" list fields (not the color presets').
        if (line.rfind("| ", 0) == 0 && line.rfind("| `", 0) != 0 && line.rfind("| -", 0) != 0)
            field_table = line.rfind("| field", 0) == 0;
        if (section == "?" || !field_table || line.rfind("| `", 0) != 0) continue;
        std::vector<std::string> cells;
        size_t pos = 1;
        while (pos < line.size()) {
            const size_t next = line.find(" | ", pos);
            cells.push_back(
                line.substr(pos, next == std::string::npos ? std::string::npos : next - pos));
            if (next == std::string::npos) break;
            pos = next + 3;
        }
        for (std::string& c : cells) {
            while (!c.empty() && (c.front() == ' ' || c.front() == '|'))
                c.erase(c.begin());
            while (!c.empty() && (c.back() == ' ' || c.back() == '|'))
                c.pop_back();
        }
        // `a`, `b` in the first cell: both keys share the row.
        const std::string& first = cells[0];
        for (size_t a = first.find('`'); a != std::string::npos; a = first.find('`', a + 1)) {
            const size_t b = first.find('`', a + 1);
            if (b == std::string::npos) break;
            rows[section][first.substr(a + 1, b - a - 1)] = cells;
            a = b;
        }
    }
    return rows;
}

// The first number written in a cell, if any ("0.25", "1e5", "10⁶", "[0, 0.93, −0.37]").
std::optional<double> first_number(std::string s) {
    for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
             {"−", "-"}, {"10⁴", "1e4"}, {"10⁶", "1e6"}, {"10⁹", "1e9"}, {",", ""}})
        for (size_t p; (p = s.find(from)) != std::string::npos;)
            s.replace(p, from.size(), to);
    for (size_t i = 0; i < s.size(); ++i) {
        if (std::isdigit(static_cast<unsigned char>(s[i])) ||
            (s[i] == '-' && i + 1 < s.size() &&
             std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
            return std::stod(s.substr(i));
        }
    }
    return std::nullopt;
}

TEST(StyleSchema, DocsDescribeEveryFieldWithItsDefault) {
    const std::string docs = read_text(fs::path(WISP_SOURCE_DIR) / "docs/style.md");
    const Rows rows =
        field_rows(read_text(fs::path(WISP_SOURCE_DIR) / "docs/animate.md"), field_rows(docs));
    const Style defaults;
    std::set<std::string> documented_sections;
    for (const StyleField& f : style_schema()) {
        // Each of these has its own section and table ([[solve.field]], [[group]], …).
        if (f.type == FieldType::kGroups || f.type == FieldType::kFieldTerms) continue;
        const std::string section(field_section(f.path)), key(field_key(f.path));
        documented_sections.insert(section);
        const auto s = rows.find(section);
        ASSERT_NE(s, rows.end()) << "docs have no table for [" << section << "]";
        const auto row = s->second.find(key);
        ASSERT_NE(row, s->second.end()) << f.path << " is not documented";
        const auto& cells = row->second;
        // Style tables: field | type | default | range | meaning; dynamics: field | default | …
        const std::string& def = cells.size() >= 5 ? cells[2] : cells[1];
        const std::string text = style_field_toml(defaults, f);
        switch (f.type) {
            case FieldType::kNumber:
            case FieldType::kInteger:
            case FieldType::kSeed: {
                const auto v = first_number(def);
                ASSERT_TRUE(v) << f.path << ": default cell '" << def << "'";
                EXPECT_NEAR(*v, std::stod(text), 1e-6 * std::max(1.0, std::abs(*v)))
                    << f.path << ": docs say " << def << ", the schema " << text;
                break;
            }
            case FieldType::kBoolean:
                // A [cut] section turns the cut on: its documented default is the section's.
                EXPECT_NE(def.find(f.path == "cut.enabled" ? "true" : text), std::string::npos)
                    << f.path << ": docs say " << def;
                break;
            case FieldType::kChoice:
                if (f.get_choice(defaults) >= 0) {
                    EXPECT_NE(def.find(std::string(f.choices[f.get_choice(defaults)])),
                              std::string::npos)
                        << f.path << ": docs say " << def;
                }
                // Every choice is listed, in the row or (color presets) a table of its own.
                for (const auto& c : f.choices) {
                    std::string row_text;
                    for (const std::string& cell : cells)
                        row_text += cell + " | ";
                    EXPECT_TRUE(row_text.find(std::string(c)) != std::string::npos ||
                                docs.find("| `" + std::string(c) + "` |") != std::string::npos)
                        << f.path << " does not list " << c;
                }
                break;
            default:
                break;
        }
        // The upper bound of a range is written in the range cell.
        if ((f.type == FieldType::kNumber || f.type == FieldType::kInteger) && cells.size() >= 3) {
            const std::string& range = cells.size() >= 5 ? cells[3] : cells[2];
            std::string normalized = range;
            for (const auto& [from, to] :
                 std::vector<std::pair<std::string, std::string>>{{"10⁴", "10000"},
                                                                  {"10⁵", "100000"},
                                                                  {"10⁶", "1000000"},
                                                                  {"10⁹", "1000000000"},
                                                                  {",", ""},
                                                                  {"1e4", "10000"},
                                                                  {"1e5", "100000"},
                                                                  {"1e6", "1000000"},
                                                                  {"1e3", "1000"},
                                                                  {"π", "3.1416"}})
                for (size_t p; (p = normalized.find(from)) != std::string::npos;)
                    normalized.replace(p, from.size(), to);
            std::ostringstream hi;
            hi << std::setprecision(12) << f.hi;
            if (f.hi < 1e7 && f.path != "roots.wisps" && f.path != "roots.strands" &&
                f.path != "dynamics.strands_per_wisp") {
                EXPECT_NE(normalized.find(hi.str()), std::string::npos)
                    << f.path << ": range cell '" << range << "' lacks the bound " << hi.str();
            }
        }
    }
    // Every documented key of a schema section is a field.
    for (const std::string& section : documented_sections) {
        for (const auto& [key, cells] : rows.at(section)) {
            const std::string path = section.empty() ? key : section + "." + key;
            EXPECT_NE(find_style_field(path), nullptr)
                << "docs describe " << path << ", which the schema lacks";
        }
    }
}

// The numbers of [[braid]] and [[updo]] the editor's tools set: their defaults are the
// documented ones, the slider's range lies in the allowed one around the default, and the
// reader takes the range's ends and refuses what lies beyond them, naming the key.
TEST(StyleSchema, SectionNumbersAreDocumentedAndCheckedByTheReader) {
    const std::string docs = read_text(fs::path(WISP_SOURCE_DIR) / "docs/style.md");
    ASSERT_FALSE(section_schema().empty());
    for (const SectionField& f : section_schema()) {
        const std::string section(f.section), key(f.key);
        // docs/style.md's table under "#### `[[braid]]`", read as a table of [braid].
        const size_t at = docs.find("#### `[[" + section + "]]`");
        ASSERT_NE(at, std::string::npos) << section;
        std::string part = docs.substr(at, docs.find("\n#### ", at + 1) - at);
        part.replace(4, section.size() + 6, "`[" + section + "]`");
        const Rows rows = field_rows(part);
        ASSERT_TRUE(rows.count(section) && rows.at(section).count(key)) << section << "." << key;
        const auto v = first_number(rows.at(section).at(key)[2]);
        ASSERT_TRUE(v) << section << "." << key;
        EXPECT_NEAR(*v, f.get_default(), 1e-6) << section << "." << key;
        EXPECT_LE(f.lo, f.soft_lo);
        EXPECT_LT(f.soft_lo, f.soft_hi);
        EXPECT_LE(f.soft_hi, f.hi);
        EXPECT_GE(f.get_default(), f.soft_lo) << section << "." << key;
        EXPECT_LE(f.get_default(), f.soft_hi) << section << "." << key;
        const auto error_of = [&](double value) -> std::string {
            std::ostringstream text;
            text << "[[" << section << "]]\n"
                 << key << " = " << std::setprecision(12) << value
                 << (f.type == FieldType::kNumber && value == std::floor(value) ? ".0" : "")
                 << "\n";
            try {
                parse_style(text.str(), "sections");
            } catch (const Error& e) {
                return e.what();
            }
            return "";
        };
        const std::string field = "field '" + section + "[0]." + key + "'";
        EXPECT_EQ(error_of(f.soft_lo), "");
        EXPECT_EQ(error_of(f.soft_hi), "");
        EXPECT_NE(error_of(f.lo_open ? f.lo : f.lo - 1).find(field), std::string::npos);
        EXPECT_NE(error_of(f.hi + 1).find(field), std::string::npos);
    }
}

}  // namespace
}  // namespace wisp
