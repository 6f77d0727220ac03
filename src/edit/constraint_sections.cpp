#include "edit/constraint_sections.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>

#include "core/atomic_file.hpp"
#include "edit/wire.hpp"
#include "groom/hairdressing.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

const std::vector<std::string> kSectionKinds = {"group", "tie", "braid", "updo", "comb"};

nlohmann::json node_to_json(const toml::node& node) {
    if (const auto* s = node.as_string()) return s->get();
    if (const auto* i = node.as_integer()) return i->get();
    if (const auto* f = node.as_floating_point()) return f->get();
    if (const auto* b = node.as_boolean()) return b->get();
    nlohmann::json out = nullptr;
    if (const auto* a = node.as_array()) {
        out = nlohmann::json::array();
        for (const toml::node& e : *a)
            out.push_back(node_to_json(e));
    } else if (const auto* t = node.as_table()) {
        out = nlohmann::json::object();
        for (auto&& [k, v] : *t)
            out[std::string(k.str())] = node_to_json(v);
    }
    return out;
}

// A key as the sections hold it: lower-case letters, digits and '_' (the reader then says
// whether the section takes it).
bool plain_key(const std::string& key) {
    return !key.empty() && key.size() <= 32 && std::all_of(key.begin(), key.end(), [](char c) {
        return std::islower(static_cast<unsigned char>(c)) ||
               std::isdigit(static_cast<unsigned char>(c)) || c == '_';
    });
}

// "constraints:4:1: field 'tie[0].point': must be …" → ("tie[0].point", "must be …"), the
// line of the text the editor made up left out.
SectionsError reader_error(const std::string& message) {
    const size_t at = message.find("field '");
    if (at == std::string::npos) return SectionsError("sections", message);
    const size_t end = message.find('\'', at + 7);
    const std::string field = message.substr(at + 7, end - at - 7);
    const size_t colon = message.find(": ", end);
    return SectionsError(field, colon == std::string::npos ? message : message.substr(colon + 2));
}

}  // namespace

nlohmann::json section_paths(const nlohmann::json& sections, const std::vector<GroupSpec>& groups,
                             const HeadFrame& head) {
    nlohmann::json out = nlohmann::json::array();
    size_t g = 0;
    for (const nlohmann::json& s : sections) {
        nlohmann::json paths = nlohmann::json::array();
        size_t count = 1;
        if (s.value("section", "") == "braid") {
            const nlohmann::json strands = s.value("strands", nlohmann::json(BraidSpec{}.strands));
            count = strands.is_number_integer() ? strands.get<size_t>() : 0;
        }
        for (size_t k = 0; k < count && g + k < groups.size(); ++k)
            for (const ConstraintSpec& c : groups[g + k].queue) {
                if (c.kind == ConstraintSpec::Kind::kPoint) continue;
                nlohmann::json points = nlohmann::json::array();
                for (const Vec3f& p : c.trajectory) {
                    const Vec3f q = c.head_relative ? head.to_space(p) : p;
                    points.push_back({q.x(), q.y(), q.z()});
                }
                paths.push_back({{"points", std::move(points)},
                                 {"smooth", c.smooth},
                                 {"radius", c.head_relative ? c.radius * head.radius : c.radius}});
            }
        g += count;
        out.push_back(std::move(paths));
    }
    // Groups and sections out of step (they never should be): no paths rather than wrong ones.
    if (g != groups.size())
        for (nlohmann::json& paths : out)
            paths = nlohmann::json::array();
    return out;
}

nlohmann::json head_units_frame(const HeadFrame& head) {
    return {{"origin", {head.center.x(), head.center.y(), head.center.z()}},
            {"scale", head.radius},
            {"units", "head units"}};
}

