#pragma once

#include "core/broadphase.h"
#include "core/largebuffer.h"
#include "core/world.h"

#include <cstdint>
#include <vector>

namespace marbles {

/// The "exact" model of PHYSICS.md: an event-driven simulation in continuous time. Between
/// events every marble moves exactly under linear drag and gravity; collisions (marble-marble,
/// marble-pin, marble-wall) happen at their exact time of contact and are resolved by an
/// impulse along the contact normal with restitution e. See exactmodel.cpp for the derivations.
///
/// Data structures (designed for 1e5 marbles and more, cost linear in N): each frame the marbles
/// are renumbered in the order of a folded uniform grid, so that neighbours lie side by side in
/// memory, in 64-byte records that hold all a neighbour test reads. Each marble is "anchored" in
/// a cell a margin wider than the contact distance and needs a grid event only when it strays
/// further than the margin from its anchor within one frame. A few marbles far larger than the
/// rest (RadiusSplit) are left out of the grid: every marble looks at them, they at what they can
/// reach. Per marble the calendar keeps its best contact and that next grid event; a calendar
/// queue (time slots over the frame) holds only the marbles with an event inside the frame, and
/// per-marble collision stamps reveal stale partner events lazily.
/// All buffers are kept between frames (no allocation in steady state) and are rebuilt from the
/// World at the start of every frame, so they are caches only; the one exception, the layer
/// that keeps marbles at rest out of that rebuilding (Sleeping), is checked against the World
/// every frame instead.
class ExactModel final : public Stepper {
public:
    /// With e < 1 only: after this many marble-marble or marble-pin collisions of a marble within
    /// one frame, its further collisions in that frame are elastic (inelastic-collapse guard).
    static constexpr int elasticAfterCollisions = 32;
    /// With e < 1 only: after this many marble-marble or marble-pin collisions of a marble within
    /// one frame, it is frozen (held at rest as an immovable body) until the frame ends.
    static constexpr int freezeAfterCollisions = 256;
    /// After this many re-checks (curved paths under gravity whose contact test did not conclude)
    /// of a marble within one frame, it is frozen likewise, whatever e.
    static constexpr int freezeAfterRechecks = 1024;
    /// After this many resting contacts (marble-marble or marble-pin contacts approaching slower
    /// than sqrt(2 |g| restHeightPx)) of a marble within one frame, it is frozen likewise.
    static constexpr int freezeAfterRestingContacts = 16;
    /// Whatever e: after this many marble-marble or marble-pin collisions of a marble within one
    /// frame, it is frozen likewise. Only a marble wedged where it cannot fit (overlapping two
    /// pins, or squeezed between a wall and marbles that the other wall sends back) comes near:
    /// with e = 1 it would go from one contact straight into the next at the same instant for ever.
    static constexpr int freezeAfterElasticCollisions = 1 << 14;
    /// Whatever e: once more than this many events per marble of the world (on average;
    /// collisions and re-checks, not grid events) happen at one and the same instant, every
    /// marble that collides again at that instant is frozen likewise. Marbles wedged where they
    /// cannot fit bounce between their contacts without time passing; real simultaneous
    /// collisions (a Newton's cradle, a symmetric break) are a few per marble.
    static constexpr int freezeAfterInstantCollisions = 64;
    /// Whatever e: after this many wall bounces of a marble within one frame, it is frozen.
    /// (Elastic motion stays far below: at 1e6 px/frame across a 1,000 px stage a marble bounces
    /// about a thousand times.)
    static constexpr int freezeAfterWallBounces = 1 << 16;
    /// A wall bounce that would rise less than this height against gravity (px) becomes resting
    /// contact: the marble slides along the wall until something lifts it off.
    static constexpr double restHeightPx = 1e-3;
    /// Up to this many bodies (marbles and pins) all pairs are tested, without a grid.
    static constexpr int singleCellItems = 64;
    /// A marble may stray this fraction of the largest contact distance from its anchor (its
    /// position at the start of the frame) before it needs a grid event; grid cells are wider by
    /// twice that margin. (In a sparse scene, up to twice the marbles' mean travel in a frame:
    /// see beginFrame().)
    static constexpr double anchorMargin = 0.25;
    /// From this many marbles on, each event also requests the records of the marbles that the
    /// next events will scan, ahead of time. Measured on the crowd at frames 201-220 (one core,
    /// 1 MB of L2): 5 % slower at 30k marbles (3.8 MB of records, which the caches mostly hold),
    /// no change at 60k, 6 % faster at 100k.
    static constexpr int prefetchEventsFrom = 1 << 16;
    /// From this many marbles on, when nearly all of them sleep, the sleepers are kept out of
    /// the frame's arrays (see Sleeping): the layer is built when the last frame left at least
    /// 15/16 of the marbles at rest, and dropped when fewer than 7/8 sleep. Measured on the 100k
    /// crowd with 1 % moving, stepped with and without the layer in turns (one core): 2.6 against
    /// 3.7 ms per frame while 3.5 % move, 3.2 against 4.0 at 7.5 %, 4.3 against 5.0 at 12 %, and
    /// slower than without from about 15 %; 0.9 against 2.3 ms with every marble at rest (1k:
    /// 0.007 against 0.019 ms; 500 marbles with 1 % moving, frames 2-11: 0.005 against 0.010).
    static constexpr int sleepingLayerFrom = 256;

