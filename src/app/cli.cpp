#include "app/cli.hpp"
#include "app/dataset_command.hpp"
#include "app/edit_command.hpp"
#include "app/head_args.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <thread>

#include "app/progress.hpp"
#include "app/stats.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "dataset/metrics.hpp"
#include "dynamics/animate.hpp"
#include "dynamics/animation_pictures.hpp"
#include "geometry/builtin_head.hpp"
#include "groom/generate.hpp"
#include "groom/style_toml.hpp"
#include "io/frame_files.hpp"
#include "io/hair_io.hpp"
#include "io/usda.hpp"
#include "render/camera.hpp"
#include "render/export_view.hpp"
#include "render/render.hpp"
#include "solve/coverage.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

constexpr const char* kVersion = "0.1.0";
// Errors are printed on one line, control characters escaped, at most this long: the net
// under the readers' own excerpts of what they quote.
constexpr size_t kMaxMessageBytes = 2000;

// "x,y,z" → a finite vector.
Vec3f parse_vec3(const std::string& flag, const std::string& text) {
    Vec3f v;
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (int i = 0; i < 3; ++i) {
        const auto r = std::from_chars(p, end, v[i]);
        const bool sep_ok = i < 2 ? (r.ptr < end && *r.ptr == ',') : r.ptr == end;
        if (r.ec != std::errc() || !sep_ok || !std::isfinite(v[i]))
            throw CLI::ValidationError(flag, "expects three numbers x,y,z, got '" + text + "'");
        p = r.ptr + 1;
    }
    return v;
}

// "x,y,z" or "x,y,z,radius" → a tie (hierarchy.hpp).
Tie parse_tie(const std::string& text) {
    const size_t last = text.rfind(',');
    const bool has_radius = std::count(text.begin(), text.end(), ',') == 3;
    Tie tie;
    tie.point = parse_vec3("--tie", has_radius ? text.substr(0, last) : text);
    if (has_radius) {
        const char* begin = text.data() + last + 1;
        const char* end = text.data() + text.size();
        const auto r = std::from_chars(begin, end, tie.radius);
        if (r.ec != std::errc() || r.ptr != end || !(tie.radius > 0) || !std::isfinite(tie.radius))
            throw CLI::ValidationError("--tie",
                                       "expects x,y,z or x,y,z,radius with a radius > 0, "
                                       "got '" +
                                           text + "'");
    }
    return tie;
}

// Look options shared by `render` and `generate --png`.
struct LookArgs {
    std::string eye, target, background;
    float fov = 30.f;
    float specular_exponent = 80.f, specular_strength = -1.f;
    std::string shading = "hair";
    float rim = 1.f;
    bool no_shadows = false;

    void add_to(CLI::App* cmd) {
        cmd->add_option("--eye", eye, "Camera position x,y,z in cm (with --target)");
        cmd->add_option("--target", target, "Point the camera looks at, x,y,z in cm");
        cmd->add_option("--fov", fov, "Vertical field of view, degrees")
            ->check(CLI::Range(1.f, 170.f))
            ->capture_default_str();
        cmd->add_option("--background", background, "Background linear RGB r,g,b in [0,1]");
        cmd->add_option("--shading", shading,
                        "hair: the highlights of real hair (Marschner's shifted lobes); "
                        "fiber: the fibre model of path tracers (Chiang et al. 2016) with "
                        "melanin and multiple scattering; kajiya-kay: the paper's model")
            ->check(CLI::IsMember(shading_names()))
            ->capture_default_str();
        cmd->add_option("--specular-exponent", specular_exponent, "Kajiya-Kay specular exponent")
            ->check(CLI::Range(1.f, 10000.f))
            ->capture_default_str();
        cmd->add_option("--specular", specular_strength,
                        "Highlight strength: Kajiya-Kay's k_s (0.5), or a factor on the hair "
                        "shading's highlights (1; 0 shows the hair's own colour)")
            ->check(CLI::Range(0.f, 100.f));
        cmd->add_option("--rim", rim,
                        "Rim (back) light strength, a factor on the default's (0: off)")
            ->check(CLI::Range(0.f, 100.f))
            ->capture_default_str();
        cmd->add_flag("--no-shadows", no_shadows, "Render without self-shadowing");
    }
    void apply(RenderOptions& o) const {
        if (eye.empty() != target.empty())
            throw CLI::ValidationError("--eye", "--eye and --target go together");
        if (!eye.empty())
            o.look_at = LookAt{parse_vec3("--eye", eye), parse_vec3("--target", target)};
        o.fov_y_degrees = fov;
        if (!background.empty()) o.background = parse_vec3("--background", background);
        o.shading = parse_shading(shading);
        o.specular_exponent = specular_exponent;
        if (specular_strength >= 0.f) {
            o.specular_strength = specular_strength;
            o.hair.primary *= specular_strength;
            o.hair.secondary *= specular_strength;
        }
        o.rim.color *= rim;
        o.shadows = !no_shadows;
    }
};

// --precision of every command that writes .usda (generate, convert, animate).
void add_precision_option(CLI::App* cmd, int& precision) {
    cmd->add_option("--precision", precision,
                    ".usda: significant digits of the strands' numbers, 1-9, for a smaller "
                    "file (each value within half a unit of its last digit); default: the "
                    "shortest form that reads back exactly")
        ->check(CLI::Range(1, kMaxUsdaPrecision));
}

// What every hair output of generate and convert shares: a subset of the strands, the points
// per strand of the resampling formats (.npz, .data) and the .usda precision.
struct ExportArgs {
    size_t strands = 0;   // --export-strands; 0: all
    double fraction = 0;  // --export-fraction; 0: all
    int resample = 0;     // --resample; 0: the format's own
    int precision = 0;    // --precision; 0: shortest exact

