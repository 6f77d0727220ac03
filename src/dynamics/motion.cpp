#include "dynamics/motion.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace wisp {

namespace {

using Channels = std::array<double, 6>;  // pitch, yaw, roll (degrees), translation x, y, z (cm)

constexpr double kRadians = std::numbers::pi / 180.0;

Channels channels_of(const MotionKey& k) {
    return {k.rotate.x(),    k.rotate.y(),    k.rotate.z(),
            k.translate.x(), k.translate.y(), k.translate.z()};
}

struct TrackSample {
    Channels value{};
    Channels rate{};  // per second
};

// The clamped, non-uniform Catmull-Rom spline of motion.hpp. Computes tangents on the fly
// from the four keys around t so a track needs no cached state and no allocation. A key
// whose value equals a neighbour's (per channel) gets a zero tangent, so holds are exact:
// the plain tangent would make the spline dip before a hold and overshoot after it.
TrackSample sample_track(const std::vector<MotionKey>& keys, double t) {
    TrackSample out;
    const size_t n = keys.size();
    if (n == 0) return out;
    if (n == 1 || t <= keys.front().time) {
        out.value = channels_of(keys.front());
        return out;
    }
    if (t >= keys.back().time) {
        out.value = channels_of(keys.back());
        return out;
    }
    const auto it = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double x, const MotionKey& k) { return x < k.time; });
    // Clamped so that a NaN time still indexes a real segment.
    const size_t i =
        std::min<size_t>(n - 2, static_cast<size_t>(std::max<ptrdiff_t>(1, it - keys.begin()) - 1));
    const double t0 = keys[i].time, t1 = keys[i + 1].time, h = t1 - t0;
    const double s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -d00, d11 = 3 * s2 - 2 * s;
    const Channels p0 = channels_of(keys[i]), p1 = channels_of(keys[i + 1]);
    Channels m0{}, m1{};
    if (i > 0) {
        const Channels pm = channels_of(keys[i - 1]);
        const double dt = t1 - keys[i - 1].time;
        for (int c = 0; c < 6; ++c)
            m0[c] = pm[c] == p0[c] || p0[c] == p1[c] ? 0 : (p1[c] - pm[c]) / dt;
    }
    if (i + 2 < n) {
        const Channels pp = channels_of(keys[i + 2]);
        const double dt = keys[i + 2].time - t0;
        for (int c = 0; c < 6; ++c)
            m1[c] = p0[c] == p1[c] || p1[c] == pp[c] ? 0 : (pp[c] - p0[c]) / dt;
    }
    for (int c = 0; c < 6; ++c) {
        out.value[c] = h00 * p0[c] + h10 * h * m0[c] + h01 * p1[c] + h11 * h * m1[c];
        out.rate[c] = (d00 * p0[c] + d01 * p1[c]) / h + d10 * m0[c] + d11 * m1[c];
    }
    return out;
}

Mat3d rot_x(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << 1, 0, 0, 0, c, -s, 0, s, c;
    return m;
}
Mat3d rot_y(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << c, 0, s, 0, 1, 0, -s, 0, c;
    return m;
}
Mat3d rot_z(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << c, -s, 0, s, c, 0, 0, 0, 1;
    return m;
}
// d/da of the rotations above.
Mat3d drot_x(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << 0, 0, 0, 0, -s, -c, 0, c, -s;
    return m;
}
Mat3d drot_y(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << -s, 0, c, 0, 0, 0, -c, 0, -s;
    return m;
}
Mat3d drot_z(double a) {
    const double c = std::cos(a), s = std::sin(a);
    Mat3d m;
    m << -s, -c, 0, c, -s, 0, 0, 0, 0;
    return m;
}

// ---- presets -------------------------------------------------------------------------------

// 6x⁵ − 15x⁴ + 10x³ on [0, 1]: zero velocity and acceleration at both ends.
double smootherstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * x * (x * (6 * x - 15) + 10);
}

// ∫₀ˣ smootherstep.
double smootherstep_integral(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * x * x * (x * x - 3 * x + 2.5);
}

