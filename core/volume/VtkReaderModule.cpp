// The VTK reader module (libhvx_vtk_reader.so): VTK's MetaImage, VTK XML image and legacy VTK
// readers behind the C interface of VtkReaderAbi.h. Built as a module of its own and loaded by
// VtkReaderLibrary on first use; nothing else in Holovox links VTK.

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkLogger.h>
#include <vtkMetaImageReader.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStructuredPointsReader.h>
#include <vtkVersion.h>
#include <vtkXMLImageDataReader.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include "core/volume/VtkReaderAbi.h"

struct HvxVtkReader {
    vtkSmartPointer<vtkAlgorithm> reader;
    vtkNew<vtkCallbackCommand> observer;  // catches the reader's errors and warnings
    std::string complaint;                // the first of them since the last read began
    int extent[6] = {0, -1, 0, -1, 0, -1};
    int voxelType = HvxVtkUnsupported;
    int converted = 0;
};

namespace {

/// VTK's readers report a file cut short (the legacy reader: "Error reading binary data!") as a
/// warning or an error event, and deliver the voxels they did not read as zeros: every such
/// event fails the read.
void complain(vtkObject*, unsigned long, void* clientData, void* callData) {
    auto* r = static_cast<HvxVtkReader*>(clientData);
    if (r->complaint.empty()) r->complaint = callData ? static_cast<const char*>(callData) : "unknown";
}

/// The reader reading on this thread, for the complaints that VTK's helpers send to its output
/// window rather than to the reader (the legacy reader's "Error reading binary data!").
thread_local HvxVtkReader* reading = nullptr;

void complainToCurrent(vtkObject*, unsigned long, void*, void* callData) {
    if (reading) complain(nullptr, 0, reading, callData);
}

/// Sets `reading` for a scope, the output window's observer installed once.
class Reading {
public:
    explicit Reading(HvxVtkReader* r) {
        static const bool installed = [] {
            static vtkNew<vtkCallbackCommand> observer;
            observer->SetCallback(complainToCurrent);
            vtkOutputWindow::GetInstance()->AddObserver(vtkCommand::ErrorEvent, observer);
            vtkOutputWindow::GetInstance()->AddObserver(vtkCommand::WarningEvent, observer);
            // The complaints become Holovox's own sentences; VTK need not print them too.
            vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
            vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
            return true;
        }();
        (void)installed;
        reading = r;
    }
    ~Reading() { reading = nullptr; }
    Reading(const Reading&) = delete;
    Reading& operator=(const Reading&) = delete;
};

/// ": VTK's reader says "..."" for a complaint, without the source file, line and object VTK
/// puts before it; empty for none.
std::string vtkSays(std::string m) {
    if (m.empty()) return m;
    while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
    const auto line = m.rfind('\n');  // "In FILE, line N\n[vtkClass (0x...): ]message"
    if (line != std::string::npos) m = m.substr(line + 1);
    const auto object = m.find("): ");
    if (m.rfind("vtk", 0) == 0 && object != std::string::npos) m = m.substr(object + 3);
    return ": VTK's reader says \"" + m + "\"";
}

/// Writes `message` into the caller's buffer; returns `result`.
template <class T>
T fail(char* error, std::size_t size, const char* message, T result) {
    if (size > 0) std::snprintf(error, size, "%s", message);
    return result;
}

/// The voxel type a VTK scalar type is delivered as, and whether that widens it.
int voxelTypeOf(int vtkType, int& converted) {
    converted = 0;
    switch (vtkType) {
    case VTK_UNSIGNED_CHAR: return HvxVtkUInt8;
    case VTK_SHORT: return HvxVtkInt16;
    case VTK_UNSIGNED_SHORT: return HvxVtkUInt16;
    case VTK_FLOAT: return HvxVtkFloat32;
    case VTK_SIGNED_CHAR:
    case VTK_CHAR: converted = 1; return HvxVtkInt16;  // exact
    case VTK_DOUBLE: converted = 1; return HvxVtkFloat32;
    default: return HvxVtkUnsupported;
    }
}

vtkSmartPointer<vtkAlgorithm> makeReader(const char* path, int format, char* error, std::size_t size) {
    if (format == HvxVtkMetaImage) {
        auto r = vtkSmartPointer<vtkMetaImageReader>::New();
        if (!r->CanReadFile(path)) return fail(error, size, "not a MetaImage file", nullptr);
        r->SetFileName(path);
        return r;
    }
    if (format == HvxVtkXmlImage) {
        auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
        if (!r->CanReadFile(path)) return fail(error, size, "not a VTK XML image file", nullptr);
        r->SetFileName(path);
        return r;
    }
    if (format == HvxVtkLegacyImage) {
        auto r = vtkSmartPointer<vtkStructuredPointsReader>::New();
        r->SetFileName(path);
        if (!r->IsFileStructuredPoints()) return fail(error, size, "not a legacy VTK structured-points file", nullptr);
        return r;
    }
    return fail(error, size, "unknown image file type", nullptr);
}

HvxVtkReader* openImage(const char* path, int format, HvxVtkHeader* header, char* error, std::size_t size) try {
    auto reader = makeReader(path, format, error, size);
    if (!reader) return nullptr;
    *header = HvxVtkHeader{};
    // Only the XML reader honours an update extent smaller than the image. The legacy reader
    // reads the whole file; VTK 9.1's MetaImage reader reads the whole image into a buffer sized
    // for the extent asked for (a heap overflow: holovox-cli aborted in free() on any MetaImage
    // of more than 32 slices), so both are read whole, once.
    header->streams = format == HvxVtkXmlImage;
    auto out = std::make_unique<HvxVtkReader>();
    out->reader = reader;
    out->observer->SetCallback(complain);
    out->observer->SetClientData(out.get());
    reader->AddObserver(vtkCommand::ErrorEvent, out->observer);
    reader->AddObserver(vtkCommand::WarningEvent, out->observer);
    // On, so that VTK raises warnings as events: the reader's own reach the observer rather than
    // the terminal.
    vtkObject::GlobalWarningDisplayOn();
    {
        Reading scope(out.get());
        reader->UpdateInformation();
    }
    if (reader->GetErrorCode() != 0 || !out->complaint.empty()) {
        const std::string m = "cannot read the image header" + vtkSays(out->complaint);
        return fail(error, size, m.c_str(), nullptr);
    }
    vtkInformation* info = reader->GetOutputInformation(0);
    info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), header->extent);
    for (int a = 0; a < 3; ++a) header->spacing[a] = 1;
    if (info->Has(vtkDataObject::SPACING())) info->Get(vtkDataObject::SPACING(), header->spacing);
    if (info->Has(vtkDataObject::ORIGIN())) info->Get(vtkDataObject::ORIGIN(), header->origin);
    header->hasDirection = info->Has(vtkDataObject::DIRECTION()) ? 1 : 0;
    if (header->hasDirection) info->Get(vtkDataObject::DIRECTION(), header->direction);
    vtkInformation* scalars = vtkDataObject::GetActiveFieldInformation(
        info, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
    header->hasScalars = scalars ? 1 : 0;
    std::memcpy(out->extent, header->extent, sizeof out->extent);
    if (scalars) {
        header->components = scalars->Has(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
                                  ? scalars->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS()) : 1;
        const int vtkType = scalars->Get(vtkDataObject::FIELD_ARRAY_TYPE());
        header->voxelType = voxelTypeOf(vtkType, header->converted);
        std::snprintf(header->scalarTypeName, sizeof header->scalarTypeName, "%s", vtkImageScalarTypeNameMacro(vtkType));
        out->voxelType = header->voxelType;
        out->converted = header->converted;
    }
    return out.release();
} catch (const std::bad_alloc&) {
    return fail(error, size, "out of memory reading the image header", nullptr);
}

