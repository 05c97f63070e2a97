// libFuzzer target for the scene loader. Besides "never crashes, hangs or leaks" (the sanitizers
// and libFuzzer's own limits check those), it checks a real property: a scene that loads can be
// saved and loaded again with every number bit-identical, every string and unknown key kept,
// and the saved text is a fixed point (saving the reloaded scene gives the same text).

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

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char *>(data), size);
    const SceneLoad first = parseScene(text, "input");
    if (!first.ok) {
        // A refusal must still be one message that names the source.
        if (first.error.rfind("input: ", 0) != 0 || first.error.size() <= 7)
            failProperty("refusal without a proper message", first.error);
        return 0;
    }
    const std::string saved = sceneToJson(first.world);
    const SceneLoad second = parseScene(saved, "saved");
    if (!second.ok)
        failProperty("the saved scene does not load", second.error + "\n" + saved);
    if (const char *what = difference(first.world, second.world))
        failProperty(what, saved);
    if (sceneToJson(second.world) != saved)
        failProperty("saving the reloaded scene gives different text", saved);
    return 0;
}
