#include "dataset/dataset.hpp"

#include <archive.h>
#include <archive_entry.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "core/timer.hpp"
#include "dataset/targets.hpp"
#include "dataset/toml_value.hpp"
#include "groom/head.hpp"
#include "groom/style_schema.hpp"
#include "groom/style_toml.hpp"
#include "groom/toml_json.hpp"
#include "io/hair_io.hpp"
#include "io/npz.hpp"
#include "render/render.hpp"
#include "solve/pipeline.hpp"
#include "solve/styling_field.hpp"

namespace wisp {

namespace fs = std::filesystem;

namespace {

// The streams of one sample, all from its seed (Stream::kMisc ids): the base, the head, the
// style's seed, the cameras; each varied field draws from the stream of its path's hash.
enum : uint64_t { kBaseStream = 1, kHeadStream = 2, kStyleSeedStream = 3, kCameraStream = 4 };

uint64_t fnv1a(std::string_view s, uint64_t h = 0xcbf29ce484222325ull) {
    for (const char c : s) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string hex64(uint64_t v) {
    char buffer[17];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(v));
    return buffer;
}

template <typename T>
size_t pick(const std::vector<T>& items, double u) {
    double total = 0;
    for (const T& item : items)
        total += item.weight;
    double at = u * total;
    for (size_t i = 0; i < items.size(); ++i) {
        if (at < items[i].weight) return i;
        at -= items[i].weight;
    }
    return items.size() - 1;
}

std::string draw_value(const VaryRule& rule, Rng& rng) {
    using Kind = VaryRule::Kind;
    if (rule.kind == Kind::kChoice)
        return rule.choices[rng.below(static_cast<uint32_t>(rule.choices.size()))];
    const double u = rng.uniform_double();
    switch (rule.kind) {
        case Kind::kUniform:
            if (rule.integer) {
                // Every integer of [a, b] equally likely.
                const double lo = std::ceil(rule.a), hi = std::floor(rule.b);
                return format_draw(std::min(hi, std::floor(lo + u * (hi - lo + 1))), true);
            }
            return format_draw(rule.a + (rule.b - rule.a) * u, false);
        case Kind::kLogUniform:
            return format_draw(
                std::exp(std::log(rule.a) + (std::log(rule.b) - std::log(rule.a)) * u),
                rule.integer);
        case Kind::kNormal: {
            double u1 = u;
            const double u2 = rng.uniform_double();
            if (u1 < 1e-300) u1 = 1e-300;
            const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
            double v = std::clamp(rule.a + rule.b * z, rule.lo, rule.hi);
            if (rule.integer)
                v = std::clamp(std::round(v), std::ceil(rule.lo), std::floor(rule.hi));
            return format_draw(v, rule.integer);
        }
        default:
            return {};
    }
}

std::string host_name() {
    char buffer[256] = {};
    if (gethostname(buffer, sizeof buffer - 1) != 0) return "host";
    std::string s(buffer);
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
    return s.empty() ? "host" : s;
}

uint32_t file_crc(const fs::path& path, uint64_t* size) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), ": cannot read");
    uLong crc = crc32(0L, Z_NULL, 0);
    std::vector<char> buffer(1 << 16);
    uint64_t total = 0;
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        const std::streamsize got = in.gcount();
        if (got <= 0) break;
        crc = crc32(crc, reinterpret_cast<const Bytef*>(buffer.data()), static_cast<uInt>(got));
        total += static_cast<uint64_t>(got);
    }
    if (size) *size = total;
    return static_cast<uint32_t>(crc);
}

// The limits of a small text file of the dataset's own (dataset.json, complete.json, a
// sample's .failed note).
ReadLimits small_text(std::string_view what) {
    return {.max_bytes = 1 << 20, .what = what, .text = true};
}

