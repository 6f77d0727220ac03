#include "edit/stage_cache.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>

#include <tbb/task_group.h>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "edit/wire.hpp"
#include "groom/color.hpp"
#include "groom/generate.hpp"
#include "groom/roots.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

// The first stage fed by a field that differs between two styles (Stage::kNone if none
// does). Fields are compared by their TOML text, which is exact for floats.
Stage first_changed_stage(const Style& a, const Style& b) {
    Stage first = Stage::kNone;
    for (const StyleField& f : style_schema()) {
        if (f.stage >= first) continue;
        if (f.type == FieldType::kGroups) {
            // The groups are written as a whole; they all feed the solve.
            if (a.groups.size() != b.groups.size() ||
                groups_to_toml(a.groups) != groups_to_toml(b.groups))
                first = f.stage;
            continue;
        }
        if (style_field_toml(a, f) != style_field_toml(b, f)) first = f.stage;
    }
    return first;
}

}  // namespace

StageCache::StageCache(Style style, std::filesystem::path base_dir)
    : style_(std::move(style)), base_dir_(std::move(base_dir)) {
    head_ = load_head(style_.head);
    runs_[int(Stage::kHead)] = 1;
}

void StageCache::mark(Stage stage) {
    if (stage == Stage::kNone) return;
    if (stage < stale_) stale_ = stage;
    // Whatever changed may be the colours' spec or seed, or the roots, or feed the members.
    preview_colors_ready_ = false;
    beside_members_.reset();
}

void StageCache::make_preview_colors(size_t strands) {
    preview_colors_ready_ = false;
    const size_t all = roots_.members.size();
    if (strands >= all) return;
    const std::span<const uint32_t> ids(order(all).data(), strands);
    std::vector<int32_t> wisp(strands);
    member_wisps(roots_, ids, wisp);
    preview_colors_.resize(strands);
    color_strands(style_.color, style_.seed, wisp, preview_colors_, ids);
    preview_colors_ready_ = true;
}

void StageCache::set(std::string_view path, std::string_view toml_value,
                     const std::string& source) {
    Style next = style_;
    set_style_field(next, path, toml_value, source, base_dir_);
    const Stage stage = first_changed_stage(style_, next);
    style_ = std::move(next);
    mark(stage);
}

void StageCache::set_style(Style style) {
    const Stage stage = first_changed_stage(style_, style);
    style_ = std::move(style);
    mark(stage);
}

const HeadField& StageCache::head_field() {
    // The solve and the push out of the head need the head field; its cell follows
    // solve.cell and its bridged field solve.bridge, so it is rebuilt when they move.
    const float cell = head_field_cell(style_.solve), bridge = style_.solve.bridge;
    if (!head_field_ || cell != head_field_cell_ || bridge != head_field_bridge_) {
        head_field_ = build_head_field(style_, head_);
        head_field_cell_ = cell;
        head_field_bridge_ = bridge;
        ++head_field_runs_;
    }
    return *head_field_;
}

const StylingField& StageCache::styling_field_for(const Box3& bounds) {
    // Φ is a function of the head (a new head clears field_), the growth section, the field
    // terms, the cell and the bounds: while only κ, τ or the other solver numbers move, the
    // field of the last solve is the one a new build would give, value for value. A field
    // file is read again each time: it may have changed on disk.
    std::string key;
    for (const StyleField& f : style_schema())
        if (f.path.starts_with("growth.") || f.path == "solve.field" || f.path == "solve.cell")
            key += cat(f.path, '=', style_field_toml(style_, f), '\n');
    key.append(reinterpret_cast<const char*>(bounds.lo.data()), sizeof(float) * 3);
    key.append(reinterpret_cast<const char*>(bounds.hi.data()), sizeof(float) * 3);
    bool file = false;
    for (const FieldTerm& t : style_.solve.field)
        file |= t.kind == FieldTerm::Kind::kFile;
    if (!field_ || key != field_key_ || file) {
        field_ = styling_field(style_, head_, bounds);
        field_key_ = file ? std::string() : std::move(key);
        ++styling_field_runs_;
    }
    return *field_;
}

void StageCache::complete_masters(const MasterPrototype& prototype) {
    synthesize_master_details(style_, prototype, masters_);
}

