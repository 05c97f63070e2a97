// marbles: the desktop application. Opens the chapter's four marbles, or the scene file given.

#include "ui/mainwindow.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QFileInfo>

#include <cstdio>

int main(int argc, char *argv[])
{
    QApplication app(argc, argv);
    QCoreApplication::setOrganizationName(QStringLiteral("Marbles"));
    QCoreApplication::setApplicationName(QStringLiteral("marbles"));
    QCoreApplication::setApplicationVersion(QStringLiteral("0.1.0"));
    QGuiApplication::setApplicationDisplayName(QStringLiteral("Marbles"));

    QCommandLineParser parser;
    parser.setApplicationDescription(
        QCoreApplication::translate("main", "A physics teaching tool: the book's marbles beside the exact physics."));
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument(QStringLiteral("scene"),
                                 QCoreApplication::translate("main", "Scene file to open (*.marbles.json), or preset:ID "
                                                                     "(see marbles-cli preset list)."),
                                 QStringLiteral("[scene]"));
    parser.process(app);

    marbles::MainWindow window;
    window.show();
    const QStringList files = parser.positionalArguments();
    if (files.size() > 1) {
        std::fprintf(stderr, "%s\n",
                     qPrintable(QCoreApplication::translate("main", "marbles: one scene at a time: opening %1, not %2")
                                    .arg(files.front(), files.mid(1).join(QStringLiteral(", ")))));
    }
    // A recovered scene made from the file asked for is that file with the changes the crash
    // would have lost: opening the file again would only ask to save them, then drop them.
    const QString recovered = window.offerRecovery();
    if (!files.isEmpty() && (recovered.isEmpty() || QFileInfo(recovered) != QFileInfo(files.front())))
        window.openArgument(files.front());
    return QApplication::exec();
}
