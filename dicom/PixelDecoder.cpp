#include "dicom/PixelDecoder.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcpixel.h>
#include <dcmtk/dcmdata/dcpixseq.h>
#include <dcmtk/dcmdata/dcpxitem.h>
#include <dcmtk/dcmdata/dcxfer.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/base/Error.h"
#include "core/volume/FiniteValueSource.h"
#include "dicom/DcmtkSetup.h"
#include "dicom/Jpeg2000Decoder.h"
#include "dicom/RleDecoder.h"

namespace hvx::dicom {

struct PixelDecoder::Impl {
    DcmFileFormat file;
    std::string loaded;

    /// The instance's data set, read from its file once for all its frames.
    DcmDataset* dataset(const DicomInstance& in) {
        if (loaded != in.path) {
            loaded.clear();
            const OFCondition st =
                file.loadFile(in.path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect);
            if (st.bad()) throw core::Error(in.path + ": cannot read pixel data (" + st.text() + ")");
            loaded = in.path;
        }
        return file.getDataset();
    }
};

PixelDecoder::PixelDecoder() : impl_(std::make_unique<Impl>()) { DcmtkSetup::ensure(); }
PixelDecoder::~PixelDecoder() = default;

namespace {

/// "FILE: frame N holds " of a multi-frame object, "FILE: its pixels hold " of a single frame.
std::string whatHolds(const DicomInstance& in, std::uint32_t frame) {
    return in.path + (in.frames > 1 ? ": frame " + std::to_string(frame) + " holds " : ": its pixels hold ");
}
bool isJpeg2000(E_TransferSyntax x) {
    return x == EXS_JPEG2000LosslessOnly || x == EXS_JPEG2000 || x == EXS_JPEG2000MulticomponentLosslessOnly ||
           x == EXS_JPEG2000Multicomponent;
}

// The encapsulated bytes of one frame: all fragments for a single frame, else one fragment
// per frame.
std::vector<std::uint8_t> frameFragments(DcmPixelData* pd, E_TransferSyntax xfer, const DicomInstance& in,
                                         std::uint32_t frame, const char* what) {
    DcmPixelSequence* seq = nullptr;
    if (pd->getEncapsulatedRepresentation(xfer, nullptr, seq).bad() || !seq)
        throw core::Error(in.path + ": " + what + " pixel data is not encapsulated");
    const unsigned long items = seq->card();
    if (items < 2) throw core::Error(in.path + ": " + what + " pixel data has no fragments");
    std::vector<std::uint8_t> stream;
    auto append = [&](unsigned long i) {
        DcmPixelItem* item = nullptr;
        Uint8* bytes = nullptr;
        if (seq->getItem(item, i).bad() || !item || item->getUint8Array(bytes).bad())
            throw core::Error(in.path + ": " + what + " fragment " + std::to_string(i) + " is unreadable");
        if (bytes) stream.insert(stream.end(), bytes, bytes + item->getLength());
    };
    if (in.frames == 1) {
        for (unsigned long i = 1; i < items; ++i) append(i);
    } else if (items - 1 == in.frames) {
        append(frame + 1);
    } else {
        throw core::Error(in.path + ": multi-frame " + what + " with several fragments per frame is not supported");
    }
    return stream;
}

void decodeJpeg2000(DcmPixelData* pd, E_TransferSyntax xfer, const DicomInstance& in, std::uint32_t frame,
                    std::vector<std::int32_t>& out) {
    const auto stream = frameFragments(pd, xfer, in, frame, "JPEG 2000");
    Jpeg2000Decoder::decode(stream.data(), stream.size(), in.columns, in.rows, out, in.path);
}
}  // namespace

void PixelDecoder::decode(const DicomInstance& in, std::uint32_t frame, std::vector<std::int32_t>& out) {
    try {
        decodeFrame(in, frame, out);
    } catch (const core::Error&) {
        impl_->loaded.clear();
        throw;
    } catch (const std::exception& e) {
        // DCMTK and OpenJPEG can throw on hostile input; it is a bad file, not a crash.
        impl_->loaded.clear();
        throw core::Error(in.path + ": pixel data does not decode (" + e.what() + ")");
    }
}

void PixelDecoder::decodeFrame(const DicomInstance& in, std::uint32_t frame, std::vector<std::int32_t>& out) {
    if (!in.hasPixels()) throw core::Error(in.path + ": has no image pixel data");
    if (frame >= in.frames) throw core::Error(in.path + ": frame " + std::to_string(frame) + " does not exist");
    if (in.samplesPerPixel != 1) throw core::Error(in.path + ": colour images are not supported as volumes");
    // Before any decoder sizes anything from the header: a frame must be one Holovox can hold
    // (RLE and JPEG 2000 streams are small whatever Rows and Columns claim).
    if (std::uint64_t(in.rows) * in.columns > kMaxFramePixels || in.rows == 0 || in.columns == 0)
        throw core::Error(in.path + ": a frame of " + std::to_string(in.columns) + " × " + std::to_string(in.rows) +
                          " pixels cannot be right (Holovox decodes frames of up to 16384 × 16384)");
    if (in.floatPixelBits) return decodeFloatFrame(in, frame, out);
    if (in.bitsAllocated != 8 && in.bitsAllocated != 16 && in.bitsAllocated != 32)
        throw core::Error(in.path + ": unsupported BitsAllocated " + std::to_string(in.bitsAllocated));
    if (in.bitsStored == 0 || in.bitsStored > in.bitsAllocated || in.highBit >= in.bitsAllocated)
        throw core::Error(in.path + ": inconsistent BitsStored/HighBit");
    DcmDataset* ds = impl_->dataset(in);
    DcmElement* element = nullptr;
    if (ds->findAndGetElement(DCM_PixelData, element).bad() || !element)
        throw core::Error(in.path + ": pixel data is missing (truncated file?)");
    // A damaged file can hold (7FE0,0010) with a VR DCMTK does not parse into DcmPixelData
    // (the fuzzer found one): refuse it rather than cast blindly.
    if (element->ident() != EVR_PixelData)
        throw core::Error(in.path + ": pixel data has an unexpected encoding (VR " +
                          std::string(DcmVR(element->getVR()).getVRName()) + ")");
    auto* pd = OFstatic_cast(DcmPixelData*, element);
    const E_TransferSyntax xfer = ds->getOriginalXfer();
    const std::size_t pixels = std::size_t(in.rows) * in.columns;
    if (isJpeg2000(xfer)) {
        decodeJpeg2000(pd, xfer, in, frame, out);
    } else if (xfer == EXS_RLELossless) {
        const auto stream = frameFragments(pd, xfer, in, frame, "RLE");
        std::vector<std::uint8_t> bytes;
        const int width = in.bitsAllocated / 8;
        RleDecoder::decode(stream.data(), stream.size(), pixels, width, bytes, in.path);
        out.resize(pixels);
        for (std::size_t i = 0; i < pixels; ++i) {
            std::uint32_t v = 0;
            for (int b = width; b-- > 0;) v = (v << 8) | bytes[i * std::size_t(width) + std::size_t(b)];
            out[i] = std::int32_t(v);
        }
    } else {  // DCMTK: native, deflate, JPEG, JPEG-LS
        Uint32 frameSize = 0;
        if (pd->getUncompressedFrameSize(ds, frameSize).bad() || frameSize < pixels * (in.bitsAllocated / 8))
            throw core::Error(in.path + ": cannot size the pixel data");
        // Hostile headers must not make us allocate gigabytes: native data must really be there,
        // and no frame may exceed 1 GiB.
        if (frameSize > (1u << 30)) throw core::Error(in.path + ": frame of " + std::to_string(frameSize) + " bytes is too large");
        if (!DcmXfer(xfer).isEncapsulated() && std::uint64_t(pd->getLength()) < std::uint64_t(frameSize) * (frame + 1))
            throw core::Error(in.path + ": pixel data is shorter than its header promises (truncated file?)");
        std::vector<std::uint8_t> buf(frameSize + (frameSize & 1));
        Uint32 startFragment = 0;
        OFString colourModel;
        const OFCondition st = pd->getUncompressedFrame(ds, frame, startFragment, buf.data(), Uint32(buf.size()),
                                                        colourModel);
        if (st.bad()) {
            const char* name = DcmXfer(xfer).getXferName();
            throw core::Error(in.path + ": pixel data does not decode (" + std::string(st.text()) + ", " + name + ")");
        }
        out.resize(pixels);
        const bool full = in.bitsStored == in.bitsAllocated && in.highBit + 1 == in.bitsAllocated;
        const bool sgn = in.pixelRepresentation == 1;
        if (in.bitsAllocated == 8) {
            for (std::size_t i = 0; i < pixels; ++i) out[i] = full && sgn ? std::int8_t(buf[i]) : buf[i];
        } else if (in.bitsAllocated == 16) {
            // The common case (all 16 bits used) converts in one pass the compiler vectorises.
            if (full && sgn) {
                for (std::size_t i = 0; i < pixels; ++i) {
                    std::int16_t v;
                    std::memcpy(&v, buf.data() + 2 * i, 2);
                    out[i] = v;
                }
            } else {
                for (std::size_t i = 0; i < pixels; ++i) {
                    std::uint16_t v;
                    std::memcpy(&v, buf.data() + 2 * i, 2);
                    out[i] = v;
                }
            }
        } else {
            // Big-endian 32-bit data comes as OW: DCMTK puts each 16-bit word in this machine's
            // order, which leaves a value's two words the wrong way round (pydicom's decode of
            // rtdose_expb_1frame.dcm found it).
            const bool wordsSwapped = DcmXfer(xfer).isBigEndian() && element->getVR() == EVR_OW;
            for (std::size_t i = 0; i < pixels; ++i) {
                std::uint32_t v;
                std::memcpy(&v, buf.data() + 4 * i, 4);
                if (wordsSwapped) v = (v << 16) | (v >> 16);
                out[i] = std::int32_t(v);
            }
        }
        if (full) return;
    }
    // Mask to BitsStored (at HighBit) and sign-extend signed data.
    const int shift = in.highBit + 1 - in.bitsStored;
    if (in.bitsStored < 32) {
        const std::uint32_t mask = (1u << in.bitsStored) - 1u;
        const std::uint32_t sign = 1u << (in.bitsStored - 1);
        for (auto& v : out) {
            std::uint32_t u = (std::uint32_t(v) >> (shift > 0 ? shift : 0)) & mask;
            if (in.pixelRepresentation == 1 && (u & sign)) u |= ~mask;
            v = std::int32_t(u);
        }
    }
}

void PixelDecoder::decodeFloatFrame(const DicomInstance& in, std::uint32_t frame, std::vector<std::int32_t>& out) {
    DcmDataset* ds = impl_->dataset(in);
    const std::size_t pixels = std::size_t(in.rows) * in.columns;
    const std::size_t first = pixels * frame;
    out.resize(pixels);
    unsigned long count = 0;
    std::vector<float> converted;  // a double frame as the float32 it is stored as
    const float* floats = nullptr;
    if (in.floatPixelBits == 32) {
        const Float32* v = nullptr;
        if (ds->findAndGetFloat32Array(DCM_FloatPixelData, v, &count).bad() || !v || count < first + pixels)
            throw core::Error(in.path + ": Float Pixel Data is shorter than its header promises (truncated file?)");
        floats = v + first;
    } else {
        const Float64* v = nullptr;
        if (ds->findAndGetFloat64Array(DCM_DoubleFloatPixelData, v, &count).bad() || !v || count < first + pixels)
            throw core::Error(in.path + ": Double Float Pixel Data is shorter than its header promises (truncated file?)");
        std::size_t beyond = 0;
        converted.resize(pixels);
        for (std::size_t i = 0; i < pixels; ++i) {
            const double d = v[first + i];
            beyond += std::isfinite(d) && std::abs(d) > double(std::numeric_limits<float>::max());
            converted[i] = float(d);
        }
        if (beyond)
            throw core::Error(whatHolds(in, frame) + std::to_string(beyond) +
                              (beyond == 1 ? " value" : " values") + " beyond what a 32-bit float can hold");
        floats = converted.data();
    }
    // A float volume must hold numbers: the octree, the transfer functions and the measurements
    // take every stored value as one (as core::FiniteValueSource does for files).
    if (const std::string what = core::FiniteValueSource::nonFinite(floats, pixels); !what.empty())
        throw core::Error(whatHolds(in, frame) + what + ": Holovox reads only volumes whose every voxel is a number");
    std::memcpy(out.data(), floats, pixels * sizeof(float));  // float bits, read back as floats
}

}  // namespace hvx::dicom
