#include "core/volume/NiftiHeader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "core/base/Error.h"

namespace hvx::core {

namespace {

/// Little or big endian fields of the raw header.
class Fields {
public:
    Fields(const unsigned char* b, bool swap) : b_(b), swap_(swap) {}
    template <class T>
    T get(std::size_t offset) const {
        unsigned char tmp[sizeof(T)];
        std::memcpy(tmp, b_ + offset, sizeof(T));
        if (swap_) std::reverse(tmp, tmp + sizeof(T));
        T v;
        std::memcpy(&v, tmp, sizeof(T));
        return v;
    }

private:
    const unsigned char* b_;
    bool swap_;
};

bool hostIsLittle() {
    const std::uint16_t one = 1;
    unsigned char c;
    std::memcpy(&c, &one, 1);
    return c == 1;
}

std::string mm(double v) {
    std::ostringstream s;
    s.precision(v < 10 ? 2 : 3);
    s << v;
    return s.str();
}

/// The largest distance (mm) between the two placements of the volume's eight corners.
double cornerDistance(const glm::dmat4& a, const glm::dmat4& b, const std::array<std::uint32_t, 3>& dims) {
    double worst = 0;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec4 p((c & 1) ? dims[0] - 1.0 : 0.0, (c & 2) ? dims[1] - 1.0 : 0.0, (c & 4) ? dims[2] - 1.0 : 0.0,
                           1.0);
        worst = std::max(worst, glm::length(glm::dvec3(a * p) - glm::dvec3(b * p)));
    }
    return worst;
}

}  // namespace

glm::dmat4 NiftiHeader::quaternionAffine(double b, double c, double d, const glm::dvec3& offset,
                                         const glm::dvec3& pixdim, double qfac) {
    double a2 = 1.0 - (b * b + c * c + d * d);
    double a = 0.0;
    if (a2 > 1e-7) {
        a = std::sqrt(a2);
    } else {  // a 180-degree rotation: (b, c, d) is the axis; normalise it as nifti1_io does
        const double n = std::sqrt(b * b + c * c + d * d);
        if (n > 0) b /= n, c /= n, d /= n;
    }
    const glm::dmat3 r(a * a + b * b - c * c - d * d, 2 * (b * c + a * d), 2 * (b * d - a * c),  // column 0
                       2 * (b * c - a * d), a * a + c * c - b * b - d * d, 2 * (c * d + a * b),  // column 1
                       2 * (b * d + a * c), 2 * (c * d - a * b), a * a + d * d - c * c - b * b); // column 2
    const double zs = qfac < 0 ? -pixdim.z : pixdim.z;
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(r[0] * pixdim.x, 0);
    m[1] = glm::dvec4(r[1] * pixdim.y, 0);
    m[2] = glm::dvec4(r[2] * zs, 0);
    m[3] = glm::dvec4(offset, 1);
    return m;
}

