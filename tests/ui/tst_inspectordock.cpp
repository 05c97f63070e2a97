// The Inspector dock on a real SceneDocument: what it shows of the selected marble, and what
// typing into its fields does to the scene (through undoable edits, or not at all).

#include "core/presets.h"
#include "ui/inspectordock.h"
#include "ui/scenedocument.h"

#include <QApplication>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QSignalSpy>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

using namespace marbles;

namespace {

/// Replaces the text of a spin box as a user would: select it all, type, press Enter.
void typeInto(QAbstractSpinBox *spin, const QString &text)
{
    spin->setFocus();
    spin->selectAll();
    QTest::keyClicks(spin, text);
    QTest::keyClick(spin, Qt::Key_Return);
}

/// The red line under the fields.
QString errorText(const InspectorDock &dock)
{
    for (const QLabel *label : dock.findChildren<QLabel *>()) {
        if (label->styleSheet().contains(QStringLiteral("color")))
            return label->text();
    }
    return QStringLiteral("<no error line>");
}

} // namespace

class TestInspectorDock : public QObject {
    Q_OBJECT

private Q_SLOTS:
    void init();
    void cleanup();
    void tabGoesDownTheForm();
    void workedOutMassIsReadable();
    void showsTheSelectedMarble();
    void typedValuesAreUndoableEdits();
    void outOfRangeNumbersAreRefusedWhole_data();
    void outOfRangeNumbersAreRefusedWhole();
    void numbersBeyondTheFieldsAreSaid();
    void velocitiesShowTheZeroThresholdsDigits();
    void refusedEditShowsTheMarblesNumber();
    void fieldsFollowUndoAndReadPowersOfTen();
    void radiusIntoAnotherIsExplained();

private:
    std::unique_ptr<SceneDocument> m_document;
    std::unique_ptr<InspectorDock> m_dock;
};

void TestInspectorDock::init()
{
    m_document = std::make_unique<SceneDocument>();
    m_document->resetScene(defaultScene()); // the chapter's four marbles
    m_dock = std::make_unique<InspectorDock>(m_document.get());
    m_dock->show();
    QVERIFY(QTest::qWaitForWindowExposed(m_dock.get()));
}

void TestInspectorDock::cleanup()
{
    m_dock.reset();
    m_document.reset();
}

void TestInspectorDock::tabGoesDownTheForm()
{
    // The "mass scale x radius" box is on the way from Mass to x (Tab went past it).
    auto *mass = m_dock->findChild<QDoubleSpinBox *>(QStringLiteral("mass"));
    auto *box = m_dock->findChild<QCheckBox *>();
    auto *x = m_dock->findChild<QDoubleSpinBox *>(QStringLiteral("x"));
    QVERIFY(mass && box && x);
    // The next widget Tab can reach that is not part of `from` (a spin box's own line edit).
    auto after = [](QWidget *from) {
        QWidget *next = from->nextInFocusChain();
        while (from->isAncestorOf(next) || !(next->focusPolicy() & Qt::TabFocus))
            next = next->nextInFocusChain();
        return next;
    };
    QCOMPARE(after(mass), box);
    QCOMPARE(after(box), x);
}

