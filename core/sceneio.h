#pragma once

#include "core/world.h"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace marbles {

/// Largest scene text the loader accepts, in bytes (256 MiB); larger input is refused before it is read whole.
inline constexpr std::size_t kMaxSceneBytes = std::size_t{256} * 1024 * 1024;
/// Most memory the parsed JSON document of a scene may take, in bytes (1 GiB, estimated while
/// parsing): `[{},{},...]` costs about 27 times its size in memory, so the file limit alone
/// would still let a hostile 256 MiB file take 7 GiB.
inline constexpr std::size_t kMaxSceneMemoryBytes = std::size_t{1} << 30;
/// Most memory the World built from a scene may take, in bytes (1 GiB, estimated while parsing,
/// by its marbles, pins and pushes): 10 million marbles "{}", a 30 MB file, took 3.5 GB in all.
/// About 4.8 million marbles; the largest `gen crowd`, 1.5 million, takes 1.6 GB in all.
inline constexpr std::size_t kMaxSceneWorldBytes = std::size_t{1} << 30;
/// Deepest nesting of JSON arrays and objects the loader accepts (a scene needs 3 levels).
inline constexpr int kMaxSceneNesting = 256;
/// Largest `params.substeps` accepted: more would make one impulse-model frame take minutes.
inline constexpr int kMaxSubsteps = 1000000;
/// Radius of a marble whose scene entry gives none, px (the INTERFACES.md example marble).
inline constexpr double kDefaultMarbleRadius = 25.0;

/// Result of loading a scene: `world` holds it (frame 0) when `ok`, otherwise `error` says why.
struct SceneLoad {
    bool ok = false;
    World world;
    std::string error;
    /// The scene could not be read for want of memory (the scene itself may be valid).
    bool outOfMemory = false;
    /// When `ok`: the keys the scene holds that this program does not read, one line each
    /// ("<source>: params.Friction: not a key of params, so not used (did you mean friction?)"),
    /// the likely misspellings of a known key first, at most five, then how many more. They are
    /// kept when the scene is saved (INTERFACES.md).
    std::vector<std::string> notes;
    /// Some key is a near-miss of one this program reads (a different case, or an edit or two
    /// away): the scene most likely meant that key, whose default is in force instead.
    bool misspeltKeys = false;
};

/// Parses scene JSON text. `source` names it in messages: "<source>: <place>: <rule>".
SceneLoad parseScene(std::string_view text, std::string_view source);
/// The size rule a text too large broke: "size: <what> must be at most 268435456 bytes (256 MiB),
/// got <got>" (what: "a scene" or "a scene file"; got: its size, or "more than that").
std::string sceneTooLarge(std::string_view what, std::string_view got);
/// How readSceneText() ended.
enum class SceneRead { Whole, TooLarge, Failed };
/// Appends what `fd` holds, to its end, to `text`; stops once `text` holds more than
/// kMaxSceneBytes (TooLarge), whatever the input (a pipe or a device has no size to check
/// first, and may never end). On Failed, `error` is the errno of the failed read.
SceneRead readSceneText(int fd, std::string &text, int &error);
/// Reads a file and parses it; the message names the file as `shownAs`, or as given when that is
/// empty. ("-" is not special here.) A pipe or device is read up to the size limit; a named pipe
/// nothing writes to reads as empty, rather than waiting for a writer.
SceneLoad loadSceneFile(const std::string &path, std::string_view shownAs = {});
/// Serialises a world as a scene file: pretty JSON, unknown keys kept, numbers round-trip exactly.
/// The file starts at the world's current frame: its pushes are counted from it, and those of
/// earlier frames, which have acted, are left out; read back, the scene runs on as the world would.
std::string sceneToJson(const World &world);
/// Puts the scene file text of `world` (sceneToJson()) in `text`, and checks it: returns "" when it
/// loads back, else why it would not, as the loader says it ("marbles[0].x: must be a number, got null").
std::string sceneTextLoadingBack(const World &world, std::string &text);
/// Writes atomically (temporary file in the same folder, flushed, then renamed over the target);
/// returns "" on success or a message naming the file and the OS error. Never leaves a half-written
/// file, nor a file that would not load back (sceneTextLoadingBack()).
std::string saveSceneFile(const World &world, const std::string &path);
/// Checks params against the rules; returns "" or e.g. "params.friction: must be >= 0, got -1".
std::string validateParams(const Params &p);
/// Applies one KEY=VALUE setting (the CLI's --set, also used by the UI): keys are the params keys
/// (model, massScale, friction, zeroThreshold, pushScale, frameMs, restitution, gravity as "x,y",
/// substeps, shortCircuit as true/false/1/0) plus stage keys "width", "height", "walls".
/// massScale refreshes derived masses (World::setMassScale). Returns "" or a message naming the key and value.
/// Does NOT run the cross-field validation; callers call validateParams after all settings.
std::string setParam(World &world, std::string_view key, std::string_view value);
/// Text from outside (a file name, a key, a value, an OS message) made safe to print on one line:
/// the C0 controls and DEL, Unicode's line breaks beyond them (NEL U+0085, U+2028 and U+2029,
/// which a reader splitting lines may take as such) and bytes that are not UTF-8 each become '?';
/// characters that show nothing or reorder the text (U+FEFF, U+200B, the bidirectional controls)
/// are named, "<U+FEFF>"; beyond `maxBytes` the text is cut at a character boundary and marked "...".
std::string printableText(std::string_view text, std::size_t maxBytes = std::string_view::npos);

} // namespace marbles
