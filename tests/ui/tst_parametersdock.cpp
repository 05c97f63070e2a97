#include "core/sceneio.h"
#include "core/world.h"
#include "ui/parametersdock.h"

#include <QAbstractSpinBox>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QScrollArea>
#include <QLineEdit>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QTest>
#include <QWheelEvent>

#include <cmath>

using namespace marbles;

class TestParametersDock : public QObject {
    Q_OBJECT

private slots:
    void typingEmitsEdit_data();
    void typingEmitsEdit();
    void modelBoxEmitsEdit();
    void shortCircuitEmitsEdit();
    void setParamsEmitsNothing();
    void decimalsShown_data();
    void decimalsShown();
    void sceneValuesBelowTheFieldsAreShown();
    void invalidValuesRefused_data();
    void invalidValuesRefused();
    void focusedFieldIsScrolledIntoSight();
    void gravityTakesItsAltKey();
    void refusalIsExplainedUntilTheNextEdit();
    void wheelChangesOnlyTheFieldBeingEdited();
    void frictionWarning_data();
    void frictionWarning();
    void typedFrictionWarns();
    void thresholdAboveGravityWarns();
    void otherLocalesDecimalPoint();
    void unreadableTextIsRefused_data();
    void unreadableTextIsRefused();
    void stepsLandOnShownValues();
    void suffixStaysWhole();
    void fieldsFollowModel_data();
    void fieldsFollowModel();
    void dampedModelsNeedFrictionBelowOne();
    void everyFieldExplained_data();
    void everyFieldExplained();
};

namespace {

Params paramsWithModel(const QString &model)
{
    Params p;
    parseModelName(model.toStdString(), p.model);
    return p;
}

/// Shows `dock` with the default parameters of `model`; false if it never appeared.
bool showWithModel(ParametersDock &dock, const QString &model)
{
    dock.setParams(paramsWithModel(model));
    dock.show();
    return QTest::qWaitForWindowExposed(&dock);
}

/// Replaces the text of a spin box as a user would: select it all, type, press Enter.
void typeInto(QAbstractSpinBox *spin, const QString &text)
{
    spin->setFocus();
    spin->selectAll();
    QTest::keyClicks(spin, text);
    if (text.isEmpty())
        QTest::keyClick(spin, Qt::Key_Backspace); // emptied
    QTest::keyClick(spin, Qt::Key_Return);
}

/// The core's verdict on an emitted edit: "" when setParam and validateParams accept it.
std::string coreVerdict(const Params &before, const QString &key, const QString &value)
{
    World world;
    world.params = before;
    std::string error = setParam(world, key.toStdString(), value.toStdString());
    if (error.empty())
        error = validateParams(world.params);
    return error;
}

} // namespace

void TestParametersDock::typingEmitsEdit_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<QString>("field");
    QTest::addColumn<QString>("typed");
    QTest::addColumn<QString>("key");
    QTest::addColumn<QString>("value");

    QTest::addRow("massScale") << "book" << "massScaleEdit" << "2.5" << "massScale" << "2.5";
    QTest::addRow("friction") << "book" << "frictionEdit" << "0.25" << "friction" << "0.25";
    QTest::addRow("friction book above 1") << "book" << "frictionEdit" << "1.5" << "friction" << "1.5";
    QTest::addRow("friction exact") << "exact" << "frictionEdit" << "0.95" << "friction" << "0.95";
    QTest::addRow("zeroThreshold small") << "book" << "zeroThresholdEdit" << "0.005" << "zeroThreshold" << "0.005";
    QTest::addRow("zeroThreshold zero") << "book" << "zeroThresholdEdit" << "0" << "zeroThreshold" << "0";
    QTest::addRow("pushScale") << "book" << "pushScaleEdit" << "12.5" << "pushScale" << "12.5";
    QTest::addRow("frameMs") << "book" << "frameMsEdit" << "40" << "frameMs" << "40";
    QTest::addRow("restitution impulse") << "impulse" << "restitutionEdit" << "0.75" << "restitution" << "0.75";
    QTest::addRow("restitution exact") << "exact" << "restitutionEdit" << "0" << "restitution" << "0";
    QTest::addRow("gravity x") << "book" << "gravityXEdit" << "-0.25" << "gravity" << "-0.25,0";
    QTest::addRow("gravity y") << "exact" << "gravityYEdit" << "0.5" << "gravity" << "0,0.5";
    QTest::addRow("substeps") << "impulse" << "substepsEdit" << "8" << "substeps" << "8";
    // A decimal comma, as half of Europe writes it, is a decimal point where the locale's is a
    // point: "0,25" is a quarter, not 25 (the comma was dropped as a group separator).
    QTest::addRow("friction comma") << "book" << "frictionEdit" << "0,25" << "friction" << "0.25";
    QTest::addRow("massScale comma") << "book" << "massScaleEdit" << "2,5" << "massScale" << "2.5";
    QTest::addRow("gravity y comma") << "exact" << "gravityYEdit" << "-0,5" << "gravity" << "0,-0.5";
    // Three digits after the comma, but a leading 0 before it: no grouping, a decimal.
    QTest::addRow("friction comma 0,125") << "book" << "frictionEdit" << "0,125" << "friction" << "0.125";
    QTest::addRow("pushScale comma 12,5") << "book" << "pushScaleEdit" << "12,5" << "pushScale" << "12.5";
}