MotionKey pose(const Vec3d& rotate, const Vec3d& translate) {
    MotionKey k;
    k.rotate = rotate.cast<float>();
    k.translate = translate.cast<float>();
    return k;
}

// Appends keys sampling pose_at over [t0, t1] evenly, at most max_step apart, both ends
// included (t0 skipped when it repeats the last key).
template <typename PoseAt>
void sample(std::vector<MotionKey>& keys, double t0, double t1, double max_step, PoseAt&& pose_at) {
    const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) / max_step - 1e-9)));
    for (int j = 0; j <= n; ++j) {
        const double t = j == n ? t1 : t0 + (t1 - t0) * j / n;
        if (!keys.empty() && t <= keys.back().time + 1e-9) continue;
        MotionKey k = pose_at(t);
        k.time = t;
        keys.push_back(k);
    }
}

// Holds the last key's pose until t (a hold needs only its end key: equal neighbouring keys
// give a flat segment).
void hold_until(std::vector<MotionKey>& keys, double t) {
    if (!keys.empty() && t <= keys.back().time + 1e-9) return;
    MotionKey k = keys.empty() ? MotionKey{} : keys.back();
    k.time = t;
    keys.push_back(k);
}

constexpr double kGravity = 981;  // cm/s², the presets' jumps are ballistic under it

Motion preset_still(const HeadFrame& head) {
    Motion m;
    m.head.pivot = neck_pivot(head);
    m.body.pivot = hips_pivot(head);
    m.duration = 2;
    return m;
}

Motion preset_lean(const HeadFrame& head) {
    Motion m;
    m.head.pivot = hips_pivot(head);
    auto& keys = m.head.keys;
    const auto pitch = [](double deg) { return pose({deg, 0, 0}, Vec3d::Zero()); };
    hold_until(keys, 0.0);
    hold_until(keys, 0.3);
    sample(keys, 0.3, 1.3, 0.05, [&](double t) { return pitch(45 * smootherstep(t - 0.3)); });
    hold_until(keys, 2.0);
    sample(keys, 2.0, 3.0, 0.05, [&](double t) { return pitch(45 * (1 - smootherstep(t - 2))); });
    hold_until(keys, 4.0);
    m.body = m.head;
    m.duration = 4;
    return m;
}

// An oscillation of `cycles` periods starting at t = start whose amplitude envelope rises
// over the first quarter period and falls over the last (smootherstep), so the first and
// last extremes already reach full amplitude and the motion starts and stops smoothly.
// wave(phase) is the shape over one period (phase in [0, 2π)).
template <typename Wave>
double oscillation(double t, double start, double frequency, double cycles, Wave&& wave) {
    const double tau = t - start, length = cycles / frequency, ramp = 0.25 / frequency;
    if (tau <= 0 || tau >= length) return 0;
    const double envelope = smootherstep(tau / ramp) * smootherstep((length - tau) / ramp);
    return envelope * wave(2 * std::numbers::pi * frequency * tau);
}

Motion preset_shake(const HeadFrame& head) {
    Motion m;
    m.head.pivot = neck_pivot(head);
    m.body.pivot = hips_pivot(head);
    constexpr double kStart = 0.25, kFrequency = 1.5, kCycles = 3, kDegrees = 40;
    const double end = kStart + kCycles / kFrequency;
    auto& keys = m.head.keys;
    hold_until(keys, 0.0);
    hold_until(keys, kStart);
    sample(keys, kStart, end, 0.025, [&](double t) {
        const double yaw = oscillation(t, kStart, kFrequency, kCycles,
                                       [](double phase) { return kDegrees * std::sin(phase); });
        return pose({0, yaw, 0}, Vec3d::Zero());
    });
    hold_until(keys, 4.0);
    m.duration = 4;
    return m;
}

