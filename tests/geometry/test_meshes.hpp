#pragma once
// The meshes the geometry tests share: the MakeHuman files of ../shared/data (decimetres;
// a test skips when they are absent) and the built-in figure, built once.
#include <string>

#include "geometry/builtin_head.hpp"

namespace wisp::test {

// Head, neck and shoulders (open at y = 5 dm) and the whole body with its helper shells.
inline const std::string kHeadNeckShoulders =
    WISP_SHARED_DIR "/data/heads/makehuman/makehuman_hm08_head_neck_shoulders.obj";
inline const std::string kBase = WISP_SHARED_DIR "/data/heads/makehuman/makehuman_hm08_base.obj";

inline const Mesh& builtin_mesh() {
    static const Mesh mesh = builtin_head_mesh();
    return mesh;
}

}  // namespace wisp::test
