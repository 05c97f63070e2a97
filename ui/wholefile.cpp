#include "ui/wholefile.h"

#include <QCoreApplication>
#include <QDir>
#include <QFileInfo>
#include <QSaveFile>

#include <algorithm>

namespace marbles {

QString writeWholeFile(const QString &path, const QByteArray &data)
{
    // QSaveFile renames its temporary file over whatever is there: a device such as /dev/null
    // would become a plain file (seen as root). Only regular files, or none yet, are written.
    const QFileInfo target(path);
    if (target.exists() && !target.isFile())
        return QCoreApplication::translate("marbles", "cannot write: not a regular file (a folder or a device)");
    // The folder named, as the command line does ("No such file or directory" said neither which
    // nor that it was the folder that was missing).
    const QFileInfo folder(target.absolutePath());
    if (!folder.isDir())
        return QCoreApplication::translate("marbles", "cannot write: there is no folder %1")
            .arg(QDir::toNativeSeparators(folder.filePath()));
    QSaveFile file(path);
    if (!file.open(QIODevice::WriteOnly | QIODevice::Unbuffered))
        return QCoreApplication::translate("marbles", "cannot write: %1").arg(file.errorString());
    const qint64 written = file.write(data);
    if (written != data.size()) {
        // A write cut short (a full disk, a file size limit) need not set an error of its own.
        const QString reason = file.error() != QFileDevice::NoError
                                   ? file.errorString()
                                   : QCoreApplication::translate("marbles", "only %1 of %2 bytes could be written (is the disk full?)")
                                         .arg(std::max<qint64>(written, 0))
                                         .arg(data.size());
        file.cancelWriting();
        return QCoreApplication::translate("marbles", "cannot write: %1").arg(reason);
    }
    if (!file.commit())
        return QCoreApplication::translate("marbles", "cannot write: %1").arg(file.errorString());
    return QString();
}

} // namespace marbles
