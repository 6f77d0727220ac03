#include "render/render.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <span>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "geometry/skin_normals.hpp"
#include "render/kajiya_kay.hpp"
#include "render/opacity_shadow_map.hpp"
#include "render/shadow_depth_map.hpp"
#include "render/strand_raster.hpp"
#include "render/strand_samples.hpp"

namespace wisp {
namespace {

constexpr int kTile = 32;                // tile side, pixels
constexpr float kFlatness = 0.2f;        // pixels: pieces follow the curve this closely
constexpr float kMaxPiecePixels = 24.f;  // and are no longer (shading is interpolated along)
constexpr int kMaxPieces = 8;            // per Catmull-Rom segment
constexpr float kNear = 1e-2f;           // cm; geometry closer to the eye is dropped
constexpr float kOpaque = 1.f / 1024;    // transmittance below which a pixel is done
constexpr float kHeadBias = 0.02f;       // cm; hair roots sit on the scalp
constexpr int kSamples = 4;              // head samples per pixel (2×2)
// Rim-light visibility below which the hair's rim shading is skipped: the rim's lobes weigh at
// most ~0.5, so it adds under 1/4096 of the rim's colour, a fifth of a level on dark hair.
// Inside the hair the rim's shadow map is rarely exactly 0, and this saves most of its cost.
constexpr float kRimInvisible = 1.f / 4096;
constexpr float kSampleOffsets[kSamples][2] = {
    {0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};

// A projected, shaded strand vertex. x, y pixels; z depth (cm, ≤ 0 when behind the eye);
// w width in pixels; rgb the shaded linear colour, packed.
struct HairVertex {
    float x, y, z, w;
    uint32_t rgb;
};

// Flags in HairVertex::rgb, above pack_color's 30 bits: the strand's last vertex, and a piece
// (from this vertex to the next) that the tiles do not draw.
constexpr uint32_t kLastOfStrand = 1u << 31;
constexpr uint32_t kHiddenPiece = 1u << 30;

// Linear colour in [0, 4] as three 10-bit square roots (shaded colours exceed 1 in
// highlights; the square root spends the bits where the eye needs them).
uint32_t pack_color(const Vec3f& c) {
    auto q = [](float v) {
        return static_cast<uint32_t>(std::sqrt(std::clamp(v, 0.f, 4.f) * 0.25f) * 1023.f + 0.5f);
    };
    return q(c.x()) | (q(c.y()) << 10) | (q(c.z()) << 20);
}
Vec3f unpack_color(uint32_t v) {
    auto d = [](uint32_t q) {
        const float s = static_cast<float>(q & 1023u) * (1.f / 1023.f);
        return 4.f * s * s;
    };
    return {d(v), d(v >> 10), d(v >> 20)};
}

// The sRGB encoding, rounded to 8 bits.
uint8_t srgb8_exact(float linear) {
    const float c = std::clamp(linear, 0.f, 1.f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
    return static_cast<uint8_t>(s * 255.f + 0.5f);
}

// srgb8_exact without its pow per channel (3 per pixel): `level` holds the code of
// bucket j's lower end j/4096 and `threshold[k]` the least float coded k or more (found by
// bisection over the float bits, the encoding being monotone), so a value's code is its
// bucket's plus the thresholds it passes, at most a few. The same code to the bit.
struct Srgb8Table {
    static constexpr int kBuckets = 4096;
    std::array<uint8_t, kBuckets + 1> level;
    std::array<float, 257> threshold;
    Srgb8Table() {
        for (int k = 0; k <= 256; ++k) {
            uint32_t lo = 0, hi = 0x3f800001u;  // bits of 0 and just above 1
            while (lo < hi) {
                const uint32_t mid = lo + (hi - lo) / 2;
                float f;
                std::memcpy(&f, &mid, 4);
                if (srgb8_exact(f) >= k && k <= 255)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            std::memcpy(&threshold[k], &lo, 4);  // 256: above 1, never passed
        }
        for (int j = 0; j <= kBuckets; ++j)
            level[j] = srgb8_exact(static_cast<float>(j) / kBuckets);
    }
};

uint8_t to_srgb8(float linear) {
    static const Srgb8Table table;
    const float c = std::clamp(linear, 0.f, 1.f);
    int k = table.level[static_cast<int>(c * Srgb8Table::kBuckets)];
    while (c >= table.threshold[k + 1])
        ++k;
    return static_cast<uint8_t>(k);
}

struct Lights {
    Vec3f key_dir, key_color, fill_dir, fill_color, rim_dir, rim_color, ambient;
    bool rim = false;  // rim_color is not black
};

// The shadows one directional light casts: the hair's opacity shadow map and the head's depth
// map, either absent.
struct LightShadow {
    std::unique_ptr<OpacityShadowMap> hair;
    std::unique_ptr<ShadowDepthMap> head;
    Vec3f travel = Vec3f::Zero();  // the direction the light travels (away from it)

    // Visibility of the light in [0, 1] at p (cm, head space).
    float visibility(const Vec3f& p, float bias = 0.05f) const {
        float v = 1.f;
        if (head) v *= head->visibility(p, bias);
        if (hair && v > 0.f) v *= hair->transmittance(p);
        return v;
    }
    float head_texel() const { return head ? head->texel_size() : 0.f; }

    // visibility(p) and the optical depth of the hair behind p along the light as far as the
    // head (the hair whose back-scattered light reaches p; +inf without a hair map: hair as
    // deep as it comes), from one lookup of the hair's map at p.
    float visibility_and_behind(const Vec3f& p, float& depth_behind) const {
        float v = 1.f;
        if (head) v *= head->visibility(p);
        depth_behind = 0.f;  // in the head's shadow: no light to scatter back
        if (!hair) depth_behind = std::numeric_limits<float>::infinity();
        if (!hair || v == 0.f) return v;
        const float tau = hair->optical_depth(p);
        // Beyond the hair's box the map's column is summed whole: 10 m is as far as any.
        const float d = std::min(head ? head->distance_to_surface(p) : INFINITY, 1000.f);
        depth_behind = std::max(0.f, hair->optical_depth(p + d * travel) - tau);
        return v * std::exp(-tau);
    }
};

Vec3f camera_to_world(const Camera& cam, const Vec3f& d) {
    return (d.x() * cam.right + d.y() * cam.up - d.z() * cam.forward).normalized();
}

// Tiles of the image and, for each, its items (copied, so that a tile reads only its own
// memory) in increasing source order, with a 16-bit sort key each.
template <typename Item>
struct Bins {
    int tiles_x = 0, tiles_y = 0;
    std::vector<uint64_t> offsets;  // #tiles+1 into items and keys
    std::vector<Item> items;
    std::vector<uint16_t> keys;
};

// Deterministic two-pass binning: the sources are cut into a fixed number of chunks (not
// one per thread), each chunk counts then writes its own slots of every tile, so tile lists
// come out in source order for any thread count. tiles_of(i, emit) calls
// emit(tile, key, item) for each tile that source i touches.
template <typename Item, typename TilesOf>
void bin_items(size_t sources, int tiles, TilesOf&& tiles_of, Bins<Item>& bins) {
    const size_t chunks = std::clamp<size_t>(sources / 4096, 1, 256);
    const size_t per_chunk = (sources + chunks - 1) / chunks;
    std::vector<uint32_t> counts(chunks * tiles, 0u);
    parallel_for(chunks, [&](size_t c) {
        uint32_t* count = &counts[c * tiles];
        for (size_t i = c * per_chunk; i < std::min(sources, (c + 1) * per_chunk); ++i)
            tiles_of(i, [&](int tile, uint16_t, const auto&) { ++count[tile]; });
    });
    bins.offsets.assign(tiles + 1, 0);
    std::vector<uint64_t> cursor(chunks * tiles);
    uint64_t total = 0;
    for (int t = 0; t < tiles; ++t) {
        bins.offsets[t] = total;
        for (size_t c = 0; c < chunks; ++c) {
            cursor[c * tiles + t] = total;
            total += counts[c * tiles + t];
        }
    }
    bins.offsets[tiles] = total;
    bins.items.resize(total);
    bins.keys.resize(total);
    parallel_for(chunks, [&](size_t c) {
        uint64_t* cur = &cursor[c * tiles];
        for (size_t i = c * per_chunk; i < std::min(sources, (c + 1) * per_chunk); ++i)
            tiles_of(i, [&](int tile, uint16_t key, const Item& item) {
                const uint64_t k = cur[tile]++;
                bins.items[k] = item;
                bins.keys[k] = key;
            });
    });
}

// items (#n) stably sorted by keys (#n) into sorted: two 8-bit counting-sort passes.
void sort_by_key(const uint16_t* keys, const uint32_t* items, size_t n,
                 std::vector<uint32_t>& sorted, std::vector<uint32_t>& tmp) {
    sorted.resize(n);
    tmp.resize(n);
    std::array<uint32_t, 257> count{};
    for (size_t i = 0; i < n; ++i)
        ++count[(keys[i] & 255u) + 1];
    for (int k = 0; k < 256; ++k)
        count[k + 1] += count[k];
    for (size_t i = 0; i < n; ++i)
        tmp[count[keys[i] & 255u]++] = static_cast<uint32_t>(i);
    count.fill(0);
    for (size_t i = 0; i < n; ++i)
        ++count[(keys[i] >> 8) + 1];
    for (int k = 0; k < 256; ++k)
        count[k + 1] += count[k];
    for (uint32_t i : tmp)
        sorted[count[keys[i] >> 8]++] = items[i];
}

// A straight strand piece in the image: ends (x, y) in pixels, depth z (cm), width w
// (pixels) and shaded colour (pack_color).
struct Piece {
    float x0, y0, x1, y1, z0, z1, w0, w1;
    uint32_t c0, c1;
};

struct Scene {
    const Hair* hair = nullptr;
    const Mesh* head = nullptr;
    const RenderOptions* options = nullptr;
    Camera camera;
    Lights lights;
    LightShadow key_shadow, rim_shadow;
    std::vector<uint32_t> strand_order;  // strands in Z-order of their projected middles
    float specular_floor = 0.f;          // cone cosine below which the specular term is < 1/4096
    float lobe_shadow_exponent = 0.f;    // lobe_shadow_opacity / shadow_opacity − 1, ≥ 0
    Box3 hair_box;
    std::shared_ptr<const FiberScattering> fiber;  // kFiber's tables
};

// A strand's absorption and albedos for kFiber.
struct FiberStrand {
    Vec3f sigma_a = Vec3f::Zero();
    FiberScattering::Albedo albedo;
};

// The key's visibility for the lobes as a fraction of `shadow`, its visibility for the diffuse
// term: the lobes are light scattered once, which the hair in front blocks at a fibre's full
// opacity (lobe_shadow_opacity), where the diffuse term stands for light scattered many times,
// which passes more (shadow_opacity). Both are e^−τ of the same map, so the lobes' visibility
// is shadow^(opacity ratio), shadow times this.
float lobe_shadow(const Scene& scene, float shadow) {
    return scene.lobe_shadow_exponent > 0.f ? pow_unit(shadow, scene.lobe_shadow_exponent) : 1.f;
}

// The hair's reflectance under the key light (visible fraction `shadow`), the fill light, the
// rim light (visible fraction `rim_shadow`) and ambient: the lobes of real hair (`lobes`, the
// strand's), or Kajiya-Kay.
Vec3f shade_hair(const Scene& scene, const Vec3f& p, const Vec3f& t, const Vec3f& color,
                 float shadow, float rim_shadow, const HairLobeSet& lobes,
                 const FiberStrand& fiber_strand, float key_depth_behind = INFINITY,
                 float rim_depth_behind = INFINITY) {
    const RenderOptions& o = *scene.options;
    const Lights& l = scene.lights;
    const Vec3f e = (scene.camera.eye - p).normalized();
    if (o.shading == RenderOptions::Shading::kFiber) {
        // Radiance per unit of wisp's light intensity: π times the model's (wisp's lights have
        // no 1/π: a Lambertian surface of albedo a under intensity E shows a·E·cos θ).
        const FiberScattering& fiber = *scene.fiber;
        const FiberScattering::View view = fiber.view(t, e);
        // Returns a Vec3f: deduced, it would be Eigen's expression `kPi * out`, which refers
        // to the local `out` after the lambda has returned.
        auto light = [&](const Vec3f& dir, float fibres, float behind) -> Vec3f {
            // What comes straight through the fibres in front (e^−n), and what they scatter
            // on to the point.
            const float direct = std::exp(-fibres);
            Vec3f out = fiber.multiple(view, dir, fiber_strand.albedo, fibres, behind);
            if (direct > 1.f / 4096.f) out += direct * fiber.eval(view, dir, fiber_strand.sigma_a);
            return kPi * out;
        };
        // The fibres between the point and the light, from the map's optical depth at
        // shadow_opacity per fibre (the head's shadow counted as deep hair: none arrives).
        const float key_fibres =
            -std::log(std::max(shadow, 1e-6f)) / std::max(o.shadow_opacity, 1e-3f);
        const float key_behind = key_depth_behind / std::max(o.shadow_opacity, 1e-3f);
        const float rim_behind = rim_depth_behind / std::max(o.rim_shadow_opacity, 1e-3f);
        Vec3f c = l.ambient.cwiseProduct(color) +
                  l.key_color.cwiseProduct(light(l.key_dir, key_fibres, key_behind)) +
                  // The fill casts no shadow: the hair behind is the key's.
                  l.fill_color.cwiseProduct(light(l.fill_dir, 0.f, key_behind));
        if (l.rim && rim_shadow > kRimInvisible) {
            const float rim_fibres =
                -std::log(std::max(rim_shadow, 1e-6f)) / std::max(o.rim_shadow_opacity, 1e-3f);
            c += l.rim_color.cwiseProduct(light(l.rim_dir, rim_fibres, rim_behind));
        }
        return c;
    }
    if (o.shading == RenderOptions::Shading::kHair) {
        const HairView view(t, e);  // what the three lights share
        Vec3f c = l.ambient.cwiseProduct(color) +
                  shadow * l.key_color.cwiseProduct(hair_reflectance(view, l.key_dir, color, lobes,
                                                                     lobe_shadow(scene, shadow))) +
                  l.fill_color.cwiseProduct(hair_reflectance(view, l.fill_dir, color, lobes));
        if (l.rim && rim_shadow > kRimInvisible) {
            // Kajiya-Kay's diffuse term and the shifted lobes have no azimuth: they would light
            // a strand's far side, where a back light shines, as brightly as its near side.
            HairLobeSet rim_lobes = lobes;
            rim_lobes.azimuthal = true;
            c += rim_shadow *
                 l.rim_color.cwiseProduct(hair_reflectance(view, l.rim_dir, color, rim_lobes));
        }
        return c;
    }
    const Vec3f spec_color = Vec3f::Ones() + o.specular_tint * (color - Vec3f::Ones());
    auto light = [&](const Vec3f& dir) {
        // kajiya_kay_specular, with pow skipped where its value would be invisible.
        const float cone = kajiya_kay_cone_cosine(t, dir, e);
        const float spec =
            cone > scene.specular_floor ? pow_unit(std::min(cone, 1.f), o.specular_exponent) : 0.f;
        return (o.diffuse_strength * kajiya_kay_diffuse(t, dir)) * color +
               (o.specular_strength * spec) * spec_color;
    };
    Vec3f c = l.ambient.cwiseProduct(color) + shadow * l.key_color.cwiseProduct(light(l.key_dir)) +
              l.fill_color.cwiseProduct(light(l.fill_dir));
    if (l.rim && rim_shadow > kRimInvisible)
        c += rim_shadow * l.rim_color.cwiseProduct(light(l.rim_dir));
    return c;
}

// Head data prepared for the tiles: projected vertices, smooth normals.
struct HeadGeometry {
    std::vector<Vec3f> screen;          // #V (x, y, depth)
    std::vector<Vec3f> normals;         // #V unit, area-weighted
    std::vector<uint32_t> front_faces;  // indices of faces facing the camera, all in front
};

HeadGeometry prepare_head(const Scene& scene) {
    HeadGeometry g;
    const Mesh& mesh = *scene.head;
    g.screen.resize(mesh.vertices.size());
    parallel_for(
        mesh.vertices.size(),
        [&](size_t i) { g.screen[i] = scene.camera.project(mesh.vertices[i]); }, 4096);
    g.normals = skin_normals(mesh);
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f &a = g.screen[t[0]], &b = g.screen[t[1]], &c = g.screen[t[2]];
        if (a.z() <= kNear || b.z() <= kNear || c.z() <= kNear) continue;
        // Counter-clockwise from outside is clockwise in the y-down image.
        const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        if (area < 0.f) g.front_faces.push_back(static_cast<uint32_t>(f));
    }
    return g;
}

Vec3f shade_head(const Scene& scene, const HeadGeometry& g, uint32_t face, float px, float py) {
    const Mesh& mesh = *scene.head;
    const Vec3i& t = mesh.faces[face];
    const Vec3f &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    // The point where the pixel's central ray meets the triangle's plane, and its
    // barycentrics (clamped: the pixel centre may lie just outside the triangle).
    const Vec3f dir = scene.camera.ray(px, py);
    const Vec3f n = (b - a).cross(c - a);
    const float denom = n.dot(dir);
    Vec3f p = (a + b + c) / 3.f;
    if (std::abs(denom) > 1e-12f)
        p = scene.camera.eye + dir * (n.dot(a - scene.camera.eye) / denom);
    const float nn = std::max(n.squaredNorm(), 1e-20f);
    float wa = std::max(0.f, (c - b).cross(p - b).dot(n) / nn);
    float wb = std::max(0.f, (a - c).cross(p - c).dot(n) / nn);
    float wc = std::max(0.f, (b - a).cross(p - a).dot(n) / nn);
    const float sum = wa + wb + wc;
    if (sum > 0) {
        wa /= sum;
        wb /= sum;
        wc /= sum;
    } else {
        wa = wb = wc = 1.f / 3.f;
    }
    const Vec3f normal =
        (wa * g.normals[t[0]] + wb * g.normals[t[1]] + wc * g.normals[t[2]]).normalized();
    const Lights& l = scene.lights;
    // A light's shadow is looked up off the surface along its normal, more so where the light
    // grazes it (normal-offset shadows): there a depth texel spans a long run of the faceted
    // surface, whose own depths would otherwise shadow it in stripes (acne).
    auto lit = [&](const Vec3f& dir, const LightShadow& shadow) {
        const float cosine = lambert(normal, dir);
        if (cosine <= 0.f) return 0.f;
        const float offset = 0.05f + shadow.head_texel() * (0.5f + 2.5f * (1.f - cosine));
        return cosine * shadow.visibility(p + offset * normal, 0.1f);
    };
    Vec3f light = l.ambient + lit(l.key_dir, scene.key_shadow) * l.key_color +
                  lambert(normal, l.fill_dir) * l.fill_color;
    if (l.rim) light += lit(l.rim_dir, scene.rim_shadow) * l.rim_color;
    if (mesh.colors.size() == mesh.vertices.size())
        return light.cwiseProduct(wa * mesh.colors[t[0]] + wb * mesh.colors[t[1]] +
                                  wc * mesh.colors[t[2]]);
    return light.cwiseProduct(scene.options->skin_color);
}

// The head's samples in one tile: per sample the nearest front face and its depth (1/z
// interpolated); +inf and -1 where a sample sees no head. sample_depth, sample_face
// #kTile²·kSamples, sample s of pixel (x, y) of the tile at ((y·kTile + x)·kSamples + s).
void rasterize_head_tile(const Scene& scene, const HeadGeometry& head,
                         const Bins<uint32_t>& head_bins, int tile, float* sample_depth,
                         int32_t* sample_face) {
    const RenderOptions& o = *scene.options;
    const int tx = tile % head_bins.tiles_x, ty = tile / head_bins.tiles_x;
    const int x0 = tx * kTile, y0 = ty * kTile;
    const int x1 = std::min(x0 + kTile, o.width), y1 = std::min(y0 + kTile, o.height);
    std::fill_n(sample_depth, kTile * kTile * kSamples, std::numeric_limits<float>::infinity());
    std::fill_n(sample_face, kTile * kTile * kSamples, -1);
    if (!scene.head) return;
    for (uint64_t e = head_bins.offsets[tile]; e < head_bins.offsets[tile + 1]; ++e) {
        const uint32_t f = head_bins.items[e];
        const Vec3i& t = scene.head->faces[f];
        const Vec3f &a = head.screen[t[0]], &b = head.screen[t[1]], &c = head.screen[t[2]];
        const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        const float inv = 1.f / area;
        const int bx0 = std::max(x0, floor_to_int(std::min({a.x(), b.x(), c.x()})));
        const int bx1 = std::min(x1 - 1, floor_to_int(std::max({a.x(), b.x(), c.x()})));
        const int by0 = std::max(y0, floor_to_int(std::min({a.y(), b.y(), c.y()})));
        const int by1 = std::min(y1 - 1, floor_to_int(std::max({a.y(), b.y(), c.y()})));
        const float iza = 1.f / a.z(), izb = 1.f / b.z(), izc = 1.f / c.z();
        for (int y = by0; y <= by1; ++y)
            for (int x = bx0; x <= bx1; ++x)
                for (int s = 0; s < kSamples; ++s) {
                    const float px = x + kSampleOffsets[s][0], py = y + kSampleOffsets[s][1];
                    const float wa =
                        ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) * inv;
                    const float wb =
                        ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) * inv;
                    const float wc = 1.f - wa - wb;
                    if (wa < 0.f || wb < 0.f || wc < 0.f) continue;
                    const float z = 1.f / (wa * iza + wb * izb + wc * izc);
                    const size_t k = ((y - y0) * kTile + (x - x0)) * kSamples + s;
                    if (z < sample_depth[k]) {
                        sample_depth[k] = z;
                        sample_face[k] = static_cast<int32_t>(f);
                    }
                }
    }
}

// Per 8×8-pixel block of the image, the farthest depth that hair must be in front of to show
// in it: its farthest head sample + kHeadBias, +inf where a sample sees no head (pass 3, before
// the strands, so that the strands pass can skip the hair the head hides). The tiles
// rasterize the head again rather than keep every sample (32 MB at 1024², gigabytes at the
// largest sizes): it costs 2% of a render at 1024².
constexpr int kBlock = 8;  // pixels
struct HeadBlocks {
    int blocks_x = 0, blocks_y = 0;
    std::vector<float> far;  // #blocks_y·blocks_x; empty without a head
};

HeadBlocks head_blocks(const Scene& scene, const HeadGeometry& head,
                       const Bins<uint32_t>& head_bins) {
    HeadBlocks out;
    if (!scene.head) return out;
    const RenderOptions& o = *scene.options;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr int kTileBlocks = kTile / kBlock;
    const int tiles = head_bins.tiles_x * head_bins.tiles_y;
    out.blocks_x = head_bins.tiles_x * kTileBlocks;
    out.blocks_y = head_bins.tiles_y * kTileBlocks;
    out.far.assign(static_cast<size_t>(out.blocks_x) * out.blocks_y, kInf);
    parallel_for(static_cast<size_t>(tiles), [&](size_t tile_index) {
        const int tile = static_cast<int>(tile_index);
        if (head_bins.offsets[tile] == head_bins.offsets[tile + 1]) return;  // no head: +inf
        const int tx = tile % head_bins.tiles_x, ty = tile / head_bins.tiles_x;
        const int x0 = tx * kTile, y0 = ty * kTile;
        const int x1 = std::min(x0 + kTile, o.width), y1 = std::min(y0 + kTile, o.height);
        std::array<float, kTile * kTile * kSamples> sample_depth;
        std::array<int32_t, kTile * kTile * kSamples> sample_face;
        rasterize_head_tile(scene, head, head_bins, tile, sample_depth.data(), sample_face.data());
        // Blocks: only their pixels inside the image count.
        for (int by = 0; by < kTileBlocks; ++by)
            for (int bx = 0; bx < kTileBlocks; ++bx) {
                float far = -kInf;
                for (int y = y0 + by * kBlock; y < std::min(y0 + (by + 1) * kBlock, y1); ++y)
                    for (int x = x0 + bx * kBlock; x < std::min(x0 + (bx + 1) * kBlock, x1); ++x)
                        for (int s = 0; s < kSamples; ++s)
                            far = std::max(
                                far, sample_depth[((y - y0) * kTile + (x - x0)) * kSamples + s]);
                out.far[static_cast<size_t>(ty * kTileBlocks + by) * out.blocks_x +
                        tx * kTileBlocks + bx] = far + kHeadBias;
            }
    });
    return out;
}

// Whether the head hides every pixel that the piece from a to b may touch (the box of its ends
// widened by its width and a pixel, as the tiles test it): hair at or behind the farthest head
// sample of a pixel adds nothing to it (render_tile's depth test), so the piece's colour is
// never needed. The depths' minimum is lowered by 10⁻⁵ of itself against rounding in the
// tiles' interpolation.
bool hidden_by_head(const HeadBlocks& head, const HairVertex& a, const HairVertex& b, int width,
                    int height) {
    if (head.far.empty()) return false;
    const float r = std::max(a.w, b.w) + 1.f;
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const float lx = std::min(a.x, b.x) - r, hx = std::max(a.x, b.x) + r;
    const float ly = std::min(a.y, b.y) - r, hy = std::max(a.y, b.y) + r;
    if (hx < 0.f || hy < 0.f || lx >= w || ly >= h) return true;  // off the image
    const int bx0 = floor_to_int(std::max(lx, 0.f)) / kBlock;
    const int bx1 = floor_to_int(std::min(hx, w - 1.f)) / kBlock;
    const int by0 = floor_to_int(std::max(ly, 0.f)) / kBlock;
    const int by1 = floor_to_int(std::min(hy, h - 1.f)) / kBlock;
    const float z = std::min(a.z, b.z) * (1.f - 1e-5f);
    for (int by = by0; by <= by1; ++by)
        for (int bx = bx0; bx <= bx1; ++bx)
            if (z < head.far[static_cast<size_t>(by) * head.blocks_x + bx]) return false;
    return true;
}

// Pass 3: strand pieces. Strands are laid out in scene.strand_order (neighbours on screen
// next to each other in memory, so that a tile's pieces are gathered from a few runs):
// strand strand_order[k] owns vertices [first_vertex[k], first_vertex[k + 1]).
size_t tessellate_strands(const Scene& scene, const HeadBlocks& head,
                          std::vector<HairVertex>& vertices, std::vector<uint32_t>& first_vertex) {
    const Hair& hair = *scene.hair;
    const RenderOptions& o = *scene.options;
    const Camera& cam = scene.camera;
    const size_t strands = hair.strand_count();
    // Pieces per segment: enough for the pieces to follow the curve within kFlatness pixels
    // and be at most kMaxPiecePixels long, so that straight or distant hair costs little.
    // The curve's distance from its chord is bounded by that of its Bézier control points
    // b1 = p1 + (p2 - p0) / 6 and b2 = p2 - (p3 - p1) / 6 (convex hull); m pieces divide it
    // by about m².
    std::vector<uint8_t> pieces(hair.point_count(), 1);
    std::vector<uint32_t> counts(strands + 1, 0);
    parallel_for(
        strands,
        [&](size_t s) {
            const std::span<const Vec3f> p = hair.strand(s);
            thread_local std::vector<Vec3f> q;
            q.resize(p.size());
            bool visible = true;
            for (size_t i = 0; i < p.size(); ++i) {
                q[i] = cam.project(p[i]);
                visible = visible && q[i].z() > kNear;
            }
            uint32_t n = p.empty() ? 0 : 1;
            for (size_t i = 0; i + 1 < p.size(); ++i) {
                int m = 1;
                if (visible) {
                    const Vec2f b(q[i].x(), q[i].y()), c(q[i + 1].x(), q[i + 1].y());
                    const Vec2f a = i > 0 ? Vec2f(q[i - 1].x(), q[i - 1].y()) : Vec2f(2 * b - c);
                    const Vec2f d =
                        i + 2 < p.size() ? Vec2f(q[i + 2].x(), q[i + 2].y()) : Vec2f(2 * c - b);
                    const Vec2f chord = c - b;
                    const float len = chord.norm();
                    const Vec2f b1 = (c - a) / 6.f, b2 = (b - d) / 6.f;  // offsets from b, c
                    float dev;
                    if (len > 1e-6f) {
                        const Vec2f nrm(-chord.y() / len, chord.x() / len);
                        dev = std::max(std::abs(b1.dot(nrm)), std::abs(b2.dot(nrm)));
                    } else {
                        dev = std::max(b1.norm(), b2.norm());
                    }
                    const float by_bend = std::sqrt(dev / kFlatness);
                    const float by_length = len / kMaxPiecePixels;
                    m = std::clamp(ceil_to_int(std::max(by_bend, by_length)), 1, kMaxPieces);
                }
                pieces[hair.offsets[s] + i] = static_cast<uint8_t>(m);
                n += static_cast<uint32_t>(m);
            }
            counts[s + 1] = n;
        },
        256);
    first_vertex.assign(strands + 1, 0);
    for (size_t k = 0; k < strands; ++k)
        first_vertex[k + 1] = first_vertex[k] + counts[scene.strand_order[k] + 1];
    vertices.resize(first_vertex[strands]);
    const float tip = hair.widths.empty() ? o.tip_width : 1.f;
    const HairLobeSet base_lobes(o.hair);
    const LightShadow& key = scene.key_shadow;
    const LightShadow& rim_light = scene.rim_shadow;
    const bool rim = scene.lights.rim;
    std::atomic<size_t> hidden_pieces{0};
    parallel_for(
        strands,
        [&](size_t k_order) {
            const size_t s = scene.strand_order[k_order];
            // Each strand's secondary highlight varies a little (its sparkle), and so do its
            // brightness and width, by hashes of its index: the same at any thread count.
            auto uniform = [s](uint64_t salt) {
                return static_cast<float>(mix64(salt ^ s) >> 40) * (2.f / 16777216.f) - 1.f;
            };
            const float variation = uniform(0x5b4c1e);
            const Vec3f color =
                (hair.color_of(s) * (1.f + o.strand_brightness * uniform(0x7a3d91f2c4e5b6a7)))
                    .cwiseMin(1.f);
            FiberStrand fiber_strand;
            if (scene.fiber) {
                // The colour as the melanin that makes it: the absorption of those pigments.
                fiber_strand.sigma_a =
                    melanin_absorption(melanin_from_color(color, o.fiber.beta_n));
                fiber_strand.albedo = scene.fiber->albedo(fiber_strand.sigma_a);
            }
            const float width_scale =
                o.width_scale * (1.f + o.strand_width * uniform(0x3c6ef372fe94f82b));
            const std::span<const Vec3f> p = hair.strand(s);
            const uint32_t first = first_vertex[k_order];
            const uint8_t* m = &pieces[hair.offsets[s]];
            // The strand's samples, projected: the vertices of its pieces.
            thread_local std::vector<StrandSample> samples;
            samples.clear();
            for_each_strand_sample(
                hair, s, width_scale, tip,
                [&](size_t i, const Vec3f&, const Vec3f&) { return static_cast<int>(m[i]); },
                [&](const StrandSample& sample) { samples.push_back(sample); });
            const size_t n = samples.size();
            HairVertex* v = &vertices[first];
            for (size_t j = 0; j < n; ++j) {
                const Vec3f q = cam.project(samples[j].p);
                v[j] = HairVertex{q.x(), q.y(), q.z(), 0.f, 0u};
                if (q.z() > kNear) v[j].w = samples[j].width * cam.focal_pixels / q.z();
            }
            // Pieces the tiles will not draw (behind the eye, or hidden by the head) are
            // flagged, and a vertex that starts or ends no drawn piece is not shaded: its colour
            // is never read.
            size_t hidden = 0;
            for (size_t j = 0; j + 1 < n; ++j)
                if (v[j].z <= kNear || v[j + 1].z <= kNear ||
                    hidden_by_head(head, v[j], v[j + 1], o.width, o.height)) {
                    v[j].rgb = kHiddenPiece;
                    ++hidden;
                }
            if (hidden == n - 1 && n > 0) {
                hidden_pieces += hidden;
                v[n - 1].rgb |= kLastOfStrand;
                return;
            }
            hidden_pieces += hidden;
            const HairLobeSet lobes =
                base_lobes.with_sparkle(o.hair, variation, uniform(0x9e3779b97f4a7c15));
            // Shadows change slowly along a strand: looked up at the control points and
            // interpolated in between; the rim's, from its coarser maps, at every other control
            // point (and the tip). Each is looked up once, when a shaded vertex first needs it.
            int segment = -1;
            float shadow0 = 1.f, shadow1 = 1.f;
            int rim_a = -1, rim_b = -1;  // control points of the rim's current span
            float rim0 = 1.f, rim1 = 1.f, rim_scale = 1.f;
            // For the fibre model, the hair's depth behind each point along the key and the rim
            // light, looked up beside their shadows.
            const bool behind = scene.fiber && o.shadows;
            float behind0 = INFINITY, behind1 = INFINITY, rim_behind0 = INFINITY,
                  rim_behind1 = INFINITY;
            const int last = static_cast<int>(p.size()) - 1;
            for (size_t j = 0; j < n; ++j) {
                if (v[j].z <= kNear) continue;
                const bool drawn = (j + 1 < n && !(v[j].rgb & kHiddenPiece)) ||
                                   (j > 0 && !(v[j - 1].rgb & kHiddenPiece));
                if (!drawn) continue;
                const StrandSample& sample = samples[j];
                if (sample.segment != segment) {
                    // The lights' visibility (and for the fibre model, the hair behind).
                    auto look = [&](const LightShadow& light, const Vec3f& q, float& depth) {
                        return behind ? light.visibility_and_behind(q, depth) : light.visibility(q);
                    };
                    if (!(sample.segment == segment + 1 && segment >= 0)) {
                        shadow1 = look(key, p[sample.segment], behind1);
                    }
                    shadow0 = shadow1;
                    behind0 = behind1;
                    segment = sample.segment;
                    if (p.size() > 1) shadow1 = look(key, p[segment + 1], behind1);
                    if (rim && (rim_a < 0 || segment < rim_a || segment >= rim_b)) {
                        const int a = segment & ~1, b = std::min(a + 2, last);
                        if (!(a == rim_b && rim_a >= 0)) rim1 = look(rim_light, p[a], rim_behind1);
                        rim0 = rim1;
                        rim_behind0 = rim_behind1;
                        if (b > a) rim1 = look(rim_light, p[b], rim_behind1);
                        rim_a = a;
                        rim_b = b;
                        rim_scale = 1.f / static_cast<float>(std::max(1, b - a));
                    }
                }
                const float shadow = shadow0 + (shadow1 - shadow0) * sample.u;
                const float rim_u = (static_cast<float>(segment - rim_a) + sample.u) * rim_scale;
                const float rim_shadow = rim0 + (rim1 - rim0) * rim_u;
                // Interpolated where both ends are finite (hair within the maps).
                auto lerp = [](float a, float b, float u) {
                    return std::isinf(a) || std::isinf(b) ? std::min(a, b) : a + (b - a) * u;
                };
                v[j].rgb |= pack_color(roll_off_highlights(shade_hair(
                    scene, sample.p, sample.t, color, shadow, rim_shadow, lobes, fiber_strand,
                    lerp(behind0, behind1, sample.u), lerp(rim_behind0, rim_behind1, rim_u))));
            }
            if (n > 0) v[n - 1].rgb |= kLastOfStrand;
        },
        64);
    return hidden_pieces;
}

struct TileCounters {
    size_t fragments = 0;
};

// Pass 5 for one tile.
void render_tile(const Scene& scene, const HeadGeometry& head, const Bins<uint32_t>& head_bins,
                 const std::vector<HairVertex>& vertices, const Bins<uint32_t>& hair_bins, int tile,
                 RgbImage& image, uint8_t* alpha, TileCounters& counters) {
    const RenderOptions& o = *scene.options;
    const int tx = tile % hair_bins.tiles_x, ty = tile / hair_bins.tiles_x;
    const int x0 = tx * kTile, y0 = ty * kTile;
    const int x1 = std::min(x0 + kTile, o.width), y1 = std::min(y0 + kTile, o.height);

    // The head's samples and, per pixel, the nearest and farthest sample depths for the hair's
    // quick depth test.
    std::array<float, kTile * kTile * kSamples> sample_depth;
    std::array<int32_t, kTile * kTile * kSamples> sample_face;
    rasterize_head_tile(scene, head, head_bins, tile, sample_depth.data(), sample_face.data());
    std::array<float, kTile * kTile> near_head, far_head;
    for (int p = 0; p < kTile * kTile; ++p) {
        const float* d = &sample_depth[p * kSamples];
        near_head[p] = std::min({d[0], d[1], d[2], d[3]}) + kHeadBias;
        far_head[p] = std::max({d[0], d[1], d[2], d[3]}) + kHeadBias;
    }

    // Hair: pieces nearest first, composited under what is in front (Porter-Duff "under"),
    // each pixel closed once its transmittance drops below kOpaque.
    std::array<float, kTile * kTile * 3> accum;
    std::array<float, kTile * kTile> trans;
    accum.fill(0.f);
    trans.fill(1.f);
    int open = (x1 - x0) * (y1 - y0);
    // Bit x of open_row[y] is set while pixel (x0 + x, y0 + y) is not yet opaque: a piece
    // whose pixels are all closed is skipped before it is rasterized (in the middle of a dense
    // layer, most are), which changes nothing in the picture.
    std::array<uint32_t, kTile> open_row{};
    for (int y = 0; y < y1 - y0; ++y)
        open_row[y] = static_cast<uint32_t>((uint64_t{1} << (x1 - x0)) - 1);
    thread_local std::vector<uint32_t> order, scratch;
    const uint64_t begin = hair_bins.offsets[tile], end = hair_bins.offsets[tile + 1];
    sort_by_key(&hair_bins.keys[begin], &hair_bins.items[begin], end - begin, order, scratch);
    const float opacity = std::clamp(o.hair_opacity, 0.f, 1.f);
    size_t fragments = 0;
    const size_t count = order.size();
    for (size_t k = 0; k < count; ++k) {
        if (open == 0) break;
        // Pieces are read in depth order, scattered in memory: fetch ahead.
        if (k + 16 < count) {
            const HairVertex* ahead = &vertices[order[k + 16]];
            __builtin_prefetch(ahead);
            __builtin_prefetch(ahead + 1);
        }
        const HairVertex& v0 = vertices[order[k]];
        const HairVertex& v1 = (&v0)[1];
        {
            // The piece's pixels: its ends' box widened by its width (rasterize_strand_piece
            // reaches width / cos(slope) / 2 < 0.71 width across the line) and a pixel.
            const float r = std::max(v0.w, v1.w) + 1.f;
            const int px0 = std::max(0, floor_to_int(std::min(v0.x, v1.x) - r) - x0);
            const int px1 = std::min(x1 - x0 - 1, floor_to_int(std::max(v0.x, v1.x) + r) - x0);
            const int py0 = std::max(0, floor_to_int(std::min(v0.y, v1.y) - r) - y0);
            const int py1 = std::min(y1 - y0 - 1, floor_to_int(std::max(v0.y, v1.y) + r) - y0);
            if (px0 > px1 || py0 > py1) continue;
            const uint32_t columns =
                static_cast<uint32_t>(((uint64_t{2} << px1) - 1) & ~((uint64_t{1} << px0) - 1));
            uint32_t any = 0;
            for (int y = py0; y <= py1; ++y)
                any |= open_row[y];
            if ((any & columns) == 0) continue;
        }
        const Piece piece{v0.x, v0.y, v1.x, v1.y, v0.z, v1.z, v0.w, v1.w, v0.rgb, v1.rgb};
        const Vec3f c0 = unpack_color(piece.c0), dc = unpack_color(piece.c1) - c0;
        const float z0 = piece.z0, dz = piece.z1 - piece.z0;
        rasterize_strand_piece(piece.x0, piece.y0, piece.w0, piece.x1, piece.y1, piece.w1, x0, y0,
                               x1, y1, [&](int x, int y, float t, float coverage) {
                                   const int p = (y - y0) * kTile + (x - x0);
                                   float& tr = trans[p];
                                   if (tr < kOpaque) return;
                                   const float z = z0 + dz * t;
                                   float alpha = coverage * opacity;
                                   if (z >= near_head[p]) {
                                       if (z >= far_head[p]) return;
                                       int visible = 0;
                                       for (int s = 0; s < kSamples; ++s)
                                           visible +=
                                               z < sample_depth[p * kSamples + s] + kHeadBias;
                                       alpha *= visible * (1.f / kSamples);
                                   }
                                   const float w = tr * alpha;
                                   accum[3 * p] += w * (c0.x() + dc.x() * t);
                                   accum[3 * p + 1] += w * (c0.y() + dc.y() * t);
                                   accum[3 * p + 2] += w * (c0.z() + dc.z() * t);
                                   tr -= w;
                                   ++fragments;
                                   if (tr < kOpaque) {
                                       --open;
                                       open_row[y - y0] &= ~(1u << (x - x0));
                                   }
                               });
    }
    counters.fragments += fragments;

    // Resolve: what the hair lets through shows the head's samples (each face shaded once
    // per pixel, at the pixel centre) or the background. With `alpha`, the background is left
    // out: the pixel's coverage (hair and head) goes to alpha and its colour is divided by it.
    const Vec3f background = alpha ? Vec3f::Zero() : o.background;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const int p = (y - y0) * kTile + (x - x0);
            Vec3f under = Vec3f::Zero();
            const int32_t* f = &sample_face[p * kSamples];
            if (trans[p] >= kOpaque) {
                std::array<Vec3f, kSamples> shaded;
                for (int s = 0; s < kSamples; ++s) {
                    if (f[s] < 0) {
                        shaded[s] = background;
                        continue;
                    }
                    int same = -1;
                    for (int r = 0; r < s && same < 0; ++r)
                        if (f[r] == f[s]) same = r;
                    shaded[s] =
                        same >= 0
                            ? shaded[same]
                            : roll_off_highlights(shade_head(
                                  scene, head, static_cast<uint32_t>(f[s]), x + 0.5f, y + 0.5f));
                }
                for (const Vec3f& c : shaded)
                    under += c;
                under *= trans[p] / kSamples;
            }
            const size_t pixel = static_cast<size_t>(y) * o.width + x;
            Vec3f color(accum[3 * p] + under.x(), accum[3 * p + 1] + under.y(),
                        accum[3 * p + 2] + under.z());
            if (alpha) {
                int empty = 0;
                for (int s = 0; s < kSamples; ++s)
                    empty += f[s] < 0;
                const float cover = std::clamp(1.f - trans[p] * empty / kSamples, 0.f, 1.f);
                const uint8_t a = static_cast<uint8_t>(std::lround(cover * 255.f));
                alpha[pixel] = a;
                color = a > 0 ? Vec3f(color / cover) : Vec3f::Zero();
            }
            uint8_t* out = &image.rgb[pixel * 3];
            out[0] = to_srgb8(color.x());
            out[1] = to_srgb8(color.y());
            out[2] = to_srgb8(color.z());
        }
}

}  // namespace