    /// Where the marbles at rest are kept between frames. A sleeper (velocity and pending push
    /// exactly +0, no gravity, finite) cannot move until something runs into it, so instead of
    /// being read, renumbered and written back every frame like the moving marbles, it stays in
    /// a layer kept from frame to frame, and joins the frame's arrays only when a moving marble
    /// comes within reach of it. Every frame checks the layer against the World (an edit, a push
    /// or a jump back in time wakes the marbles it changed), and ties are broken by the place
    /// each marble would have among all of them, so the results are the same bits either way.
    enum class Sleeping : std::uint8_t {
        Auto,   ///< from sleepingLayerFrom marbles, when nearly all sleep (see there)
        Always, ///< whenever there is no gravity and the grid is used (for tests)
        Never,  ///< every marble is read every frame
    };

    ExactModel();
    ~ExactModel() override;

    /// Advances `world` one frame (PHYSICS.md, model "exact"). Consumes pending pushes as an
    /// instant velocity change; leaves acceleration zero; does not touch world.frame.
    void step(World &world) override;

    /// Where the next frames keep the marbles at rest (Sleeping::Auto unless set).
    void setSleeping(Sleeping use) { m_sleepingUse = use; }
    /// Sleepers the last frame left alone: neither read nor written (0 without the layer).
    int lastSleepingCount() const { return m_layer ? m_layerLive - (m_count - m_awake) : 0; }

    /// Whether a few marbles far larger than the rest are left out of the grid (RadiusSplit; on
    /// unless set). Off, the grid is sized from the largest radius. For tests and benchmarks.
    void setSplitRadii(bool on) { m_splitRadii = on; }
    /// Marbles the last frame left out of the grid as oversize (RadiusSplit).
    int lastOversizeCount() const { return m_oversize; }
    /// How far, px, a marble could stray from its anchor in the last frame before a grid event
    /// (anchorMargin of the contact distance, or more in a sparse scene: see beginFrame()).
    double lastAnchorMargin() const { return m_margin; }

    /// Events handled in the last frame: collisions, grid events and re-predictions.
    std::int64_t lastEventCount() const { return m_eventCount; }
    /// Collisions (impulses applied) in the last frame.
    std::int64_t lastCollisionCount() const { return m_collisionCount; }
    /// Marbles the guard against endless collision sequences froze in the last frame (0 with e = 1
    /// and no gravity).
    int lastFrozenCount() const { return m_frozenCount; }
    /// The frozen marbles, and the marbles wider than the stage stopped between its walls (one
    /// that met a wall moving across it: kinetic energy lost, whatever e), each counted once.
    int lastHeldCount() const override { return m_frozenCount + m_pinchedCount; }
    bool leftAllFinite() const override { return m_leftAllFinite; }

private:
    enum class EventKind : std::uint8_t { Wall, Pin, Pair, Cross, RecheckPin, RecheckPair, None };

