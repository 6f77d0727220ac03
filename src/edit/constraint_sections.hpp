#pragma once
// The editor's constraint sections (issue 16, placing constraints; Choe & Ko §4, §6.2): the
// [[tie]], [[comb]], [[braid]], [[updo]] and [[group]] tables the user places or opens, kept
// as the TOML reader reads them so that Save writes them as a user would (`[[tie]] point =
// …`), and the selections painted on the scalp, held as images until Save writes them beside
// the style.
//
// A section is a JSON object: "section" (group, tie, braid, updo or comb) and the section's
// TOML keys as docs/style.md gives them ({"section": "tie", "name": "ponytail", "point": [0,
// 3, -12], "head_relative": false}); a [[group]]'s queue is "constraint": [{…}, …]. One key
// is the editor's own: "selection": KEY names a mask painted in the editor (set_mask), which
// the TOML text writes as `mask = "DOC.KEY.mask.png"`.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/image.hpp"
#include "groom/style.hpp"
#include "solve/styling_field.hpp"  // HeadFrame

namespace wisp {

// A bad section: `field` is its TOML path ("tie[0].point", "sections[2].section").
struct SectionsError : Error {
    SectionsError(std::string field_, const std::string& message)
        : Error(message), field(std::move(field_)) {}
    std::string field;
};

// The paths the sections' groups follow, for the editor to draw them as the solver has
// them (a braid's strands and an updo's spiral expanded by groom/hairdressing.cpp, not
// again in the browser): one array per section of {"points": [[x, y, z], …] (cm, head
// space), "smooth", "radius" (cm)}, one per trajectory or direction constraint of its
// groups. `groups` are those the sections expand into (ConstraintSections::set), in section
// order (a braid expands into `strands` groups, any other section into one); `head` maps
// head units to cm. A section whose groups cannot be matched gets no paths.
nlohmann::json section_paths(const nlohmann::json& sections, const std::vector<GroupSpec>& groups,
                             const HeadFrame& head);

// How each section's positions and sizes map to cm, as the reader takes them: one
// {"origin": [x, y, z], "scale": s, "units": "head units" or "cm"} per section, cm = origin +
// scale·value for a position and scale·value for a size. A section in head units (`head_relative`,
// the default) maps through `head`; one with `head_relative = false` is in cm already (origin 0,
// scale 1). The editor places and drags a section's handles with it, so it never guesses the units.
nlohmann::json section_frames(const nlohmann::json& sections, const HeadFrame& head);

// The frame of head units (as section_frames gives a head-relative section's): what the
// editor writes a new section in.
nlohmann::json head_units_frame(const HeadFrame& head);

class ConstraintSections {
  public:
    // The most sections the editor holds (the reader allows 256 groups in all).
    static constexpr size_t kMaxSections = 256;

    // The sections of a style read from a file or a preset: as the file wrote them
    // (Style::sections: a [[braid]] stays a braid) when they expand into its groups, else its
    // groups as [[group]] tables. Painted masks are forgotten.
    void load(const Style& style, const std::filesystem::path& base_dir);

    // Replaces the sections, checked by the style reader (parse_style) against `style`'s
    // roots.wisps and strands; returns the groups they expand into, with the painted masks
    // attached. Throws SectionsError naming the section's key ("tie[0].point") and the
    // reader's reason; the sections are unchanged then.
    std::vector<GroupSpec> set(const nlohmann::json& sections, const Style& style,
                               const std::filesystem::path& base_dir, const std::string& document);
    // The groups of the current sections (after a painted mask or a new document name).
    std::vector<GroupSpec> groups(const Style& style, const std::filesystem::path& base_dir,
                                  const std::string& document) const;

    const nlohmann::json& json() const { return sections_; }

    // A painted selection (scalp UV space, as a map image): KEY is letters, digits, '-' and
    // '_', at most 32 characters (throws wisp::Error otherwise).
    void set_mask(const std::string& key, std::shared_ptr<const GrayImage> pixels);
    // The painted selection KEY, or null.
    const GrayImage* mask(const std::string& key) const;

    // The sections as TOML text (`[[tie]]` …), painted masks named DOC.KEY.mask.png for the
    // document DOC.toml.
    std::string toml(const std::string& document) const;
    // Writes the painted masks the sections use as DOC.KEY.mask.png into `dir`, each
    // atomically, adding their names to `files`.
    void write_masks(const std::filesystem::path& dir, const std::string& document,
                     std::vector<std::string>& files) const;

    // DOC.KEY.mask.png
    static std::string mask_file(const std::string& document, const std::string& key);

  private:
    std::vector<GroupSpec> parse(const nlohmann::json& sections, const Style& style,
                                 const std::filesystem::path& base_dir,
                                 const std::string& document) const;

    nlohmann::json sections_ = nlohmann::json::array();
    std::map<std::string, std::shared_ptr<const GrayImage>> masks_;
};

}  // namespace wisp