nlohmann::json section_frames(const nlohmann::json& sections, const HeadFrame& head) {
    const nlohmann::json cm = {{"origin", {0.f, 0.f, 0.f}}, {"scale", 1.f}, {"units", "cm"}};
    nlohmann::json out = nlohmann::json::array();
    for (const nlohmann::json& s : sections) {
        // The reader's default, true; the sections held were checked by it (a boolean).
        const auto relative = s.find("head_relative");
        const bool head_relative =
            relative == s.end() || !relative->is_boolean() || relative->get<bool>();
        out.push_back(head_relative ? head_units_frame(head) : cm);
    }
    return out;
}

std::string ConstraintSections::mask_file(const std::string& document, const std::string& key) {
    return std::filesystem::path(document).stem().string() + "." + key + ".mask.png";
}

void ConstraintSections::load(const Style& style, const std::filesystem::path& base_dir) {
    sections_ = nlohmann::json::array();
    masks_.clear();
    // The sections as the file wrote them (a [[braid]] stays a braid, with its handles and
    // sliders), if they still expand into the style's groups: groups set since (by the
    // Python layer, say) make them stale, and then the groups are what there is.
    if (!style.sections.empty()) {
        nlohmann::json written = nlohmann::json::array();
        for (const SectionSource& s : style.sections) {
            nlohmann::json section = nlohmann::json::parse(s.table, nullptr, false);
            if (!section.is_object()) break;
            section["section"] = s.kind;
            written.push_back(std::move(section));
        }
        try {
            if (written.size() == style.sections.size() &&
                groups_to_toml(parse(written, style, base_dir, "untitled.toml"), base_dir) ==
                    groups_to_toml(style.groups, base_dir)) {
                sections_ = std::move(written);
                return;
            }
        } catch (const Error&) {
            // Not the editor's to show as written: fall back to the groups.
        }
    }
    const toml::table root = toml::parse(groups_to_toml(style.groups, base_dir));
    if (const toml::array* groups = root["group"].as_array())
        for (const toml::node& g : *groups) {
            nlohmann::json section = node_to_json(g);
            section["section"] = "group";
            sections_.push_back(std::move(section));
        }
}

void ConstraintSections::set_mask(const std::string& key, std::shared_ptr<const GrayImage> pixels) {
    if (key.empty() || key.size() > 32 || !std::all_of(key.begin(), key.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
        }))
        fail("'", excerpt(key), "': a selection's key is 1 to 32 letters, digits, '-' or '_'");
    if (masks_.size() >= kMaxSections && !masks_.count(key))
        fail("at most ", kMaxSections, " painted selections");
    masks_[key] = std::move(pixels);
}

const GrayImage* ConstraintSections::mask(const std::string& key) const {
    const auto it = masks_.find(key);
    return it == masks_.end() ? nullptr : it->second.get();
}

std::string ConstraintSections::toml(const std::string& document) const {
    std::string out;
    std::map<std::string, int> count;
    for (const nlohmann::json& s : sections_) {
        const std::string kind = s["section"].get<std::string>();
        const std::string path = cat(kind, "[", count[kind]++, "]");
        out += "\n[[" + kind + "]]\n";
        for (const auto& [key, value] : s.items()) {
            if (key == "section" || key == "constraint") continue;
            if (key == "selection") {
                out += "mask = " + toml_quote(mask_file(document, value.get<std::string>())) + "\n";
                continue;
            }
            out += key + " = " + json_to_toml_value(value, path + "." + key) + "\n";
        }
        if (!s.contains("constraint")) continue;
        int k = 0;
        for (const nlohmann::json& c : s["constraint"]) {
            out += "[[" + kind + ".constraint]]\n";
            for (const auto& [key, value] : c.items())
                out += key + " = " +
                       json_to_toml_value(value, cat(path, ".constraint[", k, "].", key)) + "\n";
            ++k;
        }
    }
    return out;
}

