#include "ui/autosaver.h"

#include "core/sceneio.h"
#include "ui/scenedocument.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QLockFile>
#include <QSaveFile>
#include <QStandardPaths>

namespace marbles {

AutoSaver::AutoSaver(SceneDocument *document, const QString &directory, QObject *parent)
    : QObject(parent)
    , m_document(document)
    , m_directory(directory.isEmpty() ? QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)
                                      : directory)
{
    QDir().mkpath(m_directory);
    m_lock = std::make_unique<QLockFile>(QDir(m_directory).filePath(QStringLiteral("autosave.lock")));
    m_active = m_lock->tryLock(0);
    connect(&m_timer, &QTimer::timeout, this, &AutoSaver::saveNow);
}

AutoSaver::~AutoSaver() = default;

QString AutoSaver::scenePath() const
{
    return QDir(m_directory).filePath(QStringLiteral("autosave.marbles.json"));
}

QString AutoSaver::sourcePath() const
{
    return QDir(m_directory).filePath(QStringLiteral("autosave.source"));
}

void AutoSaver::start(int intervalMs)
{
    if (!m_active)
        return;
    m_timer.start(intervalMs);
}

bool AutoSaver::saveNow()
{
    if (!m_active)
        return false;
    if (!m_document->isModified()) {
        discard();
        return true;
    }
    const std::string json = sceneToJson(m_document->world());
    QSaveFile scene(scenePath());
    if (!scene.open(QIODevice::WriteOnly)
        || scene.write(json.data(), static_cast<qint64>(json.size())) != static_cast<qint64>(json.size())
        || !scene.commit())
        return false;
    QSaveFile source(sourcePath());
    const QByteArray name = m_document->fileName().toUtf8();
    return source.open(QIODevice::WriteOnly) && source.write(name) == name.size() && source.commit();
}

bool AutoSaver::hasRecovery() const
{
    return m_active && QFile::exists(scenePath());
}

QString AutoSaver::recoverySource() const
{
    QFile source(sourcePath());
    if (!source.open(QIODevice::ReadOnly))
        return {};
    return QString::fromUtf8(source.readAll());
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
    const SceneLoad load = parseScene(std::string_view(text.constData(), static_cast<std::size_t>(text.size())),
                                      "autosave.marbles.json");
    if (!load.ok) {
        if (error)
            *error = QString::fromStdString(load.error);
        return false;
    }
    m_document->resetScene(load.world, recoverySource());
    m_document->markModified();
    return true;
}

void AutoSaver::discard()
{
    if (!m_active)
        return;
    QFile::remove(scenePath());
    QFile::remove(sourcePath());
}

} // namespace marbles
