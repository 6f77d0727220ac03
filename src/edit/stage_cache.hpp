#pragma once
// The editor's stage cache: a style, its head and the output of every pipeline stage
// (DESIGN.md: head → roots → masters → solve → members → color), so that a change re-runs
// only the stages from the first one it feeds (StyleField::stage, groom/style_schema.hpp)
// on. update() gives exactly the hair generate_hairstyle() gives for the same style, byte
// for byte.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/cancel.hpp"
#include "geometry/mesh_distance.hpp"
#include "groom/generate.hpp"
#include "groom/head.hpp"
#include "groom/style.hpp"
#include "groom/style_schema.hpp"
#include "solve/pipeline.hpp"

namespace wisp {

// Called as each stage of an update starts (the editor's progress events).
using StageProgress = std::function<void(Stage stage)>;

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
    // The same, abandoned as soon as `cancel` fires (a newer request arrived): the stage then
    // running publishes nothing, the cache stays stale from it (the stages that finished
    // before it stay done) and the result is null. `progress`, when given, is called as each
    // stage starts.
    const HairstyleResult* update(const CancelToken& cancel, const StageProgress& progress = {});
    // The solved masters, running the stages up to the solve only (the preview's first
    // answer while a solver parameter moves); null when cancelled.
    const Masters& update_masters();
    const Masters* update_masters(const CancelToken& cancel, const StageProgress& progress = {});
    // The first answer while a solver value (κ, τ, …) moves: when the solve is stale, a
    // coarse solve of every k-th wisp only (at most kPreviewWisps of them), each carrying the
    // strands of the k wisps from it on over a cross-section grown to match (so the density
    // field holds all the hair); the cache's stages are left as they were, and the full
    // update that follows solves every wisp exactly. When the solve is up to date, the solved
    // masters. Null when cancelled.
    static constexpr size_t kPreviewWisps = 700;
    const Masters* update_masters_preview(const CancelToken& cancel = {},
                                          const StageProgress& progress = {});
    // A preview of `strands` strands while a value moves: the stages up to the solve as
    // update() runs them (so they are done for the full update that follows), then the
    // members, cut, push out of the head and colour of only the first `strands` strands of
    // strand_order (edit/wire.hpp), strand i being strand_order[i] of the full hair. When the
    // members are up to date, or `strands` covers them all, it is the full hair (update()).
    // Null when cancelled.
    const Hair* update_preview(size_t strands, const CancelToken& cancel = {},
                               const StageProgress& progress = {});

    // What GET /api/hair?strands=N sends: encode_strands (edit/wire.hpp) of the first
    // min(N, all) strands of the whole hair in strand_order, byte for byte what encoding the
    // hair of update() would give (while the members are stale and fewer strands than all are
    // asked for, update_preview's subset, strand i being strand_order[i] of the full hair:
    // the same bytes unless the cut removes strands, which shifts them). Only
    // what the answer shows is computed: while the members are stale, the strands sent alone
    // (update_preview); while only the colour is, the colours of the strands sent alone (the
    // colour stage stays stale for the update that follows), written over the positions
    // encoded the last time, which a colour change leaves as they were. Null when cancelled.
    // The buffer is shared with the caller, who may keep it while sending it: the next call
    // encodes afresh rather than write into a buffer still held.
    std::shared_ptr<const std::string> hair_bytes(size_t strands, const CancelToken& cancel = {},
                                                  const StageProgress& progress = {});

    // The strands of the whole hair: the last full result's when the members are up to
    // date, else the member roots' (what update_preview draws its subset from).
    size_t strands_in_all() const {
        return stale_ > Stage::kMembers ? result_.hair.strand_count() : roots_.members.size();
    }
    // The stages hair_bytes(strands) reports as it runs them (a preview's members count as
    // one, its colours none), for a progress bar's length: 0 when nothing is stale. Counted
    // with the roots there are now, which stale roots may change.
    int stages_to_send(size_t strands) const {
        if (stale_ == Stage::kNone) return 0;
        if (stale_ <= Stage::kMembers && strands < strands_in_all())
            return int(Stage::kMembers) - int(stale_) + 1;
        return kStageCount - int(stale_);
    }

    // The last update's result: its solve stats (the groups' progress) are the current
    // style's once stale() is past Stage::kSolve, the rest once it is Stage::kNone.
    const HairstyleResult& result() const { return result_; }

