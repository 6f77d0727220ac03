#include "dynamics/body.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <queue>
#include <utility>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "geometry/mesh_distance.hpp"

namespace wisp {
namespace {

// Spheres keep this far (beyond the inset) from the caps that close an open mesh: near a
// hole the winding number is about 1/2, so "inside" is ambiguous there.
constexpr float kCutClearance = 0.5f;  // cm
// The greedy stops when the best sphere would bring less than this fraction of the area.
constexpr double kMinGain = 1e-3;
// The refinement's moves, in cells: 26 neighbours at half a cell, at most this many times.
constexpr float kRefineStep = 0.5f;
constexpr int kRefineMoves = 4;

// A regular grid centred on the fitted box, so that a mesh symmetric in x gets samples
// symmetric in x (and left and right spheres in pairs). Sample i sits at a cell's centre.
struct SampleGrid {
    Vec3f origin = Vec3f::Zero();  // centre of cell (0, 0, 0)
    Vec3i dims = Vec3i::Ones();
    float cell = 1.f;
    size_t count() const { return static_cast<size_t>(dims.x()) * dims.y() * dims.z(); }
    size_t index(int x, int y, int z) const {
        return (static_cast<size_t>(z) * dims.y() + y) * dims.x() + x;
    }
    Vec3f position(size_t i) const {
        const auto x = static_cast<float>(i % dims.x());
        const auto y = static_cast<float>(i / dims.x() % dims.y());
        const auto z = static_cast<float>(i / dims.x() / dims.y());
        return origin + cell * Vec3f(x, y, z);
    }
    Vec3i cell_of(const Vec3f& p) const {  // clamped to the grid
        const Vec3f q = (p - origin) / cell;
        Vec3i c;
        for (int k = 0; k < 3; ++k)
            c[k] = std::clamp(static_cast<int>(std::lround(q[k])), 0, dims[k] - 1);
        return c;
    }
};

// Depth below the surface of the closed mesh, kept kCutClearance from the caps: 0 outside.
struct Depth {
    const MeshDistance& closed;
    const MeshDistance* caps;  // null for a closed mesh
    float operator()(const Vec3f& p) const {
        if (!(closed.winding_number(p) > 0.5f)) return 0.f;
        float d = closed.unsigned_distance(p);
        if (caps) d = std::min(d, caps->unsigned_distance(p) - kCutClearance);
        return std::max(d, 0.f);
    }
};

// The surface hair meets, as area-weighted points binned per grid cell: the targets the
// spheres should come within `cover` of. Each triangle is split into k² equal sub-triangles
// (k from its longest edge) so that large triangles spread their area over the cells they
// cross. A flat cut at the bottom of a closed mesh (the built-in head's chest) is no surface
// hair meets; nor is the surface below the grid.
struct Targets {
    std::vector<Vec3f> position;   // #T, area-weighted mean of the surface in the cell, cm
    std::vector<double> weight;    // #T, cm² of surface
    std::vector<int32_t> of_cell;  // #cells of the grid: target index or -1
};

Targets surface_targets(const Mesh& mesh, const SampleGrid& grid) {
    std::vector<double> weight(grid.count(), 0.0);
    std::vector<Vec3d> moment(grid.count(), Vec3d::Zero());
    const float bottom = mesh.bounds().lo.y();
    const float floor = grid.origin.y() - 0.5f * grid.cell;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        if (std::max({a.y(), b.y(), c.y()}) < bottom + 0.05f * grid.cell &&
            mesh.face_normal(f).y() < -0.9f)
            continue;
        const float area = mesh.face_area(f);
        if (!(area > 0)) continue;
        const float longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
        const int k = std::clamp(static_cast<int>(std::ceil(2.f * longest / grid.cell)), 1, 64);
        const double w = static_cast<double>(area) / (k * k);
        const Vec3f u = (b - a) / static_cast<float>(k), v = (c - a) / static_cast<float>(k);
        auto add = [&](float i, float j) {
            const Vec3f p = a + i * u + j * v;
            if (p.y() < floor) return;
            const Vec3i q = grid.cell_of(p);
            const size_t g = grid.index(q.x(), q.y(), q.z());
            weight[g] += w;
            moment[g] += w * p.cast<double>();
        };
        for (int i = 0; i < k; ++i)
            for (int j = 0; i + j < k; ++j) {
                add(i + 1.f / 3, j + 1.f / 3);
                if (i + j + 1 < k) add(i + 2.f / 3, j + 2.f / 3);
            }
    }
    Targets targets;
    targets.of_cell.assign(grid.count(), -1);
    for (size_t g = 0; g < grid.count(); ++g) {
        if (!(weight[g] > 0)) continue;
        targets.of_cell[g] = static_cast<int32_t>(targets.position.size());
        targets.position.push_back((moment[g] / weight[g]).cast<float>());
        targets.weight.push_back(weight[g]);
    }
    return targets;
}

// Calls on_target(t) for every target within `radius + cover` of c, the centre of a sphere
// of `radius` at depth `radius + inset`, in a fixed order. Every surface point is at least
// that depth from c, and a target (a mean of surface points in one cell) at most a cell
// nearer, so cells wholly within that core are skipped.
template <typename OnTarget>
void for_targets_near(const SampleGrid& grid, const Targets& targets, const Vec3f& c, float radius,
                      float inset, float cover, OnTarget&& on_target) {
    const float outer = radius + cover;
    const float outer2 = outer * outer;
    // In cell units: q the centre, ro and ri the radii of the shell that can hold targets.
    const Vec3f q = (c - grid.origin) / grid.cell;
    const float ro = outer / grid.cell;
    const float ri = std::max(0.f, (radius + inset) / grid.cell - 1.f);
    const Vec3i lo = grid.cell_of(c - Vec3f::Constant(outer));
    const Vec3i hi = grid.cell_of(c + Vec3f::Constant(outer));
    constexpr float kSlack = 0.01f;  // cells: rounding, and points clamped into border cells
    auto run = [&](int y, int z, int x0, int x1) {
        for (int x = std::max(x0, lo.x()); x <= std::min(x1, hi.x()); ++x) {
            const int32_t t = targets.of_cell[grid.index(x, y, z)];
            if (t >= 0 && (targets.position[t] - c).squaredNorm() <= outer2) on_target(t);
        }
    };
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y) {
            // The row's cells whose nearest point is within ro, less those whose farthest
            // point is within ri.
            const float ny = std::max(0.f, std::abs(y - q.y()) - 0.5f);
            const float nz = std::max(0.f, std::abs(z - q.z()) - 0.5f);
            const float e2 = ro * ro - ny * ny - nz * nz;
            if (e2 < 0) continue;
            const float e = std::sqrt(e2) + 0.5f + kSlack;
            const int x0 = static_cast<int>(std::ceil(q.x() - e));
            const int x1 = static_cast<int>(std::floor(q.x() + e));
            const float fy = std::abs(y - q.y()) + 0.5f, fz = std::abs(z - q.z()) + 0.5f;
            const float h2 = ri * ri - fy * fy - fz * fz;
            const float h = h2 > 0 ? std::sqrt(h2) - 0.5f - kSlack : 0.f;
            if (h > 0) {
                run(y, z, x0, static_cast<int>(std::floor(q.x() - h)));
                run(y, z, static_cast<int>(std::ceil(q.x() + h)), x1);
            } else {
                run(y, z, x0, x1);
            }
        }
}

}  // namespace

