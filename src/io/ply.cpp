#include "io/ply.hpp"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <limits>
#include <optional>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/io_util.hpp"

namespace wisp {
namespace {

enum class Type { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class Format { kAscii, kBinaryLE, kBinaryBE };

std::optional<Type> type_from_name(std::string_view s) {
    if (s == "char" || s == "int8") return Type::kInt8;
    if (s == "uchar" || s == "uint8") return Type::kUint8;
    if (s == "short" || s == "int16") return Type::kInt16;
    if (s == "ushort" || s == "uint16") return Type::kUint16;
    if (s == "int" || s == "int32") return Type::kInt32;
    if (s == "uint" || s == "uint32") return Type::kUint32;
    if (s == "float" || s == "float32") return Type::kFloat32;
    if (s == "double" || s == "float64") return Type::kFloat64;
    return std::nullopt;
}

size_t type_size(Type t) {
    switch (t) {
        case Type::kInt8:
        case Type::kUint8:
            return 1;
        case Type::kInt16:
        case Type::kUint16:
            return 2;
        case Type::kInt32:
        case Type::kUint32:
        case Type::kFloat32:
            return 4;
        case Type::kFloat64:
            return 8;
    }
    return 0;
}

struct Property {
    std::string name;
    Type type = Type::kFloat32;
    bool list = false;
    Type count_type = Type::kUint8;
    std::vector<double> values;  // #count, scalar properties only (lists are skipped)
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;

    const Property* find(std::string_view n) const {
        for (const Property& p : props)
            if (p.name == n && !p.list) return &p;
        return nullptr;
    }
};

template <typename T>
T load(const char* p, bool swap) {
    T v;
    std::memcpy(&v, p, sizeof v);
    if (swap && sizeof(T) > 1) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof v);
        std::reverse(b, b + sizeof(T));
        std::memcpy(&v, b, sizeof v);
    }
    return v;
}

double load_value(Type t, const char* p, bool swap) {
    switch (t) {
        case Type::kInt8:
            return load<int8_t>(p, swap);
        case Type::kUint8:
            return load<uint8_t>(p, swap);
        case Type::kInt16:
            return load<int16_t>(p, swap);
        case Type::kUint16:
            return load<uint16_t>(p, swap);
        case Type::kInt32:
            return load<int32_t>(p, swap);
        case Type::kUint32:
            return load<uint32_t>(p, swap);
        case Type::kFloat32:
            return load<float>(p, swap);
        case Type::kFloat64:
            return load<double>(p, swap);
    }
    return 0;
}

// The ascii body as a stream of words with line numbers for errors.
class AsciiWords {
  public:
    AsciiWords(std::string_view text, size_t line, const std::string& name)
        : text_(text), line_(line), name_(name) {}
    std::string_view next(std::string_view what) {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
            if (text_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ == text_.size()) fail(name_, ":", line_, ": file ends before ", what);
        const size_t start = pos_;
        while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])))
            ++pos_;
        return text_.substr(start, pos_ - start);
    }
    double number(std::string_view what) {
        const std::string_view w = next(what);
        double v;
        if (!io_detail::parse_number(w, v))
            fail(name_, ":", line_, ": `", excerpt(w), "` is not a number (", what, ")");
        return v;
    }
    size_t line() const { return line_; }
    size_t remaining() const { return text_.size() - pos_; }

  private:
    std::string_view text_;
    size_t pos_ = 0, line_;
    const std::string& name_;
};

}  // namespace

