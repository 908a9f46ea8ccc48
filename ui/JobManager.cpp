#include "ui/JobManager.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QMetaObject>
#include <QPointer>
#include <QThread>

#include <thread>

#include "core/base/Error.h"

namespace hvx::ui {

struct JobManager::Job {
    std::shared_ptr<core::JobContext> context;
    std::thread thread;
};

JobManager::JobManager(QObject* parent) : QObject(parent) {}

JobManager::~JobManager() {
    for (auto& [id, job] : jobs_) job->context->cancel();
    for (auto& [id, job] : jobs_)
        if (job->thread.joinable()) job->thread.join();
}

int JobManager::start(const QString& title, Work work, Done done) {
    const int id = nextId_++;
    auto job = std::make_shared<Job>();
    QPointer<JobManager> self(this);
    job->context = std::make_shared<core::JobContext>([self, id](const core::JobProgress& p) {
        QMetaObject::invokeMethod(
            self.data(),
            [self, id, p] {
                if (self) emit self->progressed(id, p.fraction, p.etaSeconds, QString::fromStdString(p.stage));
            },
            Qt::QueuedConnection);
    });
    jobs_[id] = job;
    emit started(id, title);
    auto context = job->context;
    job->thread = std::thread([self, id, context, work = std::move(work), done = std::move(done)] {
        QString state = "done", message;
        try {
            message = work(*context);
        } catch (const core::Cancelled&) {
            state = "cancelled";
            message = QObject::tr("cancelled");
        } catch (const std::exception& e) {
            state = "failed";
            message = QString::fromStdString(e.what());
        }
        QMetaObject::invokeMethod(
            self.data(),
            [self, id, state, message, done] {
                if (!self) return;
                auto it = self->jobs_.find(id);
                if (it != self->jobs_.end()) {
                    if (it->second->thread.joinable()) it->second->thread.join();
                    self->jobs_.erase(it);
                }
                if (state == "done" && done) done(message);
                emit self->finished(id, state, message);
            },
            Qt::QueuedConnection);
    });
    return id;
}

void JobManager::cancel(int id) {
    if (auto it = jobs_.find(id); it != jobs_.end()) it->second->context->cancel();
}

bool JobManager::waitIdle(int timeoutMs) {
    QElapsedTimer t;
    t.start();
    while (!jobs_.empty() && t.elapsed() < timeoutMs) {
        QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
        QThread::msleep(5);
    }
    return jobs_.empty();
}

}  // namespace hvx::ui