void TestParametersDock::typingEmitsEdit()
{
    QFETCH(QString, model);
    QFETCH(QString, field);
    QFETCH(QString, typed);
    QFETCH(QString, key);
    QFETCH(QString, value);

    ParametersDock dock;
    QVERIFY(showWithModel(dock, model));
    auto *spin = dock.findChild<QAbstractSpinBox *>(field);
    QVERIFY(spin);
    QVERIFY(spin->isEnabled());

    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    typeInto(spin, typed);
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.at(0).at(0).toString(), key);
    QCOMPARE(spy.at(0).at(1).toString(), value);
    // What the dock emits, the core accepts.
    QCOMPARE(coreVerdict(paramsWithModel(model), key, value), std::string());

    // Enter again without a change is not a second edit (no empty undo command).
    QTest::keyClick(spin, Qt::Key_Return);
    QCOMPARE(spy.count(), 1);
}

void TestParametersDock::modelBoxEmitsEdit()
{
    ParametersDock dock;
    dock.setParams(Params{});
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    auto *box = dock.findChild<QComboBox *>(QStringLiteral("modelEdit"));
    QVERIFY(box);

    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Down);
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.at(0).at(0).toString(), QStringLiteral("model"));
    QCOMPARE(spy.at(0).at(1).toString(), QStringLiteral("impulse"));
    QTest::keyClick(box, Qt::Key_Down);
    QCOMPARE(spy.count(), 2);
    QCOMPARE(spy.at(1).at(1).toString(), QStringLiteral("exact"));
    QCOMPARE(dock.shownParams().model, ModelKind::Exact);
    QTest::keyClick(box, Qt::Key_Home);
    QCOMPARE(spy.count(), 3);
    QCOMPARE(spy.at(2).at(1).toString(), QStringLiteral("book"));
}

void TestParametersDock::shortCircuitEmitsEdit()
{
    ParametersDock dock;
    dock.setParams(Params{});
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    auto *box = dock.findChild<QCheckBox *>(QStringLiteral("shortCircuitEdit"));
    QVERIFY(box);

    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    QTest::mouseClick(box, Qt::LeftButton, {}, QPoint(box->height() / 2, box->height() / 2));
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.at(0).at(0).toString(), QStringLiteral("shortCircuit"));
    QCOMPARE(spy.at(0).at(1).toString(), QStringLiteral("true"));
    QTest::mouseClick(box, Qt::LeftButton, {}, QPoint(box->height() / 2, box->height() / 2));
    QCOMPARE(spy.count(), 2);
    QCOMPARE(spy.at(1).at(1).toString(), QStringLiteral("false"));
}

void TestParametersDock::setParamsEmitsNothing()
{
    ParametersDock dock;
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);

    Params p;
    p.model = ModelKind::Impulse;
    p.massScale = 2.0;
    p.friction = 0.3;
    p.zeroThreshold = 0.0005;
    p.pushScale = 25.0;
    p.frameMs = 16.5;
    p.restitution = 0.8;
    p.gravity = {0.125, -0.5};
    p.substeps = 12;
    p.shortCircuit = true;
    dock.setParams(p);

    Params book;
    book.friction = 2.75; // a book friction above 1 shown as is, then a model change
    dock.setParams(book);
    dock.setParams(p);
    QCOMPARE(spy.count(), 0);

    const Params shown = dock.shownParams();
    constexpr double tol = 1e-12;
    QCOMPARE(shown.model, p.model);
    QCOMPARE_LE(std::abs(shown.massScale - p.massScale), tol);
    QCOMPARE_LE(std::abs(shown.friction - p.friction), tol);
    QCOMPARE_LE(std::abs(shown.zeroThreshold - p.zeroThreshold), tol);
    QCOMPARE_LE(std::abs(shown.pushScale - p.pushScale), tol);
    QCOMPARE_LE(std::abs(shown.frameMs - p.frameMs), tol);
    QCOMPARE_LE(std::abs(shown.restitution - p.restitution), tol);
    QCOMPARE_LE(std::abs(shown.gravity.x - p.gravity.x), tol);
    QCOMPARE_LE(std::abs(shown.gravity.y - p.gravity.y), tol);
    QCOMPARE(shown.substeps, p.substeps);
    QCOMPARE(shown.shortCircuit, p.shortCircuit);
}

void TestParametersDock::decimalsShown_data()
{
    QTest::addColumn<QString>("field");
    QTest::addColumn<double>("value");
    QTest::addColumn<QString>("text");

    QTest::addRow("threshold default") << "zeroThresholdEdit" << 0.01 << "0.01 px/frame";
    QTest::addRow("threshold tiny") << "zeroThresholdEdit" << 0.0001 << "0.0001 px/frame";
    QTest::addRow("threshold zero") << "zeroThresholdEdit" << 0.0 << "0 px/frame";
    QTest::addRow("friction") << "frictionEdit" << 0.125 << "0.125";
    QTest::addRow("frameMs whole") << "frameMsEdit" << 20.0 << "20 ms";
    QTest::addRow("massScale") << "massScaleEdit" << 1.25 << "1.25 per px";
    QTest::addRow("pushScale large") << "pushScaleEdit" << 25000.0 << "25000";
}

void TestParametersDock::decimalsShown()
{
    QFETCH(QString, field);
    QFETCH(double, value);
    QFETCH(QString, text);

    ParametersDock dock;
    auto *spin = dock.findChild<QDoubleSpinBox *>(field);
    QVERIFY(spin);
    spin->setValue(value);
    QCOMPARE(spin->text(), text);
}

void TestParametersDock::sceneValuesBelowTheFieldsAreShown()
{
    // A helper's finding: a scene file's frame interval of 0.05 ms (valid: the rule is > 0) read
    // "0.1 ms", the field's lowest, while the plot and the status bar ran at 0.05, so every figure
    // per second was twice what the field said, and 0.1 typed changed nothing. The lowest a field
    // takes widens to a scene's value where the rule allows it; the rule's own stays.
    ParametersDock dock;
    Params p;
    p.frameMs = 0.05;
    dock.setParams(p);
    QCOMPARE_LE(std::abs(dock.shownParams().frameMs - 0.05), 1e-12);
    auto *frameMs = dock.findChild<QDoubleSpinBox *>(QStringLiteral("frameMsEdit"));
    QVERIFY(frameMs);
    QCOMPARE(frameMs->text(), QStringLiteral("0.05 ms"));
}

