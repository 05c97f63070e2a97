#pragma once

#include <QString>

class QWidget;

namespace marbles {

/// Whether a file dialog opens a file or names one to write.
enum class FileDialogMode { Open, Save };

/// Asks for a file name in a file dialog ("" when cancelled). Qt's own dialog (used where the
/// desktop offers none) tells the files it lists apart by their names alone: it had read each
/// file's first bytes to name its type, and hung for good on /proc/kmsg, which nothing ever
/// writes to (the Open dialog typed to /proc/ as root). For a save, a name typed without an
/// extension gets `defaultSuffix` (no dot) before the dialog asks whether to replace a file of
/// that name: the suffix added afterwards had replaced "victim.marbles.json" without a word.
QString askFileName(QWidget *parent, FileDialogMode mode, const QString &caption, const QString &start,
                    const QString &filter, const QString &defaultSuffix = QString());

} // namespace marbles
