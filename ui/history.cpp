#include "ui/history.h"

#include <cassert>

namespace marbles {

FrameSnapshot FrameSnapshot::of(const World &world)
{
    FrameSnapshot s;
    s.copyFrom(world);
    return s;
}

void FrameSnapshot::copyFrom(const World &world)
{
    frame = world.frame;
    position.assign(world.position.begin(), world.position.end());
    velocity.assign(world.velocity.begin(), world.velocity.end());
    acceleration.assign(world.acceleration.begin(), world.acceleration.end());
    lastHit.assign(world.lastHit.begin(), world.lastHit.end());
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
    // Once the history is full, the oldest frame's buffers are reused for the newest: a big
    // scene then costs one copy per frame, not an allocation, page faults and a free.
    const std::size_t incoming = sizeof(FrameSnapshot)
        + static_cast<std::size_t>(world.marbleCount()) * (3 * sizeof(Vec2) + sizeof(HitRecord));
    if (!m_frames.empty() && (m_frames.size() >= m_maxFrames || m_bytes + incoming > m_maxBytes)) {
        FrameSnapshot recycled = std::move(m_frames.front());
        m_bytes -= recycled.byteSize();
        m_frames.pop_front();
        recycled.copyFrom(world);
        m_frames.push_back(std::move(recycled));
    } else {
        m_frames.push_back(FrameSnapshot::of(world));
    }
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
