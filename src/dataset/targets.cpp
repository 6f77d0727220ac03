#include "dataset/targets.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/catmull_rom.hpp"
#include "core/error.hpp"

namespace wisp {

namespace {

constexpr float kNear = 1e-3f;  // cm: what lies closer to the eye plane is not drawn

}  // namespace

TargetMaps draw_targets(const Hair& hair, const Mesh* head, const Camera& camera, bool confidence) {
    TargetMaps m;
    m.width = camera.width;
    m.height = camera.height;
    const size_t n = static_cast<size_t>(m.width) * m.height;
    const float far = std::numeric_limits<float>::infinity();
    m.depth.assign(n, far);
    m.orientation.assign(n, 0.f);
    m.direction.assign(n, 0.f);
    m.hair.assign(n, 0);
    m.surface.assign(n, 0);
    m.coverage.assign(n, 0.f);
    m.confidence.assign(n, 0.f);
    m.strand.assign(n, -1);

    if (head) {
        // Barycentric rasterization at pixel centres; 1/z interpolates linearly on screen.
        for (const Vec3i& f : head->faces) {
            const Vec3f a = camera.project(head->vertices[f[0]]);
            const Vec3f b = camera.project(head->vertices[f[1]]);
            const Vec3f c = camera.project(head->vertices[f[2]]);
            if (a.z() < kNear || b.z() < kNear || c.z() < kNear) continue;
            const float area =
                (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
            if (area == 0.f || !std::isfinite(area)) continue;
            const int x0 =
                std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
            const int x1 =
                std::min(m.width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
            const int y0 =
                std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
            const int y1 = std::min(m.height - 1,
                                    static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const float px = x + 0.5f, py = y + 0.5f;
                    const float w0 =
                        ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
                    const float w1 =
                        ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
                    const float w2 = 1.f - w0 - w1;
                    if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                    const float z = 1.f / (w0 / a.z() + w1 / b.z() + w2 / c.z());
                    float& d = m.depth[static_cast<size_t>(y) * m.width + x];
                    if (z < d) d = z;
                }
        }
    }

    // The hair, in front of the head: each segment stepped one pixel at a time along its
    // major axis; a step covers w·ℓ·√(1 + s²) of its pixel (w the strand's projected width in
    // pixels, ℓ ≤ 1 the step's length on the major axis, s the slope), at most all of it. A
    // pixel's hair coverage is 1 − Π(1 − c) over the steps in it, so a lone strand far thinner
    // than a pixel covers little of it and a clump of them covers it, as in the picture.
    const std::vector<float> head_depth = m.depth;
    for (size_t i = 0; i < n; ++i)
        m.surface[i] = head_depth[i] < far;
    std::vector<float> clear(n, 1.f);  // the share of the pixel no hair covers
    // The k-buffer: per pixel, the nearest kTargetLayers strand samples (depth, coverage,
    // orientation), nearest first; depth ∞ where a layer is empty.
    const size_t layers = confidence ? n * kTargetLayers : 0;
    std::vector<float> layer_z(layers, far), layer_c(layers, 0.f), layer_theta(layers, 0.f);
    // Behind them, the rest as one layer (as multi-layer alpha blending merges what does not
    // fit): what it lets through (Π(1 − c)), and Σ c·e^{2iθ} and Σ c for its mean orientation.
    const size_t tails = confidence ? n : 0;
    std::vector<float> tail_clear(tails, 1.f), tail_x(tails, 0.f), tail_y(tails, 0.f),
        tail_w(tails, 0.f);
    auto to_tail = [&](size_t at, float c, float theta) {
        tail_clear[at] *= 1.f - c;
        tail_x[at] += c * std::cos(2.f * theta);
        tail_y[at] += c * std::sin(2.f * theta);
        tail_w[at] += c;
    };
    const bool widths = !hair.widths.empty();
    for (size_t s = 0; s + 1 < hair.offsets.size(); ++s)
        for (uint32_t i = hair.offsets[s]; i + 1 < hair.offsets[s + 1]; ++i) {
            const Vec3f p = camera.project(hair.points[i]);
            const Vec3f q = camera.project(hair.points[i + 1]);
            if (p.z() < kNear || q.z() < kNear) continue;
            const float dx = q.x() - p.x(), dy = q.y() - p.y();
            // Image rows grow downwards: the angle is measured with y up.
            const float directed = std::atan2(-dy, dx);
            float theta = directed;
            if (theta < 0) theta += static_cast<float>(M_PI);
            if (theta >= static_cast<float>(M_PI)) theta -= static_cast<float>(M_PI);
            const float major = std::max(std::abs(dx), std::abs(dy));
            const float steps_f = std::ceil(major);
            if (!std::isfinite(steps_f) || steps_f > 1e5f) continue;
            const int steps = std::max(1, static_cast<int>(steps_f));
            const float minor = std::min(std::abs(dx), std::abs(dy));
            const float along =
                major / steps *
                std::sqrt(1.f + (major > 0 ? minor * minor / (major * major) : 0.f));
            const float w0 = widths ? hair.widths[i] : hair.default_width;
            const float w1 = widths ? hair.widths[i + 1] : hair.default_width;
            for (int k = 0; k < steps; ++k) {
                const float t = (k + 0.5f) / steps;
                const int x = static_cast<int>(std::floor(p.x() + dx * t));
                const int y = static_cast<int>(std::floor(p.y() + dy * t));
                if (x < 0 || y < 0 || x >= m.width || y >= m.height) continue;
                const float z = 1.f / ((1.f - t) / p.z() + t / q.z());
                const size_t at = static_cast<size_t>(y) * m.width + x;
                if (z >= head_depth[at]) continue;
                const float w = ((1.f - t) * w0 + t * w1) * camera.focal_pixels / z;
                const float c = std::min(1.f, w * along);
                clear[at] *= 1.f - c;
                if (z < m.depth[at]) {
                    m.depth[at] = z;
                    m.orientation[at] = theta;
                    m.direction[at] = directed;
                    m.strand[at] = static_cast<int32_t>(s);
                }
                if (!confidence) continue;
                // Into the k-buffer, if nearer than its farthest layer (which goes to the tail),
                // else into the tail.
                float* lz = &layer_z[at * kTargetLayers];
                int j = kTargetLayers - 1;
                if (!(z < lz[j])) {
                    to_tail(at, c, theta);
                    continue;
                }
                float* lc = &layer_c[at * kTargetLayers];
                float* lt = &layer_theta[at * kTargetLayers];
                if (lz[j] < far) to_tail(at, lc[j], lt[j]);
                for (; j > 0 && z < lz[j - 1]; --j) {
                    lz[j] = lz[j - 1];
                    lc[j] = lc[j - 1];
                    lt[j] = lt[j - 1];
                }
                lz[j] = z;
                lc[j] = c;
                lt[j] = theta;
            }
        }
    // Hair where it covers at least half the pixel. The depth stays the nearest surface any
    // strand or the head puts there: a depth map of the geometry, to be read with the mask.
    for (size_t i = 0; i < n; ++i) {
        m.hair[i] = clear[i] <= 0.5f;
        m.coverage[i] = 1.f - clear[i];
        if (!m.hair[i]) {
            m.orientation[i] = 0.f;
        } else if (confidence) {
            // Front to back: each layer shows what those in front let through.
            float through = 1.f, sx = 0.f, sy = 0.f, sw = 0.f;
            for (int j = 0; j < kTargetLayers && layer_z[i * kTargetLayers + j] < far; ++j) {
                const float wgt = through * layer_c[i * kTargetLayers + j];
                const float a = 2.f * layer_theta[i * kTargetLayers + j];
                sx += wgt * std::cos(a);
                sy += wgt * std::sin(a);
                sw += wgt;
                through *= 1.f - layer_c[i * kTargetLayers + j];
            }
            if (tail_w[i] > 0.f) {
                const float wgt = through * (1.f - tail_clear[i]);
                sx += wgt * tail_x[i] / tail_w[i];
                sy += wgt * tail_y[i] / tail_w[i];
                sw += wgt;
            }
            m.confidence[i] = sw > 0.f ? std::min(1.f, std::hypot(sx, sy) / sw) : 0.f;
        }
        if (m.depth[i] == far) m.depth[i] = 0.f;
    }
    return m;
}

RgbImage orientation_image(const TargetMaps& maps) {
    RgbImage image{maps.width, maps.height, {}};
    image.rgb.assign(static_cast<size_t>(maps.width) * maps.height * 3, 0);
    for (size_t i = 0; i < maps.hair.size(); ++i) {
        if (!maps.hair[i]) continue;
        const float t = 2.f * maps.orientation[i];
        image.rgb[3 * i] = 255;
        image.rgb[3 * i + 1] = static_cast<uint8_t>(std::lround(127.5f * (1.f + std::cos(t))));
        image.rgb[3 * i + 2] = static_cast<uint8_t>(std::lround(127.5f * (1.f + std::sin(t))));
    }
    return image;
}

GrayImage mask_image(const TargetMaps& maps) {
    GrayImage image{maps.width, maps.height, {}};
    image.values.assign(maps.hair.size(), 0.f);
    for (size_t i = 0; i < maps.hair.size(); ++i)
        if (maps.hair[i]) image.values[i] = 1.f;
    return image;
}

HairVolume hair_volume(const Hair& hair, const Vec3f& lo, const Vec3f& hi, const Vec3i& dims) {
    if (!(lo.array() < hi.array()).all() || !lo.allFinite() || !hi.allFinite())
        fail("volume: the box's low corner must lie below its high one on every axis");
    if ((dims.array() < 1).any() || (dims.array() > 1024).any() ||
        static_cast<size_t>(dims.x()) * dims.y() * dims.z() > kMaxVolumeVoxels)
        fail("volume: ", dims.x(), "x", dims.y(), "x", dims.z(), " voxels; each side 1 to 1024, ",
             kMaxVolumeVoxels, " voxels at most");
    HairVolume v;
    v.dims = dims;
    v.lo = lo;
    v.hi = hi;
    const size_t n = static_cast<size_t>(dims.x()) * dims.y() * dims.z();
    v.occupancy.assign(n, 0);
    v.orientation.assign(3 * n, 0.f);
    const Vec3f cell = (hi - lo).cwiseQuotient(dims.cast<float>());
    const float step = 0.5f * cell.minCoeff();
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const std::span<const Vec3f> p = hair.strand(s);
        for (size_t i = 0; i + 1 < p.size(); ++i) {
            const Vec3f d = p[i + 1] - p[i];
            const float len = d.norm();
            if (!(len > 0.f)) continue;
            const Vec3f dir = d / len;
            const float steps_f = std::ceil(len / step);
            if (!(steps_f < 1e7f)) continue;  // a segment across the world: not hair
            const int steps = std::max(1, static_cast<int>(steps_f));
            for (int k = 0; k < steps; ++k) {
                const Vec3f q = (p[i] + d * ((k + 0.5f) / steps) - lo).cwiseQuotient(cell);
                if ((q.array() < 0.f).any() || !(q.array() < dims.cast<float>().array()).all())
                    continue;
                const size_t at =
                    (static_cast<size_t>(q.z()) * dims.y() + static_cast<size_t>(q.y())) *
                        dims.x() +
                    static_cast<size_t>(q.x());
                v.occupancy[at] = 1;
                for (int c = 0; c < 3; ++c)
                    v.orientation[3 * at + c] += dir[c];
            }
        }
    }
    for (size_t i = 0; i < n; ++i) {
        float* o = &v.orientation[3 * i];
        const float norm = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        const float inv = norm > 1e-6f ? 1.f / norm : 0.f;
        for (int c = 0; c < 3; ++c)
            o[c] *= inv;
    }
    return v;
}

ScalpTexture scalp_texture(const Hair& hair, int size, int points) {
    if (hair.root_uv.size() != hair.strand_count())
        fail("scalp texture: the hair has no root UVs (hair grown by wisp has them)");
    if (size < 4 || size > 1024 || points < 2 || points > 1024 ||
        static_cast<size_t>(size) * size * points > (size_t{1} << 26))
        fail("scalp texture: ", size, "² texels of ", points,
             " points; size 4 to 1024, points 2 to 1024, 2^26 points in all at most");
    ScalpTexture t;
    t.size = size;
    t.points = points;
    const size_t n = static_cast<size_t>(size) * size;
    t.mask.assign(n, 0);
    t.strand.assign(n, -1);
    t.offsets.assign(n * points * 3, 0.f);
    t.roots.assign(n * 3, 0.f);
    t.normals.assign(n * 3, 0.f);
    // The strand nearest each texel's centre among those rooted in it (ties: the lower index).
    std::vector<float> best(n, std::numeric_limits<float>::infinity());
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const Vec2f uv = hair.root_uv[s];
        if (!(uv.x() >= 0.f && uv.x() < 1.f && uv.y() > 0.f && uv.y() <= 1.f)) continue;
        const int j = std::min(size - 1, static_cast<int>(uv.x() * size));
        const int i = std::min(size - 1, static_cast<int>((1.f - uv.y()) * size));
        const Vec2f centre((j + 0.5f) / size, 1.f - (i + 0.5f) / size);
        const float d = (uv - centre).squaredNorm();
        const size_t at = static_cast<size_t>(i) * size + j;
        if (d < best[at]) {
            best[at] = d;
            t.strand[at] = static_cast<int32_t>(s);
        }
    }
    std::vector<Vec3f> p(points);
    std::vector<float> w(points);
    for (size_t at = 0; at < n; ++at) {
        const int32_t s = t.strand[at];
        if (s < 0 || hair.strand_size(s) == 0) continue;
        t.mask[at] = 1;
        const std::span<const Vec3f> strand = hair.strand(s);
        catmull_rom_resample(strand, {}, 0.f, p, w);
        for (int k = 0; k < points; ++k)
            for (int c = 0; c < 3; ++c)
                t.offsets[(at * points + k) * 3 + c] = p[k][c] - strand[0][c];
        for (int c = 0; c < 3; ++c) {
            t.roots[at * 3 + c] = strand[0][c];
            if (!hair.root_normal.empty()) t.normals[at * 3 + c] = hair.root_normal[s][c];
        }
    }
    return t;
}

CameraMatrices opencv_matrices(const Camera& cam) {
    CameraMatrices m;
    Eigen::Matrix3f r;
    r.row(0) = cam.right;
    r.row(1) = -cam.up;
    r.row(2) = cam.forward;
    const Vec3f t = -(r * cam.eye);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            m.world_to_camera[4 * i + j] = r(i, j);
        m.world_to_camera[4 * i + 3] = t[i];
    }
    m.world_to_camera[15] = 1;
    m.K = {cam.focal_pixels, 0, 0.5 * cam.width, 0, cam.focal_pixels, 0.5 * cam.height, 0, 0, 1};
    return m;
}

