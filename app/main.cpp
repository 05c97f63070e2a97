// marbles: the desktop application. Opens the chapter's four marbles, or the scene file given.

#include "ui/mainwindow.h"

#include <QApplication>
#include <QCommandLineParser>

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
                                 QCoreApplication::translate("main", "Scene file to open (*.marbles.json)."),
                                 QStringLiteral("[scene]"));
    parser.process(app);

    marbles::MainWindow window;
    window.show();
    const QStringList files = parser.positionalArguments();
    window.offerRecovery();
    if (!files.isEmpty())
        window.openFile(files.front());
    return QApplication::exec();
}
