#pragma once
// The hair renderer (Choe & Ko 2005 §5 on the CPU): the head with diffuse skin shading and
// every strand as a thin camera-facing ribbon along its Catmull-Rom curve, shaded with the
// lobes of real hair (hair_shading.hpp) or Kajiya-Kay (kajiya_kay.hpp) under a key, a fill
// and a rim light and ambient, shadowed from the key and the rim light by an opacity shadow
// map of the hair (opacity_shadow_map.hpp) and a depth map of the head (shadow_depth_map.hpp)
// each, antialiased by coverage and composited front to back.
//
// Passes, each timed in RenderStats::stages:
//   1. camera       named view framed on framing_bounds(), or an explicit look-at
//   2. shadows      opacity shadow map of the hair + depth map of the head, from the key and
//                   from the rim light
//   3. head         head triangles binned to 32×32-pixel tiles and rasterized with 2×2 samples
//                   per pixel (nearest face and depth per sample), and per 8×8-pixel block the
//                   farthest head sample
//   4. strands      each Catmull-Rom segment cut into pieces of ≤ 24 pixels; every piece end
//                   projected; pieces the head hides at every pixel they may touch are flagged,
//                   and only the ends of the others shaded (hair lobes × shadow), width tapered
//                   to the tip
//   5. bin          the pieces binned to the tiles, in strand order
//   6. tiles        per tile, in parallel: the pieces sorted by depth and rasterized front to
//                   back with coverage, per pixel, until it is opaque; the head's samples shaded
//                   under what the hair lets through (deferred shading); resolved to sRGB.
// Every pass writes only its own outputs, so the picture is bit-identical for any thread
// count.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/hair.hpp"
#include "core/image.hpp"
#include "core/math.hpp"
#include "core/timer.hpp"
#include "geometry/mesh.hpp"
#include "render/camera.hpp"
#include "render/fiber_scattering.hpp"
#include "render/hair_shading.hpp"

namespace wisp {

struct DirectionalLight {
    // Towards the light, in camera space (x right, y up, z towards the viewer), so that
    // every view is lit alike; normalized by the renderer.
    Vec3f direction;
    Vec3f color;  // linear RGB intensity
};

struct LookAt {
    Vec3f eye, target;  // cm, head space
    Vec3f up = Vec3f::UnitY();
};

struct RenderOptions {
    int width = 1024, height = 1024;     // pixels
    std::string view = "three-quarter";  // one of view_names(), unless look_at is set
    std::optional<LookAt> look_at;       // explicit camera; overrides view
    float fov_y_degrees = 30.f;
    Vec3f background = Vec3f(0.3f, 0.3f, 0.31f);  // linear RGB

    // The hair's reflectance: kHair, the lobes of real hair (hair_shading.hpp), or kKajiyaKay,
    // the model of Choe & Ko §5: colour = ambient·c + Σ_lights light·(diffuse_strength·c·
    // sin(t,l) + specular_strength·s·cone^specular_exponent), s = mix(white, c, specular_tint).
    // kFiber: the far-field fibre model of Chiang et al. 2016 (Cycles' Principled Hair BSDF),
    // the strand's colour as the melanin that gives it, with light scattered many times by
    // dual scattering (fiber_scattering.hpp).
    enum class Shading { kHair, kKajiyaKay, kFiber };
    Shading shading = Shading::kHair;
    HairLobes hair;
    FiberParams fiber;
    float diffuse_strength = 0.7f;
    float specular_strength = 0.5f;
    float specular_exponent = 80.f;
    float specular_tint = 0.4f;
    // Key from the upper left, fill from the right, rim from behind on the upper right, all
    // relative to the camera. The rim (back) light outlines the hair against the background
    // and makes the hair at the silhouette glow through its transmission lobe; black turns it
    // off (and its shadow maps with it).
    DirectionalLight key{Vec3f(-0.8f, 0.6f, 0.3f), Vec3f(1.5f, 1.47f, 1.4f)};
    DirectionalLight fill{Vec3f(0.8f, 0.1f, 0.6f), Vec3f(0.19f, 0.2f, 0.22f)};
    DirectionalLight rim{Vec3f(0.45f, 0.5f, -0.75f), Vec3f(1.6f, 1.6f, 1.7f)};
    Vec3f ambient = Vec3f(0.05f, 0.05f, 0.055f);