void write_json_file(const fs::path& path, const nlohmann::json& j) {
    write_file_atomic(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

nlohmann::json vec(const Vec3f& v) {
    return {v.x(), v.y(), v.z()};
}

// Whether process `pid` of this host is running.
bool process_alive(long pid) {
    return pid > 0 && (kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

// Temporary folders of sample `name` left by runs on this host that are no longer alive
// (killed mid-sample) are removed; those of live runs are left alone.
void remove_stale_temporaries(const fs::path& samples, const std::string& name) {
    const std::string prefix = "." + name + ".tmp-" + host_name() + "-";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(samples, ec)) {
        const std::string f = entry.path().filename().string();
        if (f.rfind(prefix, 0) != 0) continue;
        if (process_alive(std::strtol(f.c_str() + prefix.size(), nullptr, 10))) continue;
        fs::remove_all(entry.path(), ec);
    }
}

// A run's claim on sample `name` while it makes it: the file `.NAME.claim-HOST`, created
// exclusively (O_EXCL), holding the run's pid. Two runs started on one folder of this host so
// share its samples instead of each making all of them. A claim whose process is gone (a run
// killed mid-sample) is taken over. Claims of other hosts are not seen: their liveness cannot
// be told, and runs on several machines take disjoint slices.
class SampleClaim {
  public:
    SampleClaim(const fs::path& samples, const std::string& name)
        : path_(samples / cat(".", name, ".claim-", host_name())) {
        for (int attempt = 0; attempt < 2 && !held_; ++attempt) {
            const int fd = ::open(path_.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0644);
            if (fd >= 0) {
                const std::string pid = std::to_string(getpid()) + "\n";
                const bool wrote =
                    ::write(fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
                ::close(fd);
                if (!wrote) fail(path_.string(), ": cannot write: ", std::strerror(errno));
                held_ = true;
                break;
            }
            if (errno != EEXIST) fail(path_.string(), ": cannot create: ", std::strerror(errno));
            if (!stale(path_)) return;
            std::error_code ec;
            fs::remove(path_, ec);
        }
    }
    ~SampleClaim() {
        std::error_code ec;
        if (held_) fs::remove(path_, ec);
    }
    SampleClaim(const SampleClaim&) = delete;
    SampleClaim& operator=(const SampleClaim&) = delete;
    bool held() const { return held_; }

    // A claim whose process is gone, or one left empty for over a minute (its run died
    // between creating and writing it).
    static bool stale(const fs::path& claim) {
        std::ifstream in(claim);
        long pid = 0;
        if (in >> pid) return !process_alive(pid);
        std::error_code ec;
        const auto age = fs::file_time_type::clock::now() - fs::last_write_time(claim, ec);
        return !ec && age > std::chrono::minutes(1);
    }

  private:
    fs::path path_;
    bool held_ = false;
};

// This host's claims whose runs are gone (killed between publishing a sample and removing
// the claim), removed when a run starts.
void remove_stale_claims(const fs::path& samples) {
    const std::string suffix = ".claim-" + host_name();
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(samples, ec)) {
        const std::string f = entry.path().filename().string();
        if (f.size() > suffix.size() &&
            f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0 &&
            SampleClaim::stale(entry.path()))
            fs::remove(entry.path(), ec);
    }
}

// Loading a head (and fitting its scalp) costs as much as a small sample's grooming: a run
// keeps the heads it has loaded, keyed by the style's [head] fields as TOML.
std::shared_ptr<const Head> cached_head(const Style& style) {
    static std::mutex mutex;
    static std::vector<std::pair<std::string, std::shared_ptr<const Head>>> cache;
    std::string key;
    for (const StyleField& f : style_schema())
        if (f.path.rfind("head.", 0) == 0)
            key += std::string(f.path) + "=" + style_field_toml(style, f) + "\n";
    {
        const std::lock_guard lock(mutex);
        for (const auto& [k, head] : cache)
            if (k == key) return head;
    }
    auto head = std::make_shared<const Head>(load_head(style.head));
    const std::lock_guard lock(mutex);
    if (cache.size() >= 16) cache.erase(cache.begin());
    cache.emplace_back(key, head);
    return head;
}

}  // namespace

SampleDraw draw_sample(const DatasetSpec& spec, uint64_t k) {
    SampleDraw d;
    d.index = k;
    d.seed = Rng(spec.seed, Stream::kMisc, k).next();
    switch (spec.sampling) {
        case DatasetSpec::Sampling::kWeighted:
            d.base = pick(spec.bases, Rng(d.seed, Stream::kMisc, kBaseStream).uniform_double());
            d.head = pick(spec.heads, Rng(d.seed, Stream::kMisc, kHeadStream).uniform_double());
            break;
        case DatasetSpec::Sampling::kStratified: {
            // R2: the plastic number g, steps 1/g and 1/g² (mod 1) from ½.
            constexpr double g = 1.32471795724474602596;
            const double kd = static_cast<double>(k);
            d.base = pick(spec.bases, std::fmod(0.5 + kd / g, 1.0));
            d.head = pick(spec.heads, std::fmod(0.5 + kd / (g * g), 1.0));
            break;
        }
        case DatasetSpec::Sampling::kGrid: {
            const uint64_t pair = k % (spec.bases.size() * spec.heads.size());
            d.base = pair % spec.bases.size();
            d.head = pair / spec.bases.size();
            break;
        }
    }
    d.style = spec.bases[d.base].style;
    const HeadChoice& head = spec.heads[d.head];
    try {
        for (const auto& [path, value] : head.fields)
            set_style_field(d.style, path, value, cat(spec.source, ":", head.line), spec.base_dir);
        d.style.seed = Rng(d.seed, Stream::kMisc, kStyleSeedStream).next() >> 1;
        d.values = nlohmann::json::object();
        for (const VaryRule& rule : spec.vary) {
            Rng rng(d.seed, Stream::kMisc, fnv1a(rule.path));
            const std::string text = draw_value(rule, rng);
            apply_draw(d.style, rule.path, text, cat(spec.source, ":", rule.line), spec.base_dir);
            d.values_toml += rule.path + " = " + text + "\n";
            d.values[rule.path] = toml_value_to_json(text);
        }
        for (const VaryRule& rule : spec.render) {
            const std::string path = "render." + rule.path;
            Rng rng(d.seed, Stream::kMisc, fnv1a(path));
            const std::string text = draw_value(rule, rng);
            d.render_values.emplace_back(rule.path, text);
            d.values_toml += path + " = " + text + "\n";
            d.values[path] = toml_value_to_json(text);
        }
    } catch (const Error& e) {
        fail("sample ", k, ": ", e.what());
    } catch (const toml::parse_error& e) {
        fail("sample ", k, ": ", e.description());
    }
    // As `wisp generate` does: a wisp needs at least one strand.
    d.style.wisps = std::min(d.style.wisps, d.style.strands);
    Rng camera(d.seed, Stream::kMisc, kCameraStream);
    for (size_t c = 0; c < spec.cameras.size() * 3; ++c)
        d.camera_draws.push_back(2.0 * camera.uniform_double() - 1.0);
    d.hash = fnv1a(d.values_toml, fnv1a(spec.bases[d.base].name + "\n" + head.name + "\n"));
    return d;
}

nlohmann::json manifest_entry(const DatasetSpec& spec, const SampleDraw& draw) {
    return {{"index", draw.index},
            {"seed", draw.seed},
            {"style_seed", draw.style.seed},
            {"base", spec.bases[draw.base].name},
            {"head", spec.heads[draw.head].name},
            {"values", draw.values},
            {"hash", hex64(draw.hash)}};
}

namespace {

// Linear sRGB of a black body at `kelvin` (1500 to 15000), luminance 1: Planck's law
// integrated against the CIE 1931 colour matching functions (their multi-lobe Gaussian fit,
// Wyman, Sloan and Shirley 2013), XYZ to linear sRGB.
Vec3f black_body(double kelvin) {
    double X = 0, Y = 0, Z = 0;
    auto g = [](double x, double mu, double s1, double s2) {
        const double t = (x - mu) / (x < mu ? s1 : s2);
        return std::exp(-0.5 * t * t);
    };
    for (double nm = 380; nm <= 780; nm += 5) {
        const double l = nm * 1e-9;
        const double planck = 1.0 / (std::pow(l, 5) * (std::exp(1.4387769e-2 / (l * kelvin)) - 1));
        const double x = 1.056 * g(nm, 599.8, 37.9, 31.0) + 0.362 * g(nm, 442.0, 16.0, 26.7) -
                         0.065 * g(nm, 501.1, 20.4, 26.2);
        const double y = 0.821 * g(nm, 568.8, 46.9, 40.5) + 0.286 * g(nm, 530.9, 16.3, 31.1);
        const double z = 1.217 * g(nm, 437.0, 11.8, 36.0) + 0.681 * g(nm, 459.0, 26.0, 13.8);
        X += planck * x;
        Y += planck * y;
        Z += planck * z;
    }
    const Vec3f rgb(static_cast<float>((3.2406 * X - 1.5372 * Y - 0.4986 * Z) / Y),
                    static_cast<float>((-0.9689 * X + 1.8758 * Y + 0.0415 * Z) / Y),
                    static_cast<float>((0.0557 * X - 0.2040 * Y + 1.0570 * Z) / Y));
    const Vec3f clamped = rgb.cwiseMax(0.f);
    return clamped / (0.2126f * clamped.x() + 0.7152f * clamped.y() + 0.0722f * clamped.z());
}

// HSV (hue in degrees) to linear RGB, the value linear.
Vec3f hsv(double h, double s, double v) {
    h = std::fmod(std::fmod(h, 360.0) + 360.0, 360.0) / 60.0;
    const int i = static_cast<int>(h) % 6;
    const double f = h - std::floor(h), p = v * (1 - s), q = v * (1 - s * f),
                 t = v * (1 - s * (1 - f));
    const double rgb[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    return {static_cast<float>(rgb[i][0]), static_cast<float>(rgb[i][1]),
            static_cast<float>(rgb[i][2])};
}

}  // namespace

RenderOptions sample_render_options(const SampleDraw& draw) {
    RenderOptions o;
    if (draw.render_values.empty()) return o;
    std::map<std::string, double> v;
    for (const RenderField& f : render_field_table())
        v[f.name] = f.fallback;
    bool background = false, temperature = false;
    for (const auto& [name, text] : draw.render_values) {
        const toml::table t = toml::parse("v = " + text);
        if (name == "shading") {
            o.shading = parse_shading(t["v"].value_or(std::string("hair")));
            continue;
        }
        v[name] = t["v"].value_or(0.0);
        background |= name.starts_with("background_");
        temperature |= name == "key_temperature";
    }
    const double deg = M_PI / 180;
    const Eigen::Matrix3f turn =
        (Eigen::AngleAxisf(static_cast<float>(v["key_azimuth"] * deg), Vec3f::UnitY()) *
         Eigen::AngleAxisf(static_cast<float>(-v["key_elevation"] * deg), Vec3f::UnitX()))
            .toRotationMatrix();
    o.key.direction = turn * o.key.direction;
    const float key_luminance =
        0.2126f * o.key.color.x() + 0.7152f * o.key.color.y() + 0.0722f * o.key.color.z();
    if (temperature) o.key.color = key_luminance * black_body(v["key_temperature"]);
    o.key.color *= static_cast<float>(v["key_intensity"]);
    o.fill.color *= static_cast<float>(v["fill_intensity"]);
    o.rim.color *= static_cast<float>(v["rim_intensity"]);
    o.ambient *= static_cast<float>(v["ambient_intensity"]);
    if (background)
        o.background = hsv(v["background_hue"], v["background_saturation"], v["background_value"]);
    o.strand_brightness = static_cast<float>(v["strand_brightness"]);
    return o;
}

Camera sample_camera(const DatasetSpec& spec, const SampleDraw& draw, size_t c, const Hair& hair,
                     const Mesh& head) {
    const CameraSpec& cs = spec.cameras[c];
    RenderOptions options;
    options.width = spec.output.width;
    options.height = spec.output.height;
    options.view = cs.view;
    options.fov_y_degrees = static_cast<float>(cs.fov_y_degrees);
    Box3 box;
    if (cs.hair_only) {
        for (const Vec3f& p : hair.points)
            box.extend(p);
    } else {
        box = framing_bounds(hair, &head);
    }
    const Camera framed =
        cs.hair_only && !box.empty()
            ? frame_view(cs.view, box, options.width, options.height, options.fov_y_degrees)
            : render_camera(hair, &head, options);
    const Vec3f target = box.empty() ? framed.eye + framed.forward : box.center();
    const double* u = &draw.camera_draws[3 * c];
    const float azimuth = static_cast<float>(cs.azimuth * u[0] * M_PI / 180);
    const float elevation = static_cast<float>(cs.elevation * u[1] * M_PI / 180);
    const float distance = static_cast<float>(1 + cs.distance * u[2]);
    // Round the target: first about the camera's right axis (elevation), then about Y.
    const Eigen::Matrix3f turn =
        (Eigen::AngleAxisf(azimuth, Vec3f::UnitY()) * Eigen::AngleAxisf(-elevation, framed.right))
            .toRotationMatrix();
    Vec3f eye = target + distance * (turn * (framed.eye - target));
    const Vec3f up = turn * framed.up;
    Camera cam = look_at(eye, target, up, options.fov_y_degrees, options.width, options.height);
    if (!cs.hair_only || box.empty()) return cam;
    // A hair-centred crop: aimed at the middle of the hair's picture and brought as near as
    // fills 95% of the picture's tighter side with it (twice, as perspective shifts both).
    Vec3f aim = target;
    for (int pass = 0; pass < 2; ++pass) {
        Box3 seen;
        for (const Vec3f& p : hair.points) {
            const Vec3f q = cam.project(p);
            if (q.z() > 1e-3f) seen.extend(q);
        }
        if (seen.empty()) break;
        const float depth = (aim - cam.eye).dot(cam.forward);
        const Vec3f mid = seen.center();
        aim = cam.eye +
              depth / cam.focal_pixels *
                  (cam.forward * cam.focal_pixels + cam.right * (mid.x() - 0.5f * cam.width) -
                   cam.up * (mid.y() - 0.5f * cam.height));
        const float fill = std::max(seen.size().x() / cam.width, seen.size().y() / cam.height);
        if (!(fill > 0.f)) break;
        eye = aim + (cam.eye - aim) * (fill / 0.95f);
        cam = look_at(eye, aim, up, options.fov_y_degrees, options.width, options.height);
    }
    return cam;
}

std::string sample_name(uint64_t samples, uint64_t k) {
    int digits = 6;
    for (uint64_t n = samples > 0 ? samples - 1 : 0; n >= 1'000'000; n /= 10)
        ++digits;
    std::string s = std::to_string(k);
    return std::string(s.size() < static_cast<size_t>(digits) ? digits - s.size() : 0, '0') + s;
}

bool write_sample(const DatasetSpec& spec, uint64_t k, const fs::path& folder,
                  std::vector<std::pair<std::string, double>>* times) {
    Stopwatch watch;
    const auto lap = [&](const std::string& stage) {
        if (times) times->emplace_back(stage, watch.ms());
        watch = Stopwatch();
    };
    const fs::path parent = folder.parent_path();
    const std::string name = folder.filename().string();
    fs::create_directories(parent);
    const SampleClaim claim(parent, name);
    // Another run on this host is making it, or made it since this run looked.
    if (!claim.held() || fs::exists(folder / "complete.json")) return false;
    remove_stale_temporaries(parent, name);
    const fs::path tmp = parent / cat(".", name, ".tmp-", host_name(), "-", getpid());
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    // Whatever goes wrong below, no temporary folder is left (a kill -9 leaves one, which
    // the next run of the sample removes, and which is never mistaken for a sample).
    struct Cleanup {
        fs::path path;
        ~Cleanup() {
            std::error_code ec;
            if (!path.empty()) fs::remove_all(path, ec);
        }
    } cleanup{tmp};

    const SampleDraw draw = draw_sample(spec, k);
    const std::shared_ptr<const Head> head_ptr = cached_head(draw.style);
    const Head& head = *head_ptr;
    lap("head");
    const HairstyleResult result = generate_hairstyle(draw.style, head);
    const Hair& hair = result.hair;
    lap("generate");

    // The files it reads from the dataset's inputs as paths relative to the sample, so that
    // the style goes on working where the dataset is moved.
    Style written = draw.style;
    const fs::path home = fs::absolute(folder).lexically_normal();
    const fs::path dataset = home.parent_path().parent_path();
    for_each_style_file(written, [&](fs::path& p) {
        const fs::path a = fs::absolute(p).lexically_normal();
        const fs::path in_dataset = a.lexically_relative(dataset);
        if (!in_dataset.empty() && *in_dataset.begin() != "..") p = a.lexically_relative(home);
    });
    write_file_atomic(tmp / "style.toml", "# wisp dataset sample " + std::to_string(k) +
                                              ": `wisp generate style.toml`"
                                              " makes this sample's hair\n" +
                                              style_to_toml(written));
    HairWriteOptions hair_options;
    hair_options.resample_points = spec.output.resample;
    for (const std::string& ext : spec.output.hair)
        write_hair(tmp / ("hair." + ext), hair, hair_options);
    lap("write hair");

    if (spec.output.volume.x() > 0) {
        const HeadFrame frame = head_frame(head);
        const HairVolume v = hair_volume(hair, frame.to_space(spec.output.volume_lo),
                                         frame.to_space(spec.output.volume_hi), spec.output.volume);
        const std::vector<size_t> shape = {static_cast<size_t>(v.dims.z()),
                                           static_cast<size_t>(v.dims.y()),
                                           static_cast<size_t>(v.dims.x())};
        const float box[6] = {v.lo.x(), v.lo.y(), v.lo.z(), v.hi.x(), v.hi.y(), v.hi.z()};
        const NpyArray arrays[] = {
            npy_array("occupancy", shape, std::span<const uint8_t>(v.occupancy)),
            npy_array("orientation", {shape[0], shape[1], shape[2], 3},
                      std::span<const float>(v.orientation)),
            npy_array("box", {2, 3}, std::span<const float>(box))};
        write_npz(tmp / "volume.npz", arrays);
        lap("volume");
    }

    if (spec.output.scalp_texture > 0) {
        const ScalpTexture st =
            scalp_texture(hair, spec.output.scalp_texture, spec.output.scalp_points);
        const size_t r = static_cast<size_t>(st.size), pts = static_cast<size_t>(st.points);
        const NpyArray arrays[] = {
            npy_array("mask", {r, r}, std::span<const uint8_t>(st.mask)),
            npy_array("strand", {r, r}, std::span<const int32_t>(st.strand)),
            npy_array("offsets", {r, r, pts, 3}, std::span<const float>(st.offsets)),
            npy_array("roots", {r, r, 3}, std::span<const float>(st.roots)),
            npy_array("normals", {r, r, 3}, std::span<const float>(st.normals))};
        write_npz(tmp / "scalp.npz", arrays);
        lap("scalp texture");
    }

    nlohmann::json cameras = nlohmann::json::array();
    std::vector<double> npz_k, npz_w2c, npz_fov;
    std::vector<int32_t> npz_size;
    for (size_t c = 0; c < spec.cameras.size(); ++c) {
        const Camera cam = sample_camera(spec, draw, c, hair, *head.mesh);
        const std::string prefix = cat("cam", c);
        const OutputSpec& out = spec.output;
        auto file = [&](OutputMap m) {
            return tmp / (prefix + output_map_table()[static_cast<int>(m)].suffix);
        };
        if (out.has(OutputMap::kPicture)) {
            RenderOptions options = sample_render_options(draw);
            options.width = cam.width;
            options.height = cam.height;
            options.fov_y_degrees = cam.fov_y_degrees;
            options.look_at = LookAt{cam.eye, cam.eye + cam.forward, cam.up};
            write_png(file(OutputMap::kPicture), render(hair, head.mesh.get(), options));
            lap("render");
        }
        if (out.maps & ~(1u << static_cast<int>(OutputMap::kPicture))) {
            const TargetMaps maps =
                draw_targets(hair, head.mesh.get(), cam, out.has(OutputMap::kConfidence));
            const std::vector<size_t> shape = {static_cast<size_t>(maps.height),
                                               static_cast<size_t>(maps.width)};
            auto npy = [&](OutputMap m, const char* name, auto values) {
                write_file_atomic(file(m), encode_npy(npy_array(name, shape, values)));
            };
            if (out.has(OutputMap::kOrientation))
                write_png(file(OutputMap::kOrientation), orientation_image(maps));
            if (out.has(OutputMap::kMask))
                write_file_atomic(file(OutputMap::kMask), encode_gray_png(mask_image(maps)));
            if (out.has(OutputMap::kDepth))
                npy(OutputMap::kDepth, "depth", std::span<const float>(maps.depth));
            if (out.has(OutputMap::kStrand))
                write_png(file(OutputMap::kStrand), strand_map_image(maps));
            if (out.has(OutputMap::kConfidence))
                npy(OutputMap::kConfidence, "confidence", std::span<const float>(maps.confidence));
            if (out.has(OutputMap::kMatte))
                write_file_atomic(file(OutputMap::kMatte), encode_gray_png(matte_image(maps)));
            if (out.has(OutputMap::kStrandId))
                npy(OutputMap::kStrandId, "strand_id", std::span<const int32_t>(maps.strand));
            if (out.has(OutputMap::kDepthHairstep)) {
                const std::vector<float> d = hairstep_depth(maps);
                npy(OutputMap::kDepthHairstep, "depth_hairstep", std::span<const float>(d));
            }
            lap("maps");
        }
        // OpenCV's convention: x right, y down, z forward; x_pixel = K (R p + t).
        const CameraMatrices mats = opencv_matrices(cam);
        nlohmann::json w2c = nlohmann::json::array();
        for (int i = 0; i < 3; ++i)
            w2c.push_back({mats.world_to_camera[4 * i], mats.world_to_camera[4 * i + 1],
                           mats.world_to_camera[4 * i + 2], mats.world_to_camera[4 * i + 3]});
        w2c.push_back({0, 0, 0, 1});
        // cameras.npz: the same numbers, row-major, as float64 (each holds the float above).
        npz_k.insert(npz_k.end(), mats.K.begin(), mats.K.end());
        npz_w2c.insert(npz_w2c.end(), mats.world_to_camera.begin(), mats.world_to_camera.end());
        npz_size.push_back(cam.width);
        npz_size.push_back(cam.height);
        npz_fov.push_back(cam.fov_y_degrees);
        cameras.push_back({{"name", prefix},
                           {"view", spec.cameras[c].view},
                           {"width", cam.width},
                           {"height", cam.height},
                           {"fov_y_degrees", cam.fov_y_degrees},
                           {"fx", cam.focal_pixels},
                           {"fy", cam.focal_pixels},
                           {"cx", 0.5 * cam.width},
                           {"cy", 0.5 * cam.height},
                           {"eye", vec(cam.eye)},
                           {"right", vec(cam.right)},
                           {"up", vec(cam.up)},
                           {"forward", vec(cam.forward)},
                           {"world_to_camera", w2c}});
    }
    write_json_file(tmp / "cameras.json",
                    {{"units", "cm, head space (Y up, +Z forward)"},
                     {"convention",
                      "world_to_camera maps head space to OpenCV camera space (x "
                      "right, y down, z forward); pixel = K (R p + t), pixel (i, j) "
                      "covers [i, i+1) x [j, j+1)"},
                     {"cameras", cameras}});
    const size_t ncam = spec.cameras.size();
    const NpyArray camera_arrays[] = {
        npy_array("K", {ncam, 3, 3}, std::span<const double>(npz_k)),
        npy_array("world_to_camera", {ncam, 4, 4}, std::span<const double>(npz_w2c)),
        npy_array("image_size", {ncam, 2}, std::span<const int32_t>(npz_size)),
        npy_array("fov_y_degrees", {ncam}, std::span<const double>(npz_fov))};
    write_npz(tmp / "cameras.npz", camera_arrays);

    nlohmann::json meta = manifest_entry(spec, draw);
    meta["strands"] = hair.strand_count();
    meta["points"] = hair.point_count();
    meta["wisps"] = result.masters.count();
    meta["points_per_strand"] = draw.style.points_per_strand;
    meta["version"] = kDatasetVersion;
    meta["solver"] = {{"joints", result.solve.joints},
                      {"unresolved_joints", result.solve.unresolved}};
    meta["points_inside_head"] = result.points_inside_head;
    write_json_file(tmp / "meta.json", meta);

    // The completion marker, last: what it lists is what the sample is.
    nlohmann::json files = nlohmann::json::object();
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(tmp))
        names.insert(entry.path().filename().string());
    for (const std::string& f : names) {
        uint64_t size = 0;
        const uint32_t crc = file_crc(tmp / f, &size);
        files[f] = {{"bytes", size}, {"crc32", crc}};
    }
    write_json_file(tmp / "complete.json", {{"index", k}, {"files", files}});
    lap("write");

    std::error_code ec;
    fs::rename(tmp, folder, ec);
    if (ec) {
        // Another run published the sample first (the same bytes), or a folder without a
        // marker is in the way: keep a complete one, replace anything else.
        if (fs::exists(folder / "complete.json")) return true;
        fs::remove_all(folder);
        fs::rename(tmp, folder);
    }
    cleanup.path.clear();
    return true;
}

namespace {

fs::path spec_copy(const fs::path& dir) {
    return dir / "spec.toml";
}

// Loads every head the samples can draw (each base style with each [[head]]), so that a head
// that is missing, is not a mesh, or lacks the scalp group it names fails the plan, naming
// its line, not every sample of a run (or of a Slurm array) later.
void check_heads(const DatasetSpec& spec) {
    for (const BaseStyle& base : spec.bases)
        for (const HeadChoice& head : spec.heads) {
            const std::string where = cat(spec.source, ":", head.line);
            try {
                Style style = base.style;
                for (const auto& [path, value] : head.fields)
                    set_style_field(style, path, value, where, spec.base_dir);
                cached_head(style);
            } catch (const Error& e) {
                fail(head.line > 0 ? where : spec.source, ": head '", head.name, "' (base ",
                     base.name, "): ", e.what());
            } catch (const toml::parse_error& e) {
                fail(where, ": head '", head.name, "': ", e.description());
            }
        }
}

// The deepest folder holding both (absolute, lexically normal paths).
fs::path common_folder(const fs::path& a, const fs::path& b) {
    fs::path out;
    for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end() && *i == *j; ++i, ++j)
        out /= *i;
    return out;
}

// Copies every file the samples read (base style files, and the head meshes, images and field
// files of every drawn style) into `dir`/inputs, each under its path relative to the deepest
// folder holding them all and the spec's folder, so that the spec's relative paths resolve
// against inputs/<the spec's folder> as they did against the spec's folder: the dataset
// moves, or goes to another machine, whole. Returns that folder, relative to `dir`. A path
// the spec gives as absolute resolves as it was and is still read from where it is.
fs::path pack_inputs(const DatasetSpec& spec, const std::vector<fs::path>& needed,
                     const fs::path& dir) {
    const fs::path spec_dir = fs::absolute(spec.base_dir).lexically_normal();
    std::vector<fs::path> files;
    fs::path root = spec_dir;
    for (const fs::path& f : needed) {
        fs::path a = fs::absolute(f).lexically_normal();
        if (std::find(files.begin(), files.end(), a) != files.end()) continue;
        std::error_code ec;
        if (!fs::is_regular_file(a, ec))
            fail(spec.source, ": ", f.string(), ", which a sample reads, is not a file");
        root = common_folder(root, a.parent_path());
        files.push_back(std::move(a));
    }
    const fs::path inputs = dir / "inputs";
    for (const fs::path& f : files) {
        const fs::path to = inputs / f.lexically_relative(root);
        fs::create_directories(to.parent_path());
        std::ifstream in(f, std::ios::binary);
        if (!in) fail(spec.source, ": cannot read ", f.string());
        AtomicFile out(to);
        out.stream() << in.rdbuf();
        if (in.bad()) fail(spec.source, ": cannot read ", f.string());
        out.commit();
    }
    // The spec's folder itself, even with nothing in it: the OS resolves "../x" from it only
    // if it is there.
    const fs::path spec_inputs = fs::path("inputs") / spec_dir.lexically_relative(root);
    fs::create_directories(dir / spec_inputs);
    return spec_inputs;
}

}  // namespace

uint64_t plan_dataset(const fs::path& spec_path, const fs::path& dir) {
    const DatasetSpec spec = load_dataset_spec(spec_path);
    check_heads(spec);
    ReadLimits limits;
    limits.what = "a dataset spec";
    limits.text = true;
    const std::string text = read_file(spec_path, limits);
    std::error_code ec;
    if (fs::exists(dir / "dataset.json", ec)) {
        const std::string old = read_file(spec_copy(dir), limits);
        if (old != text)
            fail(dir.string(), ": already planned from another spec (its spec.toml differs from ",
                 spec_path.string(), "); plan into a new folder");
    }
    fs::create_directories(dir / "samples");
    // What the samples read, besides the spec: the base style files and every file of every
    // drawn style (a head a rule draws, a map image).
    std::vector<fs::path> needed;
    auto need = [&](const fs::path& f) {
        if (std::find(needed.begin(), needed.end(), f) == needed.end()) needed.push_back(f);
    };
    for (const BaseStyle& base : spec.bases)
        if (!base.name.starts_with("preset:")) need(spec.base_dir / base.name);
    // Streamed: a large dataset's manifest need not fit in memory.
    AtomicFile manifest(dir / "manifest.jsonl");
    for (uint64_t k = 0; k < spec.samples; ++k) {
        const SampleDraw draw = draw_sample(spec, k);
        for (const fs::path& f : style_files(draw.style))
            need(f);
        manifest.stream() << manifest_entry(spec, draw).dump() << '\n';
    }
    const fs::path spec_dir = pack_inputs(spec, needed, dir);
    manifest.commit();
    write_file_atomic(spec_copy(dir), text);
    write_json_file(dir / "dataset.json", {{"samples", spec.samples},
                                           {"seed", spec.seed},
                                           {"spec", spec_path.filename().string()},
                                           {"spec_dir", spec_dir.generic_string()},
                                           {"version", kDatasetVersion}});
    return spec.samples;
}

DatasetSpec load_planned_spec(const fs::path& dir) {
    const fs::path info = dir / "dataset.json";
    std::error_code ec;
    if (!fs::exists(info, ec))
        fail(dir.string(),
             ": no dataset.json: not a planned dataset (run `wisp dataset plan "
             "SPEC.toml -o ",
             dir.string(), "` first)");
    const ReadLimits limits = small_text("dataset.json");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(read_file(info, limits));
        // Relative: the dataset's own inputs folder (an absolute one is kept, as datasets
        // planned before their inputs were packed have it).
        return load_dataset_spec(spec_copy(dir),
                                 fs::absolute(dir) / j.at("spec_dir").get<std::string>());
    } catch (const nlohmann::json::exception& e) {
        fail(info.string(), ": ", e.what());
    }
}