Hair decode_ply(std::string_view bytes, const std::string& name) {
    // Header: text lines up to and including "end_header".
    std::vector<Element> elements;
    std::optional<Format> format;
    float default_width = Hair().default_width;
    Vec3f default_color = Hair().default_color;
    size_t pos = 0, line_no = 0;
    bool ended = false;
    while (!ended) {
        if (pos >= bytes.size()) fail(name, ":", line_no, ": header has no end_header line");
        size_t eol = bytes.find('\n', pos);
        if (eol == std::string_view::npos) eol = bytes.size();
        std::string_view line = bytes.substr(pos, eol - pos);
        pos = std::min(eol + 1, bytes.size());
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        std::vector<std::string_view> w;
        for (size_t i = 0; i < line.size();) {
            while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
                ++i;
            size_t j = i;
            while (j < line.size() && line[j] != ' ' && line[j] != '\t')
                ++j;
            if (j > i) w.push_back(line.substr(i, j - i));
            i = j;
        }
        auto bad = [&](const auto&... what) { fail(name, ":", line_no, ": ", what...); };
        if (line_no == 1) {
            if (line != "ply") bad("not a PLY file (first line is not `ply`)");
            continue;
        }
        if (w.empty()) continue;
        if (w[0] == "comment") {
            if (w.size() >= 4 && w[1] == "wisp" && w[2] == "default_width") {
                float v;
                if (!io_detail::parse_number(w[3], v) || !std::isfinite(v) || v < 0.f)
                    bad("bad default_width `", excerpt(w[3]), "`");
                default_width = v;
            } else if (w.size() >= 6 && w[1] == "wisp" && w[2] == "default_color") {
                for (int k = 0; k < 3; ++k)
                    if (!io_detail::parse_number(w[3 + k], default_color[k]) ||
                        !std::isfinite(default_color[k]))
                        bad("bad default_color `", excerpt(w[3 + k]), "`");
            }
        } else if (w[0] == "obj_info") {
        } else if (w[0] == "format") {
            if (w.size() < 2) bad("format without a value");
            if (w[1] == "ascii")
                format = Format::kAscii;
            else if (w[1] == "binary_little_endian")
                format = Format::kBinaryLE;
            else if (w[1] == "binary_big_endian")
                format = Format::kBinaryBE;
            else
                bad("unknown format `", excerpt(w[1]), "`");
        } else if (w[0] == "element") {
            if (w.size() != 3) bad("expected `element <name> <count>`");
            Element e;
            e.name = excerpt(w[1]);  // names are matched against plain ones and quoted
            if (!io_detail::parse_number(w[2], e.count))
                bad("bad element count `", excerpt(w[2]), "`");
            elements.push_back(std::move(e));
        } else if (w[0] == "property") {
            if (elements.empty()) bad("property before any element");
            Property p;
            if (w.size() == 5 && w[1] == "list") {
                const auto ct = type_from_name(w[2]), vt = type_from_name(w[3]);
                if (!ct || !vt) bad("unknown list property type");
                if (*ct == Type::kFloat32 || *ct == Type::kFloat64)
                    bad("list count must be an integer type");
                p.list = true;
                p.count_type = *ct;
                p.type = *vt;
                p.name = excerpt(w[4]);
            } else if (w.size() == 3) {
                const auto t = type_from_name(w[1]);
                if (!t) bad("unknown property type `", excerpt(w[1]), "`");
                p.type = *t;
                p.name = excerpt(w[2]);
            } else {
                bad("expected `property <type> <name>` or `property list <count type> <type> "
                    "<name>`");
            }
            elements.back().props.push_back(std::move(p));
        } else if (w[0] == "end_header") {
            ended = true;
        } else {
            bad("unknown header line `", excerpt(w[0]), "`");
        }
    }
    if (!format) fail(name, ": header has no format line");

    // Body. Element counts are checked against the bytes left before any allocation.
    if (*format == Format::kAscii) {
        AsciiWords in(bytes.substr(pos), line_no + 1, name);
        for (Element& e : elements) {
            if (e.props.empty()) continue;
            if (e.count > in.remaining() / std::max<size_t>(1, e.props.size()) + 1)
                fail(name, ":", in.line(), ": element ", e.name, " declares ", e.count,
                     " records, more than the ", in.remaining(), " bytes left can hold");
            for (Property& p : e.props)
                if (!p.list) p.values.resize(e.count);
            for (uint64_t r = 0; r < e.count; ++r)
                for (Property& p : e.props) {
                    if (!p.list) {
                        p.values[r] = in.number(p.name.c_str());
                        continue;
                    }
                    const double n = in.number(p.name.c_str());
                    if (!(n >= 0 && n == std::floor(n)))
                        fail(name, ":", in.line(), ": bad list length ", n);
                    for (double k = 0; k < n; ++k)
                        in.number(p.name.c_str());
                }
        }
    } else {
        const bool swap = *format == Format::kBinaryBE;
        io_detail::ByteReader in(bytes.substr(pos), name);
        for (Element& e : elements) {
            if (e.props.empty()) continue;
            uint64_t min_record = 0;
            for (const Property& p : e.props)
                min_record += type_size(p.list ? p.count_type : p.type);
            if (min_record == 0 || e.count > in.remaining() / min_record)
                in.fail_at(pos + in.offset(), "element ", e.name, " declares ", e.count,
                           " records of at least ", min_record, " bytes, but only ", in.remaining(),
                           " bytes are left");
            for (Property& p : e.props)
                if (!p.list) p.values.resize(e.count);
            for (uint64_t r = 0; r < e.count; ++r)
                for (Property& p : e.props) {
                    if (!p.list) {
                        const size_t sz = type_size(p.type);
                        in.require(sz, p.name);
                        p.values[r] = load_value(p.type, in.view(sz, p.name).data(), swap);
                        continue;
                    }
                    const size_t cs = type_size(p.count_type);
                    const double n = load_value(p.count_type, in.view(cs, p.name).data(), swap);
                    if (n < 0) in.fail_at(pos + in.offset(), "negative list length");
                    in.view(size_t(n) * type_size(p.type), p.name);
                }
        }
    }

    // Hair from the elements.
    const Element* vertex = nullptr;
    const Element* edge = nullptr;
    const Element* strand = nullptr;
    for (const Element& e : elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name == "edge") edge = &e;
        if (e.name == "strand") strand = &e;
    }
    if (!vertex) fail(name, ": no `vertex` element");
    const Property* px = vertex->find("x");
    const Property* py = vertex->find("y");
    const Property* pz = vertex->find("z");
    if (!px || !py || !pz) fail(name, ": element vertex needs properties x, y and z");
    const Property* pw = vertex->find("width");
    const size_t nv = vertex->count;
    if (nv > UINT32_MAX) fail(name, ": more than 2^32 vertices");

    std::vector<uint32_t> index;
    std::vector<uint32_t> offsets{0};
    if (strand) {
        const Property* pc = strand->find("vertex_count");
        if (!pc) fail(name, ": element strand needs property vertex_count");
        uint64_t sum = 0;
        for (size_t s = 0; s < strand->count; ++s) {
            const double n = pc->values[s];
            // Compared as doubles before any conversion: a count of 1e300 or NaN is an
            // error, not undefined behaviour.
            if (!(n >= 0 && n == std::floor(n) && n <= double(nv - sum)))
                fail(name, ": strand ", s, " has vertex_count ", n, ", which runs past the ", nv,
                     " vertices");
            sum += uint64_t(n);
            offsets.push_back(static_cast<uint32_t>(sum));
        }
        if (sum != nv)
            fail(name, ": strand vertex counts add up to ", sum, " but there are ", nv,
                 " vertices");
        index.resize(nv);
        for (size_t i = 0; i < nv; ++i)
            index[i] = static_cast<uint32_t>(i);
    } else if (edge) {
        const Property* a = edge->find("vertex1");
        const Property* b = edge->find("vertex2");
        if (!a || !b) fail(name, ": element edge needs properties vertex1 and vertex2");
        for (size_t k = 0; k < edge->count; ++k) {
            const double va = a->values[k], vb = b->values[k];
            if (!(va >= 0 && va < double(nv) && va == std::floor(va)) ||
                !(vb >= 0 && vb < double(nv) && vb == std::floor(vb)))
                fail(name, ": edge ", k, " (", va, ", ", vb, ") refers to a vertex outside 0..",
                     nv - 1);
            if (offsets.size() > 1 && index.back() == uint32_t(va)) {
                index.push_back(uint32_t(vb));
                offsets.back() = static_cast<uint32_t>(index.size());
            } else {
                index.push_back(uint32_t(va));
                index.push_back(uint32_t(vb));
                offsets.push_back(static_cast<uint32_t>(index.size()));
            }
        }
    } else {
        fail(name, ": neither a `strand` nor an `edge` element: no strands to read");
    }

    Hair hair;
    hair.default_width = default_width;
    hair.default_color = default_color;
    hair.offsets = std::move(offsets);
    hair.points.resize(index.size());
    for (size_t k = 0; k < index.size(); ++k) {
        const uint32_t i = index[k];
        const double x = px->values[i], y = py->values[i], z = pz->values[i];
        // Checked as doubles: converting a double beyond float's range is undefined.
        if (!(std::abs(x) <= kMaxCoordinate && std::abs(y) <= kMaxCoordinate &&
              std::abs(z) <= kMaxCoordinate))
            fail(name, ": vertex ", i, " is not finite or farther than ", kMaxCoordinate,
                 " cm from the origin: (", x, ", ", y, ", ", z, ")");
        hair.points[k] = Vec3f(float(x), float(y), float(z));
    }
    if (pw) {
        hair.widths.resize(index.size());
        for (size_t k = 0; k < index.size(); ++k) {
            const double w = pw->values[index[k]];
            if (!(w >= 0 && w <= kMaxCoordinate))
                fail(name, ": vertex ", index[k], " width ", w,
                     " is negative, not finite or absurdly large");
            hair.widths[k] = float(w);
        }
    }
    if (strand) {
        const Property* r = strand->find("red");
        const Property* g = strand->find("green");
        const Property* b = strand->find("blue");
        if (r && g && b) {
            const double scale = r->type == Type::kUint8 ? 1.0 / 255.0 : 1.0;
            hair.colors.resize(strand->count);
            for (size_t s = 0; s < strand->count; ++s) {
                const double c[3] = {r->values[s] * scale, g->values[s] * scale,
                                     b->values[s] * scale};
                for (double v : c)
                    if (!(std::abs(v) <= std::numeric_limits<float>::max()))
                        fail(name, ": strand ", s, " color component ", v, " is not finite");
                hair.colors[s] = Vec3f(float(c[0]), float(c[1]), float(c[2]));
            }
        }
        if (const Property* id = strand->find("wisp_id")) {
            hair.wisp.resize(strand->count);
            for (size_t s = 0; s < strand->count; ++s) {
                const double v = id->values[s];
                if (!(v == std::floor(v) && v >= INT32_MIN && v <= INT32_MAX))
                    fail(name, ": strand ", s, " has wisp_id ", v,
                         ", which is not a whole number in the int32 range");
                hair.wisp[s] = int32_t(v);
            }
        }
    }
    hair.validate(name);
    return hair;
}

