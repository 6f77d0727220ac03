// The usda writer: text built into one std::string (floats by put_shortest, the same bytes
// as std::to_chars), strands formatted in parallel blocks and joined in order, so the bytes
// never depend on the thread count.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>
#include <vector>

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "geometry/skin_normals.hpp"
#include "io/float_text.hpp"
#include "io/io_util.hpp"
#include "io/usda.hpp"

namespace wisp {
namespace {

using io_detail::append_number;
using io_detail::kShortestFloatRoom;

// Appends "(x, y, z)", USD's tuple form.
void append_tuple(std::string& out, const Vec3f& v) {
    out += '(';
    append_number(out, v.x());
    out += ", ";
    append_number(out, v.y());
    out += ", ";
    append_number(out, v.z());
    out += ')';
}

// Hot loops format straight into a char buffer: a float's text is at most 15 characters
// ("-1.1754944e-38", or "-1.23456789e-38" at a precision), so a run of k values with
// separators needs at most 17·k bytes. Writing a float may also touch scratch bytes after its
// text, up to kShortestFloatRoom from where it starts: append_raw leaves that much room.
constexpr size_t kMaxFloatChars = 16;

// precision 0: the shortest exact form; else that many significant digits (%g's form).
char* put_float(char* p, float v, int precision = 0) {
    return precision == 0
               ? io_detail::put_shortest(p, v)
               : std::to_chars(p, p + kMaxFloatChars, v, std::chars_format::general, precision).ptr;
}

char* put_vec(char* p, const Vec3f& v, int precision = 0) {
    *p++ = '(';
    p = put_float(p, v.x(), precision);
    *p++ = ',';
    *p++ = ' ';
    p = put_float(p, v.y(), precision);
    *p++ = ',';
    *p++ = ' ';
    p = put_float(p, v.z(), precision);
    *p++ = ')';
    return p;
}

// The float a reader gets back from v written at `precision` digits.
float written_value(float v, int precision) {
    char buf[kShortestFloatRoom];
    char* end = put_float(buf, v, precision);
    float back = v;
    std::from_chars(buf, end, back);
    return back;
}

// put_float through a cache of the values already formatted, for arrays that repeat a few
// values (widths: a taper along the strand, the same for strands of the same length): a hit
// copies the text instead of formatting. An open-addressing table (linear probing) holds up
// to half its slots; a direct-mapped one lost most of a 32-point taper to collisions.
struct FloatTextCache {
    static constexpr size_t kSlots = 1024, kMaxHeld = kSlots / 2;
    std::array<uint32_t, kSlots> bits{};
    std::array<uint8_t, kSlots> size{};  // 0: empty
    std::array<std::array<char, kMaxFloatChars>, kSlots> text;
    size_t held = 0;
    int precision = 0;  // of the texts held

    char* put(char* p, float v, int digits) {
        if (digits != precision) {
            size = {};
            held = 0;
            precision = digits;
        }
        const uint32_t key = std::bit_cast<uint32_t>(v);
        size_t i = (key * 2654435761u) >> 22;
        while (size[i] > 0 && bits[i] != key)
            i = (i + 1) % kSlots;
        // Whole slots are copied (the room after p holds them): a copy of the text's own
        // length compiles to `rep movs`, slower than formatting.
        if (size[i] > 0) {
            std::memcpy(p, text[i].data(), kMaxFloatChars);
            return p + size[i];
        }
        char* end = put_float(p, v, precision);
        if (held < kMaxHeld) {
            ++held;
            bits[i] = key;
            size[i] = static_cast<uint8_t>(end - p);
            std::memcpy(text[i].data(), p, kMaxFloatChars);
        }
        return end;
    }
};

// Appends up to `max_bytes` written by write(char*) -> char* end (with the scratch room of the
// last float beyond them).
template <typename Write>
void append_raw(std::string& out, size_t max_bytes, Write&& write) {
    const size_t at = out.size();
    out.resize(at + max_bytes + kShortestFloatRoom);
    char* end = write(out.data() + at);
    out.resize(static_cast<size_t>(end - out.data()));
}

// Text goes to `buf`; with a file, buf is written out whenever it grows past a few MB, so
// writing a file never holds the whole text in memory. `parts` are the block buffers of
// format_strands, kept from one array to the next so their pages are touched once.
struct Out {
    std::string buf;
    AtomicFile* file = nullptr;
    uint64_t at = 0;  // the file's bytes written so far: where buf goes
    std::vector<std::string> parts;
    int precision = 0;  // UsdaWriteOptions::precision of the strands' floats

