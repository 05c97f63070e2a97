#include "ui/parametersdock.h"

#include "core/sceneio.h"

#include "ui/dockpage.h"
#include "ui/focusedwheel.h"
#include "ui/numbertext.h"
#include "ui/quiettext.h"
#include "ui/refusingspinbox.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QScrollArea>
#include <QStyle>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

namespace marbles {

namespace {

/// A double spin box that keeps many decimals internally but shows only the ones that matter:
/// 0.01 reads "0.01", 20 reads "20", 0.125 reads "0.125" (up to decimals() digits).
class AdaptiveSpinBox : public RefusingDoubleSpinBox {
public:
    explicit AdaptiveSpinBox(QWidget *parent = nullptr)
        : RefusingDoubleSpinBox(parent)
    {
        setDecimals(6);
    }

    QString textFromValue(double value) const override
    {
        QLocale loc = locale();
        loc.setNumberOptions(loc.numberOptions() | QLocale::OmitGroupSeparator);
        QString text = loc.toString(value, 'f', decimals());
        const QString point = loc.decimalPoint();
        if (text.contains(point)) {
            const QString zero = loc.zeroDigit();
            while (text.endsWith(zero))
                text.chop(zero.size());
            if (text.endsWith(point))
                text.chop(point.size());
        }
        return text;
    }
};

/// The text setParam() reads for a number: the shortest decimal that round-trips, C locale.
QString numberText(double value)
{
    return QString::number(value, 'g', QLocale::FloatingPointShortest);
}

/// Small grey word-wrapped text under a field: the plain-words meaning of the parameter.
QLabel *explanationLabel(const QString &text, QWidget *parent)
{
    auto *label = new QLabel(text, parent);
    label->setWordWrap(true);
    QFont font = label->font();
    font.setPointSizeF(font.pointSizeF() * 0.9);
    label->setFont(font);
    setQuietText(label);
    label->setContentsMargins(0, 0, 0, 6);
    return label;
}

/// A field's explanation line back to its explanation, after a refusal was shown there.
void explainAgain(QLabel *help)
{
    help->setText(help->property("explanation").toString());
    help->setStyleSheet(QString());
    help->setForegroundRole(QPalette::WindowText); // its quiet colour (setQuietText())
}

// Why a number was refused, in the line under its field: in the Inspector's solid red, not in
// the explanation's placeholder role, whose half-transparent ink left the red at about 2:1
// contrast (hard to read on a projector).
void showRefusal(QLabel *help, const QString &text)
{
    help->setText(text);
    help->setForegroundRole(QPalette::WindowText);
    help->setStyleSheet(QStringLiteral("QLabel { color: %1; }").arg(QLatin1String(kRefusalColour)));
}

constexpr int kModelRole = Qt::UserRole; ///< model box item data: the setParam() value

// Tooltips for fields the current model ignores: they say why the field is disabled.
const char *const kRestitutionUnused =
    "Not used by the book model: its collisions share the speed by the chapter's mass ratio instead.";
const char *const kSubstepsUnused = "Only the impulse model divides a frame into sub-steps.";
const char *const kShortCircuitUnused = "Only the book model can stop testing a marble after its first hit.";
// The same, short, in the line under the field: longer there, the line widened the whole dock
// (a word-wrapped label asks for more width the longer its text), taking it from the stage.
const char *const kRestitutionUnusedShort = "Not used by the book model.";
const char *const kSubstepsUnusedShort = "Used by the impulse model only.";
const char *const kShortCircuitUnusedShort = "Used by the book model only.";

} // namespace

ParametersDock::ParametersDock(QWidget *parent)
    : QDockWidget(tr("Parameters"), parent)
{
    setObjectName(QStringLiteral("parametersDock"));
    buildUi();
    setParams(Params{});
}

void ParametersDock::buildUi()
{
    auto *page = new QWidget;
    auto *form = new QFormLayout(page);
    form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    form->setRowWrapPolicy(QFormLayout::DontWrapRows);
    form->setVerticalSpacing(2);

    // One row: label, field (formula in the tooltip of both), then the explanation under it.
    auto addField = [&](const QString &label, QWidget *field, const QString &formula, const QString &explanation) {
        field->setToolTip(formula);
        auto *labelWidget = new QLabel(label, page);
        // A row of several fields (gravity's x and y) hands its Alt key to the first of them.
        labelWidget->setBuddy(field->focusProxy() ? field->focusProxy() : field);
        labelWidget->setToolTip(formula);
        form->addRow(labelWidget, field);
        auto *help = explanationLabel(explanation, page);
        help->setObjectName(field->objectName() + QStringLiteral("Help"));
        help->setProperty("explanation", explanation);
        help->setProperty("usedExplanation", explanation); // updateForModel() adds why, where unused
        form->addRow(help);
        // A number refused by the field (or by one of its boxes) is explained in this line.
        QList<QAbstractSpinBox *> spins = field->findChildren<QAbstractSpinBox *>();
        spins.append(qobject_cast<QAbstractSpinBox *>(field));
        for (QAbstractSpinBox *spin : spins) {
            auto *box = dynamic_cast<Refusing *>(spin); // no Q_OBJECT, so no qobject_cast
            if (!box)
                continue;
            // Shown until the field takes a value, the one it had included (typing "0.1" where
            // 0.1 stayed after a refusal left the refusal up); leaving the field without typing
            // does not hide it unread.
            if (auto *edit = spin->findChild<QLineEdit *>())
                connect(edit, &QLineEdit::textEdited, spin, [spin] { spin->setProperty("typed", true); });
            connect(spin, &QAbstractSpinBox::editingFinished, this, [this, spin, box, help] {
                const std::optional<double> refused = box->takeRefused();
                const bool typed = spin->property("typed").toBool();
                spin->setProperty("typed", false);
                if (!refused && !typed)
                    return;
                // One refusal at a time, the latest: three fields refused in a row showed three
                // red lines, each long after it was read (a teacher tester's finding).
                if (m_refusalShown && m_refusalShown != help)
                    explainAgain(m_refusalShown);
                m_refusalShown = nullptr;
                if (refused) {
                    showRefusal(help, refusalText(spin, *box, *refused));
                    m_refusalShown = help;
                    Q_EMIT this->refused();
                } else {
                    explainAgain(help);
                }
            });
            const auto explain = [help] { explainAgain(help); };
            if (auto *real = qobject_cast<QDoubleSpinBox *>(spin))
                connect(real, &QDoubleSpinBox::valueChanged, this, explain);
            else if (auto *whole = qobject_cast<QSpinBox *>(spin))
                connect(whole, &QSpinBox::valueChanged, this, explain);
        }
    };
    auto makeSpin = [&](const char *name, double min, double max, double step, const QString &suffix) {
        auto *spin = new AdaptiveSpinBox(page);
        spin->setObjectName(QString::fromLatin1(name));
        spin->setRange(min, max);
        spin->setSingleStep(step);
        spin->setSuffix(suffix);
        return spin;
    };

    // The chapter's constants first, in the order the chapter introduces them. Each label's
    // Alt key is its own, and none is a menu's (File, Edit, Simulation, View, Help): Alt+F went
    // to Friction instead of the File menu, Alt+H to Short circuit. The Plot dock's are apart too.
    m_massScale = makeSpin("massScaleEdit", 0.000001, 1000.0, 0.05, tr(" per px"));
    addField(tr("&Mass scale"), m_massScale, tr("m = mass scale \u00d7 r"),
             tr("Mass per pixel of radius: bigger marbles are heavier. Hits depend on the ratio of "
                "masses only; the scale changes how far a click pushes, and the energy and momentum figures "
                "(for the marbles without a mass of their own)."));

    m_friction = makeSpin("frictionEdit", 0.0, kBookFrictionMax, 0.01, QString());
    addField(tr("Fr&iction"), m_friction,
             tr("book: a += \u2212v \u00d7 k\nexact, impulse: the velocity is multiplied by (1 \u2212 k) each frame (smoothly over the frame in exact)"),
             tr("Fraction of its speed a marble loses to air each frame. The book model takes up to 3, "
                "to show where its arithmetic breaks (above 1 a marble swings back and forth)."));
    // A warning line under a field, shown while what it says holds (updateWarnings()).
    const auto addWarning = [page, form](const QString &name) {
        auto *warning = new QLabel(page);
        warning->setObjectName(name);
        warning->setWordWrap(true);
        warning->setTextFormat(Qt::PlainText);
        warning->setContentsMargins(0, 0, 0, 6);
        warning->setVisible(false);
        form->addRow(warning);
        return warning;
    };
    m_frictionWarning = addWarning(QStringLiteral("frictionWarning"));

    m_zeroThreshold = makeSpin("zeroThresholdEdit", 0.0, 1000.0, 0.005, tr(" px/frame"));
    addField(tr("&Zero threshold"), m_zeroThreshold,
             tr("if \u2212Z \u2264 v.x \u2264 Z then v.x = 0 (the same for v.y)"),
             tr("A velocity component (x or y) no larger than this snaps to exactly zero: a slow marble "
                "comes to rest, and one moving nearly along an axis loses its small sideways part."));
    m_thresholdWarning = addWarning(QStringLiteral("thresholdWarning"));

    m_pushScale = makeSpin("pushScaleEdit", -1000000.0, 1000000.0, 1.0, QString());
    addField(tr("&Push scale"), m_pushScale, tr("a += (centre \u2212 click) \u00d7 push scale / m"),
             tr("How hard a click pushes; clicking further from the centre pushes harder (negative pulls)."));

    m_frameMs = makeSpin("frameMsEdit", 0.1, 10000.0, 1.0, tr(" ms"));
    addField(tr("Frame i&nterval"), m_frameMs, tr("at 1\u00d7 speed one frame lasts this many ms of real time (the toolbar's speed divides it); the physics counts frames"),
             tr("Real time between two frames at 1\u00d7 speed: changes how fast the run plays, not its physics. The time shown "
                "(t, the plot in seconds) counts every frame at this interval, those before a change too."));

    // The models and what only they use.
    m_model = new FocusedWheel<QComboBox>(page); // as the number fields
    m_model->setObjectName(QStringLiteral("modelEdit"));
    m_model->setAccessibleName(tr("Model")); // a screen reader read out its current text alone
    m_model->addItem(tr("Book (the chapter's code)"), QStringLiteral("book"));
    m_model->addItem(tr("Impulse (what games do)"), QStringLiteral("impulse"));
    m_model->addItem(tr("Exact (the reference)"), QStringLiteral("exact"));
    addField(tr("M&odel"), m_model,
             tr("book: the chapter, step by step, flaws included\n"
                "impulse: sub-steps with momentum-conserving impulses\n"
                "exact: continuous time, collisions at their exact moment"),
             tr("Which physics moves the marbles: the book's, a game engine's, or the exact one."));

    m_restitution = makeSpin("restitutionEdit", 0.0, 1.0, 0.05, QString());
    addField(tr("&Restitution"), m_restitution,
             tr("v\u2099' = \u2212e \u00d7 v\u2099 (the speed of approach along the hit, for two marbles the one "
                "relative to the other)"),
             tr("Bounciness: the share of the speed of approach along a hit that comes back (1: all of it; 0: none, "
                "two marbles move on together, a marble stops against a wall or pin)."));

    auto *gravity = new QWidget(page);
    gravity->setObjectName(QStringLiteral("gravityEdit"));
    auto *gravityRow = new QHBoxLayout(gravity);
    gravityRow->setContentsMargins(0, 0, 0, 0);
    m_gravityX = makeSpin("gravityXEdit", -1000.0, 1000.0, 0.05, QString());
    m_gravityY = makeSpin("gravityYEdit", -1000.0, 1000.0, 0.05, QString());
    m_gravityX->setPrefix(QStringLiteral("x "));
    m_gravityY->setPrefix(QStringLiteral("y "));
    // Without a label each of their own, a screen reader named them not at all (a helper's finding).
    m_gravityX->setAccessibleName(tr("Gravity x"));
    m_gravityY->setAccessibleName(tr("Gravity y"));
    gravityRow->addWidget(m_gravityX);
    gravityRow->addWidget(m_gravityY);
    gravity->setFocusProxy(m_gravityX);
    const QString gravityFormula = tr("a += g (px/frame\u00b2) every frame");
    m_gravityX->setToolTip(gravityFormula);
    m_gravityY->setToolTip(gravityFormula);
    addField(tr("&Gravity"), gravity, gravityFormula,
             tr("A steady pull on every marble, in px/frame\u00b2; y points down the screen."));

    m_substeps = new CountSpinBox(page);
    m_substeps->setObjectName(QStringLiteral("substepsEdit"));
    m_substeps->setRange(1, 1000);
    addField(tr("Su&bsteps"), m_substeps, tr("h = 1 / substeps frame"),
             tr("Smaller steps inside each frame: more accurate, but slower."));

    m_shortCircuit = new QCheckBox(tr("Stop at the first hit"), page);
    m_shortCircuit->setObjectName(QStringLiteral("shortCircuitEdit"));
    addField(tr("Short circ&uit"), m_shortCircuit, tr("after a marble's first hit, skip its remaining tests this frame"),
             tr("The shortcut the chapter suggests (its own code does not take it): a marble checks no more "
                "walls, pins or marbles once it hits one, so it can miss a second hit."));

    // Remember each field's own tooltip: a disabled field shows why instead, and gets it back.
    for (QWidget *w : {static_cast<QWidget *>(m_restitution), static_cast<QWidget *>(m_substeps),
                       static_cast<QWidget *>(m_shortCircuit)})
        w->setProperty("formulaToolTip", w->toolTip());

    // A projector's small dock scrolls, and changed a model it did not show before the focused
    // field was scrolled into sight.
    m_scrollToFocus = putInScrollArea(this, page);
    page->installEventFilter(this);

    connect(m_massScale, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("massScale"), v); });
    connect(m_friction, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("friction"), v); });
    connect(m_zeroThreshold, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("zeroThreshold"), v); });
    connect(m_pushScale, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("pushScale"), v); });
    connect(m_frameMs, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("frameMs"), v); });
    connect(m_restitution, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { onDoubleEdited(QStringLiteral("restitution"), v); });
    connect(m_gravityX, &QDoubleSpinBox::valueChanged, this, &ParametersDock::onGravityEdited);
    connect(m_gravityY, &QDoubleSpinBox::valueChanged, this, &ParametersDock::onGravityEdited);
    connect(m_substeps, &QSpinBox::valueChanged, this,
            [this](int v) { emit paramEdited(QStringLiteral("substeps"), QString::number(v)); });
    connect(m_shortCircuit, &QCheckBox::toggled, this, [this](bool on) {
        emit paramEdited(QStringLiteral("shortCircuit"), on ? QStringLiteral("true") : QStringLiteral("false"));
    });
    connect(m_model, &QComboBox::activated, this, &ParametersDock::onModelActivated);
}

