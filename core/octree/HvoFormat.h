#pragma once
#include <bit>
#include <cstdint>
#include <type_traits>

/// On-disk layout of the .hvo multiresolution brick octree (version 1).
///
/// File := FileHeader (512 bytes) | brick payloads (any order) | node table (NodeRecord[nodeCount])
/// All integers are little endian. Node 0 is the root; nodes are stored level by level from the
/// root (breadth first), and the children of a node are contiguous, in octant order
/// (bit 0 = +x, bit 1 = +y, bit 2 = +z). A node at level l with grid coordinate (x, y, z)
/// covers level-l voxels [x*B, (x+1)*B) along i (likewise j, k), where level l is the volume
/// box-filtered l times by 2 (dims_l = ceil(dims_{l-1} / 2)). Each payload is a cube of
/// E = B + 2*border samples starting at level voxel x*B - border, with coordinates clamped to
/// the volume: neighbour samples are replicated so a brick never needs another brick.
/// Version 2 (FileSplitVoxels) holds split-voxels instead, over the grid of cells (FileHeader::split).
namespace hvx::core::hvo {

static_assert(std::endian::native == std::endian::little, ".hvo I/O assumes a little-endian host");

inline constexpr char kMagic[8] = {'H', 'O', 'L', 'O', 'V', 'O', 'X', '\0'};
inline constexpr std::uint32_t kVersion = 1;
/// Split-voxel octrees (thesis ch. 4): nodes hold split-voxels, not samples. Readers of
/// version 1 refuse them ("unsupported version 2") rather than read their cells as voxels.
inline constexpr std::uint32_t kVersionSplitVoxels = 2;
inline constexpr std::uint32_t kNoNode = 0xffffffffu;

/// Lossless per-brick compression.
enum class Codec : std::uint32_t { None = 0, Zstd = 1, Lz4 = 2 };

/// FileHeader::flags.
enum FileFlags : std::uint32_t {
    FileLabels = 1u,
    FileLossy8 = 2u,
    FileEmptyThreshold = 4u,
    FileShuffled = 8u,  ///< multi-byte payloads are byte-shuffled into planes before compression
    FileMonochrome1 = 16u,  ///< display inverted (DICOM MONOCHROME1)
    FileSpacingAssumed = 32u,      ///< VolumeGeometry::spacingAssumed
    FileOrientationAssumed = 64u,  ///< VolumeGeometry::orientationAssumed
    FileSplitVoxels = 128u,        ///< version 2: payloads are split-voxels (see FileHeader::split)
    FileNotHounsfield = 256u,      ///< VolumeGeometry::notHounsfield
};
/// NodeRecord::flags.
enum NodeFlags : std::uint32_t { NodeEmpty = 1u, NodeLossy8 = 2u };

struct FileHeader {
    char magic[8];
    std::uint32_t version;
    std::uint32_t headerSize;
    std::uint32_t dims[3];
    std::uint32_t brickSize;
    std::uint32_t border;
    std::uint32_t levelCount;
    std::uint32_t scalarType;
    std::uint32_t codec;
    std::uint32_t flags;
    std::uint32_t complete;  ///< 1 only once the node table is written
    double spacing[3];
    double origin[3];
    double direction[9];  ///< column-major: direction[3*c + r] is row r of axis c
    double rescaleSlope;
    double rescaleIntercept;
    double valueMin;
    double valueMax;
    double emptyBelow;     ///< stored-value threshold (valid with FileEmptyThreshold)
    double lossyRmsError;  ///< RMS error of 8-bit quantisation over leaf interiors
    double lossyMaxError;  ///< max abs error of 8-bit quantisation
    char modality[16];
    std::uint64_t nodeCount;
    std::uint64_t nodeTableOffset;
    std::uint64_t nodeTableChecksum;  ///< XXH3-64 of the node table
    std::uint64_t fileSize;
    std::uint64_t payloadBytes;  ///< sum of compressed payload sizes
    std::uint64_t rawBrickBytes; ///< sum of uncompressed sizes of stored payloads
    /// The source's display windows (DICOM presets), unused entries with width 0. Written in
    /// what older versions kept as reserved zeros, so their files read as "no window".
    struct Window {
        double centre;
        double width;
        char name[16];
    } windows[4];
    /// The DICOM Frame of Reference UID (up to 64 characters, zero padded; all zeros when the
    /// source had none). Written in what older versions kept as reserved zeros.
    char frameOfReferenceUid[64];
    /// Split-voxel files: dims, spacing and origin above describe the grid of cells (cell (0,0,0)'s
    /// centre at the origin, cells n voxels apart), so the octree's layout and traversal are the
    /// usual ones over it; this is the source volume the cells stand for. A payload is
    /// brickSize³ cells (no border), each SplitVoxel::encodedSize bytes. Zeros in version 1.
    struct Split {
        std::uint32_t sourceDims[3];
        std::uint16_t n;        ///< voxels per cell edge at level 0
        std::uint16_t overlap;  ///< M, neighbour layers each fit saw
    } split;
    std::uint64_t headerChecksum;  ///< XXH3-64 of the first 504 bytes
};
static_assert(sizeof(FileHeader) == 512);
static_assert(std::is_trivially_copyable_v<FileHeader>);

struct NodeRecord {
    std::uint64_t payloadOffset;  ///< 0 when the node stores no payload (empty)
    std::uint64_t checksum;       ///< XXH3-64 of the compressed payload
    std::uint32_t payloadSize;    ///< compressed bytes
    std::uint32_t flags;          ///< NodeFlags
    std::uint32_t parent;         ///< kNoNode for the root
    std::uint32_t firstChild;     ///< kNoNode for leaves
    std::uint16_t x, y, z;        ///< grid coordinate at this node's level
    std::uint8_t level;           ///< 0 = leaves (full resolution)
    std::uint8_t childMask;       ///< bit o set when child in octant o exists
    float minValue;  ///< smallest stored value in the brick and all its descendants
    float maxValue;  ///< largest stored value in the brick and all its descendants
    float quantMin;  ///< lossy 8-bit nodes: the value byte 0 stands for
    float quantMax;  ///< lossy 8-bit nodes: the value byte 255 stands for
    std::uint32_t reserved[2];
};
static_assert(sizeof(NodeRecord) == 64);
static_assert(std::is_trivially_copyable_v<NodeRecord>);

}  // namespace hvx::core::hvo