    void add_to(CLI::App* cmd) {
        cmd->add_option("--export-strands", strands,
                        "Write only N of the strands, spread evenly over them (deterministic)")
            ->check(CLI::Range(size_t(1), size_t(1) << 32));
        cmd->add_option("--export-fraction", fraction,
                        "Write only this fraction (0, 1] of the strands, spread evenly")
            ->check(CLI::Range(1e-9, 1.0));
        cmd->add_option("--resample", resample,
                        ".npz and .data: points per strand, evenly spaced along each strand "
                        "(default: .npz 32, .data 100 as USC-HairSalon has them)")
            ->check(CLI::Range(2, 4096));
        add_precision_option(cmd, precision);
    }
    void check() const {
        if (strands && fraction > 0)
            throw CLI::ValidationError("--export-strands and --export-fraction: give one");
    }
    // The strands to write (all of them when no subset was asked for).
    Hair apply(Hair hair) const {
        check();
        const size_t S = hair.strand_count();
        size_t n = S;
        if (strands) n = std::min(S, strands);
        if (fraction > 0)
            n = std::max<size_t>(1, static_cast<size_t>(std::llround(fraction * double(S))));
        if (n >= S) return hair;
        const std::vector<uint32_t> keep = even_subset(S, n);
        return select_strands(hair, keep);
    }
};

struct GenerateArgs {
    std::string style_path;
    std::string preset;
    std::vector<std::string> outputs;
    std::string seed;
    int threads = 0, strands = 0, wisps = 0;
    std::string stats;
    bool obj_segments = false;
    std::string up = "y";  // .usda up axis: "y" (head space) or "z"
    ExportArgs exports;
    bool guides = false, with_head = false;
    HeadArgs head;
    bool quiet = false;
    std::string png;
    std::string views;
    std::string size = "1024x1024";
    LookArgs look;
};

// "WxH" → (W, H), each in [16, 16384].
std::pair<int, int> parse_size(const std::string& text) {
    const size_t x = text.find('x');
    int w = 0, h = 0;
    if (x != std::string::npos) {
        const char* b = text.data();
        const auto r1 = std::from_chars(b, b + x, w);
        const auto r2 = std::from_chars(b + x + 1, b + text.size(), h);
        if (r1.ec == std::errc() && r1.ptr == b + x && r2.ec == std::errc() &&
            r2.ptr == b + text.size() && w >= 16 && h >= 16 && w <= 16384 && h <= 16384)
            return {w, h};
    }
    throw CLI::ValidationError("--size",
                               "expects WxH with each side in [16, 16384], got '" + text + "'");
}

std::vector<std::string> split_views(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        if (comma > start) out.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return out;
}

// The picture options of --size, --eye, --target, --background ... and the views, all
// checked (CLI::ValidationError) before any work starts.
struct PngArgs {
    RenderOptions options;
    std::vector<std::string> views;
};
PngArgs png_args(const std::string& views, const std::string& size, const LookArgs& look,
                 const char* views_flag) {
    PngArgs a;
    std::tie(a.options.width, a.options.height) = parse_size(size);
    look.apply(a.options);
    if (a.options.look_at && a.options.look_at->eye == a.options.look_at->target)
        throw CLI::ValidationError("--eye", "the camera cannot look at its own position");
    a.views = split_views(views.empty() ? "three-quarter" : views);
    if (a.views.empty())
        throw CLI::ValidationError(views_flag, "names no view, got '" + excerpt(views) + "'");
    const auto& names = view_names();
    for (const std::string& v : a.views)
        if (v != "three_quarter" && std::find(names.begin(), names.end(), v) == names.end()) {
            std::string list;
            for (const std::string& n : names)
                list += (list.empty() ? "" : ", ") + n;
            throw CLI::ValidationError(views_flag,
                                       "unknown view '" + excerpt(v) + "' (views: " + list + ")");
        }
    return a;
}

// Fails (wisp::Error) unless `path` can be written: its folder exists and is writable, or
// can be created under a writable folder. Checked before any work starts.
void check_writable(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) fail(path, ": is a folder, not a file");
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    // The nearest folder that exists: the writer creates the ones below it.
    while (!fs::exists(dir, ec)) {
        if (!dir.has_parent_path()) {
            dir = ".";  // a relative folder to create in the current one (`-o out/a.usda`)
            break;
        }
        if (dir.parent_path() == dir) break;
        dir = dir.parent_path();
    }
    if (!fs::is_directory(dir, ec))
        fail(path, ": cannot write: ", dir.string(), " is not a folder");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        fail(path, ": cannot write in ", dir.string(), ": ", std::strerror(errno));
}

// Checks an output hair file: its format is one wisp knows, and it can be written.
void check_hair_output(const std::string& path) {
    hair_format_from_path(path);
    check_writable(path);
}

// Renders hair (and the head) to a PNG: one view, or a contact sheet of several.
void render_png(const std::string& path, const Hair& hair, const Mesh& head, const PngArgs& png,
                bool quiet) {
    RenderOptions options = png.options;
    const std::vector<std::string>& list = png.views;
    if (list.size() == 1) {
        options.view = list[0];
        write_png(path, render(hair, &head, options));
    } else {
        Progress progress("rendering view", static_cast<int>(list.size()), quiet);
        write_png(path,
                  contact_sheet(hair, &head, list, options, [&](int done, const std::string& view) {
                      progress.step(done, view);
                  }));
    }
}

Style resolve_style(const std::string& path, const std::string& preset) {
    if (!path.empty() && !preset.empty())
        throw CLI::ValidationError("give a style file or --preset, not both");
    if (!path.empty()) return load_style(path);
    return load_preset(preset.empty() ? "default" : preset);
}

// generate_hairstyle, its errors named by the style they come from (its file, or its preset):
// what fails once the style and the head are read is the style's values on that head.
// Runs `work` on a style read from `path` (or the preset `preset`): an error it throws names
// the style first, so that a message about the head or the grid says which style asked.
template <typename Work>
auto with_style_named(const std::string& path, const std::string& preset, Work&& work) {
    try {
        return work();
    } catch (const Error& e) {
        fail(path.empty() ? "preset '" + (preset.empty() ? "default" : preset) + "'" : path, ": ",
             e.what());
    }
}

