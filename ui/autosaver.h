#pragma once

#include <QObject>
#include <QString>
#include <QTimer>

#include <memory>

class QLockFile;

namespace marbles {

class SceneDocument;

/// Crash insurance: while the scene has unsaved edits, a timer writes it to an autosave file in
/// QStandardPaths::AppDataLocation. On the next start a leftover autosave means the last session
/// did not end cleanly, and the scene can be recovered; a clean exit deletes it. A lock file
/// keeps a second running instance from writing over (or recovering) the first one's autosave.
class AutoSaver : public QObject {
    Q_OBJECT

public:
    /// Time between autosaves, ms.
    static constexpr int kDefaultIntervalMs = 30000;

    /// Autosaves `document` (which must outlive this) into `directory` (empty = AppDataLocation).
    explicit AutoSaver(SceneDocument *document, const QString &directory = {}, QObject *parent = nullptr);
    ~AutoSaver() override;

    /// False when another instance owns the autosave (this one then never writes or recovers).
    bool isActive() const { return m_active; }
    /// Starts the timer.
    void start(int intervalMs = kDefaultIntervalMs);
    /// Writes the scene now if it has unsaved edits (or deletes the autosave if it has none).
    /// Returns false when writing failed.
    bool saveNow();
    /// True when an autosave from an earlier session is waiting to be recovered.
    bool hasRecovery() const;
    /// The file the autosaved scene came from ("" for an untitled scene).
    QString recoverySource() const;
    /// Loads the autosave into the document (modified, named after its source); false with `error` on failure.
    bool recover(QString *error);
    /// Deletes the autosave (a clean exit, or the user declined recovery).
    void discard();
    /// Path of the autosaved scene.
    QString scenePath() const;

private:
    QString sourcePath() const;

    SceneDocument *m_document;
    QString m_directory;
    QTimer m_timer;
    std::unique_ptr<QLockFile> m_lock;
    bool m_active = false;
};

} // namespace marbles