Vec3f roll_off_highlights(const Vec3f& linear) {
    const float m = linear.maxCoeff();
    if (!(m > kHighlightKnee)) return linear;
    // x ↦ r·x / (x + r) above the knee: slope 1 there, approaching r far above, so highlights
    // a few times brighter than the display still differ.
    constexpr float r = 1.f - kHighlightKnee;
    const float x = m - kHighlightKnee;
    const float shoulder = kHighlightKnee + r * x / (x + r);
    return linear * (shoulder / m);
}

const std::vector<std::string>& shading_names() {
    static const std::vector<std::string> names{"hair", "fiber", "kajiya-kay"};
    return names;
}

RenderOptions::Shading parse_shading(const std::string& name) {
    using S = RenderOptions::Shading;
    if (name == "hair") return S::kHair;
    if (name == "fiber") return S::kFiber;
    if (name == "kajiya-kay") return S::kKajiyaKay;
    std::string names;
    for (const std::string& n : shading_names())
        names += (names.empty() ? "" : ", ") + n;
    fail("shading: unknown model '", name, "' (one of ", names, ")");
}

Box3 framing_bounds(const Hair& hair, const Mesh* head) {
    const Box3 hair_box = hair.bounds();
    Box3 box = hair_box;
    if (head && !head->vertices.empty()) {
        // Down to 4 cm below the hair, and at least to the chin: a head is 22–24 cm from crown
        // to chin, so 26 cm below the mesh's top frames the face under short hair too.
        float head_top = -INFINITY;
        for (const Vec3f& v : head->vertices)
            head_top = std::max(head_top, v.y());
        const float floor_y =
            hair_box.empty() ? -INFINITY : std::min(hair_box.lo.y() - 4.f, head_top - 26.f);
        for (const Vec3f& v : head->vertices)
            if (v.y() >= floor_y) box.extend(v);
    }
    return box;
}

