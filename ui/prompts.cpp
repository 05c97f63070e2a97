#include "ui/prompts.h"

#include "ui/filedialog.h"

#include <QCoreApplication>
#include <QFileInfo>
#include <QMessageBox>
#include <QPushButton>

namespace marbles {

namespace {

QString tr(const char *text)
{
    return QCoreApplication::translate("marbles", text);
}

QString sceneFilter()
{
    return tr("Marbles scenes (*.marbles.json *.json);;All files (*)");
}

} // namespace

Prompts::~Prompts() = default;

Prompts::SaveChoice Prompts::askSaveChanges(QWidget *parent, const QString &documentName, std::int64_t frame,
                                            const QString &unsavable)
{
    QString text = tr("The scene \"%1\" has changes that are not saved.\nSave them before they are lost?").arg(documentName);
    // Save asks next which frame to save (askSaveFrame()). After the book model's blow-up the
    // frame shown cannot be saved (Save had been offered, then refused with a message of its own).
    if (!unsavable.isEmpty())
        text += tr("\n\nThe frame shown cannot be saved (%1); Save offers the start of the run, with every change.")
                    .arg(unsavable);
    else if (frame > 0)
        text += tr("\n\nThe run is at frame %1: Save then asks whether to save that frame or the run's start.").arg(frame);
    const auto answer = QMessageBox::warning(parent, tr("Unsaved changes"), text,
                                             QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel,
                                             QMessageBox::Save);
    switch (answer) {
    case QMessageBox::Save:
        return SaveChoice::Save;
    case QMessageBox::Discard:
        return SaveChoice::Discard;
    default:
        return SaveChoice::Cancel;
    }
}

Prompts::SaveFrame Prompts::askSaveFrame(QWidget *parent, const QString &fileName, std::int64_t frame,
                                         std::int64_t startFrame, const QString &unsavable)
{
    // Ctrl+S in the middle of a lesson's run had put that frame over the lesson's file, and said
    // so only afterwards (a helper's finding): the run's start is offered first, and is the default.
    QMessageBox box(QMessageBox::Question, tr("Save at frame %1?").arg(frame),
                    unsavable.isEmpty()
                        ? tr("The run is at frame %1. Save %2 as its start, frame %3, with every change, or as the "
                             "scene is now? Saved as it is now, it opens at this frame, as frame 0, and the run starts "
                             "again here: Home comes back to this frame, the plot starts again, and the edits made "
                             "before it can no longer be undone.")
                              .arg(frame)
                              .arg(fileName)
                              .arg(startFrame)
                        : tr("%1 cannot be saved as the scene is now: %2. Save the start of its run, frame %3, with "
                             "every change?")
                              .arg(fileName, unsavable)
                              .arg(startFrame),
                    QMessageBox::Cancel, parent);
    QPushButton *start = box.addButton(tr("Save the &Start (Frame %1)").arg(startFrame), QMessageBox::AcceptRole);
    QPushButton *now = nullptr;
    if (unsavable.isEmpty())
        now = box.addButton(tr("Save &Frame %1").arg(frame), QMessageBox::AcceptRole);
    box.setDefaultButton(start);
    box.exec();
    if (box.clickedButton() == start)
        return SaveFrame::Start;
    if (now && box.clickedButton() == now)
        return SaveFrame::Now;
    return SaveFrame::Cancel;
}

bool Prompts::askRecover(QWidget *parent, const QString &details)
{
    // Discarding is said to be for good, and takes its own button: Esc (or No) had deleted the
    // autosave without a word, and the next start offered nothing. Esc now recovers, which
    // loses nothing (the scene recovered can still be closed without saving).
    QMessageBox box(QMessageBox::Question, tr("Recover scene"),
                    tr("Marbles did not close properly last time.\n%1\n\nRecover the autosaved scene? Discard "
                       "deletes it for good.")
                        .arg(details),
                    QMessageBox::NoButton, parent);
    QPushButton *recover = box.addButton(tr("&Recover"), QMessageBox::AcceptRole);
    box.addButton(tr("&Discard"), QMessageBox::DestructiveRole);
    box.setDefaultButton(recover);
    box.setEscapeButton(recover);
    box.exec();
    return box.clickedButton() == recover;
}

QString Prompts::askOpenFileName(QWidget *parent, const QString &directory)
{
    return askFileName(parent, FileDialogMode::Open, tr("Open scene"), directory, sceneFilter());
}

QString Prompts::askSaveFileName(QWidget *parent, const QString &suggestion)
{
    // "lesson" becomes "lesson.marbles.json" in the dialog, which then asks before replacing it.
    QString path = askFileName(parent, FileDialogMode::Save, tr("Save scene"), suggestion, sceneFilter(),
                               QStringLiteral("marbles.json"));
    if (path.isEmpty() || path.endsWith(QStringLiteral(".json"), Qt::CaseInsensitive))
        return path;
    // Another extension ("lesson.txt") is kept, and the scene's added after it: asked here.
    path += QStringLiteral(".marbles.json");
    if (QFileInfo::exists(path)
        && QMessageBox::warning(parent, tr("Save scene"), tr("%1 already exists.\nDo you want to replace it?").arg(path),
                                QMessageBox::Yes | QMessageBox::No, QMessageBox::No)
               != QMessageBox::Yes)
        return QString();
    return path;
}

void Prompts::showError(QWidget *parent, const QString &title, const QString &text)
{
    QMessageBox::warning(parent, title, text);
}

} // namespace marbles
