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

/// Parses a whole integer option value in [minimum, maximum]; throws InvalidInput naming the option.
long long parseInteger(std::string_view option, std::string_view text, long long minimum,
                       long long maximum = std::numeric_limits<long long>::max());
/// The most marbles a generated crowd may have (gen crowd --n, bench --crowd and --max-n).
inline constexpr long long kMaxCrowd = 10'000'000;
/// Parses a finite double option value; throws InvalidInput naming the option.
double parseNumber(std::string_view option, std::string_view text);

/// The arguments with each "--option=value" as "--option" "value", as run and gen read them.
std::vector<std::string> splitOptionValues(const std::vector<std::string> &args);
/// Whether a path is "-": standard input as SCENE, standard output as run's or a scene's --out.
inline bool isStandardStream(const std::string &path) { return path == "-"; }
/// How messages name SCENE: "stdin" for "-", else as given.
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
    explicit OutputFile(const std::string &path);
    void write(std::string_view bytes);
    void commit();

private:
    static const std::string &checkedPath(const std::string &path);
    void throwIfFailed() const;
    std::string m_path;
    WholeFileWriter m_writer;
};

/// Writes `text` to `path` whole (an OutputFile opened, written and committed).
void writeFileAtomically(const std::string &path, const std::string &text);
/// `x` printed with the printf `spec`, or `missing` when x is NaN (a figure that does not apply).
std::string formatNumber(double x, const char *spec = "%.3g", const char *missing = "n/a");

/// `marbles-cli bench ...`: run time against error, or --scale; returns an exit code.
int benchCommand(const std::vector<std::string> &args);
/// `marbles-cli stress ...`: numerical stability; 0 only when every row meets its expectation.
int stressCommand(const std::vector<std::string> &args);

} // namespace marbles::cli
