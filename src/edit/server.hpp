#pragma once
// The editor's HTTP server (cpp-httplib): the front end (web/, embedded at build time) and
// a JSON and binary API over a StageCache. Security (issue 16): bound to 127.0.0.1 unless
// told otherwise; requests whose Host or Origin is not the server's own are refused (DNS
// rebinding); every /api/ request carries the per-launch token; bodies are size-limited
// (1 MiB, a head upload 64 MiB: EditOptions);
// a bad value is a 400 naming the field and the reason.
//
// API (every path under /api/ needs `X-Wisp-Token: TOKEN` or `?token=TOKEN`):
//   GET  /api/schema          the style schema (edit/wire.hpp schema_json)
//   GET  /api/style           {"values": {path: value}, "toml": text, "stale": stage}
//   POST /api/set             {"path": "solve.stiffness", "value": 0.5} → {"stale": stage}
//                             or 400 {"field": path, "error": message}
//   POST /api/preset          {"name": "curly"}: the whole style from a shipped preset
//   GET  /api/presets         ["bangs", …]
//   GET  /api/hair?strands=N  the first N strands in shuffled order (encode_strands): fewer
//                             than all grow only those (StageCache::update_preview); a
//                             request overtaken by a newer one (or a set), before it starts
//                             or while its stages run, is cancelled and gets 409
//   GET  /api/masters         the solved masters (encode_masters): the first preview; 409
//                             as /api/hair; ?preview=1 while a slider moves: a coarse solve
//                             of every k-th wisp (StageCache::update_masters_preview)
//   GET  /api/head            the head mesh (encode_head)
//   GET  /api/stats           strands, points, stage runs and times
//   GET  /api/scalp           {"center", "crown", "max_polar_angle"}: the scalp's polar UV map
//                             (geometry/scalp.hpp), for painting in 3D
//   GET  /api/map?field=F     the scalp map F (maps.density, …) as the painter's image
//                             (encode_map); a procedural or constant map rasterized
//   POST /api/map?field=F&low=L&high=H   body: a PNG (2…1024 pixels a side) in scalp UV
//                             space: F becomes { image = "DOC.KEY.png", low, high } with these
//                             pixels (8-bit, as Save writes them) → {"stale", "value"}
//   GET  /api/files           {"document": name, "files": [the *.toml of the folder]}
//   POST /api/save            {"name": "x.toml"} (default: the document): the TOML and its
//                             painted maps (x.density.png, …) into the style's folder,
//                             atomically; a plain file name only → {"document", "files"}
//   POST /api/autosave        the same as DOC.autosave.toml (and its maps); the document
//                             keeps its name
//   POST /api/open            {"name": "x.toml"}: a style file of the folder, with its maps
//   POST /api/export          {"name": "x.hair"}: the full hair in any format `wisp` writes
//                             by extension (.usda .hair .obj .ply .data .npz)
//   GET  /api/events          progress of long runs, text/event-stream: edit/progress_events.hpp
//   /api/motion/…             the Motion mode (issue 17): edit/motion_routes.hpp
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "groom/style.hpp"

namespace wisp {

struct EditOptions {
    std::string host = "127.0.0.1";  // the address to bind; another one is the caller's risk
    int port = 0;                    // 0: a free port
    std::string token;               // empty: 128 random bits from /dev/urandom, in hex
    size_t max_body = 1 << 20;       // bytes of a request body
    // Bytes of a head upload's body (POST /api/head, an OBJ: realistic heads are megabytes);
    // every other route keeps max_body.
    size_t max_head_body = size_t(64) << 20;
    std::string document;  // the style's file name in base_dir ("untitled.toml")
};

class EditServer {
  public:
    // Loads the style's head (throws wisp::Error as load_head does).
    EditServer(Style style, std::filesystem::path base_dir, EditOptions options = {});
    ~EditServer();  // stops the server
    EditServer(const EditServer&) = delete;
    EditServer& operator=(const EditServer&) = delete;

    // Binds (throws wisp::Error if the address or port cannot be bound) and serves on a
    // thread of its own until stop().
    void start();
    // Stops serving and joins the thread; safe to call twice.
    void stop();

    int port() const;
    const std::string& token() const;
    // http://HOST:PORT/?token=TOKEN
    std::string url() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Whether the front end was built into this binary (Node and npm were found at build time).
bool editor_front_end_built();

}  // namespace wisp
