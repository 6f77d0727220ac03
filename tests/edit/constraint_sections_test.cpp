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

}  // namespace
}  // namespace wisp
