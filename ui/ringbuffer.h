#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <vector>

namespace marbles {

/// A fixed-capacity FIFO that overwrites its oldest entry when full: the plot's sample store.
/// push() is O(1) and never allocates once the buffer is full; index 0 is the oldest entry.
template<typename T>
class RingBuffer {
public:
    /// An empty buffer holding at most `capacity` entries (at least 1).
    explicit RingBuffer(std::size_t capacity = 1)
        : m_capacity(capacity > 0 ? capacity : 1)
    {
    }

    /// Most entries held at once.
    std::size_t capacity() const { return m_capacity; }
    /// Entries held now, at most capacity().
    std::size_t size() const { return m_data.size(); }
    /// True when nothing is held.
    bool isEmpty() const { return m_data.empty(); }

    /// Appends `value`; when full, the oldest entry is dropped to make room.
    void push(const T &value)
    {
        if (m_data.size() < m_capacity) {
            m_data.push_back(value);
            return;
        }
        m_data[m_head] = value;
        m_head = (m_head + 1) % m_capacity;
    }

    /// Entry `i`, counted from the oldest (0) to the newest (size() - 1).
    const T &at(std::size_t i) const
    {
        assert(i < m_data.size());
        return m_data[(m_head + i) % m_data.size()];
    }
    T &at(std::size_t i)
    {
        assert(i < m_data.size());
        return m_data[(m_head + i) % m_data.size()];
    }

    /// The newest entry; the buffer must not be empty.
    const T &last() const { return at(m_data.size() - 1); }

    /// Drops the `count` newest entries (all of them when there are fewer); the capacity stays.
    /// O(size()) when the buffer has wrapped around, O(1) otherwise.
    void dropNewest(std::size_t count)
    {
        if (count >= m_data.size()) {
            clear();
            return;
        }
        // Oldest first from index 0 again, so that the next push appends after the newest kept.
        std::rotate(m_data.begin(), m_data.begin() + static_cast<std::ptrdiff_t>(m_head), m_data.end());
        m_head = 0;
        m_data.resize(m_data.size() - count);
    }

    /// Drops every entry; the capacity stays.
    void clear()
    {
        m_data.clear();
        m_head = 0;
    }

    /// Drops every entry and changes the capacity (at least 1).
    void setCapacity(std::size_t capacity)
    {
        clear();
        m_capacity = capacity > 0 ? capacity : 1;
    }

private:
    std::vector<T> m_data;
    std::size_t m_capacity;
    std::size_t m_head = 0; ///< index in m_data of the oldest entry once the buffer is full
};

} // namespace marbles
