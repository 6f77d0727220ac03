#pragma once
// The style: every parameter of a hairstyle (Choe & Ko §2, §5), with defaults, so that an
// empty style is valid. Read from TOML by style_toml.hpp; docs/style.md is the reference.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/image.hpp"
#include "core/math.hpp"
#include "geometry/scalp.hpp"
#include "groom/growth.hpp"

namespace wisp {

// A scalar probability distribution.
struct Distribution {
    enum class Kind { kConstant, kUniform, kNormal, kTable };
    Kind kind = Kind::kConstant;
    float value = 0.f;               // kConstant
    float min = 0.f, max = 1.f;      // kUniform: [min, max]; kNormal, kTable: truncation range
    float mean = 0.f, stddev = 0.f;  // kNormal (truncated to [min, max] by resampling)
    std::vector<float> table;        // kTable: a histogram, the weights of equal-width bins
                                     // over [min, max] (#≥2, ≥ 0, not all 0)
};

// A map over the scalp (Choe & Ko §2.3, Fig. 8): a constant, a grayscale image in scalp UV
// space (see geometry/scalp.hpp), or a named procedural map. The map's value in [0,1] is
// scaled to [low, high].
struct ScalarMap {
    enum class Kind { kConstant, kImage, kProcedural };
    Kind kind = Kind::kConstant;
    float value = 1.f;            // kConstant, already in the map's units
    std::filesystem::path image;  // kImage (resolved relative to the style file)
    std::string procedural;       // kProcedural: a name from procedural_map_names()
    float low = 0.f, high = 1.f;  // kImage, kProcedural: value v → low + v·(high-low)
    // kImage: the image already decoded, used instead of reading `image` (the editor's
    // painted map, which it writes to `image` on Save). Not part of the TOML text.
    std::shared_ptr<const GrayImage> pixels;
};

// What hair rests on below the head ([body]): the solver's head field, the export with the
// head and the pictures take it with the head.
struct BodySpec {
    enum class Kind {
        kAuto,   // the built-in figure as it is; a head mesh that stops above the waist (a
                 // head, a bust) gets a proxy, one that reaches it is taken as it is
        kProxy,  // a proxy under any head mesh (geometry/body_proxy.hpp)
        kMesh,   // the head mesh as it is, whatever it ends in
        kObj,    // a second mesh, `obj`, in the head's space
    };
    Kind kind = Kind::kAuto;
    std::filesystem::path obj;  // kObj: an OBJ body mesh
    float scale = 1.f;          // kObj: multiplies its coordinates to reach centimetres, > 0
};

struct HeadSpec {
    std::filesystem::path obj;  // empty: the built-in head
    float scale = 1.f;          // multiplies the OBJ's coordinates to reach centimetres, > 0
    ScalpSpec scalp;
    BodySpec body;
};

// The prototype strand (§2.2): a built-in preset or a user polyline, decomposed into
// outline and details.
struct PrototypeSpec {
    enum class Kind { kStraight, kWavy, kCurly, kKinky, kPolyline };
    Kind kind = Kind::kStraight;
    float amplitude = 0.6f;       // cm, wave amplitude or coil radius, ≥ 0
    float period = 3.f;           // cm along the strand per wave or coil turn, > 0
    float length = 40.f;          // cm of prototype generated for presets, > 0
    std::vector<Vec3f> polyline;  // kPolyline: ≥ 4 points, cm
    int window = 4;               // h of §2.2.2, ≥ 1
    float temperature = 0.03f;    // T of eq. (4), ≥ 0 (0 = argmin, eq. (3))
    float roll = 0.5f;            // radians: each master's details turn about its outline by
                                  // a uniform angle in [-roll, roll], ≥ 0
    // Each master's waves or coils differ from its neighbours' as real locks do: its details
    // are scaled by a factor uniform in [1 − amplitude_variation, 1 + amplitude_variation] and
    // its period by one in [1 − period_variation, 1 + period_variation] (the clumps carry each
    // guide's to its clump). Both in [0, 0.9].
    float amplitude_variation = 0.f;
    float period_variation = 0.f;
    // Neighbouring locks wave in step as real waves set: each master's phase is drawn from a
    // smooth field over the scalp that varies over `coherence_size` cm, mixed with its own
    // random phase by 1 − coherence (0: every master its own random phase, as the paper).
    float coherence = 0.f;       // in [0, 1]
    float coherence_size = 8.f;  // cm, > 0
    float onset = 0.f;           // cm: the details grow from none at the root to full over
                                 // this much of the strand, ≥ 0 (0: full from the root)
};

// The wisp parameters of §2.1.
struct WispSpec {
    Distribution length{Distribution::Kind::kUniform, 0.f, 0.85f, 1.f};  // l(u), u in (0,1]
    std::vector<float> deviation_radius{1.f, 1.2f, 1.5f};  // r(s) at evenly spaced s in [0,1],
                                                           // relative to the root radius, > 0
    float fuzziness = 0.3f;                                // σ, ≥ 0
};

// Clumps at two scales above and below the wisp (docs/style.md [clump]): real hair gathers
// into locks of 1–3 cm that pull together toward the tips, with smaller sub-locks inside them.
// A clump is a few neighbouring wisps of one group that share a guide, one of their masters;
// a sub-clump is a part of one wisp around one of its members' roots. At master point k
// (s = k/(n−1)) a member moves the fraction pull·s^shape of the way to its clump's guide, then
// sub_pull·s^sub_shape of the way to its sub-clump's centre; each clump and sub-clump takes
// its own share of its pull, uniform in [1 − variation, 1].
struct ClumpSpec {
    ScalarMap size{ScalarMap::Kind::kConstant, 2.f};  // cm: how far apart clumps' guides
                                                      // root, ≥ 0 (0: one wisp each)
    float pull = 0.f;                                 // at the tip, in [0, 1] (0: no clumps)
    float shape = 1.5f;          // > 0: how late along the strand the pull comes in
    float variation = 0.4f;      // in [0, 1]
    int sub_count = 3;           // sub-clumps per wisp, in [1, 16] (1: none)
    float sub_pull = 0.f;        // in [0, 1]
    float sub_shape = 1.f;       // > 0
    float sub_variation = 0.4f;  // in [0, 1]
};

// The hairline (docs/style.md [hairline]): real hair does not stop at an edge. Root density
// ramps up from the scalp's edge over `width`; there some strands are baby hairs, short and
// fine, pointing their own way; and roots lie low along their growth direction.
struct HairlineSpec {
    float width = 0.6f;       // cm: density rises from 0 at the edge to full over this, ≥ 0
                              // (0: a hard edge)
    float baby = 0.3f;        // at the edge, the fraction of strands that are baby hairs, falling
                              // to 0 across the ramp, in [0, 1]
    float baby_length = 2.f;  // cm: a baby hair's length is uniform in [0.4, 1]·this, > 0
    float lie = 0.7f;         // within three ramp widths of the edge, masters' protrusion and
                              // lift are scaled down toward (1 − lie) at the edge, in [0, 1]
    // cm: how far the line wanders in from the scalp's edge (a noise over about 1.5 cm, and
    // half as much again at the temples), so it is not a drawn line, ≥ 0 (0: the edge itself)
    float irregularity = 0.4f;
};

// Flyaways: strands that leave their clump along a short arc near their tips, as real heads
// have 1–3% of, never long strays.
struct FlyawaySpec {
    float fraction = 0.01f;  // of strands, in [0, 0.2]
    float length = 4.f;      // cm: each one's last [0.5, 1]·length leaves the clump, > 0
    float lift = 1.f;        // cm: its tip leaves its place by up to this, sideways and out, ≥ 0
};

// Stochastic HSV color (§5, Fig. 12). Hue in degrees, saturation and value in [0,1].
struct ColorSpec {
    Distribution hue{Distribution::Kind::kNormal, 0.f, 0.f, 360.f, 30.f, 2.f};
    Distribution saturation{Distribution::Kind::kNormal, 0.f, 0.f, 1.f, 0.55f, 0.04f};
    Distribution value{Distribution::Kind::kNormal, 0.f, 0.f, 1.f, 0.30f, 0.04f};
    // Per-wisp variation (Fig. 12d): each wisp's HSV is offset by a normal draw with these
    // standard deviations, shared by all its strands.
    float wisp_hue = 0.f, wisp_saturation = 0.f, wisp_value = 0.f;
};

// One term of the styling force field Φ (Choe & Ko §3.1, §6.1); terms add, each scaled by
// its weight. Φ is dimensionless: gravity alone has |Φ| = weight.
struct FieldTerm {
    enum class Kind { kGravity, kPulledBack, kSidePart, kWind, kFile, kGrowth };
    Kind kind = Kind::kGravity;
    float weight = 1.f;          // any finite value
    Vec3f direction{0, 0, -1};   // kWind: the wind's direction (normalized on use), non-zero
    float side = 1.f;            // kSidePart: +1 parts on the character's left (hair swept to the
                                 // right), −1 on the right
    std::filesystem::path file;  // kFile: a field file (docs/style.md "Field files")
};

// Which wisps a group holds (§4 step 1): by their master root.
struct Selection {
    enum class Kind { kAll, kRegion, kMask, kBox, kHalfSpace, kWisps };
    Kind kind = Kind::kAll;
    std::string region;          // kRegion: a procedural map name; roots where it is > 0.5
    std::filesystem::path mask;  // kMask: image in scalp UV space; roots where it is > 0.5
    // kMask: the image already decoded, used instead of reading `mask` (a selection painted
    // in the editor, written to `mask` on Save). Not part of the TOML text.
    std::shared_ptr<const GrayImage> mask_pixels;
    Vec3f lo = Vec3f::Zero(), hi = Vec3f::Zero();  // kBox: head-space box, cm
    Vec3f normal = Vec3f::UnitX();                 // kHalfSpace: roots with normal·p > offset
    float offset = 0.f;
    std::vector<int> wisps;     // kWisps: wisp ids (0-based, < wisps)
    bool head_relative = true;  // lo, hi, offset in head units (see ConstraintSpec)
    // The selected wisps, ordered by their root's x (the character's left, +X, last), are cut
    // into `parts` equal runs and the group keeps run `part` (braids split one region in 3).
    int part = 0, parts = 1;  // 0 ≤ part < parts
};

// A styling constraint (§4, Fig. 10).
struct ConstraintSpec {
    enum class Kind { kPoint, kTrajectory, kDirection };
    Kind kind = Kind::kPoint;
    Vec3f point = Vec3f::Zero();    // kPoint: the attraction point, cm, head space
    std::vector<Vec3f> trajectory;  // kTrajectory, kDirection: ≥ 2 points, cm
    bool smooth = false;            // the trajectory is a Catmull-Rom curve through them
    float radius = 1.f;             // tolerance (point, trajectory) or influence (direction)
                                    // radius, cm, > 0
    float weight = 1.f;             // w of eq. (7), in [0, 1]
    // Animation (dynamics): the wisps are held rigidly to the head from the root through
    // where they meet this constraint, as a tie or hairpins hold them. Point constraints
    // (ties) hold by default.
    bool hold = false;
    // A holding trajectory (a bun): hair longer than the trajectory winds on over its last
    // `repeat` of arc length (a fraction in [0, 1]; 0: it leaves the trajectory at its end).
    float repeat = 0.f;
    // Positions in head units (the default, so that styles fit any head): p ↦ c + R·p, with c
    // the centre and R the radius of the sphere fitted to the scalp (Scalp::center(), crown);
    // radius is then in head units too. false: centimetres in head space.
    bool head_relative = true;
};

// A group of wisps with its constraint queue.
struct GroupSpec {
    std::string name;
    Selection selection;
    std::vector<ConstraintSpec> queue;
};

// The deformation solver's parameters (§3).
struct SolveSpec {
    bool enabled = true;          // false: masters keep their protrusion direction
    float stiffness = 1.f;        // κ of eq. (5), ≥ 0
    float threshold = 0.5f;       // τ of eq. (6), in (0, 1]
    float cell = 1.f;             // density/field grid cell, cm, in [0.2, 10]
    float full_density = 1000.f;  // strand·cm per cm³ that counts as density 1, > 0
    float bend_step = 4.f;        // Δθ of Algorithm 1, degrees, in (0, 45]
    int max_tries = 12;           // bound on the bends per joint, ≥ 0
    bool depth_first = false;     // Algorithm 1 is breadth-first; true compares depth-first
    float head_margin = 0.25f;    // cm: head density ramps from 1 at the surface to 0 here
    float friction = 0.3f;        // μ: hair on the skin (slide_direction), ≥ 0
    float wrap = 0.f;             // cm: hair this near the skin is drawn onto it; 0: none
    float bridge = 1.f;           // cm: creases narrower than twice this lie under the hair
    // Φ: gravity, and the scalp's growth direction over the head (which frames the face).
    std::vector<FieldTerm> field{FieldTerm{}, FieldTerm{FieldTerm::Kind::kGrowth, 1.5f}};
};

// Cutting (§6.2) beyond the length map: hair past the plane n·p > offset is cut off.
struct CutSpec {
    enum class Region { kAll, kFringe };
    bool enabled = false;
    // Which strands the plane cuts: all, or those rooted in the fringe sector
    // (groom/growth.hpp fringe_sector > 0.05): a fringe cut at the brows.
    Region region = Region::kAll;
    Vec3f normal{0, -1, 0};  // unit on use, non-zero
    float offset = 0.f;      // cm, or head units (along normal, from the scalp centre)
    bool head_relative = true;
    // Point-cut texture, cm: each wisp's ends lie up to this far past the plane, and each
    // strand up to a third of it further, so the cut line is uneven as a scissor cut is.
    float texture = 0.f;
    // Bevel, cm: the last this much of every strand the plane cut turns under, toward the
    // neck, as a bob's ends are dried (0: they end straight).
    float bevel = 0.f;
};

// Animation with the Adaptive Wisp Tree (Bertails et al. 2003); docs/animate.md.
struct DynamicsSpec {
    enum class Links { kAuto, kRigid, kSoft };
    // The hierarchy (§2.1): levels coarse to fine. 2: wisps, sub-wisps; 3: groups of wisps,
    // wisps, sub-wisps; 4: adds sub-sub-wisps.
    int levels = 3;             // in [2, 4]
    int wisps_per_group = 6;    // wisps per top-level group, in [2, 64]
    int sub_wisps = 3;          // sub-GCs per GC below the wisp level, in [2, 16]
    int sections = 8;           // nodes (cross-sections) per GC along the hair, in [3, 64]
    int strands_per_wisp = 50;  // imported hair without wisp ids: strands per wisp, ≥ 1
    // Segments (§2.3): rigid links or soft springs; auto = soft for curly and kinky
    // prototypes, rigid otherwise.
    Links links = Links::kAuto;
    float stiffness = 800.f;        // 1/s²: spring toward the styled shape (turned with the head)
    float stretch = 3000.f;         // 1/s²: soft links' length spring
    float damping = 8.f;            // 1/s: damping of velocity relative to the parent node
    float air_drag = 2.f;           // 1/s: drag toward the air's velocity (wind)
    float split_threshold = 0.15f;  // §3.1: |a|·r over this splits, m²/s² (N·m/kg), > 0
    float merge_velocity = 15.f;    // §3.2: relative speed under this may merge, cm/s, > 0
    float friction = 20.f;          // α of k_f = α·m (§4.2 eq. 1), 1/s, α·dt < 1
    float repulsion = 1500.f;       // k_r per unit of the lighter node's mass (eq. 2), 1/s²
    float repulsion_angle = 30.f;   // degrees: repel only segments crossing at more
    float voxel = 0.f;              // cm: finest hair–hair grid cell; 0 = 2× the mean radius
                                    // of the finest GCs
    int iterations = 2;             // rigid links: constraint passes before the final one
    bool hair_collisions = true;
    bool body_collisions = true;
    float dt = 0.01f;                // s: time step, in (0, 0.05]
    float linear_density = 6.5e-5f;  // g per cm of one strand (node masses), > 0
};

// A constraint section as the style file wrote it ([[group]], [[tie]], [[braid]], [[updo]]
// or [[comb]]): its kind and its table as JSON text (toml_to_json). The groups are what the
// solver uses; these are for the editor, which shows and saves a braid as a braid rather than
// as the groups it expands into.
struct SectionSource {
    std::string kind;   // "braid"
    std::string table;  // {"name": "braid", "start": [0.0, -0.45, -1.15], …}
};

struct Style {
    std::string name;  // from the file name or preset
    uint64_t seed = 1;
    HeadSpec head;
    int wisps = 2000;            // N_w, ≥ 1
    int strands = 100000;        // N_s, ≥ N_w
    int points_per_strand = 32;  // control points of a full-length strand, ≥ 4
    ScalarMap density{};         // relative root density, ≥ 0
    ScalarMap length{ScalarMap::Kind::kConstant, 25.f};       // master length in cm, > 0
    ScalarMap protrusion{ScalarMap::Kind::kConstant, 0.25f};  // 0 = along the scalp, 1 = along
                                                              // the normal
    // Root lift, cm: how far hair rises off the scalp before it falls, as blow-dried hair
    // stands at the crown and the part (the solve holds each master's first joints on the
    // direction it leaves the scalp until they reach this height), ≥ 0.
    ScalarMap lift{ScalarMap::Kind::kConstant, 0.f};
    GrowthSpec growth;          // the direction hair leaves the scalp: whorl, part, front hairline
    float root_width = 0.008f;  // cm, strand diameter at the root, > 0
    float tip_width = 0.002f;   // cm, at the tip, > 0
    float taper = 4.f;          // cm: the last `taper` of a strand narrows from root_width to
                                // tip_width, ≥ 0 (0: one width, a blunt cut)
    PrototypeSpec prototype;
    WispSpec wisp;
    ClumpSpec clump;
    HairlineSpec hairline;
    FlyawaySpec flyaway;
    ColorSpec color;
    SolveSpec solve;
    std::vector<GroupSpec> groups;        // constraint groups, including those the hairdressing
                                          // sections (tie, braid, updo, comb) expand into
    std::vector<SectionSource> sections;  // the sections the groups were read from, in file
                                          // order (empty when not read from TOML); setting
                                          // `groups` leaves them stale, so a reader of them
                                          // checks that they still expand into `groups`
    CutSpec cut;
    DynamicsSpec dynamics;
};

}  // namespace wisp
