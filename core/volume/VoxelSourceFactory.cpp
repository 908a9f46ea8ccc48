#include "core/volume/VoxelSourceFactory.h"

#include <algorithm>
#include <filesystem>

#include "core/base/Error.h"
#include "core/volume/AsciiVoxelSource.h"
#include "core/volume/FiniteValueSource.h"
#include "core/volume/InflatedVoxelSource.h"
#include "core/volume/LegacyVtkHeader.h"
#include "core/volume/MetaImageHeader.h"
#include "core/volume/SliceListVoxelSource.h"
#include "core/volume/NiftiVoxelSource.h"
#include "core/volume/NrrdHeader.h"
#include "core/volume/PhantomVoxelSource.h"
#include "core/volume/VolumeChoice.h"
#include "core/volume/VtkImageSource.h"

namespace hvx::core {

std::uint32_t VoxelSourceFactory::volumesIn(const std::string& input) {
    if (NiftiVoxelSource::handles(input)) return NiftiVoxelSource(input).volumes();
    const std::string ext = std::filesystem::path(input).extension().string();
    if (ext == ".nrrd" || ext == ".nhdr") return NrrdHeader::read(input).volumes;
    return 1;
}

std::array<std::uint32_t, 3> VoxelSourceFactory::parseDims(const std::string& text) {
    std::array<std::uint32_t, 3> d{};
    std::size_t pos = 0;
    for (int a = 0; a < 3; ++a) {
        const std::size_t end = a < 2 ? text.find('x', pos) : text.size();
        if (end == std::string::npos || end == pos) throw Error("size '" + text + "' is not of the form XxYxZ");
        const std::string part = text.substr(pos, end - pos);
        if (part.find_first_not_of("0123456789") != std::string::npos || part.size() > 7)
            throw Error("size '" + text + "' is not of the form XxYxZ");
        const unsigned long v = std::stoul(part);
        if (v == 0 || v > (1u << 20)) throw Error("size '" + text + "' has a dimension out of range 1..1048576");
        d[std::size_t(a)] = std::uint32_t(v);
        pos = end + 1;
    }
    return d;
}

std::unique_ptr<VoxelSource> VoxelSourceFactory::open(const std::string& input, const RawVoxelSource::Options& raw,
                                                      std::uint32_t volume) {
    return FiniteValueSource::wrap(openFormat(input, raw, volume));
}

std::unique_ptr<VoxelSource> VoxelSourceFactory::openFormat(const std::string& input, const RawVoxelSource::Options& raw,
                                                            std::uint32_t volume) {
    const std::filesystem::path p(input);
    const std::string ext = p.extension().string();
    const bool fourD = NiftiVoxelSource::handles(input) || ext == ".nrrd" || ext == ".nhdr";
    if (volume > 0 && !fourD)  // never a silent first volume
        throw Error(input + ": holds one volume; a volume other than the first (--volume) is read from 4D NIfTI and NRRD files only");
    if (input.rfind("phantom:", 0) == 0) {
        std::string spec = input.substr(8);
        std::uint64_t seed = 1;
        const auto colon = spec.find(':');
        if (colon != std::string::npos) {
            const std::string s = spec.substr(colon + 1);
            if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18)
                throw Error("phantom seed '" + s + "' is not a number");
            seed = std::stoull(s);
            spec = spec.substr(0, colon);
        }
        return std::make_unique<PhantomVoxelSource>(parseDims(spec), seed);
    }
    if (ext == ".nrrd" || ext == ".nhdr") {
        const NrrdHeader h = NrrdHeader::read(input);
        const bool gzip = h.encoding == "gzip" || h.encoding == "gz";
        const bool text = h.encoding == "ascii" || h.encoding == "text" || h.encoding == "txt";
        if (h.encoding != "raw" && !gzip && !text)
            throw Error(input + ": NRRD encoding '" + h.encoding + "' is not supported (raw, gzip and ascii are)");
        const std::string& data = h.dataPath;
        const VolumeChoice choice{input, h.volumes, volume};
        choice.check();
        if (text && h.volumes > 1)
            throw Error(input + ": a 4-D NRRD in " + h.encoding + " encoding is not read by Holovox (in raw or gzip it is)");
        if (text)  // every value parsed and checked, slab by slab
            return std::make_unique<AsciiVoxelSource>(
                data, RawVoxelSource::described(h.geometry, h.element, false, h.headerBytes, h.warnings, input));
        const std::uint64_t volumeBytes = h.geometry.voxelCount() * elementSize(h.element);
        auto o = RawVoxelSource::described(h.geometry, h.element, h.bigEndian, h.headerBytes, h.warnings, input);
        if (h.volumes > 1) {  // a 4-D file: the volumes one after the other
            o.warnings.push_back(choice.note());
            if (gzip) {
                o.inflatedSkip = volumeBytes * volume;
                o.inflatedTotal = volumeBytes * h.volumes;
            } else {
                std::error_code ec;
                const auto size = std::filesystem::file_size(data, ec);
                const std::uint64_t need = h.headerBytes + volumeBytes * h.volumes;
                if (ec || size != need)
                    throw Error(data + ": " + std::to_string(h.volumes) + " volumes of " + std::to_string(volumeBytes) +
                                " bytes need " + std::to_string(need) + " bytes but the file has " +
                                (ec ? "none that can be read" : std::to_string(size)));
                o.headerBytes += volumeBytes * volume;
                o.trailingBytes = true;
            }
        }
        if (gzip) return std::make_unique<InflatedVoxelSource>(data, o);
        return std::make_unique<RawVoxelSource>(data, o);
    }
    if (NiftiVoxelSource::handles(input)) return std::make_unique<NiftiVoxelSource>(input, volume);
    if (VtkImageSource::isMetaImage(input)) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec)) throw Error(input + ": no such file");
        const MetaImageHeader h = MetaImageHeader::read(input);
        if (h.channels != 1)
            throw Error(input + ": its voxels hold " + std::to_string(h.channels) + " values each (ElementNumberOfChannels), as a "
                        "colour or vector image does; Holovox shows one value per voxel (save one channel as its own image)");
        const auto size = std::filesystem::file_size(h.dataFile, ec);
        if (h.compressed && h.compressedBytes > 0 && !ec && size < h.dataOffset + h.compressedBytes)
            throw Error(h.dataFile + ": truncated: its MetaImage header promises " + std::to_string(h.compressedBytes) +
                        " bytes of compressed data, the file holds " + std::to_string(size - std::min(size, h.dataOffset)));
        if (h.streamReason.empty() && !h.sliceFiles.empty())  // a file per slice, streamed
            return std::make_unique<SliceListVoxelSource>(
                h.sliceFiles, RawVoxelSource::described(h.geometry, h.element, h.bigEndian, 0, h.warnings, input), input);
        if (h.streamReason.empty()) {  // streamed by Holovox: the size of plain data checked
            const auto o = RawVoxelSource::described(h.geometry, h.element, h.bigEndian, h.dataOffset, h.warnings, input);
            if (h.ascii) return std::make_unique<AsciiVoxelSource>(h.dataFile, o);
            if (h.compressed) return std::make_unique<InflatedVoxelSource>(h.dataFile, o);
            return std::make_unique<RawVoxelSource>(h.dataFile, o);
        }
    }
    if (VtkImageSource::isLegacyVtk(input)) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec)) throw Error(input + ": no such file");
        const LegacyVtkHeader h = LegacyVtkHeader::read(input);
        if (h.streamReason.empty()) {  // streamed by Holovox: big-endian, and the file must hold the voxels
            auto o = RawVoxelSource::described(h.geometry, h.element, true, h.dataOffset, h.warnings, input);
            o.trailingBytes = true;  // other attributes may follow
            if (h.ascii) return std::make_unique<AsciiVoxelSource>(input, o);
            return std::make_unique<RawVoxelSource>(input, o);
        }
    }
    if (VtkImageSource::handles(input)) return std::make_unique<VtkImageSource>(input);
    if (raw.dims[0] == 0) {
        std::error_code ec;
        if (!std::filesystem::exists(p, ec)) throw Error(input + ": no such file");
        throw Error(input + ": unknown file type (raw files need --dims XxYxZ and --type)");
    }
    return std::make_unique<RawVoxelSource>(input, raw);
}

}  // namespace hvx::core
