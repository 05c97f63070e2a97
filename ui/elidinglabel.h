#pragma once

#include <QFontMetricsF>
#include <QLabel>
#include <QResizeEvent>

#include <cmath>

namespace marbles {

/// A one-line label that asks for its whole text's width but takes what room it is given,
/// showing its text cut with "…" where it does not fit (a label cut by its neighbours ended
/// mid-word, "...not running: it n"). text() is what is shown; fullText() the whole.
class ElidingLabel : public QLabel {
public:
    using QLabel::QLabel;

    void setFullText(const QString &text)
    {
        m_full = text;
        updateGeometry();
        elide();
    }
    const QString &fullText() const { return m_full; }

    QSize sizeHint() const override
    {
        // The text's width to the pixel above: the rounded width came a fraction short of what
        // elidedText() measures, and a label given all the room it asked for still cut its last
        // word ("890.07 (exa…").
        const QMargins m = contentsMargins();
        const int text = static_cast<int>(std::ceil(QFontMetricsF(font()).horizontalAdvance(m_full))) + 1;
        return {text + m.left() + m.right(), QLabel::sizeHint().height()};
    }
    QSize minimumSizeHint() const override { return {1, QLabel::minimumSizeHint().height()}; }

protected:
    void resizeEvent(QResizeEvent *event) override
    {
        QLabel::resizeEvent(event);
        elide();
    }

private:
    void elide() { setText(fontMetrics().elidedText(m_full, Qt::ElideRight, std::max(contentsRect().width(), 1))); }

    QString m_full;
};

} // namespace marbles
