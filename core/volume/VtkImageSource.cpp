#include "core/volume/VtkImageSource.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"
#include "core/base/Memory.h"
#include "core/volume/LegacyVtkHeader.h"
#include "core/volume/MetaImageHeader.h"
#include "core/volume/VtkReaderLibrary.h"

namespace hvx::core {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                                                   [](char a, char b) { return std::tolower(a) == b; });
}

// Slices a reader that streams (the XML reader) is asked for at a time.
constexpr std::uint32_t kSlicesPerRead = 32;

// True when a VTK XML file's VTKFile element names a compressor (its data may then hold more
// voxels than bytes), or when that element is not within the file's first 64 KiB.
bool mayBeCompressed(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(std::size_t(64) << 10, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(in.gcount()));
    const auto begin = head.find("<VTKFile");
    const auto end = begin == std::string::npos ? std::string::npos : head.find('>', begin);
    return end == std::string::npos || head.substr(begin, end - begin).find("compressor=") != std::string::npos;
}
}  // namespace

struct VtkImageSource::Impl {
    const HvxVtkReaderApi& api = VtkReaderLibrary::api();
    HvxVtkReader* reader = nullptr;
    HvxVtkHeader header{};
    std::vector<unsigned char> cache;  // slices [cacheFirst, cacheFirst + cacheCount)
    std::uint32_t cacheFirst = 0, cacheCount = 0;
    ~Impl() {
        if (reader) api.close(reader);
    }
};

bool VtkImageSource::isMetaImage(const std::string& path) { return endsWith(path, ".mha") || endsWith(path, ".mhd"); }

bool VtkImageSource::isLegacyVtk(const std::string& path) { return endsWith(path, ".vtk"); }

bool VtkImageSource::handles(const std::string& path) {
    for (const char* ext : {".mha", ".mhd", ".vtk", ".vti"})
        if (endsWith(path, ext)) return true;
    return false;
}