    void flush(bool force = false) {
        if (!file || (!force && buf.size() < (8u << 20))) return;
        file->write_at(buf.data(), buf.size(), at);
        at += buf.size();
        buf.clear();
    }
};

// Formats strands in blocks: body(strand, text) appends one strand's text. The blocks are
// formatted on the worker threads while the finished ones are placed in order (a TBB pipeline
// with a serial, in-order stage), so the bytes never depend on the thread count. Into a file,
// that stage only gives each block its offset, after the blocks before it, and the last stage
// writes blocks at their offsets one at a time but in any order (ext4 holds the file's lock
// for a buffered write: parallel writes only made a thread sleep on it), so a thread never
// waits for an earlier block to be written: it formats the next one instead. A block's buffer
// comes from a pool of `tokens` (the blocks in flight) and goes back once it is written.
template <typename Body>
void format_strands(Out& out, const Hair& hair, size_t bytes_per_point, Body&& body) {
    constexpr size_t kBlock = 512;
    const size_t strands = hair.strand_count();
    const size_t blocks = (strands + kBlock - 1) / kBlock;
    if (blocks == 0) return;
    const size_t tokens = 2 * static_cast<size_t>(tbb::this_task_arena::max_concurrency()) + 2;
    if (out.parts.size() < tokens) out.parts.resize(tokens);
    out.flush(true);
    std::vector<size_t> free_parts(tokens);
    for (size_t i = 0; i < tokens; ++i)
        free_parts[i] = tokens - 1 - i;
    std::mutex free_mutex;
    struct Block {
        size_t index, part;
        uint64_t at;
    };
    size_t next = 0;
    const auto take_block = [&](tbb::flow_control& fc) -> Block {
        if (next == blocks) {
            fc.stop();
            return {};
        }
        const std::lock_guard lock(free_mutex);
        const size_t part = free_parts.back();
        free_parts.pop_back();
        return {next++, part, 0};
    };
    const auto format_block = [&](Block b) {
        const size_t lo = b.index * kBlock, hi = std::min(strands, lo + kBlock);
        std::string& s = out.parts[b.part];
        s.clear();
        s.reserve((hair.offsets[hi] - hair.offsets[lo]) * bytes_per_point + 64 * (hi - lo));
        for (size_t i = lo; i < hi; ++i)
            body(i, s);
        return b;
    };
    const auto place_block = [&](Block b) {
        if (!out.file) {
            out.buf += out.parts[b.part];
            const std::lock_guard lock(free_mutex);
            free_parts.push_back(b.part);
            return b;
        }
        b.at = out.at;
        out.at += out.parts[b.part].size();
        return b;
    };
    const auto write_block = [&](Block b) {
        if (!out.file) return;
        const std::string& s = out.parts[b.part];
        out.file->write_at(s.data(), s.size(), b.at);
        const std::lock_guard lock(free_mutex);
        free_parts.push_back(b.part);
    };
    tbb::parallel_pipeline(
        tokens,
        tbb::make_filter<void, Block>(tbb::filter_mode::serial_in_order, take_block) &
            tbb::make_filter<Block, Block>(tbb::filter_mode::parallel, format_block) &
            tbb::make_filter<Block, Block>(tbb::filter_mode::serial_in_order, place_block) &
            tbb::make_filter<Block, void>(tbb::filter_mode::serial_out_of_order, write_block));
}

// Head space (Y up) to the layer's axes: Z up turns +Y into +Z, (x, y, z) -> (x, -z, y), the
// inverse of the reader's Z-up conversion, so a Z-up layer reads back identically.
Vec3f to_layer(const Vec3f& v, bool z_up) {
    return z_up ? Vec3f(v.x(), -v.z(), v.y()) : v;
}

void points_array(Out& out, const Hair& hair, const char* indent, bool z_up = false) {
    format_strands(out, hair, 3 * kMaxFloatChars + 8, [&](size_t s, std::string& o) {
        o += indent;
        const uint32_t a = hair.offsets[s], b = hair.offsets[s + 1];
        append_raw(o, (b - a) * (3 * kMaxFloatChars + 8) + 1, [&](char* p) {
            for (uint32_t i = a; i < b; ++i) {
                p = put_vec(p, to_layer(hair.points[i], z_up), out.precision);
                if (i + 1 < hair.point_count()) {
                    *p++ = ',';
                    *p++ = ' ';
                }
            }
            *p++ = '\n';
            return p;
        });
    });
}

// The bounds of the points in the layer's axes grown by the largest half width. With a
// precision, each bound also takes in what it reads back as when rounded: rounding is
// monotonic, so every rounded point then lies inside (the extent itself is written exact).
Box3 extent_of(const Hair& hair, bool z_up = false, int precision = 0) {
    Box3 b = hair.bounds();
    if (z_up && !b.empty()) {
        const Box3 y = b;
        b.lo = Vec3f(y.lo.x(), -y.hi.z(), y.lo.y());
        b.hi = Vec3f(y.hi.x(), -y.lo.z(), y.hi.y());
    }
    const float half = hair.max_width() * 0.5f;
    if (!b.empty()) {
        b.lo -= Vec3f::Constant(half);
        b.hi += Vec3f::Constant(half);
    } else {
        b.lo = b.hi = Vec3f::Zero();
    }
    if (precision > 0)
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::min(b.lo[k], written_value(b.lo[k], precision));
            b.hi[k] = std::max(b.hi[k], written_value(b.hi[k], precision));
        }
    return b;
}

void append_extent(std::string& out, const Box3& b) {
    out += '[';
    append_tuple(out, b.lo);
    out += ", ";
    append_tuple(out, b.hi);
    out += ']';
}

void check_strands(const Hair& hair, const std::string& name) {
    hair.validate(name);
    for (size_t s = 0; s < hair.strand_count(); ++s)
        if (hair.strand_size(s) < 2)
            fail(name, ": strand ", s, " has ", hair.strand_size(s),
                 " points; a pinned catmullRom curve needs at least 2");
}

// A BasisCurves prim under the Xform up to (not including) its points, with GroomAPI
// applied when `groom_api` (what Unreal's USD importer looks for to read it as a groom).
void begin_curves(Out& o, const Hair& hair, const char* name, bool groom_api) {
    std::string& out = o.buf;
    out += cat("    def BasisCurves \"", name, "\"");
    out +=
        groom_api ? " (\n        prepend apiSchemas = [\"GroomAPI\"]\n    )\n    {\n" : "\n    {\n";
    out += "        uniform token type = \"cubic\"\n";
    out += "        uniform token basis = \"catmullRom\"\n";
    out += "        uniform token wrap = \"pinned\"\n";
    out += "        int[] curveVertexCounts = [";
    format_strands(o, hair, 0, [&](size_t s, std::string& t) {
        if (s) t += ", ";
        append_number(t, hair.strand_size(s));
    });
    out += "]\n";
}

// Header, the Xform and the BasisCurves prim "strands" up to (not including) its points.
// GroomAPI goes on the strands, or on the Xform when it holds guides too (Unreal then reads
// every BasisCurves under it into one groom). `hair_metadata` (lines) goes into the Xform's
// metadata: the value clips of an animation's top-level layer.
void begin_layer(Out& o, const Hair& hair, const std::string& extra_metadata, bool z_up = false,
                 bool groom_on_xform = false, const std::string& hair_metadata = {}) {
    std::string& out = o.buf;
    out += "#usda 1.0\n(\n    defaultPrim = \"hair\"\n";
    out += extra_metadata;
    out += z_up ? "    metersPerUnit = 0.01\n    upAxis = \"Z\"\n)\n\n"
                : "    metersPerUnit = 0.01\n    upAxis = \"Y\"\n)\n\n";
    const std::string metadata =
        (groom_on_xform ? std::string("    prepend apiSchemas = [\"GroomAPI\"]\n")
                        : std::string()) +
        hair_metadata;
    out += metadata.empty() ? "def Xform \"hair\"\n{\n"
                            : cat("def Xform \"hair\" (\n", metadata, ")\n{\n");
    begin_curves(o, hair, "strands", !groom_on_xform);
}

// An int primvar of a value(i) per strand of `hair`, or of the one value(0) when `constant`.
template <typename Value>
void int_primvar(Out& o, const Hair& hair, const char* name, bool constant, Value&& value) {
    o.buf += cat("        int[] primvars:", name, " = [");
    if (constant)
        append_number(o.buf, static_cast<int64_t>(value(0)));
    else
        format_strands(o, hair, 0, [&](size_t i, std::string& t) {
            if (i) t += ", ";
            append_number(t, static_cast<int64_t>(value(i)));
        });
    o.buf += cat("] (\n            interpolation = \"", constant ? "constant" : "uniform",
                 "\"\n        )\n");
}

// Unreal's per-strand groom attributes beyond colour: the group (per strand, or one group),
// the root's scalp UV, and with guides the guide flag, ids and each strand's guide.
// `first_id` numbers the prim's strands for groom_id; `guide_base` is the groom_id of guide 0
// for render strands (their closest guide is guide_base + wisp id), or -1 for a guides prim.
void groom_primvars(Out& o, const Hair& hair, bool with_guides, size_t first_id,
                    int64_t guide_base) {
    if (hair.group.empty())
        int_primvar(o, hair, "groom_group_id", true, [](size_t) { return 0; });
    else
        int_primvar(o, hair, "groom_group_id", false, [&](size_t i) { return hair.group[i]; });
    if (!hair.root_uv.empty()) {
        o.buf += "        float2[] primvars:groom_root_uv = [";
        format_strands(o, hair, 0, [&](size_t i, std::string& t) {
            t += i ? ", (" : "(";
            append_raw(t, 2 * kMaxFloatChars + 3, [&](char* p) {
                p = put_float(p, hair.root_uv[i].x(), o.precision);
                *p++ = ',';
                *p++ = ' ';
                p = put_float(p, hair.root_uv[i].y(), o.precision);
                *p++ = ')';
                return p;
            });
        });
        o.buf += "] (\n            interpolation = \"uniform\"\n        )\n";
    }
    if (!with_guides) return;
    const bool guide = guide_base < 0;
    int_primvar(o, hair, "groom_guide", true, [&](size_t) { return guide ? 1 : 0; });
    int_primvar(o, hair, "groom_id", false, [&](size_t i) { return first_id + i; });
    if (guide) return;
    int_primvar(o, hair, "groom_closest_guides", false,
                [&](size_t i) { return guide_base + hair.wisp[i]; });
    o.buf +=
        "        float[] primvars:groom_guide_weights = [1] (\n            interpolation = "
        "\"constant\"\n        )\n";
}

// The strands' colours as the primvar `declaration` (type and name): one value per strand
// (uniform), or the default colour (constant) when the hair has none.
void color_primvar(Out& o, const Hair& hair, const char* declaration) {
    std::string& out = o.buf;
    out += "        ";
    out += declaration;
    if (hair.colors.empty()) {
        out += " = [";
        append_tuple(out, hair.default_color);
        out += "] (\n            interpolation = \"constant\"\n        )\n";
        return;
    }
    out += " = [\n";
    const size_t S = hair.strand_count();
    format_strands(o, hair, 0, [&](size_t s, std::string& t) {
        t += "            ";
        append_raw(t, 3 * kMaxFloatChars + 8,
                   [&](char* p) { return put_vec(p, hair.colors[s], o.precision); });
        t += s + 1 < S ? ",\n" : "\n";
    });
    out += "        ] (\n            interpolation = \"uniform\"\n        )\n";
}

// widths, displayColor, wisp ids, Unreal's primvars and the prim's closing brace.
void end_curves(Out& o, const Hair& hair, bool with_guides = false, size_t first_id = 0,
                int64_t guide_base = 0) {
    o.buf += "        float[] widths = [\n";
    format_strands(o, hair, kMaxFloatChars + 2, [&](size_t s, std::string& t) {
        t += "            ";
        const uint32_t a = hair.offsets[s], b = hair.offsets[s + 1];
        append_raw(t, (b - a) * (kMaxFloatChars + 2) + 1, [&](char* p) {
            // Widths take few values (a taper along the strand, the same for strands of the
            // same length; all the default when the hair has none): a value met before on
            // this thread copies its text.
            thread_local FloatTextCache cache;
            for (uint32_t i = a; i < b; ++i) {
                p = cache.put(p, hair.width_at(i), o.precision);
                if (i + 1 < hair.point_count()) {
                    *p++ = ',';
                    *p++ = ' ';
                }
            }
            *p++ = '\n';
            return p;
        });
    });
    std::string& out = o.buf;
    out += "        ] (\n            interpolation = \"vertex\"\n        )\n";
    color_primvar(o, hair, "color3f[] primvars:displayColor");
    if (!hair.wisp.empty()) {
        out += "        int[] primvars:wisp_id = [";
        format_strands(o, hair, 0, [&](size_t s, std::string& t) {
            if (s) t += ", ";
            append_number(t, hair.wisp[s]);
        });
        out += "] (\n            interpolation = \"uniform\"\n        )\n";
    }
    // Unreal's groom attributes (primvars named groom_*, arrays even when constant: its
    // importer reads every primvar as an array); the strand color again as float3, the type
    // Unreal converts (it skips color3f).
    color_primvar(o, hair, "float3[] primvars:groom_color");
    groom_primvars(o, hair, with_guides, first_id, guide_base);
    out += "    }\n";
}

void end_layer(Out& o, const Hair& hair) {
    end_curves(o, hair);
    o.buf += "}\n";
    o.flush(true);
}

// The head as a polygon mesh beside /hair: points, triangles, the skin's smooth vertex
// normals (skin_normals: as wisp renders it) and the scalp faces as a GeomSubset.
void head_prim(Out& o, const Mesh& mesh, std::span<const uint32_t> scalp, bool z_up) {
    const std::vector<Vec3f> normals = skin_normals(mesh);
    std::string& out = o.buf;
    out += "\ndef Mesh \"head\"\n{\n    uniform token subdivisionScheme = \"none\"\n";
    Box3 b = mesh.bounds();
    if (z_up && !b.empty()) {
        const Box3 y = b;
        b.lo = Vec3f(y.lo.x(), -y.hi.z(), y.lo.y());
        b.hi = Vec3f(y.hi.x(), -y.lo.z(), y.hi.y());
    }
    if (b.empty()) b.lo = b.hi = Vec3f::Zero();
    out += "    float3[] extent = ";
    append_extent(out, b);
    out += "\n    int[] faceVertexCounts = [";
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        out += f ? ", 3" : "3";
    out += "]\n    int[] faceVertexIndices = [";
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            if (f || k) out += ", ";
            append_number(out, mesh.faces[f][k]);
        }
    // Positions and normals turn with the up axis; colours (`turn` false) do not.
    const auto vec_array = [&](const char* decl, const std::vector<Vec3f>& v, bool turn = true) {
        out += decl;
        for (size_t i = 0; i < v.size(); ++i) {
            if (i) out += ", ";
            append_tuple(out, turn ? to_layer(v[i], z_up) : v[i]);
            if ((i & 65535) == 65535) o.flush();
        }
        out += ']';
    };
    vec_array("]\n    point3f[] points = [", mesh.vertices);
    vec_array("\n    normal3f[] normals = [", normals);
    out += " (\n        interpolation = \"vertex\"\n    )\n";
    if (!mesh.colors.empty()) {
        // The face's albedo (the built-in head's eyes and lips), linear RGB as USD's colours
        // are: Blender's importer makes it a colour attribute, usdview shows it.
        vec_array("    color3f[] primvars:displayColor = [", mesh.colors, false);
        out += " (\n        interpolation = \"vertex\"\n    )\n";
    }
    if (!scalp.empty()) {
        out +=
            "\n    def GeomSubset \"scalp\"\n    {\n        uniform token elementType = "
            "\"face\"\n        uniform token familyName = \"scalp\"\n        int[] indices = [";
        for (size_t i = 0; i < scalp.size(); ++i) {
            if (i) out += ", ";
            append_number(out, scalp[i]);
        }
        out += "]\n    }\n";
    }
    out += "}\n";
    o.flush();
}