ParametersDock::~ParametersDock()
{
    disconnect(m_scrollToFocus);
}

QString ParametersDock::refusalText(const QAbstractSpinBox *spin, const Refusing &box, double refused) const
{
    if (spin == m_friction && shownModel() != ModelKind::Book && refused >= 1.0)
        return tr("Exact and impulse need friction below 1: %1 was refused, it stays %2 (book: up to %3).")
            .arg(refusedNumber(box, refused, spin->locale()), box.shown(box.current()), box.shown(kBookFrictionMax));
    return refusalMessage(box, refused, spin->locale());
}

void ParametersDock::clearRefusal()
{
    if (m_refusalShown)
        explainAgain(m_refusalShown);
    m_refusalShown = nullptr;
}

void ParametersDock::setParams(const Params &params)
{
    const QSignalBlocker b1(m_massScale), b2(m_friction), b3(m_zeroThreshold), b4(m_pushScale), b5(m_frameMs),
        b6(m_model), b7(m_restitution), b8(m_gravityX), b9(m_gravityY), b10(m_substeps), b11(m_shortCircuit);

    // Values set from the scene (opened, undone, edited elsewhere) replace any refusal shown.
    for (QLabel *help : findChildren<QLabel *>()) {
        if (help->property("explanation").isValid())
            explainAgain(help);
    }
    m_model->setCurrentIndex(m_model->findData(QString::fromLatin1(modelName(params.model))));
    m_currentModel = params.model;
    // The friction range depends on the model: set it before the value so the value is not clamped.
    updateForModel(params.model);
    // A valid scene may hold a value beyond a field's usual range (a book friction of 5, ten
    // thousand substeps): widen the range rather than show a wrong, clamped value. Only the
    // limits that are conveniences move; the rules (massScale > 0, friction >= 0, ...) stay.
    auto show = [](auto *field, auto value, bool lowerIsRule, bool upperIsRule = false) {
        if (!lowerIsRule && value < field->minimum())
            field->setMinimum(value);
        if (!upperIsRule && value > field->maximum())
            field->setMaximum(value);
        showSceneValue(field, value);
    };
    show(m_massScale, params.massScale, true);
    show(m_friction, params.friction, true, params.model != ModelKind::Book);
    show(m_zeroThreshold, params.zeroThreshold, true);
    show(m_pushScale, params.pushScale, false);
    // Its lowest, 0.1 ms, is a convenience: the rule is > 0 (a file's 0.05 ms read "0.1 ms", and
    // the figures per second were twice what the field said).
    show(m_frameMs, params.frameMs, false);
    showSceneValue(m_restitution, params.restitution);
    show(m_gravityX, params.gravity.x, false);
    show(m_gravityY, params.gravity.y, false);
    show(m_substeps, params.substeps, true);
    m_shortCircuit->setChecked(params.shortCircuit);

    updateWarnings();
    updateModelChoices();
}

