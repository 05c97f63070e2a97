#pragma once

#include <QString>

#include <cstdint>

class QWidget;

namespace marbles {

/// The questions the main window asks the user. The default implementation shows Qt's
/// dialogs; tests install their own answers with MainWindow::setPrompts(), so no modal
/// dialog ever blocks a test.
class Prompts {
public:
    /// Answer to "save the changes?".
    enum class SaveChoice { Save, Discard, Cancel };
    /// Answer to "save the scene as it is now, or its run's start?".
    enum class SaveFrame { Now, Start, Cancel };

    virtual ~Prompts();

    /// Asks whether to save the changes to `documentName` before they are lost; `frame` is the
    /// frame the run is at, 0 at its start (elsewhere Save asks next which frame to save).
    /// Where the scene cannot be saved at that frame, `unsavable` says why (its start can be).
    virtual SaveChoice askSaveChanges(QWidget *parent, const QString &documentName, std::int64_t frame,
                                      const QString &unsavable);
    /// Asks, before a scene is saved in the middle of its run (at `frame`) to `fileName`, whether to
    /// save it as it is now, which opens there as frame 0, or its run's start (`startFrame`) with
    /// every edit. Where the frame cannot be saved, `unsavable` says why, and it is not offered.
    virtual SaveFrame askSaveFrame(QWidget *parent, const QString &fileName, std::int64_t frame,
                                   std::int64_t startFrame, const QString &unsavable);
    /// Asks whether to recover the scene described by `details` from the autosave.
    virtual bool askRecover(QWidget *parent, const QString &details);
    /// Asks for a scene file to open, starting in `directory`; empty when cancelled.
    virtual QString askOpenFileName(QWidget *parent, const QString &directory);
    /// Asks where to save the scene, starting at `suggestion`; empty when cancelled.
    virtual QString askSaveFileName(QWidget *parent, const QString &suggestion);
    /// Tells the user that something failed.
    virtual void showError(QWidget *parent, const QString &title, const QString &text);
};

} // namespace marbles
