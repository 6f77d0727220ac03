// The editor's constraint sections (edit/constraint_sections.hpp): a tie placed in the editor
// becomes the groups the CLI reads from the same [[tie]] text; bad sections name their key;
// a painted selection takes the wisps rooted where it is painted, and the text Save writes
// (with the mask file) reads back to the same wisps.
#include "edit/constraint_sections.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "groom/generate.hpp"
#include "groom/head.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

Style small_style() {
    Style style = load_preset("default");
    style.wisps = 80;
    style.strands = 800;
    return style;
}

// 1 over the left half of scalp UV (u < 0.5: the character's left, +X), 0 elsewhere.
std::shared_ptr<const GrayImage> left_half(int side) {
    auto g = std::make_shared<GrayImage>();
    g->width = g->height = side;
    g->values.resize(size_t(side) * side);
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)
            g->values[size_t(j) * side + i] = i < side / 2 ? 1.f : 0.f;
    return g;
}

TEST(ConstraintSections, TieReadsAsTheCliReadsIt) {
    const Style style = small_style();
    ConstraintSections sections;
    const auto tie = nlohmann::json::parse(R"([{"section": "tie", "name": "pony",
        "point": [0, 3.5, -11.25], "radius": 1.2, "head_relative": false}])");
    const std::vector<GroupSpec> groups = sections.set(tie, style, {}, "style.toml");
    const Style cli = parse_style(
        "[[tie]]\nname = \"pony\"\npoint = [0, 3.5, -11.25]\nradius = 1.2\nhead_relative = false\n",
        "cli");
    ASSERT_EQ(groups.size(), 1u);
    EXPECT_EQ(groups_to_toml(groups), groups_to_toml(cli.groups));
    EXPECT_EQ(groups[0].queue[0].kind, ConstraintSpec::Kind::kPoint);
    EXPECT_EQ(groups[0].queue[0].weight, 1.f);
    EXPECT_NE(sections.toml("style.toml").find("[[tie]]\n"), std::string::npos);
}

TEST(ConstraintSections, BadSectionsNameTheirKeyAndChangeNothing) {
    const Style style = small_style();
    ConstraintSections sections;
    const auto good = nlohmann::json::parse(R"([{"section": "tie", "point": [0, 3, -11]}])");
    sections.set(good, style, {}, "style.toml");
    const auto field_of = [&](const char* text) {
        try {
            sections.set(nlohmann::json::parse(text), style, {}, "style.toml");
        } catch (const SectionsError& e) {
            EXPECT_NE(std::string(e.what()), "");
            return e.field;
        }
        return std::string("no error");
    };
    EXPECT_EQ(field_of(R"([{"section": "tie", "point": [0, 1]}])"), "tie[0].point");
    EXPECT_EQ(field_of(R"([{"section": "tie", "radius": -1}])"), "tie[0].radius");
    EXPECT_EQ(field_of(R"([{"section": "tie"}, {"section": "tie", "wisps": [80]}])"),
              "tie[1].wisps[0]");
    EXPECT_EQ(field_of(R"([{"section": "knot"}])"), "sections[0].section");
    EXPECT_EQ(field_of(R"([{"section": "tie", "selection": "nothing-painted"}])"),
              "tie[0].selection");
    EXPECT_EQ(field_of(R"([{"section": "tie", "x\n[roots]": 1}])"), "tie[0]");
    EXPECT_EQ(field_of(R"({"section": "tie"})"), "sections");
    EXPECT_EQ(sections.json(), good);
}