std::vector<Sphere> fit_body_spheres(const Mesh& mesh, const HeadFrame& head,
                                     const BodyFitOptions& options) {
    if (options.max_spheres < 0)
        fail("body spheres: max_spheres must be ≥ 0, got ", options.max_spheres);
    if (!(options.spacing > 0) || !std::isfinite(options.spacing))
        fail("body spheres: spacing must be > 0 cm, got ", options.spacing);
    if (!(options.min_radius >= 0) || !(options.inset >= 0) || !(options.cover > 0) ||
        !(options.reach > 0))
        fail("body spheres: need min_radius ≥ 0, inset ≥ 0, cover > 0 and reach > 0, got ",
             options.min_radius, ", ", options.inset, ", ", options.cover, ", ", options.reach);
    std::vector<Sphere> spheres;
    if (options.max_spheres == 0) return spheres;
    if (mesh.faces.empty()) fail("body spheres: the mesh has no faces, so it encloses no volume");

    Mesh closed, caps;
    close_holes(mesh, &closed, &caps);
    const MeshDistance closed_distance(closed);
    std::unique_ptr<MeshDistance> cap_distance;
    if (!caps.faces.empty()) cap_distance = std::make_unique<MeshDistance>(caps);
    const Depth depth_at{closed_distance, cap_distance.get()};

    // The sample grid over the part of the mesh that hair reaches.
    Box3 box = mesh.bounds();
    box.lo.y() = std::max(box.lo.y(), head.center.y() - options.reach * head.radius);
    if (!(box.lo.y() <= box.hi.y()))
        fail("body spheres: the mesh lies entirely below the reach of the hair (y < ", box.lo.y(),
             " cm)");
    SampleGrid grid;
    grid.cell = options.spacing;
    for (int k = 0; k < 3; ++k)
        grid.dims[k] = std::max(1, static_cast<int>(std::ceil(box.size()[k] / grid.cell)));
    if (static_cast<double>(grid.dims.x()) * grid.dims.y() * grid.dims.z() > (1 << 23))
        fail("body spheres: a grid of ", grid.dims.x(), "×", grid.dims.y(), "×", grid.dims.z(),
             " samples at spacing ", grid.cell,
             " cm is too fine for the mesh (is the mesh in centimetres?)");
    grid.origin = box.center() - 0.5f * grid.cell * (grid.dims.cast<float>() - Vec3f::Ones());

    // Candidate centres: interior samples whose inscribed sphere is at least min_radius.
    const size_t n = grid.count();
    std::vector<float> depth(n);
    parallel_for(
        n, [&](size_t i) { depth[i] = depth_at(grid.position(i)); }, 64);
    const float smallest = std::max(options.min_radius, 1e-3f);
    std::vector<Vec3f> centre;
    std::vector<float> radius;
    for (size_t i = 0; i < n; ++i)
        if (depth[i] - options.inset >= smallest) {
            centre.push_back(grid.position(i));
            radius.push_back(depth[i] - options.inset);
        }
    if (centre.empty())
        fail("body spheres: the mesh encloses no volume at spacing ", grid.cell,
             " cm (no interior sample lies ", smallest + options.inset,
             " cm inside it); is it a closed or nearly closed surface, in centimetres?");

    const Targets targets = surface_targets(mesh, grid);
    if (targets.position.empty()) fail("body spheres: the mesh has no surface to cover");
    double total = 0;
    for (double w : targets.weight)
        total += w;

    // Greedy set cover: each step takes the candidate sphere that comes within `cover` of
    // the most surface area not yet covered. Lazily: gains only shrink as spheres are
    // picked, so a candidate whose recomputed gain still tops every other (stale, hence
    // upper-bound) gain is the true best. Ties go to the lower index, as in the plain greedy.
    std::vector<int32_t> covering(targets.position.size(), 0);  // spheres near each target
    auto gain = [&](const Vec3f& c, float r) {
        double g = 0;
        for_targets_near(grid, targets, c, r, options.inset, options.cover, [&](int32_t t) {
            if (covering[t] == 0) g += targets.weight[t];
        });
        return g;
    };
    auto cover = [&](const Vec3f& c, float r, int change) {
        for_targets_near(grid, targets, c, r, options.inset, options.cover,
                         [&](int32_t t) { covering[t] += change; });
    };
    using Entry = std::pair<double, int64_t>;  // (gain, −candidate): max-heap order
    std::vector<Entry> initial(centre.size());
    parallel_for(
        centre.size(),
        [&](size_t c) {
            initial[c] = {gain(centre[c], radius[c]), -static_cast<int64_t>(c)};
        },
        16);
    std::priority_queue<Entry> queue(std::less<Entry>(), std::move(initial));
    std::vector<Vec3f> chosen;
    std::vector<float> chosen_radius;
    while (static_cast<int>(chosen.size()) < options.max_spheres && !queue.empty()) {
        Entry top = queue.top();
        queue.pop();
        const auto c = static_cast<size_t>(-top.second);
        top.first = gain(centre[c], radius[c]);
        if (!queue.empty() && top < queue.top()) {
            queue.push(top);
            continue;
        }
        if (top.first <= kMinGain * total) break;
        cover(centre[c], radius[c], +1);
        chosen.push_back(centre[c]);
        chosen_radius.push_back(radius[c]);
    }

    // Refinement: a centre on the grid may lie up to half a cell from where its sphere would
    // hug the surface best, and at 1 cm that matters (it is worth about 5% of the area within
    // 1 cm). Each sphere in turn, the others fixed, moves by half a cell toward whichever of
    // its 26 neighbours covers more (growing or shrinking to the depth there), while that
    // helps.
    std::array<Vec3f, 26> moves;
    for (int k = 0, m = 0; k < 27; ++k)
        if (k != 13) moves[m++] = Vec3f(k % 3 - 1.f, k / 3 % 3 - 1.f, k / 9 - 1.f);
    std::array<float, 26> move_radius;
    std::array<double, 26> move_gain;
    for (size_t i = 0; i < chosen.size(); ++i) {
        cover(chosen[i], chosen_radius[i], -1);
        double now = gain(chosen[i], chosen_radius[i]);
        for (int step = 0; step < kRefineMoves; ++step) {
            parallel_for(moves.size(), [&](size_t k) {
                const Vec3f c = chosen[i] + kRefineStep * grid.cell * moves[k];
                move_radius[k] = depth_at(c) - options.inset;
                move_gain[k] = move_radius[k] >= smallest ? gain(c, move_radius[k]) : -1.0;
            });
            const auto best = static_cast<size_t>(
                std::max_element(move_gain.begin(), move_gain.end()) - move_gain.begin());
            if (!(move_gain[best] > now)) break;
            chosen[i] += kRefineStep * grid.cell * moves[best];
            chosen_radius[i] = move_radius[best];
            now = move_gain[best];
        }
        cover(chosen[i], chosen_radius[i], +1);
    }

    for (size_t i = 0; i < chosen.size(); ++i) {
        Sphere s;
        s.center = chosen[i];
        s.radius = chosen_radius[i];
        s.head = s.center.y() > head.center.y() - 0.8f * head.radius;
        spheres.push_back(s);
    }
    return spheres;
}

void clear_spheres_of(std::vector<Sphere>& spheres, const std::vector<Vec3f>& points,
                      float margin) {
    parallel_for(spheres.size(), [&](size_t i) {
        Sphere& s = spheres[i];
        float nearest2 = std::numeric_limits<float>::infinity();
        for (const Vec3f& p : points)
            nearest2 = std::min(nearest2, (p - s.center).squaredNorm());
        s.radius = std::min(s.radius, std::sqrt(nearest2) - margin);
    });
    std::erase_if(spheres, [](const Sphere& s) { return !(s.radius >= 0.25f); });
}

float sphere_distance(const std::vector<Sphere>& spheres, const Vec3f& p, int* nearest) {
    float best = std::numeric_limits<float>::infinity();
    int index = -1;
    for (size_t i = 0; i < spheres.size(); ++i) {
        const float d = (p - spheres[i].center).norm() - spheres[i].radius;
        if (d < best) {
            best = d;
            index = static_cast<int>(i);
        }
    }
    if (nearest) *nearest = index;
    return best;
}

}  // namespace wisp