    struct Event {
        double time = 0.0;   // absolute time within the frame, frames in [0, 1]
        EventKind kind = EventKind::None;
        int other = -1;      // partner marble, pin index, wall (0..3) or margin side (0..3)
        std::uint32_t stamp = 0; // the partner's stamp when predicted (pairs only)
    };
    // What a neighbour test reads of a marble, in one cache line. The trajectory in frame time t
    // is p(t) = a + b phi1(t) + g phi2(t) (see the .cpp).
    struct alignas(64) Body {
        Vec2 a;
        Vec2 b;
        double radius = 0.0;
        double contactTime = 0.0;    // time of its best contact (infinity: none)
        int bucket = 0;              // bucket of its anchor cell (-1: oversize, in none)
        int id = 0;                  // index in the World
        int rank = 0;                // place in the order of ties (see the .cpp, point 4)
        std::uint8_t gravityOff = 0; // bit 0: no gravity along x (held on a wall, or frozen), bit 1: y
        std::uint8_t frozen = 0;
        std::uint8_t moved = 0;      // anchored outside the bucket it was sorted into
    };
    static_assert(sizeof(Body) == 64);
    // The collapse guard's per-frame counts of one marble. The counts saturate (count()) far above
    // every limit they are compared with, so they decide exactly as unbounded counts would.
    struct Guard {
        std::uint32_t wallHits = 0;
        std::uint16_t pairHits = 0;
        std::uint16_t recheckHits = 0;
        std::uint8_t restHits = 0;
        std::uint8_t locked = 0; // bit 0: x held against a wall, bit 1: y
        std::uint8_t pinched = 0; // counted in m_pinchedCount (once a frame, whichever walls)
    };
    static_assert(freezeAfterWallBounces < 0xffffffffu && freezeAfterCollisions < 0xffff
                  && freezeAfterElasticCollisions < 0xffff
                  && freezeAfterRechecks < 0xffff && freezeAfterRestingContacts < 0xff);
    // A calendar entry: a marble's event, with its tie-break packed for cheap comparison, and the
    // ticket it was scheduled under (it is stale once the marble's ticket has changed).
    struct Key {
        double time;
        std::uint64_t tie;
        int marble;
        int rank;              // the marble's Body::rank, the last tie-break
        std::uint32_t ticket;  // m_ticket[marble] when scheduled
        std::int32_t next = -1; // in a later slot's list: the next node, or -1
    };