HairstyleResult generate_named(const Style& style, const Head& head, const std::string& path,
                               const std::string& preset) {
    return with_style_named(path, preset, [&] { return generate_hairstyle(style, head); });
}

// A picture's file: PNG is the one format the renderer writes, so another extension is a
// mistake to report before the work, not a PNG under a misleading name.
void check_png_output(const std::string& path, const char* option) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".png")
        throw CLI::ValidationError(
            option, "writes PNG pictures: give a name ending in .png, got '" + path + "'");
}

uint64_t parse_seed(const std::string& text) {
    if (text == "random") {
        std::random_device device;
        return (static_cast<uint64_t>(device()) << 32) | device();
    }
    uint64_t value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end)
        throw CLI::ValidationError(
            "--seed", "expects a non-negative integer or 'random', got '" + text + "'");
    return value;
}

void info(bool quiet, const std::string& line) {
    if (!quiet) std::cerr << line << '\n';
}

// How much of the face the hair veils and how much scalp it leaves bare from the top, back
// and sides (solve/coverage.hpp), the part line and the hairline's soft edge left out.
nlohmann::json coverage_stats(const Hair& hair, const Head& head, const Style& style) {
    const FaceLandmarks face = face_landmarks(head);
    const HeadFrame frame = head_frame(*head.scalp);
    nlohmann::json j;
    j["face_covered"] = face_coverage(hair, *head.mesh, face.eye_y, face.chin_y).fraction();
    j["face_window_cm"] = {{"eye_y", face.eye_y}, {"chin_y", face.chin_y}, {"half_width", 4.5}};
    const auto parting = [&](const Vec3f& p) {
        return on_part(style.growth, (p - frame.center).normalized(), 1.2f / frame.radius);
    };
    for (const char* view : {"top", "back", "left", "right"}) {
        const Coverage c =
            scalp_coverage(hair, *head.scalp, ortho_view(view), parting, 1.f, &style.hairline);
        j["scalp_bare"][view] = c.cells ? 1.f - c.fraction() : 0.f;
    }
    return j;
}

int run_generate(const GenerateArgs& args) {
    Stopwatch total;
    Style style = resolve_style(args.style_path, args.preset);
    args.head.apply(style);
    if (!args.seed.empty()) style.seed = parse_seed(args.seed);
    if (args.strands > 0) style.strands = args.strands;
    if (args.wisps > 0) style.wisps = args.wisps;
    if (args.wisps > 0 && style.wisps > style.strands)
        throw CLI::ValidationError(
            "--wisps", cat("more wisps (", style.wisps, ") than strands (", style.strands, ")"));
    style.wisps = std::min(style.wisps, style.strands);
    // Every argument and output is checked before the work starts: a mistake found after
    // it would cost the whole generation.
    for (const std::string& out : args.outputs)
        check_hair_output(out);
    args.exports.check();
    if (args.guides || args.with_head) {
        bool usda = false;
        for (const std::string& out : args.outputs)
            usda |= hair_format_from_path(out) == HairFormat::kUsda;
        if (!usda)
            throw CLI::ValidationError(args.guides ? "--guides" : "--with-head",
                                       "is written into .usda outputs only; give -o FILE.usda");
    }
    std::optional<PngArgs> png;
    if (!args.png.empty()) {
        png = png_args(args.views, args.size, args.look, "--views");
        check_png_output(args.png, "--png");
        check_writable(args.png);
    }
    if (!args.stats.empty()) check_writable(args.stats);
    const ThreadLimit limit(args.threads);

    Stopwatch watch;
    const Head head =
        with_style_named(args.style_path, args.preset, [&] { return load_head(style.head); });
    StageTimes times{{"head", watch.ms()}};
    info(args.quiet,
         cat("wisp: ", style.wisps, " wisps, ", style.strands, " strands on the ", head.source,
             " (scalp ", static_cast<int>(head.scalp->area()), " cm²), seed ", style.seed));
    HairstyleResult result = generate_named(style, head, args.style_path, args.preset);
    times.insert(times.end(), result.times.begin(), result.times.end());

    HairWriteOptions options;
    options.obj_segments = args.obj_segments;
    options.usda_z_up = args.up == "z";
    options.usda_precision = args.exports.precision;
    options.resample_points = args.exports.resample;
    options.camera = export_camera(result.hair, *head.mesh);
    const Hair guides =
        args.guides ? guide_strands(result.masters, result.wisp_group, style.root_width) : Hair();
    if (args.guides) options.usda_guides = &guides;
    if (args.with_head) {
        options.usda_head = head.mesh.get();
        options.usda_head_scalp = head.scalp->faces();
    }
    const bool subset = args.exports.strands || args.exports.fraction > 0;
    const Hair exported = subset ? args.exports.apply(result.hair) : Hair();
    const Hair& written = subset ? exported : result.hair;
    if (subset)
        info(args.quiet, cat("wisp: writing ", written.strand_count(), " of ",
                             result.hair.strand_count(), " strands"));
    for (const std::string& out : args.outputs) {
        watch = Stopwatch();
        write_hair(out, written, options);
        times.emplace_back("write " + out, watch.ms());
        info(args.quiet, cat("wisp: wrote ", out));
    }
    if (!args.png.empty()) {
        watch = Stopwatch();
        render_png(args.png, result.hair, *head.mesh, *png, args.quiet);
        times.emplace_back("render " + args.png, watch.ms());
        info(args.quiet, cat("wisp: wrote ", args.png));
    }
    if (!args.stats.empty()) {
        nlohmann::json j = hair_stats(result.hair);
        j["wisps"] = result.masters.count();
        j["seed"] = style.seed;
        j["style"] = style.name;
        j["head"] = head.source;
        j["body"] = head.body;
        j["scalp_area_cm2"] = head.scalp->area();
        j["points_per_strand"] = style.points_per_strand;
        j["threads"] =
            args.threads > 0 ? args.threads : static_cast<int>(std::thread::hardware_concurrency());
        j["time_ms"] = stage_stats(times);
        j["time_ms"]["wall"] = total.ms();
        j["version"] = kVersion;
        j["solver"] = solve_stats_json(result.solve, style.solve);
        for (const auto& [stage, ms] : result.times)
            if (stage == "solve") j["solver"]["time_ms"] = ms;
        j["coverage"] = coverage_stats(result.hair, head, style);
        j["points_pushed_out_of_head"] = result.points_pushed;
        j["points_inside_head"] = result.points_inside_head;
        // Hair hanging past the end of the body (into the air below a bust) reads as wrong.
        const float bottom = head.mesh->bounds().lo.y() - 1.f;
        j["points_below_body"] = std::count_if(result.hair.points.begin(), result.hair.points.end(),
                                               [&](const Vec3f& p) { return p.y() < bottom; });
        j["strands_cut"] = result.strands_cut;
        j["strands_removed_by_cut"] = result.strands_removed;
        write_json(args.stats, j);
        info(args.quiet, cat("wisp: wrote ", args.stats));
    }
    info(args.quiet,
         cat("wisp: ", result.hair.strand_count(), " strands, ", result.hair.point_count(),
             " points in ", static_cast<int>(total.ms()), " ms"));
    return 0;
}