namespace {

// What is wrong with a sample folder that has its complete.json: "" when nothing. Every file
// it lists must be there with its size; with `checksums`, with its CRC-32 too (which reads
// the files: `verify`, or `run --verify`).
std::string sample_problem(const fs::path& folder, bool checksums) {
    const ReadLimits limits = small_text("complete.json");
    std::error_code ec;
    try {
        const nlohmann::json j = nlohmann::json::parse(read_file(folder / "complete.json", limits));
        for (const auto& [f, entry] : j.at("files").items()) {
            const uint64_t bytes = entry.at("bytes").get<uint64_t>();
            if (!fs::exists(folder / f, ec)) return f + " is missing";
            if (!checksums) {
                if (fs::file_size(folder / f, ec) != bytes || ec)
                    return f + " does not match its size";
                continue;
            }
            uint64_t size = 0;
            const uint32_t crc = file_crc(folder / f, &size);
            if (size != bytes || crc != entry.at("crc32").get<uint32_t>())
                return f + " does not match its size or CRC-32";
        }
    } catch (const std::exception& e) {
        return std::string("complete.json: ") + e.what();
    }
    return "";
}

}  // namespace

RunSummary run_dataset(const fs::path& dir, const RunOptions& options) {
    const DatasetSpec spec = load_planned_spec(dir);
    const Slice slice = options.slice;
    if (slice.count == 0 || slice.index >= slice.count)
        fail("task ", slice.index, " of ", slice.count, ": the index must be below the count");
    std::vector<uint64_t> todo;
    for (uint64_t k = slice.index; k < spec.samples; k += slice.count)
        todo.push_back(k);
    const fs::path samples = dir / "samples";
    fs::create_directories(samples);
    remove_stale_claims(samples);

    RunSummary summary;
    std::mutex mutex;
    std::atomic<size_t> next{0};
    uint64_t done = 0;
    const auto worker = [&] {
        for (size_t i = next++; i < todo.size(); i = next++) {
            const uint64_t k = todo[i];
            const std::string name = sample_name(spec.samples, k);
            const fs::path folder = samples / name;
            const fs::path failed = samples / (name + ".failed");
            std::error_code ec;
            bool skipped = fs::exists(folder / "complete.json", ec);
            bool remade = false;
            if (skipped && !sample_problem(folder, options.verify).empty()) {
                // A sample that lost or changed a file since it was made is made again; its
                // marker goes first, so that no run takes the folder for a finished one.
                fs::remove(folder / "complete.json", ec);
                skipped = false;
                remade = true;
            }
            bool ok = true, elsewhere = false;
            std::vector<std::pair<std::string, double>> times;
            std::string why;
            if (!skipped) {
                try {
                    elsewhere = !write_sample(spec, k, folder, &times);
                    if (!elsewhere) fs::remove(failed, ec);
                } catch (const std::exception& e) {
                    ok = false;
                    why = e.what();
                    try {
                        write_file_atomic(failed, why + "\n");
                    } catch (const std::exception&) {
                    }
                }
            }
            const std::lock_guard lock(mutex);
            ++done;
            if (elsewhere) {
                ++summary.elsewhere;
                skipped = true;
            } else if (skipped)
                ++summary.skipped;
            else if (ok)
                ++summary.made;
            else
                ++summary.failed;
            summary.remade += remade && ok && !elsewhere ? 1 : 0;
            if (!ok && options.on_failure) options.on_failure(k, why);
            if (ok && !skipped && options.on_times) options.on_times(k, times);
            if (options.on_sample) options.on_sample(done, todo.size(), k, skipped);
        }
    };
    const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(todo.size())));
    std::vector<std::thread> threads;
    for (int j = 1; j < jobs; ++j)
        threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads)
        t.join();
    return summary;
}

