#pragma once

#include <QObject>
#include <QString>
#include <QStringList>
#include <QTimer>

#include <future>
#include <memory>

class QLockFile;

namespace marbles {

class SceneDocument;

/// Crash insurance: while the scene has unsaved edits, a timer writes it to an autosave file in
/// QStandardPaths::AppDataLocation. On the next start a leftover autosave means the last session
/// did not end cleanly, and the scene can be recovered; a clean exit deletes it. A lock file
/// keeps a second running instance from writing over (or recovering) the first one's autosave.
/// What is kept is the scene as at the start of its run (SceneDocument::worldAtStart()): the
/// teacher's work is the scene and its edits, and a scene taken mid-run would come back with its
/// marbles moved and its scripted pushes that had acted gone.
/// The timer's saves take a copy of the world and write it on a worker thread, so that a large
/// scene (100,000 marbles: 16 MB of JSON, about 0.3 s) does not stall a running window.
class AutoSaver : public QObject {
    Q_OBJECT

public:
    /// Time between autosaves, ms.
    static constexpr int kDefaultIntervalMs = 30000;

    /// Autosaves `document` (which must outlive this) into `directory` (empty = AppDataLocation).
    explicit AutoSaver(SceneDocument *document, const QString &directory = {}, QObject *parent = nullptr);
    ~AutoSaver() override;

    /// True once this instance holds the autosave's lock (it then writes and recovers).
    bool isActive() const { return m_active; }
    /// True when another instance holds the lock: this one then never writes or recovers. A lock
    /// that could not be written (a full disk, a folder that cannot be made) is tried again at
    /// each save, which says it failed until it can be taken.
    bool heldElsewhere() const { return m_heldElsewhere; }
    /// Starts the timer.
    void start(int intervalMs = kDefaultIntervalMs);
    /// Writes the scene now if it has unsaved edits (or deletes the autosave if it has none).
    /// Returns false when writing failed, or when an earlier session's autosave still waits for
    /// recover(), setAside() or discard() (nothing is written over it or deleted until then).
    /// Waits for a background save first.
    bool saveNow();
    /// Same, but the writing happens on a worker thread (the timer's way); does nothing while the
    /// previous background save is still writing. Returns false when nothing was started.
    bool saveInBackground();
    /// Waits for a background save to end; returns whether it wrote its files (true if none ran).
    bool waitForBackgroundSave();
    /// True when an autosave from an earlier session is waiting to be recovered.
    bool hasRecovery() const;
    /// Names an untitled scene by the preset it came from (autosaved with it; "" for none).
    void setPresetTitle(const QString &title) { m_presetTitle = title; }
    /// The file the autosaved scene came from ("" for an untitled scene).
    QString recoverySource() const;
    /// The preset an untitled autosaved scene came from ("" for none, or for a file).
    QString recoveryPresetTitle() const;
    /// Loads the autosave into the document (modified, named after its source); false with `error` on failure.
    bool recover(QString *error);
    /// Moves an autosave that could not be recovered out of the way, beside it as
    /// autosave-unrecovered-<date>-<time>.marbles.json, so that nothing the teacher had is
    /// deleted and the next start does not ask again. Returns its new path ("" if it could not
    /// be moved: then it stays where it is).
    QString setAside();
    /// Deletes the autosave (a clean exit, or the user declined recovery), after waiting for a
    /// background save, which would otherwise write it again.
    void discard();
    /// Path of the autosaved scene.
    QString scenePath() const;

Q_SIGNALS:
    /// An autosave could not be written (a full disk): the changes are not protected.
    void failed();

private:
    /// Takes the lock if no other instance holds it; whether this instance holds it.
    bool takeLock();
    /// Whether the process that holds the lock (by its file) still runs; false where the file
    /// cannot be read.
    bool lockOwnerRuns() const;
    /// takeLock() for a save; failed() where it could not be taken and the scene has changes.
    bool lockForSaving();
    QString sourcePath() const;
    /// What the source file holds: the scene's file name, then a NUL (which no path holds) and
    /// the preset title (an autosave of an older version has the file name alone).
    QByteArray sourceRecord() const;
    /// The source file's two fields (file name, preset title).
    QStringList readSourceRecord() const;
    /// Writes the autosave files (any thread).
    static bool writeFiles(const QString &scenePath, const std::string &json, const QString &sourcePath,
                           const QByteArray &sourceRecord);

    SceneDocument *m_document;
    QString m_directory;
    QTimer m_timer;
    std::unique_ptr<QLockFile> m_lock;
    bool m_active = false;
    bool m_heldElsewhere = false;
    // An earlier session's autosave was here at the start, and the teacher has not yet chosen to
    // recover, set aside or discard it: the timer's saves leave it alone (a helper's finding: the
    // first tick, 30 s into the recovery question, deleted it, the scene being unmodified).
    bool m_recoveryPending = false;
    QString m_presetTitle;
    std::future<bool> m_background; // the background save in flight, if any
};

} // namespace marbles
