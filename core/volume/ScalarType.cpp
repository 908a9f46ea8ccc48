#include "core/volume/ScalarType.h"

#include <algorithm>

#include "core/base/Error.h"

namespace hvx::core {

void swapByteOrder(void* data, std::size_t count, std::size_t width) {
    auto* p = static_cast<unsigned char*>(data);
    for (std::size_t n = 0; n < count; ++n, p += width) std::reverse(p, p + width);
}

std::size_t scalarSize(ScalarType t) {
    switch (t) {
    case ScalarType::UInt8: return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16: return 2;
    case ScalarType::Float32: return 4;
    }
    return 0;
}

std::string_view scalarName(ScalarType t) {
    switch (t) {
    case ScalarType::UInt8: return "uint8";
    case ScalarType::Int16: return "int16";
    case ScalarType::UInt16: return "uint16";
    case ScalarType::Float32: return "float32";
    }
    return "unknown";
}

ScalarType parseScalarType(std::string_view name) {
    if (name == "uint8" || name == "u8") return ScalarType::UInt8;
    if (name == "int16" || name == "i16") return ScalarType::Int16;
    if (name == "uint16" || name == "u16") return ScalarType::UInt16;
    if (name == "float32" || name == "float" || name == "f32") return ScalarType::Float32;
    throw Error("unsupported scalar type '" + std::string(name) +
                "' (supported: uint8, int16, uint16, float32)");
}

bool isValidScalarType(std::uint32_t raw) { return raw >= 1 && raw <= 4; }

}  // namespace hvx::core
