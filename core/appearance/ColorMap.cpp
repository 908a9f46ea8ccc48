#include "core/appearance/ColorMap.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "core/base/Error.h"
#include "core/base/Trim.h"

namespace hvx::core {

namespace {
std::uint8_t byte(double v) { return std::uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

/// Piecewise linear through (t, r, g, b) stops, t increasing from 0 to 1.
ColorMap::Rgb stops(double t, const std::vector<std::array<double, 4>>& s) {
    for (std::size_t i = 1; i < s.size(); ++i)
        if (t <= s[i][0]) {
            const double f = (t - s[i - 1][0]) / (s[i][0] - s[i - 1][0]);
            ColorMap::Rgb c;
            for (int a = 0; a < 3; ++a) c[std::size_t(a)] = byte(s[i - 1][std::size_t(a) + 1] + f * (s[i][std::size_t(a) + 1] - s[i - 1][std::size_t(a) + 1]));
            return c;
        }
    return {byte(s.back()[1]), byte(s.back()[2]), byte(s.back()[3])};
}

ColorMap::Rgb builtin(const std::string& name, double t) {
    if (name == "grey") return {byte(t), byte(t), byte(t)};
    // Black, red, yellow, white: each channel rises over its own third (as mricron's and
    // matplotlib's "hot").
    if (name == "hot") return {byte(3 * t), byte(3 * t - 1), byte(3 * t - 2)};
    // Blue to red through cyan, green and yellow ("jet").
    if (name == "rainbow")
        return {byte(1.5 - std::abs(4 * t - 3)), byte(1.5 - std::abs(4 * t - 2)), byte(1.5 - std::abs(4 * t - 1))};
    // PET readers' scale: black, blue, violet, red, orange, white.
    if (name == "pet")
        return stops(t, {{0, 0, 0, 0}, {0.2, 0, 0, 0.63}, {0.4, 0.63, 0, 0.63}, {0.6, 1, 0, 0}, {0.8, 1, 0.78, 0},
                         {1, 1, 1, 1}});
    return {byte(t), byte(1 - t), 1};  // cool: cyan to magenta
}
}  // namespace

const std::vector<std::string>& ColorMap::builtinNames() {
    static const std::vector<std::string> names{"grey", "hot", "rainbow", "pet", "cool"};
    return names;
}

ColorMap ColorMap::named(const std::string& name) {
    const std::string n = lowercase(name) == "gray" ? "grey" : lowercase(name);
    const auto& names = builtinNames();
    if (std::find(names.begin(), names.end(), n) == names.end()) {
        std::string list;
        for (const auto& x : names) list += (list.empty() ? "" : ", ") + x;
        throw Error("no colour map named \"" + name + "\" (built in: " + list + "; or give a .lut or .ctbl file)");
    }
    ColorMap m;
    m.name_ = n;
    for (int i = 0; i < 256; ++i) m.entries_[std::size_t(i)] = builtin(n, i / 255.0);
    return m;
}

ColorMap ColorMap::namedOrFile(const std::string& nameOrPath) {
    const auto& names = builtinNames();
    const std::string n = lowercase(nameOrPath) == "gray" ? "grey" : lowercase(nameOrPath);
    // Neither a built-in name nor a file: the names are the better answer.
    if (std::find(names.begin(), names.end(), n) != names.end() || !std::ifstream(nameOrPath)) return named(n);
    return load(nameOrPath);
}

ColorMap ColorMap::load(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open colour map " + path);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ColorMap m;
    m.name_ = path.substr(path.find_last_of('/') + 1);
    const bool lutName = path.size() > 4 && lowercase(path.substr(path.size() - 4)) == ".lut";
    if (lutName && bytes.size() == 768) {  // mricron: planar reds, greens, blues
        for (std::size_t i = 0; i < 256; ++i)
            m.entries_[i] = {std::uint8_t(bytes[i]), std::uint8_t(bytes[256 + i]), std::uint8_t(bytes[512 + i])};
        return m;
    }
    if (lutName && bytes.find('\0') != std::string::npos)
        throw Error(path + " is not a colour map: a binary mricron .lut holds exactly 768 bytes (" +
                    std::to_string(bytes.size()) + " here)");
    std::map<long, Rgb> rows;
    std::istringstream text(bytes);
    std::string line;
    int lineNo = 0;
    while (std::getline(text, line)) {
        ++lineNo;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream f(line);
        long index;
        std::string name;
        double r, g, b;
        if (!(f >> index >> name >> r >> g >> b))
            throw Error(path + " line " + std::to_string(lineNo) + ": expected \"index name R G B A\"");
        if (index < 0 || index > 65535 || r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255)
            throw Error(path + " line " + std::to_string(lineNo) + ": index or colour out of range (R, G, B 0-255)");
        if (!rows.emplace(index, Rgb{std::uint8_t(r), std::uint8_t(g), std::uint8_t(b)}).second)
            throw Error(path + " line " + std::to_string(lineNo) + ": index " + std::to_string(index) + " given twice");
    }
    if (rows.size() < 2) throw Error(path + " is not a colour map: it needs at least two \"index name R G B A\" lines");
    // Entries spread over 0..255 from the smallest index to the largest, linear between rows.
    const double lo = double(rows.begin()->first), hi = double(rows.rbegin()->first);
    for (int i = 0; i < 256; ++i) {
        const double x = lo + (hi - lo) * i / 255.0;
        auto above = rows.lower_bound(long(std::ceil(x)));
        if (above == rows.begin()) {
            m.entries_[std::size_t(i)] = above->second;
            continue;
        }
        auto below = std::prev(above);
        const double f = (x - double(below->first)) / double(above->first - below->first);
        for (std::size_t a = 0; a < 3; ++a)
            m.entries_[std::size_t(i)][a] =
                std::uint8_t(std::lround(below->second[a] + f * (double(above->second[a]) - below->second[a])));
    }
    return m;
}

ColorMap::Rgb ColorMap::at(double t) const {
    if (!(t >= 0)) t = 0;  // NaN too
    return entries_[std::size_t(std::lround(std::min(t, 1.0) * 255.0))];
}

}  // namespace hvx::core