DatasetStatus dataset_status(const fs::path& dir, bool checksums) {
    const DatasetSpec spec = load_planned_spec(dir);
    DatasetStatus s;
    s.samples = spec.samples;
    const fs::path samples = dir / "samples";
    const ReadLimits limits = small_text("a sample's .failed note");
    for (uint64_t k = 0; k < spec.samples; ++k) {
        const std::string name = sample_name(spec.samples, k);
        const fs::path folder = samples / name;
        std::error_code ec;
        if (fs::exists(folder / "complete.json", ec)) {
            const std::string problem = sample_problem(folder, checksums);
            if (problem.empty()) {
                ++s.done;
                continue;
            }
            ++s.corrupt;
            s.problems.push_back(name + ": " + problem);
        } else if (fs::exists(samples / (name + ".failed"), ec)) {
            ++s.failed;
            std::string why;
            try {
                why = read_file(samples / (name + ".failed"), limits);
            } catch (const Error&) {
            }
            while (!why.empty() && why.back() == '\n')
                why.pop_back();
            s.problems.push_back(name + ": failed: " + excerpt(why, 300));
        } else {
            ++s.pending;
        }
        s.missing.push_back(k);
    }
    return s;
}

std::string index_ranges(const std::vector<uint64_t>& indices) {
    std::string out;
    for (size_t i = 0; i < indices.size();) {
        size_t j = i;
        while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1)
            ++j;
        if (!out.empty()) out += ',';
        out += std::to_string(indices[i]);
        if (j > i) {
            out += '-';
            out += std::to_string(indices[j]);
        }
        i = j + 1;
    }
    return out;
}

