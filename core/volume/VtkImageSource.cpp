#include "core/volume/VtkImageSource.h"

#include <vtkVersion.h>
#include <vtkAlgorithm.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkImageReader2.h>
#include <vtkMatrix3x3.h>
#include <vtkMatrix4x4.h>
#include <vtkMetaImageReader.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStructuredPointsReader.h>
#include <vtkXMLImageDataReader.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkInformation.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                                                   [](char a, char b) { return std::tolower(a) == b; });
}

// Converts the file's scalar type to a supported one, or explains why not.
ScalarType mapType(int vtkType, const std::string& path, int& convertFrom) {
    convertFrom = -1;
    switch (vtkType) {
    case VTK_UNSIGNED_CHAR: return ScalarType::UInt8;
    case VTK_SHORT: return ScalarType::Int16;
    case VTK_UNSIGNED_SHORT: return ScalarType::UInt16;
    case VTK_FLOAT: return ScalarType::Float32;
    case VTK_SIGNED_CHAR:
    case VTK_CHAR: convertFrom = vtkType; return ScalarType::Int16;  // exact
    case VTK_DOUBLE: convertFrom = vtkType; return ScalarType::Float32;
    default: break;
    }
    throw Error(path + ": unsupported voxel type (" + std::string(vtkImageScalarTypeNameMacro(vtkType)) +
                "); supported: uint8, int8, int16, uint16, float32, float64");
}
/// The direction cosines of a MetaImage header (TransformMatrix, or its aliases Rotation and
/// Orientation): row a of the nine numbers is axis a's direction in LPS, as ITK writes it.
/// Identity when the header has none; refused when it is not three independent unit vectors.
glm::dmat3 metaImageDirection(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    glm::dmat3 m(1.0);
    for (int n = 0; n < 200 && std::getline(in, line); ++n) {
        const auto eq = line.find('=');
        if (eq == std::string::npos) continue;
        std::string key = line.substr(0, eq);
        key.erase(key.find_last_not_of(" \t") + 1);
        if (key == "ElementDataFile") break;
        if (key != "TransformMatrix" && key != "Rotation" && key != "Orientation") continue;
        std::istringstream v(line.substr(eq + 1));
        double d[9];
        for (double& x : d)
            if (!(v >> x)) throw Error(path + ": its " + key + " is not nine numbers");
        for (int a = 0; a < 3; ++a) m[a] = glm::dvec3(d[3 * a], d[3 * a + 1], d[3 * a + 2]);
        for (int a = 0; a < 3; ++a)
            if (std::abs(glm::length(m[a]) - 1.0) > 1e-3)
                throw Error(path + ": its " + key + " row " + std::to_string(a) + " is not a unit direction");
        if (std::abs(glm::determinant(m)) < 1e-3) throw Error(path + ": its " + key + " has dependent directions");
    }
    return m;
}
}  // namespace

struct VtkImageSource::Impl {
    vtkSmartPointer<vtkAlgorithm> reader;
    int extent[6] = {0, -1, 0, -1, 0, -1};
    int convertFrom = -1;
    bool streams = true;
    std::vector<unsigned char> cache;  // slices [cacheFirst, cacheFirst + cacheCount)
    std::uint32_t cacheFirst = 0, cacheCount = 0;
};

bool VtkImageSource::handles(const std::string& path) {
    for (const char* ext : {".mha", ".mhd", ".vtk", ".vti"})
        if (endsWith(path, ext)) return true;
    return false;
}