    void beginFrame(World &world);
    /// The spacing of the marbles, px, as a marble meets them (the stage cut into squares of
    /// `side` px); used to cap the anchor margin.
    double localSpacing(const World &world, double side);
    void makeReady(int end);
    void endFrame(World &world);
    /// A marble that began the frame at `start`, within the walls, and would end it at `p`
    /// past one (a gravity too strong for a double's time), is put on that wall with no speed out.
    void keepWithinWalls(Vec2 start, double r, Vec2 &p, Vec2 &v) const;
    void setNow(double t);
    Vec2 gravityOf(const Body &body) const;
    void stateAt(const Body &body, Vec2 &p, Vec2 &v) const;
    void setState(int i, Vec2 p, Vec2 v);
    void setContact(int i, const Event &e);
    // Up to 6 runs of buckets (3 rows, each split in two where it wraps around) and the oversize
    // marbles: the ranges of internal indices a marble's partners lie in, as [first, last) pairs.
    static constexpr int rangeSlots = 14;
    int neighbourBuckets(int i, int out[9]) const;
    template<typename Map>
    int runsAround(int bucket, int out[rangeSlots], Map map) const;
    int sleeperRanges(int i, int out[rangeSlots]) const;
    int neighbourRanges(int i, int out[rangeSlots]) const;
    [[gnu::noinline]] int oversizeRanges(int bucket, int out[rangeSlots]) const;
    bool layerAllowed(int n) const;
    bool useLayer(const World &world, int n);
    /// A marble at rest without gravity: it stays put until something hits it.
    bool resting(int i) const
    {
        return m_gravity.x == 0.0 && m_gravity.y == 0.0 && m_body[i].b.x == 0.0 && m_body[i].b.y == 0.0;
    }
    /// Whether the first look tests the pair (i, j) in i's turn (i moving): each pair of moving
    /// marbles once, from the lower index; a resting j from i's side, as it has no turn.
    bool testedFrom(int i, int j) const { return j > i || (j < i && resting(j)); }
    void buildLayer(const World &world, int n);
    void checkLayer(const World &world);
    static bool sleeps(const World &world, int w);
    bool layerSleeper(const World &world, int w) const;
    /// Whether a marble of radius r is left out of this frame's grid (RadiusSplit).
    bool leftOut(double r) const { return m_oversize > 0 && m_split.isOversize(r); }
    int sleepersBelow(int bucket, int id) const;
    void startRecords(int k, Vec2 p, Vec2 b, double radius, double mass, int bucket, int id, int rank);
    int promote(int q);
    bool nearSleeper(const Vec2 &p, const Vec2 &v, double r, int q) const;
    // The first look's marble i: its state at t = 0 and radius.
    struct FirstLook {
        Vec2 p;
        Vec2 v;
        double radius;
    };
    void offerFirstLook(int i, int j, const FirstLook &look, Event &best);
    void scanSleepers(int i, const Vec2 &p, const Vec2 &v, Event &best);
    void offerSleeper(int i, int q, const Vec2 &p, const Vec2 &v, double r, Event &best);
    // An oversize marble's scans. Out of line, so that scanMarbles() and predictAll() keep their
    // one inlined copy of the pair test.
    template<typename Run>
    bool bucketsInReach(int i, Run run) const;
    [[gnu::noinline]] void scanEveryMarble(int i, const Vec2 &p, const Vec2 &v, Event &best);
    [[gnu::noinline]] void firstLookOversize(int i, const FirstLook &look, Event &best);
    [[gnu::noinline]] void firstLookWithSleepers(int i, const FirstLook &look, Event &best);
    void firstLookRun(int i, const FirstLook &look, int firstBucket, int lastBucket, Event &best);
    void firstLookAtOversize(int i, const FirstLook &look, Event &best);
    void predictAll();
    void predictOwn(int i, Vec2 p, Vec2 v, Event &best);
    void predict(int i);
    void prefetchNear(int i) const;
    void scanPins(int i, Vec2 p, Vec2 v, const int *buckets, int count, Event &best) const;
    void scanMarbles(int i, Vec2 p, Vec2 v, const int *buckets, int count, Event &best);
    double straightWithoutGravity(int i, int j, const Vec2 &pi, const Vec2 &vi, double ri) const;
    bool pairContact(int i, int j, const Vec2 &pi, const Vec2 &vi, double horizon, double &tau, bool &recheck) const;
    void offerPair(int i, int j, const Vec2 &p, const Vec2 &v, Event &best) const;
    [[gnu::noinline]] void offerStraight(int i, int j, double s, Event &best) const;
    /// Marble i's place among all marbles in bucket order: its index, unless sleepers are kept
    /// out of the arrays (see Body::rank).
    int rankOf(int i) const { return m_layer ? m_body[i].rank : i; }
    std::uint64_t tieOf(int i, const Event &e) const;
    double searchHorizon(double limit) const;
    bool before(int i, const Event &a, const Event &b) const;
    Event contactOf(int i) const;
    Event currentEvent(int i) const;
    Key keyOf(int i) const;
    static bool keyBefore(const Key &a, const Key &b);
    void schedule(int i);
    int slotOf(double time) const;
    /// Makes `key` the live entry of its marble (the entry it had, if any, stale).
    void issueTicket(Key &key);
    void calendarInsert(Key key);
    void calendarRemove(int i);
    bool live(const Key &key) const { return m_ticket[static_cast<std::size_t>(key.marble)] == key.ticket; }
    int calendarFirst();
    void heapSiftUp(int pos);
    void heapSiftDown(int pos);
    void nextEscape(int i, Vec2 p, Vec2 v);
    void reanchor(int i);
    void moveToBucket(int i, int bucket);
    void collidePair(World &world, int i, int j);
    void collidePin(World &world, int i, int pin);
    void collideWall(World &world, int i, int wall);
    void freeze(int i);
    bool overLimit(int i) const;
    bool countContact(int i);
    void unlockMoved(int i, Vec2 v);

