#include "core/filewrite.h"
#include "tests/ui/filesizelimit.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
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

        // The writer says the failure came while writing (the command line's exit code 1, as
        // for a full standard output), not from the path (its exit code 2).
        test::FileSizeLimit limit(1000);
        WholeFileWriter writer(path.toStdString(), SpecialFiles::Refuse);
        QVERIFY(writer.error().empty());
        QVERIFY(!writer.write(std::string(5000, 'x')));
        QVERIFY(writer.failedWhileWriting());
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

    void aLinkIsFollowedAndStays()
    {
        // The file a link names is replaced; the link stays a link (the rename replaced it with
        // a plain file and left its target as it was). A dangling link creates its target.
        QTemporaryDir dir;
        const QString target = dir.filePath("target.csv");
        const QString link = dir.filePath("link.csv");
        QCOMPARE(writeFileWhole(target.toStdString(), "old", SpecialFiles::Refuse), std::string());
        QVERIFY(QFile::link(QStringLiteral("target.csv"), link));
        QCOMPARE(writeFileWhole(link.toStdString(), "new", SpecialFiles::Refuse), std::string());
        QVERIFY(QFileInfo(link).isSymLink());
        QCOMPARE(contents(target), QByteArray("new"));

        const QString dangling = dir.filePath("dangling.csv");
        QVERIFY(QFile::link(QStringLiteral("made.csv"), dangling));
        QCOMPARE(writeFileWhole(dangling.toStdString(), "made", SpecialFiles::Refuse), std::string());
        QVERIFY(QFileInfo(dangling).isSymLink());
        QCOMPARE(contents(dir.filePath("made.csv")), QByteArray("made"));

        const QString loop = dir.filePath("loop.csv");
        QVERIFY(QFile::link(QStringLiteral("loop.csv"), loop));
        QVERIFY(!writeFileWhole(loop.toStdString(), "x", SpecialFiles::Refuse).empty());
    }

    void aReadOnlyFileIsNotReplaced()
    {
        if (::geteuid() == 0)
            QSKIP("root may write to a read-only file, as a shell's > does");
        QTemporaryDir dir;
        const std::string path = dir.filePath("kept.csv").toStdString();
        QCOMPARE(writeFileWhole(path, "kept", SpecialFiles::Refuse), std::string());
        QCOMPARE(::chmod(path.c_str(), 0444), 0);
        const std::string error = writeFileWhole(path, "new", SpecialFiles::Refuse);
        QVERIFY2(error.find("Permission denied") != std::string::npos, error.c_str());
        QCOMPARE(contents(QString::fromStdString(path)), QByteArray("kept"));
    }

    void writtenInPiecesOrNotAtAll()
    {
        // A writer destroyed before its commit leaves the old file and no temporary; committed,
        // the file is every piece in order.
        QTemporaryDir dir;
        const QString path = dir.filePath("rows.csv");
        QCOMPARE(writeFileWhole(path.toStdString(), "old", SpecialFiles::Refuse), std::string());
        {
            WholeFileWriter writer(path.toStdString(), SpecialFiles::Refuse);
            QVERIFY(writer.write("a,"));
            QVERIFY(writer.write("b\n"));
        }
        QCOMPARE(contents(path), QByteArray("old"));
        QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::Hidden | QDir::NoDotAndDotDot),
                 QStringList{"rows.csv"});
        WholeFileWriter writer(path.toStdString(), SpecialFiles::Refuse);
        QVERIFY(writer.write("a,"));
        QVERIFY(writer.write("b\n"));
        QVERIFY(writer.commit());
        QCOMPARE(contents(path), QByteArray("a,b\n"));
        QVERIFY(!writer.failedWhileWriting());
    }

    void aLongNameIsWritten()
    {
        // The temporary's name is the target's cut short: a 244-byte name (255 is the most) was
        // refused as too long, its temporary's name being longer.
        QTemporaryDir dir;
        const QString path = dir.filePath(QString(240, QLatin1Char('b')) + QStringLiteral(".csv"));
        QCOMPARE(writeFileWhole(path.toStdString(), "x", SpecialFiles::Refuse), std::string());
        QCOMPARE(contents(path), QByteArray("x"));
    }

    void unfinishedTemporariesCanBeRemoved()
    {
        // What a signal handler calls: the temporaries of writers not committed go, the files
        // they would replace stay.
        QTemporaryDir dir;
        const QString path = dir.filePath("rows.csv");
        QCOMPARE(writeFileWhole(path.toStdString(), "old", SpecialFiles::Refuse), std::string());
        WholeFileWriter writer(path.toStdString(), SpecialFiles::Refuse);
        QVERIFY(writer.write("new"));
        QCOMPARE(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 2);
        removeUnfinishedTemporaries();
        QCOMPARE(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden), QStringList{"rows.csv"});
        QCOMPARE(contents(path), QByteArray("old"));
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

    void anAnonymousPipeIsReachedThroughItsLinks()
    {
        // /dev/stdout piped into another command is /proc/self/fd/1, a link whose text
        // ("pipe:[1234]") names no file: followed by hand it ended in "cannot create a file in
        // /proc/self/fd". The pipe is written by the name given.
        int ends[2];
        QVERIFY(::pipe(ends) == 0);
        const std::string path = "/proc/self/fd/" + std::to_string(ends[1]);
        QCOMPARE(writeFileWhole(path, "rows\n", SpecialFiles::WriteInPlace), std::string());
        char bytes[16] = {};
        QCOMPARE(::read(ends[0], bytes, sizeof bytes), ssize_t(5));
        QCOMPARE(QByteArray(bytes), QByteArray("rows\n"));
        QCOMPARE(writeFileWhole(path, "x", SpecialFiles::Refuse), std::string("not a regular file (a device or a pipe)"));
        ::close(ends[0]);
        ::close(ends[1]);
    }

    void sameFileByAnyName()
    {
        // Two names of one file, existing or to be: spellings, links, and a dangling link to
        // the other name (which a writer would create: two outputs there lose one).
        QTemporaryDir dir;
        const std::string d = dir.path().toStdString();
        QVERIFY(QDir(dir.path()).mkdir("sub"));
        QVERIFY(namesSameFile(d + "/x", d + "/./x"));
        QVERIFY(namesSameFile(d + "/x", d + "/sub/../x"));
        QVERIFY(!namesSameFile(d + "/x", d + "/y"));
        QVERIFY(QFile::link(dir.filePath("later"), dir.filePath("dangling")));
        QVERIFY(namesSameFile(d + "/dangling", d + "/later"));
        QVERIFY(QFile::link(dir.filePath("dangling"), dir.filePath("chain")));
        QVERIFY(namesSameFile(d + "/chain", d + "/later"));
        QCOMPARE(writeFileWhole(d + "/x", "a", SpecialFiles::Refuse), std::string());
        QVERIFY(QFile::link(dir.filePath("x"), dir.filePath("sub/link")));
        QVERIFY(namesSameFile(d + "/sub/link", d + "/x"));
        QVERIFY(!namesSameFile(d + "/sub/link", d + "/later"));
    }
};

QTEST_APPLESS_MAIN(TestFileWrite)
#include "tst_filewrite.moc"