void TestInspectorDock::workedOutMassIsReadable()
{
    // A mass worked out as mass scale x radius was a disabled field: pale grey on light grey,
    // about 1.9:1 (a keyboard tester's finding), passed by Tab and by a screen reader. It is
    // read-only instead, in the text's colour, without the arrows of a field to type in.
    const auto luminance = [](QColor c) {
        const auto channel = [](double v) { return v <= 0.03928 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
        return 0.2126 * channel(c.redF()) + 0.7152 * channel(c.greenF()) + 0.0722 * channel(c.blueF());
    };
    const auto contrast = [&](QColor a, QColor b) {
        const double la = luminance(a);
        const double lb = luminance(b);
        return (std::max(la, lb) + 0.05) / (std::min(la, lb) + 0.05);
    };
    m_dock->setMarble(2);
    QVERIFY(!m_document->world().info[2].hasMass);
    QDoubleSpinBox *mass = m_dock->field(QStringLiteral("mass"));
    QDoubleSpinBox *radius = m_dock->field(QStringLiteral("radius"));
    QVERIFY(mass->isEnabled());
    QVERIFY(mass->isReadOnly());
    QCOMPARE(mass->buttonSymbols(), QAbstractSpinBox::NoButtons);
    const QPalette shown = mass->palette();
    QCOMPARE_GE(contrast(shown.color(QPalette::Active, QPalette::Text), shown.color(QPalette::Active, QPalette::Base)), 4.5);
    QCOMPARE(shown.color(QPalette::Active, QPalette::Base), shown.color(QPalette::Active, QPalette::Window));
    // Tab stops at it on the way down, and typing does not change it.
    radius->setFocus();
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Tab);
    QVERIFY(mass->isAncestorOf(QApplication::focusWidget()) || QApplication::focusWidget() == mass);
    const double before = m_document->world().mass[2];
    QTest::keyClicks(QApplication::focusWidget(), QStringLiteral("9"));
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Return);
    QCOMPARE(m_document->world().mass[2], before);
    QCOMPARE(m_document->undoStack()->count(), 0);

    // A theme changed while it shows (to dark): the field follows, its text as readable.
    QPalette dark = QApplication::palette();
    dark.setColor(QPalette::Window, QColor(0x30, 0x30, 0x30));
    dark.setColor(QPalette::Base, QColor(0x20, 0x20, 0x20));
    dark.setColor(QPalette::Text, QColor(0xee, 0xee, 0xee));
    dark.setColor(QPalette::WindowText, QColor(0xee, 0xee, 0xee));
    const QPalette light = QApplication::palette();
    QApplication::setPalette(dark);
    QTRY_COMPARE(mass->palette().color(QPalette::Active, QPalette::Base), QColor(0x30, 0x30, 0x30));
    QCOMPARE_GE(contrast(mass->palette().color(QPalette::Active, QPalette::Text), mass->palette().color(QPalette::Active, QPalette::Base)), 4.5);
    QApplication::setPalette(light);
    QTRY_COMPARE(mass->palette().color(QPalette::Active, QPalette::Base), light.color(QPalette::Active, QPalette::Window));

    // Unticked, the marble has a mass of its own, in a field to type in.
    m_dock->findChild<QCheckBox *>()->click();
    QVERIFY(m_document->world().info[2].hasMass);
    QVERIFY(!mass->isReadOnly());
    QCOMPARE(mass->buttonSymbols(), QAbstractSpinBox::UpDownArrows);
    QCOMPARE(mass->palette().color(QPalette::Active, QPalette::Base), m_dock->palette().color(QPalette::Active, QPalette::Base));

    // Unticked, a mass typed, ticked again: three undo steps (they had been one, and Ctrl+Z went
    // past the mass typed, a re-tester's finding), each undone to the field it left.
    QCOMPARE(m_document->undoStack()->count(), 1);
    mass->setFocus();
    mass->selectAll();
    QTest::keyClicks(mass, QStringLiteral("80"));
    QTest::keyClick(mass, Qt::Key_Return);
    QCOMPARE(m_document->world().mass[2], 80.0);
    m_dock->findChild<QCheckBox *>()->click();
    QVERIFY(!m_document->world().info[2].hasMass);
    QCOMPARE(m_document->undoStack()->count(), 3);
    m_document->undoStack()->undo();
    QVERIFY(m_document->world().info[2].hasMass);
    QCOMPARE(m_document->world().mass[2], 80.0);
    QVERIFY(!mass->isReadOnly());
    m_document->undoStack()->undo();
    QCOMPARE(m_document->world().mass[2], before);
    QVERIFY(m_document->world().info[2].hasMass);
}

void TestInspectorDock::showsTheSelectedMarble()
{
    // Nothing selected: no fields (no stale numbers). Marble 2 selected: its numbers.
    QVERIFY(!m_dock->field(QStringLiteral("radius"))->isVisible());
    m_dock->setMarble(2);
    const World &world = m_document->world();
    QVERIFY(m_dock->field(QStringLiteral("radius"))->isVisible());
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("radius"))->value() - world.radius[2]), 0.005);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("x"))->value() - world.position[2].x), 0.005);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("y"))->value() - world.position[2].y), 0.005);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("mass"))->value() - world.mass[2]), 0.0005);
    // A frame later (pushed first, so it moves), the fields follow.
    m_document->pushMarble(2, {world.position[2].x - 10.0, world.position[2].y});
    m_document->advance(1);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("x"))->value() - m_document->world().position[2].x), 0.005);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("vx"))->value() - m_document->world().velocity[2].x), 0.0005);
    QCOMPARE_GT(m_document->world().velocity[2].x, 0.0);
    m_dock->setMarble(-1);
    QVERIFY(!m_dock->field(QStringLiteral("radius"))->isVisible());
}