    // Frame constants.
    double m_lambda = 0.0;       // drag rate, 1/frame
    double m_restitution = 1.0;
    bool m_inelastic = false;    // e < 1: the collapse guard's collision counts apply
    double m_restSpeed = 0.0;    // sqrt(2 |g| restHeightPx), px/frame
    Vec2 m_gravity;
    bool m_noGravity = true;     // m_gravity is (+0, +0): gravityOf() is (+0, +0) for every marble
    double m_width = 0.0;
    double m_height = 0.0;
    bool m_walls = true;
    GridGeometry m_geometry;
    double m_margin = 0.0;       // how far a marble may stray from its anchor, px
    bool m_singleCell = false;   // no grid: one bucket, no grid events
    int m_oversize = 0;          // marbles left out of the grid (RadiusSplit): internal 0 .. m_oversize - 1
    RadiusSplit m_split;         // this frame's
    double m_gridRadius = 0.0;   // the largest radius of the grid's marbles, px
    bool m_prefetchEvents = false; // at least prefetchEventsFrom marbles
    bool m_finite = true;        // every marble's state and the parameters are finite
    bool m_anyResting = false;   // some marble is at rest (and there is no gravity)
    int m_ready = 0;             // marbles 0 .. m_ready - 1 (internal) are read from the World
    World *m_world = nullptr;    // the World being stepped, during step()

    // The clock: the current event time and phi1, phi2, e^{-lambda t} there.
    double m_now = 0.0;
    double m_decayNow = 1.0;
    double m_phi1Now = 0.0;
    double m_phi2Now = 0.0;
    double m_phi1End = 1.0;  // phi1(1)
    double m_phi2End = 0.5;  // phi2(1)
    double m_sLeft = 1.0;    // >= phi1(1 - now), for quick rejections

    // Everything else the calendar and the guard keep of a marble, in one cache line. Its best
    // contact (see the .cpp, point 4) is split: the time in Body::contactTime, the rest here.
    struct alignas(64) Record {
        Vec2 anchor;             // where it was anchored, px
        double crossTime = 0.0;  // next grid event (infinity: none)
        double invMass = 0.0;    // 0 while frozen
        int contactOther = -1;
        std::uint32_t contactStamp = 0;
        std::uint32_t stamp = 0; // increases with every change of velocity
        int overflowNext = -1;   // next in its bucket's overflow list (while Body::moved)
        Guard guard;
        EventKind contactKind = EventKind::None;
        std::uint8_t crossSide = 0;
    };
    static_assert(sizeof(Record) == 64);

    // Marbles, in grid order: internal index i is World marble m_body[i].id.
    LargeVector<Body> m_body;
    LargeVector<Record> m_rec;
    // The frame's sort, before the records are read (makeReady()): the World index of each awake
    // marble's place. Scattered in a compact array of its own, which stays in cache, instead of
    // into the records themselves, each a cache line the first look then touched a second time.
    LargeVector<int> m_order;

    // Grid: bucket b's marbles at the start of the frame are the internal indices
    // m_start[b] .. m_start[b + 1] (those still anchored there have Body::moved == 0); marbles
    // re-anchored into another bucket join that bucket's overflow list.
    LargeVector<int> m_start;
    LargeVector<int> m_cursor;
    LargeVector<int> m_sortBucket;
    LargeVector<int> m_spacingCount; // localSpacing()'s squares
    LargeVector<int> m_overflowHead;
    int m_overflowCount = 0;
    UniformGrid m_pinGrid;

