#pragma once
#include <QObject>
#include <QString>

#include <memory>
#include <vector>

#include "core/octree/OctreeReader.h"
#include "dicom/StudyDatabase.h"

namespace hvx::ui {

class JobManager;

/// The time points of a 4D series opened on one of them: opens those whose octree exists and
/// builds the others in the background, one job at a time, starting after the one on screen
/// (the next to be played first). Each is checked against the one on screen: another grid or
/// rescale is refused with the difference named, so no time point is ever drawn in another
/// place. Dropped (its jobs' results ignored) when destroyed.
///
/// Threading: GUI thread only; the builds run on the job manager's threads.
class TimeSeriesLoader : public QObject {
    Q_OBJECT
public:
    /// `volumes` as the database numbers them; `current` the index among them shown, whose
    /// reader is `shown`.
    TimeSeriesLoader(JobManager& jobs, QString databasePath, QString seriesUid, std::vector<dicom::VolumeRow> volumes,
                     int current, std::shared_ptr<const core::OctreeReader> shown, QObject* parent = nullptr);
    /// Opens the time points that have octrees (ready() for each) and starts building the rest.
    void start();
    const QString& seriesUid() const { return seriesUid_; }

signals:
    void ready(int index, std::shared_ptr<const core::OctreeReader> reader);
    void refused(int index, const QString& why);

private:
    void offer(int index, const QString& octreePath);
    void buildNext();

    JobManager& jobs_;
    QString databasePath_, seriesUid_;
    std::vector<dicom::VolumeRow> volumes_;
    int current_;
    std::shared_ptr<const core::OctreeReader> shown_;
    std::vector<int> toBuild_;
};

}  // namespace hvx::ui