int readSlices(HvxVtkReader* r, int k0, int k1, void* dst, std::size_t dstBytes, char* error, std::size_t size) try {
    if (r->voxelType == HvxVtkUnsupported) return fail(error, size, "unsupported voxel type", 1);
    int ext[6] = {r->extent[0], r->extent[1], r->extent[2], r->extent[3], k0, k1};
    r->complaint.clear();
    {
        Reading scope(r);
        r->reader->UpdateExtent(ext);
    }
    auto* image = vtkImageData::SafeDownCast(r->reader->GetOutputDataObject(0));
    if (!r->complaint.empty()) {
        const std::string m = "cannot read voxel data (truncated or corrupt?)" + vtkSays(r->complaint);
        return fail(error, size, m.c_str(), 1);
    }
    if (r->reader->GetErrorCode() != 0 || !image || !image->GetPointData()->GetScalars())
        return fail(error, size, "cannot read voxel data (file truncated or corrupt?)", 1);
    int got[6];
    image->GetExtent(got);
    vtkDataArray* arr = image->GetPointData()->GetScalars();
    const vtkIdType sliceVoxels = vtkIdType(ext[1] - ext[0] + 1) * vtkIdType(ext[3] - ext[2] + 1);
    const vtkIdType need = sliceVoxels * (k1 - k0 + 1);
    const vtkIdType offset = vtkIdType(k0 - got[4]) * sliceVoxels;
    const std::size_t width = r->voxelType == HvxVtkUInt8 ? 1 : r->voxelType == HvxVtkFloat32 ? 4 : 2;
    if (got[0] != ext[0] || got[1] != ext[1] || got[2] != ext[2] || got[3] != ext[3] || got[4] > k0 || got[5] < k1 ||
        arr->GetNumberOfTuples() < offset + need)
        return fail(error, size, "reader returned fewer voxels than the header promises (truncated file?)", 1);
    if (dstBytes != std::size_t(need) * width) return fail(error, size, "wrong buffer size for the slices asked for", 1);
    auto* out = static_cast<unsigned char*>(dst);
    if (!r->converted) {
        std::memcpy(out, static_cast<unsigned char*>(arr->GetVoidPointer(0)) + std::size_t(offset) * width, dstBytes);
        return 0;
    }
    for (vtkIdType i = 0; i < need; ++i) {
        const double v = arr->GetComponent(offset + i, 0);
        if (r->voxelType == HvxVtkInt16) {
            const auto x = std::int16_t(v);
            std::memcpy(out + std::size_t(i) * 2, &x, 2);
        } else {
            const auto x = float(v);
            std::memcpy(out + std::size_t(i) * 4, &x, 4);
        }
    }
    return 0;
} catch (const std::bad_alloc&) {
    return fail(error, size, "out of memory reading voxel data", 1);
}

void closeImage(HvxVtkReader* r) { delete r; }

const char* version() { return vtkVersion::GetVTKVersion(); }

const HvxVtkReaderApi kApi{kHvxVtkReaderAbiVersion, openImage, readSlices, closeImage, version};

}  // namespace

extern "C" __attribute__((visibility("default"))) const HvxVtkReaderApi* hvxVtkReaderApi() { return &kApi; }
