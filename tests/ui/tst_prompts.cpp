// The application's questions. Its file dialogs: Qt's own dialog (where the desktop offers none)
// describes the files it lists by their names alone, and a save adds the scene's or export's
// extension before it asks whether to replace a file. The crash recovery's question: Esc keeps
// the autosave.

#include "ui/filedialog.h"
#include "ui/prompts.h"

#include <QAbstractFileIconProvider>
#include <QApplication>
#include <QFile>
#include <QFileDialog>
#include <QMessageBox>
#include <QPushButton>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

#include <functional>

using namespace marbles;

namespace {

/// Runs `look` on the file dialog that `ask` opens, then cancels it; returns what `ask` returned.
QString lookAtDialog(const std::function<QString()> &ask, const std::function<void(QFileDialog *)> &look)
{
    bool looked = false;
    QTimer::singleShot(0, [&] {
        auto *dialog = qobject_cast<QFileDialog *>(QApplication::activeModalWidget());
        if (!dialog)
            return;
        look(dialog);
        looked = true;
        dialog->reject();
    });
    const QString answer = ask();
    if (!looked)
        qWarning("no file dialog came up");
    return looked ? answer : QStringLiteral("(no dialog)");
}

} // namespace

class TestPrompts : public QObject {
    Q_OBJECT

private slots:
    void filesAreDescribedByTheirNamesAlone();
    void saveAddsTheExtensionBeforeAskingToReplace();
    void escapeKeepsTheAutosave();
};

void TestPrompts::filesAreDescribedByTheirNamesAlone()
{
    // A file whose bytes are a PNG's and whose name says nothing: Qt's provider read it to call it
    // a "PNG image" (and hung for good on /proc/kmsg, whose read waits for the kernel's log).
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QFile file(dir.filePath(QStringLiteral("picture")));
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write(QByteArray("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
    file.close();
    QString type;
    QString folderType;
    const QString answer = lookAtDialog(
        [&] {
            return askFileName(nullptr, FileDialogMode::Open, QStringLiteral("Open scene"), dir.path(),
                               QStringLiteral("All files (*)"));
        },
        [&](QFileDialog *dialog) {
            QAbstractFileIconProvider *icons = dialog->iconProvider();
            QVERIFY(icons);
            type = icons->type(QFileInfo(file.fileName()));
            folderType = icons->type(QFileInfo(dir.path()));
        });
    QCOMPARE(answer, QString()); // cancelled
    QVERIFY2(!type.contains(QStringLiteral("PNG")), qPrintable(type));
    QCOMPARE(folderType, QStringLiteral("Folder"));
}

void TestPrompts::saveAddsTheExtensionBeforeAskingToReplace()
{
    // "victim" typed in the Save dialog is "victim.marbles.json" when the dialog checks whether it
    // exists (the extension added after it had replaced that file without a word).
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QString suffix;
    QString typed;
    bool asksToReplace = false;
    Prompts prompts;
    lookAtDialog([&] { return prompts.askSaveFileName(nullptr, dir.filePath(QStringLiteral("scene.marbles.json"))); },
                 [&](QFileDialog *dialog) {
                     suffix = dialog->defaultSuffix();
                     dialog->selectFile(QStringLiteral("victim"));
                     typed = dialog->selectedFiles().value(0);
                     asksToReplace = !dialog->testOption(QFileDialog::DontConfirmOverwrite);
                 });
    QCOMPARE(suffix, QStringLiteral("marbles.json"));
    QCOMPARE(typed, dir.filePath(QStringLiteral("victim.marbles.json")));
    QVERIFY(asksToReplace);
}

void TestPrompts::escapeKeepsTheAutosave()
{
    // Esc on "Recover the autosaved scene?" had answered No, which deletes the autosave for good,
    // and nothing had said so. Now Esc recovers; deleting takes the Discard button, which says so.
    Prompts prompts;
    for (const bool discard : {false, true}) {
        QString text;
        QTimer::singleShot(0, [&] {
            auto *box = qobject_cast<QMessageBox *>(QApplication::activeModalWidget());
            if (!box)
                return;
            text = box->text();
            if (discard) {
                for (QAbstractButton *button : box->buttons()) {
                    if (box->buttonRole(button) == QMessageBox::DestructiveRole)
                        button->click();
                }
            } else {
                QTest::keyClick(box, Qt::Key_Escape);
            }
        });
        const bool recovered = prompts.askRecover(nullptr, QStringLiteral("An untitled scene had unsaved changes."));
        QVERIFY2(text.contains(QStringLiteral("An untitled scene had unsaved changes.")), qPrintable(text));
        QVERIFY2(text.contains(QStringLiteral("Discard deletes it for good")), qPrintable(text));
        QCOMPARE(recovered, !discard);
    }
}

QTEST_MAIN(TestPrompts)
#include "tst_prompts.moc"
