#include "groom/generate.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "core/noise.hpp"
#include "core/parallel.hpp"
#include "groom/color.hpp"
#include "groom/distribution.hpp"
#include "groom/member.hpp"
#include "groom/prototype.hpp"
#include "groom/synthesis.hpp"

namespace wisp {
namespace {

// A baby hair's or flyaway's way out of its clump: along the strand from `from` cm over
// `span` cm, it moves by lift·t^power (t from 0 to 1 over the span) toward
// cos(angle)·side·n + sin(angle)·(b turned away from the head), in the master's frame there.
struct Turn {
    float from = 0.f, span = 1.f, lift = 0.f, power = 1.f, side = 1.f, angle = 0.f;
};

}  // namespace

float deviation_radius(const std::vector<float>& table, float s) {
    if (table.empty()) return 1.f;
    if (table.size() == 1) return table[0];
    const float x = std::clamp(s, 0.f, 1.f) * static_cast<float>(table.size() - 1);
    const size_t i = std::min(static_cast<size_t>(x), table.size() - 2);
    const float f = x - static_cast<float>(i);
    return (1.f - f) * table[i] + f * table[i + 1];
}

RootParams root_params(const Style& style) {
    RootParams params;
    params.wisps = style.wisps;
    params.strands = style.strands;
    params.seed = style.seed;
    return params;
}

Roots grow_roots(const Style& style, const Head& head, const MeshDistance* scalp_surface,
                 const RootProposals* proposals) {
    MapSampler density(style.density, *head.scalp, style.growth);
    density.set_hairline(style.hairline);
    return place_roots(*head.scalp, density, root_params(style), scalp_surface, proposals);
}

void member_wisps(const Roots& roots, std::span<const uint32_t> ids, std::span<int32_t> out) {
    const std::vector<uint32_t>& offsets = roots.wisp_offsets;
    for (size_t i = 0; i < ids.size(); ++i)
        out[i] = static_cast<int32_t>(std::upper_bound(offsets.begin(), offsets.end(), ids[i]) -
                                      offsets.begin() - 1);
}

Masters master_outlines(const Style& style, const Head& head, const Roots& roots) {
    const Scalp& scalp = *head.scalp;
    const MapSampler length_map(style.length, scalp, style.growth);
    const MapSampler protrusion_map(style.protrusion, scalp, style.growth);
    const GrowthField growth_field(style.growth, scalp);
    const size_t w_count = roots.masters.size();
    const int n = style.points_per_strand;

    Masters m;
    m.points = n;
    m.roots = roots.masters;
    m.segment.resize(w_count);
    m.direction.resize(w_count);
    m.root_frame.resize(w_count);
    m.outline.resize(w_count * n);
    m.details.resize(w_count * n);
    m.frames.resize(w_count * n);
    m.control.resize(w_count * n);

    for (size_t w = 0; w < w_count; ++w) {
        const float len = length_map(m.roots[w]);
        if (!(len > 0.f) || !std::isfinite(len))
            fail("length map gives ", len, " cm at a root: hair length must be > 0");
        m.segment[w] = len / static_cast<float>(n - 1);
    }

    parallel_for(
        w_count,
        [&](size_t w) {
            const SurfacePoint& root = m.roots[w];
            // Roots at the hairline lie low along their growth direction.
            const float lie = hairline_lie(scalp, root, style.hairline);
            const float protrusion = protrusion_map(root) * (1.f - lie);
            const Vec3f growth = growth_field(scalp_direction(scalp, root.position));
            const Vec3f dir = protrusion_direction(root, growth, protrusion);
            m.direction[w] = dir;
            // Details turn with the head: the normal starts along the scalp, across the strand,
            // so waves sway over the head rather than in and out of it (where a strand leaves
            // the top sideways, a horizontal normal would lie along it and leave the wave
            // standing up off the scalp). A strand leaving straight out takes the horizontal
            // around the head instead.
            Vec3f across = root.normal.cross(dir);
            if (across.norm() < 0.2f) across = Vec3f::UnitY().cross(root.position - scalp.center());
            Frame f = frame_from(dir, across.norm() > 1e-4f ? across : Vec3f::UnitX());
            Rng rng(style.seed, Stream::kRoll, w);
            const float roll = rng.uniform(-style.prototype.roll, style.prototype.roll);
            const Eigen::AngleAxisf spin(roll, dir);
            f.n = (spin * f.n).normalized();
            f.b = f.t.cross(f.n);
            m.root_frame[w] = f;
            for (int i = 0; i < n; ++i)
                m.outline[w * n + i] = root.position + (m.segment[w] * static_cast<float>(i)) * dir;
        },
        64);
    return m;
}

MasterPrototype master_prototype(const Style& style, const Masters& masters) {
    const int h = style.prototype.window;
    float longest = 0.f;
    for (const float s : masters.segment)
        longest = std::max(longest, s);
    // A master whose period is shorter walks the prototype in longer steps.
    longest *= 1.f + style.prototype.period_variation;
    // Presets are generated long enough for any master; a user polyline must be long enough
    // to hold a window at the coarsest segment length.
    PrototypeSpec spec = style.prototype;
    if (spec.kind != PrototypeSpec::Kind::kPolyline)
        spec.length = std::max(spec.length, static_cast<float>(h + 16) * longest);
    MasterPrototype p{make_prototype_curve(spec), is_straight(spec)};
    if (spec.kind == PrototypeSpec::Kind::kPolyline &&
        p.curve.centre_arc.back() < static_cast<float>(h + 2) * longest)
        fail("prototype.points: the polyline's outline is ", p.curve.centre_arc.back(),
             " cm long, but a window of ", h, " needs at least ",
             static_cast<float>(h + 2) * longest,
             " cm at the longest master's segment length (length / (points_per_strand-1), times 1 "
             "+ period_variation)");
    return p;
}

void synthesize_master_details(const Style& style, const MasterPrototype& prototype, Masters& m,
                               bool update_frames) {
    const int n = m.points;
    const int h = style.prototype.window;
    parallel_for(
        m.count(),
        [&](size_t w) {
            // This master's waves: its own amplitude and period (the same draws whatever the
            // variations, so changing one keeps the other's).
            Rng wave(style.seed, Stream::kWave, w);
            const float amplitude =
                1.f + style.prototype.amplitude_variation * wave.uniform(-1.f, 1.f);
            const float rate = 1.f + style.prototype.period_variation * wave.uniform(-1.f, 1.f);
            const float own_phase = wave.uniform();
            SynthesisParams sp;
            sp.window = h;
            sp.substeps = prototype.straight
                              ? 1
                              : synthesis_substeps(m.segment[w], style.prototype.period / rate);
            sp.temperature = style.prototype.temperature;
            // Fully rewritten by each call: reusing them per thread changes no result.
            static thread_local SynthesisScratch scratch;
            static thread_local std::vector<Vec3f> proto, work;
            decompose(prototype.curve, rate * m.segment[w] / sp.substeps, proto, work);
            std::span<Vec3f> details(m.details.data() + w * n, static_cast<size_t>(n));
            sp.scale = synthesis_scale(proto, h);
            const float coherence = style.prototype.coherence;
            if (coherence > 0.f && !prototype.straight) {
                // A phase in periods: the shared field's (spanning about two periods over the
                // head, so patches differ) mixed with this master's own.
                const float field =
                    value_noise(stream_seed(style.seed, Stream::kWaveField),
                                m.roots[w].position / style.prototype.coherence_size);
                // Hair falls from its root, so a root placed higher reaches a given height
                // further along: taking its height off the phase puts neighbours' crests at
                // the same height, as waves set on a head are seen.
                const float fall = -m.roots[w].position.y() / style.prototype.period;
                float phase = coherence * (2.f * field + fall) + (1.f - coherence) * own_phase;
                phase -= std::floor(phase);
                const float samples_per_period = style.prototype.period *
                                                 static_cast<float>(sp.substeps) /
                                                 (rate * m.segment[w]);
                sp.start = static_cast<int>(std::lround(phase * samples_per_period));
            }
            Rng srng(style.seed, Stream::kMaster, w);
            synthesize_details(proto, sp, srng, details, {}, scratch);
            // The root stays on the scalp: details are relative to the first one.
            const Vec3f d0 = details[0];
            const float onset = style.prototype.onset;
            for (int k = 0; k < n; ++k) {
                const float grow =
                    onset > 0.f ? smoothstep(0.f, onset, static_cast<float>(k) * m.segment[w])
                                : 1.f;
                details[k] = grow * amplitude * (details[k] - d0);
            }
            if (update_frames) update_master(m, w);
        },
        8);
}

Masters synthesize_masters(const Style& style, const Head& head, const Roots& roots) {
    Masters m = master_outlines(style, head, roots);
    synthesize_master_details(style, master_prototype(style, m), m);
    return m;
}

MemberGrowth::MemberGrowth(const Style& style, const Scalp& scalp, const Roots& roots, int points,
                           std::span<const int32_t> wisp_group, std::span<const uint32_t> only)
    : roots_(roots),
      scalp_(scalp),
      clump_(style.clump),
      seed_(style.seed),
      wisp_group_(wisp_group.begin(), wisp_group.end()),
      only_(only.begin(), only.end()),
      n_(points),
      fuzziness_(style.wisp.fuzziness),
      root_width_(style.root_width),
      tip_width_(style.tip_width),
      taper_(style.taper),
      hairline_(style.hairline),
      flyaway_(style.flyaway),
      centre_(scalp.center()) {
    const size_t w_count = roots.masters.size();
    const size_t s_count = only.empty() ? roots.members.size() : only.size();
    const auto id = [&](size_t i) { return only.empty() ? static_cast<uint32_t>(i) : only[i]; };
    const int n = points;
    Hair& hair = hair_;
    hair.default_width = style.root_width;
    hair.wisp.resize(s_count);
    hair.root_uv.resize(s_count);
    hair.root_normal.resize(s_count);
    for (size_t i = 0; i < s_count; ++i) {
        hair.root_uv[i] = roots.members[id(i)].uv;
        hair.root_normal[i] = roots.members[id(i)].normal;
    }
    hair.offsets.assign(s_count + 1, 0);
    u_.resize(s_count);
    parallel_for(
        s_count,
        [&](size_t i) {
            Rng rng(style.seed, Stream::kLength, id(i));
            u_[i] = std::clamp(sample(style.wisp.length, rng), 1e-3f, 1.f);
        },
        4096);
    if (only.empty()) {
        for (size_t w = 0; w < w_count; ++w)
            for (uint32_t j = roots.wisp_offsets[w]; j < roots.wisp_offsets[w + 1]; ++j)
                hair.wisp[j] = static_cast<int32_t>(w);
    } else {
        member_wisps(roots, only, hair.wisp);
    }
    // Baby hairs near the scalp's edge (more of them the nearer), flyaways among the rest;
    // each strand's draws come from its root's id, so a subset (`only`) gets the same.
    kind_.assign(s_count, kOrdinary);
    std::optional<MapSampler> length_map;
    for (size_t i = 0; i < s_count; ++i) {
        const uint32_t j = id(i);
        if (hairline_.width > 0.f && hairline_.baby > 0.f) {
            // The line's noise only near the edge: most roots are far from it.
            const SurfacePoint& root = roots.members[j];
            const float from_edge = scalp.edge_distance(root);
            const float edge =
                from_edge < hairline_.width + hairline_wander(hairline_.irregularity)
                    ? hairline_edge(scalp, root.position, from_edge, hairline_.irregularity)
                    : from_edge;
            if (edge < hairline_.width) {
                Rng rng(style.seed, Stream::kHairline, j);
                if (rng.uniform() <
                    hairline_.baby * (1.f - std::max(edge, 0.f) / hairline_.width)) {
                    kind_[i] = kBaby;
                    if (!length_map) length_map.emplace(style.length, scalp, style.growth);
                    const float master = (*length_map)(roots.masters[hair.wisp[i]]);
                    const float length = hairline_.baby_length * rng.uniform(0.4f, 1.f);
                    if (master > 0.f) u_[i] = std::min(u_[i], std::max(length / master, 1e-3f));
                    continue;
                }
            }
        }
        if (flyaway_.fraction > 0.f) {
            Rng rng(style.seed, Stream::kFlyaway, j);
            if (rng.uniform() < flyaway_.fraction) kind_[i] = kFlyaway;
        }
    }
    for (size_t i = 0; i < s_count; ++i)
        hair.offsets[i + 1] = hair.offsets[i] + member_point_count(n, u_[i]);
    hair.points.resize(hair.offsets.back());
    hair.widths.resize(hair.offsets.back());

    // r_k relative to the root: the table is scaled so that r_1 is the wisp's root radius.
    std::vector<float> rel(n);
    const float r0 = deviation_radius(style.wisp.deviation_radius, 0.f);
    for (int k = 0; k < n; ++k)
        rel[k] = deviation_radius(style.wisp.deviation_radius,
                                  static_cast<float>(k) / static_cast<float>(n - 1)) /
                 r0;
    radius_.resize(w_count * n);
    for (size_t w = 0; w < w_count; ++w)
        for (int k = 0; k < n; ++k)
            radius_[w * n + k] = roots.wisp_radius[w] * rel[k];
    pull_ = clump_profile(clump_.pull, clump_.shape, n);
    if (clump_.sub_count > 1 && clump_.sub_pull > 0.f) {
        sub_pull_ = clump_profile(clump_.sub_pull, clump_.sub_shape, n);
        sub_centre_.resize(s_count);
        sub_share_.resize(s_count);
        std::vector<uint32_t> ids(s_count);
        for (size_t i = 0; i < s_count; ++i)
            ids[i] = id(i);
        sub_clump_centres(clump_, roots, ids, hair.wisp, sub_centre_);
        for (size_t i = 0; i < s_count; ++i)
            sub_share_[i] =
                clump_share(style.seed, 2 * uint64_t{sub_centre_[i]} + 1, clump_.sub_variation);
    }
    offset_.resize(s_count);
    rng_.assign(s_count, Rng(0));
    parallel_for(
        s_count, [&](size_t i) { rng_[i] = Rng(style.seed, Stream::kMember, id(i)); }, 1024);
}

void MemberGrowth::grow(const Masters& masters, int k0, int k1, const CancelToken& cancel) {
    const size_t n = static_cast<size_t>(n_);
    if (k0 <= 0 && guides_.guide.empty()) {
        guides_ = clump_guides(clump_, scalp_, masters, wisp_group_);
        clump_share_.resize(masters.count());
        for (size_t w = 0; w < masters.count(); ++w)
            clump_share_[w] = clump_share(seed_, 2 * uint64_t{w}, clump_.variation);
    }
    const bool clumps = !guides_.size.empty();
    const bool subs = !sub_centre_.empty();
    const int from = std::max(k0, 0), to = std::min(k1, n_);
    if (clumps && from < to) {
        // How far toward its guide a wisp's members go at each point of the band: the
        // profile, the clump's share, less where the solve took the two masters apart.
        weight_.resize(masters.count() * n);
        guide_at_.resize(masters.count() * n);
        parallel_for(
            masters.count(),
            [&](size_t w) {
                const size_t g = static_cast<size_t>(guides_.guide[w]);
                const float size = guides_.size[w];
                const Vec3f* own = masters.control.data() + w * n;
                const Vec3f* guide = masters.control.data() + g * n;
                for (int k = from; k < to; ++k) {
                    const size_t kk = static_cast<size_t>(k);
                    const float apart = (guide[kk] - own[kk]).norm();
                    const float a = pull_[kk] * clump_share_[g] *
                                    (1.f - smoothstep(1.5f * size, 3.f * size, apart));
                    weight_[w * n + kk] = a;
                    // The point that a member pulled `a` of the way toward lands where
                    // clump_point puts its master: a blend toward it is then the clump's pull.
                    const Vec3f to = clump_point(masters, w, g, kk, a);
                    guide_at_[w * n + kk] =
                        a > 1e-6f ? Vec3f(own[kk] + (to - own[kk]) / a) : own[kk];
                }
            },
            256);
    }
    ProgressCounter progress(cancel, hair_.strand_count());
    parallel_for(
        hair_.strand_count(),
        [&](size_t i) {
            if (cancel.cancelled()) return;
            const size_t w = static_cast<size_t>(hair_.wisp[i]);
            const std::span<const Vec3f> master = masters.strand(w);
            const std::span<const Frame> frames(masters.frames.data() + w * n, n);
            const std::span<const float> radius(radius_.data() + w * n, n);
            const uint32_t j = only_.empty() ? static_cast<uint32_t>(i) : only_[i];
            const float segment = masters.segment[w];
            const float k_end = std::clamp(u_[i], 0.f, 1.f) * static_cast<float>(n - 1);
            if (k0 <= 0) {
                offset_[i] = frames[0].to_local(roots_.members[j].position - master[0]);
                // The last taper_ cm narrow to the tip; a strand shorter than that starts
                // narrower (a baby hair is fine all along).
                const std::span<float> widths(hair_.widths.data() + hair_.offsets[i],
                                              hair_.offsets[i + 1] - hair_.offsets[i]);
                const float length = k_end * segment;
                for (size_t k = 0; k < widths.size(); ++k) {
                    const float to_tip = length - std::min(static_cast<float>(k), k_end) * segment;
                    const float t = taper_ > 0.f ? std::min(to_tip / taper_, 1.f) : 1.f;
                    widths[k] = tip_width_ + (root_width_ - tip_width_) * t;
                }
            }
            const uint8_t kind = kind_[i];
            if (!clumps && !subs && kind == kOrdinary) {
                grow_member_points(master, frames, radius, u_[i], fuzziness_, k0, k1, offset_[i],
                                   rng_[i], hair_.strand(i));
            } else {
                const float* weight = clumps ? weight_.data() + w * n : nullptr;
                const Vec3f* guide = clumps ? guide_at_.data() + w * n : nullptr;
                // The sub-clump: around the path its centre's root offset takes through the
                // wisp's cylinder, carried by the clump as the member is.
                const Vec3f centre =
                    subs ? frames[0].to_local(roots_.members[sub_centre_[i]].position - master[0])
                         : Vec3f::Zero();
                const float inv_r0 = 1.f / radius[0];
                const float sub_share = subs ? sub_share_[i] : 0.f;
                // A baby hair leaves at an angle of its own from the root, a flyaway over its
                // last stretch: toward one side, partly outward (never into the head), with
                // its clump's pull let go. Their draws, a stream apart from the constructor's.
                Turn turn;
                if (kind != kOrdinary) {
                    Rng r(seed_, kind == kBaby ? Stream::kHairline : Stream::kFlyaway,
                          uint64_t{j} + (uint64_t{1} << 32));
                    turn.side = r.uniform() < 0.5f ? -1.f : 1.f;
                    turn.angle = r.uniform(0.f, 1.f);
                    if (kind == kBaby) {
                        turn.from = 0.f;
                        turn.span = k_end * segment + 1e-3f;
                        turn.lift = r.uniform(0.3f, 0.8f) * turn.span;
                        turn.power = 1.f;
                    } else {
                        turn.span = flyaway_.length * r.uniform(0.5f, 1.f);
                        turn.from = std::max(k_end * segment - turn.span, 0.f);
                        turn.lift = flyaway_.lift * r.uniform(0.5f, 1.f);
                        turn.power = 2.f;
                    }
                }
                grow_member_points(
                    master, frames, radius, u_[i], fuzziness_, k0, k1, offset_[i], rng_[i],
                    hair_.strand(i), [&](int k, const Vec3f& p) {
                        const size_t kk = static_cast<size_t>(k);
                        float t = 0.f;  // how far along its turn
                        if (kind != kOrdinary)
                            t = std::clamp(
                                (static_cast<float>(k) * segment - turn.from) / turn.span, 0.f,
                                1.f);
                        const float hold = kind == kOrdinary ? 1.f
                                           : kind == kBaby   ? 0.f
                                                             : 1.f - smoothstep(0.f, 1.f, t);
                        const float a = clumps ? hold * weight[kk] : 0.f;
                        Vec3f q = clumps ? Vec3f(p + a * (guide[kk] - p)) : p;
                        if (subs) {
                            Vec3f c =
                                master[kk] + frames[kk].to_world(centre * (radius[kk] * inv_r0));
                            if (clumps) c += a * (guide[kk] - c);
                            q += (hold * sub_pull_[kk] * sub_share) * (c - q);
                        }
                        if (t > 0.f) {
                            Vec3f out = frames[kk].b;
                            if (out.dot(q - centre_) < 0.f) out = -out;
                            const Vec3f dir = std::cos(turn.angle) * turn.side * frames[kk].n +
                                              std::sin(turn.angle) * out;
                            q += (turn.lift * std::pow(t, turn.power)) * dir;
                        }
                        return q;
                    });
            }
            progress.step();
        },
        64);
}

int MemberGrowth::settled(size_t i, int k1) const {
    return member_points_settled(n_, u_[i], static_cast<int>(hair_.strand(i).size()), k1);
}

Hair grow_members(const Style& style, const Scalp& scalp, const Masters& masters,
                  const Roots& roots, std::span<const int32_t> wisp_group,
                  std::span<const uint32_t> only, const CancelToken& cancel) {
    MemberGrowth growth(style, scalp, roots, masters.points, wisp_group, only);
    growth.grow(masters, 0, masters.points, cancel);
    return std::move(growth.hair());
}

Hair guide_strands(const Masters& masters, std::span<const int32_t> wisp_group, float width) {
    const size_t W = masters.count(), n = static_cast<size_t>(masters.points);
    Hair g;
    g.default_width = width;
    g.points = masters.control;
    g.offsets.resize(W + 1);
    g.wisp.resize(W);
    g.root_uv.resize(W);
    g.root_normal.resize(W);
    for (size_t w = 0; w < W; ++w) {
        g.offsets[w + 1] = static_cast<uint32_t>((w + 1) * n);
        g.wisp[w] = static_cast<int32_t>(w);
        g.root_uv[w] = masters.roots[w].uv;
        g.root_normal[w] = masters.roots[w].normal;
    }
    if (!wisp_group.empty()) g.group.assign(wisp_group.begin(), wisp_group.end());
    return g;
}

GenerateResult generate(const Style& style, const Head& head) {
    GenerateResult result;
    Stopwatch watch;
    const Roots roots = grow_roots(style, head);
    result.times.emplace_back("roots", watch.ms());
    watch = Stopwatch();
    result.masters = synthesize_masters(style, head, roots);
    result.times.emplace_back("masters", watch.ms());
    watch = Stopwatch();
    result.hair = grow_members(style, *head.scalp, result.masters, roots);
    result.times.emplace_back("members", watch.ms());
    watch = Stopwatch();
    result.hair.colors.resize(result.hair.strand_count());
    color_strands(style.color, style.seed, result.hair.wisp, result.hair.colors);
    result.times.emplace_back("color", watch.ms());
    return result;
}

}  // namespace wisp
