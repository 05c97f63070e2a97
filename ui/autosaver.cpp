#include "ui/autosaver.h"

#include "core/sceneio.h"
#include "ui/scenedocument.h"
#include "ui/wholefile.h"

#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QLockFile>
#include <QStandardPaths>
#include <QSysInfo>

#include <cerrno>
#include <chrono>
#include <system_error>

#include <signal.h>

namespace marbles {

AutoSaver::AutoSaver(SceneDocument *document, const QString &directory, QObject *parent)
    : QObject(parent)
    , m_document(document)
    , m_directory(directory.isEmpty() ? QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)
                                      : directory)
{
    m_lock = std::make_unique<QLockFile>(QDir(m_directory).filePath(QStringLiteral("autosave.lock")));
    takeLock();
    // An autosave no other window keeps waits for the teacher's answer, whether or not this
    // window could take the lock: with the disk full at start it was not offered, and once there
    // was room the first save found the new window unmodified and deleted it (a helper's finding).
    m_recoveryPending = hasRecovery();
    connect(&m_timer, &QTimer::timeout, this, &AutoSaver::saveInBackground);
}

bool AutoSaver::takeLock()
{
    // A helper's finding: with the disk full at start the lock could not be written, and the
    // window said another one kept the autosave, and never autosaved, space freed or not.
    if (m_active || m_heldElsewhere)
        return m_active;
    QDir().mkpath(m_directory);
    m_active = m_lock->tryLock(0);
    m_heldElsewhere = !m_active && m_lock->error() == QLockFile::LockFailedError && lockOwnerRuns();
    return m_active;
}

bool AutoSaver::lockOwnerRuns() const
{
    // A lock left by a window that crashed, which could not be replaced (the disk full), had the
    // window say that another one kept the autosave, and never try again (a helper's finding).
    qint64 pid = 0;
    QString host;
    QString application;
    if (!m_lock->getLockInfo(&pid, &host, &application))
        return false; // unreadable: not another window's to respect; tried again at each save
    if (pid <= 0 || host != QSysInfo::machineHostName())
        return true; // another machine's (a shared home): assume it runs
    return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

AutoSaver::~AutoSaver()
{
    waitForBackgroundSave();
}

QString AutoSaver::scenePath() const
{
    return QDir(m_directory).filePath(QStringLiteral("autosave.marbles.json"));
}

QString AutoSaver::sourcePath() const
{
    return QDir(m_directory).filePath(QStringLiteral("autosave.source"));
}

bool AutoSaver::lockForSaving()
{
    if (takeLock())
        return true;
    // Not taken, and not another window's: changes this save should have kept are not kept.
    if (!m_heldElsewhere && m_document->isModified())
        Q_EMIT failed();
    return false;
}

void AutoSaver::start(int intervalMs)
{
    if (m_heldElsewhere)
        return;
    m_timer.start(intervalMs);
}

bool AutoSaver::writeFiles(const QString &scenePath, const std::string &json, const QString &sourcePath,
                           const QByteArray &sourceRecord)
{
    return writeWholeFile(scenePath, QByteArray::fromStdString(json)).isEmpty()
        && writeWholeFile(sourcePath, sourceRecord).isEmpty();
}

QByteArray AutoSaver::sourceRecord() const
{
    QByteArray record = m_document->fileName().toUtf8();
    if (m_document->fileName().isEmpty() && !m_presetTitle.isEmpty()) {
        record.append('\0');
        record.append(m_presetTitle.toUtf8());
    }
    return record;
}

QStringList AutoSaver::readSourceRecord() const
{
    QFile source(sourcePath());
    if (!source.open(QIODevice::ReadOnly))
        return {QString(), QString()};
    const QByteArray record = source.readAll();
    const qsizetype nul = record.indexOf('\0');
    if (nul < 0)
        return {QString::fromUtf8(record), QString()};
    return {QString::fromUtf8(record.left(nul)), QString::fromUtf8(record.mid(nul + 1))};
}

bool AutoSaver::saveNow()
{
    if (m_recoveryPending || !lockForSaving())
        return false;
    waitForBackgroundSave();
    if (!m_document->isModified()) {
        discard();
        return true;
    }
    const bool written = writeFiles(scenePath(), sceneToJson(m_document->worldAtStart()), sourcePath(), sourceRecord());
    if (!written)
        Q_EMIT failed();
    return written;
}

bool AutoSaver::saveInBackground()
{
    if (m_recoveryPending || !lockForSaving())
        return false;
    if (m_background.valid() && m_background.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        return false; // still writing the last one: the next tick tries again
    waitForBackgroundSave();
    if (!m_document->isModified()) {
        discard();
        return false;
    }
    // The copy is the only work done here; turning it into JSON and writing it is the worker's.
    try {
        m_background = std::async(std::launch::async,
                                  [world = m_document->worldAtStart(), scene = scenePath(), source = sourcePath(),
                                   record = sourceRecord()] {
                                      return writeFiles(scene, sceneToJson(world), source, record);
                                  });
    } catch (const std::system_error &) {
        return saveNow(); // no thread to be had: write it here rather than not at all
    }
    return true;
}

bool AutoSaver::waitForBackgroundSave()
{
    if (!m_background.valid())
        return true;
    const bool written = m_background.get();
    if (!written)
        Q_EMIT failed();
    return written;
}

bool AutoSaver::hasRecovery() const
{
    return !m_heldElsewhere && QFile::exists(scenePath());
}

QString AutoSaver::recoverySource() const
{
    return readSourceRecord().value(0);
}

QString AutoSaver::recoveryPresetTitle() const
{
    return readSourceRecord().value(1);
}

bool AutoSaver::recover(QString *error)
{
    QFile file(scenePath());
    if (!file.open(QIODevice::ReadOnly)) {
        if (error)
            *error = QCoreApplication::translate("marbles", "%1: cannot open: %2").arg(scenePath(), file.errorString());
        return false;
    }
    const QByteArray text = file.readAll();
    // Named by its whole path: a damaged autosave is set aside, and the teacher may want it.
    const SceneLoad load = parseScene(std::string_view(text.constData(), static_cast<std::size_t>(text.size())),
                                      QDir::toNativeSeparators(scenePath()).toStdString());
    if (!load.ok) {
        if (error)
            *error = QString::fromStdString(load.error);
        return false;
    }
    m_document->resetScene(load.world, recoverySource());
    m_document->markModified();
    m_recoveryPending = false;
    return true;
}

QString AutoSaver::setAside()
{
    if (!m_active)
        return {};
    m_recoveryPending = false; // kept or not, the teacher has answered: this session autosaves
    waitForBackgroundSave();
    const QFileInfo scene(scenePath());
    const QString stamp = QDateTime::currentDateTime().toString(QStringLiteral("yyyyMMdd-HHmmss"));
    QString kept;
    for (int n = 1; kept.isEmpty() || QFileInfo::exists(kept); ++n) {
        kept = scene.dir().filePath(QStringLiteral("autosave-unrecovered-%1%2.marbles.json")
                                        .arg(stamp, n == 1 ? QString() : QStringLiteral("-%1").arg(n)));
    }
    if (!QFile::rename(scene.filePath(), kept))
        return {};
    QFile::remove(sourcePath());
    return kept;
}

void AutoSaver::discard()
{
    m_recoveryPending = false; // answered (without the lock, the first save that takes it deletes it)
    if (!m_active)
        return;
    waitForBackgroundSave();
    QFile::remove(scenePath());
    QFile::remove(sourcePath());
}

} // namespace marbles