void TestParametersDock::invalidValuesRefused_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<QString>("field");
    QTest::addColumn<QString>("typed");

    QTest::addRow("massScale zero") << "book" << "massScaleEdit" << "0";
    QTest::addRow("massScale negative") << "book" << "massScaleEdit" << "-1";
    QTest::addRow("friction negative") << "book" << "frictionEdit" << "-0.5";
    QTest::addRow("friction book huge") << "book" << "frictionEdit" << "50";
    QTest::addRow("friction exact 1") << "exact" << "frictionEdit" << "1";
    QTest::addRow("friction exact 1.5") << "exact" << "frictionEdit" << "1.5";
    QTest::addRow("friction impulse 2") << "impulse" << "frictionEdit" << "2";
    QTest::addRow("zeroThreshold negative") << "book" << "zeroThresholdEdit" << "-0.01";
    QTest::addRow("frameMs zero") << "book" << "frameMsEdit" << "0";
    QTest::addRow("frameMs negative") << "book" << "frameMsEdit" << "-20";
    QTest::addRow("restitution above 1") << "exact" << "restitutionEdit" << "1.5";
    QTest::addRow("restitution negative") << "impulse" << "restitutionEdit" << "-0.2";
    QTest::addRow("substeps zero") << "impulse" << "substepsEdit" << "0";
    QTest::addRow("substeps negative") << "impulse" << "substepsEdit" << "-3";
    QTest::addRow("letters") << "book" << "frictionEdit" << "abc";
    // Beyond the doubles: refused as typed (its last keystroke was dropped, "1e40" refused).
    QTest::addRow("massScale 1e400") << "book" << "massScaleEdit" << "1e400";
    QTest::addRow("friction -1e400") << "book" << "frictionEdit" << "-1e400";
}

void TestParametersDock::invalidValuesRefused()
{
    QFETCH(QString, model);
    QFETCH(QString, field);
    QFETCH(QString, typed);

    ParametersDock dock;
    const Params before = paramsWithModel(model);
    QVERIFY(showWithModel(dock, model));
    auto *spin = dock.findChild<QAbstractSpinBox *>(field);
    QVERIFY(spin);

    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    typeInto(spin, typed);
    // Whatever the keystrokes did, nothing the core would refuse came out, and the field
    // still shows a valid value.
    for (const QList<QVariant> &edit : spy) {
        const std::string verdict = coreVerdict(before, edit.at(0).toString(), edit.at(1).toString());
        QVERIFY2(verdict.empty(), verdict.c_str());
    }
    // A number out of range is refused whole: the field keeps its value (no other number made
    // of the keystrokes it could take, such as 0.5 from "1.5" or 1 from "-1"), and the line under
    // it says what was typed and why it was not taken.
    double fieldValue = 0.0;
    double valueBefore = 0.0;
    if (auto *d = qobject_cast<QDoubleSpinBox *>(spin)) {
        fieldValue = d->value();
        valueBefore = field == QLatin1String("frictionEdit") ? before.friction
            : field == QLatin1String("massScaleEdit")        ? before.massScale
            : field == QLatin1String("zeroThresholdEdit")    ? before.zeroThreshold
            : field == QLatin1String("frameMsEdit")          ? before.frameMs
                                                              : before.restitution;
    } else if (auto *i = qobject_cast<QSpinBox *>(spin)) {
        fieldValue = i->value();
        valueBefore = before.substeps;
    } else {
        QFAIL("not a spin box");
    }
    bool isNumber = false;
    const double typedValue = typed.toDouble(&isNumber);
    if (isNumber || std::isinf(typedValue)) {
        QCOMPARE(spy.count(), 0);
        QCOMPARE(fieldValue, valueBefore);
        const QString help = dock.findChild<QLabel *>(field + QStringLiteral("Help"))->text();
        QVERIFY2(help.contains(typed) && help.contains(QStringLiteral("it stays")), qPrintable(help));
        if (field == QLatin1String("frictionEdit") && model != QLatin1String("book"))
            QVERIFY2(help.contains(QStringLiteral("need friction below 1")), qPrintable(help));
    }
    const Params after = dock.shownParams();
    World world;
    world.params = after;
    QCOMPARE(validateParams(world.params), std::string());
}

void TestParametersDock::focusedFieldIsScrolledIntoSight()
{
    // On a projector's small dock the last fields are below the fold: a field given the focus
    // (Alt and its letter does so without Tab) is scrolled into sight, and the scroll area is no
    // Tab stop of its own.
    ParametersDock dock;
    dock.resize(360, 160);
    dock.show();
    dock.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&dock));
    auto *scroll = qobject_cast<QScrollArea *>(dock.widget());
    QVERIFY(scroll);
    QCOMPARE(scroll->focusPolicy(), Qt::NoFocus);
    auto *model = dock.findChild<QComboBox *>(QStringLiteral("modelEdit"));
    QVERIFY(model);
    auto inSight = [&] {
        const QRect at(model->mapTo(scroll->viewport(), QPoint(0, 0)), model->size());
        return scroll->viewport()->rect().contains(at);
    };
    QVERIFY(!inSight()); // the test needs it below the fold
    model->setFocus(Qt::ShortcutFocusReason);
    QTRY_VERIFY(inSight());
}