struct AnimateArgs {
    std::string input;  // style TOML or hair file
    std::string preset;
    std::string motion = "lean";
    int frames = 48;
    double fps = 24;
    std::vector<std::string> outputs;
    std::string png, mp4, view = "three-quarter",
                          size = cat(kAnimationPictureSide, "x", kAnimationPictureSide);
    std::string stats, seed, links;
    HeadArgs head;
    std::vector<std::string> ties;
    int threads = 0, strands = 0, levels = 0, sub_wisps = 0, wisps_per_group = 0, sections = 0;
    bool single_level = false, quiet = false;
    std::string usda = "clips";  // .usda layout: clips (a layer per frame) or single
    bool guides = false;         // .usda: animate one guide strand per wisp only
    int precision = 0;           // .usda: --precision; 0: shortest exact
    LookArgs look;
};

bool is_style_file(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".toml" || ext == ".TOML";
}

// `wisp animate --guides`: one guide per wisp, a render strand moved by the simulation like
// every strand of its wisp: the wisp's longest strand, the one whose root is nearest the
// wisp's mean root among those (then the lowest index). Returns the guides' strand indices in
// wisp-id order and, in `bound`, the strands with wisp ids renumbered to their guide's index.
std::vector<uint32_t> pick_guides(const Hair& hair, Hair& bound) {
    if (hair.wisp.size() != hair.strand_count())
        throw CLI::ValidationError("--guides", "the hair has no wisp ids to pick guides by");
    std::map<int32_t, std::vector<uint32_t>> wisps;
    for (size_t s = 0; s < hair.strand_count(); ++s)
        wisps[hair.wisp[s]].push_back(static_cast<uint32_t>(s));
    std::vector<uint32_t> guides;
    bound = hair;
    for (const auto& [id, members] : wisps) {
        Vec3d mean = Vec3d::Zero();
        size_t longest = 0;
        for (uint32_t s : members) {
            mean += hair.points[hair.offsets[s]].cast<double>();
            longest = std::max<size_t>(longest, hair.strand_size(s));
        }
        mean /= static_cast<double>(members.size());
        uint32_t best = members.front();
        double best_d = std::numeric_limits<double>::infinity();
        for (uint32_t s : members) {
            if (hair.strand_size(s) != longest) continue;
            const double d = (hair.points[hair.offsets[s]].cast<double>() - mean).squaredNorm();
            if (d < best_d) {
                best_d = d;
                best = s;
            }
        }
        for (uint32_t s : members)
            bound.wisp[s] = static_cast<int32_t>(guides.size());
        guides.push_back(best);
    }
    return guides;
}

