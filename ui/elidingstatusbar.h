#pragma once

#include <QStatusBar>

namespace marbles {

/// A status bar whose message, when longer than the room left of the permanent figures, ends in
/// "…" rather than being cut off against them mid-word ("...below 2 for the boc4 marble(s)");
/// the whole message is its tool tip then. currentMessage() is the whole message.
/// Only for permanent widgets: a normal widget's frame is not drawn.
class ElidingStatusBar : public QStatusBar {
    Q_OBJECT
public:
    using QStatusBar::QStatusBar;

    /// The room the message is drawn in, left of the first permanent widget shown.
    QRect messageRect() const;
    /// The message as drawn (elided to messageRect()).
    QString shownMessage() const;

protected:
    void paintEvent(QPaintEvent *event) override;
    bool event(QEvent *event) override;
};

} // namespace marbles
