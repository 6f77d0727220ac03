#pragma once
// The editor's stage cache: a style, its head and the output of every pipeline stage
// (DESIGN.md: head → roots → masters → solve → members → color), so that a change re-runs
// only the stages from the first one it feeds (StyleField::stage, groom/style_schema.hpp)
// on. update() gives exactly the hair generate_hairstyle() gives for the same style, byte
// for byte.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "groom/head.hpp"
#include "groom/style.hpp"
#include "groom/style_schema.hpp"
#include "solve/pipeline.hpp"

namespace wisp {

class StageCache {
  public:
    // Loads the style's head (throws wisp::Error as load_head does); nothing is generated
    // before update(). `base_dir` resolves relative paths of values set later.
    explicit StageCache(Style style, std::filesystem::path base_dir = {});

    const Style& style() const { return style_; }
    const Head& head() const { return head_; }

    // Sets one field from an inline TOML value (set_style_field: the reader's checks and
    // messages, source "SOURCE"); the style is unchanged on error. Marks the field's stage
    // and those after it stale, unless the value is the same as before.
    void set(std::string_view path, std::string_view toml_value,
             const std::string& source = "value");
    // Replaces the whole style (open, preset): the stages from the first field that differs.
    void set_style(Style style);

    // Marks `stage` and those after it stale: a change the style's TOML text does not show
    // (a painted map's pixels, a map file rewritten under the same name).
    void mark_stale(Stage stage) { mark(stage); }

    // The first stale stage (Stage::kNone when everything is up to date).
    Stage stale() const { return stale_; }

    // Runs the stale stages and returns the result (colors included). Throws wisp::Error as
    // the stages do (a map image that cannot be read); the cache then stays stale from the
    // stage that failed, so a later fix re-runs it.
    const HairstyleResult& update();
    // The solved masters, running the stages up to the solve only (the preview's first
    // answer while a solver parameter moves).
    const Masters& update_masters();

    // How many times each stage ran (indexed by Stage, kHead … kColor), for tests and the
    // HUD, and how long it took the last time (ms).
    const std::array<int, kStageCount>& runs() const { return runs_; }
    const std::array<double, kStageCount>& last_ms() const { return last_ms_; }
    int head_field_runs() const { return head_field_runs_; }

  private:
    void mark(Stage stage);
    void run_until(Stage last);  // runs the stale stages up to `last` inclusive

    Style style_;
    std::filesystem::path base_dir_;
    Head head_;
    std::optional<HeadField> head_field_;
    float head_field_cell_ = 0.f;
    Roots roots_;
    Masters masters_;         // as synthesized
    GroupSelection groups_;   // the constraint groups' wisps (the solve stage)
    HairstyleResult result_;  // hair, solved masters, stats
    Stage stale_ = Stage::kRoots;
    std::array<int, kStageCount> runs_{};
    std::array<double, kStageCount> last_ms_{};
    int head_field_runs_ = 0;
};

}  // namespace wisp
