#include "io/obj_curves.hpp"

#include <cmath>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/io_util.hpp"

namespace wisp {
namespace {

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits the next whitespace-separated word off s.
std::string_view next_word(std::string_view& s) {
    size_t i = 0;
    while (i < s.size() && is_space(s[i]))
        ++i;
    size_t j = i;
    while (j < s.size() && !is_space(s[j]))
        ++j;
    std::string_view w = s.substr(i, j - i);
    s.remove_prefix(j);
    return w;
}

}  // namespace

Hair decode_obj_curves(std::string_view text, const std::string& name) {
    std::vector<Vec3f> verts;
    std::vector<uint32_t> index;       // vertex index per strand point, strand after strand
    std::vector<uint32_t> offsets{0};  // into index
    bool chaining = false;             // the current strand was built from 2-point lines
    std::vector<uint32_t> line;
    size_t line_no = 0;
    while (!text.empty()) {
        const size_t eol = text.find('\n');
        std::string_view rest = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        ++line_no;
        const std::string_view key = next_word(rest);
        if (key == "v") {
            Vec3f p;
            for (int k = 0; k < 3; ++k) {
                const std::string_view w = next_word(rest);
                if (w.empty()) fail(name, ":", line_no, ": `v` needs 3 coordinates, found ", k);
                if (!io_detail::parse_number(w, p[k]))
                    fail(name, ":", line_no, ": `", excerpt(w), "` is not a number");
                if (!std::isfinite(p[k]))
                    fail(name, ":", line_no, ": vertex coordinate `", excerpt(w),
                         "` is not finite");
            }
            verts.push_back(p);
        } else if (key == "l") {
            line.clear();
            for (std::string_view w = next_word(rest); !w.empty(); w = next_word(rest)) {
                const std::string_view v = w.substr(0, w.find('/'));
                int64_t i;
                if (!io_detail::parse_number(v, i))
                    fail(name, ":", line_no, ": `", excerpt(w), "` is not a vertex index");
                const int64_t n = int64_t(verts.size());
                const int64_t resolved = i < 0 ? n + i : i - 1;
                if (i == 0 || resolved < 0 || resolved >= n)
                    fail(name, ":", line_no, ": vertex index ", i, " is out of range (",
                         verts.size(), " vertices defined so far)");
                line.push_back(static_cast<uint32_t>(resolved));
            }
            if (line.empty()) fail(name, ":", line_no, ": `l` without vertex indices");
            if (line.size() == 2 && chaining && index.back() == line[0]) {
                index.push_back(line[1]);
                offsets.back() = static_cast<uint32_t>(index.size());
                continue;
            }
            index.insert(index.end(), line.begin(), line.end());
            offsets.push_back(static_cast<uint32_t>(index.size()));
            chaining = line.size() == 2;
        }
        // Everything else (vt, vn, f, g, o, s, usemtl, comments, ...) is not hair.
    }
    Hair hair;
    hair.offsets = std::move(offsets);
    hair.points.resize(index.size());
    for (size_t k = 0; k < index.size(); ++k)
        hair.points[k] = verts[index[k]];
    hair.validate(name);
    return hair;
}

Hair read_obj_curves(const std::filesystem::path& path) {
    return decode_obj_curves(
        io_detail::read_whole_file(path, {io_detail::kMaxHairFileBytes, "an OBJ file", true}),
        path.string());
}

std::string encode_obj_curves(const Hair& hair, bool segments, const std::string& name) {
    hair.validate(name);
    for (size_t s = 0; s < hair.strand_count(); ++s)
        if (hair.strand_size(s) == 0)
            fail(name, ": strand ", s, " has no points; OBJ cannot store it");
    std::string out;
    out.reserve(hair.point_count() * 40 + hair.strand_count() * 16 + 128);
    out += "# wisp hair: ";
    io_detail::append_number(out, hair.strand_count());
    out += " strands as polylines, centimetres, Y up\n";
    for (const Vec3f& p : hair.points) {
        out += "v ";
        io_detail::append_number(out, p.x());
        out += ' ';
        io_detail::append_number(out, p.y());
        out += ' ';
        io_detail::append_number(out, p.z());
        out += '\n';
    }
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const uint32_t a = hair.offsets[s] + 1, b = hair.offsets[s + 1] + 1;
        if (b - a == 1 || !segments) {
            out += 'l';
            for (uint32_t i = a; i < b; ++i) {
                out += ' ';
                io_detail::append_number(out, i);
            }
            out += '\n';
        } else {
            for (uint32_t i = a; i + 1 < b; ++i) {
                out += "l ";
                io_detail::append_number(out, i);
                out += ' ';
                io_detail::append_number(out, i + 1);
                out += '\n';
            }
        }
    }
    return out;
}

void write_obj_curves(const std::filesystem::path& path, const Hair& hair, bool segments) {
    write_file_atomic(path, encode_obj_curves(hair, segments, path.string()));
}

}  // namespace wisp