void curves_body(Out& out, const Hair& hair, bool z_up) {
    out.buf += "        float3[] extent = ";
    append_extent(out.buf, extent_of(hair, z_up, out.precision));
    out.buf += "\n        point3f[] points = [\n";
    points_array(out, hair, "            ", z_up);
    out.buf += "        ]\n";
}

void write_single(Out& out, const Hair& hair, const UsdaWriteOptions& options) {
    const Hair* guides = options.guides;
    begin_layer(out, hair,
                cat("    doc = \"wisp hair: ", hair.strand_count(), " strands, ",
                    hair.point_count(), " control points\"\n"),
                options.z_up, guides != nullptr);
    curves_body(out, hair, options.z_up);
    const size_t S = hair.strand_count();
    end_curves(out, hair, guides != nullptr, 0, static_cast<int64_t>(S));
    if (guides) {
        out.buf += '\n';
        begin_curves(out, *guides, "guides", false);
        curves_body(out, *guides, options.z_up);
        end_curves(out, *guides, true, S, -1);
    }
    out.buf += "}\n";
    if (options.head) head_prim(out, *options.head, options.head_scalp, options.z_up);
    out.flush(true);
}

void check_precision(int precision, const std::string& name) {
    if (precision < 0 || precision > kMaxUsdaPrecision)
        fail(name, ": precision ", precision, " is not 0 (exact) or 1 … ", kMaxUsdaPrecision,
             " significant digits");
}

