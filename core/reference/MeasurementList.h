#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/reference/RegionStatistics.h"

namespace hvx::core {

/// One measurement a reader made: a distance between two points, an angle at a vertex between
/// two arms, or a region with its statistics (from level 0, see RegionStatistics). Points are
/// patient coordinates (LPS mm).
struct Measurement {
    enum class Kind { Distance, Region, Angle };
    Kind kind = Kind::Distance;
    std::string label;                  ///< "M1", "M2", … given by the list
    std::string view;                   ///< where it was made: "axial", "coronal", "sagittal", "3D"
    glm::dvec3 a{0.0}, b{0.0};          ///< a distance's ends; an angle's first arm's end and its vertex
    glm::dvec3 c{0.0};                  ///< an angle's second arm's end
    std::optional<MeasureRegion> region;
    std::optional<RegionStatistics> stats;

    /// A distance's length in mm (0 for the other kinds).
    double lengthMm() const;
    /// An angle's size in degrees, 0 to 180, in the plane of its three points (0 for the other
    /// kinds, and for an arm of no length).
    double angleDegrees() const;
    /// "distance", "angle" or "region".
    const char* kindName() const;
};

/// Whose measurements they are, for the exports: the patient and the DICOM identities of the
/// series measured (empty when the volume did not come from DICOM), and the volume file.
struct MeasurementSource {
    std::string patientName, patientId, studyUid, seriesUid, volume;
    /// The volume's source gave no voxel spacing: lengths and areas are in units of an assumed
    /// 1 mm, not millimetres, and the exports say so.
    bool spacingAssumed = false;
};

/// The measurements of one volume, in the order they were made, each with a label of its own
/// that deleting others does not change; exported as CSV (one row each, RFC 4180 quoting) or
/// JSON (the source, then the measurements), and read back from that JSON (a session).
///
/// Threading: not synchronised; one owner.
class MeasurementList {
public:
    /// Adds a measurement and returns it with its new label.
    const Measurement& add(Measurement m);
    /// Puts `m` in place of the measurement with its label (an edit: same label, same place in
    /// the list); false when there is none.
    bool replace(const Measurement& m);
    /// Removes the measurement with this label; false when there is none.
    bool remove(const std::string& label);
    void clear();
    const std::vector<Measurement>& items() const { return items_; }

    std::string toCsv(const MeasurementSource& source) const;
    std::string toJson(const MeasurementSource& source) const;
    /// The list toJson() wrote; throws core::Error naming what is wrong with any other text.
    static MeasurementList fromJson(const std::string& json);

private:
    std::vector<Measurement> items_;
    int next_ = 1;
};

}  // namespace hvx::core
