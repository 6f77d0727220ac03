#pragma once
// The names of per-frame files, as `wisp animate` and the editor's Motion export write them.
#include <string>

namespace wisp {

// `name` itself when it holds a run of '#'; else "_####" before its extension
// ("take.hair" -> "take_####.hair").
std::string numbered_pattern(const std::string& name);

// numbered_pattern(name) with its run of '#' replaced by `frame`, zero-padded to the run's
// length (longer numbers keep every digit).
std::string numbered(const std::string& name, int frame);

}  // namespace wisp
