#include "io/pbrt.hpp"

#include <cmath>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/io_util.hpp"

namespace wisp {
namespace {

using io_detail::append_number;
using io_detail::append_vec;

}  // namespace

std::string encode_pbrt(const Hair& hair, const ExportCamera& camera,
                        const std::string& image_name) {
    Vec3f right, up, forward;  // pbrt takes LookAt itself; this only validates the camera
    export_camera_basis(camera, "pbrt", right, up, forward);
    const float fov = shorter_side_fov(camera);

    std::string out;
    out.reserve(1024 + hair.point_count() * 60);
    out += "# wisp hair: ";
    append_number(out, static_cast<uint64_t>(hair.strand_count()));
    out += " strands, centimetres, Catmull-Rom converted to Bezier (Choe & Ko 2005, section 5)\n";
    // pbrt's default camera space is left-handed; flipping x keeps the image unmirrored.
    out += "Scale -1 1 1\nLookAt ";
    append_vec(out, camera.eye);
    out += "  ";
    append_vec(out, camera.target);
    out += "  ";
    append_vec(out, camera.up);
    out += "\nCamera \"perspective\" \"float fov\" [ ";
    append_number(out, fov);
    out += " ]\nFilm \"rgb\" \"integer xresolution\" [ ";
    append_number(out, camera.width);
    out += " ] \"integer yresolution\" [ ";
    append_number(out, camera.height);
    out += " ]\n    \"string filename\" [ \"" + image_name + "\" ]\n";
    out += "Sampler \"zsobol\" \"integer pixelsamples\" [ 64 ]\n";
    out += "Integrator \"volpath\" \"integer maxdepth\" [ 30 ]\n";
    out += "WorldBegin\n";
    out += "LightSource \"distant\" \"point3 from\" [ ";
    append_vec(out, camera.key_direction);
    out += " ] \"point3 to\" [ 0 0 0 ] \"float scale\" [ ";
    append_number(out, camera.key_intensity);
    out += " ]\nLightSource \"infinite\" \"rgb L\" [ 0.15 0.15 0.16 ]\n";

    out += "AttributeBegin\n";
    bool have_color = false;
    Vec3f last_color = Vec3f::Zero();
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const auto p = hair.strand(s);
        const size_t n = p.size();
        if (n < 2) continue;
        const Vec3f color = hair.color_of(s).cwiseMax(Vec3f::Zero()).cwiseMin(Vec3f::Ones());
        if (!have_color || color != last_color) {
            out += "Material \"hair\" \"rgb reflectance\" [ ";
            append_vec(out, color);
            out += " ]\n";
            have_color = true;
            last_color = color;
        }
        out +=
            "Shape \"curve\" \"string type\" \"cylinder\" \"string basis\" \"bezier\" "
            "\"integer degree\" [ 3 ]\n    \"point3 P\" [ ";
        for (size_t i = 0; i + 1 < n; ++i) {
            const Vec3f& p1 = p[i];
            const Vec3f& p2 = p[i + 1];
            const Vec3f p0 = i > 0 ? p[i - 1] : Vec3f(2.f * p1 - p2);
            const Vec3f p3 = i + 2 < n ? p[i + 2] : Vec3f(2.f * p2 - p1);
            if (i == 0) {
                append_vec(out, p1);
                out += ' ';
            }
            append_vec(out, p1 + (p2 - p0) / 6.f);
            out += ' ';
            append_vec(out, p2 - (p3 - p1) / 6.f);
            out += ' ';
            append_vec(out, p2);
            out += ' ';
        }
        const size_t first = hair.offsets[s];
        out += "]\n    \"float width0\" [ ";
        append_number(out, hair.width_at(first));
        out += " ] \"float width1\" [ ";
        append_number(out, hair.width_at(first + n - 1));
        out += " ]\n";
    }
    out += "AttributeEnd\n";
    return out;
}

void write_pbrt(const std::filesystem::path& path, const Hair& hair, const ExportCamera& camera) {
    write_file_atomic(path, encode_pbrt(hair, camera, path.stem().string() + ".exr"));
}

}  // namespace wisp