bool StageCache::run_until(Stage last, const CancelToken& cancel, const StageProgress& progress,
                           size_t preview_strands) {
    // A stage that finishes is published even if the token fires just after (its output is
    // right for the style, and the next request need not redo it); one that was cancelled
    // part way publishes nothing and leaves the cache stale from it.
    //
    // When the solve follows the masters here, the masters stage makes their outlines only
    // (all the solve reads until its end) and the details are synthesized beside the solve,
    // on the core its serial breadth-first layers leave idle.
    std::optional<MasterPrototype> details;  // the masters' details are still to synthesize
    // Published masters are whole: a return before the solve took them on (cancelled, or a
    // solve bounds error) synthesizes them here.
    struct CompleteMasters {
        StageCache& cache;
        std::optional<MasterPrototype>& details;
        ~CompleteMasters() {
            if (details) cache.complete_masters(*details);
        }
    } complete{*this, details};
    for (int s = int(stale_); s <= int(last) && s < kStageCount; ++s) {
        if (progress) progress(Stage(s));
        if (cancel.cancelled()) return false;
        Stopwatch watch;
        switch (Stage(s)) {
            case Stage::kHead:
                head_ = load_head(style_.head);
                head_field_.reset();
                field_.reset();
                scalp_surface_.reset();
                root_proposals_.reset();
                break;
            case Stage::kRoots:
                if (!scalp_surface_) scalp_surface_.emplace(scalp_surface(*head_.scalp));
                {
                    const RootParams params = root_params(style_);
                    if (!root_proposals_ || !root_proposals_->fit(params))
                        root_proposals_.emplace(root_proposals(*head_.scalp, params));
                }
                roots_ = grow_roots(style_, head_, &*scalp_surface_, &*root_proposals_);
                break;
            case Stage::kMasters:
                if (last >= Stage::kSolve && style_.solve.enabled) {
                    masters_ = master_outlines(style_, head_, roots_);
                    details.emplace(master_prototype(style_, masters_));
                } else {
                    masters_ = synthesize_masters(style_, head_, roots_);
                }
                break;
            case Stage::kSolve: {
                head_field();
                groups_ = select_groups(style_, head_, roots_);
                beside_members_.reset();
                Masters solved = masters_;
                SolveStats stats;
                const StylingField* field = nullptr;
                const bool solve = style_.solve.enabled;
                if (solve) {
                    Stopwatch field_watch;
                    field = &styling_field_for(solve_bounds(style_, head_, roots_, masters_));
                    field_ms_ = field_watch.ms();
                }
                // Beside the solve, on the core its serial layers leave idle, one task in this
                // order: the masters' details when the masters stage left them, the preview's
                // colours, then, as the solve's layers make its joints final, the solved
                // masters' frames and control points and the members (follow_solve): the
                // preview's, or the whole hair's when the members stage follows (this run goes
                // on to it, or all strands are asked for). It starts after the styling field,
                // whose build runs on both cores.
                const size_t all = roots_.members.size();
                const bool whole = last >= Stage::kMembers || preview_strands >= all;
                if (whole) preview_strands = 0;
                if (preview_strands) order(all);  // made here: the task reads it
                std::optional<MemberBands> bands;
                if (solve && (whole || preview_strands))
                    bands.emplace(style_, *head_field_, *head_.scalp, roots_, groups_.wisp_group,
                                  masters_.points,
                                  whole
                                      ? std::span<const uint32_t>()
                                      : std::span<const uint32_t>(order_.data(), preview_strands));
                std::optional<MasterPrototype> prototype = std::move(details);
                details.reset();  // the task synthesizes them, however the solve ends
                std::atomic<int> joints{1};
                bool followed = false;
                tbb::task_group beside;
                beside.run([&] {
                    if (prototype) {
                        try {
                            complete_masters(*prototype);
                        } catch (...) {
                            stale_ = Stage::kMasters;  // the masters are not whole
                            throw;
                        }
                    }
                    if (preview_strands) make_preview_colors(preview_strands);
                    if (!solve) return;
                    // The solve reads no details: they may join its masters while it runs.
                    if (prototype) solved.details = masters_.details;
                    followed =
                        follow_solve(solved, joints, bands ? &*bands : nullptr, cancel.quiet());
                });
                // Whatever ends the solve early (a cancel, a bounds error), the task is told
                // and waited for; its own exception is then dropped.
                struct Abandon {
                    std::atomic<int>& joints;
                    tbb::task_group& tasks;
                    bool armed = true;
                    ~Abandon() {
                        if (!armed) return;
                        joints.store(-1, std::memory_order_release);
                        joints.notify_all();
                        try {
                            tasks.wait();
                        } catch (...) {
                        }
                    }
                } abandon{joints, beside};
                if (solve) {
                    stats = solve_stage(style_, head_, *head_field_, roots_, groups_, solved,
                                        nullptr, field, cancel, /*update_frames=*/false, &joints);
                    if (stats.cancelled) return false;
                }
                abandon.armed = false;
                beside.wait();
                if (solve && !followed) {
                    // Cancelled after the solve finished: the solve is still published.
                    parallel_for(
                        solved.count(), [&](size_t w) { update_master(solved, w); }, 64);
                    bands.reset();
                }
                result_.wisp_group = groups_.wisp_group;
                result_.masters = std::move(solved);
                result_.solve = std::move(stats);
                if (bands) {
                    beside_members_ = bands->finish();
                    beside_members_strands_ = whole ? kWholeHair : preview_strands;
                }
                break;
            }
            case Stage::kMembers: {
                MembersResult m;
                if (beside_members_ && beside_members_strands_ == kWholeHair) {
                    m = std::move(*beside_members_);  // grown beside the solve of these masters
                    ++members_grown_beside_;
                } else {
                    m = members_stage(style_, head_, *head_field_, roots_, result_.masters,
                                      groups_.wisp_group, nullptr, {}, cancel);
                    if (cancel.cancelled()) return false;
                }
                beside_members_.reset();
                result_.hair = std::move(m.hair);
                result_.points_pushed = m.points_pushed;
                result_.points_inside_head = m.points_inside_head;
                result_.strands_cut = m.strands_cut;
                result_.strands_removed = m.strands_removed;
                ++hair_run_;
                break;
            }
            case Stage::kColor:
                color_stage(style_, result_.hair);
                break;
            case Stage::kNone:
                break;
        }
        ++runs_[s];
        last_ms_[s] = watch.ms();
        stale_ = Stage(s + 1);  // after kColor: kNone, up to date
    }
    return true;
}