VtkImageSource::VtkImageSource(std::string path) : path_(std::move(path)), impl_(std::make_unique<Impl>()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) throw Error(path_ + ": no such file");
    if (endsWith(path_, ".mha") || endsWith(path_, ".mhd")) {
        auto r = vtkSmartPointer<vtkMetaImageReader>::New();
        if (!r->CanReadFile(path_.c_str())) throw Error(path_ + ": not a MetaImage file");
        r->SetFileName(path_.c_str());
        impl_->reader = r;
    } else if (endsWith(path_, ".vti")) {
        auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
        if (!r->CanReadFile(path_.c_str())) throw Error(path_ + ": not a VTK XML image file");
        r->SetFileName(path_.c_str());
        impl_->reader = r;
    } else if (endsWith(path_, ".vtk")) {
        auto r = vtkSmartPointer<vtkStructuredPointsReader>::New();
        r->SetFileName(path_.c_str());
        if (!r->IsFileStructuredPoints()) throw Error(path_ + ": not a legacy VTK structured-points file");
        impl_->reader = r;
        impl_->streams = false;
    } else {
        throw Error(path_ + ": unknown image file type");
    }
    impl_->reader->GlobalWarningDisplayOff();
    impl_->reader->UpdateInformation();
    if (impl_->reader->GetErrorCode() != 0) throw Error(path_ + ": cannot read the image header");
    vtkInformation* info = impl_->reader->GetOutputInformation(0);
    info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), impl_->extent);
    double spacing[3] = {1, 1, 1}, origin[3] = {0, 0, 0};
    if (info->Has(vtkDataObject::SPACING())) info->Get(vtkDataObject::SPACING(), spacing);
    if (info->Has(vtkDataObject::ORIGIN())) info->Get(vtkDataObject::ORIGIN(), origin);
    vtkInformation* scalarInfo = vtkDataObject::GetActiveFieldInformation(
        info, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
    if (!scalarInfo) throw Error(path_ + ": image has no scalar data");
    const int components = scalarInfo->Has(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
                               ? scalarInfo->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS()) : 1;
    if (components != 1) throw Error(path_ + ": only single-component images are supported");
    const int vtkType = scalarInfo->Get(vtkDataObject::FIELD_ARRAY_TYPE());
    geometry_.scalarType = mapType(vtkType, path_, impl_->convertFrom);
    for (int a = 0; a < 3; ++a) {
        const int n = impl_->extent[2 * a + 1] - impl_->extent[2 * a] + 1;
        if (n <= 0) throw Error(path_ + ": image is empty");
        geometry_.dims[std::size_t(a)] = std::uint32_t(n);
    }
    // VTK's point p(i) = origin + D (extent0 + i) * spacing, D the direction matrix: from the VTI
    // file's Direction, or the MetaImage header's TransformMatrix (which VTK's reader ignores).
    glm::dmat4 toPatient(1.0);
    if (info->Has(vtkDataObject::DIRECTION())) {
        double d[9];
        info->Get(vtkDataObject::DIRECTION(), d);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) toPatient[c][r] = d[3 * r + c];
    }
    if (endsWith(path_, ".mha") || endsWith(path_, ".mhd")) toPatient = glm::dmat4(metaImageDirection(path_));
    glm::dvec3 first;
    for (int a = 0; a < 3; ++a) first[a] = impl_->extent[2 * a] * spacing[a];
    geometry_.origin = glm::dvec3(origin[0], origin[1], origin[2]) + glm::dmat3(toPatient) * first;
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 step = glm::dmat3(toPatient)[a] * spacing[a];
        const double len = glm::length(step);
        if (!(len > 0)) throw Error(path_ + ": degenerate voxel spacing or orientation");
        geometry_.spacing[a] = len;
        geometry_.direction[a] = step / len;
    }
    geometry_.validate(path_);
}

VtkImageSource::~VtkImageSource() = default;

void VtkImageSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::size_t outWidth = scalarSize(geometry_.scalarType);
    const std::size_t sliceVoxels = std::size_t(geometry_.dims[0]) * geometry_.dims[1];
    auto* out = static_cast<unsigned char*>(dst);
    for (std::uint32_t s = firstSlice; s < firstSlice + count; ++s) {
        if (s < impl_->cacheFirst || s >= impl_->cacheFirst + impl_->cacheCount) {
            const std::uint32_t chunk = impl_->streams ? std::min<std::uint32_t>(32, geometry_.dims[2] - s)
                                                       : geometry_.dims[2] - s;
            int ext[6] = {impl_->extent[0], impl_->extent[1], impl_->extent[2], impl_->extent[3],
                          impl_->extent[4] + int(s), impl_->extent[4] + int(s + chunk) - 1};
            impl_->reader->UpdateExtent(ext);
            auto* image = vtkImageData::SafeDownCast(impl_->reader->GetOutputDataObject(0));
            if (impl_->reader->GetErrorCode() != 0 || !image || !image->GetPointData()->GetScalars())
                throw Error(path_ + ": cannot read voxel data (file truncated or corrupt?)");
            int got[6];
            image->GetExtent(got);
            vtkDataArray* arr = image->GetPointData()->GetScalars();
            const std::size_t need = sliceVoxels * chunk;
            const vtkIdType offset = vtkIdType(ext[4] - got[4]) * vtkIdType(sliceVoxels);
            if (got[0] != ext[0] || got[1] != ext[1] || got[2] != ext[2] || got[3] != ext[3] || got[4] > ext[4] ||
                got[5] < ext[5] || arr->GetNumberOfTuples() < offset + vtkIdType(need))
                throw Error(path_ + ": reader returned fewer voxels than the header promises (truncated file?)");
            impl_->cache.resize(need * outWidth);
            if (impl_->convertFrom < 0) {
                std::memcpy(impl_->cache.data(), static_cast<unsigned char*>(arr->GetVoidPointer(0)) + offset * vtkIdType(outWidth),
                            need * outWidth);
            } else {
                for (std::size_t i = 0; i < need; ++i) {
                    const double v = arr->GetComponent(offset + vtkIdType(i), 0);
                    if (geometry_.scalarType == ScalarType::Int16) {
                        const auto x = std::int16_t(v);
                        std::memcpy(&impl_->cache[i * 2], &x, 2);
                    } else {
                        const auto x = float(v);
                        std::memcpy(&impl_->cache[i * 4], &x, 4);
                    }
                }
            }
            impl_->cacheFirst = s;
            impl_->cacheCount = chunk;
        }
        std::memcpy(out, impl_->cache.data() + (s - impl_->cacheFirst) * sliceVoxels * outWidth, sliceVoxels * outWidth);
        out += sliceVoxels * outWidth;
    }
}

std::string VtkImageSource::libraryVersion() { return vtkVersion::GetVTKVersion(); }

}  // namespace hvx::core
