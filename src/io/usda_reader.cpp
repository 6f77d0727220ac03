// The usda reader: a hand-written tokenizer and recursive-descent parser for the text
// format subset that BasisCurves layers use. Values of attributes wisp does not need are
// skipped token by token (never converted), so a layer with big meshes reads fast too.
#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <map>
#include <type_traits>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "io/io_util.hpp"
#include "io/usda.hpp"

namespace wisp {
namespace {

enum class TokKind { kEnd, kIdent, kNumber, kString, kAsset, kPath, kPunct };

struct Token {
    TokKind kind = TokKind::kEnd;
    std::string_view text;  // strings, assets, paths: without their delimiters
    size_t line = 0, col = 0;

    bool is(char c) const { return kind == TokKind::kPunct && text[0] == c; }
    bool is_ident(std::string_view s) const { return kind == TokKind::kIdent && text == s; }
    bool opens() const { return is('(') || is('[') || is('{'); }
    bool closes() const { return is(')') || is(']') || is('}'); }
};

std::string describe(const Token& t) {
    switch (t.kind) {
        case TokKind::kEnd:
            return "the end of the file";
        case TokKind::kString:
            return cat("the string \"", excerpt(t.text), "\"");
        default:
            return cat("`", excerpt(t.text), "`");
    }
}

bool ident_start(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool ident_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '.';
}
bool digit(char c) {
    return c >= '0' && c <= '9';
}

class Lexer {
  public:
    Lexer(std::string_view s, const std::string& name) : s_(s), name_(name) {}

    const Token& peek() {
        if (!has_) {
            tok_ = lex();
            has_ = true;
        }
        return tok_;
    }
    Token next() {
        peek();
        has_ = false;
        return tok_;
    }
    template <typename... Args>
    [[noreturn]] void error(const Token& t, const Args&... args) const {
        fail(name_, ":", t.line, ":", t.col, ": ", args...);
    }
    Token expect(char c, std::string_view context) {
        Token t = next();
        if (!t.is(c)) error(t, "expected `", c, "` ", context, ", found ", describe(t));
        return t;
    }

    // Fast paths for big numeric arrays, on the raw text when no token is peeked.
    // accept(c) consumes punctuation c if it comes next.
    bool accept(char c) {
        if (has_) {
            if (!tok_.is(c)) return false;
            has_ = false;
            return true;
        }
        skip_space_and_comments();
        if (pos_ >= s_.size() || s_[pos_] != c) return false;
        ++pos_;
        return true;
    }
    // Reads a number if one comes next and ends where the number token would; false
    // (nothing consumed) otherwise, and the caller takes the token path.
    template <typename T>
    bool number_fast(T& v) {
        if (has_) return false;
        skip_space_and_comments();
        const char* b = s_.data() + pos_;
        const char* e = s_.data() + s_.size();
        if (b == e || !(digit(*b) || *b == '-' || *b == '.')) return false;
        const auto r = std::from_chars(b, e, v);
        if (r.ec != std::errc() || (r.ptr < e && ident_char(*r.ptr))) return false;
        pos_ += static_cast<size_t>(r.ptr - b);
        return true;
    }
    // Right after the `[` of a float array, with no token peeked: when the text up to
    // the closing `]` holds only numbers, parentheses, commas and white space (what
    // writers produce), parses it in parallel blocks straight from the text. Returns
    // false with nothing consumed otherwise, or if any block is malformed: the token path
    // then parses it again and reports the exact place.
    // T is float (float arrays) or int64_t (int arrays).
    template <typename T>
    bool numeric_array_fast(std::vector<T>& out, size_t& elements, int& arity);
    // At a value to skip, with no token peeked: when it is an array of numbers, tuples,
    // commas and white space whose parentheses balance (the groom_* primvars wisp does not
    // read), moves past its `]` and returns true; false with nothing consumed otherwise
    // (the token path then skips it and reports any error at its place).
    bool skip_plain_array();

    // Where the next token starts, for messages, without lexing it.
    Token position() {
        if (has_) return tok_;
        skip_space_and_comments();
        Token t;
        t.line = line_;
        t.col = pos_ - line_start_ + 1;
        return t;
    }

  private:
    char at(size_t i) const { return i < s_.size() ? s_[i] : '\0'; }
    void advance(size_t n) {
        for (size_t k = 0; k < n; ++k, ++pos_)
            if (s_[pos_] == '\n') {
                ++line_;
                line_start_ = pos_ + 1;
            }
    }
    [[noreturn]] void error_here(size_t line, size_t col, std::string_view what) const {
        fail(name_, ":", line, ":", col, ": ", what);
    }

    void skip_space_and_comments() {
        while (pos_ < s_.size()) {
            const char c = s_[pos_];
            if (c == '\n') {
                advance(1);
            } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
                ++pos_;
            } else if (c == '#' || (c == '/' && at(pos_ + 1) == '/')) {
                const size_t e = s_.find('\n', pos_);
                pos_ = e == std::string_view::npos ? s_.size() : e;
            } else if (c == '/' && at(pos_ + 1) == '*') {
                const size_t line = line_, col = pos_ - line_start_ + 1;
                const size_t e = s_.find("*/", pos_ + 2);
                if (e == std::string_view::npos) error_here(line, col, "unterminated /* comment");
                advance(e + 2 - pos_);
            } else {
                break;
            }
        }
    }

