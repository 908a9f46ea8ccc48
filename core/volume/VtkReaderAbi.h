#pragma once
#include <cstddef>

// The C interface between VtkImageSource and the VTK reader module (libhvx_vtk_reader.so),
// which holds every use of VTK and is loaded on first use (VtkReaderLibrary): VTK's libraries
// are then not loaded, nor their symbols bound, when a program starts. Plain C types only, and
// no exception crosses it: a call that fails returns null or nonzero and writes one sentence
// (without the file's name) into the caller's error buffer.

extern "C" {

/// Bumped whenever a struct or function below changes; the loader refuses another version.
constexpr int kHvxVtkReaderAbiVersion = 1;

/// The file formats the module reads.
enum HvxVtkFormat : int { HvxVtkMetaImage = 0, HvxVtkXmlImage = 1, HvxVtkLegacyImage = 2 };

/// The voxel type delivered by read(), numbered as core::ScalarType; 0 when the file's type is
/// not supported (scalarTypeName then names it).
enum HvxVtkVoxelType : int { HvxVtkUnsupported = 0, HvxVtkUInt8 = 1, HvxVtkInt16 = 2, HvxVtkUInt16 = 3, HvxVtkFloat32 = 4 };

/// What a reader reports of a file before any voxel is read.
struct HvxVtkHeader {
    int extent[6];             // VTK's whole extent: i0 i1 j0 j1 k0 k1
    double spacing[3];
    double origin[3];
    int hasDirection;          // the file gave direction cosines (a VTI's Direction)
    double direction[9];       // row-major, as VTK keeps it: column c is axis c's direction
    int hasScalars;            // the image has point scalars at all
    int components;            // per voxel
    int voxelType;             // HvxVtkVoxelType
    int converted;             // the file's type is widened exactly into voxelType (int8, float64)
    int streams;               // the reader can read a slab of slices alone
    char scalarTypeName[32];   // the file's own type, as VTK names it
};

struct HvxVtkReader;

/// The module's functions, as one table.
struct HvxVtkReaderApi {
    int abiVersion;  // kHvxVtkReaderAbiVersion
    /// Opens `path` as `format` and fills `header`; null on failure.
    HvxVtkReader* (*open)(const char* path, int format, HvxVtkHeader* header, char* error, std::size_t errorSize);
    /// Reads slices k0..k1 (indices into the whole extent, inclusive) as header.voxelType into
    /// dst (dstBytes long, exactly what they need); 0 on success.
    int (*read)(HvxVtkReader* reader, int k0, int k1, void* dst, std::size_t dstBytes, char* error, std::size_t errorSize);
    void (*close)(HvxVtkReader* reader);
    /// VTK's version as linked ("9.1.0").
    const char* (*version)();
};

/// The module's one exported symbol.
using HvxVtkReaderApiFunction = const HvxVtkReaderApi* (*)();
#define HVX_VTK_READER_API_SYMBOL "hvxVtkReaderApi"

}  // extern "C"
