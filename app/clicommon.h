#pragma once

// Shared pieces of the marbles-cli subcommands: exit codes, argument reading and scene loading.

#include "core/filewrite.h"
#include "core/world.h"

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marbles::cli {

/// Exit codes of INTERFACES.md.
enum ExitCode : int {
    ExitOk = 0,
    ExitInternal = 1,
    ExitInvalid = 2,
    ExitNonFinite = 3,
};

/// Thrown for invalid input or arguments; main() prints the message and exits 2.
struct InvalidInput {
    std::string message;
};

/// Thrown when an output file could not be written once it was open (a full disk, an I/O
/// error): main() prints the message and exits 1, as for standard output that cannot be written.
struct WriteFailed {
    std::string message;
};

/// Thrown when a scene cannot be read for want of memory (it may be valid: exit 1, not 2).
struct OutOfMemory {
    std::string message;
};

/// Thrown by parseOptions() for --help or -h among a command's options: its usage is printed.
struct HelpRequested {};

/// Parses a whole integer option value in [minimum, maximum]; throws InvalidInput naming the option.
long long parseInteger(std::string_view option, std::string_view text, long long minimum,
                       long long maximum = std::numeric_limits<long long>::max());
/// The most marbles a generated crowd may have (gen crowd --n, bench --crowd and --max-n).
inline constexpr long long kMaxCrowd = 10'000'000;
/// Parses a finite double option value; throws InvalidInput naming the option.
double parseNumber(std::string_view option, std::string_view text);

/// A command's arguments: "--name VALUE" (or "--name=VALUE") options and flags in the order
/// given, and the other words (positional) in order.
struct Options {
    std::vector<std::string> positional;
    std::vector<std::pair<std::string, std::string>> named;

    /// The last value given for `name`, or null.
    const std::string *last(std::string_view name) const;
    /// Whether `name` was given.
    bool has(std::string_view name) const { return last(name) != nullptr; }
    /// Every value given for `name`, in order.
    std::vector<std::string> all(std::string_view name) const;
};

/// Reads a command's arguments: `valued` options take a value ("--frames 5", "--frames=5"),
/// `flags` none. "-" is a word (standard input or output), and every word after "--" too. An
/// option the command does not take, a flag given a value, a value missing, an option other than
/// --set given twice: InvalidInput naming it (and what the command takes). --help or -h:
/// HelpRequested.
Options parseOptions(const std::vector<std::string> &args, std::initializer_list<std::string_view> valued,
                     std::initializer_list<std::string_view> flags = {});
/// Whether a path is "-": standard input as SCENE, standard output as run's or a scene's --out.
inline bool isStandardStream(const std::string &path) { return path == "-"; }
/// How messages name SCENE: "stdin" for "-", else as given, on one line (printableText()).
std::string sceneLabel(const std::string &scene);

/// Loads SCENE ("-" reads standard input; "preset:ID" builds a built-in preset), applies the
/// KEY=VALUE settings in order and validates the result; throws InvalidInput with one message.
World loadWorld(const std::string &scene, const std::vector<std::string> &settings);

/// An output file (--out, --csv, --plot) replaced whole once committed (WholeFileWriter). Opened
/// before a command's work, so that a path that cannot be written (a missing folder, a read-only
/// file, a folder) fails at once with InvalidInput, nothing run and nothing printed; write() and
/// commit() throw WriteFailed where writing fails (a full disk). Destroyed uncommitted, it leaves
/// the old file as it was.
class OutputFile {
public:
    /// Opens `path`, given as `option` ("--out"), which messages name where the path cannot be
    /// a file: empty, or "-" (standard output, which a caller that can write there takes first).
    OutputFile(const std::string &option, const std::string &path);
    void write(std::string_view bytes);
    void commit();

private:
    static const std::string &checkedPath(const std::string &option, const std::string &path);
    void throwIfFailed() const;
    std::string m_path;
    WholeFileWriter m_writer;
};

/// `x` printed with the printf `spec`, or `missing` when x is NaN (a figure that does not apply).
std::string formatNumber(double x, const char *spec = "%.3g", const char *missing = "n/a");

/// `marbles-cli bench ...`: run time against error, or --scale; returns an exit code.
int benchCommand(const std::vector<std::string> &args);
/// `marbles-cli stress ...`: numerical stability; 0 only when every row meets its expectation.
int stressCommand(const std::vector<std::string> &args);

} // namespace marbles::cli
