#include "dicom/RetrieveJob.h"

#include <algorithm>

#include <filesystem>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <thread>
#include <map>
#include <mutex>

#include "core/base/Error.h"
#include "core/octree/OctreeBuilder.h"
#include "dicom/DicomHeaderReader.h"
#include "dicom/DicomSeriesSource.h"
#include "dicom/SeriesAssembler.h"
#include "dicom/SeriesOctree.h"
#include "dicom/StorageOwners.h"
#include "dicom/StorageServer.h"
#include "dicom/StudyDatabase.h"
#include "dicom/UidPath.h"

namespace hvx::dicom {

namespace {
/// The header of a file that is there and is DICOM (a file deleted or damaged since it was
/// indexed is fetched again).
bool readable(const std::string& path, DicomInstance& in) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;
    try {
        return DicomHeaderReader::read(path, in) == DicomHeaderReader::Kind::Dicom;
    } catch (const std::exception&) {
        return false;
    }
}
}  // namespace

RetrieveJob::RetrieveJob(PacsSettings settings, PacsNode node, StudyDatabase& db, std::string octreeDir)
    : settings_(std::move(settings)), node_(std::move(node)), db_(db), octreeDir_(std::move(octreeDir)) {}

std::vector<SeriesRetrieveStatus> RetrieveJob::run(const std::string& studyUid, const std::string& seriesUid,
                                                   bool buildOctrees, core::JobContext& job,
                                                   const std::function<void(const SeriesRetrieveStatus&)>& onUpdate) {
    PacsClient client(settings_.local, node_);
    client.cancelWith(job);
    StorageOwners::add(settings_.local.storageDir, db_.path());  // what it receives, this database indexes
    std::vector<SeriesRetrieveStatus> series;
    // The series, with the description and instance count the PACS gives at series level.
    QueryKeys keys;
    keys.studyUid = studyUid;
    keys.seriesUid = seriesUid;
    try {
        client.find(QueryLevel::Series, keys, [&](const QueryResult& r) {
            if (!seriesUid.empty() && r.seriesUid != seriesUid) return true;  // a PACS that ignored the key
            SeriesRetrieveStatus st;
            st.seriesUid = r.seriesUid;
            st.description = r.modality + " #" + std::to_string(r.seriesNumber) + " " + r.seriesDescription;
            st.countOnPacs = r.numberOfInstances;
            series.push_back(st);
            return true;
        });
    } catch (const core::Error&) {
        if (seriesUid.empty()) throw;  // without the series list there is nothing to retrieve
    }
    if (!seriesUid.empty() && series.empty()) {
        SeriesRetrieveStatus st;
        st.seriesUid = seriesUid;
        series.push_back(st);
    }
    if (series.empty()) throw core::Error("study " + studyUid + " has no series on PACS '" + node_.name + "'");

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
        server->requireHost(node_.aeTitle, node_.host);
        server->start();
    }

    std::mutex updateMutex;  // onUpdate is called from the workers and the builder, one at a time
    auto update = [&](const SeriesRetrieveStatus& s) {
        std::lock_guard lock(updateMutex);
        if (onUpdate) onUpdate(s);
    };
    auto buildSeries = [&, buildOctrees](std::size_t index) {
        // Runs on its own thread: every failure is kept in the series' status, none is lost.
        try {
            std::vector<DicomInstance> instances;
            StudyDatabase::ImportStats stats;
            {
                std::lock_guard lock(mutex);
                instances = received[series[index].seriesUid];
                stats = db_.addInstances(instances);
            }
            // A UID collision (images naming a study, series or instance filed under another
            // patient, study or series) refuses those images and fails the series, never mixed.
            if (!stats.conflicts.empty()) {
                std::string why;
                for (const auto& c : stats.conflicts) why += (why.empty() ? "" : "; ") + c;
                throw core::Error(why);
            }
            if (!buildOctrees || instances.empty() || !series[index].retrieved) return;
            std::vector<std::string> notes;
            auto volumes = SeriesAssembler::assemble(instances, notes);
            // The whole series where a retrieve before this one brought part of it; its files
            // are read again without the lock, which the receiver needs for every instance.
            volumes = SeriesOctree::recordVolumes(db_, volumes, instances, &mutex);
            if (volumes.empty()) return;
            std::size_t pick = 0;
            for (std::size_t i = 1; i < volumes.size(); ++i)
                if (volumes[i].slices.size() > volumes[pick].slices.size()) pick = i;
            std::filesystem::create_directories(octreeDir_);
            const std::string out =
                (std::filesystem::path(octreeDir_) / (UidPath::component(series[index].seriesUid) + ".hvo")).string();
            DicomSeriesSource source(volumes[pick]);
            core::JobContext buildJob(job, {});  // cancelling the retrieve cancels its builds
            core::OctreeBuilder(core::BuildOptions{}).build(source, out, buildJob);
            std::lock_guard lock(mutex);
            SeriesOctree::record(db_, series[index].seriesUid, out);  // throws (and deletes it) when removed meanwhile
            series[index].octreePath = out;
        } catch (const std::exception& e) {
            std::lock_guard lock(mutex);
            series[index].error = e.what();
        }
        update(series[index]);
    };

    // Several series at once, each worker over its own associations; one builder thread builds
    // each finished series' octree while the transfers go on.
    std::mutex queueMutex;
    std::condition_variable queued;
    std::deque<std::size_t> toBuild;
    bool fetching = true;
    std::thread builder([&] {
        for (;;) {
            std::unique_lock lock(queueMutex);
            queued.wait(lock, [&] { return !toBuild.empty() || !fetching; });
            if (toBuild.empty()) return;
            const std::size_t i = toBuild.front();
            toBuild.pop_front();
            lock.unlock();
            buildSeries(i);
        }
    });
    std::vector<double> done(series.size(), 0.0);
    std::atomic<std::size_t> next{0}, failures{0};
    std::atomic<bool> cancelled{false};
    auto work = [&] {
        PacsClient own(settings_.local, node_);
        own.cancelWith(job);
        for (std::size_t i = next++; i < series.size() && !cancelled; i = next++) {
            try {
                if (fetch(own, studyUid, series[i], mutex, received, onStored, [&, i](const RetrieveProgress& p) {
                        series[i].progress = p;
                        const int total = p.remaining + p.completed + p.failed + p.warning;
                        double sum = 0;
                        {
                            std::lock_guard lock(mutex);
                            done[i] = total ? double(p.completed + p.failed + p.warning) / total : 0.0;
                            for (double d : done) sum += d;
                        }
                        job.report(sum / double(series.size()),
                                   "retrieving " + std::to_string(series.size()) + " series");
                        update(series[i]);
                    }))
                    update(series[i]);
                else
                    ++failures;
            } catch (const core::Cancelled&) {
                cancelled = true;
                break;
            }
            {
                std::lock_guard lock(queueMutex);
                toBuild.push_back(i);  // a failed series is built too: what arrived is indexed, never lost
            }
            queued.notify_one();
        }
    };
    const int workers = std::min<int>(std::max(1, settings_.local.parallelAssociations), int(series.size()));
    std::vector<std::thread> threads;
    for (int w = 0; w < workers; ++w) threads.emplace_back(work);
    for (auto& t : threads) t.join();
    {
        std::lock_guard lock(queueMutex);
        fetching = false;
    }
    queued.notify_one();
    builder.join();  // a cancelled retrieve's builds see the same cancellation
    if (server) server->stop();
    if (cancelled || job.cancelled()) throw core::Cancelled();
    job.report(1.0, "done");
    if (failures == series.size()) throw core::Error(series.front().error);
    return series;
}

