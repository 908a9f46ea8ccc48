#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hvx::core {

/// The colours and names of a label map's classes. Loads the tables readers already have:
/// ITK-SNAP label descriptions, FreeSurfer's colour LUT, 3D Slicer's colour tables (.ctbl or
/// exported .txt) and mricron's binary .lut. Label 0 is the background in every one of them
/// and is never drawn.
///
/// Threading: a value type; const methods are safe from any thread.
class LabelTable {
public:
    struct Entry {
        std::string name;
        std::array<std::uint8_t, 4> rgba{0, 0, 0, 255};  ///< alpha: the label's own opacity
        bool visible = true;
    };
    /// Reads `path`, telling the format from its content (and .lut / .ctbl names). Throws
    /// core::Error naming the file and the line: unreadable lines, colours outside 0-255, an
    /// opacity outside its range, a label given twice, a table with no label.
    static LabelTable load(const std::string& path);
    /// Where a label map's own table is kept beside its octree (written when the octree is
    /// built from a DICOM SEG): "<octree>.ctbl".
    static std::string sidecarPath(const std::string& octreePath) { return octreePath + ".ctbl"; }
    /// The table a label map (octree at `octreePath`, values valueMin..valueMax) is drawn with:
    /// `lut` when given, else the table kept beside the octree (sidecarPath), else generated
    /// colours for every value of its range.
    static LabelTable forLabelMap(const std::string& octreePath, double valueMin, double valueMax,
                                  const std::string& lut = {});
    /// Distinct colours for `labels` (hues a golden angle apart), named "label N".
    static LabelTable generated(const std::vector<int>& labels);

    /// The entry of `label`, or nullptr when the table has none (label 0: always nullptr).
    const Entry* find(int label) const;
    /// Gives labels the table misses a generated colour; returns them (ascending). The caller
    /// says so: a colour the user did not choose must not pass unremarked.
    std::vector<int> addMissing(const std::vector<int>& labels);
    void setVisible(int label, bool visible);
    /// Sets a label's entry (a table made from a DICOM SEG's segments); label 0 is ignored.
    void set(int label, Entry entry);
    /// The table in 3D Slicer's colour-table format ("index name R G B A", names with their
    /// spaces as underscores), which load() reads back.
    std::string toSlicerTable() const;
    const std::map<int, Entry>& entries() const { return entries_; }
    /// The format read, for messages ("ITK-SNAP label descriptions").
    const std::string& format() const { return format_; }

private:
    std::map<int, Entry> entries_;
    std::string format_;
};

}  // namespace hvx::core
