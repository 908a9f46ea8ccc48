#include "core/volume/LegacyVtkHeader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/Trim.h"

namespace hvx::core {

namespace {
constexpr std::size_t kHeaderLimit = 64 * 1024;

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

/// The header's whitespace-separated words in order, and where the reading stands.
class Words {
public:
    explicit Words(std::string text) : text_(std::move(text)) {}
    /// The next word, or "" at the end of the text read.
    std::string next() {
        while (pos_ < text_.size() && blank(text_[pos_])) ++pos_;
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !blank(text_[pos_])) ++pos_;
        return text_.substr(start, pos_ - start);
    }
    /// The rest of the current line (without its newline), and moves past the newline; false
    /// when the text read ends first.
    bool restOfLine(std::string& rest) {
        const auto nl = text_.find('\n', pos_);
        if (nl == std::string::npos) return false;
        rest = text_.substr(pos_, nl - pos_);
        pos_ = nl + 1;
        return true;
    }
    std::size_t position() const { return pos_; }

private:
    std::string text_;
    std::size_t pos_ = 0;
};

/// VTK's legacy data type names (vtkDataReader), where their size is fixed.
bool elementOf(const std::string& type, FileElement& e) {
    static const std::pair<const char*, FileElement> kTypes[] = {
        {"unsigned_char", FileElement::UInt8},   {"char", FileElement::Int8},  // signed on the platforms VTK reads here
        {"signed_char", FileElement::Int8},      {"unsigned_short", FileElement::UInt16},
        {"short", FileElement::Int16},           {"unsigned_int", FileElement::UInt32},
        {"int", FileElement::Int32},             {"vtktypeuint64", FileElement::UInt64},
        {"vtktypeint64", FileElement::Int64},    {"float", FileElement::Float32},
        {"double", FileElement::Float64}};
    for (const auto& [name, element] : kTypes)
        if (type == name) {
            e = element;
            return true;
        }
    return false;
}
}  // namespace

LegacyVtkHeader LegacyVtkHeader::read(const std::string& path) {
    LegacyVtkHeader h = parse(path);
    if (h.direction_ && !h.streamReason.empty())
        throw Error(path + ": legacy VTK header: its DIRECTION is not part of VTK's legacy format, and VTK's reader, "
                           "which would read this file's data (" + h.streamReason + "), refuses it");
    return h;
}

