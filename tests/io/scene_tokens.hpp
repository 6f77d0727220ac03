#pragma once
// A tokenizer for the text scene formats the exporters write (RIB, pbrt): quoted strings,
// brackets, bare words and numbers; '#' starts a comment to the end of the line. For the
// tests that parse what rib.cpp and pbrt.cpp wrote.
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace wisp::test {

struct SceneToken {
    enum Kind { kWord, kString, kNumber, kOpen, kClose } kind;
    std::string text;
    double number = 0;
};

inline std::vector<SceneToken> tokenize_scene(std::string_view s) {
    std::vector<SceneToken> out;
    size_t i = 0;
    while (i < s.size()) {
        const char c = s[i];
        if (c == '#') {
            while (i < s.size() && s[i] != '\n')
                ++i;
        } else if (c == ' ' || c == '\n' || c == '\t' || c == '\r') {
            ++i;
        } else if (c == '[' || c == ']') {
            out.push_back({c == '[' ? SceneToken::kOpen : SceneToken::kClose, std::string(1, c)});
            ++i;
        } else if (c == '"') {
            const size_t end = s.find('"', i + 1);
            out.push_back({SceneToken::kString, std::string(s.substr(i + 1, end - i - 1))});
            i = end + 1;
        } else {
            size_t end = i;
            while (end < s.size() && s[end] != ' ' && s[end] != '\n' && s[end] != '[' &&
                   s[end] != ']' && s[end] != '"')
                ++end;
            std::string word(s.substr(i, end - i));
            char* stop = nullptr;
            const double v = std::strtod(word.c_str(), &stop);
            if (stop && *stop == 0 && !word.empty())
                out.push_back({SceneToken::kNumber, word, v});
            else
                out.push_back({SceneToken::kWord, word});
            i = end;
        }
    }
    return out;
}

// The numbers of the bracketed array starting at tokens[k] (which must be '['); k is left
// after the closing ']'.
inline std::vector<double> read_array(const std::vector<SceneToken>& t, size_t& k) {
    std::vector<double> v;
    if (k >= t.size() || t[k].kind != SceneToken::kOpen) return v;
    for (++k; k < t.size() && t[k].kind != SceneToken::kClose; ++k)
        v.push_back(t[k].number);
    ++k;
    return v;
}

}  // namespace wisp::test
