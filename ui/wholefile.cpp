#include "ui/wholefile.h"

#include <QCoreApplication>
#include <QSaveFile>

#include <algorithm>

namespace marbles {

QString writeWholeFile(const QString &path, const QByteArray &data)
{
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
