#include "ui/history.h"

#include <cassert>

namespace marbles {

FrameSnapshot FrameSnapshot::of(const World &world)
{
    FrameSnapshot s;
    s.frame = world.frame;
    s.position = world.position;
    s.velocity = world.velocity;
    s.acceleration = world.acceleration;
    s.lastHit = world.lastHit;
    return s;
}

void FrameSnapshot::restoreInto(World &world) const
{
    assert(static_cast<int>(position.size()) == world.marbleCount());
    if (static_cast<int>(position.size()) != world.marbleCount())
        return;
    world.frame = frame;
    world.position = position;
    world.velocity = velocity;
    world.acceleration = acceleration;
    world.lastHit = lastHit;
}

std::size_t FrameSnapshot::byteSize() const
{
    return sizeof(FrameSnapshot) + (position.capacity() + velocity.capacity() + acceleration.capacity()) * sizeof(Vec2)
        + lastHit.capacity() * sizeof(HitRecord);
}

FrameHistory::FrameHistory(std::size_t maxFrames, std::size_t maxBytes)
    : m_maxFrames(maxFrames > 0 ? maxFrames : 1)
    , m_maxBytes(maxBytes)
{
}

void FrameHistory::reset(const World &world)
{
    m_frames.clear();
    m_bytes = 0;
    m_start = FrameSnapshot::of(world);
}

void FrameHistory::record(const World &world)
{
    if (static_cast<int>(m_start.position.size()) != world.marbleCount()) {
        reset(world);
        return;
    }
    // A gap (a jump the history did not see) breaks step-back: what lies before it is stale.
    if (!m_frames.empty() && m_frames.back().frame + 1 != world.frame) {
        m_frames.clear();
        m_bytes = 0;
    }
    m_frames.push_back(FrameSnapshot::of(world));
    m_bytes += m_frames.back().byteSize();
    while (m_frames.size() > m_maxFrames || (m_bytes > m_maxBytes && m_frames.size() > 1)) {
        m_bytes -= m_frames.front().byteSize();
        m_frames.pop_front();
    }
}

bool FrameHistory::canStepBack(const World &world) const
{
    return !m_frames.empty() && m_frames.back().frame + 1 == world.frame
        && static_cast<int>(m_frames.back().position.size()) == world.marbleCount();
}

bool FrameHistory::stepBack(World &world)
{
    if (!canStepBack(world))
        return false;
    m_frames.back().restoreInto(world);
    m_bytes -= m_frames.back().byteSize();
    m_frames.pop_back();
    return true;
}

bool FrameHistory::rewind(World &world)
{
    if (static_cast<int>(m_start.position.size()) != world.marbleCount())
        return false;
    m_start.restoreInto(world);
    m_frames.clear();
    m_bytes = 0;
    return true;
}

} // namespace marbles
