#include "ui/filedialog.h"

#include <QFileDialog>
#include <QFileIconProvider>
#include <QMimeDatabase>

namespace marbles {

namespace {

/// Icons and types from the name alone: a folder or a file, and the type its extension gives.
/// (Qt's provider reads a file's content where its name does not settle the type.)
class NameOnlyIconProvider final : public QFileIconProvider {
public:
    QIcon icon(const QFileInfo &info) const override { return QFileIconProvider::icon(info.isDir() ? Folder : File); }
    QString type(const QFileInfo &info) const override
    {
        if (info.isDir())
            return QFileIconProvider::type(info); // "Folder", without reading anything
        return m_types.mimeTypeForFile(info, QMimeDatabase::MatchExtension).comment();
    }

private:
    QMimeDatabase m_types;
};

} // namespace

QString askFileName(QWidget *parent, FileDialogMode mode, const QString &caption, const QString &start,
                    const QString &filter, const QString &defaultSuffix)
{
    QFileDialog dialog(parent, caption, start, filter);
    NameOnlyIconProvider icons;
    dialog.setIconProvider(&icons);
    if (mode == FileDialogMode::Save) {
        dialog.setAcceptMode(QFileDialog::AcceptSave);
        dialog.setFileMode(QFileDialog::AnyFile);
        dialog.setDefaultSuffix(defaultSuffix);
    } else {
        dialog.setAcceptMode(QFileDialog::AcceptOpen);
        dialog.setFileMode(QFileDialog::ExistingFile);
    }
    if (dialog.exec() != QDialog::Accepted)
        return QString();
    return dialog.selectedFiles().value(0);
}

} // namespace marbles