std::vector<GroupSpec> ConstraintSections::parse(const nlohmann::json& sections, const Style& style,
                                                 const std::filesystem::path& base_dir,
                                                 const std::string& document) const {
    if (!sections.is_array()) throw SectionsError("sections", "must be an array of sections");
    if (sections.size() > kMaxSections)
        throw SectionsError("sections",
                            cat("at most ", kMaxSections, " sections, got ", sections.size()));
    // The shape the TOML text needs; the reader checks the rest.
    std::map<std::string, int> count;
    for (size_t i = 0; i < sections.size(); ++i) {
        const nlohmann::json& s = sections[i];
        const std::string at = cat("sections[", i, "]");
        if (!s.is_object()) throw SectionsError(at, "must be an object");
        if (!s.contains("section") || !s["section"].is_string() ||
            std::find(kSectionKinds.begin(), kSectionKinds.end(),
                      s["section"].get<std::string>()) == kSectionKinds.end())
            throw SectionsError(at + ".section", "must be group, tie, braid, updo or comb");
        const std::string kind = s["section"].get<std::string>();
        const std::string path = cat(kind, "[", count[kind]++, "]");
        for (const auto& [key, value] : s.items()) {
            if (!plain_key(key))
                throw SectionsError(path, cat("'", excerpt(key), "' is not a key of a section"));
            if (key == "selection" && (!value.is_string() || !mask(value.get<std::string>())))
                throw SectionsError(path + ".selection",
                                    "must name a selection painted on the scalp");
        }
        if (s.contains("constraint")) {
            if (!s["constraint"].is_array())
                throw SectionsError(path + ".constraint", "must be an array of constraints");
            for (size_t k = 0; k < s["constraint"].size(); ++k) {
                const nlohmann::json& c = s["constraint"][k];
                if (!c.is_object())
                    throw SectionsError(cat(path, ".constraint[", k, "]"), "must be an object");
                for (const auto& [key, value] : c.items())
                    if (!plain_key(key))
                        throw SectionsError(cat(path, ".constraint[", k, "]"),
                                            cat("'", excerpt(key), "' is not a key"));
            }
        }
    }
    ConstraintSections candidate;
    candidate.sections_ = sections;
    std::string text;
    try {
        text = candidate.toml(document);
    } catch (const Error& e) {
        throw reader_error(e.what());
    }
    // The reader checks wisp ids against roots.wisps.
    Style parsed;
    try {
        parsed = parse_style(
            cat("[roots]\nwisps = ", style.wisps, "\nstrands = ", style.strands, "\n", text),
            "constraints", base_dir);
    } catch (const Error& e) {
        throw reader_error(e.what());
    }
    for (GroupSpec& g : parsed.groups) {
        if (g.selection.kind != Selection::Kind::kMask) continue;
        for (const auto& [key, pixels] : masks_)
            if (g.selection.mask.filename() == mask_file(document, key))
                g.selection.mask_pixels = pixels;
    }
    return std::move(parsed.groups);
}

std::vector<GroupSpec> ConstraintSections::set(const nlohmann::json& sections, const Style& style,
                                               const std::filesystem::path& base_dir,
                                               const std::string& document) {
    std::vector<GroupSpec> groups = parse(sections, style, base_dir, document);
    sections_ = sections;
    return groups;
}

std::vector<GroupSpec> ConstraintSections::groups(const Style& style,
                                                  const std::filesystem::path& base_dir,
                                                  const std::string& document) const {
    return parse(sections_, style, base_dir, document);
}

void ConstraintSections::write_masks(const std::filesystem::path& dir, const std::string& document,
                                     std::vector<std::string>& files) const {
    for (const nlohmann::json& s : sections_) {
        if (!s.contains("selection")) continue;
        const std::string key = s["selection"].get<std::string>();
        const GrayImage* pixels = mask(key);
        if (!pixels) continue;
        const std::string name = mask_file(document, key);
        write_file_atomic(dir / name, encode_gray_png(*pixels));
        files.push_back(name);
    }
}

}  // namespace wisp