RgbImage strand_map_image(const TargetMaps& maps) {
    RgbImage image{maps.width, maps.height, {}};
    image.rgb.assign(static_cast<size_t>(maps.width) * maps.height * 3, 0);
    for (size_t i = 0; i < maps.hair.size(); ++i) {
        uint8_t* px = &image.rgb[3 * i];
        if (!maps.hair[i]) {
            px[0] = maps.surface[i] ? 128 : 0;
            continue;
        }
        px[0] = 255;
        px[1] = static_cast<uint8_t>(std::lround(127.5f * (1.f + std::cos(maps.direction[i]))));
        px[2] = static_cast<uint8_t>(std::lround(127.5f * (1.f + std::sin(maps.direction[i]))));
    }
    return image;
}

GrayImage matte_image(const TargetMaps& maps) {
    return GrayImage{maps.width, maps.height, maps.coverage};
}

std::vector<float> hairstep_depth(const TargetMaps& maps) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (size_t i = 0; i < maps.hair.size(); ++i)
        if (maps.hair[i]) {
            lo = std::min(lo, maps.depth[i]);
            hi = std::max(hi, maps.depth[i]);
        }
    std::vector<float> out(maps.hair.size(), 0.f);
    if (!(hi > lo)) return out;  // no hair, or all at one depth: 0, as off the mask
    for (size_t i = 0; i < out.size(); ++i)
        if (maps.hair[i]) out[i] = (maps.depth[i] - lo) / (hi - lo);
    return out;
}

}  // namespace wisp
