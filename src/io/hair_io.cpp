#include "io/hair_io.hpp"

#include "io/pbrt.hpp"
#include "io/rib.hpp"

#include <algorithm>
#include <sstream>

#include "core/error.hpp"
#include "io/cyhair.hpp"
#include "io/hairsalon.hpp"
#include "io/io_util.hpp"
#include "io/npz.hpp"
#include "io/obj_curves.hpp"
#include "io/ply.hpp"
#include "io/usda.hpp"

namespace wisp {

const char* hair_format_name(HairFormat format) {
    switch (format) {
        case HairFormat::kUsda:
            return "usda";
        case HairFormat::kHair:
            return "hair";
        case HairFormat::kObj:
            return "obj";
        case HairFormat::kPly:
            return "ply";
        case HairFormat::kData:
            return "data";
        case HairFormat::kRib:
            return "rib";
        case HairFormat::kPbrt:
            return "pbrt";
        case HairFormat::kNpz:
            return "npz";
    }
    return "?";
}

HairFormat hair_format_from_path(const std::filesystem::path& path) {
    const std::string ext = io_detail::lower_extension(path);
    if (ext == ".usda") return HairFormat::kUsda;
    if (ext == ".hair") return HairFormat::kHair;
    if (ext == ".obj") return HairFormat::kObj;
    if (ext == ".ply") return HairFormat::kPly;
    if (ext == ".data") return HairFormat::kData;
    if (ext == ".rib") return HairFormat::kRib;
    if (ext == ".pbrt") return HairFormat::kPbrt;
    if (ext == ".npz") return HairFormat::kNpz;
    fail(path.string(), ": unknown hair file extension \"", path.extension().string(),
         "\" (supported: .usda, .hair, .obj, .ply, .data; written only: .rib, .pbrt, .npz)");
}

Hair read_hair(const std::filesystem::path& path) {
    switch (hair_format_from_path(path)) {
        case HairFormat::kUsda:
            return read_usda(path);
        case HairFormat::kHair:
            return read_cyhair(path);
        case HairFormat::kObj:
            return read_obj_curves(path);
        case HairFormat::kPly:
            return read_ply(path);
        case HairFormat::kData:
            return read_hairsalon(path);
        case HairFormat::kRib:
        case HairFormat::kPbrt:
            fail(path.string(), ": .rib and .pbrt are scenes wisp writes but does not read");
        case HairFormat::kNpz:
            fail(path.string(), ": .npz is written for numpy; wisp does not read it");
    }
    fail(path.string(), ": unreachable");
}

void write_hair(const std::filesystem::path& path, const Hair& hair,
                const HairWriteOptions& options) {
    switch (hair_format_from_path(path)) {
        case HairFormat::kUsda:
            return write_usda(path, hair,
                              UsdaWriteOptions{.z_up = options.usda_z_up,
                                               .guides = options.usda_guides,
                                               .head = options.usda_head,
                                               .head_scalp = options.usda_head_scalp,
                                               .precision = options.usda_precision});
        case HairFormat::kHair:
            return write_cyhair(path, hair);
        case HairFormat::kObj:
            return write_obj_curves(path, hair, options.obj_segments);
        case HairFormat::kPly:
            return write_ply(path, hair);
        case HairFormat::kData:
            return write_hairsalon(
                path, hair, options.resample_points ? options.resample_points : kHairSalonPoints);
        case HairFormat::kNpz:
            return write_npz(
                path, hair,
                NpzWriteOptions{.points_per_strand =
                                    options.resample_points ? options.resample_points : 32});
        case HairFormat::kRib:
            return write_rib(path, hair, options.camera);
        case HairFormat::kPbrt:
            return write_pbrt(path, hair, options.camera);
    }
}

namespace {

void summarize(const Hair& hair, HairFileInfo& info) {
    info.strands = hair.strand_count();
    info.points = hair.point_count();
    info.min_points = info.strands ? SIZE_MAX : 0;
    for (size_t s = 0; s < info.strands; ++s) {
        info.min_points = std::min<size_t>(info.min_points, hair.strand_size(s));
        info.max_points = std::max<size_t>(info.max_points, hair.strand_size(s));
    }
    info.mean_points = info.strands ? double(info.points) / double(info.strands) : 0.0;
    info.bounds = hair.bounds();
    info.has_widths = !hair.widths.empty();
    info.has_colors = !hair.colors.empty();
    info.has_wisp_ids = !hair.wisp.empty();
    if (hair.widths.empty()) {
        info.min_width = info.max_width = hair.default_width;
    } else {
        const auto [lo, hi] = std::minmax_element(hair.widths.begin(), hair.widths.end());
        info.min_width = *lo;
        info.max_width = *hi;
    }
}

}  // namespace

HairFileInfo hair_file_info(const std::filesystem::path& path) {
    HairFileInfo info;
    info.path = path;
    info.format = hair_format_from_path(path);
    std::error_code ec;
    info.file_bytes = std::filesystem::file_size(path, ec);
    if (ec) fail(path.string(), ": cannot open: ", ec.message());
    switch (info.format) {
        case HairFormat::kUsda: {
            UsdaLayer layer = read_usda_layer(path);
            bool all_valid = true;
            for (const UsdCurves& c : layer.curves) {
                UsdPrimSummary p;
                p.path = c.path;
                p.type = c.type;
                p.basis = c.basis;
                p.wrap = c.wrap;
                p.curves = c.counts.size();
                p.points = c.points.size();
                for (size_t i = 0; i < c.counts.size(); ++i)
                    p.segments += usd_segment_count(c, i);
                p.widths_interpolation = c.widths.empty() ? ""
                                         : c.widths_interpolation.empty()
                                             ? usd_interpolation_for_size(c, c.widths.size())
                                             : c.widths_interpolation;
                p.has_colors = !c.display_color.empty();
                p.problem = usd_curves_problem(c);
                all_valid &= p.problem.empty();
                info.usd_prims.push_back(std::move(p));
            }
            if (!all_valid)
                std::erase_if(layer.curves,
                              [](const UsdCurves& c) { return !usd_curves_problem(c).empty(); });
            summarize(hair_from_usda(layer, path.string()), info);
            break;
        }
        case HairFormat::kData: {
            HairSalonStats stats;
            summarize(read_hairsalon(path, &stats), info);
            info.skipped_strands = stats.bare_roots;
            break;
        }
        default:
            summarize(read_hair(path), info);
            break;
    }
    return info;
}

std::string describe(const HairFileInfo& info) {
    std::ostringstream o;
    o << info.path.string() << ": " << hair_format_name(info.format) << ", " << info.file_bytes
      << " bytes\n";
    o << "  strands " << info.strands << ", points " << info.points << " (per strand min "
      << info.min_points << ", max " << info.max_points << ", mean " << info.mean_points << ")\n";
    if (!info.bounds.empty())
        o << "  bounds (" << info.bounds.lo.x() << ", " << info.bounds.lo.y() << ", "
          << info.bounds.lo.z() << ") .. (" << info.bounds.hi.x() << ", " << info.bounds.hi.y()
          << ", " << info.bounds.hi.z() << ") cm\n";
    o << "  widths " << (info.has_widths ? "per point" : "default") << " " << info.min_width
      << " .. " << info.max_width << " cm, colors " << (info.has_colors ? "per strand" : "default")
      << ", wisp ids " << (info.has_wisp_ids ? "yes" : "no") << "\n";
    if (info.skipped_strands) o << "  skipped " << info.skipped_strands << " bare roots\n";
    for (const UsdPrimSummary& p : info.usd_prims) {
        o << "  prim " << p.path << ": " << p.type;
        if (p.type == "cubic") o << " " << p.basis;
        o << " " << p.wrap << ", " << p.curves << " curves, " << p.points << " points, "
          << p.segments << " segments";
        if (!p.widths_interpolation.empty()) o << ", " << p.widths_interpolation << " widths";
        if (p.has_colors) o << ", displayColor";
        if (!p.problem.empty()) o << "  INVALID: " << p.problem;
        o << "\n";
    }
    return o.str();
}

}  // namespace wisp
