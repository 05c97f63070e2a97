#include "ui/worldedit.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace marbles {

MarbleRecord marbleRecord(const World &world, int i)
{
    assert(i >= 0 && i < world.marbleCount());
    MarbleRecord r;
    if (i < 0 || i >= world.marbleCount())
        return r;
    r.position = world.position[i];
    r.velocity = world.velocity[i];
    r.acceleration = world.acceleration[i];
    r.radius = world.radius[i];
    r.mass = world.mass[i];
    r.info = world.info[i];
    r.lastHit = world.lastHit[i];
    return r;
}

void insertMarble(World &world, int i, const MarbleRecord &record)
{
    assert(i >= 0 && i <= world.marbleCount());
    if (i < 0 || i > world.marbleCount())
        return;
    world.position.insert(world.position.begin() + i, record.position);
    world.velocity.insert(world.velocity.begin() + i, record.velocity);
    world.acceleration.insert(world.acceleration.begin() + i, record.acceleration);
    world.radius.insert(world.radius.begin() + i, record.radius);
    world.mass.insert(world.mass.begin() + i, record.mass);
    world.info.insert(world.info.begin() + i, record.info);
    world.lastHit.insert(world.lastHit.begin() + i, record.lastHit);
    for (Push &p : world.pushes) {
        if (p.marble >= i)
            ++p.marble;
    }
}

void insertPin(World &world, int j, Vec2 q, const std::string &extraJson)
{
    const int count = static_cast<int>(world.pins.size());
    assert(j >= 0 && j <= count);
    if (j < 0 || j > count)
        return;
    world.pins.insert(world.pins.begin() + j, q);
    world.pinExtraJson.insert(world.pinExtraJson.begin() + j, extraJson);
}

int marbleAt(const World &world, Vec2 p)
{
    for (int i = world.marbleCount() - 1; i >= 0; --i) {
        if (distance(world.position[i], p) <= world.radius[i])
            return i;
    }
    return -1;
}

int pinAt(const World &world, Vec2 p, double tolerancePx)
{
    int best = -1;
    double bestDistance = tolerancePx;
    for (int j = 0; j < static_cast<int>(world.pins.size()); ++j) {
        const double d = distance(world.pins[j], p);
        if (d <= bestDistance) {
            best = j;
            bestDistance = d;
        }
    }
    return best;
}

bool isFreeSpot(const World &world, Vec2 p, double r, BodyKind kind, int ignoreMarble, int ignorePin)
{
    if (!isFinite(p))
        return false;
    const double margin = kind == BodyKind::Marble ? r : 0.0;
    if (p.x - margin < 0.0 || p.y - margin < 0.0 || p.x + margin > world.stage.width
        || p.y + margin > world.stage.height)
        return false;
    for (int i = 0; i < world.marbleCount(); ++i) {
        if (i == ignoreMarble)
            continue;
        const double d = distance(world.position[i], p);
        if (kind == BodyKind::Marble ? d < r + world.radius[i] : d <= world.radius[i])
            return false;
    }
    // A marble keeps clear of the pins' centres, a pin of their dots.
    const double pinReach = kind == BodyKind::Marble ? r : 2.0 * kPinDotRadiusPx;
    for (int j = 0; j < static_cast<int>(world.pins.size()); ++j) {
        if (j != ignorePin && (kind == BodyKind::Marble ? distance(world.pins[j], p) <= pinReach
                                                        : distance(world.pins[j], p) < pinReach))
            return false;
    }
    return true;
}

std::optional<Vec2> nearestFreeSpot(const World &world, Vec2 p, double r, BodyKind kind, int ignoreMarble,
                                    int ignorePin, double maxDistancePx)
{
    // A drop off the stage comes onto it, at the stage's nearest edge: a pin dragged below the
    // stage had been refused as "no free spot near (360, 1539)", and a marble dropped past a
    // wall came back 2 px rings short of it (779.99 for 780; a helper's findings).
    const double margin = kind == BodyKind::Marble ? r : 0.0;
    if (isFinite(p) && world.stage.width >= 2.0 * margin && world.stage.height >= 2.0 * margin) {
        p.x = std::clamp(p.x, margin, world.stage.width - margin);
        p.y = std::clamp(p.y, margin, world.stage.height - margin);
    }
    if (isFreeSpot(world, p, r, kind, ignoreMarble, ignorePin))
        return p;
    constexpr double ringStepPx = 2.0;
    for (double d = ringStepPx; d <= maxDistancePx; d += ringStepPx) {
        // Candidates about 2 px apart along the ring; the first free one is as near as any other.
        const int count = std::max(8, static_cast<int>(std::ceil(2.0 * std::numbers::pi * d / ringStepPx)));
        for (int k = 0; k < count; ++k) {
            const double angle = 2.0 * std::numbers::pi * k / count;
            const Vec2 q{p.x + d * std::cos(angle), p.y + d * std::sin(angle)};
            if (isFreeSpot(world, q, r, kind, ignoreMarble, ignorePin))
                return q;
        }
    }
    return std::nullopt;
}

} // namespace marbles
