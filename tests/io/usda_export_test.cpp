// What the .usda writer declares for Unreal's groom importer and for other USD tools beyond
// the strands: root UVs, groups, guides (UsdaWriteOptions::guides) and the head mesh
// (UsdaWriteOptions::head). Checked as a parse of the declarations, against the names and
// types of Unreal's converter (USDGroomConversion.cpp) and groom builder (GroomBuilder.cpp).
#include <gtest/gtest.h>

#include <map>
#include <regex>

#include "core/parallel.hpp"
#include "io/usda.hpp"
#include "io_test_util.hpp"

namespace wisp {
namespace {

// One prim's text: from `def <kind> "<name>"` to the next `def ` at the same or lower depth.
std::string prim_text(const std::string& text, const std::string& def) {
    const size_t at = text.find(def);
    if (at == std::string::npos) return "";
    const size_t end = text.find("\n    def ", at + def.size());
    const size_t end2 = text.find("\ndef ", at + def.size());
    return text.substr(at, std::min(end, end2) - at);
}

// name -> (type, interpolation) of every attribute declared in `text`.
struct Decl {
    std::string type, interpolation;
    size_t values = 0;  // top-level values in its [ ... ]
};
std::map<std::string, Decl> declarations(const std::string& text) {
    static const std::regex decl(
        R"(\n\s*(?:uniform\s+)?([A-Za-z0-9]+(?:\[\])?)\s+([\w:]+)\s*=\s*)");
    std::map<std::string, Decl> out;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), decl);
         it != std::sregex_iterator(); ++it) {
        Decl d;
        d.type = (*it)[1];
        size_t at = static_cast<size_t>(it->position() + it->length());
        if (at < text.size() && text[at] == '[') {
            int depth = 0;
            size_t i = at;
            bool any = false;
            for (; i < text.size(); ++i) {
                const char c = text[i];
                if (c == '[' || c == '(') ++depth;
                if (c == ']' || c == ')') --depth;
                if (depth == 1 && c == ',') ++d.values;
                if (depth >= 1 && c != '[' && c != ' ' && c != '\n') any = true;
                if (depth == 0) break;
            }
            d.values += any ? 1 : 0;
            const size_t paren = text.find_first_not_of(" ", i + 1);
            if (paren < text.size() && text[paren] == '(') {
                const size_t close = text.find(')', paren);
                const std::string meta = text.substr(paren, close - paren);
                const size_t q = meta.find("interpolation = \"");
                if (q != std::string::npos)
                    d.interpolation = meta.substr(q + 17, meta.find('"', q + 17) - q - 17);
            }
        }
        out[(*it)[2]] = d;
    }
    return out;
}

// 30 strands in 3 wisps with root UVs, normals and groups; the 3 guides.
struct Groom {
    Hair hair, guides;
};
Groom sample_groom() {
    Groom g;
    g.hair = test::random_hair(31, 30, 5);
    g.guides = test::random_hair(32, 3, 6, false, false, false);
    for (size_t s = 0; s < 30; ++s) {
        g.hair.wisp[s] = int32_t(s / 10);
        g.hair.root_uv.emplace_back(0.25f + 0.01f * float(s), 0.5f);
        g.hair.root_normal.emplace_back(0.f, 1.f, 0.f);
        g.hair.group.push_back(int32_t(s / 10 == 2 ? 1 : 0));
    }
    for (int w = 0; w < 3; ++w) {
        g.guides.wisp.push_back(w);
        g.guides.group.push_back(w == 2 ? 1 : 0);
        g.guides.root_uv.emplace_back(0.3f, 0.1f * float(w));
    }
    return g;
}

TEST(UsdaExport, RootUvAndGroupsPerStrand) {
    const Groom g = sample_groom();
    const std::string text = encode_usda(g.hair, "g.usda");
    const auto d = declarations(text);
    EXPECT_EQ(d.at("primvars:groom_root_uv").type, "float2[]");
    EXPECT_EQ(d.at("primvars:groom_root_uv").interpolation, "uniform");
    EXPECT_EQ(d.at("primvars:groom_root_uv").values, 30u);
    EXPECT_EQ(d.at("primvars:groom_group_id").type, "int[]");
    EXPECT_EQ(d.at("primvars:groom_group_id").interpolation, "uniform");
    EXPECT_EQ(d.at("primvars:groom_group_id").values, 30u);
    EXPECT_NE(text.find("(0.26, 0.5)"), std::string::npos);
    // No guides: no guide attributes, GroomAPI on the curves.
    EXPECT_FALSE(d.count("primvars:groom_guide"));
    EXPECT_NE(text.find("def BasisCurves \"strands\" (\n        prepend apiSchemas"),
              std::string::npos);
    // wisp reads the layer back unchanged.
    const Hair r = hair_from_usda(parse_usda(text, "g.usda"), "g.usda");
    test::expect_same_geometry(g.hair, r);
}

