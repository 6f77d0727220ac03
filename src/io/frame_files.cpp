#include "io/frame_files.hpp"

#include <filesystem>

namespace wisp {

std::string numbered_pattern(const std::string& name) {
    if (name.find('#') != std::string::npos) return name;
    const std::filesystem::path p(name);
    return (p.parent_path() / (p.stem().string() + "_####" + p.extension().string())).string();
}

std::string numbered(const std::string& name, int frame) {
    const std::string pattern = numbered_pattern(name);
    const size_t first = pattern.find('#');
    size_t last = first;
    while (last < pattern.size() && pattern[last] == '#')
        ++last;
    std::string digits = std::to_string(frame);
    if (digits.size() < last - first) digits.insert(0, last - first - digits.size(), '0');
    return pattern.substr(0, first) + digits + pattern.substr(last);
}

}  // namespace wisp
