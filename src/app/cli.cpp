#include "app/cli.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <thread>

#include "app/stats.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "geometry/builtin_head.hpp"
#include "groom/generate.hpp"
#include "groom/style_toml.hpp"
#include "io/hair_io.hpp"
#include "render/render.hpp"
#include "solve/pipeline.hpp"

namespace wisp {
namespace {

constexpr const char* kVersion = "0.1.0";

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

// Look options shared by `render` and `generate --png`.
struct LookArgs {
    std::string eye, target, background;
    float fov = 30.f;
    float specular_exponent = 80.f, specular_strength = -1.f;
    bool no_shadows = false;

    void add_to(CLI::App* cmd) {
        cmd->add_option("--eye", eye, "Camera position x,y,z in cm (with --target)");
        cmd->add_option("--target", target, "Point the camera looks at, x,y,z in cm");
        cmd->add_option("--fov", fov, "Vertical field of view, degrees")
            ->check(CLI::Range(1.f, 170.f))
            ->capture_default_str();
        cmd->add_option("--background", background, "Background linear RGB r,g,b in [0,1]");
        cmd->add_option("--specular-exponent", specular_exponent, "Kajiya-Kay specular exponent")
            ->check(CLI::Range(1.f, 10000.f))
            ->capture_default_str();
        cmd->add_option("--specular", specular_strength, "Kajiya-Kay specular strength")
            ->check(CLI::Range(0.f, 100.f));
        cmd->add_flag("--no-shadows", no_shadows, "Render without self-shadowing");
    }
    void apply(RenderOptions& o) const {
        if (eye.empty() != target.empty())
            throw CLI::ValidationError("--eye", "--eye and --target go together");
        if (!eye.empty())
            o.look_at = LookAt{parse_vec3("--eye", eye), parse_vec3("--target", target)};
        o.fov_y_degrees = fov;
        if (!background.empty()) o.background = parse_vec3("--background", background);
        o.specular_exponent = specular_exponent;
        if (specular_strength >= 0.f) o.specular_strength = specular_strength;
        o.shadows = !no_shadows;
    }
};

struct GenerateArgs {
    std::string style_path;
    std::string preset;
    std::vector<std::string> outputs;
    std::string seed;
    int threads = 0;
    std::string stats;
    bool obj_segments = false;
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

// Renders hair (and the head) to a PNG: one view, or a contact sheet of several.
void render_png(const std::string& path, const Hair& hair, const Mesh& head,
                const std::string& views, const std::string& size, const LookArgs& look) {
    RenderOptions options;
    std::tie(options.width, options.height) = parse_size(size);
    look.apply(options);
    const std::vector<std::string> list = split_views(views.empty() ? "three-quarter" : views);
    if (list.size() == 1) {
        options.view = list[0];
        write_png(path, render(hair, &head, options));
    } else {
        write_png(path, contact_sheet(hair, &head, list, options));
    }
}

// The camera that .rib and .pbrt scenes get: the renderer's three-quarter view.
ExportCamera export_camera(const Hair& hair, const Mesh& head) {
    RenderOptions options;
    const Camera c = render_camera(hair, &head, options);
    ExportCamera e;
    e.eye = c.eye;
    e.target = c.eye + c.forward;
    e.up = c.up;
    e.fov_y_degrees = c.fov_y_degrees;
    e.width = c.width;
    e.height = c.height;
    return e;
}

Style resolve_style(const std::string& path, const std::string& preset) {
    if (!path.empty() && !preset.empty())
        throw CLI::ValidationError("give a style file or --preset, not both");
    if (!path.empty()) return load_style(path);
    return load_preset(preset.empty() ? "default" : preset);
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

int run_generate(const GenerateArgs& args) {
    Stopwatch total;
    Style style = resolve_style(args.style_path, args.preset);
    if (!args.seed.empty()) style.seed = parse_seed(args.seed);
    for (const std::string& out : args.outputs)
        hair_format_from_path(out);  // fail early
    const ThreadLimit limit(args.threads);

    Stopwatch watch;
    const Head head = load_head(style.head);
    StageTimes times{{"head", watch.ms()}};
    info(args.quiet,
         cat("wisp: ", style.wisps, " wisps, ", style.strands, " strands on the ", head.source,
             " (scalp ", static_cast<int>(head.scalp->area()), " cm²), seed ", style.seed));
    HairstyleResult result = generate_hairstyle(style, head);
    times.insert(times.end(), result.times.begin(), result.times.end());

    HairWriteOptions options;
    options.obj_segments = args.obj_segments;
    options.camera = export_camera(result.hair, *head.mesh);
    for (const std::string& out : args.outputs) {
        watch = Stopwatch();
        write_hair(out, result.hair, options);
        times.emplace_back("write " + out, watch.ms());
        info(args.quiet, cat("wisp: wrote ", out));
    }
    if (!args.png.empty()) {
        watch = Stopwatch();
        render_png(args.png, result.hair, *head.mesh, args.views, args.size, args.look);
        times.emplace_back("render " + args.png, watch.ms());
        info(args.quiet, cat("wisp: wrote ", args.png));
    }
    if (!args.stats.empty()) {
        nlohmann::json j = hair_stats(result.hair);
        j["wisps"] = result.masters.count();
        j["seed"] = style.seed;
        j["style"] = style.name;
        j["head"] = head.source;
        j["scalp_area_cm2"] = head.scalp->area();
        j["points_per_strand"] = style.points_per_strand;
        j["threads"] =
            args.threads > 0 ? args.threads : static_cast<int>(std::thread::hardware_concurrency());
        j["time_ms"] = stage_stats(times);
        j["time_ms"]["wall"] = total.ms();
        j["version"] = kVersion;
        const SolveStats& solve = result.solve;
        j["solver"] = {{"enabled", style.solve.enabled},
                       {"order", style.solve.depth_first ? "depth-first" : "breadth-first"},
                       {"joints", solve.joints},
                       {"collision_iterations", solve.bends},
                       {"colliding_joints", solve.collisions},
                       {"unresolved_joints", solve.unresolved},
                       {"projected_joints", solve.projected},
                       {"constrained_joints", solve.constrained},
                       {"group_progress", solve.group_progress}};
        for (const auto& [stage, ms] : result.times)
            if (stage == "solve") j["solver"]["time_ms"] = ms;
        j["points_pushed_out_of_head"] = result.points_pushed;
        j["points_inside_head"] = result.points_inside_head;
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
        "Output file(s); the format follows the extension: .usda .hair .obj .ply");
    generate_cmd->add_option("--png", gen.png, "Also render the hairstyle to this PNG");
    generate_cmd->add_option("--views", gen.views,
                             "Views for --png, comma-separated (front, back, left, right, "
                             "three-quarter, top); several make a contact sheet");
    generate_cmd->add_option("--size", gen.size, "Image size WxH for --png")->capture_default_str();
    gen.look.add_to(generate_cmd);
    generate_cmd->add_option("--seed", gen.seed,
                             "Random seed (overrides the style's), or 'random'");
    generate_cmd->add_option("--threads", gen.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024));
    generate_cmd->add_option("--stats", gen.stats, "Write the run's figures as JSON");
    generate_cmd->add_flag("--obj-segments", gen.obj_segments,
                           "OBJ: one `l` per segment (Blender's OBJ importer keeps only the "
                           "first two points of longer `l` lines)");
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

    std::string convert_in, convert_out;
    bool convert_segments = false;
    CLI::App* convert_cmd = app.add_subcommand("convert", "Convert a hair file to another format");
    convert_cmd->add_option("input", convert_in, "Input: .hair .usda .obj .ply .data")->required();
    convert_cmd->add_option("output", convert_out, "Output: .hair .usda .obj .ply")->required();
    convert_cmd->add_flag("--obj-segments", convert_segments, "OBJ: one `l` per segment");

    app.add_subcommand("presets", "List the shipped style presets");

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
    LookArgs render_look;
    render_look.add_to(render_cmd);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        if (*generate_cmd) {
            if (gen.outputs.empty() && gen.png.empty())
                throw CLI::ValidationError("generate", "give at least one -o FILE or --png FILE");
            return run_generate(gen);
        }
        if (*render_cmd) {
            const Hair hair = read_hair(render_in);
            const Mesh head =
                render_head.empty() ? builtin_head_mesh() : read_obj_mesh(render_head, head_scale);
            render_png(render_out, hair, head, render_view, render_size, render_look);
            std::cerr << "wisp: wrote " << render_out << '\n';
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
            std::cout << j.dump(2) << '\n';
            return 0;
        }
        if (*convert_cmd) {
            hair_format_from_path(convert_out);
            const Hair hair = read_hair(convert_in);
            HairWriteOptions options;
            options.obj_segments = convert_segments;
            options.camera = export_camera(hair, builtin_head_mesh());
            write_hair(convert_out, hair, options);
            std::cerr << "wisp: wrote " << convert_out << " (" << hair.strand_count()
                      << " strands)\n";
            return 0;
        }
        if (app.got_subcommand("presets")) {
            for (const std::string& name : preset_names())
                std::cout << name << '\n';
            return 0;
        }
    } catch (const CLI::ValidationError& e) {
        std::cerr << "wisp: usage error: " << e.what() << '\n';
        return 2;
    } catch (const Error& e) {
        std::cerr << "wisp: error: " << e.what() << '\n';
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "wisp: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "wisp: error: " << e.what() << '\n';
        return 1;
    }
    return 2;
}

}  // namespace wisp
