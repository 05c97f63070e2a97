#pragma once

#include "core/world.h"

#include <QDockWidget>
#include <QString>

class QCheckBox;
class QComboBox;
class QAbstractSpinBox;
class QDoubleSpinBox;
class QLabel;
class QSpinBox;

namespace marbles {

class Refusing;

/// The Parameters dock: one field per scene parameter, each with its formula in a tooltip and
/// a one-line explanation for a teacher. Edits apply at once (no Apply button): every user
/// change is announced with paramEdited(), which the main window turns into an undo command.
/// Values the model would refuse cannot be entered (ranges follow PHYSICS.md and the model).
class ParametersDock : public QDockWidget {
    Q_OBJECT

public:
    /// Largest friction the book model's field accepts (> 2 shows the book's instability).
    static constexpr double kBookFrictionMax = 3.0;
    /// Largest friction the exact and impulse models accept: k must stay below 1.
    static constexpr double kDampedFrictionMax = 0.999999;

    /// The dock, objectName "parametersDock", showing the default parameters.
    explicit ParametersDock(QWidget *parent = nullptr);
    /// Disconnects from the application's focus changes before the fields go (a field losing the
    /// focus as it is destroyed would otherwise scroll a page half destroyed).
    ~ParametersDock() override;

    /// Shows `params` in every field; emits no paramEdited().
    void setParams(const Params &params);
    /// The width at which every field shows whole, without a sideways scroll bar.
    int fieldsWidth() const;
    /// The values the fields show now (what the user sees), as Params.
    Params shownParams() const;
    /// Takes a refusal shown back to its field's explanation (another dock showed one).
    void clearRefusal();

signals:
    /// A number typed was refused and the line under its field says why.
    void refused();
    /// The user changed one field: `key` and `value` are what marbles::setParam() takes
    /// (e.g. "friction", "0.2"; "gravity", "0,0.5"; "shortCircuit", "true").
    void paramEdited(const QString &key, const QString &value);

protected:
    bool eventFilter(QObject *watched, QEvent *event) override;

private:
    QMetaObject::Connection m_scrollToFocus; // a focused field scrolled into sight
    /// Gives the scrolled page the height its wrapped help texts need at its width.
    void fitPageHeight();
    void buildUi();
    /// Enables the fields the model uses, sets the friction range and the warning.
    void updateForModel(ModelKind model);
    /// Shows the book model's friction warnings for 1 < k <= 2 and k > 2, and the zero
    /// threshold's when gravity cannot set a marble at rest moving.
    void updateWarnings();
    /// Disables the exact and impulse entries of the model box while friction >= 1.
    void updateModelChoices();
    ModelKind shownModel() const;

    void onDoubleEdited(const QString &key, double value);
    /// Why a number typed into `spin` was refused (out of its range); the box kept its value.
    QString refusalText(const QAbstractSpinBox *spin, const Refusing &box, double refused) const;
    void onGravityEdited();
    void onModelActivated(int index);

    QDoubleSpinBox *m_massScale = nullptr;
    QDoubleSpinBox *m_friction = nullptr;
    QLabel *m_frictionWarning = nullptr;
    QLabel *m_thresholdWarning = nullptr;
    QLabel *m_refusalShown = nullptr; ///< the explanation line showing a refusal now, if any
    QDoubleSpinBox *m_zeroThreshold = nullptr;
    QDoubleSpinBox *m_pushScale = nullptr;
    QDoubleSpinBox *m_frameMs = nullptr;
    QComboBox *m_model = nullptr;
    QDoubleSpinBox *m_restitution = nullptr;
    QDoubleSpinBox *m_gravityX = nullptr;
    QDoubleSpinBox *m_gravityY = nullptr;
    QSpinBox *m_substeps = nullptr;
    QCheckBox *m_shortCircuit = nullptr;
    ModelKind m_currentModel = ModelKind::Book; ///< the model shown before the user's last choice
};

} // namespace marbles