void TestParametersDock::gravityTakesItsAltKey()
{
    // Alt+G (the Gravity label's letter) goes to the x field: the label's buddy was the row of
    // both fields, which takes no focus, so Alt+G did nothing.
    ParametersDock dock;
    QLabel *gravity = nullptr;
    for (QLabel *label : dock.findChildren<QLabel *>()) {
        if (label->text() == QStringLiteral("&Gravity"))
            gravity = label;
    }
    QVERIFY(gravity);
    QCOMPARE(gravity->buddy(), dock.findChild<QDoubleSpinBox *>(QStringLiteral("gravityXEdit")));
}

void TestParametersDock::wheelChangesOnlyTheFieldBeingEdited()
{
    // A helper's finding: the wheel over a field not clicked into changed it (push scale 10 to
    // 9, and in the Inspector a marble at rest got a velocity), as the dock scrolled under the
    // pointer. It goes to the dock; a field being edited still takes it.
    ParametersDock dock;
    QVERIFY(showWithModel(dock, QStringLiteral("book")));
    auto *push = dock.findChild<QDoubleSpinBox *>(QStringLiteral("pushScaleEdit"));
    auto *friction = dock.findChild<QDoubleSpinBox *>(QStringLiteral("frictionEdit"));
    QVERIFY(push && friction);
    friction->setFocus();
    QTRY_VERIFY(friction->hasFocus());
    QCOMPARE(push->focusPolicy(), Qt::StrongFocus); // the wheel gives it no focus
    const double before = push->value();
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    const auto wheel = [](QWidget *target) {
        const QPointF at(target->width() / 2.0, target->height() / 2.0);
        QWheelEvent event(at, target->mapToGlobal(at), QPoint(), QPoint(0, -120), Qt::NoButton, Qt::NoModifier,
                          Qt::NoScrollPhase, false);
        QCoreApplication::sendEvent(target, &event);
    };
    wheel(push);
    QCOMPARE(push->value(), before);
    QCOMPARE(spy.count(), 0);
    push->setFocus();
    QTRY_VERIFY(push->hasFocus());
    wheel(push);
    QCOMPARE_LT(push->value(), before);
    QCOMPARE(spy.count(), 1);
    // And the Model box (the book model became the impulse one as the dock scrolled; a helper's
    // re-test).
    auto *model = dock.findChild<QComboBox *>(QStringLiteral("modelEdit"));
    QVERIFY(model);
    const int chosen = model->currentIndex();
    wheel(model);
    QCOMPARE(model->currentIndex(), chosen);
    QCOMPARE(spy.count(), 1);
}

void TestParametersDock::refusalIsExplainedUntilTheNextEdit()
{
    // A teacher on the exact model types 1.5 for the friction: the field stays 0.1 and says why;
    // typing 0.3 then takes it, and the line under the field explains the field again.
    ParametersDock dock;
    QVERIFY(showWithModel(dock, QStringLiteral("exact")));
    auto *friction = dock.findChild<QDoubleSpinBox *>(QStringLiteral("frictionEdit"));
    auto *help = dock.findChild<QLabel *>(QStringLiteral("frictionEditHelp"));
    QVERIFY(friction && help);
    const QString explanation = help->text();
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);

    typeInto(friction, QStringLiteral("1.5"));
    QCOMPARE(spy.count(), 0);
    QCOMPARE(friction->text(), QStringLiteral("0.1"));
    QCOMPARE(help->text(), QStringLiteral("Exact and impulse need friction below 1: 1.5 was refused, it stays 0.1 (book: up to 3)."));

    // Leaving the field leaves the explanation up; a value taken replaces it.
    dock.findChild<QDoubleSpinBox *>(QStringLiteral("zeroThresholdEdit"))->setFocus();
    QVERIFY(help->text().contains(QStringLiteral("1.5 was refused")));
    typeInto(friction, QStringLiteral("0.3"));
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.last().at(0).toString(), QStringLiteral("friction"));
    QCOMPARE(spy.last().at(1).toString(), QStringLiteral("0.3"));
    QCOMPARE(help->text(), explanation);

    // A refusal shown when the scene's values come in (an undo, another scene) gives way to them.
    typeInto(friction, QStringLiteral("2"));
    QVERIFY(help->text().contains(QStringLiteral("2 was refused")));
    dock.setParams(paramsWithModel(QStringLiteral("exact")));
    QCOMPARE(help->text(), explanation);

    // The mass scale's upper end: 5000 is not cut to 500.
    auto *massScale = dock.findChild<QDoubleSpinBox *>(QStringLiteral("massScaleEdit"));
    typeInto(massScale, QStringLiteral("5000"));
    QCOMPARE(spy.count(), 1);
    QCOMPARE(dock.findChild<QLabel *>(QStringLiteral("massScaleEditHelp"))->text(),
             QStringLiteral("5000 is above this field's maximum (1000 per px): it stays 1.25 per px."));

    // One refusal at a time, the latest: the mass scale's gives way to the zero threshold's
    // (three refused fields in a row showed three red lines).
    auto *threshold = dock.findChild<QDoubleSpinBox *>(QStringLiteral("zeroThresholdEdit"));
    auto *thresholdHelp = dock.findChild<QLabel *>(QStringLiteral("zeroThresholdEditHelp"));
    const QString thresholdExplanation = thresholdHelp->text();
    typeInto(threshold, QStringLiteral("-1"));
    QVERIFY2(thresholdHelp->text().contains(QStringLiteral("it stays")), qPrintable(thresholdHelp->text()));
    QCOMPARE(dock.findChild<QLabel *>(QStringLiteral("massScaleEditHelp"))->property("explanation").toString(),
             dock.findChild<QLabel *>(QStringLiteral("massScaleEditHelp"))->text());
    // A value taken elsewhere clears it too.
    typeInto(friction, QStringLiteral("0.2"));
    QCOMPARE(thresholdHelp->text(), thresholdExplanation);
}

