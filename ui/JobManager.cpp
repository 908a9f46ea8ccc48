#include "ui/JobManager.h"

#include <QEvent>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QThread>

#include <thread>

#include "core/base/Error.h"

namespace hvx::ui {

struct JobManager::Job {
    std::shared_ptr<core::JobContext> context;
    std::thread thread;
};

struct JobManager::Mailbox {
    std::mutex mutex;
    std::deque<std::function<void()>> items;
};

JobManager::JobManager(QObject* parent)
    : QObject(parent), mailbox_(std::make_shared<Mailbox>()), drainTimer_(new QTimer(this)) {
    drainTimer_->setInterval(15);
    connect(drainTimer_, &QTimer::timeout, this, &JobManager::drain);
}

JobManager::~JobManager() {
    for (auto& [id, job] : jobs_) job->context->cancel();
    for (auto& [id, job] : jobs_)
        if (job->thread.joinable()) job->thread.join();
}

void JobManager::post(std::function<void()> onGuiThread) {
    std::lock_guard lock(mailbox_->mutex);
    mailbox_->items.push_back(std::move(onGuiThread));
}

void JobManager::drain() {
    std::deque<std::function<void()>> items;
    {
        std::lock_guard lock(mailbox_->mutex);
        items.swap(mailbox_->items);
    }
    for (auto& f : items) f();
    if (jobs_.empty()) {
        std::lock_guard lock(mailbox_->mutex);
        if (mailbox_->items.empty()) drainTimer_->stop();
    }
}

int JobManager::start(const QString& title, Work work, Done done) {
    const int id = nextId_++;
    auto job = std::make_shared<Job>();
    job->context = std::make_shared<core::JobContext>([this, id](const core::JobProgress& p) {
        post([this, id, p] { emit progressed(id, p.fraction, p.etaSeconds, QString::fromStdString(p.stage)); });
    });
    jobs_[id] = job;
    if (!drainTimer_->isActive()) drainTimer_->start();
    emit started(id, title);
    auto context = job->context;
    job->thread = std::thread([this, id, context, work = std::move(work), done = std::move(done)] {
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
        post([this, id, state, message, done] {
            auto it = jobs_.find(id);
            if (it != jobs_.end()) {
                if (it->second->thread.joinable()) it->second->thread.join();
                jobs_.erase(it);
            }
            if (state == "done" && done) done(message);
            emit finished(id, state, message);
        });
    });
    return id;
}

namespace {
/// While a job runs on the GUI thread: user input reaches the Jobs panel's Cancel buttons
/// ("cancelJobN") and nothing else, so that the work is never re-entered.
class OnlyCancelInput : public QObject {
public:
    bool eventFilter(QObject* receiver, QEvent* e) override {
        switch (e->type()) {
        case QEvent::MouseButtonPress:
        case QEvent::MouseButtonRelease:
        case QEvent::MouseButtonDblClick:
        case QEvent::KeyPress:
        case QEvent::KeyRelease:
        case QEvent::Wheel:
        case QEvent::Shortcut:
        case QEvent::ShortcutOverride:
            return !receiver->objectName().startsWith(QLatin1String("cancelJob"));
        default:
            return false;
        }
    }
};
}  // namespace

QString JobManager::runHere(const QString& title, const Work& work) {
    const int id = nextId_++;
    OnlyCancelInput filter;
    core::JobContext context([this, id, &filter](const core::JobProgress& p) {
        emit progressed(id, p.fraction, p.etaSeconds, QString::fromStdString(p.stage));
        // The panel shows it now, and its Cancel button can be pressed.
        QCoreApplication::instance()->installEventFilter(&filter);
        QCoreApplication::processEvents(QEventLoop::AllEvents);
        QCoreApplication::instance()->removeEventFilter(&filter);
    });
    here_ = &context;
    hereId_ = id;
    struct Forget {
        JobManager* m;
        ~Forget() {
            m->here_ = nullptr;
            m->hereId_ = -1;
        }
    } forget{this};
    emit started(id, title);
    try {
        const QString message = work(context);
        emit progressed(id, 1.0, 0.0, {});
        emit finished(id, "done", message);
        return message;
    } catch (const core::Cancelled&) {
        emit finished(id, "cancelled", QObject::tr("cancelled"));
        throw;
    } catch (const std::exception& e) {
        emit finished(id, "failed", QString::fromStdString(e.what()));
        throw;
    }
}

void JobManager::cancel(int id) {
    if (id == hereId_ && here_) here_->cancel();
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
