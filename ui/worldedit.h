#pragma once

#include "core/world.h"

#include <optional>
#include <vector>

namespace marbles {

/// Everything a World holds about one marble, so that it can be removed and put back exactly.
struct MarbleRecord {
    Vec2 position;
    Vec2 velocity;
    Vec2 acceleration;
    double radius = 0.0;
    double mass = 0.0;
    MarbleInfo info;
    HitRecord lastHit;
};

/// Copies marble i out of `world`.
MarbleRecord marbleRecord(const World &world, int i);
/// Inserts `record` as marble i (0 <= i <= marbleCount()); later marbles shift up, pushes are renumbered.
void insertMarble(World &world, int i, const MarbleRecord &record);
/// Inserts pin `q` at index j (0 <= j <= pin count), with its unknown keys `extraJson`.
void insertPin(World &world, int j, Vec2 q, const std::string &extraJson = {});

/// The marble whose disc contains `p` (the last one drawn, i.e. the highest index, wins), or -1.
int marbleAt(const World &world, Vec2 p);
/// The pin nearest to `p` within `tolerancePx`, or -1.
int pinAt(const World &world, Vec2 p, double tolerancePx);

/// What a spot must keep clear of.
enum class BodyKind { Marble, Pin };

/// Drawn radius of a pin's dot (PinItem), stage px.
constexpr double kPinDotRadiusPx = 4.0;

/// True when a marble of radius `r` (or a pin, for BodyKind::Pin) at `p` lies on the stage and
/// overlaps nothing, with the physics' own tests: marbles overlap when their distance is below the
/// sum of radii, a pin is inside a marble when its distance is at most the radius. A pin also
/// keeps its dot clear of the other pins' (two dots apart): the physics would take two pins at
/// one place, but the class would see one (a helper's pin dropped on another stayed 0.5 px off it).
/// Marble `ignoreMarble` and pin `ignorePin` (the body being placed) are not tested.
bool isFreeSpot(const World &world, Vec2 p, double r, BodyKind kind, int ignoreMarble = -1, int ignorePin = -1);

/// The free spot nearest to `p`, searched on rings of growing radius (2 px apart) out to
/// `maxDistancePx` around the nearest place on the stage (`p` itself when on it); that place when
/// it is free; nothing when no spot is free.
std::optional<Vec2> nearestFreeSpot(const World &world, Vec2 p, double r, BodyKind kind, int ignoreMarble = -1,
                                    int ignorePin = -1, double maxDistancePx = 400.0);

} // namespace marbles