void TestParametersDock::frictionWarning_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<double>("friction");
    QTest::addColumn<QString>("warning"); // "" none, else a phrase the warning contains

    QTest::addRow("book 0.1") << "book" << 0.1 << "";
    QTest::addRow("book 1") << "book" << 1.0 << "";
    QTest::addRow("book 1.0001") << "book" << 1.0001 << "flips sign every frame";
    QTest::addRow("book 1.5") << "book" << 1.5 << "flips sign every frame";
    QTest::addRow("book 2") << "book" << 2.0 << "flips sign every frame";
    QTest::addRow("book 2.0001") << "book" << 2.0001 << "grow without bound";
    QTest::addRow("book 3") << "book" << 3.0 << "grow without bound";
    QTest::addRow("exact 0.9") << "exact" << 0.9 << "";
    QTest::addRow("impulse 0.5") << "impulse" << 0.5 << "";
}

void TestParametersDock::frictionWarning()
{
    QFETCH(QString, model);
    QFETCH(double, friction);
    QFETCH(QString, warning);

    ParametersDock dock;
    Params p = paramsWithModel(model);
    p.friction = friction;
    dock.setParams(p);
    auto *label = dock.findChild<QLabel *>(QStringLiteral("frictionWarning"));
    QVERIFY(label);
    if (warning.isEmpty()) {
        QVERIFY(label->isHidden());
    } else {
        QVERIFY(!label->isHidden());
        QVERIFY2(label->text().contains(warning), qPrintable(label->text()));
        QVERIFY(!label->styleSheet().isEmpty()); // coloured
    }
}

void TestParametersDock::thresholdAboveGravityWarns()
{
    // Gravity no larger than the zero threshold never sets a marble at rest moving: it hung in
    // mid-air with no word why (a teacher's finding). Said under the threshold, as it is typed.
    ParametersDock dock;
    Params p = paramsWithModel(QStringLiteral("exact"));
    p.gravity = {0.0, 0.15};
    p.zeroThreshold = 0.01;
    dock.setParams(p);
    dock.resize(360, 500);
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    auto *label = dock.findChild<QLabel *>(QStringLiteral("thresholdWarning"));
    QVERIFY(label);
    QVERIFY(!label->isVisible());
    auto *threshold = dock.findChild<QDoubleSpinBox *>(QStringLiteral("zeroThresholdEdit"));
    QVERIFY(threshold);
    typeInto(threshold, QStringLiteral("2"));
    QVERIFY(label->isVisible());
    // The exact model moves it within the frame, then its speed snaps to 0 (0.15 x 0.1 / -ln 0.9
    // a frame's end, with the default friction): it creeps on, never faster.
    QVERIFY2(label->text().contains(QStringLiteral("never gathers speed, it creeps 0.07")), qPrintable(label->text()));
    QVERIFY(!label->styleSheet().isEmpty());
    // In the book model the position moves by the snapped speed: it stays put.
    p.zeroThreshold = 2.0;
    p.model = ModelKind::Book;
    dock.setParams(p);
    QVERIFY2(label->text().contains(QStringLiteral("stays where it is, even in mid-air")), qPrintable(label->text()));
    p.model = ModelKind::Exact;
    dock.setParams(p);
    typeInto(threshold, QStringLiteral("0.1499")); // below |g|, above the 0.142 a frame gives with drag: held
    QVERIFY(label->isVisible());
    typeInto(threshold, QStringLiteral("0.1"));
    QVERIFY(!label->isVisible());
    // Without gravity nothing is held up: no warning, below what a click gives.
    p.gravity = {0.0, 0.0};
    p.zeroThreshold = 5.0;
    dock.setParams(p);
    QVERIFY(!label->isVisible());
    // A threshold at least what a click gives (push scale 10 / mass scale 1.25 = 8 px/frame at a
    // marble's rim) zeroes every click: said (at 100 a clicked marble never moved, without a word).
    for (const double z : {8.0, 100.0}) {
        p.zeroThreshold = z;
        dock.setParams(p);
        QVERIFY(label->isVisible());
        QVERIFY2(label->text().contains(QStringLiteral("A click gives a marble at most 8 px/frame")), qPrintable(label->text()));
    }
    p.pushScale = 200.0; // 160 px/frame at the rim
    dock.setParams(p);
    QVERIFY(!label->isVisible());
    p.pushScale = 10.0;
    p.zeroThreshold = 5.0;
    p.gravity = {-3.0, 0.0}; // sideways too
    dock.setParams(p);
    QVERIFY(label->isVisible());
}

void TestParametersDock::typedFrictionWarns()
{
    ParametersDock dock;
    dock.setParams(Params{});
    dock.resize(360, 500); // shorter than its fields: the page scrolls
    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    auto *spin = dock.findChild<QDoubleSpinBox *>(QStringLiteral("frictionEdit"));
    auto *label = dock.findChild<QLabel *>(QStringLiteral("frictionWarning"));
    QVERIFY(spin && label);
    QVERIFY(!label->isVisible());
    // Every help text keeps the height its wrapped lines need (the warning's coming and going
    // squeezed them: first and last lines cut off).
    const auto helpTextsWhole = [&] {
        QCoreApplication::processEvents();
        for (const QLabel *help : dock.findChildren<QLabel *>()) {
            if (help->isVisible() && help->wordWrap() && help->height() < help->heightForWidth(help->width()))
                return false;
        }
        return true;
    };
    QVERIFY(helpTextsWhole());

    typeInto(spin, QStringLiteral("1.5"));
    QVERIFY(label->isVisible());
    QVERIFY(label->text().contains(QStringLiteral("flips sign every frame")));
    typeInto(spin, QStringLiteral("2.5"));
    QVERIFY(label->isVisible());
    QVERIFY(label->text().contains(QStringLiteral("grow without bound")));
    QVERIFY(helpTextsWhole());
    typeInto(spin, QStringLiteral("0.2"));
    QVERIFY(!label->isVisible());
    QVERIFY(helpTextsWhole());
}

