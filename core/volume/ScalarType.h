#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace hvx::core {

/// Voxel storage types an .hvo file and a VoxelSource can carry.
enum class ScalarType : std::uint32_t { UInt8 = 1, Int16 = 2, UInt16 = 3, Float32 = 4 };

/// Bytes per voxel of a scalar type.
std::size_t scalarSize(ScalarType t);
/// Lower-case name used on the command line and in `info` ("uint8", "int16", ...).
std::string_view scalarName(ScalarType t);
/// Parses a name as written by scalarName; throws core::Error naming the text otherwise.
ScalarType parseScalarType(std::string_view name);
/// True for a value the enum defines (used to validate file headers).
bool isValidScalarType(std::uint32_t raw);
/// Reverses the byte order of `count` values of `width` bytes each, in place (files written
/// with the other endianness).
void swapByteOrder(void* data, std::size_t count, std::size_t width);

/// Calls f with a default-constructed value of the C++ type that matches t, so templated code
/// can dispatch once per volume rather than per voxel.
template <class F>
decltype(auto) dispatchScalar(ScalarType t, F&& f) {
    switch (t) {
    case ScalarType::UInt8: return f(std::uint8_t{});
    case ScalarType::Int16: return f(std::int16_t{});
    case ScalarType::UInt16: return f(std::uint16_t{});
    case ScalarType::Float32: break;
    }
    return f(float{});
}

}  // namespace hvx::core