const HairstyleResult& StageCache::update() {
    return *update(CancelToken());
}

const HairstyleResult* StageCache::update(const CancelToken& cancel,
                                          const StageProgress& progress) {
    if (!run_until(Stage::kColor, cancel, progress)) return nullptr;
    result_.times.clear();
    for (int s = 0; s < kStageCount; ++s)
        result_.times.emplace_back(stage_name(Stage(s)), last_ms_[s]);
    return &result_;
}

const Masters& StageCache::update_masters() {
    return *update_masters(CancelToken());
}

const Masters* StageCache::update_masters(const CancelToken& cancel,
                                          const StageProgress& progress) {
    if (!run_until(Stage::kSolve, cancel, progress)) return nullptr;
    return &result_.masters;
}

const Hair* StageCache::update_preview(size_t strands, const CancelToken& cancel,
                                       const StageProgress& progress) {
    if (!run_until(Stage::kSolve, cancel, progress, strands)) return nullptr;
    if (stale_ > Stage::kMembers || strands >= roots_.members.size()) {
        const HairstyleResult* r = update(cancel, progress);
        return r ? &r->hair : nullptr;
    }
    if (progress) progress(Stage::kMembers);
    if (cancel.cancelled()) return nullptr;
    Stopwatch watch;
    const std::span<const uint32_t> ids(order(roots_.members.size()).data(), strands);
    MembersResult m;
    if (beside_members_ && beside_members_strands_ == strands) {
        // Grown beside the solve that made these masters.
        m = std::move(*beside_members_);
        beside_members_.reset();
        ++members_grown_beside_;
    } else {
        m = members_stage(style_, head_, *head_field_, roots_, result_.masters, groups_.wisp_group,
                          nullptr, ids, cancel);
        if (cancel.cancelled()) return nullptr;
    }
    preview_ = std::move(m.hair);
    preview_members_ms_ = watch.ms();
    // Strand i is strand ids[i] of the full hair, so it takes that strand's colour, unless the
    // cut removed strands and shifted the indices.
    if (preview_colors_ready_ && m.strands_removed == 0 &&
        preview_colors_.size() == preview_.strand_count())
        preview_.colors = preview_colors_;
    else
        color_stage(style_, preview_, m.strands_removed == 0 ? ids : std::span<const uint32_t>());
    preview_ms_ = watch.ms();
    preview_color_ms_ = preview_ms_ - preview_members_ms_;
    return &preview_;
}

const std::vector<uint32_t>& StageCache::order(size_t n) {
    if (order_.size() != n) order_ = strand_order(n);
    return order_;
}

