#include "core/filewrite.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace marbles {

namespace {

std::string osError(int error)
{
    return std::generic_category().message(error);
}

// The file a chain of symbolic links ends at (which may not exist yet: writing to a dangling
// link creates the file it names, as a shell's > does). Gives up after 40 links (a loop).
std::filesystem::path followLinks(std::filesystem::path path, std::error_code &error)
{
    namespace fs = std::filesystem;
    for (int hops = 0; hops < 40; ++hops) {
        struct stat link {};
        if (::lstat(path.c_str(), &link) != 0 || !S_ISLNK(link.st_mode))
            return path; // not there (yet), or not a link
        const fs::path target = fs::read_symlink(path, error);
        if (error)
            return path;
        path = target.is_absolute() ? target : path.parent_path() / target;
    }
    error = std::make_error_code(std::errc::too_many_symbolic_link_levels);
    return path;
}

// The temporaries of the writers alive, for removeUnfinishedTemporaries(): fixed slots that a
// signal handler can read without locks. A slot is claimed atomically (writers on two threads
// take two slots), its path written, then marked ready; more writers than slots go unlisted.
constexpr int kSlots = 8;
enum SlotState : int { Free, Claimed, Ready };
struct Slot {
    char path[4096];
    std::atomic<int> state{Free};
};
static_assert(std::atomic<int>::is_always_lock_free);
Slot g_slots[kSlots];

void registerTemporary(const std::string &path)
{
    if (path.size() >= sizeof(g_slots[0].path))
        return;
    for (Slot &slot : g_slots) {
        int expected = Free;
        if (slot.state.compare_exchange_strong(expected, Claimed)) {
            std::memcpy(slot.path, path.c_str(), path.size() + 1);
            slot.state.store(Ready);
            return;
        }
    }
}

void forgetTemporary(const std::string &path)
{
    for (Slot &slot : g_slots) {
        if (slot.state.load() == Ready && path == slot.path) {
            slot.state.store(Free);
            return;
        }
    }
}

} // namespace

void WholeFileWriter::writeInPlace(SpecialFiles special)
{
    if (special == SpecialFiles::Refuse) {
        m_error = "not a regular file (a device or a pipe)";
        return;
    }
    m_fd = ::open(m_path.c_str(), O_WRONLY | O_CLOEXEC);
    if (m_fd < 0)
        fail("cannot open it", errno, false);
}

bool namesSameFile(const std::string &a, const std::string &b)
{
    namespace fs = std::filesystem;
    struct stat statA {};
    struct stat statB {};
    if (::stat(a.c_str(), &statA) == 0 && ::stat(b.c_str(), &statB) == 0)
        return statA.st_dev == statB.st_dev && statA.st_ino == statB.st_ino;
    // One not there yet: where the links lead, as a writer follows them (a dangling link names
    // the file it would create), then the same place by its absolute, normal spelling.
    std::error_code error;
    const auto place = [&error](const std::string &path) {
        const fs::path target = followLinks(fs::path(path), error);
        return fs::weakly_canonical(fs::absolute(target, error), error);
    };
    const fs::path placeA = place(a);
    const fs::path placeB = place(b);
    return error ? a == b : placeA == placeB;
}

void removeUnfinishedTemporaries() noexcept
{
    for (Slot &slot : g_slots) {
        if (slot.state.load() == Ready)
            ::unlink(slot.path);
    }
}

