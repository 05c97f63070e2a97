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
    explicit ElidingStatusBar(QWidget *parent = nullptr);

    /// The room the message is drawn in, left of the first permanent widget shown.
    QRect messageRect() const;
    /// The message as drawn (elided to messageRect()).
    QString shownMessage() const;
    /// Permanent widgets that make room for a message (labels that elide their text): while one
    /// is shown they are narrowed, in proportion to the room they ask for, until the message has
    /// its width, up to two fifths of the bar. Figures that filled a narrow window's bar left a
    /// message none.
    void setYielding(const QList<QWidget *> &widgets);

protected:
    void paintEvent(QPaintEvent *event) override;
    bool event(QEvent *event) override;
    void resizeEvent(QResizeEvent *event) override;

private:
    void makeRoom();
    QList<QWidget *> m_yielding;
};

} // namespace marbles