Camera render_camera(const Hair& hair, const Mesh* head, const RenderOptions& o) {
    if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
        fail("render: image size ", o.width, "x", o.height, " is outside 1..16384");
    if (o.look_at)
        return look_at(o.look_at->eye, o.look_at->target, o.look_at->up, o.fov_y_degrees, o.width,
                       o.height);
    Box3 box = framing_bounds(hair, head);
    if (box.empty()) box.extend(Vec3f::Zero());
    return frame_view(o.view, box, o.width, o.height, o.fov_y_degrees);
}

RgbImage render(const Hair& hair, const Mesh* head, const RenderOptions& o, RenderStats* stats,
                std::vector<uint8_t>* alpha) {
    RenderStats local;
    RenderStats& st = stats ? *stats : local;
    st = RenderStats{};
    Stopwatch clock;
    auto lap = [&](const char* name) {
        st.stages.emplace_back(name, clock.ms());
        clock = Stopwatch();
    };

    Scene scene;
    scene.hair = &hair;
    scene.head = head && !head->faces.empty() ? head : nullptr;
    scene.options = &o;
    scene.camera = render_camera(hair, scene.head, o);
    scene.hair_box = hair.bounds();
    scene.lights.key_dir = camera_to_world(scene.camera, o.key.direction);
    scene.lights.key_color = o.key.color;
    scene.lights.fill_dir = camera_to_world(scene.camera, o.fill.direction);
    scene.lights.fill_color = o.fill.color;
    scene.lights.rim_dir = camera_to_world(scene.camera, o.rim.direction);
    scene.lights.rim_color = o.rim.color;
    scene.lights.rim = o.rim.color.maxCoeff() > 0.f;
    scene.lights.ambient = o.ambient;
    scene.lobe_shadow_exponent = o.shadow_opacity > 0.f
                                     ? std::max(0.f, o.lobe_shadow_opacity / o.shadow_opacity - 1.f)
                                     : 0.f;
    scene.specular_floor = std::pow(1.f / 4096.f, 1.f / std::max(o.specular_exponent, 1e-3f));
    if (o.shading == RenderOptions::Shading::kFiber) scene.fiber = fiber_scattering(o.fiber);
    lap("camera");

    if (o.shadows) {
        Box3 all = scene.hair_box;
        if (scene.head) all.extend(scene.head->bounds());
        auto cast = [&](const Vec3f& dir, int resolution, int slices, float opacity, int stride,
                        int head_resolution, LightShadow& out) {
            const LightFrame frame = LightFrame::towards(dir);
            out.travel = frame.w;
            if (hair.point_count() > 0) {
                OpacityShadowMapOptions so;
                so.resolution = resolution;
                so.slices = slices;
                so.strand_opacity = opacity;
                so.strand_stride = stride;
                so.width_scale = o.width_scale;
                so.tip_width = hair.widths.empty() ? o.tip_width : 1.f;
                out.hair = std::make_unique<OpacityShadowMap>(hair, frame, scene.hair_box, so);
            }
            if (scene.head)
                out.head =
                    std::make_unique<ShadowDepthMap>(*scene.head, frame, all, head_resolution);
        };
        cast(scene.lights.key_dir, o.shadow_resolution, o.shadow_slices, o.shadow_opacity, 1, 512,
             scene.key_shadow);
        if (scene.lights.rim)
            cast(scene.lights.rim_dir, o.rim_shadow_resolution, o.rim_shadow_slices,
                 o.rim_shadow_opacity, o.rim_shadow_stride, 256, scene.rim_shadow);
    }
    lap("shadows");

    HeadGeometry head_geometry;
    if (scene.head) head_geometry = prepare_head(scene);
    // Depth keys: 16 bits over the depth range of the framed box.
    Box3 box = scene.hair_box;
    if (scene.head) box.extend(scene.head->bounds());
    float z_lo = INFINITY, z_hi = -INFINITY;
    for (int k = 0; k < 8; ++k) {
        const float z = (box.corner(k) - scene.camera.eye).dot(scene.camera.forward);
        z_lo = std::min(z_lo, z);
        z_hi = std::max(z_hi, z);
    }
    z_lo = std::max(z_lo, kNear);
    const float key_scale = 65535.f / std::max(z_hi - z_lo, 1e-3f);

    Bins<uint32_t> hair_bins, head_bins;
    hair_bins.tiles_x = head_bins.tiles_x = (o.width + kTile - 1) / kTile;
    hair_bins.tiles_y = head_bins.tiles_y = (o.height + kTile - 1) / kTile;
    const int tiles = hair_bins.tiles_x * hair_bins.tiles_y;
    const float width_f = static_cast<float>(o.width), height_f = static_cast<float>(o.height);
    auto tile_range = [&](float lx, float ly, float hx, float hy, auto&& visit) {
        if (hx < 0.f || hy < 0.f || lx >= width_f || ly >= height_f) return;
        const int tx0 = std::max(0, static_cast<int>(lx) / kTile);
        const int ty0 = std::max(0, static_cast<int>(ly) / kTile);
        const int tx1 = std::min(hair_bins.tiles_x - 1, static_cast<int>(hx) / kTile);
        const int ty1 = std::min(hair_bins.tiles_y - 1, static_cast<int>(hy) / kTile);
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx)
                visit(ty * hair_bins.tiles_x + tx);
    };
    if (scene.head) {
        bin_items(
            head_geometry.front_faces.size(), tiles,
            [&](size_t i, auto&& emit) {
                const uint32_t f = head_geometry.front_faces[i];
                const Vec3i& t = scene.head->faces[f];
                const Vec3f &a = head_geometry.screen[t[0]], &b = head_geometry.screen[t[1]],
                            &c = head_geometry.screen[t[2]];
                tile_range(std::min({a.x(), b.x(), c.x()}), std::min({a.y(), b.y(), c.y()}),
                           std::max({a.x(), b.x(), c.x()}), std::max({a.y(), b.y(), c.y()}),
                           [&](int tile) { emit(tile, uint16_t{0}, f); });
            },
            head_bins);
    } else {
        head_bins.offsets.assign(tiles + 1, 0);
    }
    const HeadBlocks head_blocks_far = head_blocks(scene, head_geometry, head_bins);
    lap("head");

    std::vector<HairVertex> vertices;
    std::vector<uint32_t> first_vertex;
    {
        std::vector<Vec2f> middle(hair.strand_count());
        parallel_for(
            middle.size(),
            [&](size_t s) {
                const std::span<const Vec3f> p = hair.strand(s);
                const Vec3f q = p.empty() ? Vec3f::Zero() : scene.camera.project(p[p.size() / 2]);
                middle[s] = Vec2f(q.x(), q.y());
            },
            4096);
        scene.strand_order = morton_order(middle);
    }
    const size_t hidden_pieces = tessellate_strands(scene, head_blocks_far, vertices, first_vertex);
    lap("strands");

    // A piece joins vertex i to i + 1; a strand's last vertex starts none. Each piece's depth
    // key and tile rectangle are found once, for bin_items' two passes to read.
    const size_t strands = hair.strand_count();
    struct PieceTiles {
        uint16_t key = 0, tx0 = 1, ty0 = 0, tx1 = 0, ty1 = 0;  // none: tx0 > tx1
    };
    std::vector<PieceTiles> piece_tiles(vertices.size());
    parallel_for(
        vertices.size(),
        [&](size_t i) {
            if (i + 1 >= vertices.size()) return;
            const HairVertex& a = vertices[i];
            const HairVertex& b = vertices[i + 1];
            if (a.rgb & (kLastOfStrand | kHiddenPiece)) return;
            if (a.z <= kNear || b.z <= kNear) return;
            const float r = 0.5f * std::max({a.w, b.w, 1.f}) + 1.f;
            const float lx = std::min(a.x, b.x) - r, ly = std::min(a.y, b.y) - r;
            const float hx = std::max(a.x, b.x) + r, hy = std::max(a.y, b.y) + r;
            if (hx < 0.f || hy < 0.f || lx >= width_f || ly >= height_f) return;
            const float zm = 0.5f * (a.z + b.z);
            PieceTiles& p = piece_tiles[i];
            p.key = static_cast<uint16_t>(std::clamp((zm - z_lo) * key_scale, 0.f, 65535.f));
            p.tx0 = static_cast<uint16_t>(std::max(0, static_cast<int>(lx) / kTile));
            p.ty0 = static_cast<uint16_t>(std::max(0, static_cast<int>(ly) / kTile));
            p.tx1 = static_cast<uint16_t>(
                std::min(hair_bins.tiles_x - 1, static_cast<int>(std::min(hx, width_f)) / kTile));
            p.ty1 = static_cast<uint16_t>(
                std::min(hair_bins.tiles_y - 1, static_cast<int>(std::min(hy, height_f)) / kTile));
        },
        4096);
    bin_items(
        vertices.size(), tiles,
        [&](size_t i, auto&& emit) {
            const PieceTiles& p = piece_tiles[i];
            const uint32_t piece = static_cast<uint32_t>(i);
            for (int ty = p.ty0; ty <= p.ty1; ++ty)
                for (int tx = p.tx0; tx <= p.tx1; ++tx)
                    emit(ty * hair_bins.tiles_x + tx, p.key, piece);
        },
        hair_bins);
    const size_t pieces = vertices.size() - std::min(vertices.size(), strands);
    lap("bin");

    RgbImage image;
    image.width = o.width;
    image.height = o.height;
    image.rgb.assign(static_cast<size_t>(o.width) * o.height * 3, 0);
    uint8_t* alpha_out = nullptr;
    if (alpha) {
        alpha->assign(static_cast<size_t>(o.width) * o.height, 0);
        alpha_out = alpha->data();
    }
    std::vector<TileCounters> counters(tiles);
    parallel_for(static_cast<size_t>(tiles), [&](size_t t) {
        render_tile(scene, head_geometry, head_bins, vertices, hair_bins, static_cast<int>(t),
                    image, alpha_out, counters[t]);
    });
    lap("tiles");

    for (const TileCounters& c : counters)
        st.fragments += c.fragments;
    st.tile_entries = hair_bins.items.size();
    st.head_triangles = head_geometry.front_faces.size();
    st.pieces = pieces;
    st.hidden_pieces = hidden_pieces;
    return image;
}

