#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/volume/ScalarType.h"

namespace hvx::core {

/// The element types a volume file may hold (NIfTI, NRRD, MetaImage, raw), a wider set than
/// Holovox stores (ScalarType): int8 is kept as int16 (exact); 32- and 64-bit integers and
/// float64 as float32 (exact for integers up to 2^24 in magnitude, 7 significant digits).
enum class FileElement { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

/// Bytes per element in the file.
std::size_t elementSize(FileElement e);
/// Lower-case name, as the command line takes it ("int8", "float64", ...).
std::string_view elementName(FileElement e);
/// Parses elementName's names (and ScalarType's short forms: u8, i16, u16, f32, float, double);
/// throws core::Error naming the text and listing the names otherwise.
FileElement parseFileElement(std::string_view name);
/// The element type a stored type is read from unchanged.
FileElement fileElementOf(ScalarType t);
/// The type Holovox keeps an element type as.
ScalarType storedTypeOf(FileElement e);
/// What keeping `e` as storedTypeOf(e) may change, a sentence fragment ("its 32-bit integers are
/// kept as 32-bit floats (...)"); empty where every value is kept exactly.
std::string conversionWarning(FileElement e);

/// Turns `count` elements of type `e` read from a file (`in`, in the file's byte order; swapped
/// in place when `swap`) into storedTypeOf(e) at `out`, which may be `in` itself when the two
/// types have the same size. Returns the index of the first finite float64 too large for a
/// float32 (nothing is written for it or after it), or `count` when all converted.
std::size_t decodeElements(unsigned char* in, std::size_t count, FileElement e, bool swap, void* out);

/// Fills `dst` with `count` slices of `sliceVoxels` elements each, slice `firstSlice` first, as
/// storedTypeOf(e): `read(into, bytes)` delivers the file's next bytes in order (read in place
/// where the types have the same size; otherwise through `buffer`, at most 64 MiB at a time).
/// `bigEndian`: the file's byte order. A float64 beyond float32's range is a core::Error naming
/// `file` and the slice.
void decodeSlices(FileElement e, bool bigEndian, std::uint64_t sliceVoxels, std::uint32_t firstSlice, std::uint32_t count,
                  std::vector<unsigned char>& buffer, void* dst,
                  const std::function<void(unsigned char*, std::uint64_t)>& read, const std::string& file);

}  // namespace hvx::core