Hair read_ply(const std::filesystem::path& path) {
    return decode_ply(io_detail::read_whole_file(
                          path, {io_detail::kMaxHairFileBytes, "a PLY file", false, "ply"}),
                      path.string());
}

std::string encode_ply(const Hair& hair, const std::string& name) {
    hair.validate(name);
    const size_t S = hair.strand_count(), P = hair.point_count();
    if (P > size_t(INT32_MAX)) fail(name, ": too many points for PLY int indices");
    size_t E = 0;
    for (size_t s = 0; s < S; ++s)
        E += hair.strand_size(s) > 0 ? hair.strand_size(s) - 1 : 0;
    const bool widths = !hair.widths.empty(), colors = !hair.colors.empty(),
               wisp = !hair.wisp.empty();

    std::string out;
    out += "ply\nformat binary_little_endian 1.0\n";
    out += "comment wisp hair: strands as vertex chains, centimetres, Y up\n";
    out += "comment wisp default_width ";
    io_detail::append_number(out, hair.default_width);
    out += "\ncomment wisp default_color ";
    for (int k = 0; k < 3; ++k) {
        io_detail::append_number(out, hair.default_color[k]);
        out += k < 2 ? " " : "\n";
    }
    out += cat("element vertex ", P, "\nproperty float x\nproperty float y\nproperty float z\n");
    if (widths) out += "property float width\n";
    out += cat("element edge ", E, "\nproperty int vertex1\nproperty int vertex2\n");
    out += cat("element strand ", S, "\nproperty int vertex_count\n");
    if (colors) out += "property float red\nproperty float green\nproperty float blue\n";
    if (wisp) out += "property int wisp_id\n";
    out += "end_header\n";

    const size_t header = out.size();
    out.resize(header + P * (widths ? 16 : 12) + E * 8 +
               S * (4 + (colors ? 12 : 0) + (wisp ? 4 : 0)));
    char* p = out.data() + header;
    auto put = [&p](const void* v, size_t n) {
        std::memcpy(p, v, n);
        p += n;
    };
    for (size_t i = 0; i < P; ++i) {
        put(hair.points[i].data(), 12);
        if (widths) put(&hair.widths[i], 4);
    }
    for (size_t s = 0; s < S; ++s)
        for (uint32_t i = hair.offsets[s]; i + 1 < hair.offsets[s + 1]; ++i) {
            const int32_t ab[2] = {int32_t(i), int32_t(i + 1)};
            put(ab, 8);
        }
    for (size_t s = 0; s < S; ++s) {
        const int32_t n = int32_t(hair.strand_size(s));
        put(&n, 4);
        if (colors) put(hair.colors[s].data(), 12);
        if (wisp) put(&hair.wisp[s], 4);
    }
    return out;
}

void write_ply(const std::filesystem::path& path, const Hair& hair) {
    write_file_atomic(path, encode_ply(hair, path.string()));
}

}  // namespace wisp