Params ParametersDock::shownParams() const
{
    Params p;
    p.model = shownModel();
    p.massScale = m_massScale->value();
    p.friction = m_friction->value();
    p.zeroThreshold = m_zeroThreshold->value();
    p.pushScale = m_pushScale->value();
    p.frameMs = m_frameMs->value();
    p.restitution = m_restitution->value();
    p.gravity = {m_gravityX->value(), m_gravityY->value()};
    p.substeps = m_substeps->value();
    p.shortCircuit = m_shortCircuit->isChecked();
    return p;
}

ModelKind ParametersDock::shownModel() const
{
    ModelKind kind = ModelKind::Book;
    parseModelName(m_model->currentData(kModelRole).toString().toStdString(), kind);
    return kind;
}

void ParametersDock::updateForModel(ModelKind model)
{
    const bool book = model == ModelKind::Book;
    const bool impulse = model == ModelKind::Impulse;

    {
        // The friction cap changes with the model: the exact and impulse models need k < 1
        // (their drag factor is (1 - k) per frame, raised to fractional powers).
        const QSignalBlocker block(m_friction);
        m_friction->setMaximum(book ? std::max(kBookFrictionMax, m_friction->value()) : kDampedFrictionMax);
    }

    auto enable = [this](QWidget *w, bool on, const char *why, const char *shortWhy) {
        w->setEnabled(on);
        w->setToolTip(on ? w->property("formulaToolTip").toString() : tr(why));
        // Said under the field too, in short: greyed out with its tooltip alone (shown only to a
        // pointer resting on it), Pachinko's restitution of 0.8 did not say why.
        if (auto *help = findChild<QLabel *>(w->objectName() + QStringLiteral("Help"))) {
            const QString used = help->property("usedExplanation").toString();
            help->setProperty("explanation", on ? used : tr(shortWhy) + QLatin1Char(' ') + used);
            explainAgain(help);
        }
    };
    enable(m_restitution, !book, kRestitutionUnused, kRestitutionUnusedShort);
    enable(m_substeps, impulse, kSubstepsUnused, kSubstepsUnusedShort);
    enable(m_shortCircuit, book, kShortCircuitUnused, kShortCircuitUnusedShort);
    updateWarnings();
}