void check_options(const Hair& hair, const UsdaWriteOptions& options, const std::string& name) {
    check_precision(options.precision, name);
    if (options.guides) {
        check_strands(*options.guides, name + " guides");
        if (hair.wisp.empty() && hair.strand_count())
            fail(name, ": guides need the strands' wisp ids (which guide drives each strand)");
        for (size_t s = 0; s < hair.wisp.size(); ++s)
            if (hair.wisp[s] < 0 || size_t(hair.wisp[s]) >= options.guides->strand_count())
                fail(name, ": strand ", s, " has wisp id ", hair.wisp[s], ", but there are ",
                     options.guides->strand_count(), " guides");
    }
    if (const Mesh* m = options.head) {
        for (size_t f = 0; f < m->faces.size(); ++f)
            for (int k = 0; k < 3; ++k)
                if (m->faces[f][k] < 0 || size_t(m->faces[f][k]) >= m->vertices.size())
                    fail(name, ": head face ", f, " has vertex ", m->faces[f][k], " of ",
                         m->vertices.size());
        for (const Vec3f& v : m->vertices)
            if (!v.allFinite()) fail(name, ": the head has a vertex that is not finite");
        if (!m->colors.empty() && m->colors.size() != m->vertices.size())
            fail(name, ": the head has ", m->colors.size(), " vertex colours for ",
                 m->vertices.size(), " vertices");
        for (const Vec3f& c : m->colors)
            if (!c.allFinite()) fail(name, ": the head has a vertex colour that is not finite");
        for (uint32_t f : options.head_scalp)
            if (f >= m->faces.size())
                fail(name, ": scalp face ", f, " of ", m->faces.size(), " head faces");
    }
}

