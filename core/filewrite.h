#pragma once

#include <string>
#include <string_view>

namespace marbles {

/// What writeFileWhole() does with a path that exists and is neither a regular file nor a folder
/// (a device such as /dev/null or /dev/stdout, a named pipe).
enum class SpecialFiles {
    WriteInPlace, ///< write the bytes to it as it is (the command line's --out /dev/stdout)
    Refuse,       ///< refuse it: a scene saved into a device is lost
};

/// Writes `bytes` as the whole content of the file at `path`, or leaves it as it was. A regular
/// file (or a new one) is written to a temporary file beside it, flushed to disk and renamed over
/// it, so that readers see the old content or the new, never a part; a file replaced keeps its
/// permissions. A folder is refused. A path of another kind is written to in place or refused, as
/// `special` says: a temporary file renamed over a device node would replace the device (as root,
/// /dev/null became a plain file).
///
/// Returns "" on success, else why nothing was written, without the path ("it is a folder",
/// "writing failed: No space left on device", ...).
std::string writeFileWhole(const std::string &path, std::string_view bytes, SpecialFiles special);

} // namespace marbles
