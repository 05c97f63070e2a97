#pragma once

#include <QByteArray>
#include <QString>

namespace marbles {

/// Writes `data` to `path` whole or not at all: into a temporary file beside it, flushed to disk,
/// then renamed over it (QSaveFile). Returns "" or the reason it was not written; the file that
/// was there is then as it was. Refuses a path that is not a regular file (a folder, a device).
///
/// Unbuffered on purpose: Qt 6.4's buffered QSaveFile::commit() reports success after the write
/// of its buffer failed (a full disk), renaming a short or empty file over the old one. Written
/// unbuffered, the failure is the write's own short count.
QString writeWholeFile(const QString &path, const QByteArray &data);

} // namespace marbles