    Token lex() {
        skip_space_and_comments();
        Token t;
        t.line = line_;
        t.col = pos_ - line_start_ + 1;
        if (pos_ >= s_.size()) return t;
        const size_t start = pos_;
        const char c = s_[pos_];
        if (c == '"' || c == '\'') {
            const bool triple = at(pos_ + 1) == c && at(pos_ + 2) == c;
            const size_t open = triple ? 3 : 1;
            size_t i = pos_ + open;
            for (;; ++i) {
                if (i >= s_.size()) error_here(t.line, t.col, "unterminated string");
                if (s_[i] == '\\') {
                    ++i;
                    continue;
                }
                if (!triple && s_[i] == '\n')
                    error_here(t.line, t.col, "string runs past the end of its line");
                if (s_[i] == c && (!triple || (at(i + 1) == c && at(i + 2) == c))) break;
            }
            t.kind = TokKind::kString;
            t.text = s_.substr(pos_ + open, i - pos_ - open);
            advance(i + open - pos_);
            return t;
        }
        if (c == '@') {
            const bool triple = at(pos_ + 1) == '@' && at(pos_ + 2) == '@';
            const std::string_view close = triple ? "@@@" : "@";
            const size_t e = s_.find(close, pos_ + close.size());
            if (e == std::string_view::npos) error_here(t.line, t.col, "unterminated asset path");
            t.kind = TokKind::kAsset;
            t.text = s_.substr(pos_ + close.size(), e - pos_ - close.size());
            advance(e + close.size() - pos_);
            return t;
        }
        if (c == '<') {
            const size_t e = s_.find('>', pos_);
            if (e == std::string_view::npos) error_here(t.line, t.col, "unterminated path <...>");
            t.kind = TokKind::kPath;
            t.text = s_.substr(pos_ + 1, e - pos_ - 1);
            advance(e + 1 - pos_);
            return t;
        }
        if (ident_start(c) || ((c == '-' || c == '+') && ident_start(at(pos_ + 1)))) {
            size_t i = pos_ + 1;
            while (i < s_.size() && ident_char(s_[i]))
                ++i;
            t.kind = TokKind::kIdent;
            t.text = s_.substr(start, i - start);
            pos_ = i;
            return t;
        }
        if (digit(c) ||
            ((c == '-' || c == '+' || c == '.') && (digit(at(pos_ + 1)) || at(pos_ + 1) == '.'))) {
            size_t i = pos_ + 1;
            while (i < s_.size()) {
                const char d = s_[i];
                if (digit(d) || d == '.') {
                    ++i;
                } else if ((d == 'e' || d == 'E')) {
                    ++i;
                    if (at(i) == '-' || at(i) == '+') ++i;
                } else {
                    break;
                }
            }
            t.kind = TokKind::kNumber;
            t.text = s_.substr(start, i - start);
            pos_ = i;
            return t;
        }
        if (std::string_view("()[]{}=,:;&").find(c) != std::string_view::npos) {
            t.kind = TokKind::kPunct;
            t.text = s_.substr(pos_, 1);
            ++pos_;
            return t;
        }
        error_here(t.line, t.col,
                   cat("unexpected character `", excerpt(std::string_view(&c, 1)), "`"));
    }

    std::string_view s_;
    const std::string& name_;
    size_t pos_ = 0, line_ = 1, line_start_ = 0;
    Token tok_;
    bool has_ = false;
};

// Characters a plain numeric array may hold.
constexpr auto kPlainArrayChars = [] {
    std::array<bool, 256> ok{};
    for (char ch : std::string_view("0123456789.eE+-(), \t\r\n"))
        ok[static_cast<unsigned char>(ch)] = true;
    return ok;
}();

// The decimal a writer gives (`-0.56645864`, `3e-3`: at most 15 significant digits, scaled
// by 10^-k with 0 <= k <= 12) as the float nearest to it, without from_chars: m / 10^k in
// double is correctly rounded, and rounding that double to float gives the float nearest
// the decimal itself. (Double rounding could only differ if m / 10^k lay within a double's
// half ulp of a float's midpoint without being one; its distance to a midpoint M·2^e is a
// nonzero integer over 2^j·10^k, at least 2^-53 relative for M < 2^25 and 5^k < 2^28.)
// Returns false, consuming nothing, for anything else: the caller then uses from_chars.
// Consumes what from_chars would: sign, digits, optional `.` and digits, optional exponent.
inline bool parse_float_fast(const char*& p, const char* e, float& v) {
    static constexpr double kPow10[] = {1e0, 1e1, 1e2, 1e3,  1e4,  1e5, 1e6,
                                        1e7, 1e8, 1e9, 1e10, 1e11, 1e12};
    const char* q = p;
    const bool negative = q < e && *q == '-';
    if (negative) ++q;
    // Leading zeros add no significant digit; m holds at most 15 digits (below 2^53).
    const char* start = q;
    while (q < e && *q == '0')
        ++q;
    uint64_t m = 0;
    const char* first = q;
    while (q < e && digit(*q))
        m = m * 10 + static_cast<uint64_t>(*q++ - '0');
    ptrdiff_t significant = q - first;
    const bool integer_part = q > start;
    ptrdiff_t fraction = 0;
    if (q < e && *q == '.') {
        const char* dot = ++q;
        if (significant == 0)
            while (q < e && *q == '0')
                ++q;
        const char* f = q;
        while (q < e && digit(*q))
            m = m * 10 + static_cast<uint64_t>(*q++ - '0');
        significant += q - f;
        fraction = q - dot;
    }
    if ((!integer_part && fraction == 0) || significant > 15 || fraction > 64) return false;
    int exponent = 0;
    if (q < e && (*q == 'e' || *q == 'E')) {
        const char* x = q + 1;
        const bool neg_exp = x < e && *x == '-';
        if (x < e && (*x == '-' || *x == '+')) ++x;
        if (x < e && digit(*x)) {
            while (x < e && digit(*x)) {
                exponent = exponent * 10 + (*x++ - '0');
                if (exponent > 1000) return false;
            }
            if (neg_exp) exponent = -exponent;
            q = x;
        }
    }
    const ptrdiff_t k = fraction - exponent;
    if (k < 0 || k > 12) return false;
    const float f = static_cast<float>(static_cast<double>(m) / kPow10[k]);
    v = negative ? -f : f;
    p = q;
    return true;
}

// Numbers already parsed, by their text: arrays of scalars that repeat a few values
// (widths: a taper along the strand, the same for every strand of a length) skip
// from_chars on a hit. Direct-mapped on a hash of the text.
struct NumberTextCache {
    static constexpr size_t kSlots = 64, kMaxText = 16;
    struct Slot {
        uint8_t size = 0;  // 0: empty
        char text[kMaxText];
        float value;
    };
    std::array<Slot, kSlots> slots;