TEST(UsdaExport, GuidesForUnreal) {
    const Groom g = sample_groom();
    const std::string text = encode_usda(g.hair, "g.usda", UsdaWriteOptions{.guides = &g.guides});
    // GroomAPI on the Xform, so that both curve prims become one groom.
    EXPECT_NE(text.find("def Xform \"hair\" (\n    prepend apiSchemas = [\"GroomAPI\"]\n)"),
              std::string::npos);
    EXPECT_EQ(text.find("def BasisCurves \"strands\" ("), std::string::npos);
    const auto strands = declarations(prim_text(text, "def BasisCurves \"strands\""));
    const auto guides = declarations(prim_text(text, "def BasisCurves \"guides\""));
    ASSERT_FALSE(guides.empty());
    // The guide flag (int, 1 for guides), the ids the closest guides refer to, the single
    // closest guide (int) and its weight (float): GroomBuilder's "single" variant.
    EXPECT_EQ(strands.at("primvars:groom_guide").type, "int[]");
    EXPECT_EQ(strands.at("primvars:groom_guide").interpolation, "constant");
    EXPECT_EQ(guides.at("primvars:groom_guide").type, "int[]");
    EXPECT_NE(text.find("int[] primvars:groom_guide = [1]"), std::string::npos);
    EXPECT_NE(text.find("int[] primvars:groom_guide = [0]"), std::string::npos);
    EXPECT_EQ(strands.at("primvars:groom_id").values, 30u);
    EXPECT_EQ(guides.at("primvars:groom_id").values, 3u);
    EXPECT_EQ(strands.at("primvars:groom_closest_guides").type, "int[]");
    EXPECT_EQ(strands.at("primvars:groom_closest_guides").interpolation, "uniform");
    EXPECT_EQ(strands.at("primvars:groom_guide_weights").type, "float[]");
    EXPECT_FALSE(guides.count("primvars:groom_closest_guides"));
    // Strand 25 (wisp 2) is driven by guide 2, whose groom_id is 30 + 2; guides carry the
    // group of their wisp, so Unreal puts them in the same group as their strands.
    const std::string s_text = prim_text(text, "def BasisCurves \"strands\"");
    const size_t cg = s_text.find("groom_closest_guides = [");
    EXPECT_EQ(s_text.substr(cg + 24, 12), "30, 30, 30, ");
    EXPECT_NE(s_text.find("32, 32, 32]", cg), std::string::npos);
    EXPECT_NE(text.find("int[] primvars:groom_id = [30, 31, 32]"), std::string::npos);
    EXPECT_NE(text.find("int[] primvars:groom_group_id = [0, 0, 1]"), std::string::npos);
    // Both prims parse, and wisp reads the strands and the guides.
    const UsdaLayer layer = parse_usda(text, "g.usda");
    ASSERT_EQ(layer.curves.size(), 2u);
    EXPECT_EQ(layer.curves[1].path, "/hair/guides");
    EXPECT_EQ(layer.curves[1].counts, (std::vector<int>{6, 6, 6}));
    EXPECT_EQ(usd_curves_problem(layer.curves[1]), "");
    // The guides are flagged, and reading the layer as hair draws the render strands only.
    EXPECT_FALSE(layer.curves[0].guide);
    EXPECT_TRUE(layer.curves[1].guide);
    test::expect_same_geometry(g.hair, hair_from_usda(layer, "g.usda"));
    // A layer of guides alone still reads as the guides' strands.
    UsdaLayer only_guides = layer;
    only_guides.curves.erase(only_guides.curves.begin());
    EXPECT_EQ(hair_from_usda(only_guides, "g.usda").strand_count(), 3u);
    // A strand whose wisp has no guide is an error.
    Groom bad = sample_groom();
    bad.hair.wisp[4] = 3;
    test::expect_error(
        [&] { encode_usda(bad.hair, "b.usda", UsdaWriteOptions{.guides = &bad.guides}); },
        "b.usda: strand 4 has wisp id 3, but there are 3 guides");
}