    // Strands.
    float width_scale = 1.f;   // multiplies the hair's widths
    float tip_width = 0.3f;    // width at the tip as a fraction of the width at mid-length
    float hair_opacity = 1.f;  // opacity of a strand where it covers a whole pixel
    // Per-strand variation, from a hash of the strand's index (the same at any thread count),
    // so that a dense layer shows its single hairs: each strand's colour is scaled by
    // 1 ± strand_brightness and its width by 1 ± strand_width (uniform, mean 1).
    float strand_brightness = 0.3f;
    float strand_width = 0.5f;

    Vec3f skin_color = kSkinAlbedo;  // linear RGB albedo of a head without vertex colours

    // Shadows from the key and the rim light (the fill is soft and casts none).
    bool shadows = true;
    int shadow_resolution = 192;  // key light: opacity shadow map texels per side
    int shadow_slices = 48;       // key light: opacity shadow map slabs along the light
    // The rim light lights only the hair's outer layer at the silhouette, where a coarser
    // map does as well: texels per side, slabs. Its head depth map is 256² (the key's 512²).
    int rim_shadow_resolution = 128;
    int rim_shadow_slices = 32;
    float shadow_opacity = 0.4f;  // light blocked by one strand fully covering a texel
    // The same for the hair lobes' (R, TRT, TT) share of the key light: light scattered once,
    // which a fibre in front blocks whole, where shadow_opacity, for the diffuse term, stands
    // for light scattered many times through the hair. Without it, the primary highlight of the
    // strands under the outer layer added up to an even grey film over a sheet of dark hair.
    float lobe_shadow_opacity = 1.f;
    // The same for the rim light: a fibre's full opacity, so that the rim lights the outermost
    // strands of the silhouette and not, through a sparse layer, the whole hair's far side.
    float rim_shadow_opacity = 1.f;
    // The rim's map deposits every n-th strand with n times the opacity (a 128² map does not
    // resolve single strands; the walk over the strands was the rim's largest cost).
    int rim_shadow_stride = 4;
};

// The shading models by name (`--shading`, Python's shading=): "hair", "fiber", "kajiya-kay".
const std::vector<std::string>& shading_names();
// The model of a name of shading_names(); throws wisp::Error naming the choices otherwise.
RenderOptions::Shading parse_shading(const std::string& name);

struct RenderStats {
    StageTimes stages;          // (pass, ms) in the order above
    size_t pieces = 0;          // straight strand pieces
    size_t hidden_pieces = 0;   // of which hidden by the head (or behind the eye): not drawn
    size_t tile_entries = 0;    // (piece, tile) pairs after binning
    size_t fragments = 0;       // hair fragments composited (after early termination)
    size_t head_triangles = 0;  // front-facing head triangles binned
};

// The display's response to shaded light (linear RGB), as a film's shoulder: colours whose
// largest channel is at most kHighlightKnee pass unchanged; above it the largest channel
// rolls off toward 1 (continuous in value and slope at the knee) and the others keep their
// ratio to it. A highlight brighter than the display so keeps its hue, where clipping channel
// by channel turns the orange-brown light through brown hair yellow. render() applies it to
// every shaded colour of hair and head before compositing, so the background shows as given.
constexpr float kHighlightKnee = 0.8f;
Vec3f roll_off_highlights(const Vec3f& linear);

// The box that named views frame: the hair and the part of the head above the hair's
// lowest point less 4 cm, or above 26 cm below the head's top if that is lower (so that the
// face shows under short hair, and a bust mesh's shoulders do not shrink it); the whole head
// if there is no hair. Empty only if both are.
Box3 framing_bounds(const Hair& hair, const Mesh* head);

// The camera render() uses for these options.
Camera render_camera(const Hair& hair, const Mesh* head, const RenderOptions& options);

// Renders hair (and head, if not null; both cm, head space) to an 8-bit sRGB image of
// options.width × options.height. Throws wisp::Error for an unknown view or a bad size.
// With `alpha`, it receives #H·W coverage (0 to 255, row-major, top row first: the share of
// the pixel that hair and head cover), the background is left out, and the image's colours
// are straight (not premultiplied): the colour of what covers the pixel, black where nothing
// does.
RgbImage render(const Hair& hair, const Mesh* head, const RenderOptions& options,
                RenderStats* stats = nullptr, std::vector<uint8_t>* alpha = nullptr);

// Renders each view of `views` at options.width × options.height and lays them out left to
// right, top to bottom, on a grid of ceil(sqrt(n)) columns (one row for n ≤ 3).
// `on_view`, if set, is told after each view (its 1-based number and name), for progress.
RgbImage contact_sheet(const Hair& hair, const Mesh* head, const std::vector<std::string>& views,
                       const RenderOptions& options,
                       const std::function<void(int, const std::string&)>& on_view = {});

}  // namespace wisp