// The checks of both animation writers before frame `index` of `frames` is written: not one
// too many, valid, and frame 0's strands.
void check_next_frame(const std::filesystem::path& path, const Hair& first, const Hair& frame,
                      size_t index, size_t frames) {
    if (index == frames) fail(path.string(), ": more frames than announced (", frames, ")");
    frame.validate(cat(path.string(), " frame ", index));
    if (frame.offsets != first.offsets)
        fail(path.string(), ": frame ", index,
             " has a different topology (strand point counts) than frame 0");
}

void check_frames(const std::vector<Hair>& frames, double fps, const std::string& name) {
    if (frames.empty()) fail(name, ": an animation needs at least one frame");
    if (!(fps > 0) || !std::isfinite(fps))
        fail(name, ": frames per second must be positive, not ", fps);
    check_strands(frames.front(), name);
    for (size_t f = 1; f < frames.size(); ++f) {
        frames[f].validate(cat(name, " frame ", f));
        if (frames[f].offsets != frames.front().offsets)
            fail(name, ": frame ", f,
                 " has a different topology (strand point counts) than frame 0");
    }
}

std::string animation_metadata(size_t frames, double fps) {
    std::string meta;
    meta += "    endTimeCode = ";
    append_number(meta, frames - 1);
    meta += "\n    framesPerSecond = ";
    append_number(meta, fps);
    meta += "\n    startTimeCode = 0\n    timeCodesPerSecond = ";
    append_number(meta, fps);
    meta += "\n";
    return meta;
}