TEST(ConstraintSections, PaintedSelectionTakesItsWispsAndSavesAsAMask) {
    const fs::path dir =
        fs::temp_directory_path() / ("wisp_constraint_sections_test_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    Style style = small_style();
    const Head head = load_head(style.head);
    const Roots roots = grow_roots(style, head);

    ConstraintSections sections;
    sections.set_mask("left", left_half(64));
    style.groups = sections.set(
        nlohmann::json::parse(R"([{"section": "tie", "name": "left", "selection": "left",
            "point": [6, 3, -11], "head_relative": false}])"),
        style, dir, "style.toml");
    ASSERT_EQ(style.groups.size(), 1u);
    ASSERT_TRUE(style.groups[0].selection.mask_pixels);
    const GroupSelection painted = select_groups(style, head, roots);
    ASSERT_GT(painted.selected[0].size(), 5u);
    EXPECT_LT(painted.selected[0].size(), roots.masters.size() - 5);
    for (const uint32_t w : painted.selected[0])
        EXPECT_LT(roots.masters[w].uv.x(), 0.5f + 1.f / 64);

    // What Save writes: the mask file and the [[tie]] naming it, read back by the CLI.
    std::vector<std::string> files;
    sections.write_masks(dir, "style.toml", files);
    ASSERT_EQ(files, std::vector<std::string>{"style.left.mask.png"});
    Style plain = style;
    plain.groups.clear();
    const Style read =
        parse_style(style_to_toml(plain, dir) + sections.toml("style.toml"), "saved", dir);
    ASSERT_EQ(read.groups.size(), 1u);
    EXPECT_FALSE(read.groups[0].selection.mask_pixels);
    EXPECT_EQ(read.groups[0].selection.mask, dir / "style.left.mask.png");
    EXPECT_EQ(select_groups(read, head, roots).selected, painted.selected);
    fs::remove_all(dir);
}

TEST(ConstraintSections, LoadedGroupsSetBackToTheSameGroups) {
    const Style style = load_preset("ponytail");
    ASSERT_FALSE(style.groups.empty());
    ConstraintSections sections;
    sections.load(style, {});
    EXPECT_EQ(sections.json().size(), style.groups.size());
    const std::vector<GroupSpec> again = sections.set(sections.json(), style, {}, "x.toml");
    EXPECT_EQ(groups_to_toml(again), groups_to_toml(style.groups));
}

// A style read from TOML keeps its sections as written: the braid and updo presets load as a
// [[braid]] and an [[updo]] with the file's keys and values (as the tools make them, so they
// get their handles and sliders), not as the [[group]] tables they expand into; their text
// reads back to the same groups and, loaded again, writes the same bytes.
TEST(ConstraintSections, BraidAndUpdoFromTomlLoadAsWrittenAndSaveTheSameBytes) {
    for (const std::string preset : {"braid", "updo", "ponytail", "combed-back"}) {
        SCOPED_TRACE(preset);
        const Style style = load_preset(preset);
        ConstraintSections sections;
        sections.load(style, {});
        ASSERT_EQ(sections.json().size(), style.sections.size());
        const nlohmann::json& s = sections.json()[0];
        EXPECT_EQ(s["section"], style.sections[0].kind);
        if (preset == "braid") {
            EXPECT_EQ(s["section"], "braid");
            EXPECT_EQ(s["strands"], 3);
            EXPECT_EQ(s["start"], nlohmann::json({0.0, -0.45, -1.15}));
            EXPECT_EQ(s["period"], 0.55);
        }
        if (preset == "updo") {
            EXPECT_EQ(s["section"], "updo");
            EXPECT_EQ(s["bun_radius"], 0.38);
        }
        const std::string text = sections.toml("style.toml");
        EXPECT_NE(text.find("[[" + style.sections[0].kind + "]]\n"), std::string::npos) << text;
        EXPECT_EQ(text.find("[[group]]"), std::string::npos) << text;
        if (preset == "braid") {
            EXPECT_NE(text.find("period = 0.55\n"), std::string::npos) << text;
        }
        // The text as Save writes it reads back to the same groups, and again to the same text.
        Style read = parse_style(cat("[roots]\nwisps = ", style.wisps, "\n", text), "saved");
        EXPECT_EQ(groups_to_toml(read.groups), groups_to_toml(style.groups));
        ConstraintSections again;
        again.load(read, {});
        EXPECT_EQ(again.toml("style.toml"), text);
    }
}

