#pragma once
// The editor's Motion mode over HTTP (issue 17): the endpoints that start a MotionSession
// (motion_session.hpp) from the current style, drive it, send its frames and tree, record it
// and export the recorded animation as `wisp animate` writes it. The server's pre-routing
// handler already applies the Host/Origin rules and the token to every /api/ path; a bad
// value here is a 400 {"field", "error"}.
//
//   POST /api/motion/start    {"strands": 20000, "fps": 25, "single_level": false}: the
//                             current style's full hair becomes the rest shape (the stages
//                             run first if stale) → the session's description (below)
//   POST /api/motion/reset    a new session from the same rest shape and settings
//   POST /api/motion/stop     ends the session
//   POST /api/motion/play, /api/motion/pause, /api/motion/step (one frame, paused)
//   POST /api/motion/drag     {"rotate": [x, y, z] degrees, "translate": [x, y, z] cm}: the
//                             head about the neck pivot (the body follows the translation)
//   POST /api/motion/preset   {"name": "lean" | "shake" | "nod" | "jump" | "run"}
//   POST /api/motion/wind     {"direction": [x, y, z], "strength": cm/s, "gust": cm/s,
//                             "frequency": Hz}
//   POST /api/motion/dynamics {"path": "dynamics.stiffness", "value": 500}: a dynamics field
//                             the simulation reads at every step (stiffness, stretch,
//                             damping, air_drag, split_threshold, merge_velocity, friction,
//                             repulsion, repulsion_angle, iterations, hair_collisions,
//                             body_collisions), applied from the next step; the style
//                             reader's checks, then the simulation's (friction · dt < 1)
//   GET  /api/motion          the session's description and state: {"frame", "playing",
//                             "error", "shown", "points", "fps", "pivot", "head_center",
//                             "head_radius", "levels",
//                             "active_per_level", "splits", "merges", "step_ms", "skin_ms"}
//   GET  /api/motion/strands  the shown strands at rest (encode_strands: topology, colours)
//   GET  /api/motion/frame?after=N&wait=MS   the newest frame (encode_frame) if past N,
//                             waiting up to MS (≤ 1000) ms; 204 when none came. A slow client
//                             gets the newest and skips the rest: the simulation never waits.
//                             Headers X-Wisp-Head, X-Wisp-Body: the poses, 12 numbers each
//                             (rotation row by row, translation cm), head space → world
//   GET  /api/motion/stream?tree=1   the frames as they come (chunked, binary): a message
//                             (motion_session.hpp: the frame, the poses, the tree with
//                             tree=1, the splits and merges since the last message) for the
//                             newest frame whenever the client has taken the last one, so a
//                             slow client skips frames and the simulation never waits. Ends
//                             when the session is replaced or stopped, or the server stops.
//   GET  /api/motion/tree     the newest frame's tree (encode_tree)
//   POST /api/motion/record   {"name": "take.json"}: the recording as a motion file
//   POST /api/motion/export   {"name": "take.usda"} (value clips) or "take.hair" (frames
//                             take_0000.hair …; .obj and .ply too): the style as
//                             take.style.toml (with its painted maps), the recording as
//                             take.motion.json, and the recorded frames of the whole hair
//                             written by `wisp animate`'s writers from those files; with
//                             "png": true the frames as take_####.png and with "mp4": true
//                             as take.mp4 too, rendered as `wisp animate --png --mp4` does
//                             (a 400 naming "mp4" when ffmpeg is not on PATH) →
//                             {"files", "frames", "command"}: the command line that gives
//                             the same files
//   GET  /api/motion/export   the export's progress: {"exporting", "stage" (animating,
//                             rendering, encoding), "done", "frames"}
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "groom/head.hpp"
#include "groom/style.hpp"
#include "solve/pipeline.hpp"

namespace httplib {
class Server;
}

namespace wisp {

// What the routes need of the editor's server.
struct MotionHost {
    // Calls `use` with the current style, its head and its full hair (running the stale
    // stages), under the server's cache lock.
    std::function<void(
        const std::function<void(const Style&, const Head&, const HairstyleResult&)>&)>
        with_hair;
    // Writes `style` as `toml_name` into the style's folder with its painted maps beside it;
    // returns the file names written. Throws wisp::Error for a bad name.
    std::function<std::vector<std::string>(const Style&, const std::string&)> write_style;
    // `name` as a plain file name in the style's folder ending in one of `extensions`;
    // throws wisp::Error saying what is wrong.
    std::function<std::filesystem::path(const std::string&,
                                        std::initializer_list<std::string_view>)>
        file_in_folder;
};

class MotionRoutes {
  public:
    explicit MotionRoutes(MotionHost host);
    ~MotionRoutes();  // ends the session (joins its thread)
    MotionRoutes(const MotionRoutes&) = delete;
    MotionRoutes& operator=(const MotionRoutes&) = delete;

    // Adds the routes. The frame stream relies on the server's small socket send buffers
    // (EditServer sets them) to hold little in flight.
    void add_to(httplib::Server& server);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace wisp