NiftiHeader NiftiHeader::parse(const unsigned char* bytes, std::size_t size, const std::string& what) {
    if (size < 348) throw Error(what + ": too short for a NIfTI header (" + std::to_string(size) + " bytes)");
    std::int32_t sizeofHdr;
    std::memcpy(&sizeofHdr, bytes, 4);
    std::int32_t swapped = sizeofHdr;
    {
        unsigned char t[4];
        std::memcpy(t, &sizeofHdr, 4);
        std::reverse(t, t + 4);
        std::memcpy(&swapped, t, 4);
    }
    bool swap = false;
    if (sizeofHdr == 540 || swapped == 540)
        throw Error(what + ": NIfTI-2 files are not supported yet (convert with nibabel or FSL to NIfTI-1)");
    if (sizeofHdr != 348) {
        if (swapped != 348) throw Error(what + ": not a NIfTI-1 file (sizeof_hdr is not 348)");
        swap = true;
    }
    NiftiHeader h;
    h.bigEndian = hostIsLittle() == swap;
    const Fields f(bytes, swap);
    if (std::memcmp(bytes + 344, "n+1", 4) != 0 && std::memcmp(bytes + 344, "ni1", 4) != 0)
        throw Error(what + ": not a NIfTI-1 file (magic is neither n+1 nor ni1)");
    if (std::memcmp(bytes + 344, "ni1", 4) == 0)
        throw Error(what + ": a NIfTI header with a separate .img file is not supported; use a single .nii");

    std::array<std::int16_t, 8> dim{};
    for (int i = 0; i < 8; ++i) dim[std::size_t(i)] = f.get<std::int16_t>(40 + 2 * std::size_t(i));
    if (dim[0] < 1 || dim[0] > 7) throw Error(what + ": dim[0] = " + std::to_string(dim[0]) + " is not 1..7");
    for (int i = 1; i <= 7; ++i) {
        if (i > dim[0]) dim[std::size_t(i)] = 1;
        if (dim[std::size_t(i)] < 1)
            throw Error(what + ": dim[" + std::to_string(i) + "] = " + std::to_string(dim[std::size_t(i)]) +
                        " is not a size");
    }
    for (int i = 5; i <= 7; ++i)
        if (dim[std::size_t(i)] > 1)
            throw Error(what + ": dim[" + std::to_string(i) + "] = " + std::to_string(dim[std::size_t(i)]) +
                        ": vector or multi-component NIfTI images are not supported");
    for (int a = 0; a < 3; ++a) h.geometry.dims[std::size_t(a)] = std::uint32_t(dim[std::size_t(a) + 1]);
    h.volumes = std::uint32_t(dim[4]);

    h.dataType = f.get<std::int16_t>(70);
    switch (h.dataType) {
    case Uint8: h.element = FileElement::UInt8; break;
    case Int8: h.element = FileElement::Int8; break;
    case Int16: h.element = FileElement::Int16; break;
    case Uint16: h.element = FileElement::UInt16; break;
    case Float32: h.element = FileElement::Float32; break;
    case Int32: h.element = FileElement::Int32; break;
    case Uint32: h.element = FileElement::UInt32; break;
    case Float64: h.element = FileElement::Float64; break;
    case Int64: h.element = FileElement::Int64; break;
    case Uint64: h.element = FileElement::UInt64; break;
    default:
        throw Error(what + ": NIfTI datatype " + std::to_string(h.dataType) +
                    " (RGB, complex or unknown) is not supported; supported: integers and floats");
    }
    h.geometry.scalarType = storedTypeOf(h.element);
    if (const auto w = conversionWarning(h.element); !w.empty()) h.warnings.push_back(w);

    const float voxOffset = f.get<float>(108);
    if (!(voxOffset >= 348.0f) || voxOffset > 1e12f)
        throw Error(what + ": vox_offset " + std::to_string(voxOffset) + " is not a byte offset after the header");
    h.voxOffset = std::uint64_t(voxOffset);

    const float slope = f.get<float>(112), inter = f.get<float>(116);
    if (std::isfinite(slope) && slope != 0.0f) {  // a slope of 0 (or not a number) means no scaling
        if (!std::isfinite(inter))
            throw Error(what + ": scl_slope is " + std::to_string(slope) + " but scl_inter is not a number, so its "
                        "values cannot be known (nibabel refuses it too)");
        h.geometry.rescaleSlope = slope;
        h.geometry.rescaleIntercept = inter;
    }

    double unit = 1.0;  // to millimetres
    switch (f.get<std::uint8_t>(123) & 7) {
    case 1: unit = 1000.0; break;   // metres
    case 3: unit = 0.001; break;    // micrometres
    default: break;                 // millimetres, or unknown (NIfTI's default is mm)
    }

    glm::dvec3 pixdim;
    for (int a = 0; a < 3; ++a) pixdim[a] = f.get<float>(80 + 4 * std::size_t(a));
    const double pixdim0 = f.get<float>(76);
    const double qfac = pixdim0 < 0 ? -1.0 : 1.0;  // 0 is 1, as the standard says

    h.qformCode = f.get<std::int16_t>(252);
    h.sformCode = f.get<std::int16_t>(254);
    if (h.qformCode > 0) {
        // Why the qform cannot place the volume, if it cannot: a refusal when it is the one
        // used, a note when the sform places the volume instead.
        std::string unusable;
        for (int a = 0; a < 3 && unusable.empty(); ++a)
            if (!(pixdim[a] > 0) || !std::isfinite(pixdim[a]))
                unusable = "pixdim[" + std::to_string(a + 1) + "] = " + std::to_string(pixdim[a]) + " is not a voxel size";
        if (unusable.empty() && pixdim0 != 0 && pixdim0 != 1 && pixdim0 != -1)
            unusable = "pixdim[0] (qfac) = " + std::to_string(pixdim0) + " is neither 1 nor -1 (nifti1_io takes it as " +
                       (qfac < 0 ? "-1" : "1") + ", nibabel as 1: the slice order, and so the handedness, is not known)";
        if (!unusable.empty() && h.sformCode <= 0)
            throw Error(what + ": " + unusable + ", so the qform cannot place the volume");
        if (!unusable.empty()) {
            h.warnings.push_back("its qform is not used (" + unusable + "); the sform places the volume");
            h.qformCode = 0;
        } else {
            const glm::dvec3 offset(f.get<float>(268), f.get<float>(272), f.get<float>(276));
            h.qform = quaternionAffine(f.get<float>(256), f.get<float>(260), f.get<float>(264), offset, pixdim, qfac);
        }
    }
    if (h.sformCode > 0) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) h.sform[c][r] = f.get<float>(280 + 16 * std::size_t(r) + 4 * std::size_t(c));
    }

    glm::dmat4 affine(1.0);
    if (h.sformCode > 0) {
        affine = h.sform;
        if (h.qformCode > 0) {
            const double apart = cornerDistance(h.qform, h.sform, h.geometry.dims);
            const bool mirrored = (glm::determinant(glm::dmat3(h.qform)) < 0) != (glm::determinant(glm::dmat3(h.sform)) < 0);
            if (mirrored)
                h.warnings.push_back("its qform and sform differ in handedness (one is the other mirrored); the sform "
                                     "is used, as nibabel, FSL and SPM do");
            else if (apart * unit > 0.01)  // the file's unit: 0.01 mm
                h.warnings.push_back("its qform and sform disagree by up to " + mm(apart * unit) +
                                     " mm; the sform is used, as nibabel, FSL and SPM do");
        }
    } else if (h.qformCode > 0) {
        affine = h.qform;
    } else {
        for (int a = 0; a < 3; ++a) {
            const double s = pixdim[a] > 0 && std::isfinite(pixdim[a]) ? pixdim[a] : 1.0;
            affine[a][a] = s;
        }
        h.warnings.push_back("it has no orientation (qform_code and sform_code are 0): it is placed by its voxel "
                             "sizes alone, and left and right are not known");
        h.geometry.orientationAssumed = true;  // the views draw "?" for the orientation letters
    }

    // RAS+ millimetres (in the file's unit) to LPS millimetres.
    glm::dmat4 toLps(1.0);
    toLps[0][0] = -unit;
    toLps[1][1] = -unit;
    toLps[2][2] = unit;
    const glm::dmat4 m = toLps * affine;
    h.geometry.origin = glm::dvec3(m[3]);
    for (int a = 0; a < 3; ++a) {
        const glm::dvec3 step(m[a]);
        const double len = glm::length(step);
        if (!(len > 0) || !std::isfinite(len))
            throw Error(what + ": its " + (h.sformCode > 0 ? "sform" : "qform") + " gives axis " + std::to_string(a) +
                        " no length, so the volume cannot be placed");
        h.geometry.spacing[a] = len;
        h.geometry.direction[a] = step / len;
    }
    if (!std::isfinite(h.geometry.origin.x) || !std::isfinite(h.geometry.origin.y) || !std::isfinite(h.geometry.origin.z))
        throw Error(what + ": its placement has a non-finite origin");
    h.geometry.modality = "OT";  // a NIfTI names no modality (NiftiVoxelSource reads a BIDS sidecar's)
    h.geometry.validate(what);
    return h;
}

}  // namespace hvx::core