// Sections that no longer expand into the style's groups (the groups were set since) are not
// shown: the groups are, as [[group]] tables.
TEST(ConstraintSections, StaleSectionsLoadAsTheGroups) {
    Style style = load_preset("braid");
    style.groups.pop_back();
    ConstraintSections sections;
    sections.load(style, {});
    ASSERT_EQ(sections.json().size(), style.groups.size());
    for (const nlohmann::json& s : sections.json())
        EXPECT_EQ(s["section"], "group");
}

// A braid and an updo placed in the editor (in head units, the sections' default) read as
// the CLI reads the same text, and the paths sent for drawing are the solver's trajectories
// (groom/hairdressing.cpp's expansion) in cm: one per braid strand, the updo's spiral, none
// for a tie.
TEST(ConstraintSections, BraidAndUpdoPathsAreTheCliExpansionInCentimetres) {
    const Style style = small_style();
    ConstraintSections sections;
    const auto placed = nlohmann::json::parse(R"([
        {"section": "braid", "name": "plait", "strands": 4, "start": [0, -0.4, -1.1],
         "axis": [0, -1, -0.2], "side": [1, 0, 0], "length": 2, "width": 0.3, "period": 0.6},
        {"section": "tie", "point": [0, 3, -11], "head_relative": false},
        {"section": "updo", "point": [0, 0.5, -1.1], "facing": [0, 0.2, -1], "turns": 3}])");
    const std::vector<GroupSpec> groups = sections.set(placed, style, {}, "style.toml");
    const Style cli = parse_style(sections.toml("style.toml"), "cli");
    ASSERT_EQ(groups.size(), 6u);
    EXPECT_EQ(groups_to_toml(groups), groups_to_toml(cli.groups));
    EXPECT_EQ(groups[0].name, "plait strand 0");
    EXPECT_EQ(groups[3].selection.parts, 4);

    HeadFrame head;
    head.center = Vec3f(0.f, 3.f, -0.7f);
    head.radius = 9.5f;
    const nlohmann::json paths = section_paths(sections.json(), groups, head);
    ASSERT_EQ(paths.size(), 3u);
    ASSERT_EQ(paths[0].size(), 4u);
    EXPECT_EQ(paths[1].size(), 0u);
    ASSERT_EQ(paths[2].size(), 1u);
    for (int strand = 0; strand < 4; ++strand) {
        const ConstraintSpec& c = groups[strand].queue[1];
        const nlohmann::json& p = paths[0][strand];
        ASSERT_EQ(p["points"].size(), c.trajectory.size());
        EXPECT_TRUE(p["smooth"].get<bool>());
        EXPECT_FLOAT_EQ(p["radius"].get<float>(), c.radius * 9.5f);
        for (size_t k = 0; k < c.trajectory.size(); ++k) {
            const Vec3f cm = head.to_space(c.trajectory[k]);
            for (int a = 0; a < 3; ++a)
                EXPECT_FLOAT_EQ(p["points"][k][a].get<float>(), cm[a]);
        }
    }
    // The spiral starts at the bun's centre and reaches bun_radius (0.3 head units) from it.
    const nlohmann::json& spiral = paths[2][0]["points"];
    const Vec3f centre = head.to_space(Vec3f(0.f, 0.5f, -1.1f));
    const auto at = [&](size_t k) {
        return Vec3f(spiral[k][0].get<float>(), spiral[k][1].get<float>(),
                     spiral[k][2].get<float>());
    };
    EXPECT_NEAR((at(0) - centre).norm(), 0.f, 1e-4f);
    EXPECT_NEAR((at(spiral.size() - 1) - centre).norm(), 0.3f * 9.5f, 1e-3f);
    // Sections and groups out of step give no paths rather than wrong ones.
    const std::vector<GroupSpec> fewer(groups.begin(), groups.begin() + 3);
    for (const nlohmann::json& p : section_paths(sections.json(), fewer, head))
        EXPECT_TRUE(p.empty());
}

