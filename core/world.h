#pragma once

#include "core/vec2.h"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace marbles {

/// The three physics models of PHYSICS.md.
enum class ModelKind { Book, Impulse, Exact };

/// "book", "impulse" or "exact".
std::string_view modelName(ModelKind kind);
/// Parses "book", "impulse" or "exact"; false for anything else.
bool parseModelName(std::string_view name, ModelKind &kind);

/// Scene `params`, with the book's defaults (PHYSICS.md, "Parameters").
struct Params {
    ModelKind model = ModelKind::Book;
    double massScale = 1.25;     ///< mass per px of radius
    double friction = 0.1;       ///< k: fraction of velocity given up per frame
    double zeroThreshold = 0.01; ///< Z: |v component| <= Z becomes exactly 0 (px/frame)
    double pushScale = 10.0;     ///< click force multiplier
    double frameMs = 20.0;       ///< wall-clock length of one frame, ms (the physics never sees it)
    double restitution = 1.0;    ///< e in [0, 1], impulse and exact models
    Vec2 gravity;                ///< px/frame^2
    int substeps = 1;            ///< impulse model: sub-steps per frame
    bool shortCircuit = false;   ///< book model: first hit ends a marble's tests for the frame

    friend bool operator==(const Params &, const Params &) = default;
};

/// Whether a marble held at rest to finish a frame (StepResult::heldMarbles) is worth a word:
/// with e = 1 and no gravity the exact model holds one only where it cannot follow it (a marble
/// too fast for the frame's event budget, or wedged where it cannot fit), and kinetic energy is
/// then not conserved; with e < 1 or gravity it holds marbles that come to rest, as it should.
inline bool heldMarblesBreakEnergy(const Params &p)
{
    return p.restitution == 1.0 && p.gravity.x == 0.0 && p.gravity.y == 0.0;
}

/// The stage rectangle [0, width] x [0, height] in px, and whether its edges are walls.
struct Stage {
    double width = 800.0;
    double height = 600.0;
    bool walls = true;

    friend bool operator==(const Stage &, const Stage &) = default;
};

/// A scripted click: acts on the update from `frame` to `frame + 1` (PHYSICS.md, "Push").
struct Push {
    std::int64_t frame = 0;
    int marble = 0;
    Vec2 at; ///< the click point, px
    std::string extraJson; ///< unknown keys of the push in its file ("" when none), kept when saved

    friend bool operator==(const Push &, const Push &) = default;
};

/// What a marble carries besides its physics: for the UI and for lossless saving.
struct MarbleInfo {
    std::string name;
    std::string color;      ///< "#rrggbb", or empty for the default blue
    bool hasMass = false;   ///< true when the scene gave `mass` explicitly
    std::string extraJson;  ///< unknown keys of this marble, as a JSON object text ("" when none)

    friend bool operator==(const MarbleInfo &, const MarbleInfo &) = default;
};

/// A marble's most recent reflection, for the chapter's Figure 11.12 overlay.
/// All three vectors are unit length, as the book draws them.
struct HitRecord {
    std::int64_t frame = -1; ///< frame the hit produced; -1 = never hit
    Vec2 velocityIn;         ///< normalised velocity before the reflection
    Vec2 normal;             ///< normalised collision vector (towards the pin or the other marble)
    Vec2 velocityOut;        ///< normalised velocity after the reflection

    friend bool operator==(const HitRecord &, const HitRecord &) = default;

    /// The record of a hit produced in `frame` that turned velocity `in` into `out` along the
    /// unit `normal`: both velocities normalised (zero where they have no direction).
    static HitRecord of(std::int64_t frame, Vec2 in, Vec2 normal, Vec2 out)
    {
        return {frame, unitOrZero(in), normal, unitOrZero(out)};
    }
};

/// Outcome of one frame.
struct StepResult {
    bool finite = true;  ///< false when a marble left finite numbers
    int badMarble = -1;  ///< the first such marble, in scene order
    int heldMarbles = 0; ///< marbles the model held to finish the frame (Stepper::lastHeldCount())
};

class World;

/// One physics model: advances a world by one frame. Implementations may keep caches
/// (grids, event calendars) but never state that changes results: the same World state
/// always steps to the same next state, bit for bit, whatever the model saw before.
class Stepper {
public:
    virtual ~Stepper() = default;
    /// Advances `world` from frame f to f + 1. Scripted pushes for frame f have already been
    /// added to the marbles' pending acceleration; the stepper consumes it and leaves it zero.
    /// Does not touch world.frame.
    virtual void step(World &world) = 0;
    /// Marbles the last step() held to finish it (the exact model's guards against endless
    /// collision sequences: at rest for the rest of the frame, or a marble wider than the stage
    /// stopped between its walls); 0 for models without such guards.
    virtual int lastHeldCount() const { return 0; }
    /// True when the last step() left every marble's position and velocity finite, as the model
    /// made sure on its way (World::step() then skips its own pass over them: at 100k marbles,
    /// 3.2 MB read each frame); false when it does not know.
    virtual bool leftAllFinite() const { return false; }
};

/// The simulated world: stage, parameters, marbles (structure of arrays, index = scene order),
/// pins and scripted pushes. Copyable: a copy is a full snapshot of the state.
class World {
public:
    World();
    ~World();
    World(const World &other);
    World &operator=(const World &other);
    World(World &&) noexcept;
    World &operator=(World &&) noexcept;