namespace {

// A word for bash, quoted so that nothing in it is expanded.
std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (const char c : s) {
        if (c == '\'')
            out += "'\\''";
        else
            out += c;
    }
    return out + "'";
}

}  // namespace

std::string slurm_script(const fs::path& dir, const SlurmOptions& o) {
    if (o.tasks < 1) fail("--tasks must be at least 1");
    for (const std::string* s : {&o.partition, &o.time})
        if (s->find_first_of("\n\r\"'\\ \t") != std::string::npos)
            fail("slurm: '", excerpt(*s), "' holds a character sbatch options cannot");
    const fs::path abs = fs::absolute(dir);
    std::string s = "#!/bin/bash\n";
    s += "# wisp dataset: a job array whose task i makes the samples k with k % " +
         std::to_string(o.tasks) + " == i.\n";
    s += "# Resubmitting it (or single tasks: sbatch --array=3,7 ...) makes what is missing.\n";
    s += "#SBATCH --job-name=wisp-dataset\n";
    s += cat("#SBATCH --array=0-", o.tasks - 1, o.throttle > 0 ? cat("%", o.throttle) : "", "\n");
    s += "#SBATCH --output=" + (abs / "slurm" / "task-%A_%a.log").string() + "\n";
    if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
    if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
    if (o.cpus_per_task > 0) s += cat("#SBATCH --cpus-per-task=", o.cpus_per_task, "\n");
    s += "set -euo pipefail\n";
    s += "exec " + shell_quote(o.wisp) + " dataset run " + shell_quote(abs.string()) +
         " --task-id \"$SLURM_ARRAY_TASK_ID\" --tasks " + std::to_string(o.tasks) + "\n";
    return s;
}

}  // namespace wisp

