#include "groom/style_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "groom/hairdressing.hpp"

namespace wisp {

const char* stage_name(Stage stage) {
    switch (stage) {
        case Stage::kHead:
            return "head";
        case Stage::kRoots:
            return "roots";
        case Stage::kMasters:
            return "masters";
        case Stage::kSolve:
            return "solve";
        case Stage::kMembers:
            return "members";
        case Stage::kColor:
            return "color";
        case Stage::kNone:
            return "none";
    }
    return "?";
}

namespace {

using T = FieldType;
using S = Stage;

// The field's storage in a Style, as a FieldRef.
#define WISP_REF(member) [](Style& s) -> FieldRef { return &s.member; }

// Bounds that keep a hostile or mistyped file from asking for absurd work or memory;
// style_toml.cpp holds the ones that are not a single field's range.
constexpr double kMaxStrands = 10'000'000;
constexpr double kMaxCoordinate = 1e4;  // cm or head units
constexpr double kPi = 3.1416;          // prototype.roll's bound, as documented

const std::vector<StyleField>& fields() {
    static const std::vector<StyleField> table = {
        // Top level.
        {.path = "name",
         .type = T::kString,
         .stage = S::kNone,
         .panel = "style",
         .doc = "shown in stats and file metadata",
         .ref = WISP_REF(name)},
        {.path = "seed",
         .type = T::kSeed,
         .stage = S::kRoots,
         .panel = "style",
         .doc = "seeds every random choice: the same style and seed give the same hair",
         .ref = WISP_REF(seed)},

        // [head]
        {.path = "head.obj",
         .type = T::kPath,
         .stage = S::kHead,
         .panel = "head",
         .doc = "an OBJ head mesh, relative to the style file (empty: the built-in head)",
         .ref = WISP_REF(head.obj)},
        {.path = "head.scale",
         .type = T::kNumber,
         .stage = S::kHead,
         .panel = "head",
         .lo = 0,
         .hi = 1e6,
         .lo_open = true,
         .doc = "multiplies the OBJ's coordinates to reach centimetres",
         .ref = WISP_REF(head.scale)},
        {.path = "head.scalp.method",
         .type = T::kChoice,
         .stage = S::kHead,
         .panel = "head",
         .paper = "§6",
         .choices = {"group", "mask", "hairline"},
         .doc = "how scalp faces are selected",
         .get_choice = [](const Style& s) { return static_cast<int>(s.head.scalp.kind); },
         .set_choice = [](Style& s,
                          int i) { s.head.scalp.kind = static_cast<ScalpSpec::Kind>(i); }},
        {.path = "head.scalp.group",
         .type = T::kString,
         .stage = S::kHead,
         .panel = "head",
         .positive = true,
         .doc = "group: the OBJ face group or material of the scalp",
         .ref = WISP_REF(head.scalp.group)},
        {.path = "head.scalp.mask",
         .type = T::kPath,
         .stage = S::kHead,
         .panel = "head",
         .doc = "mask: a grayscale image in the mesh's UV space; faces above 0.5 are scalp",
         .ref = WISP_REF(head.scalp.mask)},
        {.path = "head.scalp.front",
         .type = T::kNumber,
         .stage = S::kHead,
         .panel = "head",
         .unit = "cm",
         .lo = 0,
         .hi = 50,
         .lo_open = true,
         .doc = "hairline: its depth below the top of the head at the forehead",
         .ref = WISP_REF(head.scalp.hairline_front)},
        {.path = "head.scalp.side",
         .type = T::kNumber,
         .stage = S::kHead,
         .panel = "head",
         .unit = "cm",
         .lo = 0,
         .hi = 50,
         .lo_open = true,
         .doc = "hairline: its depth above the ears",
         .ref = WISP_REF(head.scalp.hairline_side)},
        {.path = "head.scalp.back",
         .type = T::kNumber,
         .stage = S::kHead,
         .panel = "head",
         .unit = "cm",
         .lo = 0,
         .hi = 50,
         .lo_open = true,
         .doc = "hairline: its depth at the nape",
         .ref = WISP_REF(head.scalp.hairline_back)},

        // [body]
        {.path = "body.method",
         .type = T::kChoice,
         .stage = S::kHead,
         .panel = "head",
         .choices = {"auto", "proxy", "mesh", "obj"},
         .doc = "what hair rests on below the head: auto (the built-in figure; a proxy torso "
                "under a head mesh that stops above the waist), proxy (always), mesh (the head "
                "mesh as it is), obj (body.obj)",
         .get_choice = [](const Style& s) { return static_cast<int>(s.head.body.kind); },
         .set_choice = [](Style& s, int i) { s.head.body.kind = static_cast<BodySpec::Kind>(i); }},
        {.path = "body.obj",
         .type = T::kPath,
         .stage = S::kHead,
         .panel = "head",
         .doc = "obj: a body mesh (OBJ) in the head's space, relative to the style file",
         .ref = WISP_REF(head.body.obj)},
        {.path = "body.scale",
         .type = T::kNumber,
         .stage = S::kHead,
         .panel = "head",
         .lo = 0,
         .hi = 1e6,
         .lo_open = true,
         .doc = "obj: multiplies the body OBJ's coordinates to reach centimetres",
         .ref = WISP_REF(head.body.scale)},

        // [roots]
        {.path = "roots.wisps",
         .type = T::kInteger,
         .stage = S::kRoots,
         .panel = "counts",
         .paper = "§2.3 N_w",
         .lo = 1,
         .hi = kMaxStrands,
         .doc = "N_w: the number of wisps, their master roots spread evenly over the scalp",
         .ref = WISP_REF(wisps)},
        {.path = "roots.strands",
         .type = T::kInteger,
         .stage = S::kRoots,
         .panel = "counts",
         .paper = "§2.3 N_s",
         .lo = 1,
         .hi = kMaxStrands,
         .doc = "N_s: the total number of strands, masters included",
         .ref = WISP_REF(strands)},
        {.path = "roots.points_per_strand",
         .type = T::kInteger,
         .stage = S::kMasters,
         .panel = "counts",
         .paper = "§2.1",
         .lo = 4,
         .hi = 1024,
         .doc = "control points of a full-length strand; about 8 per wave or curl period",
         .ref = WISP_REF(points_per_strand)},

        // [maps]
        {.path = "maps.density",
         .type = T::kMap,
         .stage = S::kRoots,
         .panel = "maps",
         .paper = "§2.3 Fig. 8",
         .lo = 0,
         .hi = 1e6,
         .positive = true,
         .doc = "relative density of member roots",
         .ref = WISP_REF(density),
         .map_low = 0,
         .map_high = 1},
        {.path = "maps.length",
         .type = T::kMap,
         .stage = S::kMasters,
         .panel = "maps",
         .paper = "§2.3 Fig. 8",
         .unit = "cm",
         .lo = 0,
         .hi = 500,
         .lo_open = true,
         .doc = "the length of the master strand rooted at each point",
         .ref = WISP_REF(length),
         .map_low = 1,
         .map_high = 25},
        {.path = "maps.protrusion",
         .type = T::kMap,
         .stage = S::kMasters,
         .panel = "maps",
         .paper = "§2.3 Fig. 8",
         .lo = 0,
         .hi = 1,
         .doc = "the direction a master leaves the scalp: 0 tangent, 1 along the normal",
         .ref = WISP_REF(protrusion),
         .map_low = 0,
         .map_high = 1},

        // [growth]
        {.path = "growth.part",
         .type = T::kChoice,
         .stage = S::kMasters,
         .panel = "growth",
         .choices = {"none", "centre", "left", "right"},
         .doc = "the parting; \"left\" lies on the character's left (+X)",
         .get_choice =
             [](const Style& s) {
                 switch (s.growth.part) {
                     case GrowthSpec::Part::kNone:
                         return 0;
                     case GrowthSpec::Part::kCentre:
                         return 1;
                     case GrowthSpec::Part::kSide:
                         break;
                 }
                 return s.growth.part_offset < 0 ? 3 : 2;
             },
         // A right part is a side part at a negative offset (growth.hpp).
         .set_choice =
             [](Style& s, int i) {
                 using Part = GrowthSpec::Part;
                 s.growth.part = i == 0 ? Part::kNone : i == 1 ? Part::kCentre : Part::kSide;
                 s.growth.part_offset = (i == 3 ? -1.f : 1.f) * std::abs(s.growth.part_offset);
             }},
        {.path = "growth.part_offset",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "growth",
         .unit = "head units",
         .lo = 0,
         .hi = 0.8,
         .lo_open = true,
         .doc = "a side part's distance from the midline (its sign comes from growth.part)",
         .ref = WISP_REF(growth.part_offset)},
        {.path = "growth.part_length",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "growth",
         .unit = "head units",
         .lo = 0,
         .hi = 3,
         .lo_open = true,
         .doc = "how far the part runs back from the front hairline: 1 reaches the whorl",
         .ref = WISP_REF(growth.part_length)},
        {.path = "growth.front",
         .type = T::kChoice,
         .stage = S::kMasters,
         .panel = "growth",
         .choices = {"sides", "back", "fringe"},
         .doc = "where front hairline hair goes",
         .get_choice = [](const Style& s) { return static_cast<int>(s.growth.front); },
         .set_choice = [](Style& s, int i) { s.growth.front = static_cast<GrowthSpec::Front>(i); }},
        {.path = "growth.whorl",
         .type = T::kDirection,
         .stage = S::kMasters,
         .panel = "growth",
         .lo = -kMaxCoordinate,
         .hi = kMaxCoordinate,
         .doc = "the crown whorl's direction from the scalp's centre",
         .ref = WISP_REF(growth.whorl)},
        {.path = "growth.whorl_turn",
         .type = T::kChoice,
         .stage = S::kMasters,
         .panel = "growth",
         .choices = {"clockwise", "counter-clockwise"},
         .doc = "the whorl's sense seen from above",
         .get_choice = [](const Style& s) { return s.growth.whorl_turn < 0 ? 1 : 0; },
         .set_choice = [](Style& s, int i) { s.growth.whorl_turn = i == 1 ? -1.f : 1.f; }},
        {.path = "growth.whorl_swirl",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "growth",
         .lo = 0,
         .hi = 2,
         .doc = "how strongly hair turns about the whorl near it",
         .ref = WISP_REF(growth.whorl_swirl)},
        {.path = "growth.map",
         .type = T::kPath,
         .stage = S::kMasters,
         .panel = "growth",
         .doc = "a growth-direction map in scalp UV: red and green give the direction",
         .ref = WISP_REF(growth.map)},
        {.path = "growth.map_strength",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "growth",
         .lo = 0,
         .hi = 1,
         .doc = "how much the map takes over where it is strong",
         .ref = WISP_REF(growth.map_strength)},

        // [strand]
        {.path = "strand.root_width",
         .type = T::kNumber,
         .stage = S::kMembers,
         .panel = "strand",
         .unit = "cm",
         .lo = 0,
         .hi = 1,
         .lo_open = true,
         .doc = "strand diameter at the root",
         .ref = WISP_REF(root_width)},
        {.path = "strand.tip_width",
         .type = T::kNumber,
         .stage = S::kMembers,
         .panel = "strand",
         .unit = "cm",
         .lo = 0,
         .hi = 1,
         .lo_open = true,
         .doc = "strand diameter at the tip",
         .ref = WISP_REF(tip_width)},

        // [prototype]
        {.path = "prototype.shape",
         .type = T::kChoice,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2",
         .choices = {"straight", "wavy", "curly", "kinky", "polyline"},
         .doc = "a built-in prototype strand, or your own polyline",
         .get_choice = [](const Style& s) { return static_cast<int>(s.prototype.kind); },
         .set_choice = [](Style& s,
                          int i) { s.prototype.kind = static_cast<PrototypeSpec::Kind>(i); }},
        {.path = "prototype.amplitude",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2",
         .unit = "cm",
         .lo = 0,
         .hi = 100,
         .doc = "wave amplitude or coil radius of a built-in shape",
         .ref = WISP_REF(prototype.amplitude)},
        {.path = "prototype.period",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2",
         .unit = "cm",
         .lo = 0,
         .hi = 1000,
         .lo_open = true,
         .doc = "length along the strand of one wave or coil turn",
         .ref = WISP_REF(prototype.period)},
        {.path = "prototype.length",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2",
         .unit = "cm",
         .lo = 0,
         .hi = 1000,
         .lo_open = true,
         .doc = "how much of a built-in prototype is generated",
         .ref = WISP_REF(prototype.length)},
        {.path = "prototype.points",
         .type = T::kPolyline,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2",
         .unit = "cm",
         .lo = -kMaxCoordinate,
         .hi = kMaxCoordinate,
         .doc = "your prototype strand, root first (shape = \"polyline\")",
         .ref = WISP_REF(prototype.polyline)},
        {.path = "prototype.window",
         .type = T::kInteger,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2.2 h",
         .lo = 1,
         .hi = 256,
         .doc = "h: how many preceding points the synthesis matches (about one period)",
         .ref = WISP_REF(prototype.window)},
        {.path = "prototype.temperature",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "prototype",
         .paper = "§2.2.2 eq. (4) T",
         .lo = 0,
         .hi = 100,
         .doc = "T: 0 copies the best match, strands grow more varied as T rises",
         .ref = WISP_REF(prototype.temperature)},
        {.path = "prototype.roll",
         .type = T::kNumber,
         .stage = S::kMasters,
         .panel = "prototype",
         .unit = "radians",
         .lo = 0,
         .hi = kPi,
         .doc = "each master's details turn about its outline by up to this angle",
         .ref = WISP_REF(prototype.roll)},

        // [wisp]
        {.path = "wisp.length",
         .type = T::kDistribution,
         .stage = S::kMembers,
         .panel = "wisp",
         .paper = "§2.1 l(u)",
         .lo = 0,
         .hi = 1,
         .positive = true,
         .doc = "l(u): a member's length relative to its master",
         .ref = WISP_REF(wisp.length)},
        // r(s) also scales the wisps' footprint in the solver's density grid.
        {.path = "wisp.deviation_radius",
         .type = T::kRadii,
         .stage = S::kSolve,
         .panel = "wisp",
         .paper = "§2.1 r(s)",
         .lo = 0,
         .hi = 100,
         .doc = "r(s): the wisp's radius from root to tip, relative to its root radius",
         .ref = WISP_REF(wisp.deviation_radius)},
        {.path = "wisp.fuzziness",
         .type = T::kNumber,
         .stage = S::kMembers,
         .panel = "wisp",
         .paper = "§2.1 eq. (1) σ",
         .lo = 0,
         .hi = 10,
         .doc = "σ: how much members wander inside the wisp (0.1 tidy, 1 unruly)",
         .ref = WISP_REF(wisp.fuzziness)},

        // [color]
        {.path = "color.preset",
         .type = T::kChoice,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5",
         .choices = {"black", "dark-brown", "brown", "auburn", "red", "blonde", "platinum", "gray"},
         .doc = "sets hue, saturation, value and the wisp_ fields to a natural hair color",
         .get_choice = [](const Style&) { return -1; },
         .set_choice = nullptr},
        {.path = "color.hue",
         .type = T::kDistribution,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12",
         .unit = "degrees",
         .lo = 0,
         .hi = 360,
         .doc = "hair hues are reds to yellows: about 10–45",
         .ref = WISP_REF(color.hue)},
        {.path = "color.saturation",
         .type = T::kDistribution,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12",
         .lo = 0,
         .hi = 1,
         .doc = "saturation",
         .ref = WISP_REF(color.saturation)},
        {.path = "color.value",
         .type = T::kDistribution,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12",
         .lo = 0,
         .hi = 1,
         .doc = "brightness: black hair ≈ 0.08, blonde ≈ 0.7",
         .ref = WISP_REF(color.value)},
        {.path = "color.wisp_hue",
         .type = T::kNumber,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12d",
         .unit = "degrees",
         .lo = 0,
         .hi = 180,
         .doc = "standard deviation of each wisp's hue offset",
         .ref = WISP_REF(color.wisp_hue)},
        {.path = "color.wisp_saturation",
         .type = T::kNumber,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12d",
         .lo = 0,
         .hi = 1,
         .doc = "standard deviation of each wisp's saturation offset",
         .ref = WISP_REF(color.wisp_saturation)},
        {.path = "color.wisp_value",
         .type = T::kNumber,
         .stage = S::kColor,
         .panel = "colour",
         .paper = "§5 Fig. 12d",
         .lo = 0,
         .hi = 1,
         .doc = "standard deviation of each wisp's value offset",
         .ref = WISP_REF(color.wisp_value)},

        // [solve]
        {.path = "solve.enabled",
         .type = T::kBoolean,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "§3",
         .doc = "false: masters keep the direction they leave the scalp with",
         .ref = WISP_REF(solve.enabled)},
        {.path = "solve.stiffness",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "§3.2 eq. (5) κ",
         .lo = 0,
         .hi = 1000,
         .doc = "κ: how strongly each segment keeps its rest direction against Φ",
         .ref = WISP_REF(solve.stiffness)},
        {.path = "solve.threshold",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "§3.3 eq. (6) τ",
         .lo = 0,
         .hi = 1,
         .lo_open = true,
         .doc = "τ: the density at which hair counts as colliding; smaller gives more volume",
         .ref = WISP_REF(solve.threshold)},
        // The head's distance field is built at a cell derived from this one (Stage::kSolve
        // re-runs it when its cell changes: see edit/stage_cache.cpp).
        {.path = "solve.cell",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "§3.3",
         .unit = "cm",
         .lo = 0.2,
         .hi = 10,
         .doc = "the cell of the grid holding Φ and the density",
         .ref = WISP_REF(solve.cell)},
        {.path = "solve.full_density",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "§3.3",
         .lo = 0,
         .hi = 1e9,
         .lo_open = true,
         .doc = "strand·cm of hair per cm³ that counts as density 1",
         .ref = WISP_REF(solve.full_density)},
        {.path = "solve.bend_step",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "Algorithm 1 Δθ",
         .unit = "degrees",
         .lo = 0,
         .hi = 45,
         .lo_open = true,
         .doc = "Δθ: how far a colliding joint bends per try",
         .ref = WISP_REF(solve.bend_step)},
        {.path = "solve.max_tries",
         .type = T::kInteger,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "Algorithm 1",
         .lo = 0,
         .hi = 1000,
         .doc = "how many Δθ bends a joint may take before the least dense is kept",
         .ref = WISP_REF(solve.max_tries)},
        {.path = "solve.order",
         .type = T::kChoice,
         .stage = S::kSolve,
         .panel = "solver",
         .paper = "Algorithm 1",
         .choices = {"breadth-first", "depth-first"},
         .doc = "joint j of every wisp before joint j + 1 of any (the paper), or wisp by wisp",
         .get_choice = [](const Style& s) { return s.solve.depth_first ? 1 : 0; },
         .set_choice = [](Style& s, int i) { s.solve.depth_first = i == 1; }},
        {.path = "solve.head_margin",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .unit = "cm",
         .lo = 0,
         .hi = 10,
         .doc = "the head's density falls from 1 at its surface to 0 this far out",
         .ref = WISP_REF(solve.head_margin)},
        {.path = "solve.friction",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .lo = 0,
         .hi = 10,
         .doc = "μ of hair on the skin: hair lying on the shoulders, chest or back slides down "
                "them only where the slope pulls harder than μ times it presses",
         .ref = WISP_REF(solve.friction)},
        {.path = "solve.bridge",
         .type = T::kNumber,
         .stage = S::kSolve,
         .panel = "solver",
         .unit = "cm",
         .lo = 0,
         .hi = 5,
         .doc = "hair lies over creases of the head narrower than twice this (behind the ears) "
                "instead of following the skin into them; 0 follows every crease",
         .ref = WISP_REF(solve.bridge)},
        {.path = "solve.field",
         .type = T::kFieldTerms,
         .stage = S::kSolve,
         .panel = "styling field",
         .paper = "§3.1, §6.1 Φ",
         .doc = "the styling force field Φ: a sum of weighted terms",
         .ref = WISP_REF(solve.field)},

        // [cut]
        {.path = "cut.enabled",
         .type = T::kBoolean,
         .stage = S::kMembers,
         .panel = "cut",
         .paper = "§6.2",
         .doc = "false keeps the section but does not cut",
         .ref = WISP_REF(cut.enabled)},
        {.path = "cut.region",
         .type = T::kChoice,
         .stage = S::kMembers,
         .panel = "cut",
         .paper = "§6.2",
         .choices = {"all", "fringe"},
         .doc = "which strands the plane cuts: all, or those rooted in the fringe sector",
         .get_choice = [](const Style& s) { return static_cast<int>(s.cut.region); },
         .set_choice = [](Style& s, int i) { s.cut.region = static_cast<CutSpec::Region>(i); }},
        {.path = "cut.normal",
         .type = T::kDirection,
         .stage = S::kMembers,
         .panel = "cut",
         .paper = "§6.2",
         .lo = -kMaxCoordinate,
         .hi = kMaxCoordinate,
         .doc = "points toward the hair that is cut off",
         .ref = WISP_REF(cut.normal)},
        {.path = "cut.offset",
         .type = T::kNumber,
         .stage = S::kMembers,
         .panel = "cut",
         .paper = "§6.2",
         .unit = "head units",
         .lo = -kMaxCoordinate,
         .hi = kMaxCoordinate,
         .doc = "the plane's distance along the normal from the scalp centre",
         .ref = WISP_REF(cut.offset)},
        {.path = "cut.head_relative",
         .type = T::kBoolean,
         .stage = S::kMembers,
         .panel = "cut",
         .doc = "offset in head units; false: centimetres",
         .ref = WISP_REF(cut.head_relative)},
        {.path = "cut.texture",
         .type = T::kNumber,
         .stage = S::kMembers,
         .panel = "cut",
         .unit = "cm",
         .lo = 0,
         .hi = 100,
         .doc = "point-cut texture: each wisp ends up to this far past the plane, each strand up "
                "to a third of it further, for an uneven, natural cut line",
         .ref = WISP_REF(cut.texture)},

        // Constraint groups and hairdressing operations (§4, §6.2), read in file order.
        {.path = "group",
         .type = T::kGroups,
         .stage = S::kSolve,
         .panel = "constraints",
         .paper = "§4",
         .doc = "a constraint group: a selection of wisps and its queue"},
        {.path = "tie",
         .type = T::kGroups,
         .stage = S::kSolve,
         .panel = "constraints",
         .paper = "§6.2",
         .doc = "tying, a ponytail: a point constraint with w = 1"},
        {.path = "braid",
         .type = T::kGroups,
         .stage = S::kSolve,
         .panel = "constraints",
         .paper = "§6.2",
         .doc = "braiding: strands gathered, then each on its braid path"},
        {.path = "updo",
         .type = T::kGroups,
         .stage = S::kSolve,
         .panel = "constraints",
         .paper = "§6.2 Fig. 15c",
         .doc = "an updo: a tie followed by a spiral into a bun"},
        {.path = "comb",
         .type = T::kGroups,
         .stage = S::kSolve,
         .panel = "constraints",
         .paper = "§6.2",
         .doc = "combing: a direction constraint along the comb's path"},

        // [dynamics] (Bertails et al. 2003; docs/animate.md)
        {.path = "dynamics.levels",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §2.1",
         .lo = 2,
         .hi = 4,
         .doc = "hierarchy levels, coarse to fine",
         .ref = WISP_REF(dynamics.levels)},
        {.path = "dynamics.wisps_per_group",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §2.1",
         .lo = 2,
         .hi = 64,
         .doc = "wisps per top-level group",
         .ref = WISP_REF(dynamics.wisps_per_group)},
        {.path = "dynamics.sub_wisps",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §2.1",
         .lo = 2,
         .hi = 16,
         .doc = "sub-GCs per GC below the wisp level",
         .ref = WISP_REF(dynamics.sub_wisps)},
        {.path = "dynamics.sections",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §2.1",
         .lo = 3,
         .hi = 64,
         .doc = "nodes per GC along the hair",
         .ref = WISP_REF(dynamics.sections)},
        {.path = "dynamics.strands_per_wisp",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .lo = 1,
         .hi = kMaxStrands,
         .doc = "hair without wisp ids: at most this many strands per wisp",
         .ref = WISP_REF(dynamics.strands_per_wisp)},
        {.path = "dynamics.links",
         .type = T::kChoice,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §2.3",
         .choices = {"auto", "rigid", "soft"},
         .doc = "rigid links or soft springs; auto = soft for curly and kinky prototypes",
         .get_choice = [](const Style& s) { return static_cast<int>(s.dynamics.links); },
         .set_choice = [](Style& s,
                          int i) { s.dynamics.links = static_cast<DynamicsSpec::Links>(i); }},
        {.path = "dynamics.stiffness",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "1/s²",
         .lo = 0,
         .hi = 1e5,
         .doc = "spring toward the styled shape",
         .ref = WISP_REF(dynamics.stiffness)},
        {.path = "dynamics.stretch",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "1/s²",
         .lo = 0,
         .hi = 1e6,
         .doc = "soft links' length spring",
         .ref = WISP_REF(dynamics.stretch)},
        {.path = "dynamics.damping",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "1/s",
         .lo = 0,
         .hi = 1000,
         .doc = "damping of velocity relative to the parent node",
         .ref = WISP_REF(dynamics.damping)},
        {.path = "dynamics.air_drag",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "1/s",
         .lo = 0,
         .hi = 1000,
         .doc = "drag toward the air's velocity",
         .ref = WISP_REF(dynamics.air_drag)},
        {.path = "dynamics.split_threshold",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §3.1",
         .unit = "m²/s²",
         .lo = 0,
         .hi = 1e3,
         .lo_open = true,
         .doc = "|a|·r over this splits a node",
         .ref = WISP_REF(dynamics.split_threshold)},
        {.path = "dynamics.merge_velocity",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §3.2",
         .unit = "cm/s",
         .lo = 0,
         .hi = 1e5,
         .lo_open = true,
         .doc = "relative speed under which nodes may merge",
         .ref = WISP_REF(dynamics.merge_velocity)},
        {.path = "dynamics.friction",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §4.2 eq. (1) α",
         .unit = "1/s",
         .lo = 0,
         .hi = 1e4,
         .doc = "α of k_f = α·m; α·dt must be < 1",
         .ref = WISP_REF(dynamics.friction)},
        {.path = "dynamics.repulsion",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §4.2 eq. (2)",
         .unit = "1/s²",
         .lo = 0,
         .hi = 1e6,
         .doc = "k_r per unit of the lighter node's mass",
         .ref = WISP_REF(dynamics.repulsion)},
        {.path = "dynamics.repulsion_angle",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "degrees",
         .lo = 0,
         .hi = 90,
         .doc = "repel only segments crossing at more",
         .ref = WISP_REF(dynamics.repulsion_angle)},
        {.path = "dynamics.voxel",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "cm",
         .lo = 0,
         .hi = 100,
         .doc = "finest hair–hair grid cell; 0 = twice the mean finest radius",
         .ref = WISP_REF(dynamics.voxel)},
        {.path = "dynamics.iterations",
         .type = T::kInteger,
         .stage = S::kNone,
         .panel = "dynamics",
         .lo = 0,
         .hi = 100,
         .doc = "rigid links: constraint passes before the final one",
         .ref = WISP_REF(dynamics.iterations)},
        {.path = "dynamics.hair_collisions",
         .type = T::kBoolean,
         .stage = S::kNone,
         .panel = "dynamics",
         .paper = "AWT §4",
         .doc = "hair–hair collisions",
         .ref = WISP_REF(dynamics.hair_collisions)},
        {.path = "dynamics.body_collisions",
         .type = T::kBoolean,
         .stage = S::kNone,
         .panel = "dynamics",
         .doc = "hair–body collisions",
         .ref = WISP_REF(dynamics.body_collisions)},
        {.path = "dynamics.dt",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "s",
         .lo = 0,
         .hi = 0.05,
         .lo_open = true,
         .doc = "time step",
         .ref = WISP_REF(dynamics.dt)},
        {.path = "dynamics.linear_density",
         .type = T::kNumber,
         .stage = S::kNone,
         .panel = "dynamics",
         .unit = "g/cm",
         .lo = 0,
         .hi = 1,
         .lo_open = true,
         .doc = "mass of one strand per cm",
         .ref = WISP_REF(dynamics.linear_density)},
    };
    return table;
}

#undef WISP_REF

struct Sections {
    std::vector<std::string> names;              // "" first, in schema order
    std::vector<std::vector<std::string>> keys;  // per name
};

const Sections& sections() {
    static const Sections s = [] {
        Sections out;
        const auto add = [&](const std::string& section, const std::string& key) {
            auto it = std::find(out.names.begin(), out.names.end(), section);
            if (it == out.names.end()) {
                out.names.push_back(section);
                out.keys.emplace_back();
                it = out.names.end() - 1;
            }
            auto& keys = out.keys[it - out.names.begin()];
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
        };
        add("", "");
        out.keys[0].clear();
        for (const StyleField& f : fields()) {
            // Every prefix is a key of the section above it: head.scalp.front adds "head" to
            // the top level, "scalp" to head and "front" to head.scalp.
            std::string_view path = f.path;
            std::string section;
            for (;;) {
                const size_t dot = path.find('.');
                const std::string key(path.substr(0, dot));
                add(section, key);
                if (dot == std::string_view::npos) break;
                section = section.empty() ? key : section + "." + key;
                path.remove_prefix(dot + 1);
            }
        }
        return out;
    }();
    return s;
}

// A section's default: the member of a default spec.
#define WISP_SECTION_DEFAULT(spec, member) []() -> double { return spec{}.member; }

const std::vector<SectionField>& section_fields() {
    constexpr double kInf = kMaxCoordinate;
    static const std::vector<SectionField> table = {
        {.section = "braid",
         .key = "strands",
         .type = T::kInteger,
         .lo = 3,
         .hi = 16,
         .soft_lo = 3,
         .soft_hi = 8,
         .doc = "how many strands (and groups)",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, strands)},
        {.section = "braid",
         .key = "length",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.5,
         .soft_hi = 4,
         .doc = "the braid's length along the axis",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, length)},
        {.section = "braid",
         .key = "width",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.1,
         .soft_hi = 1,
         .doc = "the braid's width",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, width)},
        {.section = "braid",
         .key = "period",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.2,
         .soft_hi = 1.5,
         .doc = "axis length of one full cycle of the pattern",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, period)},
        {.section = "braid",
         .key = "radius",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.02,
         .soft_hi = 0.3,
         .doc = "how tightly the strands keep to their path (tolerance radius)",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, radius)},
        {.section = "braid",
         .key = "weight",
         .type = T::kNumber,
         .lo = 0,
         .hi = 1,
         .soft_lo = 0,
         .soft_hi = 1,
         .doc = "w of eq. (7) for both constraints",
         .get_default = WISP_SECTION_DEFAULT(BraidSpec, weight)},
        {.section = "updo",
         .key = "radius",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.03,
         .soft_hi = 0.4,
         .doc = "tolerance radius of the tie and of the spiral",
         .get_default = WISP_SECTION_DEFAULT(UpdoSpec, radius)},
        {.section = "updo",
         .key = "bun_radius",
         .type = T::kNumber,
         .unit = "head units",
         .lo = 0,
         .hi = kInf,
         .lo_open = true,
         .soft_lo = 0.1,
         .soft_hi = 0.8,
         .doc = "the spiral's outer radius",
         .get_default = WISP_SECTION_DEFAULT(UpdoSpec, bun_radius)},
        {.section = "updo",
         .key = "turns",
         .type = T::kNumber,
         .lo = 0,
         .hi = 50,
         .lo_open = true,
         .soft_lo = 0.5,
         .soft_hi = 6,
         .doc = "how many times the hair winds around",
         .get_default = WISP_SECTION_DEFAULT(UpdoSpec, turns)},
        {.section = "updo",
         .key = "weight",
         .type = T::kNumber,
         .lo = 0,
         .hi = 1,
         .soft_lo = 0,
         .soft_hi = 1,
         .doc = "w of eq. (7) for both constraints",
         .get_default = WISP_SECTION_DEFAULT(UpdoSpec, weight)},
    };
    return table;
}

}  // namespace