bool RetrieveJob::fetch(PacsClient& client, const std::string& studyUid, SeriesRetrieveStatus& s, std::mutex& mutex,
                        std::map<std::string, std::vector<DicomInstance>>& received,
                        const std::function<void(const DicomInstance&)>& onStored,
                        const std::function<void(const RetrieveProgress&)>& progress) {
    try {
        // What the PACS has, and which of it is here already (indexed, and its file there).
        std::map<std::string, std::string> indexed;
        {
            std::lock_guard lock(mutex);
            indexed = db_.onlineInstancesOfSeries(s.seriesUid);
        }
        // Nothing of it here and the PACS gave its count with the series: the count is the
        // completeness check, and the instance list (slow on some archives) is not needed.
        const std::vector<std::string> onPacs =
            indexed.empty() && s.countOnPacs > 0 ? std::vector<std::string>{} : instancesOnPacs(client, studyUid, s.seriesUid);
        std::vector<std::string> missing;
        std::vector<DicomInstance> here;
        for (const auto& sop : onPacs) {
            const auto it = indexed.find(sop);
            DicomInstance in;
            if (it != indexed.end() && readable(it->second, in) && in.sopInstanceUid == sop)
                here.push_back(in);
            else
                missing.push_back(sop);
        }
        s.alreadyHere = int(here.size());
        {
            std::lock_guard lock(mutex);
            received[s.seriesUid] = here;
        }
        // Only what is missing when part is here; the whole series otherwise.
        const std::vector<std::string> only = here.empty() ? std::vector<std::string>{} : missing;
        if (here.empty() || !missing.empty()) {
            // A PACS that limits how many associations it serves is given time (the other
            // workers' associations end), then the series fails with its reason.
            for (int attempt = 0;; ++attempt) {
                try {
                    if (node_.retrieve == RetrieveMethod::Get)
                        client.get(studyUid, s.seriesUid, settings_.local.storageDir, onStored, progress, only);
                    else
                        client.move(studyUid, s.seriesUid, settings_.local.aeTitle, progress, only);
                    break;
                } catch (const AssociationRejected&) {
                    if (attempt >= 4) throw;
                    std::this_thread::sleep_for(std::chrono::milliseconds(250 << attempt));
                }
            }
        }
        const std::size_t expected =
            !onPacs.empty()     ? onPacs.size()
            : s.countOnPacs > 0 ? std::size_t(s.countOnPacs)
                                : std::size_t(std::max(0, s.progress.completed + s.progress.failed + s.progress.warning));
        checkComplete(s, expected, [&] {
            std::lock_guard lock(mutex);
            return received[s.seriesUid].size();
        }());
        s.retrieved = true;
        return true;
    } catch (const core::Cancelled&) {
        throw;
    } catch (const std::exception& e) {
        s.error = e.what();
        return false;
    }
}