void TestParametersDock::otherLocalesDecimalPoint()
{
    // Where the locale writes a decimal comma, a point typed is the decimal mark (it was a group
    // separator there: "0.25" read as 25).
    ParametersDock dock;
    dock.setLocale(QLocale(QLocale::German, QLocale::Germany));
    QVERIFY(showWithModel(dock, QStringLiteral("book")));
    auto *friction = dock.findChild<QAbstractSpinBox *>(QStringLiteral("frictionEdit"));
    QVERIFY(friction);
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    typeInto(friction, QStringLiteral("0.25"));
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.at(0).at(1).toString(), QStringLiteral("0.25"));
    QCOMPARE(friction->text(), QStringLiteral("0,25"));
    typeInto(friction, QStringLiteral("0,5"));
    QCOMPARE(spy.count(), 2);
    QCOMPARE(spy.at(1).at(1).toString(), QStringLiteral("0.5"));
}

void TestParametersDock::unreadableTextIsRefused_data()
{
    QTest::addColumn<bool>("german");
    QTest::addColumn<QString>("model");
    QTest::addColumn<QString>("field");
    QTest::addColumn<QString>("typed");
    QTest::addColumn<QString>("why");

    // Typed key by key, the first comma became a point and the rest was dropped or appended:
    // "1,000" frame interval was 1 ms, "1,000,000" push scale 1, "1,000.5" friction 1.0005.
    const QString twoWays = QStringLiteral("can be read two ways");
    QTest::addRow("frameMs 1,000") << false << "book" << "frameMsEdit" << "1,000" << twoWays;
    QTest::addRow("pushScale 1,000,000") << false << "book" << "pushScaleEdit" << "1,000,000" << twoWays;
    QTest::addRow("pushScale 1,000.5") << false << "book" << "pushScaleEdit" << "1,000.5" << twoWays;
    QTest::addRow("friction 1,000.5") << false << "book" << "frictionEdit" << "1,000.5" << twoWays;
    QTest::addRow("German massScale 1.000") << true << "book" << "massScaleEdit" << "1.000" << twoWays;
    // A whole-number field takes digits only ("2,5" substeps was 25).
    const QString whole = QStringLiteral("takes whole numbers");
    QTest::addRow("substeps 2,5") << false << "impulse" << "substepsEdit" << "2,5" << whole;
    QTest::addRow("substeps 2.5") << false << "impulse" << "substepsEdit" << "2.5" << whole;
    QTest::addRow("substeps 1,000") << false << "impulse" << "substepsEdit" << "1,000" << whole;
    QTest::addRow("substeps 1e3") << false << "impulse" << "substepsEdit" << "1e3" << whole; // was 13
    // Letters stay as typed and are refused: a dropped keystroke made "2x5" 25 and "e5" 5.
    const QString noNumber = QStringLiteral("is not a number");
    QTest::addRow("massScale 2x5") << false << "book" << "massScaleEdit" << "2x5" << noNumber;
    QTest::addRow("massScale e5") << false << "book" << "massScaleEdit" << "e5" << noNumber;
    QTest::addRow("friction abc") << false << "book" << "frictionEdit" << "abc" << noNumber;
    // Read by QLocale as a number, and put back without a word.
    QTest::addRow("friction nan") << false << "book" << "frictionEdit" << "nan" << noNumber;
    QTest::addRow("massScale NaN") << false << "book" << "massScaleEdit" << "NaN" << noNumber;
    // Emptied: the number comes back, and the line says why.
    QTest::addRow("pushScale empty") << false << "book" << "pushScaleEdit" << "" << "was left empty";
    QTest::addRow("substeps empty") << false << "impulse" << "substepsEdit" << "" << "was left empty";
    // Too small for a double: named as typed (it was cut to "1e-40" while typing).
    QTest::addRow("zeroThreshold 1e-400") << false << "book" << "zeroThresholdEdit" << "1e-400"
                                          << "closer to 0 than a number can be";
}

void TestParametersDock::unreadableTextIsRefused()
{
    QFETCH(bool, german);
    QFETCH(QString, model);
    QFETCH(QString, field);
    QFETCH(QString, typed);
    QFETCH(QString, why);

    ParametersDock dock;
    if (german)
        dock.setLocale(QLocale(QLocale::German, QLocale::Germany));
    QVERIFY(showWithModel(dock, model));
    auto *spin = dock.findChild<QAbstractSpinBox *>(field);
    QVERIFY(spin);
    const QString shownBefore = spin->text();
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    typeInto(spin, typed);
    QCOMPARE(spy.count(), 0);
    QCOMPARE(spin->text(), shownBefore);
    QLabel *line = dock.findChild<QLabel *>(field + QStringLiteral("Help"));
    const QString help = line->text();
    QVERIFY2(help.contains(typed) && help.contains(why) && help.contains(QStringLiteral("stays")), qPrintable(help));
    // In solid red ink (drawn in the explanation's half-transparent role it was about 2:1 against
    // the dock, hard to read on a projector).
    const QImage drawn = line->grab().toImage();
    int darkest = 255;
    for (int y = 0; y < drawn.height(); ++y) {
        for (int x = 0; x < drawn.width(); ++x)
            darkest = std::min(darkest, drawn.pixelColor(x, y).lightness());
    }
    QCOMPARE_LE(darkest, 110);
    // The value the field kept, typed and taken, ends the refusal (it stayed up, the value
    // being unchanged); leaving the field without typing does not.
    typeInto(spin, typed);
    QVERIFY(line->text().contains(why));
    spin->clearFocus();
    QVERIFY(line->text().contains(why));
    typeInto(spin, shownBefore.section(QLatin1Char(' '), 0, 0));
    QCOMPARE(line->text(), line->property("explanation").toString());
}

