#include "ui/history.h"

#include <algorithm>
#include <cassert>
#include <utility>

namespace marbles {

void FrameHistory::Frame::copyFrom(const World &world)
{
    frame = world.frame;
    position.assign(world.position.begin(), world.position.end());
    velocity.assign(world.velocity.begin(), world.velocity.end());
    acceleration.assign(world.acceleration.begin(), world.acceleration.end());
    hitsBefore.clear();
}

void FrameHistory::Frame::restoreInto(World &world) const
{
    assert(static_cast<int>(position.size()) == world.marbleCount());
    world.frame = frame;
    world.position = position;
    world.velocity = velocity;
    world.acceleration = acceleration;
}

std::size_t FrameHistory::Frame::byteSize() const
{
    return sizeof(Frame) + (position.capacity() + velocity.capacity() + acceleration.capacity()) * sizeof(Vec2)
        + hitsBefore.capacity() * sizeof(std::pair<int, HitRecord>);
}

FrameHistory::FrameHistory(std::size_t maxFrames, std::size_t maxBytes)
    : m_maxFrames(maxFrames > 0 ? maxFrames : 1)
    , m_maxBytes(maxBytes)
{
}

void FrameHistory::forgetFrames()
{
    m_frames.clear();
    m_bytes = 0;
    m_setAside.clear();
    m_setAsideFrames = 0;
    m_setAsideBytes = 0;
}

void FrameHistory::forgetOldestSetAside()
{
    SetAside &oldest = m_setAside.front();
    m_setAsideBytes -= oldest.frames.front().byteSize();
    --m_setAsideFrames;
    oldest.frames.pop_front();
    if (oldest.frames.empty())
        m_setAside.erase(m_setAside.begin());
}

bool FrameHistory::overBudget(std::size_t incomingFrames, std::size_t incomingBytes) const
{
    return m_frames.size() + m_setAsideFrames + incomingFrames > m_maxFrames
        || m_bytes + m_setAsideBytes + incomingBytes > m_maxBytes;
}

void FrameHistory::reset(const World &world)
{
    forgetFrames();
    m_limit = {};
    m_start.copyFrom(world);
    // A timeline starts without the clicks' pushes still to act (what is pending between frames;
    // a scene's scripted pushes are added as their frame is stepped): a click is not an edit,
    // and Home forgets it. The world keeps it pending.
    std::fill(m_start.acceleration.begin(), m_start.acceleration.end(), Vec2{});
    m_startHits = world.lastHit;
    m_hits = world.lastHit;
}

void FrameHistory::noteHitChanges(const World &world)
{
    // What changed since the newest frame was kept (its step, normally) is logged in that frame
    // with the value it had there; m_hits then follows the world.
    Frame &newest = m_frames.back();
    m_bytes -= newest.byteSize();
    newest.hitsBefore.clear();
    const std::size_t n = world.lastHit.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (!(world.lastHit[i] == m_hits[i])) {
            newest.hitsBefore.emplace_back(static_cast<int>(i), m_hits[i]);
            m_hits[i] = world.lastHit[i];
        }
    }
    m_bytes += newest.byteSize();
}

FrameHistory::Frame FrameHistory::takeOldest()
{
    Frame oldest = std::move(m_frames.front());
    m_bytes -= oldest.byteSize();
    m_frames.pop_front();
    return oldest;
}

void FrameHistory::record(const World &world)
{
    if (static_cast<int>(m_start.position.size()) != world.marbleCount()) {
        reset(world);
        return;
    }
    // A gap (a jump the history did not see) breaks step-back: what lies before it is stale.
    if (!m_frames.empty() && m_frames.back().frame + 1 != world.frame)
        forgetFrames();
    if (m_frames.empty())
        m_hits = world.lastHit;
    else
        noteHitChanges(world);
    // Once the history is full, the oldest frame's buffers are reused for the newest: a big
    // scene then costs one copy per frame, not an allocation, page faults and a free.
    const std::size_t incoming = sizeof(Frame) + static_cast<std::size_t>(world.marbleCount()) * 3 * sizeof(Vec2);
    // The frames set aside for undoing an add are the first to go.
    while (!m_setAside.empty() && overBudget(1, incoming))
        forgetOldestSetAside();
    const auto noteLimit = [this] {
        m_limit = {m_frames.size(), m_frames.size() + m_setAsideFrames < m_maxFrames};
    };
    if (!m_frames.empty() && overBudget(1, incoming)) {
        Frame recycled = takeOldest();
        recycled.copyFrom(world);
        m_frames.push_back(std::move(recycled));
        noteLimit();
    } else {
        m_frames.emplace_back();
        m_frames.back().copyFrom(world);
    }
    m_bytes += m_frames.back().byteSize();
    while (m_frames.size() > m_maxFrames || (m_bytes > m_maxBytes && m_frames.size() > 1)) {
        takeOldest();
        noteLimit();
    }
}