Motion preset_nod(const HeadFrame& head) {
    Motion m;
    m.head.pivot = neck_pivot(head);
    m.body.pivot = hips_pivot(head);
    constexpr double kStart = 0.25, kFrequency = 1.2, kCycles = 2;
    const double end = kStart + kCycles / kFrequency;
    auto& keys = m.head.keys;
    hold_until(keys, 0.0);
    hold_until(keys, kStart);
    sample(keys, kStart, end, 0.025, [&](double t) {
        // 17.5 s + 7.5 s²: +25° (down) at s = 1, −10° (up) at s = −1, one sign per half period.
        const double pitch = oscillation(t, kStart, kFrequency, kCycles, [](double phase) {
            const double s = std::sin(phase);
            return 17.5 * s + 7.5 * s * s;
        });
        return pose({pitch, 0, 0}, Vec3d::Zero());
    });
    hold_until(keys, 4.0);
    m.duration = 4;
    return m;
}

// Two jumps of height 1.5 R. Each: crouch to −c (smootherstep), push off with velocity
// v0·(τ/T)³ (so y = −c + c·(τ/T)⁴ reaches 0 at take-off speed v0 = √(2 g h)), a ballistic
// flight, the mirrored landing down to −c, and a smooth rise back to rest.
Motion preset_jump(const HeadFrame& head) {
    Motion m;
    m.head.pivot = neck_pivot(head);
    const double r = head.radius, height = 1.5 * r, crouch = 0.3 * r;
    const double v0 = std::sqrt(2 * kGravity * height), air = 2 * v0 / kGravity;
    const double push = 4 * crouch / v0;
    constexpr double kCrouchTime = 0.25, kRiseTime = 0.35, kGap = 0.2;
    const auto up = [](double y) { return pose(Vec3d::Zero(), {0, y, 0}); };
    auto& keys = m.head.keys;
    double t = 0.2;
    hold_until(keys, 0.0);
    for (int jump = 0; jump < 2; ++jump) {
        hold_until(keys, t);
        const double t0 = t;
        sample(keys, t0, t0 + kCrouchTime, 0.025,
               [&](double x) { return up(-crouch * smootherstep((x - t0) / kCrouchTime)); });
        const double t1 = t0 + kCrouchTime;
        sample(keys, t1, t1 + push, push / 6, [&](double x) {
            const double u = (x - t1) / push;
            return up(-crouch + crouch * u * u * u * u);
        });
        const double t2 = t1 + push;
        sample(keys, t2, t2 + air, 0.025, [&](double x) {
            const double a = x - t2;
            return up(v0 * a - 0.5 * kGravity * a * a);
        });
        const double t3 = t2 + air;
        sample(keys, t3, t3 + push, push / 6, [&](double x) {
            const double u = 1 - (x - t3) / push;
            return up(-crouch + crouch * u * u * u * u);
        });
        const double t4 = t3 + push;
        sample(keys, t4, t4 + kRiseTime, 0.025,
               [&](double x) { return up(-crouch * (1 - smootherstep((x - t4) / kRiseTime))); });
        t = t4 + kRiseTime + kGap;
    }
    m.duration = std::max(3.0, keys.back().time + 0.3);
    hold_until(keys, m.duration);
    m.body = m.head;
    return m;
}

// Forward speed v(t) = V·u(t): u rises 0 → 1 over [0, 0.5] and falls back over [3.0, 3.5]
// (smootherstep); the bob (vertical ±0.3 R at 2.6 Hz) and the forward lean (10° about the
// hips) scale with u.
Motion preset_run(const HeadFrame& head) {
    Motion m;
    m.head.pivot = hips_pivot(head);
    const double r = head.radius, speed = 30 * r;
    constexpr double kAccel = 0.5, kStop = 3.0, kDecel = 0.5, kBob = 2.6, kLean = 10;
    const auto at = [&](double t) {
        double u, z;
        if (t <= kAccel) {
            u = smootherstep(t / kAccel);
            z = speed * kAccel * smootherstep_integral(t / kAccel);
        } else if (t <= kStop) {
            u = 1;
            z = speed * (0.5 * kAccel + (t - kAccel));
        } else {
            const double x = std::min(1.0, (t - kStop) / kDecel);
            u = 1 - smootherstep(x);
            z = speed * (0.5 * kAccel + (kStop - kAccel) + kDecel * (x - smootherstep_integral(x)));
        }
        const double y = 0.3 * r * u * std::sin(2 * std::numbers::pi * kBob * t);
        return pose({kLean * u, 0, 0}, {0, y, z});
    };
    auto& keys = m.head.keys;
    sample(keys, 0, kStop + kDecel, 0.02, at);
    hold_until(keys, 4.0);
    m.body = m.head;
    m.duration = 4;
    return m;
}