std::span<const SectionField> section_schema() {
    return section_fields();
}

const SectionField* find_section_field(std::string_view section, std::string_view key) {
    for (const SectionField& f : section_fields())
        if (f.section == section && f.key == key) return &f;
    return nullptr;
}

std::span<const StyleField> style_schema() {
    return fields();
}

const StyleField* find_style_field(std::string_view path) {
    for (const StyleField& f : fields())
        if (f.path == path) return &f;
    return nullptr;
}

std::string_view field_section(std::string_view path) {
    const size_t dot = path.rfind('.');
    return dot == std::string_view::npos ? std::string_view() : path.substr(0, dot);
}

std::string_view field_key(std::string_view path) {
    const size_t dot = path.rfind('.');
    return dot == std::string_view::npos ? path : path.substr(dot + 1);
}

const std::vector<std::string>& section_keys(std::string_view section) {
    const Sections& s = sections();
    for (size_t i = 0; i < s.names.size(); ++i)
        if (s.names[i] == section) return s.keys[i];
    static const std::vector<std::string> none;
    return none;
}

const std::vector<std::string>& style_sections() {
    return sections().names;
}

const char* field_type_name(FieldType type) {
    switch (type) {
        case FieldType::kNumber:
            return "number";
        case FieldType::kInteger:
            return "integer";
        case FieldType::kSeed:
            return "seed";
        case FieldType::kBoolean:
            return "boolean";
        case FieldType::kString:
            return "string";
        case FieldType::kPath:
            return "path";
        case FieldType::kChoice:
            return "choice";
        case FieldType::kPoint:
            return "point";
        case FieldType::kDirection:
            return "direction";
        case FieldType::kMap:
            return "map";
        case FieldType::kDistribution:
            return "distribution";
        case FieldType::kRadii:
            return "radii";
        case FieldType::kPolyline:
            return "polyline";
        case FieldType::kFieldTerms:
            return "field_terms";
        case FieldType::kGroups:
            return "groups";
    }
    return "?";
}

}  // namespace wisp