    // Calendar: the marbles whose earlier event (best contact or grid event) falls inside the
    // frame, in a calendar queue. The frame [0, 1] is cut into equal time slots; an event goes to
    // the slot of its time (or to the current slot, if earlier), so the next event is the least
    // key of the current slot, kept in a small heap, and scheduling a later event costs O(1)
    // where one heap of them all moved the entries of other marbles at every level.
    // Entries are not taken out when a marble's event changes: each marble has a ticket, and an
    // entry under another ticket is stale, dropped when it comes up. The later slots' entries are
    // nodes of m_nodes, listed per slot; the first look's nodes lie in slot order, so a slot's
    // turn reads on from the last one's instead of jumping to a marble's record. A frame's
    // calendar thus holds the first look's entries and at most two more per event (32 bytes
    // each; the collapse guards bound the events), all dropped when the frame ends.
    LargeVector<std::uint32_t> m_ticket; // per marble: the ticket of its entry, 0: none
    std::uint32_t m_lastTicket = 0;
    LargeVector<Key> m_heap;          // the current slot's entries (some stale)
    LargeVector<Key> m_nodes;         // the later slots' entries (some stale)
    LargeVector<std::int32_t> m_slotHead; // per later slot: first node of its list, or -1
    LargeVector<Key> m_firstKeys;     // the first look's events, before the slots are sized
    LargeVector<std::int32_t> m_slotCount; // the first look's entries per slot (then where each goes)
    int m_firstSlot = 0;              // the current slot (no entry lies in an earlier one)
    int m_scheduled = 0;              // live entries in the calendar
    std::vector<int> m_restingHit; // marbles at rest that got a contact in the first look

    // The sleepers' layer (see Sleeping): the sleepers sorted by bucket (ascending World index
    // within a bucket), kept from frame to frame for the lattice m_layerGeometry. A sleeper that
    // wakes keeps its place as a dead entry (id -1) until the layer is built again.
    // What the scans read of a sleeper, in half a cache line; its mass is in m_sleeperMass.
    struct Sleeper {
        Vec2 p;
        double radius = 0.0;
        int id = -1;       // index in the World; -1: dead (woke in an earlier frame)
        int promoted = -1; // its index in the frame's arrays once it joined them this frame
    };
    static_assert(sizeof(Sleeper) == 32);
    Sleeping m_sleepingUse = Sleeping::Auto;
    bool m_splitRadii = true;
    bool m_layer = false;              // this frame keeps the sleepers in the layer
    LargeVector<Sleeper> m_sleepers;
    LargeVector<double> m_sleeperMass; // per entry
    LargeVector<int> m_sleepStart;     // per bucket: first entry; then the entry count
    LargeVector<int> m_sleepBefore;    // per bucket: live sleepers in the buckets before it
    LargeVector<std::uint8_t> m_inLayer; // per World marble: a live sleeper
    GridGeometry m_layerGeometry;
    int m_layerLive = 0;               // live sleepers at the start of this frame
    int m_layerDead = 0;               // dead entries
    int m_outsideSleepers = 0;         // marbles that could sleep but were read as awake
    int m_awake = 0;                   // marbles sorted into the arrays at the start of the frame
    int m_count = 0;                   // those and the sleepers that joined them since
    int m_endedAtRest = -1;            // marbles the last frame left at rest (-1: none yet)
    int m_endedCount = 0;              // of how many

    std::int64_t m_eventCount = 0;
    std::int64_t m_collisionCount = 0;
    int m_frozenCount = 0;
    int m_pinchedCount = 0; // marbles too wide for the stage stopped between its walls this frame
    // Every marble finite after the last step: those endFrame() wrote, checked on the way, and
    // the sleepers kept in the layer, finite when they joined it and the same bits since.
    bool m_leftAllFinite = false;
};

} // namespace marbles