int run_animate(const AnimateArgs& args) {
    Stopwatch total;
    const ThreadLimit limit(args.threads);
    // Every argument and output is checked before the work starts.
    for (const std::string& out : args.outputs) {
        hair_format_from_path(out);  // the name given, not frame 0's, in its message
        check_writable(numbered(out, 0));
    }
    const PngArgs png = png_args(args.view, args.size, args.look, "--view");
    if (png.views.size() != 1)
        throw CLI::ValidationError("--view", "animate renders one view, got '" + args.view + "'");
    if (!args.png.empty()) {
        check_png_output(args.png, "--png");
        check_writable(numbered(args.png, 0));
    }
    if (!args.mp4.empty()) check_writable(args.mp4);
    if (!args.stats.empty()) check_writable(args.stats);
    std::vector<Tie> ties;
    for (const std::string& t : args.ties)
        ties.push_back(parse_tie(t));
    if (!args.input.empty() && !args.preset.empty())
        throw CLI::ValidationError("animate", "give a style or hair file, or --preset, not both");
    const bool from_style = args.input.empty() || is_style_file(args.input);

    Style style = from_style ? resolve_style(args.input, args.preset) : Style{};
    if (!args.seed.empty()) style.seed = parse_seed(args.seed);
    if (args.strands > 0) {
        style.strands = args.strands;
        style.wisps = std::min(style.wisps, style.strands);
    }
    DynamicsSpec& spec = style.dynamics;
    if (args.levels) spec.levels = args.levels;
    if (args.sub_wisps) spec.sub_wisps = args.sub_wisps;
    if (args.wisps_per_group) spec.wisps_per_group = args.wisps_per_group;
    if (args.sections) spec.sections = args.sections;
    if (!args.links.empty())
        spec.links = args.links == "rigid"  ? DynamicsSpec::Links::kRigid
                     : args.links == "soft" ? DynamicsSpec::Links::kSoft
                                            : DynamicsSpec::Links::kAuto;
    args.head.apply(style);

    Stopwatch watch;
    const Head head = from_style ? with_style_named(args.input, args.preset,
                                                    [&] { return load_head(style.head); })
                                 : load_head(style.head);
    const HeadFrame frame = head_frame(*head.scalp);
    const Motion motion = load_motion(args.motion, frame);  // its errors before the work
    StageTimes times{{"head", watch.ms()}};
    Hair rest;
    std::vector<float> held;  // per wisp: the length its ties hold
    watch = Stopwatch();
    if (from_style) {
        info(args.quiet, cat("wisp: ", style.wisps, " wisps, ", style.strands, " strands on the ",
                             head.source, ", seed ", style.seed));
        HairstyleResult generated = generate_named(style, head, args.input, args.preset);
        rest = std::move(generated.hair);
        held = std::move(generated.solve.held_length);
        times.emplace_back("generate", watch.ms());
    } else {
        rest = read_hair(args.input);
        times.emplace_back("read", watch.ms());
    }

    AnimateSettings settings;
    settings.frames = args.frames;
    settings.fps = args.fps;
    settings.single_level = args.single_level;
    settings.wisp_held = std::move(held);
    // Ties for hair without constraints: each tie's holds, the longest where several catch a
    // strand.
    try {
        std::vector<size_t> caught;
        settings.strand_held = tie_holds(rest, ties, &caught);
        for (size_t t = 0; t < caught.size(); ++t)
            info(args.quiet, cat("wisp: tie ", t + 1, " holds ", caught[t], " strands"));
    } catch (const Error& e) {
        throw CLI::ValidationError("--tie", e.what());
    }

    // Outputs: .usda as value clips (a layer per frame and a small top-level layer) or one
    // time-sampled layer (--usda single); a numbered file per frame for the other formats.
    // Until the run ends well, every file written so far is removed on an error or a signal.
    std::vector<std::unique_ptr<UsdaAnimationWriter>> usda;
    std::vector<std::unique_ptr<UsdaClipWriter>> clips;
    Hair bound;  // --guides: the render strands at rest, wisp ids renumbered to their guides
    const std::vector<uint32_t> guide_strands =
        args.guides ? pick_guides(rest, bound) : std::vector<uint32_t>();
    const Hair* guided = args.guides ? &bound : nullptr;
    const Hair rest_guides = args.guides ? select_strands(rest, guide_strands) : Hair();
    const Hair& first_frame = args.guides ? rest_guides : rest;
    if (args.guides)
        for (const std::string& out : args.outputs)
            if (hair_format_from_path(out) != HairFormat::kUsda)
                throw CLI::ValidationError("--guides", "writes .usda only, not " + out);
    std::vector<std::string> per_frame;
    std::vector<std::unique_ptr<FileSeries>> series;
    for (const std::string& out : args.outputs) {
        if (hair_format_from_path(out) != HairFormat::kUsda) {
            per_frame.push_back(out);
            const std::string pattern = numbered_pattern(out);
            const size_t first = pattern.find('#'), last = pattern.find_last_of('#') + 1;
            series.push_back(std::make_unique<FileSeries>(
                pattern.substr(0, first), pattern.substr(last), static_cast<int>(last - first)));
        } else if (args.usda == "single") {
            usda.push_back(std::make_unique<UsdaAnimationWriter>(
                out, first_frame, args.fps, args.frames, guided, args.precision));
        } else {
            clips.push_back(std::make_unique<UsdaClipWriter>(out, first_frame, args.fps,
                                                             args.frames, guided, args.precision));
        }
    }
    // PNG frames where --png says, or for an MP4 alone in a temporary folder.
    const PictureFrames picture_frames(
        args.png.empty() ? std::string() : numbered_pattern(args.png), !args.mp4.empty());
    RenderOptions look = png.options;
    look.view = png.views[0];
    AnimationPictures pictures(look, *head.mesh, frame, motion,
                               static_cast<double>(args.frames) / args.fps);
    HairWriteOptions write_options;
    Progress progress("frame", args.frames, args.quiet);

    const AnimationStats stats = animate(
        rest, *head.mesh, frame, motion, spec, style.prototype.kind, settings,
        [&](int f, const Hair& hair, const FramePose& pose) {
            const Hair frame_guides = args.guides ? select_strands(hair, guide_strands) : Hair();
            const Hair& animated = args.guides ? frame_guides : hair;
            for (auto& writer : usda)
                writer->add(animated);
            for (auto& writer : clips)
                writer->add(animated);
            for (size_t k = 0; k < per_frame.size(); ++k) {
                write_hair(numbered(per_frame[k], f), hair, write_options);
                series[k]->added(static_cast<size_t>(f));
            }
            if (!picture_frames.pattern().empty())
                pictures.write(numbered(picture_frames.pattern(), f), hair, pose);
            progress.step(f + 1);
        });
    for (auto& writer : usda)
        writer->finish();
    for (auto& writer : clips)
        writer->finish();
    for (auto& s : series)
        s->keep();
    for (const std::string& out : args.outputs)
        info(args.quiet,
             cat("wisp: wrote ",
                 hair_format_from_path(out) != HairFormat::kUsda ? numbered(out, 0) + " …"
                 : args.usda == "single"
                     ? out
                     : cat(out, " (value clips ",
                           UsdaClipWriter::frame_path(out, 0, size_t(args.frames)).string(),
                           " …)")));
    if (!args.png.empty()) info(args.quiet, cat("wisp: wrote ", numbered(args.png, 0), " …"));
    if (!args.mp4.empty()) {
        encode_mp4(picture_frames.pattern(), args.fps, args.mp4);
        info(args.quiet, cat("wisp: wrote ", args.mp4));
    }
    if (!args.stats.empty()) {
        nlohmann::json j = animation_stats_json(stats, rest, motion, args.frames, args.fps);
        j["version"] = kVersion;
        j["input"] = from_style ? style.name : args.input;
        j["single_level"] = args.single_level;
        times.emplace_back("hierarchy", stats.hierarchy_ms);
        times.emplace_back("body spheres", stats.bodies_ms);
        times.emplace_back("bind strands", stats.bind_ms);
        j["time_ms"] = stage_stats(times);
        j["time_ms"]["wall"] = total.ms();
        write_json(args.stats, j);
        info(args.quiet, cat("wisp: wrote ", args.stats));
    }
    info(args.quiet,
         cat("wisp: ", args.frames, " frames, ", stats.steps, " steps, ",
             static_cast<int>(stats.step_ms_mean * 1000) / 1000.0, " ms per step, ", stats.splits,
             " splits, ", stats.merges, " merges in ", static_cast<int>(total.ms()), " ms"));
    return 0;
}

}  // namespace

