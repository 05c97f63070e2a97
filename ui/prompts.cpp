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
    // A Save that could only fail is not offered (after the book model's blow-up it was, and
    // then refused with a message of its own).
    if (!unsavable.isEmpty()) {
        const QString text = tr("The scene \"%1\" has changes that are not saved, and they cannot be saved as it is "
                                "now: %2.\n\nTo keep them, Cancel, then step back to an earlier frame (or press Home "
                                "to go back to the start) and save there.")
                                 .arg(documentName, unsavable);
        const auto answer = QMessageBox::warning(parent, tr("Unsaved changes"), text,
                                                 QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Cancel);
        return answer == QMessageBox::Discard ? SaveChoice::Discard : SaveChoice::Cancel;
    }
    QString text = tr("The scene \"%1\" has changes that are not saved.\nSave them before they are lost?").arg(documentName);
    if (frame > 0)
        text += tr("\n\nIt is saved as it is now, at frame %1, which it opens at as frame 0; the run's start is not "
                   "kept (Cancel, then Home, to save that).")
                    .arg(frame);
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