void ParametersDock::updateWarnings()
{
    const auto show = [](QLabel *warning, const QString &text, QColor colour) {
        warning->setText(text);
        warning->setStyleSheet(
            text.isEmpty() ? QString() : QStringLiteral("QLabel { color: %1; font-weight: bold; }").arg(colour.name()));
        warning->setVisible(!text.isEmpty());
    };
    const QColor orange(0xb3, 0x5c, 0x00);
    // The book's update is v' = v + (-v k) = (1 - k) v each frame. For 1 < k <= 2 the factor
    // (1 - k) lies in [-1, 0): the velocity reverses every frame while it shrinks (or, at k = 2,
    // keeps its size). For k > 2, |1 - k| > 1: each frame multiplies the speed, so it grows
    // without bound. The exact and impulse models refuse k >= 1, so only the book can show this.
    const double k = m_friction->value();
    if (shownModel() == ModelKind::Book && k > 2.0)
        show(m_frictionWarning, tr("\u26a0 The book's update is unstable: speeds grow without bound (|1 \u2212 k| > 1)."),
             QColor(0xc6, 0x28, 0x28));
    else if (shownModel() == ModelKind::Book && k > 1.0)
        show(m_frictionWarning, tr("\u26a0 Velocity flips sign every frame (1 \u2212 k < 0)."), orange);
    else
        show(m_frictionWarning, QString(), QColor());
    // A marble at rest under gravity whose speed after a frame is within the threshold snaps back
    // to 0 every frame: it hung in mid-air with no word why (a teacher's finding). What one frame
    // does to it is asked of the model shown itself: the book's stays put, the exact model's and
    // the impulse model's creep on (they move it within the frame), and drag lowers the speed a
    // frame gives below |g|.
    QString held;
    const Params params = shownParams();
    const bool valid = validateParams(params).empty();
    if ((params.gravity.x != 0.0 || params.gravity.y != 0.0) && valid) {
        World probe;
        probe.stage = {1e9, 1e9, false};
        probe.params = params;
        const Vec2 start{5e8, 5e8};
        probe.addMarble(start, 1.0);
        probe.step();
        const Vec2 v = probe.velocity[0];
        const double moved = length({probe.position[0].x - start.x, probe.position[0].y - start.y});
        if (v.x == 0.0 && v.y == 0.0) {
            held = moved == 0.0
                ? tr("\u26a0 Gravity is within the zero threshold: a marble at rest stays where it is, even in mid-air.")
                : tr("\u26a0 Gravity is within the zero threshold: a marble at rest never gathers speed, it creeps "
                     "%1 px a frame.")
                      .arg(shownNumber(moved, 'g', 3));
        }
    }
    // A click at a marble's rim changes its velocity by pushScale / massScale (a = (p - c)
    // pushScale / m, |p - c| = r, m = massScale r), a click nearer its centre by less: with a
    // threshold at least that, every click's push was zeroed in its frame, and nothing said why
    // a marble clicked did not move.
    const double clickMost = std::abs(params.pushScale) / params.massScale;
    if (valid && clickMost > 0.0 && clickMost <= params.zeroThreshold) {
        if (!held.isEmpty())
            held += QLatin1Char('\n');
        held += tr("\u26a0 A click gives a marble at most %1 px/frame (push scale / mass scale): this threshold "
                   "zeroes it at once.")
                    .arg(shownNumber(clickMost, 'g', 3));
    }
    show(m_thresholdWarning, held, orange);
    fitPageHeight();
}