int run_cli(int argc, char** argv) {
    CLI::App app{"wisp: realistic hairstyles from a few intuitive parameters (Choe & Ko 2005)"};
    app.set_version_flag("--version", kVersion);
    app.require_subcommand(1);

    GenerateArgs gen;
    CLI::App* generate_cmd = app.add_subcommand(
        "generate", "Generate a hairstyle from a style file or a preset and write hair files");
    generate_cmd->add_option("style", gen.style_path, "Style file (TOML); see docs/style.md")
        ->check(CLI::ExistingFile);
    generate_cmd->add_option("--preset", gen.preset, "A shipped preset (see `wisp presets`)");
    generate_cmd->add_option(
        "-o,--output", gen.outputs,
        "Output file(s); the format follows the extension: .usda .hair .obj .ply .data .npz "
        ".rib .pbrt");
    generate_cmd->add_option("--png", gen.png, "Also render the hairstyle to this PNG");
    generate_cmd->add_option("--views", gen.views,
                             "Views for --png, comma-separated (front, back, left, right, "
                             "three-quarter, top); several make a contact sheet");
    generate_cmd->add_option("--size", gen.size, "Image size WxH for --png")->capture_default_str();
    gen.look.add_to(generate_cmd);
    gen.head.add_to(generate_cmd);
    generate_cmd->add_option("--seed", gen.seed,
                             "Random seed (overrides the style's), or 'random'");
    generate_cmd->add_option("--threads", gen.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    generate_cmd->add_option("--strands", gen.strands, "Override the style's strand count")
        ->check(CLI::Range(1, 10000000));
    generate_cmd->add_option("--wisps", gen.wisps, "Override the style's wisp count")
        ->check(CLI::Range(1, 1000000));
    generate_cmd->add_option("--stats", gen.stats, "Write the run's figures as JSON");
    generate_cmd->add_flag("--obj-segments", gen.obj_segments,
                           "OBJ: one `l` per segment (Blender's OBJ importer keeps only the "
                           "first two points of longer `l` lines)");
    generate_cmd
        ->add_option("--up", gen.up, "USD: up axis, y (wisp's) or z (points turned +Y to +Z)")
        ->check(CLI::IsMember({"y", "z"}));
    gen.exports.add_to(generate_cmd);
    generate_cmd->add_flag("--guides", gen.guides,
                           "USD: also write the master strands (one per wisp) as guides, "
                           "flagged groom_guide = 1, each strand tied to its wisp's guide "
                           "(Unreal's groom_closest_guides)");
    generate_cmd->add_flag("--with-head", gen.with_head,
                           "USD: also write the head mesh (and its scalp faces as a subset) "
                           "into the stage, aligned with the hair");
    generate_cmd->add_flag("-q,--quiet", gen.quiet, "Print nothing but errors");

    std::string head_out = "head.obj";
    float head_scale = 1.f;
    CLI::App* head_cmd =
        app.add_subcommand("head", "Write the built-in head (scalp faces in group 'scalp')");
    head_cmd->add_option("-o,--output", head_out, "Output OBJ")->capture_default_str();

    std::string info_path;
    bool info_json = false;
    CLI::App* info_cmd = app.add_subcommand("info", "Describe a hair file");
    info_cmd->add_option("file", info_path, "A .hair, .usda, .obj, .ply or .data file")->required();
    info_cmd->add_flag("--json", info_json, "Print JSON instead of text");

    std::string compare_a, compare_b, compare_head, compare_views = "front,left,back,right";
    int compare_size = 256, compare_threads = 0;
    float compare_voxel = 0.5f;
    bool compare_json = false, compare_no_head = false;
    CLI::App* compare_cmd = app.add_subcommand(
        "compare",
        "How close hair A (a reconstruction) is to a reference B: strand precision, recall and "
        "F1, chamfer, position, curvature, orientation and silhouette in pictures, occupancy "
        "(docs/dataset.md)");
    compare_cmd->add_option("a", compare_a, "The hair to score: .hair .usda .obj .ply .data")
        ->required();
    compare_cmd->add_option("b", compare_b, "The reference (ground truth), in any of those")
        ->required();
    compare_cmd->add_option("--head", compare_head,
                            "Head OBJ that hides the hair behind it in the views (default: the "
                            "built-in head)");
    compare_cmd->add_option("--head-scale", head_scale, "Scale of --head to centimetres");
    compare_cmd->add_flag("--no-head", compare_no_head, "Views without a head");
    compare_cmd->add_option("--views", compare_views, "Views for the orientation and silhouette")
        ->capture_default_str();
    compare_cmd->add_option("--size", compare_size, "The views' pictures, pixels a side")
        ->check(CLI::Range(16, 4096))
        ->capture_default_str();
    compare_cmd->add_option("--voxel", compare_voxel, "Occupancy grid cell, cm")
        ->check(CLI::Range(0.01, 100.0))
        ->capture_default_str();
    compare_cmd->add_option("--threads", compare_threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    compare_cmd->add_flag("--json", compare_json, "Print JSON instead of text");

    std::string convert_in, convert_out;
    bool convert_segments = false;
    std::string convert_up = "y";
    CLI::App* convert_cmd = app.add_subcommand("convert", "Convert a hair file to another format");
    convert_cmd->add_option("input", convert_in, "Input: .hair .usda .obj .ply .data")->required();
    convert_cmd
        ->add_option("output", convert_out, "Output: .usda .hair .obj .ply .data .npz .rib .pbrt")
        ->required();
    convert_cmd->add_flag("--obj-segments", convert_segments, "OBJ: one `l` per segment");
    convert_cmd->add_option("--up", convert_up, "USD: up axis, y or z")
        ->check(CLI::IsMember({"y", "z"}));
    ExportArgs convert_exports;
    convert_exports.add_to(convert_cmd);

    app.add_subcommand("presets", "List the shipped style presets");

    EditCommands edit_args;  // `wisp edit` and `wisp schema` (app/edit_command.cpp)
    add_edit_commands(app, edit_args);
    DatasetCommands dataset_args;  // `wisp dataset ...` (app/dataset_command.cpp)
    add_dataset_commands(app, dataset_args);

    std::string render_in, render_out, render_head, render_view = "three-quarter",
                                                    render_size = "1024x1024";
    CLI::App* render_cmd = app.add_subcommand("render", "Render a hair file to PNG");
    render_cmd->add_option("hair", render_in, "A .hair, .usda, .obj, .ply or .data file")
        ->required();
    render_cmd->add_option("-o,--output", render_out, "Output PNG")->required();
    render_cmd->add_option("--head", render_head, "Head OBJ (default: the built-in head)");
    render_cmd->add_option("--head-scale", head_scale, "Scale of --head to centimetres");
    render_cmd
        ->add_option("--view", render_view,
                     "front, back, left, right, three-quarter, top, or several "
                     "comma-separated for a contact sheet")
        ->capture_default_str();
    render_cmd->add_option("--size", render_size, "Image size WxH")->capture_default_str();
    int render_threads = 0;
    bool render_quiet = false;
    render_cmd->add_option("--threads", render_threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    render_cmd->add_flag("-q,--quiet", render_quiet, "No progress or summary on stderr");
    LookArgs render_look;
    render_look.add_to(render_cmd);

    AnimateArgs anim;
    CLI::App* animate_cmd = app.add_subcommand(
        "animate",
        "Animate a hairstyle with the Adaptive Wisp Tree (Bertails et al. 2003); docs/animate.md");
    animate_cmd
        ->add_option("input", anim.input,
                     "Style file (.toml) or hair file (.hair .usda .obj .ply .data)")
        ->check(CLI::ExistingFile);
    animate_cmd->add_option("--preset", anim.preset, "A shipped style preset");
    animate_cmd
        ->add_option("--motion", anim.motion,
                     "lean, shake, nod, jump, run, still, or a motion JSON file (docs/motion.md)")
        ->capture_default_str();
    animate_cmd->add_option("--frames", anim.frames, "Frames to write")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    animate_cmd
        ->add_option("--usda", anim.usda,
                     ".usda output: clips (a layer per frame, referenced by a small top-level "
                     "layer as USD value clips) or single (one time-sampled layer)")
        ->check(CLI::IsMember({"clips", "single"}))
        ->capture_default_str();
    animate_cmd->add_option("--fps", anim.fps, "Frames per second")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    animate_cmd->add_option("-o,--output", anim.outputs,
                            "Output: .usda (value clips: a layer per frame and a top-level layer, "
                            "or one time-sampled layer, see --usda) or .hair/.obj/.ply (one file "
                            "per frame; #### in the name is the frame number)");
    animate_cmd->add_flag(
        "--guides", anim.guides,
        ".usda: animate one guide strand per wisp only (groom_guide = 1), beside the render "
        "strands at rest bound to their wisp's guide (groom_closest_guides): what Unreal, "
        "Houdini or a DCC needs to rebuild the rest, at a fraction of the size");
    add_precision_option(animate_cmd, anim.precision);
    animate_cmd->add_option("--png", anim.png, "Render every frame: PNG name with ####");
    animate_cmd->add_option("--mp4", anim.mp4, "Also encode the frames to an MP4 (ffmpeg)");
    animate_cmd->add_option("--view", anim.view, "Camera view for --png/--mp4")
        ->capture_default_str();
    animate_cmd->add_option("--size", anim.size, "Image size WxH")->capture_default_str();
    anim.look.add_to(animate_cmd);
    animate_cmd->add_flag("--single-level", anim.single_level,
                          "Keep every finest node active (the paper's baseline)");
    animate_cmd->add_option("--levels", anim.levels, "Hierarchy levels (2-4)")
        ->check(CLI::Range(2, 4));
    animate_cmd->add_option("--sub-wisps", anim.sub_wisps, "Sub-wisps per wisp (2-16)")
        ->check(CLI::Range(2, 16));
    animate_cmd->add_option("--wisps-per-group", anim.wisps_per_group, "Wisps per group (2-64)")
        ->check(CLI::Range(2, 64));
    animate_cmd->add_option("--sections", anim.sections, "Nodes along every wisp (3-64)")
        ->check(CLI::Range(3, 64));
    animate_cmd->add_option("--links", anim.links, "auto, rigid or soft")
        ->check(CLI::IsMember({"auto", "rigid", "soft"}));
    animate_cmd->add_option("--strands", anim.strands, "Override the style's strand count")
        ->check(CLI::Range(1, 10000000));
    animate_cmd->add_option(
        "--tie", anim.ties,
        "Hold the strands passing within radius (cm, default 2) of the point x,y,z (the rest "
        "hair's coordinates, cm) rigidly to the head from the root to there, like a ponytail's "
        "tie: x,y,z[,radius]; repeatable");
    anim.head.add_to(animate_cmd);
    animate_cmd->add_option("--seed", anim.seed, "Random seed of the style, or 'random'");
    animate_cmd->add_option("--threads", anim.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    animate_cmd->add_option("--stats", anim.stats, "Write the run's figures as JSON");
    animate_cmd->add_flag("-q,--quiet", anim.quiet, "Print nothing but errors");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version (exit code 0) print as CLI11 has them; a parse error may quote
        // the user's arguments, so it goes through excerpt() like every other message.
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "wisp: usage error: " << excerpt(e.what(), kMaxMessageBytes)
                  << "\nRun with --help for more information.\n";
        return 2;
    }

    try {
        if (*generate_cmd) {
            if (gen.outputs.empty() && gen.png.empty())
                throw CLI::ValidationError("generate", "give at least one -o FILE or --png FILE");
            return run_generate(gen);
        }
        if (*animate_cmd) {
            if (anim.outputs.empty() && anim.png.empty() && anim.mp4.empty() && anim.stats.empty())
                throw CLI::ValidationError("animate",
                                           "give -o FILE, --png FILE, --mp4 FILE or --stats FILE");
            return run_animate(anim);
        }
        if (*render_cmd) {
            const ThreadLimit limit(render_threads);
            const PngArgs png = png_args(render_view, render_size, render_look, "--view");
            check_png_output(render_out, "--output");
            check_writable(render_out);
            const Hair hair = read_hair(render_in);
            HeadSpec spec;
            spec.obj = render_head;
            spec.scale = head_scale;
            const Head head = load_head_mesh(spec);  // with the body it gets in `generate`
            render_png(render_out, hair, *head.mesh, png, render_quiet);
            info(render_quiet, cat("wisp: wrote ", render_out));
            return 0;
        }
        if (*head_cmd) {
            write_obj_mesh(head_out, builtin_head_mesh());
            std::cerr << "wisp: wrote " << head_out << '\n';
            return 0;
        }
        if (*info_cmd) {
            const HairFileInfo i = hair_file_info(info_path);
            if (!info_json) {
                std::cout << describe(i);
                return 0;
            }
            nlohmann::json j;
            j["path"] = i.path.string();
            j["format"] = hair_format_name(i.format);
            j["bytes"] = i.file_bytes;
            j["strands"] = i.strands;
            j["points"] = i.points;
            j["points_per_strand"] = {
                {"min", i.min_points}, {"max", i.max_points}, {"mean", i.mean_points}};
            if (!i.bounds.empty())
                j["bbox"] = {{"min", {i.bounds.lo.x(), i.bounds.lo.y(), i.bounds.lo.z()}},
                             {"max", {i.bounds.hi.x(), i.bounds.hi.y(), i.bounds.hi.z()}}};
            j["has_widths"] = i.has_widths;
            j["has_colors"] = i.has_colors;
            j["skipped_strands"] = i.skipped_strands;
            for (const UsdPrimSummary& p : i.usd_prims)
                j["usd_prims"].push_back({{"path", p.path},
                                          {"type", p.type},
                                          {"basis", p.basis},
                                          {"wrap", p.wrap},
                                          {"curves", p.curves},
                                          {"points", p.points},
                                          {"segments", p.segments},
                                          {"problem", p.problem}});
            // Prim names and paths may hold bytes that are not UTF-8: replaced, not fatal.
            std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
            return 0;
        }
        if (*compare_cmd) {
            const ThreadLimit limit(compare_threads);
            CompareOptions options;
            options.views = png_args(compare_views, "16x16", LookArgs{}, "--views").views;
            options.size = compare_size;
            options.voxel = compare_voxel;
            const Hair a = read_hair(compare_a), b = read_hair(compare_b);
            HeadSpec spec;
            spec.obj = compare_head;
            spec.scale = head_scale;
            const Head head = compare_no_head ? Head{} : load_head_mesh(spec);
            const CompareResult r = compare_hair(a, b, head.mesh.get(), options);
            if (compare_json) {
                std::cout << to_json(r).dump(2) << '\n';
                return 0;
            }
            std::printf("A %s: %zu strands, %zu points\nB %s: %zu strands, %zu points\n",
                        compare_a.c_str(), r.strands_a, r.points_a, compare_b.c_str(), r.strands_b,
                        r.points_b);
            std::printf("strands (precision / recall / F1):\n");
            for (const StrandScore& k : r.strands)
                std::printf("  %g mm, %g°: %.3f / %.3f / %.3f\n", 10 * k.distance, k.angle,
                            k.precision, k.recall, k.f1);
            std::printf("chamfer: A to B %.4f cm, B to A %.4f cm\n", r.chamfer_a_to_b,
                        r.chamfer_b_to_a);
            if (r.corresponding)
                std::printf("corresponding strands: position %.4f cm, curvature %.4f /cm\n",
                            r.position_error, r.curvature_error);
            else
                std::printf("corresponding strands: none (%zu strands against %zu)\n", r.strands_a,
                            r.strands_b);
            std::printf("views (%s): orientation error %.2f°, silhouette IoU %.4f\n",
                        compare_views.c_str(), r.orientation_error, r.silhouette_iou);
            std::printf("occupancy IoU (%g cm voxels): %.4f\n", compare_voxel, r.occupancy_iou);
            return 0;
        }
        if (*convert_cmd) {
            const HairFormat format = hair_format_from_path(convert_out);
            check_hair_output(convert_out);
            convert_exports.check();
            const Hair hair = convert_exports.apply(read_hair(convert_in));
            HairWriteOptions options;
            options.obj_segments = convert_segments;
            options.usda_z_up = convert_up == "z";
            options.usda_precision = convert_exports.precision;
            options.resample_points = convert_exports.resample;
            // Only scenes have a camera; framing it builds the head, a tenth of a second.
            if (format == HairFormat::kRib || format == HairFormat::kPbrt)
                options.camera = export_camera(hair, builtin_head_mesh());
            write_hair(convert_out, hair, options);
            std::cerr << "wisp: wrote " << convert_out << " (" << hair.strand_count()
                      << " strands)\n";
            return 0;
        }
        if (const auto code = run_edit_commands(edit_args)) return *code;
        if (const auto code = run_dataset_commands(dataset_args)) return *code;
        if (app.got_subcommand("presets")) {
            for (const std::string& name : preset_names())
                std::cout << name << '\n';
            return 0;
        }
    } catch (const CLI::ValidationError& e) {
        std::cerr << "wisp: usage error: " << excerpt(e.what(), kMaxMessageBytes) << '\n';
        return 2;
    } catch (const Error& e) {
        std::cerr << "wisp: error: " << excerpt(e.what(), kMaxMessageBytes) << '\n';
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "wisp: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "wisp: error: " << excerpt(e.what(), kMaxMessageBytes) << '\n';
        return 1;
    }
    return 2;
}

}  // namespace wisp
