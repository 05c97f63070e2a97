#pragma once

#include "core/broadphase.h"
#include "core/world.h"

#include <cstdint>
#include <vector>

namespace marbles {

/// The "impulse" model of PHYSICS.md, what games do: fixed sub-steps of h = 1/substeps frame,
/// each a semi-implicit Euler step (velocity first: drag factor (1-k)^h, gravity; then
/// position), followed by one pass that finds overlaps on a uniform grid and resolves each with
/// the exact model's momentum-conserving impulse plus a positional correction.
/// Its error against the exact model shrinks in proportion to h (first order).
///
/// Pairs are resolved one after another (each sees the corrections of the ones before). Each
/// sub-step copies the marbles into bucket order (a stable counting sort), and pairs are taken
/// in that order: bucket by bucket in row-major order, each marble with the later marbles of
/// its bucket and then with the forward half of its neighbourhood. Neighbours are thus side by
/// side in memory, and every candidate is examined once.
class ImpulseModel final : public Stepper {
public:
    /// Advances `world` one frame. Consumes pending pushes as an instant velocity change;
    /// leaves acceleration zero; does not touch world.frame.
    void step(World &world) override;

private:
    /// A marble's shape and place, in bucket order (what the distance test reads).
    struct Body {
        double x;
        double y;
        double r;
        int id; ///< index in the world (scene order)
    };
    /// A marble's velocity and inverse mass, in bucket order (read only for overlapping pairs).
    struct Motion {
        double vx;
        double vy;
        double invMass;
    };

    void sortIntoBuckets(const World &world);
    void resolvePairs(World &world, double e, std::int64_t hitFrame);

    GridGeometry m_geometry;
    UniformGrid m_pinGrid;          // rebuilt every frame
    std::vector<int> m_bucketOf;    // per marble (scene order): its bucket this sub-step
    std::vector<int> m_start;       // per bucket: first slot; m_start[bucketCount] = n
    std::vector<Body> m_bodies;     // per slot
    std::vector<Motion> m_motions;  // per slot
};

} // namespace marbles