void ParametersDock::fitPageHeight()
{
    // Each wrapped help text must be as tall as its lines at the width it has. The form works
    // its height out for a width the text does not get (the row's, less the text's own
    // margins), and the scroll area not again when a warning comes or goes: the texts were
    // squeezed, their first and last lines cut off, a blank left under the friction field after
    // the warning went. Each text's smallest height is set from its width whenever the page's
    // changes, and the page grows to hold them (the scroll area scrolls it).
    auto *scroll = qobject_cast<QScrollArea *>(widget());
    QWidget *page = scroll ? scroll->widget() : nullptr;
    if (!page || !page->layout())
        return;
    page->layout()->activate(); // every text at the width the page gives it now
    bool changed = false;
    for (QLabel *text : page->findChildren<QLabel *>()) {
        if (!text->wordWrap() || text->text().isEmpty() || !text->isVisibleTo(page))
            continue;
        const int needed = text->heightForWidth(text->width());
        if (needed > 0 && text->minimumHeight() != needed) {
            text->setMinimumHeight(needed);
            changed = true;
        }
    }
    if (changed) {
        page->layout()->activate();
        scroll->setWidgetResizable(true); // lays the page out again, at its new smallest height
    }
}

bool ParametersDock::eventFilter(QObject *watched, QEvent *event)
{
    const auto *scroll = qobject_cast<const QScrollArea *>(widget());
    if (scroll && watched == scroll->widget() && event->type() == QEvent::Resize)
        fitPageHeight();
    return QDockWidget::eventFilter(watched, event);
}

