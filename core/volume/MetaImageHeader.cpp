#include "core/volume/MetaImageHeader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/Trim.h"

namespace hvx::core {

namespace {
bool isTrue(const std::string& v) { return v == "True" || v == "true" || v == "TRUE" || v == "1"; }

/// n numbers from a field's value, or an error naming the field.
template <int N>
std::array<double, N> numbers(const std::string& value, const std::string& key, const std::string& path) {
    std::istringstream in(value);
    std::array<double, N> out{};
    for (double& x : out)
        if (!(in >> x) || !std::isfinite(x))
            throw Error(path + ": its " + key + " is not " + std::to_string(N) + " numbers");
    return out;
}
/// The files a MetaIO file pattern names, read as MetaIO reads them: "slice%03d.raw" (files 1 to
/// the number of slices), "slice%03d.raw FIRST" (FIRST and on, one per slice), and "slice%03d.raw
/// FIRST LAST STEP", the name rejoined when it holds spaces ("my scan%03d.raw 1 3 1"). The name
/// must hold one plain integer (%d or %i, an optional 0 flag, width and l or ll): anything else, such as
/// "%s" or "%n", is refused rather than handed to a printf. `slices` is DimSize's third.
std::vector<std::string> patternFiles(const std::string& value, const std::string& path, std::uint32_t slices) {
    std::vector<std::string> words;
    for (std::istringstream fields(value); fields;) {
        std::string w;
        if (fields >> w) words.push_back(w);
    }
    auto number = [&](const std::string& w) {
        std::size_t used = 0;
        long long v = 0;
        try {
            v = std::stoll(w, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        // Far beyond any slice number, and no overflow in what follows.
        if (used != w.size() || v < -(1LL << 40) || v > (1LL << 40))
            throw Error(path + ": its ElementDataFile '" + value + "' has '" + w + "' where a file number should be");
        return v;
    };
    std::string pattern;
    long long first = 1, last = 0, step = 1;
    if (words.size() == 1 || words.size() == 2) {
        pattern = words[0];
        if (words.size() == 2) first = number(words[1]);
        last = first + (long long)slices - 1;
    } else if (words.size() >= 4) {
        for (std::size_t i = 0; i + 3 < words.size(); ++i) pattern += (i ? " " : "") + words[i];
        first = number(words[words.size() - 3]);
        last = number(words[words.size() - 2]);
        step = number(words[words.size() - 1]);
    } else {
        throw Error(path + ": its ElementDataFile '" + value + "' is not a file pattern, or one with first, last and step");
    }
    const auto at = pattern.find('%');
    std::size_t end = at == std::string::npos ? pattern.size() : at + 1;
    const bool zeros = end < pattern.size() && pattern[end] == '0';
    if (zeros) ++end;
    std::size_t width = 0;
    while (end < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[end])) && width < 100)
        width = width * 10 + std::size_t(pattern[end++] - '0');
    for (int l = 0; l < 2 && end < pattern.size() && pattern[end] == 'l'; ++l) ++end;  // %ld, %lld
    if (end >= pattern.size() || (pattern[end] != 'd' && pattern[end] != 'i') || pattern.find('%', end) != std::string::npos ||
        width >= 100)
        throw Error(path + ": its ElementDataFile pattern '" + pattern + "' is not a name with one integer (%d)");
    // MetaIO counts up only (its loop runs while the number is at most the last): a step down
    // is read by no other tool, and refused rather than read one way here and another there.
    if (step < 0)
        throw Error(path + ": its file pattern counts down (step " + std::to_string(step) +
                    "), which MetaIO and VTK do not read; refused");
    if (step == 0 || last < first)
        throw Error(path + ": its file pattern's numbers run the wrong way for its step (" + std::to_string(first) + " to " +
                    std::to_string(last) + " by " + std::to_string(step) + ")");
    const long long count = (last - first) / step + 1;
    if (count > (1LL << 20)) throw Error(path + ": its file pattern names " + std::to_string(count) + " files");
    std::vector<std::string> files;
    const auto folder = std::filesystem::path(path).parent_path();
    for (long long i = 0, n = first; i < count; ++i, n += step) {
        std::string digits = std::to_string(n < 0 ? -n : n);
        if (digits.size() < width) digits.insert(0, width - digits.size() - (n < 0 ? 1 : 0), zeros ? '0' : ' ');
        if (n < 0) digits.insert(zeros ? 0 : digits.find_first_not_of(' '), "-");
        files.push_back((folder / (pattern.substr(0, at) + digits + pattern.substr(end + 1))).string());
    }
    return files;
}
}  // namespace

MetaImageHeader MetaImageHeader::read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    MetaImageHeader h;
    VolumeGeometry& g = h.geometry;
    int ndims = 0;
    bool dims = false, spacing = false, binary = false, binarySeen = false, dataFileSeen = false;
    std::string elementType;
    std::int64_t headerSize = 0;
    glm::dvec3 elementSize(0.0);
    std::string line;
    for (int n = 0; n < 200 && !dataFileSeen && std::getline(in, line); ++n) {
        const auto eq = line.find('=');
        if (eq == std::string::npos) {
            if (n == 0) throw Error(path + ": not a MetaImage header (no 'key = value' line first)");
            continue;
        }
        const std::string key = trimBlanks(line.substr(0, eq));
        const std::string value = trimBlanks(line.substr(eq + 1));
        if (key == "ObjectType") {
            if (value != "Image") throw Error(path + ": a MetaImage '" + value + "' object, not an image");
        } else if (key == "NDims") {
            ndims = std::atoi(value.c_str());
            if (ndims > 3)  // its TransformMatrix, sizes and spacings then hold ndims² and ndims numbers
                throw Error(path + ": a MetaImage of NDims = " + std::to_string(ndims) +
                            " (a time series or vectors): Holovox reads 3-D MetaImages only");
        } else if (key == "DimSize") {
            const auto d = numbers<3>(value, key, path);
            for (int a = 0; a < 3; ++a) {
                if (!(d[std::size_t(a)] >= 1 && d[std::size_t(a)] <= (1u << 20)) || d[std::size_t(a)] != std::floor(d[std::size_t(a)]))
                    throw Error(path + ": its DimSize '" + value + "' is not three sizes of 1 to 1048576");
                g.dims[std::size_t(a)] = std::uint32_t(d[std::size_t(a)]);
            }
            dims = true;
        } else if (key == "ElementType") {
            elementType = value;
        } else if (key == "ElementSpacing") {
            const auto s = numbers<3>(value, key, path);
            g.spacing = glm::dvec3(s[0], s[1], s[2]);
            spacing = true;
        } else if (key == "ElementSize") {
            const auto s = numbers<3>(value, key, path);
            elementSize = glm::dvec3(s[0], s[1], s[2]);
        } else if (key == "Offset" || key == "Origin" || key == "Position") {
            const auto o = numbers<3>(value, key, path);
            g.origin = glm::dvec3(o[0], o[1], o[2]);
        } else if (key == "TransformMatrix" || key == "Rotation" || key == "Orientation") {
            const auto d = numbers<9>(value, key, path);
            glm::dmat3 m;
            for (int a = 0; a < 3; ++a) m[a] = glm::dvec3(d[std::size_t(3 * a)], d[std::size_t(3 * a + 1)], d[std::size_t(3 * a + 2)]);
            for (int a = 0; a < 3; ++a)
                if (std::abs(glm::length(m[a]) - 1.0) > 1e-3)
                    throw Error(path + ": its " + key + " row " + std::to_string(a) + " is not a unit direction");
            if (std::abs(glm::determinant(m)) < 1e-3) throw Error(path + ": its " + key + " has dependent directions");
            g.direction = m;
        } else if (key == "AnatomicalOrientation") {
            if (value != "RAI" && value.find('?') == std::string::npos)
                h.warnings.push_back(path + ": its AnatomicalOrientation is " + value +
                                     ", not ITK's RAI (LPS); like ITK, Holovox places the axes by the "
                                     "TransformMatrix alone and takes them as LPS");
        } else if (key == "BinaryData") {
            binary = isTrue(value);
            binarySeen = true;
        } else if (key == "BinaryDataByteOrderMSB" || key == "ElementByteOrderMSB") {
            h.bigEndian = isTrue(value);
        } else if (key == "CompressedData") {
            h.compressed = isTrue(value);
        } else if (key == "CompressedDataSize") {
            h.compressedBytes = std::strtoull(value.c_str(), nullptr, 10);
        } else if (key == "ElementNumberOfChannels") {
            h.channels = std::atoi(value.c_str());
        } else if (key == "HeaderSize") {
            headerSize = std::strtoll(value.c_str(), nullptr, 10);
        } else if (key == "ElementDataFile") {
            dataFileSeen = true;  // the last field: the data (LOCAL) follows it
            if (value == "LOCAL") {
                h.dataFile = path;
                h.dataOffset = std::uint64_t(in.tellg());
            } else if (value == "LIST" || value.rfind("LIST ", 0) == 0) {
                // LIST [2D]: the names of the slice files follow, a line each, as MetaIO writes them.
                h.dataFile = path;
                const std::string dim = trimBlanks(value.substr(4));
                // Only 2-D files, a slice each, make a 3-D image: VTK's reader had built a "LIST 3D"
                // as zeros without a word.
                if (!dim.empty() && dim != "2D" && dim != "2")
                    throw Error(path + ": its ElementDataFile = " + value + " lists " + dim +
                                " files; Holovox reads a list of 2-D slice files only");
                for (std::string name; std::getline(in, name);) {
                    name = trimBlanks(name);
                    if (name.empty()) continue;
                    if (h.sliceFiles.size() >= (std::size_t(1) << 20))
                        throw Error(path + ": its list of data files is longer than any volume's slices");
                    h.sliceFiles.push_back((std::filesystem::path(path).parent_path() / name).string());
                }
                if (h.sliceFiles.empty()) throw Error(path + ": its ElementDataFile = LIST names no file");
            } else if (value.find('%') != std::string::npos) {
                h.dataFile = path;
                if (!dims) throw Error(path + ": its file pattern comes before DimSize");
                h.sliceFiles = patternFiles(value, path, g.dims[2]);
            } else if (value.find(' ') != std::string::npos) {
                h.streamReason = "its data is a list of files";
                h.dataFile = path;
            } else {
                h.dataFile = (std::filesystem::path(path).parent_path() / value).string();
            }
        }
    }
    if (!dataFileSeen) throw Error(path + ": not a MetaImage header (no ElementDataFile field)");
    if (!dims) throw Error(path + ": MetaImage header has no DimSize");
    if (!spacing && elementSize != glm::dvec3(0.0)) g.spacing = elementSize;
    if (!spacing && elementSize == glm::dvec3(0.0)) {  // MetaIO's default, 1, is not a measurement
        g.spacingAssumed = true;
        h.warnings.push_back(path + ": MetaImage header gives no ElementSpacing: 1 mm assumed, lengths are not millimetres");
    }
    auto notStreamable = [&](const std::string& why) {
        if (h.streamReason.empty()) h.streamReason = why;
    };
    if (ndims != 3) notStreamable("it has NDims = " + std::to_string(ndims));
    if (!h.sliceFiles.empty()) {  // a file per slice, each the slice's voxels alone
        if (h.compressed) notStreamable("its list of data files is compressed");
        if (headerSize != 0) notStreamable("it gives a HeaderSize for a list of data files");
        if (dims && h.streamReason.empty() && h.sliceFiles.size() != g.dims[2])
            throw Error(path + ": its ElementDataFile names " + std::to_string(h.sliceFiles.size()) +
                        " slice files for DimSize's " + std::to_string(g.dims[2]) + " slices");
    }
    h.ascii = !binary;  // MetaIO's default
    if (!binarySeen)
        h.warnings.push_back(path + ": MetaImage header gives no BinaryData: its data are read as text, as MetaIO reads them");
    if (h.ascii && !h.sliceFiles.empty()) notStreamable("its list of data files is ASCII");
    if (h.ascii && h.compressed) notStreamable("its data is ASCII and compressed");
    if (h.channels != 1) notStreamable("it has " + std::to_string(h.channels) + " channels");
    // MetaIO's element types (metaTypes.h: MET_LONG is 32 bits, MET_LONG_LONG 64).
    static const std::pair<const char*, FileElement> kTypes[] = {
        {"MET_CHAR", FileElement::Int8},        {"MET_UCHAR", FileElement::UInt8},
        {"MET_SHORT", FileElement::Int16},      {"MET_USHORT", FileElement::UInt16},
        {"MET_INT", FileElement::Int32},        {"MET_UINT", FileElement::UInt32},
        {"MET_LONG", FileElement::Int32},       {"MET_ULONG", FileElement::UInt32},
        {"MET_LONG_LONG", FileElement::Int64},  {"MET_ULONG_LONG", FileElement::UInt64},
        {"MET_FLOAT", FileElement::Float32},    {"MET_DOUBLE", FileElement::Float64}};
    const auto* type = std::find_if(std::begin(kTypes), std::end(kTypes), [&](const auto& t) { return elementType == t.first; });
    if (type == std::end(kTypes)) {
        notStreamable("its ElementType is " + elementType);
    } else {
        h.element = type->second;
        g.scalarType = storedTypeOf(h.element);
    }
    if (h.streamReason.empty() && h.sliceFiles.empty() && h.ascii) {  // text: its length is not the voxels'
        if (h.dataFile != path && headerSize > 0) h.dataOffset = std::uint64_t(headerSize);
        if (headerSize == -1) notStreamable("it gives HeaderSize = -1 for ASCII data");
        if (h.dataFile == path && headerSize != 0) notStreamable("it gives a HeaderSize for local data");
    } else if (h.streamReason.empty() && h.sliceFiles.empty()) {
        // The bytes the data takes in its file: the voxels, or the compressed size when given.
        const std::uint64_t bytes = h.compressed ? h.compressedBytes
                                                 : std::uint64_t(g.dims[0]) * g.dims[1] * g.dims[2] * core::elementSize(h.element);
        if (h.dataFile != path && headerSize > 0) h.dataOffset = std::uint64_t(headerSize);
        if (headerSize == -1 && bytes == 0) {
            notStreamable("it gives HeaderSize = -1 for compressed data of no stated size");
        } else if (headerSize == -1) {  // the data is the end of its file
            std::error_code ec;
            const auto size = std::filesystem::file_size(h.dataFile, ec);
            if (ec) throw Error(h.dataFile + ": cannot read the MetaImage data file (" + ec.message() + ")");
            if (size < bytes)
                throw Error(h.dataFile + ": " + std::to_string(size) + " bytes, fewer than the " + std::to_string(bytes) +
                            " its MetaImage header describes");
            h.dataOffset = size - bytes;
        } else if (h.dataFile == path && headerSize != 0) {
            notStreamable("it gives a HeaderSize for local data");
        }
    }
    return h;
}

}  // namespace hvx::core