// The points' time samples come first and the extents after them (attribute order does
// not matter in a layer), so frames can be written as they are made.
void add_animation_frame(Out& out, const Hair& frame, size_t index) {
    out.buf += "            ";
    append_number(out.buf, index);
    out.buf += ": [\n";
    points_array(out, frame, "                ");
    out.buf += "            ],\n";
}

// The render strands at rest, written whole with their guide binding, and the guides prim up
// to its points (guides mode of the animation writers: the frames are the guides).
void begin_guides_layer(Out& out, const Hair& strands, const Hair& guides,
                        const std::string& metadata, const std::string& hair_metadata = {}) {
    begin_layer(out, strands, metadata, false, true, hair_metadata);
    curves_body(out, strands, false);
    end_curves(out, strands, true, 0, static_cast<int64_t>(strands.strand_count()));
    out.buf += '\n';
    begin_curves(out, guides, "guides", false);
}

// Closes the animated prim (`first`'s strands, or with `strands` its guides) and the layer.
void end_animated_layer(Out& out, const Hair& first, const Hair* strands) {
    if (!strands) return end_layer(out, first);
    end_curves(out, first, true, strands->strand_count(), -1);
    out.buf += "}\n";
    out.flush(true);
}

void end_animation(Out& out, const Hair& first, const std::vector<Box3>& extents,
                   const Hair* strands = nullptr) {
    out.buf += "        }\n        float3[] extent.timeSamples = {\n";
    for (size_t f = 0; f < extents.size(); ++f) {
        out.buf += "            ";
        append_number(out.buf, f);
        out.buf += ": ";
        append_extent(out.buf, extents[f]);
        out.buf += ",\n";
    }
    out.buf += "        }\n";
    end_animated_layer(out, first, strands);
}

void write_animation(Out& out, const std::vector<Hair>& frames, double fps) {
    const Hair& first = frames.front();
    begin_layer(out, first, animation_metadata(frames.size(), fps));
    out.buf += "        point3f[] points.timeSamples = {\n";
    std::vector<Box3> extents;
    for (size_t f = 0; f < frames.size(); ++f) {
        add_animation_frame(out, frames[f], f);
        extents.push_back(extent_of(frames[f]));
    }
    end_animation(out, first, extents);
}

}  // namespace

std::string encode_usda(const Hair& hair, const std::string& name,
                        const UsdaWriteOptions& options) {
    check_strands(hair, name);
    check_options(hair, options, name);
    Out out;
    out.precision = options.precision;
    out.buf.reserve(hair.point_count() * 48 + hair.strand_count() * 96 + 1024);
    write_single(out, hair, options);
    return std::move(out.buf);
}

