// marbles-cli: the headless face of Marbles (INTERFACES.md). Links no Qt.

#include "app/clicommon.h"
#include "core/filewrite.h"
#include "core/presets.h"
#include "core/sceneio.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace marbles::cli {

long long parseInteger(std::string_view option, std::string_view text, long long minimum, long long maximum)
{
    long long value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    const bool whole = end == text.data() + text.size() && !text.empty();
    // A whole number beyond the range (99999999999999999999) is too large, not "no number".
    if (ec == std::errc::result_out_of_range && whole)
        throw InvalidInput{std::string(option) + ": must be " + (text.front() == '-' ? ">= " + std::to_string(minimum)
                                                                                      : "<= " + std::to_string(maximum))
                           + ", got " + std::string(text)};
    if (ec != std::errc() || !whole)
        throw InvalidInput{std::string(option) + ": must be a whole number, got '" + std::string(text) + "'"};
    if (value < minimum)
        throw InvalidInput{std::string(option) + ": must be >= " + std::to_string(minimum) + ", got "
                           + std::string(text)};
    if (value > maximum)
        throw InvalidInput{std::string(option) + ": must be <= " + std::to_string(maximum) + ", got "
                           + std::string(text)};
    return value;
}

double parseNumber(std::string_view option, std::string_view text)
{
    const std::string s(text);
    char *end = nullptr;
    errno = 0;
    const double value = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(value))
        throw InvalidInput{std::string(option) + ": must be a finite number, got '" + s + "'"};
    return value;
}

const std::string *Options::last(std::string_view name) const
{
    const std::string *found = nullptr;
    for (const auto &[k, v] : named) {
        if (k == name)
            found = &v;
    }
    return found;
}

std::vector<std::string> Options::all(std::string_view name) const
{
    std::vector<std::string> out;
    for (const auto &[k, v] : named) {
        if (k == name)
            out.push_back(v);
    }
    return out;
}

Options parseOptions(const std::vector<std::string> &args, std::initializer_list<std::string_view> valued,
                     std::initializer_list<std::string_view> flags)
{
    const auto takes = [&] {
        std::string list;
        for (const auto *names : {&valued, &flags}) {
            for (std::string_view name : *names)
                list += (list.empty() ? "" : ", ") + std::string(name);
        }
        return list.empty() ? std::string(" (this command takes no options)") : " (this command takes " + list + ")";
    };
    Options o;
    bool wordsOnly = false;
    for (std::size_t k = 0; k < args.size(); ++k) {
        const std::string &a = args[k];
        if (wordsOnly || a == "-" || !a.starts_with('-')) {
            o.positional.push_back(a);
            continue;
        }
        if (a == "--") {
            wordsOnly = true;
            continue;
        }
        if (a == "--help" || a == "-h")
            throw HelpRequested{};
        // "-x" was taken for a second SCENE ("expected exactly one SCENE, got 2").
        if (!a.starts_with("--"))
            throw InvalidInput{a + ": unknown option" + takes()};
        std::string name = a;
        std::string value;
        bool hasValue = false;
        if (const auto eq = a.find('='); eq != std::string::npos) {
            name = a.substr(0, eq);
            value = a.substr(eq + 1);
            hasValue = true;
        }
        if (std::find(flags.begin(), flags.end(), name) != flags.end()) {
            if (hasValue)
                throw InvalidInput{name + ": takes no value, got '" + value + "'"};
            if (o.last(name))
                throw InvalidInput{name + ": given twice"};
            o.named.emplace_back(name, "");
            continue;
        }
        if (std::find(valued.begin(), valued.end(), name) == valued.end())
            throw InvalidInput{name + ": unknown option" + takes()};
        if (!hasValue) {
            // The next word is its value unless it is an option itself ("--frames --every 3"
            // took "--every" as the frame count; a value may start with one dash: "-1").
            if (k + 1 >= args.size() || args[k + 1].starts_with("--"))
                throw InvalidInput{name + ": missing value"};
            value = args[++k];
        }
        // Only --set adds up; another option given twice was taken at its last value without a
        // word ("--out a.csv --out b.csv" wrote b.csv alone).
        if (name != "--set") {
            if (const std::string *earlier = o.last(name))
                throw InvalidInput{name + ": given twice ('" + *earlier + "', then '" + value + "')"};
        }
        o.named.emplace_back(name, value);
    }
    return o;
}

