#pragma once

#include "core/world.h"

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace marbles {

/// Step-back memory for the run: the frames simulated so far, newest last, bounded by a frame
/// count and a byte budget (the oldest frames are forgotten first), plus the first frame of the
/// timeline, which is never forgotten so that "back to start" always works.
///
/// A kept frame holds every marble's position, velocity and push, but of the last-hit records
/// (the collision vectors, more than half of a marble's state) only those the step from it
/// changed, with their values before the step: the history keeps one full copy of the records,
/// as of its newest frame, and walks back from it.
class FrameHistory {
public:
    /// At least this many frames are kept unless the byte budget is reached first.
    static constexpr std::size_t kDefaultMaxFrames = 10000;
    /// Byte budget of the kept frames: 256 MiB.
    static constexpr std::size_t kDefaultMaxBytes = std::size_t{256} * 1024 * 1024;

    explicit FrameHistory(std::size_t maxFrames = kDefaultMaxFrames, std::size_t maxBytes = kDefaultMaxBytes);

    /// Forgets every frame; `world` becomes the start of a new timeline, without the clicks'
    /// pushes still to act (its accelerations), which rewind() does not give back.
    void reset(const World &world);
    /// Remembers `world` as it is now, just before it is stepped.
    void record(const World &world);
    /// True when the frame just before `world.frame` is kept.
    bool canStepBack(const World &world) const;
    /// Restores the frame before `world.frame` and forgets it; false (world untouched) when it is not kept.
    bool stepBack(World &world);
    /// Restores the first frame of the timeline and forgets the rest; false when the marble count changed.
    bool rewind(World &world);
    /// Writes the first frame of the timeline into `world` (a copy of the one this history follows),
    /// keeping every frame; false (world untouched) when the marble count changed.
    bool restoreStart(World &world) const;

    /// One marble's part of the timeline's first frame.
    struct MarbleStart {
        Vec2 position;
        Vec2 velocity;
        Vec2 acceleration;
        HitRecord lastHit;
    };
    /// Marble i's part of the first frame (a default one past the end).
    MarbleStart startOf(int i) const;
    /// One marble's part of the timeline: of its first frame, and of the step-back frames.
    struct MarbleTrack {
        MarbleStart start;
        struct Kept {
            std::int64_t frame = 0;
            Vec2 position;
            Vec2 velocity;
            Vec2 acceleration;
        };
        std::vector<Kept> frames;                                // the step-back frames', oldest first
        std::vector<std::pair<std::int64_t, HitRecord>> hitsBefore; // its entries in their hitsBefore
        HitRecord newestHit;                                     // its record as of the newest frame

        /// Its part of kept frame `frame`, or null when that frame is not in the track.
        const Kept *keptAt(std::int64_t frame) const;
        /// Its last-hit record as of kept frame `frame`: the value noted before the first step
        /// from `frame` on that changed it, or newestHit when none did.
        HitRecord hitAt(std::int64_t frame) const;
        /// Its state at `frame`: a kept frame's, or the first frame's (`startFrame`); none when
        /// the track does not reach that frame.
        std::optional<MarbleStart> stateAt(std::int64_t frame, std::int64_t startFrame) const;
    };
    /// A marble joins the scene at index i (0 <= i <= count): the first frame gets it as
    /// `track.start`, so that rewind() still reaches it. The step-back frames get it back too when
    /// they are frames `track` was taken from (a deleted marble put back where it was deleted).
    /// Frames that have no place for it leave Step Back: those before a marble added (a `track`
    /// without frames) are set aside for its undo, others are forgotten. Returns the number that
    /// takeBackSetAside() takes them back by, or 0 when none were set aside.
    std::uint64_t insertMarble(int i, const MarbleTrack &track);
    /// The add that set aside frames `setAside` undone where it was made (its column already
    /// removed by removeMarble(), `world` as it is now, no step-back frame kept since): those
    /// frames come back, so that Step Back goes on past the add, and those set aside after them
    /// (adds undone before) are forgotten. False (nothing comes back) when they do not fit there.
    bool takeBackSetAside(std::uint64_t setAside, const World &world);
    /// Frames set aside for undoing adds (they count in the frame and byte budgets, and are the
    /// first forgotten when a budget is reached).
    std::size_t setAsideSize() const { return m_setAsideFrames; }
    /// Marble i leaves the scene: the first frame and the step-back frames lose it (the others'
    /// frames stay, so that Step Back still goes back past the delete); returns its part of them.
    MarbleTrack removeMarble(int i);
    /// True when the kept frames have as many marbles as `world` (so they can be restored into it).
    bool fits(const World &world) const { return startSize() == world.marbleCount(); }
    /// Marbles in the timeline's first frame.
    int startSize() const { return static_cast<int>(m_start.position.size()); }
    /// Frame number of the start of the timeline.
    std::int64_t startFrame() const { return m_start.frame; }
    /// Number of step-back frames kept (the start frame not counted).
    std::size_t size() const { return m_frames.size(); }
    /// Bytes held by the step-back frames.
    std::size_t byteSize() const { return m_bytes; }
    /// The last time a budget made this timeline forget its oldest frames: how many frames it
    /// kept then, and whether the byte budget was the limit (else the frame count). No frames:
    /// none were forgotten that way (Step Back ends at the start, or before a marble added).
    struct Limit {
        std::size_t frames = 0;
        bool bytes = false;
    };
    Limit lastLimit() const { return m_limit; }
    /// The marbles' velocities at `frame` as kept (the start of the timeline or a step-back
    /// frame), or null when that frame is not kept.
    const std::vector<Vec2> *velocitiesAt(std::int64_t frame) const;
    /// The oldest frame from which every frame up to the one before `now` is kept (the start of
    /// the timeline or a step-back frame): what Step Back from `now` goes through without a break.
    /// `now` itself when the frame before it is not kept.
    std::int64_t firstUnbrokenFrame(std::int64_t now) const;
    /// The marbles' positions at `frame` as kept, or null when that frame is not kept.
    const std::vector<Vec2> *positionsAt(std::int64_t frame) const;
    /// The same, with `now` (the world this history follows) answering for its own frame.
    const std::vector<Vec2> *velocitiesAt(std::int64_t frame, const World &now) const
    {
        return frame == now.frame ? &now.velocity : velocitiesAt(frame);
    }

private:
    /// One kept frame: the state a step changes, except the last-hit records, of which only
    /// those the step from this frame changed are kept, with their values at this frame.
    /// Radius, mass, pins, params and the stage are not kept: a frame is only restored into a
    /// world with the same marbles (a marble removed leaves every frame; one added clears them).
    struct Frame {
        std::int64_t frame = 0;
        std::vector<Vec2> position;
        std::vector<Vec2> velocity;
        std::vector<Vec2> acceleration;
        std::vector<std::pair<int, HitRecord>> hitsBefore;

        /// Copies the frame number, positions, velocities and pushes of `world`, reusing the
        /// buffers; hitsBefore is emptied.
        void copyFrom(const World &world);
        /// Writes them back into `world` (same marble count), bit for bit; not the last hits.
        void restoreInto(World &world) const;
        /// Approximate heap size, bytes.
        std::size_t byteSize() const;
    };

    void noteHitChanges(const World &world);
    /// Forgets every step-back frame, and those set aside (which can only follow on from them).
    void forgetFrames();
    /// Forgets the oldest frame set aside.
    void forgetOldestSetAside();
    /// True while the frames (set aside too), with `incoming` bytes more, are over a budget.
    bool overBudget(std::size_t incomingFrames, std::size_t incomingBytes) const;
    /// The start of the timeline or a kept frame, `frame`; null when it is neither.
    const Frame *keptFrame(std::int64_t frame) const;
    /// Removes the oldest kept frame from the history and returns it (its buffers can be reused).
    Frame takeOldest();

    std::size_t m_maxFrames;
    std::size_t m_maxBytes;
    Frame m_start; // the start of the timeline, with its last-hit records in m_startHits
    std::vector<HitRecord> m_startHits;
    std::deque<Frame> m_frames;
    // The last-hit records as of the newest kept frame (or, with none kept, as of the world the
    // history last saw): the newest frame's hitsBefore are filled in from it at the next record.
    std::vector<HitRecord> m_hits;
    std::size_t m_bytes = 0;
    /// Step-back frames that preceded a marble added (insertMarble()), with the last-hit records
    /// as of the newest of them, oldest adds first: an add's undo takes its own back.
    struct SetAside {
        std::uint64_t number = 0;
        std::deque<Frame> frames;
        std::vector<HitRecord> hits;
        Limit limit; // the step-back frames' lastLimit() when they were set aside
    };
    std::vector<SetAside> m_setAside;
    std::size_t m_setAsideFrames = 0;
    std::size_t m_setAsideBytes = 0;
    Limit m_limit;
    std::uint64_t m_setAsideCount = 0; // numbers them
};

} // namespace marbles
