#pragma once

#include "core/world.h"
#include "ui/comparerun.h"
#include "ui/scenedocument.h"

#include <vector>

namespace marbles::test {

/// The document's and the comparison's worlds at each frame of a run, index = frames run.
struct BothRuns {
    std::vector<World> ours;
    std::vector<World> theirs;
};

/// Runs `doc` on `frames` frames one at a time from where it is, with `compare` beside it
/// (tracking), noting both worlds before the first and after each.
inline BothRuns runBoth(SceneDocument &doc, const CompareRun &compare, int frames)
{
    BothRuns run{{doc.world()}, {*compare.world()}};
    for (int f = 1; f <= frames; ++f) {
        doc.advance(1);
        run.ours.push_back(doc.world());
        run.theirs.push_back(*compare.world());
    }
    return run;
}

} // namespace marbles::test