void TestInspectorDock::typedValuesAreUndoableEdits()
{
    m_dock->setMarble(1);
    const World before = m_document->world();
    typeInto(m_dock->field(QStringLiteral("radius")), QStringLiteral("25"));
    QCOMPARE(m_document->world().radius[1], 25.0);
    // The mass follows the radius (massScale x r) while it is not set by hand.
    QCOMPARE(m_document->world().mass[1], before.params.massScale * 25.0);
    typeInto(m_dock->field(QStringLiteral("vx")), QStringLiteral("-3.5"));
    QCOMPARE(m_document->world().velocity[1].x, -3.5);
    QCOMPARE(m_document->world().velocity[1].y, before.velocity[1].y); // the other component as it was
    QCOMPARE(m_document->undoStack()->count(), 2);
    m_document->undoStack()->undo();
    m_document->undoStack()->undo();
    QCOMPARE(m_document->world().radius[1], before.radius[1]);
    QCOMPARE(m_document->world().mass[1], before.mass[1]);
    QCOMPARE(m_document->world().velocity[1].x, before.velocity[1].x);
    QCOMPARE_LE(std::abs(m_dock->field(QStringLiteral("radius"))->value() - before.radius[1]), 0.005);
}

void TestInspectorDock::outOfRangeNumbersAreRefusedWhole_data()
{
    QTest::addColumn<QString>("field");
    QTest::addColumn<QString>("typed");
    QTest::addColumn<QString>("message");
    // Without the refusal these came through as 600 px and 0.3 kept the old radius silently.
    QTest::newRow("radius above") << "radius" << "6000" << "6000 is above this field's maximum (5000 px)";
    QTest::newRow("radius below") << "radius" << "0.3" << "0.3 is below this field's minimum (0.5 px)";
    QTest::newRow("speed above") << "vx" << "200000" << "200000 is above this field's maximum (100000 px/frame)";
}

void TestInspectorDock::outOfRangeNumbersAreRefusedWhole()
{
    QFETCH(QString, field);
    QFETCH(QString, typed);
    QFETCH(QString, message);
    m_dock->setMarble(0);
    const World before = m_document->world();
    typeInto(m_dock->field(field), typed);
    QCOMPARE(m_document->undoStack()->count(), 0);
    QCOMPARE(m_document->world().radius[0], before.radius[0]);
    QCOMPARE(m_document->world().velocity[0].x, before.velocity[0].x);
    QVERIFY2(errorText(*m_dock).startsWith(message) && errorText(*m_dock).contains(QStringLiteral("it stays")),
             qPrintable(errorText(*m_dock)));
    // A value the field takes clears the line.
    typeInto(m_dock->field(QStringLiteral("radius")), QStringLiteral("30"));
    QCOMPARE(m_document->world().radius[0], 30.0);
    QCOMPARE(errorText(*m_dock), QString());
}

void TestInspectorDock::numbersBeyondTheFieldsAreSaid()
{
    // The book's blow-up (friction above 2) takes speeds far past what the fields hold: the field
    // shows its limit, and the line below them the true number. Back in range, the line goes.
    World scene = defaultScene();
    scene.velocity[1] = {1.25e27, -3.0};
    scene.position[1].y = std::numeric_limits<double>::quiet_NaN();
    m_document->resetScene(scene);
    m_dock->setMarble(1);
    auto *note = m_dock->findChild<QLabel *>(QStringLiteral("beyondNote"));
    QVERIFY(note);
    QVERIFY(note->isVisible());
    QCOMPARE(note->text(), QStringLiteral("y is not a number.\nvx is 1.25e+27 px/frame (the field stops at %1).")
                               .arg(m_dock->field(QStringLiteral("vx"))->textFromValue(1.0e5)));
    QCOMPARE(m_dock->field(QStringLiteral("vx"))->value(), 1.0e5);
    QCOMPARE(m_dock->field(QStringLiteral("vy"))->value(), -3.0);
    m_dock->setMarble(2);
    QVERIFY(!note->isVisible());
    m_dock->setMarble(1);
    QVERIFY(note->isVisible());
    m_dock->setMarble(-1);
    QVERIFY(!note->isVisible());
}

void TestInspectorDock::velocitiesShowTheZeroThresholdsDigits()
{
    // A velocity just above the zero threshold, left moving, read as the threshold itself
    // ("0.010" for 0.0104 with the default 0.01): the fields have two digits more than it.
    World scene = defaultScene();
    scene.velocity[1] = {0.0104, -0.0099};
    m_document->resetScene(scene);
    m_dock->setMarble(1);
    QDoubleSpinBox *vx = m_dock->field(QStringLiteral("vx"));
    QDoubleSpinBox *vy = m_dock->field(QStringLiteral("vy"));
    const QString unit = vx->suffix();
    QCOMPARE(vx->text(), vx->locale().toString(0.0104, 'f', 4) + unit);
    QCOMPARE(vy->text(), vy->locale().toString(-0.0099, 'f', 4) + unit);
    // The threshold changed: the digits follow it, three at the least, six at the most.
    for (const auto &[threshold, decimals] : {std::pair{0.001, 5}, std::pair{0.5, 3}, std::pair{0.0, 3},
                                              std::pair{1e-9, 6}, std::pair{0.01, 4}}) {
        QVERIFY(m_document->setParam(QStringLiteral("zeroThreshold"), QString::number(threshold)).isEmpty());
        QCOMPARE(vx->decimals(), decimals);
        QCOMPARE(vy->decimals(), decimals);
    }
    QCOMPARE(m_document->world().velocity[1].x, 0.0104); // shown, never rounded into the scene
}