// ---- reading -------------------------------------------------------------------------------

using nlohmann::json;

// A SAX pass over the document before the DOM is built: it knows the path of the value
// being parsed, so a syntax error can name the field it happened in, and it finds repeated
// fields (the DOM keeps only the last value of a repeated field, silently dropping input).
// nlohmann's callback parser would do both in one pass but is ~100× slower than this.
class JsonPaths {
  public:
    bool null() { return value(); }
    bool boolean(bool) { return value(); }
    bool number_integer(json::number_integer_t) { return value(); }
    bool number_unsigned(json::number_unsigned_t) { return value(); }
    bool number_float(json::number_float_t, const json::string_t&) { return value(); }
    bool string(json::string_t&) { return value(); }
    bool binary(json::binary_t&) { return value(); }
    bool start_object(size_t) { return start(false); }
    bool start_array(size_t) { return start(true); }
    bool end_object() { return end(); }
    bool end_array() { return end(); }
    bool key(json::string_t& name) {
        Level& top = levels_[depth_ - 1];
        top.key = name;
        if (std::find(top.keys.begin(), top.keys.end(), name) != top.keys.end()) {
            if (repeated_.empty()) repeated_ = current();
        } else {
            top.keys.push_back(name);
        }
        return true;
    }
    bool parse_error(size_t, const std::string&, const nlohmann::detail::exception& e) {
        // e.what() is "[json.exception.parse_error.101] parse error at line L, column C: ..."
        // or, for a number too large for a double, "[json.exception.out_of_range.406] ...".
        error_ = e.what();
        const size_t bracket = error_.find("] ");
        if (bracket != std::string::npos) error_ = error_.substr(bracket + 2);
        error_at_ = current();
        return false;
    }

    const std::string& error() const { return error_; }  // empty when the text is valid JSON
    const std::string& error_at() const { return error_at_; }
    const std::string& first_repeated() const { return repeated_; }  // or empty

  private:
    struct Level {
        bool array = false;
        size_t index = 0;
        std::string key;  // the current field of an object
        std::vector<std::string> keys;
    };
    bool start(bool array) {
        // Levels are reused, so their strings and key lists keep their capacity.
        if (depth_ == levels_.size()) levels_.emplace_back();
        Level& level = levels_[depth_++];
        level.array = array;
        level.index = 0;
        level.key.clear();
        level.keys.clear();
        return true;
    }
    bool end() {
        --depth_;
        return value();
    }
    bool value() {
        if (depth_ == 0) return true;
        Level& top = levels_[depth_ - 1];
        if (top.array) {
            ++top.index;
        } else {
            top.key.clear();  // between fields an error belongs to the object
        }
        return true;
    }
    // The path of the value being parsed ("" at the top level).
    std::string current() const {
        std::string path;
        for (size_t d = 0; d < depth_; ++d) {
            const Level& level = levels_[d];
            if (level.array) {
                path += cat("[", level.index, "]");
            } else if (!level.key.empty()) {
                path += path.empty() ? level.key : "." + level.key;
            }
        }
        return path;
    }

    std::vector<Level> levels_;
    size_t depth_ = 0;
    std::string error_, error_at_, repeated_;
};

// The name of a field, spelled out only when a message needs it ("head.keys[3].t"), so that
// reading a key costs no string building. A Field refers to its parent: use it within the
// expression or scope where the parent lives.
struct Field {
    const Field* parent = nullptr;
    std::string_view name;  // empty for an array element
    size_t index = 0;

