#include "core/volume/FileElement.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
struct Entry {
    FileElement element;
    const char* name;
    std::size_t size;
};
constexpr Entry kEntries[] = {
    {FileElement::Int8, "int8", 1},     {FileElement::UInt8, "uint8", 1},     {FileElement::Int16, "int16", 2},
    {FileElement::UInt16, "uint16", 2}, {FileElement::Int32, "int32", 4},     {FileElement::UInt32, "uint32", 4},
    {FileElement::Int64, "int64", 8},   {FileElement::UInt64, "uint64", 8},   {FileElement::Float32, "float32", 4},
    {FileElement::Float64, "float64", 8},
};

const Entry& entry(FileElement e) { return kEntries[std::size_t(e)]; }

template <class From, class To>
void widen(const unsigned char* in, std::size_t n, unsigned char* out) {
    // Forwards: To is no wider than From, so `out` may be `in`.
    for (std::size_t i = 0; i < n; ++i) {
        From v;
        std::memcpy(&v, in + i * sizeof(From), sizeof(From));
        const To t = To(v);
        std::memcpy(out + i * sizeof(To), &t, sizeof(To));
    }
}
}  // namespace

std::size_t elementSize(FileElement e) { return entry(e).size; }

std::string_view elementName(FileElement e) { return entry(e).name; }

FileElement parseFileElement(std::string_view name) {
    for (const auto& e : kEntries)
        if (name == e.name) return e.element;
    if (name == "u8") return FileElement::UInt8;
    if (name == "i16") return FileElement::Int16;
    if (name == "u16") return FileElement::UInt16;
    if (name == "f32" || name == "float") return FileElement::Float32;
    if (name == "double") return FileElement::Float64;
    std::string names;
    for (const auto& e : kEntries) names += std::string(names.empty() ? "" : ", ") + e.name;
    throw Error("unsupported voxel type '" + std::string(name) + "' (supported: " + names + ")");
}

FileElement fileElementOf(ScalarType t) {
    switch (t) {
    case ScalarType::UInt8: return FileElement::UInt8;
    case ScalarType::Int16: return FileElement::Int16;
    case ScalarType::UInt16: return FileElement::UInt16;
    case ScalarType::Float32: break;
    }
    return FileElement::Float32;
}

ScalarType storedTypeOf(FileElement e) {
    switch (e) {
    case FileElement::UInt8: return ScalarType::UInt8;
    case FileElement::Int8:
    case FileElement::Int16: return ScalarType::Int16;
    case FileElement::UInt16: return ScalarType::UInt16;
    default: return ScalarType::Float32;
    }
}

std::string conversionWarning(FileElement e) {
    switch (e) {
    case FileElement::Int32:
    case FileElement::UInt32:
    case FileElement::Int64:
    case FileElement::UInt64:
        return "its " + std::to_string(8 * elementSize(e)) +
               "-bit integers are kept as 32-bit floats (exact up to 16777216 in magnitude)";
    case FileElement::Float64: return "its 64-bit floats are kept as 32-bit floats (7 significant digits)";
    default: return {};
    }
}

std::size_t decodeElements(unsigned char* in, std::size_t count, FileElement e, bool swap, void* out) {
    const std::size_t width = elementSize(e);
    if (swap && width > 1) swapByteOrder(in, count, width);
    auto* o = static_cast<unsigned char*>(out);
    switch (e) {
    case FileElement::Int8: {  // widening: from the end, so that out may be in
        for (std::size_t i = count; i-- > 0;) {
            const std::int16_t v = std::int8_t(in[i]);
            std::memcpy(o + 2 * i, &v, 2);
        }
        return count;
    }
    case FileElement::Int32: widen<std::int32_t, float>(in, count, o); return count;
    case FileElement::UInt32: widen<std::uint32_t, float>(in, count, o); return count;
    case FileElement::Int64: widen<std::int64_t, float>(in, count, o); return count;
    case FileElement::UInt64: widen<std::uint64_t, float>(in, count, o); return count;
    case FileElement::Float64:
        for (std::size_t i = 0; i < count; ++i) {
            double v;
            std::memcpy(&v, in + 8 * i, 8);
            if (std::isfinite(v) && std::abs(v) > double(std::numeric_limits<float>::max())) return i;
            const float f = float(v);
            std::memcpy(o + 4 * i, &f, 4);
        }
        return count;
    default:
        if (o != in) std::memcpy(o, in, count * width);
        return count;
    }
}

void decodeSlices(FileElement e, bool bigEndian, std::uint64_t sliceVoxels, std::uint32_t firstSlice, std::uint32_t count,
                  std::vector<unsigned char>& buffer, void* dst,
                  const std::function<void(unsigned char*, std::uint64_t)>& read, const std::string& file) {
    const std::size_t width = elementSize(e), stored = scalarSize(storedTypeOf(e));
    const bool swap = bigEndian != (std::endian::native == std::endian::big);
    const std::uint32_t slab =
        width == stored ? count : std::max<std::uint32_t>(1, std::uint32_t((64u << 20) / std::max<std::uint64_t>(1, sliceVoxels * width)));
    auto* out = static_cast<unsigned char*>(dst);
    for (std::uint32_t done = 0; done < count;) {
        const std::uint32_t n = std::min(slab, count - done);
        const std::size_t voxels = std::size_t(sliceVoxels * n);
        unsigned char* in = out;
        if (width != stored) {
            buffer.resize(voxels * width);
            in = buffer.data();
        }
        read(in, std::uint64_t(voxels) * width);
        const std::size_t converted = decodeElements(in, voxels, e, swap, out);
        if (converted < voxels)
            throw Error(file + ": slice " + std::to_string(firstSlice + done + converted / sliceVoxels) +
                        " holds a value beyond what a 32-bit float can hold");
        out += voxels * stored;
        done += n;
    }
}

}  // namespace hvx::core
