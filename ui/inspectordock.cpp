#include "ui/inspectordock.h"

#include "ui/dockpage.h"
#include "ui/numbertext.h"
#include "ui/refusingspinbox.h"
#include "ui/scenedocument.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QScreen>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QStringList>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

namespace marbles {

namespace {

QDoubleSpinBox *makeBox(double min, double max, int decimals, const QString &suffix, const QString &tip)
{
    // Typed values apply on Enter or when the field loses focus, not at every keystroke; a
    // number beyond the range is refused whole (see onRefused), not cut to one within it.
    auto *box = new RefusingDoubleSpinBox();
    box->setRange(min, max);
    box->setDecimals(decimals);
    box->setSuffix(suffix);
    box->setToolTip(tip);
    return box;
}

void showValue(QDoubleSpinBox *box, double value, bool overTyping)
{
    // Typing not yet taken is left alone; a field whose number was taken shows the scene's, even
    // with the focus (an Undo right after Enter left the undone radius on show).
    const auto *refusing = dynamic_cast<const Refusing *>(box);
    if (box->hasFocus() && refusing && refusing->typing() && !overTyping)
        return;
    const QSignalBlocker blocker(box);
    showSceneValue(box, value);
}

} // namespace

InspectorDock::InspectorDock(SceneDocument *document, QWidget *parent)
    : QDockWidget(tr("Inspector"), parent)
    , m_document(document)
{
    setObjectName(QStringLiteral("inspectorDock"));
    auto *body = new QWidget(this);
    auto *layout = new QVBoxLayout(body);
    m_title = new QLabel(body);
    m_title->setWordWrap(true);
    layout->addWidget(m_title);

    m_form = new QWidget(body);
    auto *form = new QFormLayout(m_form);
    form->setContentsMargins(0, 0, 0, 0);
    m_radius = makeBox(0.5, 5000.0, 2, tr(" px"), tr("Radius r, px. The mass follows as mass scale \u00d7 r unless the marble has its own."));
    m_mass = makeBox(0.001, 1.0e9, 3, QString(), massTip(true));
    m_autoMass = new QCheckBox(tr("mass scale × radius"), m_form);
    m_autoMass->setToolTip(tr("Checked: the mass is the mass scale (Parameters) times the radius, as in the book; "
                              "unchecked: the marble has a mass of its own."));
    m_x = makeBox(-1.0e6, 1.0e6, 2, tr(" px"), tr("Centre x, px (right is +x)."));
    m_y = makeBox(-1.0e6, 1.0e6, 2, tr(" px"), tr("Centre y, px (down is +y)."));
    m_vx = makeBox(-1.0e5, 1.0e5, 3, tr(" px/frame"), tr("Velocity x, px per frame."));
    m_vy = makeBox(-1.0e5, 1.0e5, 3, tr(" px/frame"), tr("Velocity y, px per frame."));
    // A name a class can call the marble by ("heavy", "cue ball"): the plot's legend and the
    // saved scene carry it (presets had names, a teacher's own marbles could not get one).
    m_name = new QLineEdit(m_form);
    m_name->setObjectName(QStringLiteral("name"));
    m_name->setClearButtonEnabled(true);
    m_name->setToolTip(tr("The marble's name, shown in the plot's legend and kept in the saved scene; empty for none."));
    m_radius->setObjectName(QStringLiteral("radius"));
    m_mass->setObjectName(QStringLiteral("mass"));
    m_x->setObjectName(QStringLiteral("x"));
    m_y->setObjectName(QStringLiteral("y"));
    m_vx->setObjectName(QStringLiteral("vx"));
    m_vy->setObjectName(QStringLiteral("vy"));
    form->addRow(tr("Name"), m_name);
    form->addRow(tr("Radius"), m_radius);
    form->addRow(tr("Mass"), m_mass);
    form->addRow(QString(), m_autoMass);
    form->addRow(tr("x"), m_x);
    form->addRow(tr("y"), m_y);
    form->addRow(tr("vx"), m_vx);
    form->addRow(tr("vy"), m_vy);
    layout->addWidget(m_form);
    // Down the form, the check box included (Tab went from Mass to x past it).
    QWidget *order[] = {m_name, m_radius, m_mass, m_autoMass, m_x, m_y, m_vx, m_vy};
    for (std::size_t k = 1; k < std::size(order); ++k)
        QWidget::setTabOrder(order[k - 1], order[k]);

    // A field shows numbers within its range only; a marble past it (the book's blow-up at a
    // friction above 2 reaches 1e27 px/frame and more) gets its true numbers said here.
    m_beyond = new QLabel(body);
    m_beyond->setObjectName(QStringLiteral("beyondNote"));
    m_beyond->setWordWrap(true);
    m_beyond->setVisible(false);
    layout->addWidget(m_beyond);

    m_compared = new QLabel(body);
    m_compared->setObjectName(QStringLiteral("comparedNote"));
    m_compared->setWordWrap(true);
    m_compared->setVisible(false);
    layout->addWidget(m_compared);

    m_error = new QLabel(body);
    m_error->setWordWrap(true);
    m_error->setStyleSheet(QStringLiteral("color: %1;").arg(QLatin1String(kRefusalColour)));
    // Room for three lines kept at all times, as the longest refusals take ("... can be read two
    // ways ..."): a message that appeared took its room from the fields, which moved up under the
    // pointer aimed at one of them.
    m_error->setMinimumHeight(3 * m_error->fontMetrics().lineSpacing());
    m_error->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    layout->addWidget(m_error);
    layout->addStretch(1);
    // Filled in for a marble, the page is taller than a projector's dock has room for: it grew
    // the window past the screen's edge (the status bar below it) and moved the stage between
    // the press and the release of the click that selected the marble.
    m_scrollToFocus = putInScrollArea(this, body);

    for (QDoubleSpinBox *box : {m_radius, m_mass, m_x, m_y, m_vx, m_vy}) {
        connect(box, &QAbstractSpinBox::editingFinished, this, [this, box] {
            // Runs after the edit's valueChanged (and its report()): a number refused here is
            // explained; an edit that changed nothing (a blank, letters) leaves no earlier
            // refusal on show, which would read as this edit's.
            auto *refusing = dynamic_cast<Refusing *>(box);
            if (const std::optional<double> refused = refusing ? refusing->takeRefused() : std::nullopt) {
                m_error->setText(refusalMessage(*refusing, *refused, box->locale()));
                Q_EMIT this->refused();
            } else if (!m_reportedThisEdit) {
                m_error->clear();
            }
            m_reportedThisEdit = false;
        });
    }
    connect(m_name, &QLineEdit::editingFinished, this, [this] {
        if (m_marble >= 0 && m_name->isModified()) {
            m_name->setModified(false);
            report(m_document->setMarbleName(m_marble, m_name->text()));
        }
    });
    connect(m_radius, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onRadius);
    connect(m_mass, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onMass);
    connect(m_autoMass, &QCheckBox::toggled, this, &InspectorDock::onAutoMass);
    connect(m_x, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onX);
    connect(m_y, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onY);
    connect(m_vx, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onVx);
    connect(m_vy, &QDoubleSpinBox::valueChanged, this, &InspectorDock::onVy);
    connect(m_document, &SceneDocument::stepped, this, &InspectorDock::refresh);
    connect(m_document, &SceneDocument::sceneChanged, this, &InspectorDock::refresh);
    refresh();
}

InspectorDock::~InspectorDock()
{
    // QWidget's destructor takes the focus from a field, which ends its edit: the fields' slots
    // here must not run on a dock already half destroyed (UBSan saw it).
    disconnect(m_scrollToFocus);
    for (QDoubleSpinBox *box : {m_radius, m_mass, m_x, m_y, m_vx, m_vy})
        disconnect(box, nullptr, this, nullptr);
}

void InspectorDock::clearRefusal()
{
    m_error->clear();
}

QDoubleSpinBox *InspectorDock::field(const QString &name) const
{
    return m_form->findChild<QDoubleSpinBox *>(name);
}

void InspectorDock::setMarble(int i)
{
    m_marble = i;
    m_error->clear();
    refresh();
}

void InspectorDock::fitToPage()
{
    // Room for the whole page where the screen has it, at most two fifths of its height: in a
    // scroll area the page asked for none, and at 1600 x 1000 the fields came out under a
    // scroll bar, vy cut off (a helper's finding). On a projector's small screen the page
    // scrolls instead of making the window taller than the screen.
    auto *scroll = qobject_cast<QScrollArea *>(widget());
    if (!scroll || !scroll->widget())
        return;
    const int screenHeight = screen() ? screen()->availableGeometry().height() : 0;
    scroll->setMinimumHeight(std::min(scroll->widget()->sizeHint().height(), screenHeight * 2 / 5));
}

void InspectorDock::showMarble(bool overTyping)
{
    const World &world = m_document->world();
    if (m_marble < 0 || m_marble >= world.marbleCount()) {
        m_marble = -1;
        m_title->setText(tr("Select a marble to see and edit it."));
        m_compared->setVisible(false);
        // No stale numbers of a marble that is not selected: the fields go away until one is.
        m_form->setEnabled(false);
        m_form->setVisible(false);
        m_beyond->setVisible(false);
        fitToPage();
        return;
    }
    const QString name = QString::fromStdString(world.info[m_marble].name);
    // The name is in its field below: a long one in the title wrapped it onto a second line
    // and moved every field down under the pointer.
    m_title->setText(tr("Marble %1").arg(m_marble));
    // A name being typed is left alone, as a number being typed is; Esc puts back "kept".
    if (!(m_name->hasFocus() && m_name->isModified()) || overTyping) {
        m_name->setText(name);
        m_name->setModified(false);
    }
    m_name->setProperty("kept", name);
    m_name->setPlaceholderText(tr("marble %1").arg(m_marble));
    m_form->setEnabled(true);
    m_form->setVisible(true);
    for (QDoubleSpinBox *box : {m_vx, m_vy}) {
        if (const int decimals = velocityDecimals(world.params.zeroThreshold); box->decimals() != decimals) {
            const QSignalBlocker blocker(box);
            box->setDecimals(decimals);
        }
    }
    // Each field shows its number; one past the field's range is said in words below them.
    QStringList beyond;
    const std::pair<QDoubleSpinBox *, double> shown[] = {
        {m_radius, world.radius[m_marble]}, {m_mass, world.mass[m_marble]},
        {m_x, world.position[m_marble].x},  {m_y, world.position[m_marble].y},
        {m_vx, world.velocity[m_marble].x}, {m_vy, world.velocity[m_marble].y},
    };
    for (const auto &[box, value] : shown) {
        showValue(box, value, overTyping);
        if (value >= box->minimum() && value <= box->maximum())
            continue;
        if (std::isnan(value))
            beyond << tr("%1 is not a number.").arg(box->objectName());
        else
            beyond << tr("%1 is %2%3 (the field stops at %4).")
                          .arg(box->objectName(), shownNumber(value, 'g', 4), box->suffix(),
                               box->textFromValue(value < box->minimum() ? box->minimum() : box->maximum()));
    }
    {
        const QSignalBlocker blocker(m_autoMass);
        m_autoMass->setChecked(!world.info[m_marble].hasMass);
    }
    showMassEditable(world.info[m_marble].hasMass);
    m_beyond->setText(beyond.join(QLatin1Char('\n')));
    m_beyond->setVisible(!beyond.isEmpty());
    showCompared();
    fitToPage();
}

void InspectorDock::showMassEditable(bool editable)
{
    // A mass worked out from the radius is read-only, not disabled: disabled, its number was pale
    // grey on light grey (about 1.9:1, hard to read on a projector), and Tab and a screen reader
    // passed it by. Read-only, it keeps the text's colour on the window's background, without
    // arrows, so that it does not look like a field to type in.
    // (Shown at every frame of a run: only a switch changes anything.)
    if (m_mass->isReadOnly() != editable)
        return;
    m_mass->setToolTip(massTip(editable));
    m_mass->setReadOnly(!editable);
    m_mass->setButtonSymbols(editable ? QAbstractSpinBox::UpDownArrows : QAbstractSpinBox::NoButtons);
    paintMassField();
}

QString InspectorDock::massTip(bool editable)
{
    return editable ? tr("Mass m, the marble's own; ticking \"mass scale × radius\" gives it the book's mass scale × r.")
                    : tr("Mass m = mass scale (Parameters) × radius, as in the book; untick \"mass scale × radius\" to "
                         "give the marble a mass of its own.");
}

void InspectorDock::paintMassField()
{
    // The window's background, from the palette in force: a theme changed to dark while it showed
    // kept the light grey under the text turned light.
    QPalette shown = palette();
    if (m_mass->isReadOnly())
        shown.setColor(QPalette::Base, shown.color(QPalette::Window));
    m_mass->setPalette(shown);
}

void InspectorDock::changeEvent(QEvent *event)
{
    QDockWidget::changeEvent(event);
    // Once the new palette has reached the fields too (it comes to the dock first), and not
    // while the dock is being built.
    if ((event->type() == QEvent::PaletteChange || event->type() == QEvent::ApplicationPaletteChange) && m_mass)
        QMetaObject::invokeMethod(this, &InspectorDock::paintMassField, Qt::QueuedConnection);
}

void InspectorDock::setComparison(std::function<const World *()> world, std::function<QString()> model)
{
    m_comparison = std::move(world);
    m_comparisonModel = std::move(model);
    showCompared();
}

void InspectorDock::showCompared()
{
    // The marble as the compared model has it at the same frame (its dashed ghost), with the
    // fields' decimals, so that the two can be read one above the other.
    const World &world = m_document->world();
    const World *compared = m_comparison ? m_comparison() : nullptr;
    const bool shown = compared && m_marble >= 0 && m_marble < world.marbleCount()
        && compared->marbleCount() == world.marbleCount() && compared->frame == world.frame;
    m_compared->setVisible(shown);
    if (!shown)
        return;
    const auto k = static_cast<std::size_t>(m_marble);
    const Vec2 p = compared->position[k];
    const Vec2 v = compared->velocity[k];
    const int decimals = velocityDecimals(world.params.zeroThreshold);
    // Its numbers separated as in a list, and its two parts by a dash where that is a semicolon
    // ("x 232,29; y 298,92 px \u2014 vx ..." in German: "x 232,29, y" read as one number).
    const QString sep = shownListSeparator();
    const QString parts = sep == QLatin1String(", ") ? QStringLiteral("; ") : QStringLiteral(" \u2014 ");
    m_compared->setText(tr("In the %1 model (its ghost): x %2%6y %3 px%7vx %4%6vy %5 px/frame")
                            .arg(m_comparisonModel ? m_comparisonModel() : QString(), shownNumber(p.x, 'f', 2), shownNumber(p.y, 'f', 2),
                                 shownNumber(v.x, 'f', decimals), shownNumber(v.y, 'f', decimals), sep, parts));
}

void InspectorDock::report(const QString &error)
{
    m_reportedThisEdit = true;
    m_error->setText(error);
    if (!error.isEmpty()) {
        Q_EMIT refused();
        Q_EMIT message(error);
        showMarble(true);
    }
}

void InspectorDock::onRadius(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarbleRadius(m_marble, value));
}

void InspectorDock::onMass(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarbleMass(m_marble, value));
}

void InspectorDock::onAutoMass(bool automatic)
{
    if (m_marble < 0)
        return;
    report(m_document->setMarbleMass(m_marble, automatic ? 0.0 : m_document->world().mass[m_marble]));
}

// Each field changes only its own component: the other keeps its exact value, not the rounded one shown.
void InspectorDock::onX(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarblePosition(m_marble, {value, m_document->world().position[m_marble].y}));
}

void InspectorDock::onY(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarblePosition(m_marble, {m_document->world().position[m_marble].x, value}));
}

void InspectorDock::onVx(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarbleVelocity(m_marble, {value, m_document->world().velocity[m_marble].y}));
}

void InspectorDock::onVy(double value)
{
    if (m_marble >= 0)
        report(m_document->setMarbleVelocity(m_marble, {m_document->world().velocity[m_marble].x, value}));
}

} // namespace marbles