// The frames sent beside the sections say the units the reader took each one in: a braid or
// updo in head units (the default, or head_relative = true) maps through the head frame, one
// with head_relative = false is in cm as written. Mapped by its frame, each braid's start
// and each bun's centre is where the server's expansion (the paths drawn) begins, and the
// spiral's reach is bun_radius times the frame's scale.
TEST(ConstraintSections, FramesGiveEachSectionsUnitsSoItsHandlesSitOnItsPaths) {
    const Style style = small_style();
    ConstraintSections sections;
    const auto placed = nlohmann::json::parse(R"([
        {"section": "braid", "start": [0, -0.4, -1.1], "length": 2, "width": 0.3},
        {"section": "braid", "start": [0, -1.5, -10.5], "axis": [0, -1, -0.2], "length": 20,
         "width": 3, "period": 5, "radius": 0.6, "head_relative": false},
        {"section": "updo", "point": [0, 8, -9], "facing": [0, 0.3, -1], "bun_radius": 2.8,
         "radius": 1.2, "head_relative": false},
        {"section": "updo", "point": [0, 0.5, -1.1], "head_relative": true}])");
    const std::vector<GroupSpec> groups = sections.set(placed, style, {}, "style.toml");
    HeadFrame head;
    head.center = Vec3f(0.f, 3.f, -0.7f);
    head.radius = 9.5f;
    const nlohmann::json frames = section_frames(sections.json(), head);
    const nlohmann::json paths = section_paths(sections.json(), groups, head);
    ASSERT_EQ(frames.size(), 4u);
    const std::vector<float> scales = {9.5f, 1.f, 1.f, 9.5f};
    for (size_t i = 0; i < 4; ++i) {
        const nlohmann::json& f = frames[i];
        const Vec3f origin(f["origin"][0].get<float>(), f["origin"][1].get<float>(),
                           f["origin"][2].get<float>());
        const float scale = f["scale"].get<float>();
        EXPECT_EQ(scale, scales[i]) << i;
        EXPECT_EQ(f["units"], scale == 1.f ? "cm" : "head units") << i;
        EXPECT_EQ(origin, scale == 1.f ? Vec3f::Zero().eval() : head.center) << i;
        const nlohmann::json& s = sections.json()[i];
        const nlohmann::json& at = s.contains("start") ? s["start"] : s["point"];
        const Vec3f cm =
            origin + scale * Vec3f(at[0].get<float>(), at[1].get<float>(), at[2].get<float>());
        const nlohmann::json& first = paths[i][0]["points"];
        const auto point = [&](size_t k) {
            return Vec3f(first[k][0].get<float>(), first[k][1].get<float>(),
                         first[k][2].get<float>());
        };
        EXPECT_NEAR((point(0) - cm).norm(), 0.f, 1e-3f) << i;
        if (s["section"] == "updo") {
            EXPECT_NEAR((point(first.size() - 1) - cm).norm(), scale * s.value("bun_radius", 0.3f),
                        1e-3f)
                << i;
        }
    }
    EXPECT_EQ(head_units_frame(head), frames[0]);
}

// A braid's painted selection is split into its strands: each strand's group takes a third
// of the painted wisps, all of them on the painted half, and the three make up the whole.
TEST(ConstraintSections, BraidSplitsItsPaintedSelectionIntoStrands) {
    Style style = small_style();
    const Head head = load_head(style.head);
    const Roots roots = grow_roots(style, head);
    ConstraintSections sections;
    sections.set_mask("back", left_half(64));
    style.groups = sections.set(
        nlohmann::json::parse(R"([{"section": "braid", "name": "b", "selection": "back"}])"), style,
        {}, "style.toml");
    ASSERT_EQ(style.groups.size(), 3u);
    const GroupSelection picked = select_groups(style, head, roots);
    size_t total = 0;
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(style.groups[k].selection.mask_pixels);
        EXPECT_GT(picked.selected[k].size(), 2u);
        for (const uint32_t w : picked.selected[k])
            EXPECT_LT(roots.masters[w].uv.x(), 0.5f + 1.f / 64);
        total += picked.selected[k].size();
    }
    EXPECT_LT(total, roots.masters.size() - 5);
    EXPECT_NE(sections.toml("style.toml").find("mask = \"style.back.mask.png\""),
              std::string::npos);
}

}  // namespace
}  // namespace wisp