void TestParametersDock::suffixStaysWhole()
{
    // A keystroke into the unit or after it is dropped, as a spin box does (the cursor lands there
    // when the field is refreshed under it during a run): kept, it broke the unit and the number
    // ran into it ("0.08045rame px/frame", a tester typing into vx while the run played). Inside
    // the number, what is typed stays, to be refused with why.
    ParametersDock dock;
    QVERIFY(showWithModel(dock, QStringLiteral("book")));
    auto *spin = dock.findChild<QDoubleSpinBox *>(QStringLiteral("zeroThresholdEdit"));
    QVERIFY(spin);
    for (const QString &broken : {QStringLiteral("0.01 px/f4rame"), QStringLiteral("0.01 px/frame4"), QStringLiteral("0.01 p,x/frame"),
                                  QStringLiteral("0.01 px/framez"), QStringLiteral("0.01 px/fame"),
                                  QStringLiteral("0.01 px/framez px/frame")}) {
        QString text = broken;
        int pos = 10;
        QVERIFY2(spin->validate(text, pos) == QValidator::Invalid, qPrintable(broken));
    }
    QString inside = QStringLiteral("0.0x1 px/frame");
    int pos = 4;
    QCOMPARE(spin->validate(inside, pos), QValidator::Intermediate);
    // Cut from the end, the unit stays refused.
    QString cut = QStringLiteral("0.01 px/fram");
    pos = 12;
    QCOMPARE(spin->validate(cut, pos), QValidator::Invalid);

    // The unit typed after a number typed over the field is the field's own: "25px" was refused
    // as no number in a field that showed "px" (a teacher tester's finding).
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    typeInto(spin, QStringLiteral("0.25px/frame"));
    QCOMPARE(spin->text(), QStringLiteral("0.25 px/frame"));
    QCOMPARE(spy.count(), 1);
    QCOMPARE(spy.last().at(1).toString(), QStringLiteral("0.25"));
    auto *frameMs = dock.findChild<QDoubleSpinBox *>(QStringLiteral("frameMsEdit"));
    typeInto(frameMs, QStringLiteral("40MS")); // (Space, in the window, plays)
    QCOMPARE(spy.count(), 2);
    QCOMPARE(spy.last().at(1).toString(), QStringLiteral("40"));
    QCOMPARE(dock.findChild<QLabel *>(QStringLiteral("frameMsEditHelp"))->property("explanation").toString(),
             dock.findChild<QLabel *>(QStringLiteral("frameMsEditHelp"))->text());
}

void TestParametersDock::stepsLandOnShownValues()
{
    // Restitution 1, Down twice (steps of 0.05): 0.9, not 0.8999999999999999.
    ParametersDock dock;
    QVERIFY(showWithModel(dock, QStringLiteral("exact")));
    auto *spin = dock.findChild<QDoubleSpinBox *>(QStringLiteral("restitutionEdit"));
    QVERIFY(spin);
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    spin->setFocus();
    QTest::keyClick(spin, Qt::Key_Down);
    QTest::keyClick(spin, Qt::Key_Down);
    QCOMPARE(spy.count(), 2);
    QCOMPARE(spy.at(0).at(1).toString(), QStringLiteral("0.95"));
    QCOMPARE(spy.at(1).at(1).toString(), QStringLiteral("0.9"));
    for (int k = 0; k < 4; ++k)
        QTest::keyClick(spin, Qt::Key_Down);
    QCOMPARE(spy.last().at(1).toString(), QStringLiteral("0.7"));
    for (int k = 0; k < 10; ++k)
        QTest::keyClick(spin, Qt::Key_Up); // stops at the maximum
    QCOMPARE(spin->value(), 1.0);
}

void TestParametersDock::fieldsFollowModel_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<bool>("restitution");
    QTest::addColumn<bool>("substeps");
    QTest::addColumn<bool>("shortCircuit");

    QTest::addRow("book") << "book" << false << false << true;
    QTest::addRow("impulse") << "impulse" << true << true << false;
    QTest::addRow("exact") << "exact" << true << false << false;
}