namespace wisp {

namespace {

// A POSIX ustar archive written by libarchive into a stream (the AtomicFile of a shard).
// Every member gets mode 0644, owner and group 0 without names, and time 0, so that the
// archive's bytes depend only on the members' names and contents, in the order added.
class TarWriter {
  public:
    TarWriter(std::ostream& out, const std::string& what) : out_(out), what_(what) {
        archive_ = archive_write_new();
        entry_ = archive_entry_new();
        if (!archive_ || !entry_) fail(what_, ": libarchive could not allocate");
        check(archive_write_set_format_ustar(archive_));
        check(archive_write_add_filter_none(archive_));
        // One 512-byte block per write: no padding of the last write to libarchive's 10 KiB
        // default blocks beyond what ustar needs (two zero blocks).
        check(archive_write_set_bytes_per_block(archive_, 512));
        check(archive_write_set_bytes_in_last_block(archive_, 1));
        check(archive_write_open(archive_, this, nullptr, &TarWriter::write, nullptr));
    }
    TarWriter(const TarWriter&) = delete;
    TarWriter& operator=(const TarWriter&) = delete;
    ~TarWriter() {
        archive_entry_free(entry_);
        archive_write_free(archive_);
    }

    void add(const std::string& name, const std::string& bytes) {
        archive_entry_clear(entry_);
        archive_entry_set_pathname(entry_, name.c_str());
        archive_entry_set_filetype(entry_, AE_IFREG);
        archive_entry_set_perm(entry_, 0644);
        archive_entry_set_size(entry_, static_cast<la_int64_t>(bytes.size()));
        archive_entry_set_mtime(entry_, 0, 0);
        archive_entry_set_uid(entry_, 0);
        archive_entry_set_gid(entry_, 0);
        check(archive_write_header(archive_, entry_));
        if (!bytes.empty() && archive_write_data(archive_, bytes.data(), bytes.size()) !=
                                  static_cast<la_ssize_t>(bytes.size()))
            fail(what_, ": member '", excerpt(name), "': ", archive_error_string(archive_));
    }