RgbImage contact_sheet(const Hair& hair, const Mesh* head, const std::vector<std::string>& views,
                       const RenderOptions& options,
                       const std::function<void(int, const std::string&)>& on_view) {
    if (views.empty()) fail("contact sheet: no views");
    const int n = static_cast<int>(views.size());
    const int columns = n <= 3 ? n : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    const int rows = (n + columns - 1) / columns;
    RgbImage sheet;
    sheet.width = columns * options.width;
    sheet.height = rows * options.height;
    sheet.rgb.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 0);
    const uint8_t bg[3] = {to_srgb8(options.background.x()), to_srgb8(options.background.y()),
                           to_srgb8(options.background.z())};
    for (size_t i = 0; i < sheet.rgb.size(); ++i)
        sheet.rgb[i] = bg[i % 3];
    for (int v = 0; v < n; ++v) {
        RenderOptions o = options;
        o.view = views[v];
        o.look_at.reset();
        const RgbImage img = render(hair, head, o);
        const int cx = (v % columns) * options.width, cy = (v / columns) * options.height;
        for (int y = 0; y < img.height; ++y)
            std::copy_n(&img.rgb[static_cast<size_t>(y) * img.width * 3], img.width * 3,
                        &sheet.rgb[(static_cast<size_t>(cy + y) * sheet.width + cx) * 3]);
        if (on_view) on_view(v + 1, views[v]);
    }
    return sheet;
}

}  // namespace wisp