    Stage stage;
    Params params;

    // Marbles, structure of arrays. All vectors have marbleCount() entries.
    std::vector<Vec2> position;      ///< px
    std::vector<Vec2> velocity;      ///< px/frame
    std::vector<Vec2> acceleration;  ///< px/frame^2, pending (pushes); zero after every frame
    std::vector<double> radius;      ///< px, > 0
    std::vector<double> mass;        ///< massScale * radius unless info[i].hasMass
    std::vector<MarbleInfo> info;
    std::vector<HitRecord> lastHit;

    std::vector<Vec2> pins;               ///< fixed points, px
    std::vector<std::string> pinExtraJson; ///< unknown keys of each pin ("" when none)
    std::vector<Push> pushes;             ///< scripted clicks, in file order

    std::string paramsExtraJson; ///< unknown keys inside "params"
    std::string stageExtraJson;  ///< unknown keys inside "stage"
    std::string sceneExtraJson;  ///< unknown top-level keys

    std::int64_t frame = 0; ///< frames simulated since the scene was loaded

    /// Number of marbles.
    int marbleCount() const { return static_cast<int>(radius.size()); }
    /// What each marble, pin and scripted push takes in the World's arrays, bytes (text held on
    /// the heap by strings not counted).
    static constexpr std::size_t kMarbleBytes =
        3 * sizeof(Vec2) + 2 * sizeof(double) + sizeof(MarbleInfo) + sizeof(HitRecord);
    static constexpr std::size_t kPinBytes = sizeof(Vec2) + sizeof(std::string);
    static constexpr std::size_t kPushBytes = sizeof(Push);
    /// About what this World takes, bytes, by those costs.
    std::size_t approximateBytes() const
    {
        return sizeof(World) + radius.size() * kMarbleBytes + pins.size() * kPinBytes + pushes.size() * kPushBytes;
    }

    /// Appends a marble; mass = massScale * radius unless `explicitMass` > 0. Returns its index.
    int addMarble(Vec2 p, double r, Vec2 v = {}, double explicitMass = 0.0);
    /// Removes marble i; later marbles shift down and pushes are renumbered (those naming i are dropped).
    void removeMarble(int i);
    /// Appends a pin; returns its index.
    int addPin(Vec2 q);
    /// Removes pin j.
    void removePin(int j);

    /// Sets radius of marble i and refreshes its derived mass.
    void setRadius(int i, double r);
    /// Gives marble i an explicit mass (> 0), or back to massScale * radius with 0.
    void setExplicitMass(int i, double m);
    /// Changes massScale and refreshes every derived mass.
    void setMassScale(double s);
    /// Recomputes mass[i] = massScale * radius[i] for marbles without an explicit mass.
    void refreshMasses();

    /// The chapter's hitMarble: a click at `at` adds (p - at) * pushScale / m to marble i's
    /// pending acceleration, so it acts on the next update. Exact and impulse models apply it
    /// as an instant velocity change at the start of that update.
    void push(int i, Vec2 at);
    /// A push waiting in an acceleration `a`, worked out again for a new mass or push scale.
    /// PHYSICS.md's push reads m_i and pushScale just before the update it acts on, so a click's
    /// push waiting for the next frame follows an edit of either, as a scripted push does: from
    /// a = (p - c) * pushScaleWas / massWas it gives (p - c) * pushScale / mass, to rounding.
    static Vec2 rescaledPush(Vec2 a, double massWas, double pushScaleWas, double mass, double pushScale);
    /// Whether marble i has a push still to act (its pending acceleration is not zero).
    bool pushPending(int i) const
    {
        const Vec2 a = acceleration[static_cast<std::size_t>(i)];
        return a.x != 0.0 || a.y != 0.0;
    }
    /// Applies the scripted pushes of the current frame (those in `pushes` for `frame`), in file
    /// order, as step() does before the model runs.
    void applyScriptedPushes();
    /// Whether the next step() applies scripted push `p` (it is for this frame, on a marble
    /// that exists).
    bool appliesNow(const Push &p) const { return p.frame == frame && p.marble >= 0 && p.marble < marbleCount(); }
    /// What the scripted pushes of the current frame will add to marble i's acceleration on the
    /// next step() (zero when none is due), as push() computes it.
    Vec2 scriptedPushDue(int i) const;

    /// Advances one frame with params.model: scripted pushes for this frame, then the model.
    /// Returns whether every marble is still finite.
    StepResult step();
    /// The first marble, in scene order, whose position or velocity is not finite; -1 when none.
    int firstNonFiniteMarble() const;

    /// Kinetic energy, sum of m v^2 / 2 (mass px^2/frame^2).
    double kineticEnergy() const;
    /// Total momentum, sum of m v (mass px/frame).
    Vec2 momentum() const;

private:
    /// What a click at `at` adds to marble i's acceleration.
    Vec2 pushAcceleration(int i, Vec2 at) const;

    std::unique_ptr<Stepper> m_stepper;
    ModelKind m_stepperKind = ModelKind::Book;
};

/// Creates the stepper for a model (used by World::step; exposed for tests and benchmarks).
std::unique_ptr<Stepper> makeStepper(ModelKind kind);

} // namespace marbles
