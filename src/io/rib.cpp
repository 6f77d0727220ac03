#include "io/rib.hpp"

#include <algorithm>
#include <cmath>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/io_util.hpp"

namespace wisp {
namespace {

using io_detail::append_number;
using io_detail::append_vec;

constexpr size_t kCurvesPerCall = 10000;

}  // namespace

std::string encode_rib(const Hair& hair, const ExportCamera& camera,
                       const std::string& image_name) {
    Vec3f r, u, f;
    export_camera_basis(camera, "RIB", r, u, f);
    const float fov = shorter_side_fov(camera);

    std::string out;
    out.reserve(64 + hair.point_count() * 40);
    out += "##RenderMan RIB\n# wisp hair: ";
    append_number(out, static_cast<uint64_t>(hair.strand_count()));
    out += " strands, centimetres, Catmull-Rom curves (Choe & Ko 2005, section 5)\n";
    out += "version 3.04\n";
    out += "Display \"" + image_name + "\" \"file\" \"rgba\"\n";
    out += "Format ";
    append_number(out, camera.width);
    out += ' ';
    append_number(out, camera.height);
    out += " 1\nPixelSamples 4 4\nProjection \"perspective\" \"fov\" [";
    append_number(out, fov);
    // Row-vector convention: p_camera = p_world · M.
    out += "]\nTransform [";
    const float m[16] = {r.x(),
                         u.x(),
                         f.x(),
                         0.f,
                         r.y(),
                         u.y(),
                         f.y(),
                         0.f,
                         r.z(),
                         u.z(),
                         f.z(),
                         0.f,
                         -r.dot(camera.eye),
                         -u.dot(camera.eye),
                         -f.dot(camera.eye),
                         1.f};
    for (int i = 0; i < 16; ++i) {
        if (i) out += ' ';
        append_number(out, m[i]);
    }
    out += "]\nWorldBegin\n";
    out += "LightSource \"ambientlight\" 1 \"intensity\" [0.1]\n";
    out += "LightSource \"distantlight\" 2 \"from\" [";
    append_vec(out, camera.key_direction);
    out += "] \"to\" [0 0 0] \"intensity\" [";
    append_number(out, camera.key_intensity);
    // A standard shader every RenderMan-compliant renderer ships; swap in a Kajiya-Kay hair
    // shader (the paper's) where one is available.
    out +=
        "]\nSurface \"plastic\" \"Ks\" [0.4] \"roughness\" [0.08]\nBasis \"catmull-rom\" 1 "
        "\"catmull-rom\" 1\n";

    std::vector<size_t> strands;
    for (size_t s = 0; s < hair.strand_count(); ++s)
        if (hair.strand_size(s) >= 2) strands.push_back(s);
    for (size_t begin = 0; begin < strands.size(); begin += kCurvesPerCall) {
        const size_t end = std::min(strands.size(), begin + kCurvesPerCall);
        out += "Curves \"cubic\" [";
        for (size_t k = begin; k < end; ++k) {
            if (k > begin) out += ' ';
            append_number(out, static_cast<uint64_t>(hair.strand_size(strands[k]) + 2));
        }
        out += "] \"nonperiodic\"\n\"P\" [";
        for (size_t k = begin; k < end; ++k) {
            const auto p = hair.strand(strands[k]);
            const size_t n = p.size();
            append_vec(out, 2.f * p[0] - p[1]);
            for (const Vec3f& q : p) {
                out += ' ';
                append_vec(out, q);
            }
            out += ' ';
            append_vec(out, 2.f * p[n - 1] - p[n - 2]);
            out += '\n';
        }
        out += "]\n\"width\" [";
        for (size_t k = begin; k < end; ++k) {
            const size_t first = hair.offsets[strands[k]];
            for (size_t i = 0; i < hair.strand_size(strands[k]); ++i) {
                if (k > begin || i) out += ' ';
                append_number(out, hair.width_at(first + i));
            }
        }
        out += "]\n\"uniform color Cs\" [";
        for (size_t k = begin; k < end; ++k) {
            if (k > begin) out += ' ';
            append_vec(out, hair.color_of(strands[k]));
        }
        out += "]\n";
    }
    out += "WorldEnd\n";
    return out;
}

void write_rib(const std::filesystem::path& path, const Hair& hair, const ExportCamera& camera) {
    write_file_atomic(path, encode_rib(hair, camera, path.stem().string() + ".tif"));
}

}  // namespace wisp