WholeFileWriter::WholeFileWriter(const std::string &path, SpecialFiles special)
{
    namespace fs = std::filesystem;
    // A device or a pipe is taken by the name given, whatever links lead to it: /dev/stdout is a
    // link to /proc/self/fd/1, whose own link text ("pipe:[1234]") names no file, so following
    // the links by hand ended in "cannot create a file in /proc/self/fd" (--out /dev/stdout piped
    // into another command, or a shell's >(...)).
    struct stat given {};
    if (::stat(path.c_str(), &given) == 0 && !S_ISREG(given.st_mode) && !S_ISDIR(given.st_mode)) {
        m_path = path;
        writeInPlace(special);
        return;
    }
    std::error_code linkError;
    const fs::path target = followLinks(fs::path(path), linkError);
    if (linkError) {
        fail(linkError.message(), 0, false);
        return;
    }
    m_path = target.string();
    const std::string base = target.filename().string();
    if (base.empty() || base == "." || base == "..") {
        m_error = "not a file name";
        return;
    }
    m_folder = target.parent_path().empty() ? std::string(".") : target.parent_path().string();

    struct stat existing {};
    const bool exists = ::stat(m_path.c_str(), &existing) == 0;
    if (exists && S_ISDIR(existing.st_mode)) {
        m_error = "it is a folder";
        return;
    }
    if (exists && !S_ISREG(existing.st_mode)) {
        writeInPlace(special);
        return;
    }
    // A read-only file is not replaced behind its owner's back (the rename would need only the
    // folder to be writable).
    if (exists && ::access(m_path.c_str(), W_OK) != 0) {
        fail("the file cannot be written to", errno, false);
        return;
    }

    // The temporary file sits beside the target, so the final rename stays within one file
    // system and is atomic.
    // Its name is the target's, cut short enough that the suffix still fits a file name's 255
    // bytes (a 244-byte name was refused as too long).
    static std::atomic<unsigned> counter{0};
    const std::string stem = "." + base.substr(0, 200);
    for (int attempt = 0; attempt < 100 && m_fd < 0; ++attempt) {
        m_temporary = (fs::path(m_folder) / (stem + ".tmp-" + std::to_string(::getpid()) + "-"
                                             + std::to_string(counter.fetch_add(1))))
                          .string();
        m_fd = ::open(m_temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (m_fd < 0 && errno != EEXIST) {
            const int error = errno;
            m_temporary.clear();
            fail("cannot create a file in " + m_folder
                     + (error == EACCES ? " (the file is replaced whole, through a new file beside it)" : ""),
                 error, false);
            return;
        }
    }
    if (m_fd < 0) {
        m_temporary.clear();
        m_error = "cannot create a temporary file in " + m_folder;
        return;
    }
    registerTemporary(m_temporary);
    // Replacing a file keeps its permissions; a new file gets the usual ones (0666 less umask).
    if (exists)
        ::fchmod(m_fd, existing.st_mode & 07777);
}

WholeFileWriter::~WholeFileWriter()
{
    if (m_fd >= 0)
        ::close(m_fd);
    if (!m_committed && !m_temporary.empty()) { // commit() forgot it already
        ::unlink(m_temporary.c_str());
        forgetTemporary(m_temporary);
    }
}

void WholeFileWriter::fail(const std::string &what, int error, bool whileWriting)
{
    if (!m_error.empty())
        return;
    m_error = error != 0 ? what + ": " + osError(error) : what;
    m_failedWhileWriting = whileWriting;
}

bool WholeFileWriter::write(std::string_view bytes)
{
    if (!m_error.empty() || m_committed)
        return false;
    std::size_t written = 0;
    while (written < bytes.size()) {
        const ssize_t n = ::write(m_fd, bytes.data() + written, bytes.size() - written);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            fail("writing failed", errno, true);
            return false;
        }
        written += static_cast<std::size_t>(n);
    }
    return true;
}

bool WholeFileWriter::commit()
{
    if (!m_error.empty() || m_committed)
        return m_error.empty();
    // A file written in place (a device, a pipe) is only closed; a temporary reaches the disk
    // before it is renamed over the file.
    const bool inPlace = m_temporary.empty();
    if (!inPlace && ::fsync(m_fd) != 0) {
        fail("flushing to disk failed", errno, true);
        return false;
    }
    if (::close(std::exchange(m_fd, -1)) != 0) {
        fail("closing failed", errno, true);
        return false;
    }
    if (inPlace) {
        m_committed = true;
        return true;
    }
    if (::rename(m_temporary.c_str(), m_path.c_str()) != 0) {
        fail("cannot replace the file", errno, true);
        return false;
    }
    m_committed = true;
    forgetTemporary(m_temporary);
    // Make the rename itself durable; a failure here cannot undo it, so it is not reported.
    if (const int dir = ::open(m_folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
    return true;
}

std::string writeFileWhole(const std::string &path, std::string_view bytes, SpecialFiles special)
{
    WholeFileWriter writer(path, special);
    writer.write(bytes);
    writer.commit();
    return writer.error();
}

} // namespace marbles