    Field operator/(std::string_view child) const { return {this, child, 0}; }
    Field operator[](size_t i) const { return {this, {}, i}; }
    std::string str() const {
        std::string s = parent ? parent->str() : std::string();
        if (!name.empty()) return s.empty() ? std::string(name) : cat(s, ".", name);
        return parent ? cat(s, "[", index, "]") : s;
    }
};

const Field kRoot;

class MotionReader {
  public:
    MotionReader(std::string file, const HeadFrame& head) : file_(std::move(file)), head_(head) {}

    Motion read(const std::string& text) {
        JsonPaths paths;
        if (!json::sax_parse(text, &paths)) {
            const std::string what = excerpt(paths.error(), 200);
            if (paths.error_at().empty()) fail(file_, ": invalid JSON: ", what);
            fail(file_, ": ", excerpt(paths.error_at(), 256), ": invalid JSON: ", what);
        }
        if (!paths.first_repeated().empty())
            fail(file_, ": ", excerpt(paths.first_repeated(), 256), ": field given twice");
        json root;
        try {
            root = json::parse(text);
        } catch (const json::exception& e) {  // not expected after the SAX pass
            fail(file_, ": invalid JSON: ", e.what());
        }
        if (!root.is_object())
            fail(file_, ": expected a JSON object at the top level, found ", root.type_name());
        check_fields(
            root, kRoot,
            {"format", "version", "units", "head", "body", "gravity", "wind", "gust", "duration"});

        const json* format = find(root, "format");
        if (!format) error(kRoot / "format", "missing (expected \"wisp-motion\")");
        if (!format->is_string() || format->get_ref<const std::string&>() != "wisp-motion")
            error(kRoot / "format", "expected \"wisp-motion\", found ", excerpt(format->dump()));
        const json* version = find(root, "version");
        if (!version) error(kRoot / "version", "missing (expected 1)");
        if (!version->is_number() || version->get<double>() != 1)
            error(kRoot / "version", "expected 1, found ", excerpt(version->dump()));
        if (const json* units = find(root, "units")) {
            const bool cm = units->is_string() && units->get_ref<const std::string&>() == "cm";
            const bool head = units->is_string() && units->get_ref<const std::string&>() == "head";
            if (!cm && !head)
                error(kRoot / "units", "expected \"head\" or \"cm\", found ",
                      excerpt(units->dump()));
            head_units_ = head;
        }

        Motion m;
        m.name = file_;
        const json* head = find(root, "head");
        if (!head) error(kRoot / "head", "missing (the head track is required)");
        m.head = track(*head, kRoot / "head");
        const json* body = find(root, "body");
        m.body = body ? track(*body, kRoot / "body") : m.head;
        if (const json* g = find(root, "gravity")) m.gravity = vec3(*g, kRoot / "gravity");
        if (const json* w = find(root, "wind")) m.wind = vec3(*w, kRoot / "wind");
        if (const json* gust = find(root, "gust")) {
            const Field f = kRoot / "gust";
            if (!gust->is_object()) error(f, "expected an object, found ", gust->type_name());
            check_fields(*gust, f, {"amplitude", "frequency"});
            if (const json* a = find(*gust, "amplitude")) {
                m.gust_amplitude = to_float(number(*a, f / "amplitude"), f / "amplitude");
                if (m.gust_amplitude < 0) error(f / "amplitude", "must be ≥ 0, found ", *a);
            }
            if (const json* fr = find(*gust, "frequency")) {
                m.gust_frequency = to_float(number(*fr, f / "frequency"), f / "frequency");
                if (!(m.gust_frequency > 0)) error(f / "frequency", "must be > 0, found ", *fr);
            }
        }
        double last = 0;
        if (!m.head.keys.empty()) last = std::max(last, m.head.keys.back().time);
        if (!m.body.keys.empty()) last = std::max(last, m.body.keys.back().time);
        m.duration = last;
        if (const json* d = find(root, "duration")) {
            m.duration = number(*d, kRoot / "duration");
            if (m.duration < 0 || m.duration > kMaxMotionTime)
                error(kRoot / "duration", "must be ≥ 0 and ≤ ", kMaxMotionTime, " s, found ", *d);
        }
        return m;
    }