    void finish() { check(archive_write_close(archive_)); }

  private:
    static la_ssize_t write(struct archive*, void* self, const void* data, size_t n) {
        auto* w = static_cast<TarWriter*>(self);
        w->out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
        return w->out_ ? static_cast<la_ssize_t>(n) : -1;
    }
    void check(int status) {
        if (status != ARCHIVE_OK) {
            const char* why = archive_error_string(archive_);
            fail(what_, ": ", why ? why : "libarchive failed");
        }
    }

    std::ostream& out_;
    std::string what_;
    struct archive* archive_ = nullptr;
    struct archive_entry* entry_ = nullptr;
};

}  // namespace

size_t pack_dataset(const fs::path& dir, uint64_t samples_per_shard) {
    if (samples_per_shard == 0) fail("pack: --samples-per-shard must be at least 1");
    const DatasetSpec spec = load_planned_spec(dir);
    std::vector<uint64_t> done;
    std::error_code ec;
    for (uint64_t k = 0; k < spec.samples; ++k)
        if (fs::exists(dir / "samples" / sample_name(spec.samples, k) / "complete.json", ec))
            done.push_back(k);
    fs::create_directories(dir / "pack");
    size_t shards = 0;
    ReadLimits limits;
    limits.what = "a sample's file";
    for (size_t first = 0; first < done.size(); first += samples_per_shard, ++shards) {
        const fs::path path = dir / "pack" / ("shard-" + sample_name(0, shards) + ".tar");
        AtomicFile file(path);
        TarWriter tar(file.stream(), path.string());
        for (size_t i = first; i < std::min(done.size(), first + samples_per_shard); ++i) {
            const std::string name = sample_name(spec.samples, done[i]);
            const fs::path folder = dir / "samples" / name;
            std::set<std::string> files;
            for (const auto& entry : fs::directory_iterator(folder))
                if (entry.is_regular_file()) files.insert(entry.path().filename().string());
            files.erase("complete.json");
            for (const std::string& f : files)
                tar.add(name + "." + f, read_file(folder / f, limits));
        }
        tar.finish();
        file.commit();
    }
    return shards;
}

}  // namespace wisp