TEST(UsdaExport, HeadMeshBesideTheHair) {
    const Groom g = sample_groom();
    Mesh head;
    head.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    head.faces = {Vec3i(0, 2, 1), Vec3i(0, 1, 3), Vec3i(0, 3, 2), Vec3i(1, 2, 3)};
    const std::vector<uint32_t> scalp{1, 3};
    for (bool z_up : {false, true}) {
        const std::string text = encode_usda(
            g.hair, "h.usda", UsdaWriteOptions{.z_up = z_up, .head = &head, .head_scalp = scalp});
        const size_t at = text.find("\ndef Mesh \"head\"");  // the last prim, with its subset
        ASSERT_NE(at, std::string::npos);
        const std::string mesh = text.substr(at);
        const auto d = declarations(mesh);
        EXPECT_EQ(d.at("faceVertexCounts").type, "int[]");
        EXPECT_EQ(d.at("faceVertexCounts").values, 4u);
        EXPECT_EQ(d.at("faceVertexIndices").values, 12u);
        EXPECT_EQ(d.at("points").type, "point3f[]");
        EXPECT_EQ(d.at("points").values, 4u);
        EXPECT_EQ(d.at("normals").type, "normal3f[]");
        EXPECT_EQ(d.at("normals").interpolation, "vertex");
        EXPECT_EQ(d.count("primvars:displayColor"), 0u);  // no colours, none written
        EXPECT_NE(mesh.find("def GeomSubset \"scalp\""), std::string::npos);
        EXPECT_NE(mesh.find("uniform token elementType = \"face\""), std::string::npos);
        EXPECT_NE(mesh.find("int[] indices = [1, 3]"), std::string::npos);
        // The same axes as the hair: vertex 2 (0, 1, 0) is up.
        EXPECT_NE(mesh.find(z_up ? "(0, -0, 1), (0, -1, 0)]" : "(0, 1, 0), (0, 0, 1)]"),
                  std::string::npos)
            << mesh;
        // wisp's reader reads past the mesh: the hair comes back alone.
        const Hair r = hair_from_usda(parse_usda(text, "h.usda"), "h.usda");
        test::expect_same_geometry(g.hair, r);
    }
    // A face's colours (the built-in head's eyes and lips) go with it, as they are: colours
    // do not turn with the up axis.
    Mesh coloured = head;
    coloured.colors = {{0.5f, 0.25f, 0.125f}, {1, 1, 1}, {0, 0, 0}, {0.75f, 0, 0}};
    for (bool z_up : {false, true}) {
        const std::string text =
            encode_usda(g.hair, "c.usda", UsdaWriteOptions{.z_up = z_up, .head = &coloured});
        const auto d = declarations(text.substr(text.find("\ndef Mesh \"head\"")));
        EXPECT_EQ(d.at("primvars:displayColor").type, "color3f[]");
        EXPECT_EQ(d.at("primvars:displayColor").values, 4u);
        EXPECT_EQ(d.at("primvars:displayColor").interpolation, "vertex");
        EXPECT_NE(text.find("[(0.5, 0.25, 0.125), (1, 1, 1), (0, 0, 0), (0.75, 0, 0)]"),
                  std::string::npos);
    }
    Mesh broken = head;
    broken.faces[2][1] = 9;
    test::expect_error([&] { encode_usda(g.hair, "m.usda", UsdaWriteOptions{.head = &broken}); },
                       "m.usda: head face 2 has vertex 9 of 4");
    coloured.colors.pop_back();
    test::expect_error([&] { encode_usda(g.hair, "m.usda", UsdaWriteOptions{.head = &coloured}); },
                       "m.usda: the head has 3 vertex colours for 4 vertices");
}

TEST(UsdaExport, SameBytesAtAnyThreadCount) {
    Groom g = sample_groom();
    g.hair = test::random_hair(33, 5000, 0);
    for (size_t s = 0; s < g.hair.strand_count(); ++s) {
        g.hair.wisp[s] = int32_t(s % 3);
        g.hair.root_uv.emplace_back(0.5f, float(s) * 1e-4f);
    }
    const UsdaWriteOptions options{.guides = &g.guides};
    std::string one, two;
    {
        const ThreadLimit limit(1);
        one = encode_usda(g.hair, "t", options);
    }
    {
        const ThreadLimit limit(2);
        two = encode_usda(g.hair, "t", options);
    }
    EXPECT_EQ(one, two);
}

}  // namespace
}  // namespace wisp