  private:
    template <typename... Args>
    [[noreturn]] void error(const Field& field, const Args&... what) const {
        fail(file_, ": ", excerpt(field.str(), 256), ": ", what...);
    }

    static const json* find(const json& object, const char* field) {
        const auto it = object.find(field);
        return it == object.end() ? nullptr : &*it;
    }

    void check_fields(const json& object, const Field& where,
                      std::initializer_list<std::string_view> allowed) const {
        for (const auto& [name, value] : object.items()) {
            if (std::find(allowed.begin(), allowed.end(), name) != allowed.end()) continue;
            std::string known;
            for (std::string_view a : allowed)
                known += cat(known.empty() ? "" : ", ", a);
            error(where / name, "unknown field (known: ", known, ")");
        }
    }

    double number(const json& v, const Field& field) const {
        if (!v.is_number())
            error(field, "expected a number, found ", v.type_name(), " ", excerpt(v.dump()));
        const double x = v.get<double>();
        if (!std::isfinite(x)) error(field, "not a finite number");
        return x;
    }

    float to_float(double x, const Field& field) const {
        if (std::abs(x) > std::numeric_limits<float>::max()) error(field, "out of range: ", x);
        return static_cast<float>(x);
    }

    Vec3f vec3(const json& v, const Field& field) const {
        if (!v.is_array() || v.size() != 3)
            error(field, "expected an array of 3 numbers, found ", excerpt(v.dump()));
        Vec3f out;
        for (size_t c = 0; c < 3; ++c)
            out[c] = to_float(number(v[c], field[c]), field[c]);
        return out;
    }

    // A translation or pivot in cm after unit conversion, within kMaxMotionTranslate.
    Vec3f length3(const json& v, const Field& field, bool is_pivot) const {
        Vec3f x = vec3(v, field);
        if (head_units_) x = is_pivot ? head_.to_space(x) : Vec3f(head_.radius * x);
        for (size_t c = 0; c < 3; ++c) {
            if (!(std::abs(x[c]) <= kMaxMotionTranslate))
                error(field[c], "|", x[c], " cm| exceeds ", kMaxMotionTranslate, " cm");
        }
        return x;
    }

    MotionTrack track(const json& v, const Field& field) const {
        if (!v.is_object()) error(field, "expected an object, found ", v.type_name());
        check_fields(v, field, {"pivot", "keys"});
        MotionTrack tr;
        tr.pivot = head_units_ ? head_.center : Vec3f::Zero();
        if (const json* p = find(v, "pivot")) tr.pivot = length3(*p, field / "pivot", true);
        const json* keys = find(v, "keys");
        const Field kf = field / "keys";
        if (!keys) error(kf, "missing (an empty list [] is a still track)");
        if (!keys->is_array()) error(kf, "expected an array, found ", keys->type_name());
        if (keys->size() > kMaxMotionKeys)
            error(kf, keys->size(), " keys, at most ", kMaxMotionKeys, " allowed");
        tr.keys.reserve(keys->size());
        for (size_t i = 0; i < keys->size(); ++i) {
            const json& k = (*keys)[i];
            const Field at = kf[i], tf = at / "t";
            if (!k.is_object()) error(at, "expected an object, found ", k.type_name());
            check_fields(k, at, {"t", "rotate", "translate"});
            MotionKey key;
            const json* t = find(k, "t");
            if (!t) error(tf, "missing");
            key.time = number(*t, tf);
            if (key.time < 0) error(tf, "times must be ≥ 0, found ", *t);
            if (key.time > kMaxMotionTime)
                error(tf, "times must be ≤ ", kMaxMotionTime, " s, found ", *t);
            if (!tr.keys.empty() && !(key.time > tr.keys.back().time))
                error(tf, "times must increase (", *t, " after ", tr.keys.back().time, ")");
            if (const json* r = find(k, "rotate")) {
                const Field rf = at / "rotate";
                key.rotate = vec3(*r, rf);
                for (size_t c = 0; c < 3; ++c) {
                    if (std::abs(key.rotate[c]) > kMaxMotionRotate)
                        error(rf[c], "|", key.rotate[c], "°| exceeds ", kMaxMotionRotate, "°");
                }
            }
            if (const json* tl = find(k, "translate"))
                key.translate = length3(*tl, at / "translate", false);
            tr.keys.push_back(key);
        }
        return tr;
    }

