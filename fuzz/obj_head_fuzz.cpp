// libFuzzer harness for OBJ head meshes (geometry/mesh.hpp, tinyobjloader): the reader takes
// only a path. What it returns must index only what it holds.
#include <cmath>

#include "fuzz_util.hpp"
#include "geometry/mesh.hpp"

namespace {

template <typename Index>
bool in_range(const std::vector<Index>& items, size_t size) {
    for (const Index& item : items)
        for (int k = 0; k < item.size(); ++k)
            if (item[k] < 0 || static_cast<size_t>(item[k]) >= size) return false;
    return true;
}

bool labels_in_range(const std::vector<int32_t>& labels, size_t faces, size_t names) {
    if (labels.empty()) return true;
    if (labels.size() != faces) return false;
    for (int32_t l : labels)
        if (l < -1 || l >= static_cast<int64_t>(names)) return false;
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    static fuzz::ScratchFile file(".obj");
    const auto mesh = fuzz::attempt([&] { return read_obj_mesh(file.write(data, size)); });
    if (!mesh) return 0;
    for (const Vec3f& v : mesh->vertices)
        if (!v.allFinite()) fuzz::broken("a head mesh vertex is not finite");
    if (!in_range(mesh->faces, mesh->vertices.size()))
        fuzz::broken("a face indexes a vertex the mesh does not hold");
    if (!mesh->face_uvs.empty() && (mesh->face_uvs.size() != mesh->faces.size() ||
                                    !in_range(mesh->face_uvs, mesh->uvs.size())))
        fuzz::broken("a face indexes a texture coordinate the mesh does not hold");
    if (!labels_in_range(mesh->face_group, mesh->faces.size(), mesh->group_names.size()) ||
        !labels_in_range(mesh->face_material, mesh->faces.size(), mesh->material_names.size()))
        fuzz::broken("a face's group or material is out of range");
    return 0;
}