int ParametersDock::fieldsWidth() const
{
    const auto *scroll = qobject_cast<const QScrollArea *>(widget());
    if (!scroll || !scroll->widget())
        return width();
    // The page as it asks to be, its scroll area's frame, room for the vertical scroll bar, and
    // the dock's own margins (its width less its content's).
    const int bar = scroll->style()->pixelMetric(QStyle::PM_ScrollBarExtent, nullptr, scroll);
    return scroll->widget()->sizeHint().width() + 2 * scroll->frameWidth() + bar + (width() - scroll->width());
}

void ParametersDock::updateModelChoices()
{
    // The exact and impulse models need friction < 1: while it is higher, they cannot be chosen.
    auto *items = qobject_cast<QStandardItemModel *>(m_model->model());
    if (!items)
        return;
    const bool damped = m_friction->value() < 1.0;
    for (int row = 0; row < items->rowCount(); ++row) {
        QStandardItem *item = items->item(row);
        if (item->data(kModelRole).toString() == QLatin1String("book"))
            continue;
        item->setEnabled(damped);
        item->setToolTip(damped ? QString() : tr("Needs friction below 1: lower the friction first."));
    }
}

void ParametersDock::onDoubleEdited(const QString &key, double value)
{
    if (key == QLatin1String("friction"))
        updateModelChoices();
    updateWarnings();
    emit paramEdited(key, numberText(value));
}

void ParametersDock::onGravityEdited()
{
    updateWarnings();
    emit paramEdited(QStringLiteral("gravity"),
                     numberText(m_gravityX->value()) + QLatin1Char(',') + numberText(m_gravityY->value()));
}

void ParametersDock::onModelActivated(int index)
{
    const QString key = m_model->itemData(index, kModelRole).toString();
    ModelKind kind = ModelKind::Book;
    if (!parseModelName(key.toStdString(), kind) || kind == m_currentModel)
        return;
    m_currentModel = kind;
    updateForModel(kind);
    emit paramEdited(QStringLiteral("model"), key);
}

} // namespace marbles