    std::string file_;
    HeadFrame head_;
    bool head_units_ = true;
};

// ---- writing -------------------------------------------------------------------------------

// Shortest text that reads back to the same value.
template <typename T>
void put_number(std::string& out, T x) {
    if (x == 0) x = 0;  // no "-0"
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
    out.append(buffer, result.ptr);
}

class MotionWriter {
  public:
    explicit MotionWriter(std::string file) : file_(std::move(file)) {}

    std::string write(const Motion& m) {
        out_ = "{\n  \"format\": \"wisp-motion\",\n  \"version\": 1,\n  \"units\": \"cm\",\n";
        out_ += "  \"duration\": ";
        number(m.duration, kRoot / "duration");
        out_ += ",\n  \"gravity\": ";
        vec3(m.gravity, kRoot / "gravity");
        out_ += ",\n  \"wind\": ";
        vec3(m.wind, kRoot / "wind");
        out_ += ",\n  \"gust\": {\"amplitude\": ";
        const Field gust = kRoot / "gust";
        number(m.gust_amplitude, gust / "amplitude");
        out_ += ", \"frequency\": ";
        number(m.gust_frequency, gust / "frequency");
        out_ += "},\n";
        // "body" is always written: without it a reader would make the body follow the head.
        track(m.head, kRoot / "head");
        out_ += ",\n";
        track(m.body, kRoot / "body");
        out_ += "\n}\n";
        return std::move(out_);
    }

  private:
    template <typename T>
    void number(T x, const Field& field) {
        if (!std::isfinite(x)) fail(file_, ": ", field.str(), ": cannot write a non-finite number");
        put_number(out_, x);
    }
    void vec3(const Vec3f& v, const Field& field) {
        out_ += "[";
        for (size_t c = 0; c < 3; ++c) {
            if (c) out_ += ", ";
            number(v[c], field[c]);
        }
        out_ += "]";
    }
    void track(const MotionTrack& tr, const Field& field) {
        out_ += cat("  \"", field.str(), "\": {\n    \"pivot\": ");
        vec3(tr.pivot, field / "pivot");
        out_ += ",\n    \"keys\": [";
        const Field keys = field / "keys";
        for (size_t i = 0; i < tr.keys.size(); ++i) {
            const MotionKey& k = tr.keys[i];
            const Field at = keys[i];
            out_ += i ? ",\n      {\"t\": " : "\n      {\"t\": ";
            number(k.time, at / "t");
            out_ += ", \"rotate\": ";
            vec3(k.rotate, at / "rotate");
            out_ += ", \"translate\": ";
            vec3(k.translate, at / "translate");
            out_ += "}";
        }
        out_ += tr.keys.empty() ? "]\n  }" : "\n    ]\n  }";
    }

    std::string file_;
    std::string out_;
};

}  // namespace

Vec3f neck_pivot(const HeadFrame& head) {
    return head.center + Vec3f(0, -1.2f * head.radius, 0);
}
Vec3f hips_pivot(const HeadFrame& head) {
    return head.center + Vec3f(0, -6.f * head.radius, 0);
}

RigidTransform MotionTrack::at(double t) const {
    if (keys.empty()) return {};
    const TrackSample s = sample_track(keys, t);
    const Mat3d r =
        rot_y(s.value[1] * kRadians) * rot_x(s.value[0] * kRadians) * rot_z(s.value[2] * kRadians);
    const Vec3d p = pivot.cast<double>();
    RigidTransform x;
    x.rotation = r.cast<float>();
    x.translation = (Vec3d(s.value[3], s.value[4], s.value[5]) + p - r * p).cast<float>();
    return x;
}

