#include "edit/stage_cache.hpp"

#include <algorithm>
#include <utility>

#include "core/timer.hpp"
#include "groom/generate.hpp"
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
    if (stage != Stage::kNone && stage < stale_) stale_ = stage;
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

void StageCache::run_until(Stage last) {
    for (int s = int(stale_); s <= int(last) && s < kStageCount; ++s) {
        Stopwatch watch;
        switch (Stage(s)) {
            case Stage::kHead:
                head_ = load_head(style_.head);
                head_field_.reset();
                break;
            case Stage::kRoots:
                roots_ = grow_roots(style_, head_);
                break;
            case Stage::kMasters:
                masters_ = synthesize_masters(style_, head_, roots_);
                break;
            case Stage::kSolve: {
                // The solve and the push out of the head need the head field; its cell
                // follows solve.cell, so it is rebuilt when that moves it.
                const float cell = head_field_cell(style_.solve);
                if (!head_field_ || cell != head_field_cell_) {
                    head_field_ = build_head_field(style_, head_);
                    head_field_cell_ = cell;
                    ++head_field_runs_;
                }
                groups_ = select_groups(style_, head_, roots_);
                result_.wisp_group = groups_.wisp_group;
                result_.masters = masters_;
                result_.solve = {};
                if (style_.solve.enabled)
                    result_.solve =
                        solve_stage(style_, head_, *head_field_, roots_, groups_, result_.masters);
                break;
            }
            case Stage::kMembers: {
                MembersResult m = members_stage(style_, head_, *head_field_, roots_,
                                                result_.masters, groups_.wisp_group);
                result_.hair = std::move(m.hair);
                result_.points_pushed = m.points_pushed;
                result_.points_inside_head = m.points_inside_head;
                result_.strands_cut = m.strands_cut;
                result_.strands_removed = m.strands_removed;
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
}

const HairstyleResult& StageCache::update() {
    run_until(Stage::kColor);
    result_.times.clear();
    for (int s = 0; s < kStageCount; ++s)
        result_.times.emplace_back(stage_name(Stage(s)), last_ms_[s]);
    return result_;
}

const Masters& StageCache::update_masters() {
    run_until(Stage::kSolve);
    return result_.masters;
}

}  // namespace wisp