std::vector<std::string> RetrieveJob::instancesOnPacs(PacsClient& client, const std::string& studyUid,
                                                     const std::string& seriesUid) const {
    std::vector<std::string> sops;
    try {
        QueryKeys keys;
        keys.studyUid = studyUid;
        keys.seriesUid = seriesUid;
        client.find(QueryLevel::Image, keys, [&](const QueryResult& r) {
            if (!r.sopInstanceUid.empty()) sops.push_back(r.sopInstanceUid);
            return true;
        });
    } catch (const core::Error&) {
        sops.clear();  // a PACS without image-level queries: the sub-operation counts will do
    }
    return sops;
}

void RetrieveJob::checkComplete(const SeriesRetrieveStatus& s, std::size_t expected, std::size_t arrived) const {
    if (node_.retrieve == RetrieveMethod::Move && arrived == 0 && expected > 0)
        throw core::Error("series " + s.description + ": the PACS reported the C-MOVE done but none of its " +
                          std::to_string(expected) + " instances reached Holovox's storage SCP; check the PACS's entry "
                          "for AE title '" + settings_.local.aeTitle + "' (it must point at this computer and port " +
                          std::to_string(settings_.local.port) + ")");
    if (arrived < expected)
        throw core::Error("series " + s.description + " is partial: " + std::to_string(arrived) + " of " +
                          std::to_string(expected) + " instances are here (" + std::to_string(s.progress.failed) +
                          " failed on the PACS side); what arrived is indexed, the series is not built; retrieve it "
                          "again to fetch only the " + std::to_string(expected - arrived) + " missing");
}

}  // namespace hvx::dicom