MotionKey MotionTrack::key_at(double t) const {
    MotionKey k;
    k.time = t;
    if (keys.empty()) return k;
    const TrackSample s = sample_track(keys, t);
    k.rotate = Vec3d(s.value[0], s.value[1], s.value[2]).cast<float>();
    k.translate = Vec3d(s.value[3], s.value[4], s.value[5]).cast<float>();
    return k;
}

RigidVelocity MotionTrack::velocity(double t) const {
    RigidVelocity out;
    out.pivot = pivot;
    if (keys.size() < 2) return out;
    const TrackSample s = sample_track(keys, t);
    const double pitch = s.value[0] * kRadians, yaw = s.value[1] * kRadians,
                 roll = s.value[2] * kRadians;
    const Mat3d rx = rot_x(pitch), ry = rot_y(yaw), rz = rot_z(roll);
    // Product rule on R = Ry·Rx·Rz, each factor's derivative times its angle's rate.
    out.turn = drot_y(yaw) * rx * rz * (s.rate[1] * kRadians) +
               ry * drot_x(pitch) * rz * (s.rate[0] * kRadians) +
               ry * rx * drot_z(roll) * (s.rate[2] * kRadians);
    out.linear = Vec3d(s.rate[3], s.rate[4], s.rate[5]);
    return out;
}

Vec3f Motion::wind_at(double t) const {
    const float speed = wind.norm();
    if (!(speed > 0)) return Vec3f::Zero();
    if (gust_amplitude == 0) return wind;
    const double gust = gust_amplitude * std::sin(2 * std::numbers::pi * gust_frequency * t);
    return wind * static_cast<float>(1 + gust / speed);
}

std::vector<std::string> motion_preset_names() {
    return {"lean", "shake", "nod", "jump", "run", "still"};
}

Motion motion_preset(std::string_view name, const HeadFrame& head) {
    Motion m;
    if (name == "lean") {
        m = preset_lean(head);
    } else if (name == "shake") {
        m = preset_shake(head);
    } else if (name == "nod") {
        m = preset_nod(head);
    } else if (name == "jump") {
        m = preset_jump(head);
    } else if (name == "run") {
        m = preset_run(head);
    } else if (name == "still") {
        m = preset_still(head);
    } else {
        std::string known;
        for (const std::string& n : motion_preset_names())
            known += cat(known.empty() ? "" : ", ", n);
        fail("unknown motion preset \"", excerpt(name), "\" (presets: ", known, ")");
    }
    m.name = std::string(name);
    return m;
}

Motion read_motion(const std::filesystem::path& path, const HeadFrame& head) {
    return MotionReader(path.string(), head)
        .read(read_file(path, {kMaxMotionFileBytes, "a motion file", true}));
}

Motion parse_motion(const std::string& text, const std::string& source, const HeadFrame& head) {
    if (text.size() > kMaxMotionFileBytes)
        fail(source, ": ", text.size(), " bytes, more than a motion file may hold (",
             kMaxMotionFileBytes, ")");
    return MotionReader(source, head).read(text);
}

Motion load_motion(const std::string& preset_or_path, const HeadFrame& head) {
    std::string names;
    for (const std::string& n : motion_preset_names()) {
        if (n == preset_or_path) return motion_preset(n, head);
        names += (names.empty() ? "" : ", ") + n;
    }
    std::error_code ec;
    if (!std::filesystem::exists(preset_or_path, ec))
        fail(excerpt(preset_or_path), ": neither a motion preset (", names,
             ") nor a motion file (no such file)");
    return read_motion(preset_or_path, head);
}

void write_motion(const std::filesystem::path& path, const Motion& motion) {
    write_file_atomic(path, MotionWriter(path.string()).write(motion));
}

}  // namespace wisp