    // Parses the number at [p, e) ending at the first character that cannot continue it;
    // false if from_chars does not take exactly that text.
    bool parse(const char*& p, const char* e, float& v) {
        const char* q = p;
        while (q < e &&
               (digit(*q) || *q == '.' || *q == '-' || *q == '+' || *q == 'e' || *q == 'E'))
            ++q;
        const size_t n = static_cast<size_t>(q - p);
        if (n == 0 || n > kMaxText) return from_chars_exact(p, q, v);
        uint32_t h = 2166136261u;
        for (size_t k = 0; k < n; ++k)
            h = (h ^ static_cast<unsigned char>(p[k])) * 16777619u;
        Slot& slot = slots[h % kSlots];
        if (slot.size == n && std::memcmp(slot.text, p, n) == 0) {
            v = slot.value;
            p = q;
            return true;
        }
        const char* start = p;
        if (!from_chars_exact(p, q, v)) return false;
        slot.size = static_cast<uint8_t>(n);
        std::memcpy(slot.text, start, n);
        slot.value = v;
        return true;
    }
    static bool from_chars_exact(const char*& p, const char* q, float& v) {
        if (const char* f = p; parse_float_fast(f, q, v) && f == q) {
            p = q;
            return true;
        }
        const auto r = std::from_chars(p, q, v);
        if (r.ec != std::errc() || r.ptr != q) return false;
        p = q;
        return true;
    }
};

// A number at p exactly as the token path would take it: starting with a digit, `-` or
// `.` (no `+`, `inf`, `nan`: those take the token path) and finite.
template <typename T>
bool plain_number(const char*& p, const char* e, T& v) {
    if (p == e || !(digit(*p) || *p == '-' || *p == '.')) return false;
    if constexpr (std::is_same_v<T, float>)
        if (parse_float_fast(p, e, v)) return true;
    const auto r = std::from_chars(p, e, v);
    if (r.ec != std::errc()) return false;
    if constexpr (std::is_floating_point_v<T>)
        if (!std::isfinite(v)) return false;
    p = r.ptr;
    return true;
}

// Parses `number` or `(number, ...)` elements separated by commas from [p, e) into out;
// false on anything else (any other character included), so the caller need not check
// the text first.
template <typename T>
bool parse_plain_block(const char* p, const char* e, std::vector<T>& out, size_t& elements,
                       int& arity) {
    auto skip_ws = [&] {
        while (p < e && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n'))
            ++p;
    };
    auto number = [&] {
        skip_ws();
        T v;
        if (!plain_number(p, e, v)) return false;
        out.push_back(v);
        return true;
    };
    NumberTextCache cache;
    auto scalar = [&] {
        T v;
        if constexpr (std::is_same_v<T, float>) {
            if (p == e || !(digit(*p) || *p == '-' || *p == '.')) return false;
            if (!cache.parse(p, e, v) || !std::isfinite(v)) return false;
        } else if (!plain_number(p, e, v)) {
            return false;
        }
        out.push_back(v);
        return true;
    };
    elements = 0;
    arity = -1;
    for (;;) {
        skip_ws();
        if (p == e) return true;  // blocks end after a comma; the last may have a trailing one
        int n = 0;
        if (*p == '(') {
            ++p;
            for (;;) {
                if (!number()) return false;
                ++n;
                skip_ws();
                if (p < e && *p == ',') {
                    ++p;
                    continue;
                }
                if (p < e && *p == ')') {
                    ++p;
                    break;
                }
                return false;
            }
        } else if (!scalar()) {
            return false;
        }
        if (arity >= 0 && n != arity) return false;
        arity = n;
        ++elements;
        skip_ws();
        if (p == e) return true;
        if (*p != ',') return false;
        ++p;
    }
}

enum class NumKind { kFloat, kInt, kString };

// A parsed attribute value: numbers flattened in file order, tuples counted.
struct Value {
    bool blocked = false;  // None
    std::vector<float> f;
    std::vector<int64_t> i;
    std::vector<std::string> s;
    size_t elements = 0;  // array elements (1 for a scalar or a tuple)
    int arity = 0;        // components per element, 0 for scalars
    Token where;
};

struct Attr {
    bool has_default = false, has_sample = false;
    Value value, sample;  // default; earliest time sample
    double sample_time = 0;
    std::string interpolation;
    // The value wisp uses: the default when authored and not blocked, else the earliest
    // time sample, else none.
    const Value* resolved() const {
        if (has_default && !value.blocked) return &value;
        if (has_sample && !sample.blocked) return &sample;
        return nullptr;
    }
};

constexpr int kMaxDepth = 200;

// How much of a prim path a message quotes: names are checked to be printable, but a path
// may be long.
constexpr size_t kPathExcerptBytes = 256;

class Parser {
  public:
    Parser(std::string_view text, const std::string& name) : lx_(text, name), name_(name) {}

    UsdaLayer parse() {
        Token t = lx_.peek();
        if (t.kind == TokKind::kPunct && t.is('(')) {
            lx_.next();
            parse_metadata([&](std::string_view key, const Token& v) {
                if (key == "upAxis" && v.kind == TokKind::kString)
                    layer_.up_axis = std::string(v.text);
                if (key == "metersPerUnit") layer_.meters_per_unit = number(v);
                if (key == "timeCodesPerSecond") layer_.time_codes_per_second = number(v);
                if (key == "startTimeCode") layer_.start_time_code = number(v);
            });
        }
        for (;;) {
            t = lx_.peek();
            if (t.kind == TokKind::kEnd) break;
            if (t.is_ident("def") || t.is_ident("over") || t.is_ident("class")) {
                parse_prim("", 0, false);
            } else if (t.is(';')) {
                lx_.next();
            } else {
                lx_.error(t, "expected `def`, `over` or `class`, found ", describe(t));
            }
        }
        if (layer_.up_axis != "Y" && layer_.up_axis != "Z")
            fail(name_, ": upAxis \"", excerpt(layer_.up_axis), "\" is neither \"Y\" nor \"Z\"");
        if (!(layer_.meters_per_unit > 0) || !std::isfinite(layer_.meters_per_unit))
            fail(name_, ": metersPerUnit ", layer_.meters_per_unit, " is not a positive number");
        return std::move(layer_);
    }

  private:
    double number(const Token& t) {
        double v;
        if (t.kind != TokKind::kNumber || !io_detail::parse_number(t.text, v))
            lx_.error(t, "expected a number, found ", describe(t));
        return v;
    }

    // Skips one value: a single token, or a balanced (...), [...] or {...} group.
    void skip_value() {
        if (lx_.skip_plain_array()) return;
        Token t = lx_.next();
        if (t.kind == TokKind::kEnd) lx_.error(t, "expected a value, found the end of the file");
        if (t.closes()) lx_.error(t, "expected a value, found ", describe(t));
        if (!t.opens()) return;
        const Token open = t;
        for (int depth = 1; depth > 0;) {
            t = lx_.next();
            if (t.kind == TokKind::kEnd) lx_.error(open, "`", open.text, "` is never closed");
            if (t.opens()) ++depth;
            if (t.closes()) --depth;
        }
    }

    // After `(`: key = value entries up to `)`. on(key, token) gets scalar values; group
    // values (lists, dictionaries) are skipped.
    template <typename On>
    void parse_metadata(On&& on) {
        parse_metadata(on, [](std::string_view) { return false; });
    }
    // on_group(key) may read a group value (the next token opens it) and return true;
    // returning false skips it.
    template <typename On, typename OnGroup>
    void parse_metadata(On&& on, OnGroup&& on_group) {
        for (;;) {
            Token t = lx_.next();
            if (t.is(')')) return;
            if (t.kind == TokKind::kEnd) lx_.error(t, "metadata `(` is never closed");
            if (t.opens()) {
                // A stray group: skip it whole.
                int depth = 1;
                while (depth > 0) {
                    Token u = lx_.next();
                    if (u.kind == TokKind::kEnd)
                        lx_.error(t, "`", excerpt(t.text), "` is never closed");
                    if (u.opens()) ++depth;
                    if (u.closes()) --depth;
                }
                continue;
            }
            if (t.kind != TokKind::kIdent) continue;  // doc strings, `;`, `,`
            if (t.text == "prepend" || t.text == "append" || t.text == "delete" ||
                t.text == "add" || t.text == "reorder") {
                t = lx_.next();
                if (t.kind != TokKind::kIdent)
                    lx_.error(t, "expected a metadata name after a list-op");
            }
            std::string_view key = t.text;
            if (lx_.peek().kind == TokKind::kIdent)
                key = lx_.next().text;  // `dictionary customData`
            if (!lx_.peek().is('=')) continue;
            lx_.next();
            const Token& v = lx_.peek();
            if (v.opens()) {
                if (!on_group(key)) skip_value();
            } else {
                Token value = lx_.next();
                if (value.closes() || value.kind == TokKind::kEnd)
                    lx_.error(value, "expected a value for `", excerpt(key), "`, found ",
                              describe(value));
                on(key, value);
            }
        }
    }

    void push_number(Value& v, const Token& t, NumKind kind) {
        if (kind == NumKind::kFloat) {
            float x;
            if (!io_detail::parse_number(t.text, x))
                lx_.error(t, "`", excerpt(t.text), "` is not a number");
            v.f.push_back(x);
        } else if (kind == NumKind::kInt) {
            int64_t x;
            if (t.text == "true")
                x = 1;
            else if (t.text == "false")
                x = 0;
            else if (!io_detail::parse_number(t.text, x))
                lx_.error(t, "`", excerpt(t.text), "` is not an integer");
            v.i.push_back(x);
        } else {
            v.s.emplace_back(t.text);
        }
    }

    // One scalar or tuple; returns its component count (0 for a scalar).
    int parse_element(Value& v, NumKind kind, int depth) {
        if (kind == NumKind::kFloat) {
            float x;
            if (lx_.number_fast(x)) {
                v.f.push_back(x);
                return 0;
            }
        } else if (kind == NumKind::kInt) {
            int64_t x;
            if (lx_.number_fast(x)) {
                v.i.push_back(x);
                return 0;
            }
        }
        if (const Token open = lx_.position(); lx_.accept('(')) {
            // The attributes wisp reads hold scalars or tuples of scalars: every tuple
            // component must add exactly one value, so values = elements × arity holds.
            if (depth > 0)
                lx_.error(open, "values nested too deeply: a tuple's components must be numbers");
            if (lx_.accept(')')) lx_.error(open, "empty tuple `()`");
            int n = 0;
            for (;;) {
                parse_element(v, kind, depth + 1);
                ++n;
                if (lx_.accept(')')) return n;
                if (!lx_.accept(',')) {
                    const Token sep = lx_.next();
                    lx_.error(sep, "expected `,` or `)` in a tuple, found ", describe(sep));
                }
                if (lx_.accept(')')) return n;
            }
        }
        Token t = lx_.next();
        const bool numeric_ident =
            t.kind == TokKind::kIdent && (t.text == "inf" || t.text == "-inf" || t.text == "nan" ||
                                          t.text == "true" || t.text == "false");
        if (t.kind == TokKind::kNumber || numeric_ident) {
            if (kind == NumKind::kString)
                v.s.emplace_back(t.text);
            else
                push_number(v, t, kind);
            return 0;
        }
        if (t.kind == TokKind::kString || t.kind == TokKind::kAsset || t.kind == TokKind::kPath ||
            t.kind == TokKind::kIdent) {
            if (kind != NumKind::kString) lx_.error(t, "expected a number, found ", describe(t));
            v.s.emplace_back(t.text);
            return 0;
        }
        lx_.error(t, "expected a value, found ", describe(t));
    }

    Value parse_value(NumKind kind) {
        Value v;
        v.where = lx_.peek();
        if (v.where.is_ident("None")) {
            lx_.next();
            v.blocked = true;
            return v;
        }
        if (!lx_.accept('[')) {
            v.arity = parse_element(v, kind, 0);
            v.elements = 1;
            return v;
        }
        if (lx_.accept(']')) return v;
        if (kind == NumKind::kFloat && lx_.numeric_array_fast(v.f, v.elements, v.arity)) return v;
        if (kind == NumKind::kInt && lx_.numeric_array_fast(v.i, v.elements, v.arity)) return v;
        for (;;) {
            const Token at = lx_.position();
            const int arity = parse_element(v, kind, 0);
            if (v.elements > 0 && arity != v.arity)
                lx_.error(at, "array element has ", arity, " components, the first had ", v.arity);
            v.arity = arity;
            ++v.elements;
            if (lx_.accept(']')) return v;
            if (!lx_.accept(',')) {
                const Token sep = lx_.next();
                lx_.error(sep, "expected `,` or `]` in an array, found ", describe(sep));
            }
            if (lx_.accept(']')) return v;
        }
    }

    // A type in a dictionary entry: `double2[]`, `asset`, `string`, `dictionary`.
    Token dictionary_type() {
        const Token t = lx_.next();
        if (t.kind != TokKind::kIdent)
            lx_.error(t, "expected a type in a dictionary, found ", describe(t));
        if (lx_.peek().is('[')) {
            lx_.next();
            lx_.expect(']', "after `[` in an array type");
        }
        return t;
    }
    Token dictionary_key(const Token& type) {
        const Token k = lx_.next();
        if (k.kind != TokKind::kIdent && k.kind != TokKind::kString)
            lx_.error(k, "expected a name after `", excerpt(type.text), "`, found ", describe(k));
        lx_.expect('=', cat("after `", excerpt(k.text), "`"));
        return k;
    }

    // `[(a, b), ...]` of a clip's active or times.
    std::vector<std::array<double, 2>> number_pairs(std::string_view what) {
        std::vector<std::array<double, 2>> out;
        lx_.expect('[', cat("to open clip ", what));
        if (lx_.accept(']')) return out;
        for (;;) {
            lx_.expect('(', cat("to open a pair of clip ", what));
            std::array<double, 2> pair{};
            pair[0] = number(lx_.next());
            lx_.expect(',', cat("in a pair of clip ", what));
            pair[1] = number(lx_.next());
            lx_.expect(')', cat("to close a pair of clip ", what));
            out.push_back(pair);
            const Token sep = lx_.next();
            if (sep.is(']')) return out;
            if (!sep.is(','))
                lx_.error(sep, "expected `,` or `]` in clip ", what, ", found ", describe(sep));
            if (lx_.accept(']')) return out;
        }
    }

    // The `clips = { dictionary <set> = { ... } }` metadata of prim `prim`: USD value clips
    // (https://openusd.org/release/api/_usd__page__value_clips.html). Explicit clip sets are
    // kept (assetPaths, active, times, primPath, manifestAssetPath); other entries skipped.
    void parse_clips(const std::string& prim) {
        const Token open = lx_.expect('{', "to open clips");
        for (;;) {
            if (lx_.accept('}')) return;
            if (lx_.peek().kind == TokKind::kEnd) lx_.error(open, "clips `{` is never closed");
            if (lx_.accept(';') || lx_.accept(',')) continue;
            const Token type = dictionary_type();
            const Token name = dictionary_key(type);
            if (!type.is_ident("dictionary") || !lx_.peek().is('{')) {
                skip_value();
                continue;
            }
            UsdClipSet set;
            set.prim = prim;
            set.name = std::string(name.text);
            set.line = name.line;
            const Token set_open = lx_.expect('{', "to open a clip set");
            for (;;) {
                if (lx_.accept('}')) break;
                if (lx_.peek().kind == TokKind::kEnd)
                    lx_.error(set_open, "clip set `{` is never closed");
                if (lx_.accept(';') || lx_.accept(',')) continue;
                const Token entry_type = dictionary_type();
                const Token key = dictionary_key(entry_type);
                if (key.text == "assetPaths") {
                    lx_.expect('[', "to open clip assetPaths");
                    while (!lx_.accept(']')) {
                        const Token a = lx_.next();
                        if (a.kind != TokKind::kAsset)
                            lx_.error(a, "expected an asset path @...@ in clip assetPaths, found ",
                                      describe(a));
                        set.asset_paths.emplace_back(a.text);
                        if (!lx_.accept(',') && !lx_.peek().is(']'))
                            lx_.error(lx_.peek(), "expected `,` or `]` in clip assetPaths, found ",
                                      describe(lx_.peek()));
                    }
                } else if (key.text == "active") {
                    set.active = number_pairs("active");
                } else if (key.text == "times") {
                    set.times = number_pairs("times");
                } else if (key.text == "primPath" || key.text == "manifestAssetPath" ||
                           key.text == "templateAssetPath") {
                    const Token v = lx_.next();
                    if (v.kind != TokKind::kString && v.kind != TokKind::kAsset)
                        lx_.error(v, "expected a string for clip ", key.text, ", found ",
                                  describe(v));
                    (key.text == "primPath"            ? set.prim_path
                     : key.text == "manifestAssetPath" ? set.manifest
                                                       : set.template_asset_path) =
                        std::string(v.text);
                } else {
                    skip_value();
                }
            }
            layer_.clip_sets.push_back(std::move(set));
        }
    }

    void parse_prim(const std::string& parent, int depth, bool in_class) {
        const Token keyword = lx_.next();
        if (depth > kMaxDepth) lx_.error(keyword, "prims nested too deeply");
        Token t = lx_.next();
        std::string_view type;
        if (t.kind == TokKind::kIdent) {
            type = t.text;
            t = lx_.next();
        }
        if (t.kind != TokKind::kString)
            lx_.error(t, "expected the prim's name in quotes, found ", describe(t));
        // Prim paths go into messages, `info` and JSON: no control characters, only UTF-8.
        if (excerpt(t.text, SIZE_MAX) != t.text)
            lx_.error(t, "prim name \"", excerpt(t.text),
                      "\" holds control characters or bytes that are not UTF-8");
        const std::string path = cat(parent, "/", t.text);
        if (lx_.peek().is('(')) {
            lx_.next();
            parse_metadata([](std::string_view, const Token&) {},
                           [&](std::string_view key) {
                               if (key != "clips" || !lx_.peek().is('{') || in_class) return false;
                               parse_clips(path);
                               return true;
                           });
        }
        lx_.expect('{', cat("to open prim ", path));
        const bool is_class = in_class || keyword.text == "class";
        const bool curves = type == "BasisCurves" && !is_class;
        size_t index = 0;
        if (curves) {
            index = layer_.curves.size();
            layer_.curves.emplace_back();
            layer_.curves[index].path = path;
            layer_.curves[index].line = keyword.line;
        }
        std::map<std::string, Attr, std::less<>> attrs;
        for (;;) {
            const Token& p = lx_.peek();
            if (p.is('}')) {
                lx_.next();
                break;
            }
            if (p.kind == TokKind::kEnd)
                lx_.error(keyword, "prim ", excerpt(path, kPathExcerptBytes), " is never closed");
            if (p.is(';')) {
                lx_.next();
                continue;
            }
            if (p.is_ident("def") || p.is_ident("over") || p.is_ident("class")) {
                parse_prim(path, depth + 1, is_class);
                continue;
            }
            parse_property(curves ? &attrs : nullptr);
        }
        if (curves) fill_curves(layer_.curves[index], attrs);
    }

    static NumKind kind_of(std::string_view attr) {
        if (attr == "type" || attr == "basis" || attr == "wrap") return NumKind::kString;
        if (attr == "curveVertexCounts" || attr == "primvars:wisp_id" ||
            attr == "primvars:displayColor:indices" || attr == "primvars:groom_guide")
            return NumKind::kInt;
        return NumKind::kFloat;
    }
    static bool wanted(std::string_view attr) {
        return attr == "type" || attr == "basis" || attr == "wrap" || attr == "curveVertexCounts" ||
               attr == "points" || attr == "widths" || attr == "primvars:widths" ||
               attr == "primvars:displayColor" || attr == "primvars:displayColor:indices" ||
               attr == "primvars:wisp_id" || attr == "primvars:groom_guide";
    }

    // One attribute, relationship or other property statement of a prim body. attrs is
    // null when the prim is not collected: values are then skipped.
    void parse_property(std::map<std::string, Attr, std::less<>>* attrs) {
        Token t = lx_.next();
        if (t.kind != TokKind::kIdent)
            lx_.error(t, "expected a property, a prim or `}`, found ", describe(t));
        if (t.text == "variantSet") {
            lx_.next();  // its name
            lx_.expect('=', "after variantSet's name");
            skip_value();
            return;
        }
        if (t.text == "reorder") {
            lx_.next();
            lx_.expect('=', "after reorder");
            skip_value();
            return;
        }
        while (t.text == "custom" || t.text == "uniform" || t.text == "varying" ||
               t.text == "config" || t.text == "prepend" || t.text == "append" ||
               t.text == "delete" || t.text == "add") {
            t = lx_.next();
            if (t.kind != TokKind::kIdent) lx_.error(t, "expected a type, found ", describe(t));
        }
        if (t.text == "rel") {
            Token n = lx_.next();
            if (n.kind != TokKind::kIdent)
                lx_.error(n, "expected a relationship name, found ", describe(n));
            if (lx_.peek().is('=')) {
                lx_.next();
                skip_value();
            }
            if (lx_.peek().is('(')) {
                lx_.next();
                parse_metadata([](std::string_view, const Token&) {});
            }
            return;
        }
        // An attribute: type[] name [= value] [( metadata )].
        if (lx_.peek().is('[')) {
            lx_.next();
            lx_.expect(']', "after `[` in an array type");
        }
        const Token name_tok = lx_.next();
        if (name_tok.kind != TokKind::kIdent)
            lx_.error(name_tok, "expected an attribute name after type `", excerpt(t.text),
                      "`, found ", describe(name_tok));
        std::string_view name = name_tok.text;
        std::string_view suffix;
        if (const size_t dot = name.rfind('.'); dot != std::string_view::npos) {
            suffix = name.substr(dot + 1);
            name = name.substr(0, dot);
        }
        if (attrs && (name == "normals" || name == "primvars:normals")) (*attrs)["normals"];
        Attr* attr = nullptr;
        if (attrs && wanted(name) && (suffix.empty() || suffix == "timeSamples"))
            attr = &(*attrs)[std::string(name)];
        const NumKind kind = kind_of(name);
        if (lx_.peek().is('=')) {
            lx_.next();
            if (suffix == "timeSamples") {
                const Token open = lx_.expect('{', "to open timeSamples");
                for (;;) {
                    const Token time_tok = lx_.next();
                    if (time_tok.is('}')) break;
                    if (time_tok.kind == TokKind::kEnd)
                        lx_.error(open, "timeSamples `{` is never closed");
                    const double time = number(time_tok);
                    lx_.expect(':', "after a time sample's time");
                    if (attr) {
                        Value v = parse_value(kind);
                        if (!attr->has_sample || time < attr->sample_time) {
                            attr->has_sample = true;
                            attr->sample_time = time;
                            attr->sample = std::move(v);
                        }
                    } else {
                        skip_value();
                    }
                    const Token& sep = lx_.peek();
                    if (sep.is(','))
                        lx_.next();
                    else if (!sep.is('}'))
                        lx_.error(sep, "expected `,` or `}` in timeSamples, found ", describe(sep));
                }
            } else if (attr && suffix.empty()) {
                attr->value = parse_value(kind);
                attr->has_default = true;
            } else {
                skip_value();
            }
        }
        if (lx_.peek().is('(')) {
            lx_.next();
            parse_metadata([&](std::string_view key, const Token& v) {
                if (attr && key == "interpolation") attr->interpolation = std::string(v.text);
            });
        }
    }

    void fill_curves(UsdCurves& c, const std::map<std::string, Attr, std::less<>>& attrs) {
        c.has_normals = attrs.count("normals") > 0;
        auto get = [&](std::string_view n) -> const Attr* {
            auto it = attrs.find(n);
            return it == attrs.end() ? nullptr : &it->second;
        };
        auto token = [&](std::string_view n, std::string& out) {
            if (const Attr* a = get(n); a && a->resolved()) {
                const Value& v = *a->resolved();
                if (v.s.size() != 1 || v.arity != 0)
                    lx_.error(v.where, excerpt(c.path, kPathExcerptBytes), ".", n,
                              ": expected one token");
                out = v.s[0];
            }
        };
        token("type", c.type);
        token("basis", c.basis);
        token("wrap", c.wrap);
        auto vec3s = [&](const Value& v, std::string_view n, std::vector<Vec3f>& out) {
            if (v.elements > 0 && v.arity != 3)
                lx_.error(v.where, excerpt(c.path, kPathExcerptBytes), ".", n,
                          ": expected 3-component tuples");
            if (v.f.size() != 3 * v.elements)
                lx_.error(v.where, excerpt(c.path, kPathExcerptBytes), ".", n,
                          ": expected 3 numbers in each tuple");
            out.resize(v.elements);
            for (size_t k = 0; k < v.elements; ++k)
                out[k] = Vec3f(v.f[3 * k], v.f[3 * k + 1], v.f[3 * k + 2]);
        };
        auto scalars = [&](const Value& v, std::string_view n) {
            if (v.elements > 0 && v.arity != 0)
                lx_.error(v.where, excerpt(c.path, kPathExcerptBytes), ".", n,
                          ": expected scalars, found tuples");
        };
        if (const Attr* a = get("curveVertexCounts"); a && a->resolved()) {
            const Value& v = *a->resolved();
            scalars(v, "curveVertexCounts");
            c.counts.resize(v.i.size());
            for (size_t k = 0; k < v.i.size(); ++k) {
                if (v.i[k] < INT_MIN || v.i[k] > INT_MAX)
                    lx_.error(v.where, excerpt(c.path, kPathExcerptBytes),
                              ".curveVertexCounts: count ", v.i[k], " is out of range");
                c.counts[k] = static_cast<int>(v.i[k]);
            }
        }
        if (const Attr* a = get("points"); a && a->resolved())
            vec3s(*a->resolved(), "points", c.points);
        const Attr* w = get("primvars:widths");
        if (!w || !w->resolved()) w = get("widths");
        if (w && w->resolved()) {
            scalars(*w->resolved(), "widths");
            c.widths = w->resolved()->f;
            c.widths_interpolation = w->interpolation;
        }
        if (const Attr* a = get("primvars:displayColor"); a && a->resolved()) {
            vec3s(*a->resolved(), "primvars:displayColor", c.display_color);
            c.display_color_interpolation = a->interpolation;
            if (const Attr* ix = get("primvars:displayColor:indices"); ix && ix->resolved()) {
                const Value& v = *ix->resolved();
                std::vector<Vec3f> expanded(v.i.size());
                for (size_t k = 0; k < v.i.size(); ++k) {
                    if (v.i[k] < 0 || size_t(v.i[k]) >= c.display_color.size())
                        lx_.error(v.where, excerpt(c.path, kPathExcerptBytes),
                                  ".primvars:displayColor:indices: index ", v.i[k],
                                  " is outside the ", c.display_color.size(), " values");
                    expanded[k] = c.display_color[v.i[k]];
                }
                c.display_color = std::move(expanded);
            }
        }
        if (const Attr* a = get("primvars:wisp_id"); a && a->resolved()) {
            const Value& v = *a->resolved();
            scalars(v, "primvars:wisp_id");
            c.wisp_id.assign(v.i.begin(), v.i.end());
            c.wisp_id_interpolation = a->interpolation;
        }
        if (const Attr* a = get("primvars:groom_guide"); a && a->resolved()) {
            const Value& v = *a->resolved();
            scalars(v, "primvars:groom_guide");
            c.guide =
                !v.i.empty() && std::all_of(v.i.begin(), v.i.end(), [](auto g) { return g == 1; });
        }
    }

    Lexer lx_;
    const std::string& name_;
    UsdaLayer layer_;
};

template <typename T>
bool Lexer::numeric_array_fast(std::vector<T>& out, size_t& elements, int& arity) {
    if (has_) return false;
    const size_t close = s_.find(']', pos_);
    if (close == std::string_view::npos) return false;
    const char* b = s_.data() + pos_;
    const char* e = s_.data() + close;
    const bool tuples = std::memchr(b, '(', size_t(e - b)) != nullptr;

    // Block boundaries just after a top-level comma (after a `)` for tuples).
    constexpr size_t kBlockBytes = 1 << 18;
    std::vector<const char*> cuts{b};
    for (const char* t = b + kBlockBytes; t < e; t = std::max(t + kBlockBytes, cuts.back())) {
        const char* q = t;
        if (tuples) {
            q = static_cast<const char*>(std::memchr(q, ')', size_t(e - q)));
            if (!q) break;
        }
        q = static_cast<const char*>(std::memchr(q, ',', size_t(e - q)));
        if (!q) break;
        cuts.push_back(q + 1);
    }
    cuts.push_back(e);
    const size_t blocks = cuts.size() - 1;
    std::vector<std::vector<T>> values(blocks);
    std::vector<size_t> counts(blocks);
    std::vector<int> arities(blocks);
    std::vector<char> ok(blocks);
    parallel_for(blocks, [&](size_t k) {
        values[k].reserve(size_t(cuts[k + 1] - cuts[k]) / 8);
        ok[k] = parse_plain_block(cuts[k], cuts[k + 1], values[k], counts[k], arities[k]);
    });
    arity = -1;
    elements = 0;
    for (size_t k = 0; k < blocks; ++k) {
        if (!ok[k]) return false;
        if (counts[k] == 0) continue;
        if (arity >= 0 && arities[k] != arity) return false;
        arity = arities[k];
        elements += counts[k];
    }
    if (arity < 0) return false;  // only white space: let the token path handle it
    std::vector<size_t> at(blocks + 1, out.size());
    for (size_t k = 0; k < blocks; ++k)
        at[k + 1] = at[k] + values[k].size();
    out.resize(at[blocks]);
    parallel_for(blocks, [&](size_t k) {
        std::copy(values[k].begin(), values[k].end(), out.begin() + static_cast<long>(at[k]));
    });
    // Move past the `]`, keeping line numbers right.
    for (const char* q = b; (q = static_cast<const char*>(std::memchr(q, '\n', size_t(e - q))));
         ++q) {
        ++line_;
        line_start_ = size_t(q - s_.data()) + 1;
    }
    pos_ = close + 1;
    return true;
}

bool Lexer::skip_plain_array() {
    if (has_) return false;
    skip_space_and_comments();
    if (pos_ >= s_.size() || s_[pos_] != '[') return false;
    const size_t close = s_.find(']', pos_);
    if (close == std::string_view::npos) return false;
    int depth = 0;
    size_t lines = 0, last_newline = 0;
    for (size_t q = pos_ + 1; q < close; ++q) {
        const char c = s_[q];
        if (!kPlainArrayChars[static_cast<unsigned char>(c)]) return false;
        if (c == '(') ++depth;
        if (c == ')' && --depth < 0) return false;
        if (c == '\n') {
            ++lines;
            last_newline = q;
        }
    }
    if (depth != 0) return false;
    if (lines) {
        line_ += lines;
        line_start_ = last_newline + 1;
    }
    pos_ = close + 1;
    return true;
}

}  // namespace

UsdaLayer parse_usda(std::string_view text, const std::string& name) {
    if (text.starts_with("PXR-USDC"))
        fail(name, ": a binary usdc (crate) file; wisp reads usda text (convert with usdcat)");
    if (!text.starts_with("#usda "))
        fail(name, ":1:1: not a usda text layer (the first line must be `#usda 1.0`)");
    return Parser(text, name).parse();
}

namespace {

UsdaLayer read_layer_file(const std::filesystem::path& path) {
    const io_detail::FileBytes bytes(path,
                                     {io_detail::kMaxHairFileBytes, "a usda file", true, "#usda "});
    return parse_usda(bytes.view(), path.string());
}

// The clip set that applies to prim `path`: the one authored on it or on its nearest
// ancestor (the first in file order when a prim holds several).
const UsdClipSet* clip_set_for(const UsdaLayer& layer, const std::string& path) {
    const UsdClipSet* best = nullptr;
    for (const UsdClipSet& set : layer.clip_sets) {
        const bool covers =
            path == set.prim || (path.starts_with(set.prim) && path.size() > set.prim.size() &&
                                 path[set.prim.size()] == '/');
        if (covers && (!best || set.prim.size() > best->prim.size())) best = &set;
    }
    return best;
}

// A layer whose BasisCurves prims take their points from value clips (wisp animate's
// top-level file, or any explicit clip set): each such prim without points of its own gets
// those of the clip active at the layer's start time code (the clip's earliest sample), so
// `info`, `render` and `convert` see the first frame. Clips inside clips are not followed
// (USD ignores a clip's own metadata too).
void resolve_clips(UsdaLayer& layer, const std::filesystem::path& path) {
    const std::string name = path.string();
    std::map<std::string, UsdaLayer> loaded;  // by resolved clip path
    for (UsdCurves& c : layer.curves) {
        if (!c.points.empty()) continue;
        const UsdClipSet* set = clip_set_for(layer, c.path);
        if (!set) continue;
        const std::string where = cat(name, ":", set->line, ": clip set \"", excerpt(set->name),
                                      "\" on ", excerpt(set->prim, 256));
        if (set->asset_paths.empty()) {
            if (!set->template_asset_path.empty())
                fail(where,
                     ": template clips (templateAssetPath) are not read by wisp; "
                     "author explicit assetPaths and active (wisp animate does)");
            fail(where, ": no assetPaths");
        }
        if (set->active.empty()) fail(where, ": no active clips");
        // USD: the clip of the last `active` entry at or before the time; before the first
        // entry, the first one.
        std::array<double, 2> pick = set->active.front();
        for (const auto& a : set->active)
            if (a[0] < pick[0]) pick = a;
        for (const auto& a : set->active)
            if (a[0] <= layer.start_time_code && a[0] >= pick[0]) pick = a;
        const double index = pick[1];
        if (!(index >= 0) || index != std::floor(index) ||
            index >= static_cast<double>(set->asset_paths.size()))
            fail(where, ": active clip ", index, " is not an index into the ",
                 set->asset_paths.size(), " assetPaths");
        const std::string& asset = set->asset_paths[static_cast<size_t>(index)];
        if (asset.empty() || excerpt(asset, SIZE_MAX) != asset)
            fail(where, ": clip asset path \"", excerpt(asset),
                 "\" is empty or holds control characters");
        const std::filesystem::path file = path.parent_path() / asset;
        auto it = loaded.find(file.string());
        if (it == loaded.end()) {
            try {
                it = loaded.emplace(file.string(), read_layer_file(file)).first;
            } catch (const Error& e) {
                fail(where, ": value clip @", excerpt(asset), "@: ", e.what());
            }
        }
        const std::string anchor = set->prim_path.empty() ? set->prim : set->prim_path;
        const std::string inside = anchor + c.path.substr(set->prim.size());
        const UsdCurves* found = nullptr;
        for (const UsdCurves& k : it->second.curves)
            if (k.path == inside) found = &k;
        if (!found || found->points.empty())
            fail(where, ": value clip @", excerpt(asset), "@ has no points for ",
                 excerpt(inside, 256));
        c.points = found->points;
    }
}

}  // namespace

UsdaLayer read_usda_layer(const std::filesystem::path& path) {
    UsdaLayer layer = read_layer_file(path);
    if (!layer.clip_sets.empty()) resolve_clips(layer, path);
    return layer;
}

std::vector<UsdCurves> read_usda_curves(const std::filesystem::path& path) {
    return read_usda_layer(path).curves;
}

}  // namespace wisp
