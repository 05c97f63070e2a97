// libFuzzer target for the scene loader. Besides "never crashes, hangs or leaks" (the sanitizers
// and libFuzzer's own limits check those), it checks a real property: a scene that loads can be
// saved and loaded again with every number bit-identical, every string and unknown key kept,
// and the saved text is a fixed point (saving the reloaded scene gives the same text). An input
// that starts with "set:" is instead a setting as `marbles-cli run --set KEY=VALUE` and the
// Parameters dock pass it to setParam(): refused, it must leave the scene as it was; accepted
// (and valid as a whole), the scene must still save and load back bit for bit.

#include "core/presets.h"
#include "core/sceneio.h"
#include "fuzz/samebits.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {

using namespace marbles;
using fuzzbits::same;

bool same(const Params &a, const Params &b)
{
    return a.model == b.model && same(a.massScale, b.massScale) && same(a.friction, b.friction)
        && same(a.zeroThreshold, b.zeroThreshold) && same(a.pushScale, b.pushScale) && same(a.frameMs, b.frameMs)
        && same(a.restitution, b.restitution) && same(a.gravity, b.gravity) && a.substeps == b.substeps
        && a.shortCircuit == b.shortCircuit;
}

bool samePushes(const std::vector<Push> &a, const std::vector<Push> &b)
{
    if (a.size() != b.size())
        return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].frame != b[i].frame || a[i].marble != b[i].marble || !same(a[i].at, b[i].at))
            return false;
    }
    return true;
}

/// The first part of the scene that differs between the two worlds, or nullptr.
const char *difference(const World &a, const World &b)
{
    if (!same(a.stage.width, b.stage.width) || !same(a.stage.height, b.stage.height) || a.stage.walls != b.stage.walls)
        return "stage";
    if (!same(a.params, b.params))
        return "params";
    if (!same(a.position, b.position))
        return "marble positions";
    if (!same(a.velocity, b.velocity))
        return "marble velocities";
    if (!same(a.radius, b.radius))
        return "marble radii";
    if (!same(a.mass, b.mass))
        return "marble masses";
    if (a.info != b.info)
        return "marble names, colours, explicit masses or unknown keys";
    if (!same(a.pins, b.pins))
        return "pins";
    if (a.pinExtraJson != b.pinExtraJson)
        return "unknown keys of pins";
    if (!samePushes(a.pushes, b.pushes))
        return "pushes";
    if (a.paramsExtraJson != b.paramsExtraJson || a.stageExtraJson != b.stageExtraJson
        || a.sceneExtraJson != b.sceneExtraJson)
        return "unknown keys of the scene, stage or params";
    if (a.frame != 0 || b.frame != 0)
        return "frame";
    return nullptr;
}

[[noreturn]] void failProperty(const char *what, const std::string &detail)
{
    std::fprintf(stderr, "fuzz_sceneio: round trip broken: %s\n%s\n", what, detail.c_str());
    std::abort();
}

/// Saves `world` and loads it back: it must load, with the same bits and the same text.
void checkRoundTrip(const World &world)
{
    const std::string saved = sceneToJson(world);
    const SceneLoad second = parseScene(saved, "saved");
    if (!second.ok)
        failProperty("the saved scene does not load", second.error + "\n" + saved);
    if (const char *what = difference(world, second.world))
        failProperty(what, saved);
    if (sceneToJson(second.world) != saved)
        failProperty("saving the reloaded scene gives different text", saved);
}

/// "KEY=VALUE" (up to the first '=') applied to the chapter's scene by setParam().
void checkSetting(std::string_view setting)
{
    const std::size_t eq = setting.find('=');
    const std::string_view key = setting.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view() : setting.substr(eq + 1);
    World world = defaultScene();
    const std::string before = sceneToJson(world);
    const std::vector<double> massesBefore = world.mass;
    const std::string error = setParam(world, key, value);
    if (!error.empty()) {
        // Refused whole, with one line that names the setting.
        if (sceneToJson(world) != before || !same(world.mass, massesBefore))
            failProperty("a refused setting changed the scene", error);
        if (error.find('\n') != std::string::npos || error.find(": ") == std::string::npos)
            failProperty("a refusal that is not one line naming the setting", error);
        return;
    }
    if (!validateParams(world.params).empty())
        return; // the CLI and the dock refuse it after all settings
    checkRoundTrip(world);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char *>(data), size);
    if (text.starts_with("set:")) {
        checkSetting(text.substr(4));
        return 0;
    }
    const SceneLoad first = parseScene(text, "input");
    if (!first.ok) {
        // A refusal must still be one message that names the source.
        if (first.error.rfind("input: ", 0) != 0 || first.error.size() <= 7)
            failProperty("refusal without a proper message", first.error);
        return 0;
    }
    checkRoundTrip(first.world);
    return 0;
}
