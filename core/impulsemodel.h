#pragma once

#include "core/broadphase.h"
#include "core/world.h"

namespace marbles {

/// The "impulse" model of PHYSICS.md, what games do: fixed sub-steps of h = 1/substeps frame,
/// each a semi-implicit Euler step (velocity first: drag factor (1-k)^h, gravity; then
/// position), followed by one pass that finds overlaps on a uniform grid and resolves each with
/// the exact model's momentum-conserving impulse plus a positional correction.
/// Its error against the exact model shrinks in proportion to h (first order).
class ImpulseModel final : public Stepper {
public:
    /// Advances `world` one frame. Consumes pending pushes as an instant velocity change;
    /// leaves acceleration zero; does not touch world.frame.
    void step(World &world) override;

private:
    UniformGrid m_marbleGrid; // rebuilt every sub-step; buffers reused
    UniformGrid m_pinGrid;    // rebuilt every frame
};

} // namespace marbles
