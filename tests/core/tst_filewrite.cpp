#include "core/filewrite.h"
#include "tests/ui/filesizelimit.h"

#include <QDir>
#include <QFile>
#include <QTemporaryDir>
#include <QtTest>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

using namespace marbles;

// writeFileWhole(): the one writer behind a saved scene, the command line's --out and --csv and
// its PNG charts.
class TestFileWrite : public QObject {
    Q_OBJECT

private:
    static QByteArray contents(const QString &path)
    {
        QFile file(path);
        return file.open(QIODevice::ReadOnly) ? file.readAll() : QByteArray("(unreadable)");
    }

private slots:
    void writesANewFileAndLeavesNoTemporary()
    {
        QTemporaryDir dir;
        const QString path = dir.filePath("a.csv");
        QCOMPARE(writeFileWhole(path.toStdString(), "x,y\n1,2\n", SpecialFiles::Refuse), std::string());
        QCOMPARE(contents(path), QByteArray("x,y\n1,2\n"));
        QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::Hidden | QDir::NoDotAndDotDot),
                 QStringList{"a.csv"});
    }

    void replacingKeepsThePermissions()
    {
        QTemporaryDir dir;
        const std::string path = dir.filePath("a.csv").toStdString();
        QCOMPARE(writeFileWhole(path, "old", SpecialFiles::Refuse), std::string());
        QCOMPARE(::chmod(path.c_str(), 0604), 0);
        QCOMPARE(writeFileWhole(path, "new", SpecialFiles::Refuse), std::string());
        struct stat info {};
        QCOMPARE(::stat(path.c_str(), &info), 0);
        QCOMPARE(info.st_mode & 07777, mode_t(0604));
        QCOMPARE(contents(QString::fromStdString(path)), QByteArray("new"));
    }

    void aFailedWriteLeavesTheOldFile()
    {
        // A full disk (a file size limit stands in for it): the old content stays, whole, and
        // no temporary file is left beside it.
        QTemporaryDir dir;
        const QString path = dir.filePath("a.csv");
        QCOMPARE(writeFileWhole(path.toStdString(), "old", SpecialFiles::Refuse), std::string());
        std::string error;
        {
            test::FileSizeLimit limit(1000);
            QVERIFY(limit.ok());
            error = writeFileWhole(path.toStdString(), std::string(5000, 'x'), SpecialFiles::WriteInPlace);
        }
        QVERIFY2(error.starts_with("writing failed: "), error.c_str());
        QCOMPARE(contents(path), QByteArray("old"));
        QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::Hidden | QDir::NoDotAndDotDot),
                 QStringList{"a.csv"});
    }

    void aMissingFolderIsNamed()
    {
        QTemporaryDir dir;
        const std::string error = writeFileWhole(dir.filePath("no/such/a.csv").toStdString(), "x", SpecialFiles::Refuse);
        QVERIFY2(error.find("No such file or directory") != std::string::npos, error.c_str());
    }

    void aFolderIsRefusedEitherWay()
    {
        QTemporaryDir dir;
        for (SpecialFiles special : {SpecialFiles::Refuse, SpecialFiles::WriteInPlace})
            QCOMPARE(writeFileWhole(dir.path().toStdString(), "x", special), std::string("it is a folder"));
        QVERIFY(QFileInfo(dir.path()).isDir());
        QCOMPARE(writeFileWhole(".", "x", SpecialFiles::WriteInPlace), std::string("not a file name"));
    }

    void aPipeIsWrittenInPlaceOrRefused()
    {
        // A temporary file renamed over a pipe or a device node replaces it; written in place,
        // the pipe stays a pipe and its reader gets the bytes.
        QTemporaryDir dir;
        const QByteArray pipe = QFile::encodeName(dir.filePath("fifo"));
        QVERIFY(::mkfifo(pipe.constData(), 0600) == 0);
        QCOMPARE(writeFileWhole(pipe.toStdString(), "x", SpecialFiles::Refuse),
                 std::string("not a regular file (a device or a pipe)"));

        const int reader = ::open(pipe.constData(), O_RDONLY | O_NONBLOCK);
        QVERIFY(reader >= 0);
        QCOMPARE(writeFileWhole(pipe.toStdString(), "rows\n", SpecialFiles::WriteInPlace), std::string());
        char bytes[16] = {};
        QCOMPARE(::read(reader, bytes, sizeof bytes), ssize_t(5));
        ::close(reader);
        QCOMPARE(QByteArray(bytes), QByteArray("rows\n"));
        struct stat info {};
        QVERIFY(::stat(pipe.constData(), &info) == 0 && S_ISFIFO(info.st_mode));
    }
};

QTEST_APPLESS_MAIN(TestFileWrite)
#include "tst_filewrite.moc"
