#pragma once
// The editor's routes for placing constraints, the views, the final picture and the head
// (issue 16 items 4, 5 and 7), beside the core ones in server.cpp. Every path is under /api/,
// so the server's pre-routing checks (Host, Origin, token) guard it.
//
//   GET  /api/constraints       {"sections": [...]} (edit/constraint_sections.hpp)
//   POST /api/constraints       {"sections": [...]}: the style's groups become what they
//                               expand into → {"stale"}; 400 {"field": "tie[0].point", …}
//   GET  /api/selection?key=K   the painted selection K as the painter's image (encode_map,
//                               128² of zeros when none is painted yet)
//   POST /api/selection?key=K   body: a PNG in scalp UV space (2…1024 pixels a side): the
//                               selection K; wisps whose root lies where it is > 0.5
//   GET  /api/report            {"solved", "joints", "unresolved", "constrained",
//                               "points_inside_head", "groups": [{name, wisps, constraints,
//                               completed, met: [fraction per constraint]}]}: the last
//                               update's figures (null where that stage is stale)
//   GET  /api/attributes?strands=N  "WISPATTR", uint32 version (2), strands S', then int32
//                               wisp[S'], int32 group[S'], float32 progress[S'] of the
//                               strands /api/hair?strands=N sends, in its order (group 0: in
//                               none); progress: the fraction of its group's queue the
//                               strand's wisp met (SolveStats::wisp_met, the count the
//                               groups' progress is made of), -1 for a strand in no group
//   POST /api/render            {"eye", "target", "up": [x, y, z] cm, "fov": degrees,
//                               "width", "height": 16…1024}: wisp's renderer's picture of the
//                               full hair from that camera, as a PNG
//   POST /api/head?name=x.obj&scale=S&method=M   body: an OBJ head mesh, read by the OBJ
//                               reader and written atomically into the style's folder; the
//                               style's head becomes it → {"stale", "values"}. The body may
//                               be up to EditOptions::max_head_body (64 MiB; other routes
//                               1 MiB)
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>

#include "edit/constraint_sections.hpp"
#include "edit/progress_events.hpp"
#include "edit/stage_cache.hpp"

// httplib.h is left to the .cpp, after Eigen: its <resolv.h> defines `_res`, a name Eigen's
// headers use.
namespace httplib {
class Server;
}

namespace wisp {

// What the routes share with the server (server.cpp's Impl owns all of it).
struct EditState {
    StageCache& cache;
    std::mutex& cache_mutex;                // held while the cache is used
    std::atomic<uint64_t>& hair_requests;   // the newest request wins (server.cpp)
    const std::filesystem::path& base_dir;  // the style's folder
    std::string& document;                  // the style's file name in base_dir
    ConstraintSections& constraints;
    ProgressEvents& events;  // the long runs' progress (GET /api/events)
};

void add_feature_routes(httplib::Server& server, EditState& state);

}  // namespace wisp