void TestParametersDock::fieldsFollowModel()
{
    QFETCH(QString, model);
    QFETCH(bool, restitution);
    QFETCH(bool, substeps);
    QFETCH(bool, shortCircuit);

    auto check = [&](ParametersDock &dock) {
        const std::pair<const char *, bool> fields[] = {
            {"restitutionEdit", restitution}, {"substepsEdit", substeps}, {"shortCircuitEdit", shortCircuit}};
        for (const auto &[name, enabled] : fields) {
            auto *w = dock.findChild<QWidget *>(QString::fromLatin1(name));
            QVERIFY(w);
            QCOMPARE(w->isEnabled(), enabled);
            // A disabled field says why; an enabled one shows its formula.
            QVERIFY(!w->toolTip().isEmpty());
            QCOMPARE(w->toolTip().contains(QStringLiteral("Only the")) || w->toolTip().contains(QStringLiteral("Not used")),
                     !enabled);
            // And the line under it, where it is seen without a pointer resting on the field
            // (greyed out, Pachinko's restitution did not say why); its explanation stays after it.
            auto *help = dock.findChild<QLabel *>(QString::fromLatin1(name) + QStringLiteral("Help"));
            QVERIFY(help);
            QCOMPARE(help->text().startsWith(QStringLiteral("Not used by the ")) || help->text().startsWith(QStringLiteral("Used by the ")),
                     !enabled);
            QVERIFY(help->text().endsWith(help->property("usedExplanation").toString()));
        }
        // The fields every model uses stay enabled.
        for (const char *name : {"massScaleEdit", "frictionEdit", "zeroThresholdEdit", "pushScaleEdit", "frameMsEdit",
                                 "modelEdit", "gravityXEdit", "gravityYEdit"})
            QVERIFY(dock.findChild<QWidget *>(QString::fromLatin1(name))->isEnabled());
    };

    // Shown by setParams...
    ParametersDock shown;
    shown.setParams(paramsWithModel(model));
    check(shown);
    if (QTest::currentTestFailed())
        return;

    // ...and chosen by the user in the model box, starting from another model.
    ParametersDock chosen;
    chosen.setParams(paramsWithModel(model == QLatin1String("book") ? QStringLiteral("exact") : QStringLiteral("book")));
    chosen.show();
    QVERIFY(QTest::qWaitForWindowExposed(&chosen));
    auto *box = chosen.findChild<QComboBox *>(QStringLiteral("modelEdit"));
    QSignalSpy spy(&chosen, &ParametersDock::paramEdited);
    box->setFocus();
    const int target = box->findData(model);
    QVERIFY(target >= 0);
    while (box->currentIndex() != target)
        QTest::keyClick(box, box->currentIndex() < target ? Qt::Key_Down : Qt::Key_Up);
    QVERIFY(spy.count() >= 1);
    QCOMPARE(spy.last().at(1).toString(), model);
    check(chosen);
}

void TestParametersDock::dampedModelsNeedFrictionBelowOne()
{
    // With book friction 1.5, exact and impulse cannot be chosen (they need k < 1).
    ParametersDock dock;
    Params p;
    p.friction = 1.5;
    dock.setParams(p);
    auto *box = dock.findChild<QComboBox *>(QStringLiteral("modelEdit"));
    auto *items = qobject_cast<QStandardItemModel *>(box->model());
    QVERIFY(items);
    QVERIFY(items->item(box->findData(QStringLiteral("book")))->isEnabled());
    QVERIFY(!items->item(box->findData(QStringLiteral("exact")))->isEnabled());
    QVERIFY(!items->item(box->findData(QStringLiteral("impulse")))->isEnabled());

    dock.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dock));
    QSignalSpy spy(&dock, &ParametersDock::paramEdited);
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Down);
    QCOMPARE(spy.count(), 0);
    QCOMPARE(dock.shownParams().model, ModelKind::Book);

    // Lower the friction and they come back.
    typeInto(dock.findChild<QDoubleSpinBox *>(QStringLiteral("frictionEdit")), QStringLiteral("0.5"));
    QVERIFY(items->item(box->findData(QStringLiteral("exact")))->isEnabled());
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Down);
    QCOMPARE(spy.last().at(0).toString(), QStringLiteral("model"));
    QCOMPARE(spy.last().at(1).toString(), QStringLiteral("impulse"));
}

void TestParametersDock::everyFieldExplained_data()
{
    QTest::addColumn<QString>("field");
    QTest::addColumn<QString>("formula"); // a piece of the tooltip

    QTest::addRow("massScale") << "massScaleEdit" << "mass scale \u00d7 r";
    QTest::addRow("friction") << "frictionEdit" << "a += \u2212v \u00d7 k";
    QTest::addRow("zeroThreshold") << "zeroThresholdEdit" << "v.x = 0";
    QTest::addRow("pushScale") << "pushScaleEdit" << "(centre \u2212 click) \u00d7 push scale / m";
    QTest::addRow("frameMs") << "frameMsEdit" << "at 1\u00d7 speed one frame lasts";
    QTest::addRow("model") << "modelEdit" << "exact:";
    QTest::addRow("gravity") << "gravityEdit" << "a += g";
}

void TestParametersDock::everyFieldExplained()
{
    QFETCH(QString, field);
    QFETCH(QString, formula);

    ParametersDock dock;
    dock.setParams(paramsWithModel(QStringLiteral("impulse"))); // every field enabled but short circuit
    auto *w = dock.findChild<QWidget *>(field);
    QVERIFY(w);
    QVERIFY2(w->toolTip().contains(formula), qPrintable(w->toolTip()));
    auto *help = dock.findChild<QLabel *>(field + QStringLiteral("Help"));
    QVERIFY(help);
    QVERIFY(help->text().endsWith(QLatin1Char('.')));
    QVERIFY(help->text().size() > 20);
    // Legible from the back of a classroom: at least 4.5:1 against the dock (the placeholder
    // colour it had was about 2.9:1).
    auto luminance = [](QColor c) {
        auto channel = [](double v) { return v <= 0.03928 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
        return 0.2126 * channel(c.redF()) + 0.7152 * channel(c.greenF()) + 0.0722 * channel(c.blueF());
    };
    const QColor ink = help->palette().color(help->foregroundRole());
    const QColor paper = help->palette().color(QPalette::Window);
    const double a = luminance(ink);
    const double b = luminance(paper);
    const double contrast = (std::max(a, b) + 0.05) / (std::min(a, b) + 0.05);
    QVERIFY2(contrast >= 4.5 && ink.alpha() == 255, qPrintable(QStringLiteral("%1 on %2: %3:1").arg(ink.name(), paper.name()).arg(contrast)));
}

QTEST_MAIN(TestParametersDock)
#include "tst_parametersdock.moc"
