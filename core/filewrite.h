#pragma once

#include <string>
#include <string_view>

namespace marbles {

/// What a WholeFileWriter does with a path that exists and is neither a regular file nor a folder
/// (a device such as /dev/null or /dev/stdout, a named pipe).
enum class SpecialFiles {
    WriteInPlace, ///< write the bytes to it as it is (the command line's --out /dev/stdout)
    Refuse,       ///< refuse it: a scene saved into a device is lost
};

/// A file written whole or not at all, in as many pieces as the caller likes. A regular file (or
/// a new one) is written to a temporary file beside it, flushed to disk and renamed over it by
/// commit(), so that readers see the old content or the new, never a part, and a run stopped half
/// way leaves the old file as it was; a file replaced keeps its permissions. A symbolic link is
/// followed (the file it names is replaced, the link stays); a file that exists and cannot be
/// written to (read-only) is refused, as is a folder. A path of another kind is written to in
/// place or refused, as `special` says: a temporary file renamed over a device node would replace
/// the device (as root, /dev/null became a plain file).
///
/// error() is "" while all is well, else why the file was not written, without the path ("it is
/// a folder", "writing failed: No space left on device", ...). Destroyed before commit(), the
/// writer removes its temporary file.
class WholeFileWriter {
public:
    WholeFileWriter(const std::string &path, SpecialFiles special);
    ~WholeFileWriter();
    WholeFileWriter(const WholeFileWriter &) = delete;
    WholeFileWriter &operator=(const WholeFileWriter &) = delete;

    /// Appends `bytes`; false (doing nothing) once anything failed.
    bool write(std::string_view bytes);
    /// Makes the file the bytes written; false if it cannot (or anything failed before).
    bool commit();

    const std::string &error() const { return m_error; }
    /// Whether the failure came while writing or committing (a full disk, an I/O error) rather
    /// than from the path (a missing folder, a read-only file, a folder).
    bool failedWhileWriting() const { return m_failedWhileWriting; }

private:
    void fail(const std::string &what, int error, bool whileWriting);
    // Opens m_path to write in place, or refuses it, as `special` says.
    void writeInPlace(SpecialFiles special);

    std::string m_path;      // the file replaced (a link's target) or written in place
    std::string m_folder;    // where it is (synced after the rename)
    std::string m_temporary; // empty when writing in place
    int m_fd = -1;
    bool m_committed = false;
    bool m_failedWhileWriting = false;
    std::string m_error;
};

/// Whether two paths name one file: the same file where both exist, else the same place once
/// links are followed as a WholeFileWriter follows them ("x", "./x", "d/../x", a dangling link
/// to "x" name the same file to be).
bool namesSameFile(const std::string &a, const std::string &b);

/// Removes the temporary files of the writers not yet committed or destroyed. Safe to call from a
/// signal handler (it only calls unlink()): a program stopped by Ctrl+C or SIGTERM calls it so
/// that an interrupted write leaves no hidden temporary beside its target.
void removeUnfinishedTemporaries() noexcept;

/// Writes `bytes` as the whole content of `path` (a WholeFileWriter, written once and committed);
/// returns "" or why nothing was written.
std::string writeFileWhole(const std::string &path, std::string_view bytes, SpecialFiles special);

} // namespace marbles
