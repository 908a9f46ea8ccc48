#include "ui/TimeSeriesLoader.h"

#include <QFileInfo>
#include <QPointer>

#include "core/base/Error.h"
#include "dicom/SeriesOctree.h"
#include "ui/JobManager.h"

namespace hvx::ui {

TimeSeriesLoader::TimeSeriesLoader(JobManager& jobs, QString databasePath, QString seriesUid,
                                   std::vector<dicom::VolumeRow> volumes, int current,
                                   std::shared_ptr<const core::OctreeReader> shown, QObject* parent)
    : QObject(parent), jobs_(jobs), databasePath_(std::move(databasePath)), seriesUid_(std::move(seriesUid)),
      volumes_(std::move(volumes)), current_(current), shown_(std::move(shown)) {}

void TimeSeriesLoader::start() {
    const int n = int(volumes_.size());
    for (int k = 1; k < n; ++k) {  // after the one on screen, in play order
        const int i = (current_ + k) % n;
        const auto& path = volumes_[std::size_t(i)].octreePath;
        if (!path.empty() && QFileInfo::exists(QString::fromStdString(path))) offer(i, QString::fromStdString(path));
        else toBuild_.push_back(i);
    }
    buildNext();
}

void TimeSeriesLoader::offer(int index, const QString& octreePath) {
    try {
        std::shared_ptr<const core::OctreeReader> reader = core::OctreeReader::open(octreePath.toStdString());
        const std::string difference = shown_->geometry().gridDifference(reader->geometry());
        if (!difference.empty()) {
            emit refused(index, tr("its grid differs from the one shown (%1)").arg(QString::fromStdString(difference)));
            return;
        }
        emit ready(index, std::move(reader));
    } catch (const core::Error& e) {
        emit refused(index, QString::fromStdString(e.what()));
    }
}

void TimeSeriesLoader::buildNext() {
    if (toBuild_.empty()) return;
    const int index = toBuild_.front();
    toBuild_.erase(toBuild_.begin());
    const std::string db = databasePath_.toStdString(), uid = seriesUid_.toStdString();
    const int number = volumes_[std::size_t(index)].number;
    QPointer<TimeSeriesLoader> self(this);
    const int id = jobs_.start(
        tr("Build octree: time point %1 (%2)").arg(number).arg(QString::fromStdString(volumes_[std::size_t(index)].varying)),
        [db, uid, number](core::JobContext& job) {
            dicom::StudyDatabase database(db);
            std::vector<std::string> warnings;
            return QString::fromStdString(dicom::SeriesOctree::build(database, uid, job, &warnings, {}, number));
        },
        [self, index](const QString& path) {
            if (!self) return;
            self->offer(index, path);
        });
    // Whatever its end (done, failed, cancelled), the next one starts; a failure is said.
    auto once = std::make_shared<QMetaObject::Connection>();
    *once = connect(&jobs_, &JobManager::finished, this, [this, once, id, index](int done, const QString& state, const QString& message) {
        if (done != id) return;
        QObject::disconnect(*once);
        if (state != "done") emit refused(index, state == "failed" ? message : tr("its octree build was %1").arg(state));
        buildNext();
    });
}

}  // namespace hvx::ui
