#pragma once

#include <QWheelEvent>

namespace marbles {

/// A widget that the wheel changes only once it has the focus (clicked or tabbed into): over one
/// without it, the wheel goes on to its dock, which scrolls, as over the text beside it. One tick
/// while a dock scrolled had given a marble at rest a velocity of 1 px/frame, and made a lesson's
/// book model the impulse one (a helper's findings).
template<typename Base>
class FocusedWheel : public Base {
public:
    using Base::Base;

protected:
    void wheelEvent(QWheelEvent *event) override
    {
        if (!this->hasFocus()) {
            event->ignore();
            return;
        }
        Base::wheelEvent(event);
    }
};

} // namespace marbles