void TestInspectorDock::refusedEditShowsTheMarblesNumber()
{
    // x = 5000 puts marble 0 past the stage's edge: the edit is refused, and the field, still
    // being typed in, goes back to the marble's x (it kept showing 5000.00 while the marble
    // stayed where it was).
    m_dock->setMarble(0);
    const World before = m_document->world();
    QDoubleSpinBox *x = m_dock->field(QStringLiteral("x"));
    typeInto(x, QStringLiteral("5000"));
    QVERIFY(x->hasFocus());
    QCOMPARE(m_document->world().position[0].x, before.position[0].x);
    QCOMPARE_LE(std::abs(x->value() - before.position[0].x), 0.005);
    QVERIFY2(errorText(*m_dock).contains(QStringLiteral("overlap")), qPrintable(errorText(*m_dock)));
    QCOMPARE(m_document->undoStack()->count(), 0);
    // An accepted edit while typing keeps the typed number, which is the marble's.
    typeInto(x, QStringLiteral("150"));
    QCOMPARE(m_document->world().position[0].x, 150.0);
    QCOMPARE_LE(std::abs(x->value() - 150.0), 0.005);
}

void TestInspectorDock::radiusIntoAnotherIsExplained()
{
    // Grown into the large marble beside it: refused, with the reason under the fields.
    m_dock->setMarble(1);
    QDoubleSpinBox *field = m_dock->field(QStringLiteral("radius"));
    typeInto(field, QStringLiteral("240"));
    QCOMPARE(m_document->world().radius[1], 20.0);
    QVERIFY2(errorText(*m_dock).contains(QStringLiteral("would make the marble overlap")), qPrintable(errorText(*m_dock)));
}

void TestInspectorDock::fieldsFollowUndoAndReadPowersOfTen()
{
    m_dock->setMarble(1);
    const double radius = m_document->world().radius[1];
    QDoubleSpinBox *field = m_dock->field(QStringLiteral("radius"));
    typeInto(field, QStringLiteral("50")); // room to grow: the large marble is 105 px away, radius 40
    QCOMPARE(m_document->world().radius[1], 50.0);
    // Undone while the field still has the focus: it shows the radius the marble has again.
    QVERIFY(field->hasFocus());
    m_document->undoStack()->undo();
    QCOMPARE(m_document->world().radius[1], radius);
    QCOMPARE_LE(std::abs(field->value() - radius), 0.005);

    // Powers of ten: 2e1 is 20 (it was taken as 21, the 'e' dropped), 1.5E1 is 15; 1e308 is
    // refused as above the field's maximum (it was taken as 1308).
    typeInto(field, QStringLiteral("2e1"));
    QCOMPARE(m_document->world().radius[1], 20.0);
    typeInto(field, QStringLiteral("1.5E1"));
    QCOMPARE(m_document->world().radius[1], 15.0);
    typeInto(field, QStringLiteral("1e308"));
    QCOMPARE(m_document->world().radius[1], 15.0);
    QVERIFY2(errorText(*m_dock).startsWith(QStringLiteral("1e+308 is above this field's maximum")), qPrintable(errorText(*m_dock)));
    // An edit that changes nothing (Enter on the number shown) leaves no earlier refusal on show.
    typeInto(field, QString());
    QCOMPARE(m_document->world().radius[1], 15.0);
    QCOMPARE(errorText(*m_dock), QString());
    // Emptied, the field gets its number back, and says so (it came back without a word).
    field->setFocus();
    field->selectAll();
    QTest::keyClick(field, Qt::Key_Backspace);
    QTest::keyClick(field, Qt::Key_Return);
    QCOMPARE(m_document->world().radius[1], 15.0);
    QCOMPARE(errorText(*m_dock), QStringLiteral("The field was left empty: it stays 15.00 px."));
    typeInto(field, QStringLiteral("nan")); // read by QLocale as a number, and put back without a word
    QCOMPARE(m_document->world().radius[1], 15.0);
    QCOMPARE(errorText(*m_dock), QStringLiteral("nan is not a number: it stays 15.00 px."));
    // A field being typed in keeps its typing when the scene changes under it.
    field->setFocus();
    field->selectAll();
    QTest::keyClicks(field, QStringLiteral("3"));
    m_document->advance(1);
    QCOMPARE(field->cleanText(), QStringLiteral("3"));
}

QTEST_MAIN(TestInspectorDock)
#include "tst_inspectordock.moc"