std::string sceneLabel(const std::string &scene)
{
    return isStandardStream(scene) ? std::string("stdin") : printableText(scene);
}

namespace {

// All of standard input. A read that fails (a folder or a closed descriptor given as standard
// input) is said as such: it read as an empty text before ("the text is empty").
std::string readStandardInput()
{
    // Up to the loader's size limit: `yes | marbles-cli check -` had read on until memory ran out.
    std::string text;
    int error = 0;
    switch (readSceneText(STDIN_FILENO, text, error)) {
    case SceneRead::Whole:
        break;
    case SceneRead::TooLarge:
        throw InvalidInput{"stdin: " + sceneTooLarge("a scene", "more than that")};
    case SceneRead::Failed:
        throw InvalidInput{"stdin: cannot read: " + std::string(std::strerror(error))};
    }
    return text;
}

} // namespace

World loadWorld(const std::string &scene, const std::vector<std::string> &settings)
{
    if (scene.empty())
        throw InvalidInput{"SCENE: an empty file name"};
    World world;
    std::vector<std::string> notes;
    constexpr std::string_view presetPrefix = "preset:";
    if (scene.rfind(presetPrefix, 0) == 0) {
        const std::string id = scene.substr(presetPrefix.size());
        if (!makePreset(id, world)) {
            std::string known;
            for (const PresetInfo &p : presets())
                known += (known.empty() ? "" : ", ") + p.id;
            throw InvalidInput{scene + ": unknown preset (known: " + known + ")"};
        }
    } else {
        SceneLoad load;
        if (isStandardStream(scene)) {
            load = parseScene(readStandardInput(), sceneLabel(scene));
        } else {
            load = loadSceneFile(scene);
        }
        if (!load.ok && load.outOfMemory)
            throw OutOfMemory{load.error};
        if (!load.ok)
            throw InvalidInput{load.error};
        notes = std::move(load.notes);
        world = std::move(load.world);
    }
    for (const std::string &setting : settings) {
        const auto eq = setting.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InvalidInput{sceneLabel(scene) + ": --set" + (setting.empty() ? std::string() : " " + setting)
                               + ": expected KEY=VALUE"};
        // The file, the place and the rule, as a file's own error (it named the setting alone).
        const std::string error = setParam(world, setting.substr(0, eq), setting.substr(eq + 1));
        if (!error.empty())
            throw InvalidInput{sceneLabel(scene) + ": --set " + error}; // "KEY=VALUE: rule"
    }
    // The rule may be broken between the two (the file's friction 2.5 with --set model=exact):
    // both are named.
    if (const std::string error = validateParams(world.params); !error.empty())
        throw InvalidInput{sceneLabel(scene) + (settings.empty() ? "" : " with --set") + ": " + error};
    // Keys it does not read: the scene runs, and standard error says which (a misspelt "Friction"
    // had left the default in force without a word). Once the scene is taken: a refusal stays the
    // one message on standard error (INTERFACES.md).
    for (const std::string &note : notes)
        std::cerr << note << '\n';
    return world;
}

OutputFile::OutputFile(const std::string &option, const std::string &path)
    : m_path(path)
    , m_writer(checkedPath(option, path), SpecialFiles::WriteInPlace)
{
    throwIfFailed();
}

const std::string &OutputFile::checkedPath(const std::string &option, const std::string &path)
{
    // run and the scene writers take "-" as standard output before they open a file; bench and
    // stress print their tables there, which a CSV would be mixed into.
    if (isStandardStream(path))
        throw InvalidInput{option + " -: standard output carries this command's table; name a file"};
    if (path.empty())
        throw InvalidInput{option + ": an empty file name"};
    return path;
}