VtkImageSource::VtkImageSource(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) throw Error(path_ + ": no such file");
    try {
        impl_ = std::make_unique<Impl>();  // loads the reader module
    } catch (const Error& e) {
        throw Error(path_ + ": " + e.what());
    }
    int format = HvxVtkMetaImage;
    if (endsWith(path_, ".vti"))
        format = HvxVtkXmlImage;
    else if (endsWith(path_, ".vtk"))
        format = HvxVtkLegacyImage;
    else if (!isMetaImage(path_))
        throw Error(path_ + ": unknown image file type");
    const HvxVtkHeader& h = impl_->header;
    char error[256] = "";
    impl_->reader = impl_->api.open(path_.c_str(), format, &impl_->header, error, sizeof error);
    if (!impl_->reader) throw Error(path_ + ": " + error);
    if (!h.hasScalars) throw Error(path_ + ": image has no scalar data");
    if (h.components != 1) throw Error(path_ + ": only single-component images are supported");
    if (h.voxelType == HvxVtkUnsupported)
        throw Error(path_ + ": unsupported voxel type (" + h.scalarTypeName +
                    "); supported: uint8, int8, int16, uint16, float32, float64");
    geometry_.scalarType = ScalarType(h.voxelType);
    for (int a = 0; a < 3; ++a) {
        const int n = h.extent[2 * a + 1] - h.extent[2 * a] + 1;
        if (n <= 0) throw Error(path_ + ": image is empty");
        geometry_.dims[std::size_t(a)] = std::uint32_t(n);
    }
    // VTK's point p(i) = origin + D (extent0 + i) * spacing, D the direction matrix: from the VTI
    // file's Direction, or the MetaImage header's TransformMatrix (which VTK's reader ignores).
    glm::dmat4 toPatient(1.0);
    if (h.hasDirection) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) toPatient[c][r] = h.direction[3 * r + c];
    }
    if (isMetaImage(path_)) {
        const MetaImageHeader mh = MetaImageHeader::read(path_);
        toPatient = glm::dmat4(mh.geometry.direction);
        geometry_.spacingAssumed = mh.geometry.spacingAssumed;
        warnings_ = mh.warnings;
    } else if (format == HvxVtkLegacyImage) {
        const LegacyVtkHeader lh = LegacyVtkHeader::read(path_);
        geometry_.spacingAssumed = lh.geometry.spacingAssumed;
        warnings_ = lh.warnings;
    } else {
        warnings_.push_back(path_ + ": a VTK file names no patient axes: taken as LPS, as ITK writes them");
    }
    glm::dvec3 first;
    for (int a = 0; a < 3; ++a) first[a] = h.extent[2 * a] * h.spacing[a];
    geometry_.origin = glm::dvec3(h.origin[0], h.origin[1], h.origin[2]) + glm::dmat3(toPatient) * first;
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 step = glm::dmat3(toPatient)[a] * h.spacing[a];
        const double len = glm::length(step);
        if (!(len > 0)) throw Error(path_ + ": degenerate voxel spacing or orientation");
        geometry_.spacing[a] = len;
        geometry_.direction[a] = step / len;
    }
    geometry_.validate(path_);
    // VTK allocates what the header announces before it reads a value: an extent the file cannot
    // hold had it take all the memory there is (and fail after minutes).
    const double sliceVoxels = double(geometry_.dims[0]) * double(geometry_.dims[1]);
    const double voxels = sliceVoxels * geometry_.dims[2];
    if (format == HvxVtkXmlImage && !mayBeCompressed(path_)) {  // uncompressed: a byte a voxel at least
        const auto size = std::filesystem::file_size(path_, ec);
        if (!ec && double(size) < voxels)
            throw Error(path_ + ": its extent gives " + std::to_string(std::uint64_t(voxels)) + " voxels, more than its " +
                        std::to_string(size) + " bytes can hold uncompressed");
    }
    const double width = double(scalarSize(geometry_.scalarType));
    const double fileWidth = !h.converted ? width : geometry_.scalarType == ScalarType::Int16 ? 1.0 : 8.0;  // int8, float64
    const double held = sliceVoxels * double(h.streams ? std::min(kSlicesPerRead, geometry_.dims[2]) : geometry_.dims[2]) *
                        (fileWidth + width);  // VTK's array, and the slices kept here
    const double memory = double(physicalMemoryBytes());
    if (held > memory / 2)
        throw Error(path_ + ": VTK's reader would hold " + gibibytes(held) + " of it in memory at once, more than half of "
                    "this machine's " + gibibytes(memory) + "; written as NRRD, NIfTI or a binary MetaImage, Holovox "
                    "streams it");
}

VtkImageSource::~VtkImageSource() = default;

void VtkImageSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::size_t outWidth = scalarSize(geometry_.scalarType);
    const std::size_t sliceVoxels = std::size_t(geometry_.dims[0]) * geometry_.dims[1];
    auto* out = static_cast<unsigned char*>(dst);
    for (std::uint32_t s = firstSlice; s < firstSlice + count; ++s) {
        if (s < impl_->cacheFirst || s >= impl_->cacheFirst + impl_->cacheCount) {
            // A reader that cannot stream is always asked for the whole image (VTK's MetaImage
            // reader writes all of it whatever extent it is asked for).
            const bool streams = impl_->header.streams != 0;
            const std::uint32_t from = streams ? s : 0;
            const std::uint32_t chunk = streams ? std::min(kSlicesPerRead, geometry_.dims[2] - s) : geometry_.dims[2];
            const int k0 = impl_->header.extent[4] + int(from);
            impl_->cache.resize(sliceVoxels * chunk * outWidth);
            char error[256] = "";
            if (impl_->api.read(impl_->reader, k0, k0 + int(chunk) - 1, impl_->cache.data(), impl_->cache.size(), error,
                                sizeof error) != 0)
                throw Error(path_ + ": " + error);
            impl_->cacheFirst = from;
            impl_->cacheCount = chunk;
        }
        std::memcpy(out, impl_->cache.data() + (s - impl_->cacheFirst) * sliceVoxels * outWidth, sliceVoxels * outWidth);
        out += sliceVoxels * outWidth;
    }
}

std::string VtkImageSource::libraryVersion() {
    try {
        return VtkReaderLibrary::api().version();
    } catch (const Error&) {
        return std::string("unavailable (") + VtkReaderLibrary::kFileName + " cannot be loaded)";
    }
}

}  // namespace hvx::core