void write_usda(const std::filesystem::path& path, const Hair& hair,
                const UsdaWriteOptions& options) {
    check_strands(hair, path.string());
    check_options(hair, options, path.string());
    AtomicFile file(path);
    Out out;
    out.file = &file;
    out.precision = options.precision;
    write_single(out, hair, options);
    file.commit();
}

std::string encode_usda_animation(const std::vector<Hair>& frames, double fps,
                                  const std::string& name) {
    check_frames(frames, fps, name);
    Out out;
    write_animation(out, frames, fps);
    return std::move(out.buf);
}

void write_usda_animation(const std::filesystem::path& path, const std::vector<Hair>& frames,
                          double fps) {
    check_frames(frames, fps, path.string());
    AtomicFile file(path);
    Out out;
    out.file = &file;
    write_animation(out, frames, fps);
    file.commit();
}

struct UsdaAnimationWriter::Impl {
    AtomicFile file;
    Out out;
    Hair first;                   // topology, widths, colors and wisp ids of frame 0
    std::optional<Hair> strands;  // guides mode: the render strands at rest
    size_t frames, written = 0;
    std::vector<Box3> extents;
    explicit Impl(const std::filesystem::path& path) : file(path) {}
};

namespace {

// Guides mode: the render strands are bound to the guides by their wisp ids.
void check_guides_mode(const Hair& strands, const Hair& guides, const std::string& name) {
    check_strands(strands, name);
    check_options(strands, UsdaWriteOptions{.guides = &guides}, name);
}

}  // namespace

UsdaAnimationWriter::UsdaAnimationWriter(const std::filesystem::path& path, const Hair& first,
                                         double fps, size_t frames, const Hair* strands,
                                         int precision)
    : path_(path) {
    if (frames == 0) fail(path.string(), ": an animation needs at least one frame");
    if (!(fps > 0) || !std::isfinite(fps))
        fail(path.string(), ": frames per second must be positive, not ", fps);
    check_precision(precision, path.string());
    check_strands(first, path.string());
    if (strands) check_guides_mode(*strands, first, path.string());
    impl_ = std::make_unique<Impl>(path);
    impl_->out.file = &impl_->file;
    impl_->out.precision = precision;
    impl_->first = first;
    if (strands) impl_->strands = *strands;
    impl_->frames = frames;
    if (strands)
        begin_guides_layer(impl_->out, *strands, first, animation_metadata(frames, fps));
    else
        begin_layer(impl_->out, first, animation_metadata(frames, fps));
    impl_->out.buf += "        point3f[] points.timeSamples = {\n";
}

UsdaAnimationWriter::~UsdaAnimationWriter() = default;

void UsdaAnimationWriter::add(const Hair& frame) {
    Impl& m = *impl_;
    check_next_frame(path_, m.first, frame, m.written, m.frames);
    add_animation_frame(m.out, frame, m.written);
    m.extents.push_back(extent_of(frame, false, m.out.precision));
    ++m.written;
    m.out.flush();
}

void UsdaAnimationWriter::finish() {
    Impl& m = *impl_;
    if (m.written != m.frames)
        fail(path_.string(), ": ", m.written, " frames written of ", m.frames, " announced");
    end_animation(m.out, m.first, m.extents, m.strands ? &*m.strands : nullptr);
    m.file.commit();
}

// ---- Value clips

namespace {

int frame_digits(size_t frames) {
    int d = 1;
    for (size_t n = frames > 0 ? frames - 1 : 0; n >= 10; n /= 10)
        ++d;
    return std::max(4, d);
}

// `<dir>/<stem>.` for the files beside `path`.
std::string clip_prefix(const std::filesystem::path& path) {
    return (path.parent_path() / path.stem()).string() + ".";
}

void write_clip_frame(const std::filesystem::path& file, const Hair& frame, size_t index,
                      const std::string& top, const char* prim, int precision) {
    AtomicFile f(file);
    Out out;
    out.file = &f;
    out.precision = precision;
    out.buf += cat("#usda 1.0\n(\n    doc = \"wisp animation: frame ", index, ", a value clip of ",
                   top, "\"\n)\n\n");
    out.buf += cat("over \"hair\"\n{\n    over BasisCurves \"", prim, "\"\n    {\n");
    out.buf += "        float3[] extent.timeSamples = {\n            ";
    append_number(out.buf, index);
    out.buf += ": ";
    append_extent(out.buf, extent_of(frame, false, precision));
    out.buf += ",\n        }\n        point3f[] points.timeSamples = {\n";
    add_animation_frame(out, frame, index);
    out.buf += "        }\n    }\n}\n";
    out.flush(true);
    f.commit();
}

}  // namespace