const FrameHistory::Frame *FrameHistory::keptFrame(std::int64_t frame) const
{
    if (frame == m_start.frame)
        return &m_start;
    // The kept frames follow one another, newest last.
    if (m_frames.empty() || frame < m_frames.front().frame || frame > m_frames.back().frame)
        return nullptr;
    const Frame &kept = m_frames[static_cast<std::size_t>(frame - m_frames.front().frame)];
    return kept.frame == frame ? &kept : nullptr;
}

std::int64_t FrameHistory::firstUnbrokenFrame(std::int64_t now) const
{
    // The kept frames follow one another, newest last; the start may lie before a gap.
    if (m_frames.empty() || m_frames.back().frame + 1 != now)
        return m_start.frame + 1 == now ? m_start.frame : now;
    const std::int64_t oldest = m_frames.front().frame;
    return m_start.frame + 1 == oldest ? m_start.frame : oldest;
}

const std::vector<Vec2> *FrameHistory::velocitiesAt(std::int64_t frame) const
{
    const Frame *kept = keptFrame(frame);
    return kept ? &kept->velocity : nullptr;
}

const std::vector<Vec2> *FrameHistory::positionsAt(std::int64_t frame) const
{
    const Frame *kept = keptFrame(frame);
    return kept ? &kept->position : nullptr;
}

bool FrameHistory::canStepBack(const World &world) const
{
    return !m_frames.empty() && m_frames.back().frame + 1 == world.frame
        && static_cast<int>(m_frames.back().position.size()) == world.marbleCount()
        && m_hits.size() == world.lastHit.size();
}

bool FrameHistory::stepBack(World &world)
{
    if (!canStepBack(world))
        return false;
    // m_hits holds the records as of the newest kept frame: exactly what that frame had.
    const Frame &newest = m_frames.back();
    newest.restoreInto(world);
    world.lastHit = m_hits;
    m_bytes -= newest.byteSize();
    m_frames.pop_back();
    // Now walk m_hits back to the frame before (the new newest), whose step led to this one.
    if (!m_frames.empty()) {
        for (const auto &[i, before] : m_frames.back().hitsBefore)
            m_hits[static_cast<std::size_t>(i)] = before;
    }
    return true;
}

bool FrameHistory::restoreStart(World &world) const
{
    if (static_cast<int>(m_start.position.size()) != world.marbleCount())
        return false;
    m_start.restoreInto(world);
    world.lastHit = m_startHits;
    return true;
}

FrameHistory::MarbleStart FrameHistory::startOf(int i) const
{
    const auto k = static_cast<std::size_t>(i);
    if (i < 0 || k >= m_start.position.size())
        return {};
    return {m_start.position[k], m_start.velocity[k], m_start.acceleration[k],
            k < m_startHits.size() ? m_startHits[k] : HitRecord{}};
}

const FrameHistory::MarbleTrack::Kept *FrameHistory::MarbleTrack::keptAt(std::int64_t frame) const
{
    // The frames follow one another.
    if (frames.empty() || frame < frames.front().frame)
        return nullptr;
    const auto index = static_cast<std::size_t>(frame - frames.front().frame);
    return index < frames.size() && frames[index].frame == frame ? &frames[index] : nullptr;
}

HitRecord FrameHistory::MarbleTrack::hitAt(std::int64_t frame) const
{
    const std::pair<std::int64_t, HitRecord> *first = nullptr;
    for (const auto &entry : hitsBefore) {
        if (entry.first >= frame && (!first || entry.first < first->first))
            first = &entry;
    }
    return first ? first->second : newestHit;
}

std::optional<FrameHistory::MarbleStart> FrameHistory::MarbleTrack::stateAt(std::int64_t frame,
                                                                           std::int64_t startFrame) const
{
    if (const Kept *kept = keptAt(frame))
        return MarbleStart{kept->position, kept->velocity, kept->acceleration, hitAt(frame)};
    if (frame == startFrame)
        return start;
    return std::nullopt;
}

