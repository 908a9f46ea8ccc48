#include "core/appearance/LabelTable.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/base/Error.h"
#include "core/base/Trim.h"

namespace hvx::core {

namespace {
bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && lowercase(s.substr(s.size() - tail.size())) == tail;
}

std::array<std::uint8_t, 4> hueColour(int label) {
    // Hues a golden angle apart at full saturation: neighbouring labels never look alike.
    const double h = std::fmod(label * 137.507764, 360.0) / 60.0;
    const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
    double r = 0, g = 0, b = 0;
    if (h < 1) r = 1, g = x;
    else if (h < 2) r = x, g = 1;
    else if (h < 3) g = 1, b = x;
    else if (h < 4) g = x, b = 1;
    else if (h < 5) r = x, b = 1;
    else r = 1, b = x;
    const auto c = [](double v) { return std::uint8_t(std::lround(55 + 200 * v)); };
    return {c(r), c(g), c(b), 255};
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

enum class Kind { ItkSnap, FreeSurfer, Slicer };
}  // namespace

LabelTable LabelTable::load(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open label table " + path);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LabelTable t;
    if (endsWith(path, ".lut") && bytes.size() == 768) {  // mricron: planar reds, greens, blues
        t.format_ = "mricron .lut";
        for (int i = 1; i < 256; ++i)
            t.entries_[i] = {"label " + std::to_string(i),
                             {std::uint8_t(bytes[std::size_t(i)]), std::uint8_t(bytes[256 + std::size_t(i)]),
                              std::uint8_t(bytes[512 + std::size_t(i)]), 255},
                             true};
        return t;
    }
    if (bytes.find('\0') != std::string::npos)
        throw Error(path + " is not a label table (binary; a mricron .lut holds exactly 768 bytes, " +
                    std::to_string(bytes.size()) + " here)");
    // ITK-SNAP quotes its names and says so in its header; Slicer's own tables are .ctbl or
    // start "# Color table file". Otherwise the five-column "index name R G B A" of FreeSurfer,
    // whose A is a transparency (0: opaque).
    Kind kind = Kind::FreeSurfer;
    if (bytes.find("ITK-SnAP") != std::string::npos || bytes.find("ITK-SNAP") != std::string::npos ||
        bytes.find('"') != std::string::npos)
        kind = Kind::ItkSnap;
    else if (endsWith(path, ".ctbl") || bytes.find("# Color table file") != std::string::npos)
        kind = Kind::Slicer;
    t.format_ = kind == Kind::ItkSnap ? "ITK-SNAP label descriptions"
                : kind == Kind::Slicer ? "3D Slicer colour table"
                                       : "FreeSurfer colour LUT";
    std::istringstream text(bytes);
    std::string line;
    std::map<int, int> lineOf;
    int lineNo = 0;
    while (std::getline(text, line)) {
        ++lineNo;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::string where = path + " line " + std::to_string(lineNo);
        std::istringstream f(line);
        double label = 0, r = 0, g = 0, b = 0, a = 0;
        Entry e;
        if (kind == Kind::ItkSnap) {  // IDX R G B A(0-1) VIS MSH "LABEL"
            int vis = 1, mesh = 1;
            if (!(f >> label >> r >> g >> b >> a >> vis >> mesh))
                throw Error(where + ": expected ITK-SNAP's IDX R G B A VIS MSH \"LABEL\"");
            if (!(a >= 0 && a <= 1)) throw Error(where + ": opacity " + num(a) + " is outside 0-1");
            const auto q1 = line.find('"'), q2 = line.rfind('"');
            e.name = q1 != std::string::npos && q2 > q1 ? line.substr(q1 + 1, q2 - q1 - 1) : "";
            e.visible = vis != 0;
            a *= 255;
        } else {  // index name R G B A
            if (!(f >> label >> e.name >> r >> g >> b >> a))
                throw Error(where + ": expected \"index name R G B A\"");
            if (!(a >= 0 && a <= 255)) throw Error(where + ": alpha " + num(a) + " is outside 0-255");
            if (kind == Kind::FreeSurfer) a = 255 - a;
        }
        if (label != std::floor(label) || label < 0 || label > 1e9)
            throw Error(where + ": the label must be a whole number from 0");
        for (const double c : {r, g, b})
            if (!(c >= 0 && c <= 255)) throw Error(where + ": colour component " + num(c) + " is outside 0-255");
        const int id = int(label);
        if (const auto seen = lineOf.find(id); seen != lineOf.end())
            throw Error(where + ": label " + std::to_string(id) + " is already given on line " +
                        std::to_string(seen->second));
        lineOf[id] = lineNo;
        if (id == 0) continue;  // the background: never drawn
        e.rgba = {std::uint8_t(std::lround(r)), std::uint8_t(std::lround(g)), std::uint8_t(std::lround(b)),
                  std::uint8_t(std::lround(a))};
        t.entries_[id] = e;
    }
    if (t.entries_.empty()) throw Error(path + " names no label (besides the background 0): not a label table");
    return t;
}

LabelTable LabelTable::forLabelMap(const std::string& octreePath, double valueMin, double valueMax,
                                   const std::string& lut) {
    if (!lut.empty()) return load(lut);
    if (std::ifstream(sidecarPath(octreePath))) return load(sidecarPath(octreePath));
    std::vector<int> values;
    const long lo = long(std::ceil(valueMin)), hi = long(std::floor(valueMax));
    for (long v = lo; v <= hi && values.size() < 65536; ++v) values.push_back(int(v));
    return generated(values);
}

LabelTable LabelTable::generated(const std::vector<int>& labels) {
    LabelTable t;
    t.format_ = "generated colours";
    t.addMissing(labels);
    return t;
}

const LabelTable::Entry* LabelTable::find(int label) const {
    const auto it = entries_.find(label);
    return label == 0 || it == entries_.end() ? nullptr : &it->second;
}

std::vector<int> LabelTable::addMissing(const std::vector<int>& labels) {
    std::vector<int> added;
    for (const int l : labels)
        if (l != 0 && !entries_.count(l)) {
            entries_[l] = {"label " + std::to_string(l), hueColour(l), true};
            added.push_back(l);
        }
    std::sort(added.begin(), added.end());
    added.erase(std::unique(added.begin(), added.end()), added.end());
    return added;
}

void LabelTable::set(int label, Entry entry) {
    if (label == 0) return;
    entries_[label] = std::move(entry);
    if (format_.empty()) format_ = "set by Holovox";
}

std::string LabelTable::toSlicerTable() const {
    std::string out = "# Color table file written by Holovox\n# " + std::to_string(entries_.size() + 1) +
                      " values\n0 Background 0 0 0 0\n";
    for (const auto& [label, e] : entries_) {
        std::string name = e.name.empty() ? "label_" + std::to_string(label) : e.name;
        for (auto& c : name)
            if (std::isspace(static_cast<unsigned char>(c))) c = '_';
        out += std::to_string(label) + " " + name + " " + std::to_string(e.rgba[0]) + " " + std::to_string(e.rgba[1]) +
               " " + std::to_string(e.rgba[2]) + " " + std::to_string(e.rgba[3]) + "\n";
    }
    return out;
}

void LabelTable::setVisible(int label, bool visible) {
    if (auto it = entries_.find(label); it != entries_.end()) it->second.visible = visible;
}

}  // namespace hvx::core