std::shared_ptr<const std::string> StageCache::hair_bytes(size_t strands, const CancelToken& cancel,
                                                          const StageProgress& progress) {
    if (!run_until(Stage::kSolve, cancel, progress, strands)) return nullptr;
    if (stale_ <= Stage::kMembers && strands < roots_.members.size()) {
        // A preview: strand i of preview_ is already strand_order[i] of the full hair.
        const Hair* preview = update_preview(strands, cancel, progress);
        if (!preview) return nullptr;
        Stopwatch watch;
        std::vector<uint32_t> ids(preview->strand_count());
        for (size_t i = 0; i < ids.size(); ++i)
            ids[i] = static_cast<uint32_t>(i);
        // Into the last preview's buffer when no one holds it any more (as bytes_ below): a
        // preview while a slider moves is about as large as the one before, so its 7.5 MB are
        // neither cleared nor faulted in again on one thread.
        const bool held = preview_bytes_ && preview_bytes_.use_count() > 1;
        std::atomic_thread_fence(std::memory_order_acquire);
        if (!preview_bytes_ || held) preview_bytes_ = std::make_shared<std::string>();
        encode_strands(*preview, ids, roots_.members.size(), *preview_bytes_);
        encode_ms_ = watch.ms();
        return preview_bytes_;
    }
    // The members are up to date, or all of them are asked for.
    if (!run_until(Stage::kMembers, cancel, progress)) return nullptr;
    const Hair& hair = result_.hair;
    const size_t all = hair.strand_count(), count = std::min(strands, all);
    const std::span<const uint32_t> ids(order(all).data(), count);
    std::vector<Vec3f> colors(count);
    if (stale_ == Stage::kColor && count < all) {
        // The colours of the strands sent only (color_stage's, strand by strand).
        if (progress) progress(Stage::kColor);
        std::vector<int32_t> wisp(count);
        for (size_t i = 0; i < count; ++i)
            wisp[i] = hair.wisp[ids[i]];
        color_strands(style_.color, style_.seed, wisp, colors, ids);
    } else {
        if (!run_until(Stage::kColor, cancel, progress)) return nullptr;
        for (size_t i = 0; i < count; ++i)
            colors[i] = hair.color_of(ids[i]);
    }
    // The positions encoded last time stay when the hair and the count are the same and no
    // one holds that buffer any more (use_count is exact here: copies are made under the
    // caller's lock only, and a holder that lets go only lowers it).
    Stopwatch watch;
    const bool held = bytes_ && bytes_.use_count() > 1;
    // A holder's reads come before its release of the buffer: seen released, they are over.
    std::atomic_thread_fence(std::memory_order_acquire);
    if (!bytes_ || bytes_run_ != hair_run_ || bytes_strands_ != count || held) {
        bytes_ = std::make_shared<std::string>(encode_strands(hair, ids, all));
        bytes_run_ = hair_run_;
        bytes_strands_ = count;
    }
    write_strand_colors(colors, *bytes_);
    encode_ms_ = watch.ms();
    return bytes_;
}

const Masters* StageCache::update_masters_preview(const CancelToken& cancel,
                                                  const StageProgress& progress) {
    if (!run_until(Stage::kMasters, cancel, progress)) return nullptr;
    const size_t w_count = masters_.count();
    if (stale_ > Stage::kSolve || !style_.solve.enabled || w_count <= kPreviewWisps)
        return update_masters(cancel, progress);
    if (progress) progress(Stage::kSolve);
    if (cancel.cancelled()) return nullptr;
    const size_t k = (w_count + kPreviewWisps - 1) / kPreviewWisps;
    const size_t count = (w_count + k - 1) / k;
    const int n = masters_.points;
    // Wisp i of the coarse problem is wisp k·i, with the strands of wisps k·i … k·i + k − 1.
    Roots roots;
    roots.wisp_offsets.push_back(0);
    Masters& m = preview_masters_;
    m = Masters();
    m.points = n;
    for (size_t i = 0; i < count; ++i) {
        const size_t w = k * i, last = std::min(w + k, w_count);
        const uint32_t own = roots_.wisp_offsets[w + 1] - roots_.wisp_offsets[w];
        const uint32_t all = roots_.wisp_offsets[last] - roots_.wisp_offsets[w];
        roots.masters.push_back(roots_.masters[w]);
        roots.wisp_offsets.push_back(roots.wisp_offsets.back() + all);
        // The same strands per cross-section as the wisp's own (Choe & Ko eq. (6)'s ρ_Δ).
        roots.wisp_radius.push_back(roots_.wisp_radius[w] *
                                    std::sqrt(float(std::max(all, 1u)) / float(std::max(own, 1u))));
        m.roots.push_back(masters_.roots[w]);
        m.segment.push_back(masters_.segment[w]);
        m.direction.push_back(masters_.direction[w]);
        m.root_frame.push_back(masters_.root_frame[w]);
        const auto copy = [&](auto& to, const auto& from) {
            to.insert(to.end(), from.begin() + w * n, from.begin() + (w + 1) * n);
        };
        copy(m.outline, masters_.outline);
        copy(m.details, masters_.details);
        copy(m.frames, masters_.frames);
        copy(m.control, masters_.control);
    }
    const HeadField& head = head_field();
    // The full problem's field covers the coarse one's reach, and stays for the exact solve.
    const StylingField& field = styling_field_for(solve_bounds(style_, head_, roots_, masters_));
    const SolveStats stats =
        solve_stage(style_, head_, head, roots, select_groups(style_, head_, roots), m, nullptr,
                    &field, cancel);
    return stats.cancelled ? nullptr : &m;
}

}  // namespace wisp
