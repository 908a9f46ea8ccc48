#include "core/volume/NrrdHeader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "core/base/Error.h"
#include "core/base/Trim.h"

namespace hvx::core {

namespace {
std::vector<glm::dvec3> parseVectors(const std::string& text, const std::string& path) {
    std::vector<glm::dvec3> out;
    std::size_t pos = 0;
    while ((pos = text.find('(', pos)) != std::string::npos) {
        const auto end = text.find(')', pos);
        if (end == std::string::npos) throw Error(path + ": malformed vector in NRRD header");
        std::string inner = text.substr(pos + 1, end - pos - 1);
        for (char& c : inner)
            if (c == ',') c = ' ';
        std::istringstream in(inner);
        glm::dvec3 v;
        if (!(in >> v.x >> v.y >> v.z)) throw Error(path + ": malformed vector in NRRD header");
        out.push_back(v);
        pos = end + 1;
    }
    return out;
}

// The element type of a NRRD "type" field (teem's names, nrrdTypeStr and its synonyms).
FileElement elementOf(const std::string& v, const std::string& path) {
    auto any = [&](std::initializer_list<const char*> names) {
        for (const char* n : names)
            if (v == n) return true;
        return false;
    };
    if (any({"signed char", "int8", "int8_t"})) return FileElement::Int8;
    if (any({"uchar", "unsigned char", "uint8", "uint8_t"})) return FileElement::UInt8;
    if (any({"short", "short int", "signed short", "signed short int", "int16", "int16_t"})) return FileElement::Int16;
    if (any({"ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t"})) return FileElement::UInt16;
    if (any({"int", "signed int", "int32", "int32_t"})) return FileElement::Int32;
    if (any({"uint", "unsigned int", "uint32", "uint32_t"})) return FileElement::UInt32;
    if (any({"longlong", "long long", "long long int", "signed long long", "signed long long int", "int64", "int64_t"}))
        return FileElement::Int64;
    if (any({"ulonglong", "unsigned long long", "unsigned long long int", "uint64", "uint64_t"})) return FileElement::UInt64;
    if (v == "float") return FileElement::Float32;
    if (v == "double") return FileElement::Float64;
    throw Error(path + ": unsupported NRRD type '" + v + "'");
}
// Millimetres in one of a NRRD "space units" or "units" entry; 0 for a unit that is not a length
// Holovox knows (an empty or "???" entry is mm, NRRD's default for a patient space).
double millimetresIn(const std::string& unit) {
    auto any = [&](std::initializer_list<const char*> names) {
        for (const char* n : names)
            if (unit == n) return true;
        return false;
    };
    if (any({"", "???", "mm", "millimeter", "millimeters", "millimetre", "millimetres"})) return 1.0;
    if (any({"cm", "centimeter", "centimeters", "centimetre", "centimetres"})) return 10.0;
    if (any({"m", "meter", "meters", "metre", "metres"})) return 1000.0;
    if (any({"um", "\xc2\xb5m", "micron", "microns", "micrometer", "micrometers", "micrometre", "micrometres"})) return 0.001;
    return 0.0;
}

// The millimetres of each of the first three quoted units of a "space units" / "units" field.
glm::dvec3 unitScales(const std::string& value, const std::string& key, const std::string& path) {
    glm::dvec3 scale(1.0);
    std::size_t pos = 0;
    for (int a = 0; a < 3; ++a) {
        const auto open = value.find('"', pos);
        const auto close = open == std::string::npos ? open : value.find('"', open + 1);
        if (close == std::string::npos) throw Error(path + ": NRRD " + key + " '" + value + "' are not quoted units");
        const std::string unit = value.substr(open + 1, close - open - 1);
        scale[a] = millimetresIn(unit);
        if (!(scale[a] > 0))
            throw Error(path + ": NRRD " + key + " '" + unit + "' is not a length Holovox knows (mm, cm, m, um)");
        pos = close + 1;
    }
    return scale;
}

// Moves h.headerBytes past `lineSkip` lines and `byteSkip` bytes of the data file (teem's
// order); a byte skip of -1 puts raw data at the file's end.
void skipToData(NrrdHeader& h, const std::string& path, long long lineSkip, long long byteSkip) {
    const std::string& data = h.dataPath;
    const bool raw = h.encoding == "raw";
    if (byteSkip != 0 && !raw)  // teem skips those bytes of the decompressed data
        throw Error(path + ": NRRD byte skip with " + h.encoding + " encoding is not read by Holovox");
    std::ifstream in(data, std::ios::binary);
    if (!in) throw Error(data + ": cannot open");
    in.seekg(std::streamoff(h.headerBytes));
    for (long long l = 0; l < lineSkip; ++l)
        if (!in.ignore(std::numeric_limits<std::streamsize>::max(), '\n') || in.eof())
            throw Error(path + ": NRRD line skip " + std::to_string(lineSkip) + " passes the end of " + data);
    h.headerBytes = std::uint64_t(in.tellg());
    if (byteSkip > 0) {
        h.headerBytes += std::uint64_t(byteSkip);
    } else if (byteSkip == -1) {
        std::error_code ec;
        const std::uint64_t size = std::filesystem::file_size(data, ec);
        if (ec) throw Error(data + ": cannot tell its size (" + ec.message() + ")");
        const std::uint64_t need = h.geometry.voxelCount() * elementSize(h.element) * h.volumes;
        if (size < h.headerBytes + need)
            throw Error(path + ": dimensions " + std::to_string(h.geometry.dims[0]) + "x" + std::to_string(h.geometry.dims[1]) +
                        "x" + std::to_string(h.geometry.dims[2]) + " need " + std::to_string(need) + " bytes at the end of " +
                        data + " but it has " + std::to_string(size > h.headerBytes ? size - h.headerBytes : 0) + " after its header");
        h.headerBytes = size - need;  // "byte skip: -1": the data are the file's last bytes
    }
}
}  // namespace

NrrdHeader NrrdHeader::read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::string line;
    if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0) throw Error(path + ": not a NRRD file");
    NrrdHeader h;
    VolumeGeometry& g = h.geometry;
    int dimension = 0;
    long long lineSkip = 0, byteSkip = 0;
    bool listNamed = false;  // a 4-D file says its last axis lists volumes (kinds or space directions)
    bool sizes = false, typed = false, spaced = false, endian = false;
    std::string space;
    std::vector<glm::dvec3> dirs;
    glm::dvec3 spaceUnits(1.0), axisUnits(1.0);  // mm per unit: of the space's axes, of the index axes
    std::optional<glm::dvec3> axisMins;
    bool cellCentred = false;
    while (std::getline(in, line)) {
        if (trimBlanks(line).empty()) break;
        if (line[0] == '#') continue;
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::string key = trimBlanks(line.substr(0, colon));
        std::string value = trimBlanks(line.substr(colon + 1 + (colon + 1 < line.size() && line[colon + 1] == '=')));
        std::istringstream v(value);
        if (key == "dimension") {
            v >> dimension;
            if (dimension != 3 && dimension != 4)
                throw Error(path + ": only 3-D single-component NRRD volumes (and 4-D lists of them) are supported");
        } else if (key == "sizes") {
            sizes = bool(v >> g.dims[0] >> g.dims[1] >> g.dims[2]);
            if (sizes && dimension == 4) sizes = bool(v >> h.volumes) && h.volumes > 0;
        } else if (key == "type") {
            h.element = elementOf(lowercase(value), path);
            typed = true;
            g.scalarType = storedTypeOf(h.element);
        } else if (key == "encoding") {
            h.encoding = lowercase(value);  // teem reads its names in any case ("ASCII", as it writes it)
        } else if (key == "endian") {
            value = lowercase(value);
            if (value != "big" && value != "little")
                throw Error(path + ": NRRD endian '" + value + "' is neither little nor big");
            h.bigEndian = value == "big";
            endian = true;
        } else if (key == "space") {
            space = lowercase(value);  // teem reads the names in any case
        } else if (key == "space units") {
            spaceUnits = unitScales(value, key, path);
        } else if (key == "units") {
            axisUnits = unitScales(value, key, path);
        } else if (key == "axis mins" || key == "axismins") {
            glm::dvec3 m;
            if (!(v >> m.x >> m.y >> m.z)) throw Error(path + ": NRRD axis mins '" + value + "' are not three numbers");
            axisMins = m;
        } else if (key == "centerings" || key == "centers") {
            std::string c;
            v >> c;
            cellCentred = c == "cell";
        } else if (key == "space directions") {
            dirs = parseVectors(value, path);
            // a "none" axis is not spatial: only a 4-D file's last axis may be one
            const bool noneLast = value.size() > 4 && value.compare(value.size() - 4, 4, "none") == 0 &&
                                  value.rfind(')') < value.size() - 4;
            listNamed = listNamed || noneLast;
            if (dirs.size() != 3 || (dimension == 4) != noneLast)
                throw Error(path + ": NRRD space directions '" + value + "' are not three vectors" +
                            (dimension == 4 ? " and a last 'none'" : ""));
        } else if (key == "space origin") {
            auto o = parseVectors(value, path);
            if (o.size() != 1) throw Error(path + ": NRRD space origin '" + value + "' is not one vector");
            g.origin = o[0];
        } else if (key == "spacings") {  // a 4-D file's fourth (NaN or a time step) is not a length
            if (!(v >> g.spacing.x >> g.spacing.y >> g.spacing.z))
                throw Error(path + ": NRRD spacings '" + value + "' are not three numbers");
            spaced = true;
        } else if (key == "data file" || key == "datafile") {
            // Several data files (a LIST after the header, or a printf pattern with its range)
            // are teem's too; Holovox reads one.
            if (value.rfind("LIST", 0) == 0 || value.find('%') != std::string::npos)
                throw Error(path + ": NRRD data in several files ('data file: " + value +
                            "') is not read by Holovox: join them into one file or one .nrrd");
            h.dataFile = value;
        } else if (key == "kinds") {
            std::string kind;
            for (int axis = 0; v >> kind; ++axis) {  // the three first axes are space; a fourth lists volumes
                const bool spatial = kind == "domain" || kind == "space" || kind == "???" || kind == "none";
                if (axis == 3 && (kind == "list" || kind == "time")) listNamed = true;
                if (axis == 3 && (listNamed || spatial)) continue;
                if (!spatial)
                    throw Error(path + ": NRRD axis kind '" + kind + "' is not spatial" +
                                (axis == 0 && dimension == 4 ? " (values interleaved per voxel, as a DWI's)" : "") +
                                ": only 3-D single-component volumes, and 4-D files whose last axis lists volumes, are read");
            }
        } else if (key == "line skip" || key == "lineskip") {
            if (!(v >> lineSkip) || lineSkip < 0 || lineSkip > 1000000)
                throw Error(path + ": NRRD line skip '" + value + "' is not a line count");
        } else if (key == "byte skip" || key == "byteskip") {
            if (!(v >> byteSkip) || byteSkip < -1 || byteSkip > (1LL << 50))
                throw Error(path + ": NRRD byte skip '" + value + "' is not a byte count or -1");
        } else if (key == "modality") {
            g.modality = value;
        }
    }
    if (!sizes) throw Error(path + ": NRRD header has no sizes");
    if (dimension == 4 && !listNamed)
        throw Error(path + ": a 4-D NRRD must say that its last axis lists volumes ('kinds: domain domain domain list' "
                           "or space directions ending in 'none'): Holovox does not guess which axis is not space");
    if (!typed) throw Error(path + ": NRRD header has no type");
    if (!endian && elementSize(h.element) > 1 && h.encoding != "ascii" && h.encoding != "text" && h.encoding != "txt")
        throw Error(path + ": NRRD header gives no endian for its " + std::to_string(elementSize(h.element)) +
                    "-byte type, so its values cannot be read (teem refuses it too)");
    const bool unitless = spaceUnits == glm::dvec3(1.0) && (!space.empty() || axisUnits == glm::dvec3(1.0));
    if (!unitless)  // teem, ITK and 3D Slicer keep the numbers as they are and call them mm
        h.warnings.push_back(path + ": NRRD " + (space.empty() ? "units" : "space units") +
                             " are not millimetres: Holovox converts them to mm (teem, ITK and 3D Slicer do not)");
    for (auto& d : dirs) d *= spaceUnits;
    g.origin *= spaceUnits;
    if (dirs.size() == 3) {
        for (int a = 0; a < 3; ++a) {
            const double len = std::sqrt(glm::dot(dirs[std::size_t(a)], dirs[std::size_t(a)]));
            if (!(len > 0)) throw Error(path + ": NRRD space direction is zero");
            g.spacing[a] = len;
            g.direction[a] = dirs[std::size_t(a)] / len;
        }
        spaced = true;
    }
    if (!spaced) {  // the views and measurements say so (VolumeGeometry::spacingAssumed)
        g.spacingAssumed = true;
        h.warnings.push_back(path + ": NRRD header gives no spacings or space directions: 1 mm assumed, lengths are not millimetres");
    }
    // The patient spaces NRRD names, turned into LPS by the axes they flip; anything else cannot
    // be placed in the patient and is refused.
    glm::dvec3 flip(1.0);
    if (space == "left-posterior-superior" || space == "lps") {
    } else if (space == "right-anterior-superior" || space == "ras") {
        flip = {-1, -1, 1};
    } else if (space == "left-anterior-superior" || space == "las") {
        flip = {1, -1, 1};
    } else if (space == "scanner-xyz") {
        h.warnings.push_back(path + ": NRRD space scanner-xyz is taken as LPS (the DICOM patient axes), as ITK does");
    } else if (space.empty()) {
        if (dirs.size() == 3)
            throw Error(path + ": NRRD header has space directions but no space, so they cannot be placed");
        h.warnings.push_back(path + ": NRRD header has no space: orientation unknown, the axes taken as L, P and S");
        g.orientationAssumed = true;  // the views draw "?" for the orientation letters
        g.spacing *= axisUnits;
        // Without a space, teem places sample 0 at the axis min (half a spacing in when cell-centred).
        if (axisMins) g.origin = (*axisMins) * axisUnits + (cellCentred ? 0.5 * g.spacing : glm::dvec3(0.0));
    } else {
        throw Error(path + ": NRRD space '" + space + "' is not a patient space Holovox can place (LPS, RAS, LAS, scanner-xyz)");
    }
    g.origin *= flip;
    for (int a = 0; a < 3; ++a) g.direction[a] *= flip;
    h.headerBytes = h.dataFile.empty() ? std::uint64_t(in.tellg()) : 0;
    h.dataPath = h.dataFile.empty() ? path : (std::filesystem::path(path).parent_path() / h.dataFile).string();
    if (lineSkip || byteSkip) skipToData(h, path, lineSkip, byteSkip);
    return h;
}

std::string NrrdHeader::format(const VolumeGeometry& g) {
    std::ostringstream o;
    o.precision(17);
    const char* type = g.scalarType == ScalarType::UInt8    ? "uint8"
                       : g.scalarType == ScalarType::Int16  ? "int16"
                       : g.scalarType == ScalarType::UInt16 ? "uint16"
                                                            : "float";
    o << "NRRD0004\n# written by Holovox\ntype: " << type << "\ndimension: 3\nspace: left-posterior-superior\n"
      << "sizes: " << g.dims[0] << ' ' << g.dims[1] << ' ' << g.dims[2] << "\nspace directions:";
    for (int a = 0; a < 3; ++a) {
        const glm::dvec3 d = g.direction[a] * g.spacing[a];
        o << " (" << d.x << ',' << d.y << ',' << d.z << ')';
    }
    o << "\nkinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: (" << g.origin.x << ','
      << g.origin.y << ',' << g.origin.z << ")\nmodality:=" << g.modality << "\n\n";
    return o.str();
}

}  // namespace hvx::core