std::uint64_t FrameHistory::insertMarble(int i, const MarbleTrack &track)
{
    const auto k = static_cast<std::size_t>(i);
    if (i < 0 || k > m_start.position.size() || m_startHits.size() != m_start.position.size())
        return 0;
    const auto at = [k](auto &values) { return values.begin() + static_cast<std::ptrdiff_t>(k); };
    const MarbleStart &start = track.start;
    m_start.position.insert(at(m_start.position), start.position);
    m_start.velocity.insert(at(m_start.velocity), start.velocity);
    m_start.acceleration.insert(at(m_start.acceleration), start.acceleration);
    m_startHits.insert(at(m_startHits), start.lastHit);
    // The step-back frames take it back only where each of them is one it was taken from (the
    // track's frames follow one another); otherwise they have no place for it.
    const bool fits = !m_frames.empty() && k <= m_hits.size()
        && std::all_of(m_frames.begin(), m_frames.end(), [&](const Frame &f) { return track.keptAt(f.frame) != nullptr; });
    if (!fits) {
        std::uint64_t number = 0;
        if (track.frames.empty() && !m_frames.empty()) {
            // A marble added: its undo takes them back.
            number = ++m_setAsideCount;
            m_setAside.push_back({number, std::move(m_frames), m_hits, m_limit});
            m_setAsideFrames += m_setAside.back().frames.size();
            m_setAsideBytes += m_bytes;
            m_frames.clear();
            m_bytes = 0;
            m_limit = {}; // Step Back now ends here, at the marble
        } else if (!m_frames.empty()) {
            forgetFrames(); // a deleted marble whose frames these are not
            m_limit = {};
        }
        // No frame kept now: the records follow the world, which has the marble. (With none kept
        // before either, Step Back at its limit, the limit that held still does.)
        if (k <= m_hits.size())
            m_hits.insert(at(m_hits), start.lastHit);
        return number;
    }
    for (Frame &f : m_frames) {
        const MarbleTrack::Kept &kept = *track.keptAt(f.frame);
        m_bytes -= f.byteSize();
        f.position.insert(at(f.position), kept.position);
        f.velocity.insert(at(f.velocity), kept.velocity);
        f.acceleration.insert(at(f.acceleration), kept.acceleration);
        for (auto &[index, record] : f.hitsBefore) {
            if (index >= i)
                ++index;
        }
        for (const auto &[frame, record] : track.hitsBefore) {
            if (frame == f.frame)
                f.hitsBefore.emplace_back(i, record);
        }
        m_bytes += f.byteSize();
    }
    // As of the newest kept frame, which is the one before the world's (a delete undone where it
    // was made, or after Step Back took the scene back past it).
    m_hits.insert(at(m_hits), track.hitAt(m_frames.back().frame));
    return 0;
}

bool FrameHistory::takeBackSetAside(std::uint64_t setAside, const World &world)
{
    const auto its = std::find_if(m_setAside.begin(), m_setAside.end(),
                                  [setAside](const SetAside &s) { return s.number == setAside; });
    if (setAside == 0 || its == m_setAside.end())
        return false;
    // Those set aside after it were set aside by adds undone before (or not where they were made).
    for (auto later = its; later != m_setAside.end(); ++later) {
        for (const Frame &f : later->frames)
            m_setAsideBytes -= f.byteSize();
        m_setAsideFrames -= later->frames.size();
    }
    SetAside taken = std::move(*its);
    m_setAside.erase(its, m_setAside.end());
    const bool fits = m_frames.empty() && !taken.frames.empty() && taken.frames.back().frame + 1 == world.frame
        && static_cast<int>(taken.frames.back().position.size()) == world.marbleCount()
        && startSize() == world.marbleCount() && taken.hits.size() == world.lastHit.size();
    if (!fits)
        return false;
    // The newest of them is the one before the world's, its last-hit records m_hits (its
    // hitsBefore are filled in when the world is recorded, as for any newest frame).
    for (const Frame &f : taken.frames)
        m_bytes += f.byteSize();
    m_frames = std::move(taken.frames);
    m_hits = std::move(taken.hits);
    m_limit = taken.limit;
    return true;
}

FrameHistory::MarbleTrack FrameHistory::removeMarble(int i)
{
    MarbleTrack track;
    const auto k = static_cast<std::size_t>(i);
    if (i < 0 || k >= m_start.position.size() || m_startHits.size() != m_start.position.size())
        return track;
    track.start = startOf(i);
    const auto at = [k](auto &values) { return values.begin() + static_cast<std::ptrdiff_t>(k); };
    m_start.position.erase(at(m_start.position));
    m_start.velocity.erase(at(m_start.velocity));
    m_start.acceleration.erase(at(m_start.acceleration));
    m_startHits.erase(at(m_startHits));
    if (k >= m_hits.size()) { // (never: the frames and m_hits follow the first frame's marbles)
        forgetFrames();
        return track;
    }
    track.newestHit = m_hits[k];
    m_hits.erase(at(m_hits));
    for (Frame &f : m_frames) {
        m_bytes -= f.byteSize();
        track.frames.push_back({f.frame, f.position[k], f.velocity[k], f.acceleration[k]});
        f.position.erase(at(f.position));
        f.velocity.erase(at(f.velocity));
        f.acceleration.erase(at(f.acceleration));
        std::erase_if(f.hitsBefore, [&](const std::pair<int, HitRecord> &entry) {
            if (entry.first == i)
                track.hitsBefore.emplace_back(f.frame, entry.second);
            return entry.first == i;
        });
        for (auto &[index, record] : f.hitsBefore) {
            if (index > i)
                --index;
        }
        m_bytes += f.byteSize();
    }
    return track;
}

bool FrameHistory::rewind(World &world)
{
    if (!restoreStart(world))
        return false;
    forgetFrames();
    m_hits = m_startHits;
    return true;
}

} // namespace marbles
