#pragma once

#include <QDockWidget>

#include <functional>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;

namespace marbles {

class SceneDocument;
class World;

/// The Inspector dock: the selected marble's radius, mass, position and velocity, editable.
/// Every change goes through the document as an undo command; scrubbing a field with the arrows
/// or the wheel merges into one undo step per field.
class InspectorDock : public QDockWidget {
    Q_OBJECT

public:
    /// The dock (objectName "inspectorDock") for `document`, which must outlive it.
    explicit InspectorDock(SceneDocument *document, QWidget *parent = nullptr);
    ~InspectorDock() override;

    /// Shows marble i (-1 shows nothing).
    void setMarble(int i);
    /// The marble shown, or -1.
    int marble() const { return m_marble; }

    /// The name field (a marble's name for the Inspector, the plot's legend and the saved scene).
    QLineEdit *nameField() const { return m_name; }
    /// The fields, for tests: "radius", "mass", "x", "y", "vx", "vy".
    QDoubleSpinBox *field(const QString &name) const;

    /// Where to find the comparison's world (null when none runs) and its model's name: the
    /// marble's place and velocity there are shown under the fields (the exact model's
    /// velocities after a collision could be read only off the plot or the CSV). Asked at each
    /// refresh, so that a world the comparison replaced is never read.
    void setComparison(std::function<const World *()> world, std::function<QString()> model);
    /// Shows the comparison's numbers again (the comparison stepped, started or stopped).
    void comparisonChanged() { showCompared(); }

    /// Clears the refusal shown under the fields (another dock showed one).
    void clearRefusal();

Q_SIGNALS:
    /// An edit was refused; `text` says why.
    void message(const QString &text);
    /// A refusal is shown under the fields.
    void refused();

protected:
    void changeEvent(QEvent *event) override;

private:
    void refresh() { showMarble(false); }
    /// Shows the selected marble's numbers; a field being typed in keeps its text unless
    /// `overTyping` (after an edit was refused: the field goes back to the marble's number).
    void showMarble(bool overTyping);
    /// Gives the page's scroll area the height the page asks for, as far as the screen has room.
    void fitToPage();
    /// Shows (or hides) the marble's place and velocity in the comparison's world.
    void showCompared();
    void showMassEditable(bool editable);
    /// The mass field's tooltip, for a mass of the marble's own or one worked out from its radius.
    static QString massTip(bool editable);
    /// The mass field's background: the window's while it is read-only, a field's otherwise.
    void paintMassField();
    void onRadius(double value);
    void onMass(double value);
    void onX(double value);
    void onY(double value);
    void onVx(double value);
    void onVy(double value);
    void onAutoMass(bool automatic);
    void report(const QString &error);

    SceneDocument *m_document;
    int m_marble = -1;
    QLabel *m_title = nullptr;
    QLineEdit *m_name = nullptr;
    QDoubleSpinBox *m_radius = nullptr;
    QDoubleSpinBox *m_mass = nullptr;
    QCheckBox *m_autoMass = nullptr;
    QDoubleSpinBox *m_x = nullptr;
    QDoubleSpinBox *m_y = nullptr;
    QDoubleSpinBox *m_vx = nullptr;
    QDoubleSpinBox *m_vy = nullptr;
    QLabel *m_error = nullptr;
    bool m_reportedThisEdit = false; // report() ran since the last field edit ended
    QLabel *m_beyond = nullptr; // the true numbers of fields that show their limit instead
    QLabel *m_compared = nullptr; // the marble in the comparison's world
    std::function<const World *()> m_comparison;
    std::function<QString()> m_comparisonModel;
    QWidget *m_form = nullptr;
    QMetaObject::Connection m_scrollToFocus; // a focused field scrolled into sight
};

} // namespace marbles