void OutputFile::write(std::string_view bytes)
{
    m_writer.write(bytes);
    throwIfFailed();
}

void OutputFile::commit()
{
    m_writer.commit();
    throwIfFailed();
}

void OutputFile::throwIfFailed() const
{
    if (m_writer.error().empty())
        return;
    const std::string message = m_path + ": cannot write: " + m_writer.error();
    if (m_writer.failedWhileWriting())
        throw WriteFailed{message};
    throw InvalidInput{message};
}

std::string formatNumber(double x, const char *spec, const char *missing)
{
    if (std::isnan(x))
        return missing;
    char buf[64];
    std::snprintf(buf, sizeof buf, spec, x);
    return buf;
}

namespace {

constexpr const char *usageText =
    "usage:\n"
    "  marbles-cli run SCENE [--frames N] [--every K] [--set KEY=VALUE ...] [--out FILE]\n"
    "  marbles-cli check SCENE [--set KEY=VALUE ...]\n"
    "  marbles-cli preset list | marbles-cli preset ID [--out FILE]\n"
    "  marbles-cli gen crowd --n N [--seed S] [--moving FRACTION] [--out FILE]\n"
    "  marbles-cli bench [--repeat R] [--csv FILE] [--plot FILE.png] [--crowd N]\n"
    "  marbles-cli bench --scale [--frames F] [--repeat R] [--max-n N] [--csv FILE]\n"
    "  marbles-cli stress [--quick] [--only TEXT] [--csv FILE]\n"
    "SCENE is a *.marbles.json file, '-' for standard input, or preset:ID (see 'preset list').\n"
    "--out - writes to standard output.\n";

// %.17g: 17 significant digits always round-trip a double exactly.
void appendNumber(std::string &out, double x)
{
    char buf[32];
    const int len = std::snprintf(buf, sizeof buf, "%.17g", x);
    out.append(buf, static_cast<std::size_t>(len));
}

void appendRows(std::string &out, const World &w)
{
    for (int i = 0; i < w.marbleCount(); ++i) {
        out += std::to_string(w.frame);
        out += ',';
        out += std::to_string(i);
        out += ',';
        appendNumber(out, w.position[i].x);
        out += ',';
        appendNumber(out, w.position[i].y);
        out += ',';
        appendNumber(out, w.velocity[i].x);
        out += ',';
        appendNumber(out, w.velocity[i].y);
        out += '\n';
    }
}

// Whether run's output would land on its own SCENE: --out naming it by any spelling or link, a
// scene read from standard input that is the --out file ("run - --out m.json < m.json"), or
// standard output going to the scene ("run m.json >> m.json").
bool writesOverScene(const std::string &scene, const std::string *outPath)
{
    if (scene.starts_with("preset:"))
        return false;
    // A standard stream's file when it is a regular one, a path's file: the same file when both
    // are there and have one device and inode.
    using FileId = std::pair<dev_t, ino_t>;
    const auto streamFile = [](int fd) -> std::optional<FileId> {
        struct stat s {};
        if (::fstat(fd, &s) == 0 && S_ISREG(s.st_mode))
            return FileId{s.st_dev, s.st_ino};
        return std::nullopt;
    };
    const auto pathFile = [](const std::string &path) -> std::optional<FileId> {
        struct stat s {};
        if (::stat(path.c_str(), &s) == 0)
            return FileId{s.st_dev, s.st_ino};
        return std::nullopt;
    };
    const auto same = [](const std::optional<FileId> &a, const std::optional<FileId> &b) { return a && b && *a == *b; };
    // "run - < s.json >> s.json": both streams open on one file (the CSV was appended to the
    // scene, or with 1<> written over its start).
    if (isStandardStream(scene))
        return same(streamFile(STDIN_FILENO), outPath ? pathFile(*outPath) : streamFile(STDOUT_FILENO));
    if (!outPath)
        return same(streamFile(STDOUT_FILENO), pathFile(scene));
    return namesSameFile(scene, *outPath);
}

int runCommand(const std::vector<std::string> &args)
{
    const Options o = parseOptions(args, {"--frames", "--every", "--set", "--out"});
    if (o.positional.size() != 1)
        throw InvalidInput{"run: expected exactly one SCENE, got " + std::to_string(o.positional.size())};
    const long long frames = o.last("--frames") ? parseInteger("--frames", *o.last("--frames"), 0) : 100;
    const long long every = o.last("--every") ? parseInteger("--every", *o.last("--every"), 1) : 1;
    // "--out -" is standard output, as "-" is standard input for SCENE.
    const std::string &scene = o.positional.front();
    const std::string *outPath = o.last("--out");
    if (outPath && isStandardStream(*outPath))
        outPath = nullptr;
    // The CSV would replace (or, on standard output, be added to) the scene being read.
    if (writesOverScene(scene, outPath))
        throw InvalidInput{(outPath ? "--out " + *outPath : std::string("standard output"))
                           + ": is SCENE, the file being read; name another file"};

    // The rows go out a megabyte at a time, to --out as to standard output: a long run's CSV is
    // never held whole in memory. --out is opened before the scene is read (a mistyped path
    // failed after a large scene had loaded) and replaced only once the run is over.
    std::optional<OutputFile> file;
    if (outPath)
        file.emplace("--out", *outPath);
    World world = loadWorld(scene, o.all("--set"));
    std::string csv = "frame,marble,x,y,vx,vy\n";
    auto flush = [&](bool force) {
        if (force || csv.size() > (1 << 20)) {
            if (file) {
                file->write(csv);
            } else if (std::fwrite(csv.data(), 1, csv.size(), stdout) != csv.size()) {
                // A full disk or a reader gone (a pipe into head): the run stops here.
                throw WriteFailed{std::string("writing to standard output failed: ") + std::strerror(errno)};
            }
            csv.clear();
        }
    };
    appendRows(csv, world);
    int status = ExitOk;
    std::string failure;
    // Frames in which the exact model held marbles where energy should have been kept (a marble
    // too fast to follow, or one wider than the stage): said once at the end (the rows had ended
    // in a stage at rest, with nothing to say why).
    long long firstHeld = -1;
    long long heldFrames = 0;
    int mostHeld = 0;
    for (long long f = 1; f <= frames; ++f) {
        const StepResult r = world.step();
        if (r.heldMarbles > 0 && heldMarblesBreakEnergy(world.params)) {
            if (firstHeld < 0)
                firstHeld = world.frame;
            ++heldFrames;
            mostHeld = std::max(mostHeld, r.heldMarbles);
        }
        if (!r.finite) {
            const Vec2 p = world.position[r.badMarble];
            const Vec2 v = world.velocity[r.badMarble];
            char state[160];
            std::snprintf(state, sizeof state, "x=%.6g, y=%.6g, vx=%.6g, vy=%.6g", p.x, p.y, v.x, v.y);
            failure = "frame " + std::to_string(world.frame) + ": marble " + std::to_string(r.badMarble)
                      + " left finite numbers (" + state + ")";
            status = ExitNonFinite;
            break;
        }
        if (f % every == 0)
            appendRows(csv, world);
        flush(false);
    }
    flush(true);
    if (file)
        file->commit();
    std::fflush(stdout);
    if (firstHeld >= 0) {
        std::cerr << sceneLabel(scene) << ": note: from frame " << firstHeld
                  << " on, the exact model held up to " << mostHeld << (mostHeld == 1 ? " marble" : " marbles") << " in "
                  << heldFrames << (heldFrames == 1 ? " frame" : " frames")
                  << " to finish them (at rest where a marble has more collisions in a frame than it can "
                     "follow; between two walls where it is wider than the stage); kinetic energy is not "
                     "conserved there\n";
    }
    if (status != ExitOk)
        std::cerr << sceneLabel(scene) << ": " << failure << '\n';
    return status;
}

int checkCommand(const std::vector<std::string> &args)
{
    const Options o = parseOptions(args, {"--set"});
    if (o.positional.size() != 1)
        throw InvalidInput{"check: expected exactly one SCENE, got " + std::to_string(o.positional.size())};
    // "check s.json >> s.json" had added its line to the scene, which then no longer loaded, and
    // said ok (a helper's finding; run refused it).
    if (writesOverScene(o.positional.front(), nullptr))
        throw InvalidInput{"standard output: is SCENE, the file being read; name another file"};
    const World w = loadWorld(o.positional.front(), o.all("--set"));
    auto plural = [](std::size_t n, const char *word) {
        const std::string w(word);
        return std::to_string(n) + " " + w + (n == 1 ? "" : (w.back() == 'h' ? "es" : "s"));
    };
    std::ostringstream line;
    line << sceneLabel(o.positional.front()) << ": ok: " << plural(w.radius.size(), "marble") << ", "
         << plural(w.pins.size(), "pin") << ", " << plural(w.pushes.size(), "push") << ", model "
         << modelName(w.params.model) << ", stage " << w.stage.width << "x" << w.stage.height << " walls "
         << (w.stage.walls ? "on" : "off") << '\n';
    std::cout << line.str();
    return ExitOk;
}

// --out's file, opened before the scene is made (a mistyped path failed only after gen had
// built its crowd, 40 s for ten million marbles), or none for standard output (no --out, or
// "--out -").
void openSceneOutput(const Options &o, std::optional<OutputFile> &file)
{
    if (const std::string *out = o.last("--out"); out && !isStandardStream(*out))
        file.emplace("--out", *out);
}

// A scene file to the file opened (replaced whole) or to standard output.
void writeScene(std::optional<OutputFile> &file, const World &w)
{
    const std::string json = sceneToJson(w);
    if (file) {
        file->write(json);
        file->commit();
    } else {
        std::cout << json;
    }
}

// What a command was given where it expected one word: "nothing" or the words, quoted.
std::string given(const std::vector<std::string> &positional)
{
    if (positional.empty())
        return "nothing";
    std::string words;
    for (const std::string &word : positional)
        words += (words.empty() ? "'" : " '") + word + "'";
    return words;
}

int presetCommand(const std::vector<std::string> &args)
{
    const Options o = parseOptions(args, {"--out"});
    if (o.positional.size() != 1)
        throw InvalidInput{"preset: expected 'list' or one preset ID, got " + given(o.positional)};
    if (o.positional.front() == "list") {
        if (o.last("--out"))
            throw InvalidInput{"preset list: --out is not used (the list goes to standard output)"};
        for (const PresetInfo &p : presets())
            std::cout << p.id << '\t' << p.title << '\t' << p.description << '\n';
        return ExitOk;
    }
    const World w = loadWorld("preset:" + o.positional.front(), {}); // an unknown ID is said first
    std::optional<OutputFile> file;
    openSceneOutput(o, file);
    writeScene(file, w);
    return ExitOk;
}

int genCommand(const std::vector<std::string> &args)
{
    const Options o = parseOptions(args, {"--n", "--seed", "--moving", "--out"});
    if (o.positional.size() != 1 || o.positional.front() != "crowd")
        throw InvalidInput{"gen: expected 'crowd', got " + given(o.positional)};
    if (!o.last("--n"))
        throw InvalidInput{"gen crowd: --n is required"};
    // At most what a scene file can hold: 2M marbles made a 329 MB file the loader refuses (its
    // limit is 256 MiB, about 165 bytes a marble), which gen wrote without a word.
    constexpr long long kMaxSceneCrowd = 1'500'000;
    const long long n = parseInteger("--n", *o.last("--n"), 0, kMaxSceneCrowd);
    const long long seed = o.last("--seed") ? parseInteger("--seed", *o.last("--seed"), 0) : 1;
    double moving = 1.0;
    if (const std::string *m = o.last("--moving")) {
        moving = parseNumber("--moving", *m);
        if (moving < 0 || moving > 1)
            throw InvalidInput{"--moving: must be in [0, 1], got " + *m};
    }
    std::optional<OutputFile> file;
    openSceneOutput(o, file);
    const World w = makeCrowd(static_cast<int>(n), static_cast<std::uint64_t>(seed), moving);
    writeScene(file, w);
    return ExitOk;
}

} // namespace

} // namespace marbles::cli

