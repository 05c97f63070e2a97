#pragma once

#include "core/world.h"

namespace marbles {

/// The chapter's updateMarbles(), verbatim (PHYSICS.md, model "book"): one explicit update per
/// frame, marbles processed in scene order and in place, with the book's arithmetic, flaws included.
class BookModel final : public Stepper {
public:
    /// Advances one frame. Consumes pending pushes (acceleration) and leaves it zero.
    void step(World &world) override;
};

/// The book's reflection off a pin at `pin` for a marble restored to `p` moving with `v`:
/// returns false (and leaves `v` alone) where the book would divide by zero.
bool bookReflectOffPin(Vec2 p, Vec2 pin, Vec2 &v, HitRecord *record = nullptr);

/// The book's marble-to-marble response: marble i (restored to `pi`, velocity `vi`, mass `mi`)
/// hit marble j (at `pj`, velocity `vj`, mass `mj`). Returns false, leaving both velocities
/// alone, where the book would divide by zero.
bool bookShareCollision(Vec2 pi, Vec2 &vi, double mi, Vec2 pj, Vec2 &vj, double mj,
                        HitRecord *record = nullptr);

} // namespace marbles