struct UsdaClipWriter::Impl {
    Hair first;
    std::optional<Hair> strands;  // guides mode: the render strands at rest
    double fps = 24;
    size_t frames = 0, written = 0;
    int precision = 0;  // UsdaWriteOptions::precision
    FileSeries series;
    Impl(const std::filesystem::path& path, size_t n)
        : series(clip_prefix(path), ".usda", frame_digits(n)) {}
};

std::filesystem::path UsdaClipWriter::frame_path(const std::filesystem::path& path, size_t i,
                                                 size_t frames) {
    std::string n = std::to_string(i);
    const auto digits = static_cast<size_t>(frame_digits(frames));
    if (n.size() < digits) n.insert(0, digits - n.size(), '0');
    return clip_prefix(path) + n + ".usda";
}

UsdaClipWriter::UsdaClipWriter(const std::filesystem::path& path, const Hair& first, double fps,
                               size_t frames, const Hair* strands, int precision)
    : path_(path) {
    const std::string name = path.string();
    if (frames == 0) fail(name, ": an animation needs at least one frame");
    if (!(fps > 0) || !std::isfinite(fps))
        fail(name, ": frames per second must be positive, not ", fps);
    check_precision(precision, name);
    // The frame files are named in the top layer as @./<stem>.<i>.usda@.
    const std::string stem = path.stem().string();
    if (stem.empty() || stem.find('@') != std::string::npos || excerpt(stem, SIZE_MAX) != stem)
        fail(name,
             ": a value clip animation needs a file name without `@` or control "
             "characters (its frames are named after it)");
    check_strands(first, name);
    if (strands) check_guides_mode(*strands, first, name);
    impl_ = std::make_unique<Impl>(path, frames);
    impl_->first = first;
    if (strands) impl_->strands = *strands;
    impl_->fps = fps;
    impl_->frames = frames;
    impl_->precision = precision;
}

UsdaClipWriter::~UsdaClipWriter() = default;

void UsdaClipWriter::add(const Hair& frame) {
    Impl& m = *impl_;
    check_next_frame(path_, m.first, frame, m.written, m.frames);
    const std::filesystem::path file = m.series.path(m.written);
    write_clip_frame(file, frame, m.written, path_.filename().string(),
                     m.strands ? "guides" : "strands", m.precision);
    m.series.added(m.written);
    ++m.written;
}

void UsdaClipWriter::finish() {
    Impl& m = *impl_;
    if (m.written != m.frames)
        fail(path_.string(), ": ", m.written, " frames written of ", m.frames, " announced");
    const std::string stem = path_.stem().string();
    const std::filesystem::path manifest = path_.parent_path() / (stem + ".manifest.usda");
    write_file_atomic(manifest,
                      "#usda 1.0\n(\n    doc = \"wisp animation: the attributes its value clips "
                      "animate\"\n)\n\nover \"hair\"\n{\n    over \"" +
                          std::string(m.strands ? "guides" : "strands") +
                          "\"\n    {\n"
                          "        float3[] extent\n        point3f[] points\n    }\n}\n");
    try {
        std::string clips = "    clips = {\n        dictionary default = {\n";
        std::string pairs;
        for (size_t f = 0; f < m.frames; ++f)
            pairs += cat(f ? ", (" : "(", f, ", ", f, ")");
        clips += cat("            double2[] active = [", pairs, "]\n");
        clips += "            asset[] assetPaths = [";
        for (size_t f = 0; f < m.frames; ++f)
            clips +=
                cat(f ? ", @./" : "@./", frame_path(path_, f, m.frames).filename().string(), "@");
        clips += "]\n";
        clips +=
            cat("            asset manifestAssetPath = @./", manifest.filename().string(), "@\n");
        clips += "            string primPath = \"/hair\"\n";
        clips += cat("            double2[] times = [", pairs, "]\n        }\n    }\n");
        AtomicFile file(path_);
        Out out;
        out.file = &file;
        out.precision = m.precision;
        const Hair* strands = m.strands ? &*m.strands : nullptr;
        if (strands)
            begin_guides_layer(out, *strands, m.first, animation_metadata(m.frames, m.fps), clips);
        else
            begin_layer(out, m.first, animation_metadata(m.frames, m.fps), false, false, clips);
        // Declared without a value: a local value would be stronger than the clips.
        out.buf += "        float3[] extent\n        point3f[] points\n";
        end_animated_layer(out, m.first, strands);
        file.commit();
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(manifest, ec);
        throw;
    }
    m.series.keep();
}

}  // namespace wisp