    // How many times each stage ran (indexed by Stage, kHead … kColor), for tests and the
    // HUD, and how long it took the last time (ms).
    const std::array<int, kStageCount>& runs() const { return runs_; }
    const std::array<double, kStageCount>& last_ms() const { return last_ms_; }
    int head_field_runs() const { return head_field_runs_; }
    // How many times the styling field was built (kept while only κ, τ and the like move).
    int styling_field_runs() const { return styling_field_runs_; }
    // How long the last update_preview of a subset took after the solve (ms), and its two
    // parts: the members (growth, cut, push out of the head; about 0 when they grew beside
    // the solve, whose stage time then holds them) and their colours.
    double preview_ms() const { return preview_ms_; }
    double preview_members_ms() const { return preview_members_ms_; }
    double preview_color_ms() const { return preview_color_ms_; }
    // How long the last solve stage spent getting its styling field (0 when it was kept), and
    // the last hair_bytes call encoding (ms): with last_ms() and the preview's parts, the
    // stage breakdown of BM_EditMapStroke20k.
    double field_ms() const { return field_ms_; }
    // How many previews and members stages took members grown beside the solve (for tests:
    // the others grew them after it).
    int members_grown_beside() const { return members_grown_beside_; }
    double encode_ms() const { return encode_ms_; }

  private:
    void mark(Stage stage);
    // Runs the stale stages up to `last` inclusive; false when cancelled. With
    // `preview_strands` (fewer than all), a solve that runs makes beside it that preview's
    // colours (make_preview_colors) and, without a cut, its members (beside_members_,
    // follow_solve), on the core the solve's serial layers leave idle; with all of them, or
    // when `last` is the members stage or after, the whole hair's members.
    bool run_until(Stage last, const CancelToken& cancel, const StageProgress& progress,
                   size_t preview_strands = 0);
    // The colours of a preview of `strands` strands (color_stage's, to the bit, while the cut
    // removes no strand), made from the roots alone: a strand's colour is a function of its id
    // and its wisp (color_strands), and the wisp of strand_order[i] is the members stage's
    // (member_wisps). Run beside the solve, on the core its serial layers leave
    // idle, instead of after the members (2 ms of a 20,000-strand preview). Ready until the
    // next change (mark).
    void make_preview_colors(size_t strands);
    // The masters' details, frames and control points (synthesize_master_details) after the
    // masters stage made their outlines only.
    void complete_masters(const MasterPrototype& prototype);
    // The head field at the style's cell, built when missing or when solve.cell moved it.
    const HeadField& head_field();
    // The styling field for the current style and solve bounds, kept while they stay.
    const StylingField& styling_field_for(const Box3& bounds);
    // strand_order(n), kept: every preview and every answer of the same hair draws on it.
    const std::vector<uint32_t>& order(size_t n);

    Style style_;
    std::filesystem::path base_dir_;
    Head head_;
    std::optional<HeadField> head_field_;
    // scalp_surface(*head_.scalp) (groom/roots.hpp): the same for every roots run on the head.
    std::optional<MeshDistance> scalp_surface_;
    // The roots' map-independent draws for this head, seed and counts (6 MB for 100,000
    // strands): a map stroke only accepts or rejects them.
    std::optional<RootProposals> root_proposals_;
    float head_field_cell_ = 0.f, head_field_bridge_ = 0.f;
    Roots roots_;
    Masters masters_;         // as synthesized
    GroupSelection groups_;   // the constraint groups' wisps (the solve stage)
    HairstyleResult result_;  // hair, solved masters, stats
    std::optional<StylingField> field_;
    std::string field_key_;  // what field_ was built from (the fields feeding it, bounds)
    Hair preview_;           // the last update_preview of a subset
    // The members of the first beside_members_strands_ strands of strand_order (kWholeHair:
    // the whole hair, in its own order), grown beside the solve that made result_.masters, for
    // the update_preview or members stage that follows; until the next change (mark).
    static constexpr size_t kWholeHair = SIZE_MAX;
    std::optional<MembersResult> beside_members_;
    size_t beside_members_strands_ = 0;
    std::vector<Vec3f> preview_colors_;  // make_preview_colors', for the roots and style now
    bool preview_colors_ready_ = false;  // when they are
    std::vector<uint32_t> order_;        // strand_order(order_.size())
    // The last hair_bytes answer from the full hair: the members run it encodes (hair_run_)
    // and how many strands; its positions stay right while the members do.
    std::shared_ptr<std::string> bytes_;
    uint64_t bytes_run_ = 0;
    size_t bytes_strands_ = 0;
    uint64_t hair_run_ = 0;  // bumped each time the members stage publishes new hair
    // The last answer of a preview (hair_bytes of fewer strands than all while the members
    // are stale), written over by the next one once no one holds it.
    std::shared_ptr<std::string> preview_bytes_;
    Masters preview_masters_;  // the last coarse solve of update_masters_preview
    Stage stale_ = Stage::kRoots;
    std::array<int, kStageCount> runs_{};
    std::array<double, kStageCount> last_ms_{};
    int head_field_runs_ = 0;
    int styling_field_runs_ = 0;
    double preview_ms_ = 0.;
    double preview_members_ms_ = 0.;
    double preview_color_ms_ = 0.;
    double field_ms_ = 0.;
    int members_grown_beside_ = 0;
    double encode_ms_ = 0.;
};

}  // namespace wisp