namespace {

// Ctrl+C, SIGTERM, a closed terminal: an interrupted write leaves no hidden temporary file (a
// run --out of a long run stopped so left 150 MB beside its target), then the signal ends the
// program as it would have.
extern "C" void onStopSignal(int signal)
{
    marbles::removeUnfinishedTemporaries();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

} // namespace

int main(int argc, char **argv)
{
    using namespace marbles::cli;
    for (int signal : {SIGINT, SIGTERM, SIGHUP})
        std::signal(signal, onStopSignal);
    // Past a file size limit a write fails (exit code 1, the old file kept), instead of SIGXFSZ
    // killing the program with its temporary file left behind.
    std::signal(SIGXFSZ, SIG_IGN);
    // A reader that goes away (run ... | head) is output that cannot be written, exit 1 as a full
    // disk is, not a death by SIGPIPE (exit 141 in a shell, with nothing said).
    std::signal(SIGPIPE, SIG_IGN);
    // Standard output that could not be written (a full disk behind a redirection) is a failure,
    // not a success with the rows cut short.
    const auto written = [](int code) {
        std::cout.flush();
        if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
            std::cerr << "writing to standard output failed: " << std::strerror(errno) << '\n';
            return code == ExitOk ? ExitInternal : code;
        }
        return code;
    };
    const std::vector<std::string> all(argv + 1, argv + argc);
    if (all.empty() || all.front() == "--help" || all.front() == "-h" || all.front() == "help") {
        if (all.empty()) {
            std::cerr << usageText;
            return ExitInvalid;
        }
        std::cout << usageText;
        return written(ExitOk);
    }
    const std::string command = all.front();
    const std::vector<std::string> args(all.begin() + 1, all.end());
    try {
        if (command == "run")
            return written(runCommand(args));
        if (command == "check")
            return written(checkCommand(args));
        if (command == "preset")
            return written(presetCommand(args));
        if (command == "gen")
            return written(genCommand(args));
        if (command == "bench")
            return written(benchCommand(args));
        if (command == "stress")
            return written(stressCommand(args));
        throw InvalidInput{"unknown command '" + command
                           + "' (the commands are run, check, preset, gen, bench and stress; 'marbles-cli --help' shows how to use them)"};
    } catch (const HelpRequested &) {
        // "marbles-cli run --help": the usage of that command (it was refused as an unknown option).
        // Its lines of the usage, and the notes on the words they use (SCENE, --out).
        std::string usage;
        std::string notes;
        const std::string_view text = usageText;
        const std::string prefix = "  marbles-cli " + command + ' ';
        for (std::size_t start = 0; start < text.size();) {
            const std::size_t end = text.find('\n', start);
            const std::string_view line = text.substr(start, end - start + 1);
            if (line.starts_with(prefix)) {
                usage += line;
            } else if (!line.starts_with(' ') && !line.starts_with("usage:")) {
                const std::string_view word = line.substr(0, line.find(' '));
                if (usage.find(word) != std::string::npos)
                    notes += line;
            }
            start = end + 1;
        }
        std::cout << "usage:\n" << usage << notes;
        return written(ExitOk);
    } catch (const InvalidInput &e) {
        std::cerr << marbles::printableText(e.message) << '\n';
        return ExitInvalid;
    } catch (const WriteFailed &e) {
        std::cerr << marbles::printableText(e.message) << '\n';
        return ExitInternal;
    } catch (const OutOfMemory &e) {
        std::cerr << marbles::printableText(e.message) << '\n';
        return ExitInternal;
    } catch (const std::bad_alloc &) {
        std::cerr << "internal error: not enough memory (std::bad_alloc)\n";
        return ExitInternal;
    } catch (const std::exception &e) {
        std::cerr << "internal error: " << marbles::printableText(e.what()) << '\n';
        return ExitInternal;
    }
}
