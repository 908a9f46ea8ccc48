#include "dicom/RetrieveJob.h"

#include <filesystem>
#include <future>
#include <map>
#include <mutex>

#include "core/base/Error.h"
#include "core/octree/OctreeBuilder.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/StorageServer.h"
#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace hvx::dicom {

RetrieveJob::RetrieveJob(PacsSettings settings, PacsNode node, StudyDatabase& db, std::string octreeDir)
    : settings_(std::move(settings)), node_(std::move(node)), db_(db), octreeDir_(std::move(octreeDir)) {}

std::vector<SeriesRetrieveStatus> RetrieveJob::run(const std::string& studyUid, const std::string& seriesUid,
                                                   bool buildOctrees, core::JobContext& job,
                                                   const std::function<void(const SeriesRetrieveStatus&)>& onUpdate) {
    PacsClient client(settings_.local, node_);
    std::vector<SeriesRetrieveStatus> series;
    if (!seriesUid.empty()) {
        series.push_back({seriesUid, "", {}, false, "", ""});
    } else {
        QueryKeys keys;
        keys.studyUid = studyUid;
        client.find(QueryLevel::Series, keys, [&](const QueryResult& r) {
            series.push_back({r.seriesUid, r.modality + " #" + std::to_string(r.seriesNumber) + " " + r.seriesDescription,
                              {}, false, "", ""});
            return true;
        });
        if (series.empty()) throw core::Error("study " + studyUid + " has no series on PACS '" + node_.name + "'");
    }

    std::mutex mutex;  // guards db_, received, series[] updates from the server and build threads
    std::map<std::string, std::vector<DicomInstance>> received;
    auto onStored = [&](const DicomInstance& in) {
        std::lock_guard lock(mutex);
        received[in.seriesInstanceUid].push_back(in);
    };
    std::unique_ptr<StorageServer> server;
    if (node_.retrieve == RetrieveMethod::Move) {
        std::vector<std::string> allowed = settings_.local.allowedCallers;
        allowed.push_back(node_.aeTitle);
        server = std::make_unique<StorageServer>(settings_.local, allowed, onStored);
        server->start();
    }

    std::future<void> building = std::async(std::launch::deferred, [] {});
    auto buildSeries = [&, buildOctrees](std::size_t index) {
        std::vector<DicomInstance> instances;
        {
            std::lock_guard lock(mutex);
            instances = received[series[index].seriesUid];
            db_.addInstances(instances);
        }
        if (!buildOctrees || instances.empty()) return;
        try {
            std::vector<std::string> notes;
            auto volumes = SeriesAssembler::assemble(instances, notes);
            if (volumes.empty()) return;
            std::size_t pick = 0;
            for (std::size_t i = 1; i < volumes.size(); ++i)
                if (volumes[i].slices.size() > volumes[pick].slices.size()) pick = i;
            std::filesystem::create_directories(octreeDir_);
            const std::string out =
                (std::filesystem::path(octreeDir_) / (UidPath::component(series[index].seriesUid) + ".hvo")).string();
            DicomSeriesSource source(volumes[pick]);
            core::JobContext buildJob;
            core::OctreeBuilder(core::BuildOptions{}).build(source, out, buildJob);
            std::lock_guard lock(mutex);
            db_.setSeriesOctree(series[index].seriesUid, out);
            series[index].octreePath = out;
        } catch (const core::Error& e) {
            std::lock_guard lock(mutex);
            series[index].error = e.what();
        }
        if (onUpdate) onUpdate(series[index]);
    };

    std::size_t failures = 0;
    for (std::size_t i = 0; i < series.size(); ++i) {
        job.throwIfCancelled();
        auto& s = series[i];
        auto progress = [&, i](const RetrieveProgress& p) {
            series[i].progress = p;
            const int total = p.remaining + p.completed + p.failed + p.warning;
            job.report((double(i) + (total ? double(p.completed + p.failed + p.warning) / total : 0.0)) /
                           double(series.size()),
                       "retrieving series " + std::to_string(i + 1) + " of " + std::to_string(series.size()));
            if (onUpdate) onUpdate(series[i]);
        };
        try {
            if (node_.retrieve == RetrieveMethod::Get)
                client.get(studyUid, s.seriesUid, settings_.local.storageDir, onStored, progress);
            else
                client.move(studyUid, s.seriesUid, settings_.local.aeTitle, progress);
            s.retrieved = true;
        } catch (const core::Error& e) {
            s.error = e.what();
            ++failures;
            if (onUpdate) onUpdate(s);
            continue;
        }
        if (onUpdate) onUpdate(s);
        // Build this series while the next one arrives.
        building.wait();
        building = std::async(std::launch::async, buildSeries, i);
    }
    building.wait();
    if (server) server->stop();
    job.report(1.0, "done");
    if (failures == series.size()) throw core::Error(series.front().error);
    return series;
}

}  // namespace hvx::dicom