LegacyVtkHeader LegacyVtkHeader::parse(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::string text(kHeaderLimit, '\0');
    in.read(text.data(), std::streamsize(text.size()));
    const bool whole = std::size_t(in.gcount()) < kHeaderLimit;  // the file ends within the text read
    text.resize(std::size_t(in.gcount()));
    if (!whole) text.resize(text.rfind('\n') + 1);  // whole lines only: no word cut off (npos + 1 = 0)
    Words words(text);
    LegacyVtkHeader h;
    VolumeGeometry& g = h.geometry;
    auto notStreamable = [&](const std::string& why) {
        if (h.streamReason.empty()) h.streamReason = why;
    };
    auto bad = [&](const std::string& what) { return Error(path + ": legacy VTK header: " + what); };
    std::string line;
    if (!words.restOfLine(line) || lowercase(line).rfind("# vtk datafile version", 0) != 0)
        throw Error(path + ": not a legacy VTK file (no '# vtk DataFile Version' line first)");
    if (!words.restOfLine(line)) {  // the title
        if (whole) throw bad("it ends after its first line");
        h.streamReason = "its header is longer than 64 KiB";
        return h;
    }
    const std::string format = lowercase(words.next());
    if (format.empty() && !whole) {
        h.streamReason = "its header is longer than 64 KiB";
        return h;
    }
    if (format == "ascii")
        h.ascii = true;
    else if (format != "binary")
        throw bad("its third line is '" + format + "', not ASCII or BINARY");
    const std::string datasetKey = lowercase(words.next());
    const std::string dataset = words.next();
    if (dataset.empty() && !whole) {
        h.streamReason = "its header is longer than 64 KiB";
        return h;
    }
    if (datasetKey != "dataset") throw bad("no DATASET after " + format);
    if (lowercase(dataset) != "structured_points") {
        h.streamReason = "it holds a " + dataset + " dataset";  // VTK's reader refuses it in words of its own
        return h;
    }

    // The numbers after a keyword, each finite, or an error naming the keyword.
    auto numbers = [&](std::size_t n, const std::string& key) {
        std::array<double, 9> v{};
        for (std::size_t i = 0; i < n; ++i) {
            const std::string w = words.next();
            char* end = nullptr;
            v[i] = std::strtod(w.c_str(), &end);
            if (w.empty() || *end != '\0' || !std::isfinite(v[i]))
                throw bad("its " + key + " is not " + std::to_string(n) + " numbers");
        }
        return v;
    };
    bool dims = false, spacing = false;
    glm::dvec3 step(1.0), origin(0.0);
    glm::dmat3 axes(1.0);
    std::uint64_t points = 0;
    for (std::string key = lowercase(words.next());; key = lowercase(words.next())) {
        if (key == "dimensions") {
            const auto d = numbers(3, "DIMENSIONS");
            for (int a = 0; a < 3; ++a) {
                if (!(d[std::size_t(a)] >= 1 && d[std::size_t(a)] <= 2147483647.0) || d[std::size_t(a)] != std::floor(d[std::size_t(a)]))
                    throw bad("its DIMENSIONS are not three whole numbers of at least 1");
                g.dims[std::size_t(a)] = std::uint32_t(d[std::size_t(a)]);
            }
            dims = true;
        } else if (key == "spacing" || key == "aspect_ratio") {
            const auto s = numbers(3, "SPACING");
            step = glm::dvec3(s[0], s[1], s[2]);
            spacing = true;
        } else if (key == "origin") {
            const auto o = numbers(3, "ORIGIN");
            origin = glm::dvec3(o[0], o[1], o[2]);
        } else if (key == "direction") {
            const auto d = numbers(9, "DIRECTION");
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) axes[c][r] = d[std::size_t(3 * r + c)];
            h.direction_ = true;
        } else if (key == "point_data") {
            const auto n = numbers(1, "POINT_DATA");
            if (!(n[0] >= 0 && n[0] < 1.8e19) || n[0] != std::floor(n[0])) throw bad("its POINT_DATA is not a count");
            points = std::uint64_t(n[0]);
            break;
        } else if (key.empty()) {
            if (whole) throw bad("it ends before its POINT_DATA");
            h.streamReason = "its header is longer than 64 KiB";
            return h;
        } else {
            h.streamReason = "its image data begin with " + key;  // CELL_DATA, FIELD, ...: VTK's reader
            return h;
        }
    }
    if (!dims) throw bad("no DIMENSIONS before its POINT_DATA");
    const std::uint64_t voxels = std::uint64_t(g.dims[0]) * g.dims[1] * g.dims[2];
    if (points != voxels)
        throw bad("its POINT_DATA " + std::to_string(points) + " is not the " + std::to_string(voxels) +
                  " points of its DIMENSIONS");
    for (int a = 0; a < 3 && h.direction_; ++a)
        if (std::abs(glm::length(axes[a]) - 1.0) > 1e-3) throw bad("its DIRECTION's column " + std::to_string(a) + " is not a unit direction");
    if (h.direction_ && std::abs(glm::determinant(axes)) < 1e-3) throw bad("its DIRECTION has dependent directions");
    if (h.direction_) {
        // DIRECTION is no keyword of VTK's legacy format (VTK neither writes nor reads it; its
        // XML .vti carries the axes): whether its nine numbers are the axes' rows or columns is
        // defined nowhere, so it is taken only where both readings agree.
        double asymmetry = 0;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) asymmetry = std::max(asymmetry, std::abs(axes[c][r] - axes[r][c]));
        if (asymmetry > 1e-6)
            throw bad("its DIRECTION is not part of VTK's legacy format, and whether its numbers give the axes by "
                      "rows or by columns is defined nowhere; these place the volume differently either way, so it "
                      "is not read (write it as .vti, NRRD, NIfTI or MetaImage, which define their axes)");
        h.warnings.push_back(path + ": DIRECTION is not part of VTK's legacy format: taken as written (it reads the "
                                    "same by rows and by columns)");
    }
    for (int a = 0; a < 3; ++a) {
        if (step[a] == 0.0) throw bad("its SPACING has a zero");
        g.spacing[a] = std::abs(step[a]);
        g.direction[a] = axes[a] * (step[a] < 0.0 ? -1.0 : 1.0);  // VTK steps along -axis for a negative spacing
    }
    g.origin = origin;
    if (!spacing) {  // VTK's default, 1, is not a measurement
        g.spacingAssumed = true;
        h.warnings.push_back(path + ": legacy VTK header gives no SPACING: 1 mm assumed, lengths are not millimetres");
    }
    h.warnings.push_back(path + ": a VTK file names no patient axes: taken as LPS, as ITK writes them");

    // The first point attribute: SCALARS name type [components], then LOOKUP_TABLE name.
    const std::string attribute = lowercase(words.next());
    if (attribute != "scalars") {
        notStreamable("its first point data are " + (attribute.empty() ? std::string("missing") : attribute) + ", not SCALARS");
        return h;
    }
    const std::string name = words.next();
    const std::string type = lowercase(words.next());
    std::string rest;
    if (name.empty() || type.empty() || !words.restOfLine(rest)) throw bad("its SCALARS line is incomplete");
    if (const auto first = rest.find_first_not_of(" \t\r"); first != std::string::npos) {
        char* end = nullptr;
        const long components = std::strtol(rest.c_str() + first, &end, 10);
        if (components != 1) notStreamable("its SCALARS have " + rest.substr(first) + " components");
    }
    if (elementOf(type, h.element))
        g.scalarType = storedTypeOf(h.element);
    else
        notStreamable("its SCALARS are of type " + type);
    if (lowercase(words.next()) != "lookup_table") {
        notStreamable("its SCALARS have no LOOKUP_TABLE line");
        return h;
    }
    if (words.next().empty() || !words.restOfLine(rest)) {
        if (whole) throw bad("it ends before its data");
        notStreamable("its header is longer than 64 KiB");
        return h;
    }
    h.dataOffset = words.position();  // binary data begin after the LOOKUP_TABLE line, as VTK reads them
    return h;
}

}  // namespace hvx::core
