#include "core/filewrite.h"

#include <atomic>
#include <cerrno>
#include <filesystem>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace marbles {

namespace {

std::string osError(int error)
{
    return std::generic_category().message(error);
}

// Writes all of `bytes` to fd (retrying short and interrupted writes); returns errno or 0.
int writeAll(int fd, std::string_view bytes)
{
    std::size_t written = 0;
    while (written < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return errno;
        }
        written += static_cast<std::size_t>(n);
    }
    return 0;
}

std::string writeInPlace(const std::string &path, std::string_view bytes)
{
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
        return osError(errno);
    const int error = writeAll(fd, bytes);
    const bool closed = ::close(fd) == 0;
    if (error != 0)
        return "writing failed: " + osError(error);
    if (!closed)
        return "closing failed: " + osError(errno);
    return {};
}

} // namespace

std::string writeFileWhole(const std::string &path, std::string_view bytes, SpecialFiles special)
{
    namespace fs = std::filesystem;
    const fs::path target(path);
    const std::string base = target.filename().string();
    if (base.empty() || base == "." || base == "..")
        return "not a file name";
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();

    struct stat existing {};
    const bool exists = ::stat(path.c_str(), &existing) == 0;
    if (exists && S_ISDIR(existing.st_mode))
        return "it is a folder";
    if (exists && !S_ISREG(existing.st_mode)) {
        if (special == SpecialFiles::Refuse)
            return "not a regular file (a device or a pipe)";
        return writeInPlace(path, bytes);
    }

    // The temporary file sits beside the target, so the final rename stays within one file
    // system and is atomic.
    static std::atomic<unsigned> counter{0};
    std::string temporary;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        temporary = (folder / ("." + base + ".tmp-" + std::to_string(::getpid()) + "-"
                               + std::to_string(counter.fetch_add(1))))
                        .string();
        fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            return "cannot create a temporary file in " + folder.string() + ": " + osError(errno);
    }
    if (fd < 0)
        return "cannot create a temporary file in " + folder.string();

    auto abandon = [&](const std::string &what, int error) {
        ::close(fd);
        ::unlink(temporary.c_str());
        return what + ": " + osError(error);
    };

    // Replacing a file keeps its permissions; a new file gets the usual ones (0666 less umask).
    if (exists)
        ::fchmod(fd, existing.st_mode & 07777);
    if (const int error = writeAll(fd, bytes); error != 0)
        return abandon("writing failed", error);
    if (::fsync(fd) != 0)
        return abandon("flushing to disk failed", errno);
    if (::close(fd) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        return "closing failed: " + osError(error);
    }
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        return osError(error);
    }
    // Make the rename itself durable; a failure here cannot undo it, so it is not reported.
    if (const int dir = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
    return {};
}

} // namespace marbles
