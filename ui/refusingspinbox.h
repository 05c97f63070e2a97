#pragma once

#include "ui/focusedwheel.h"

#include <QDoubleSpinBox>
#include <QEvent>
#include <QKeyEvent>
#include <QLocale>
#include <QSpinBox>
#include <QString>
#include <QValidator>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

namespace marbles {

/// A number typed into a spin box beyond its range, refused when the edit ended.
class Refusing {
public:
    virtual ~Refusing() = default;
    /// The number last refused (the box kept its value), if any; reading it clears it. A number
    /// beyond the doubles' range ("1e400") is refused as an infinity.
    std::optional<double> takeRefused() { return std::exchange(m_refused, std::nullopt); }
    /// The last refused number as it was typed ("1e400", "1.50").
    QString refusedText() const { return m_refusedText; }
    /// Why the last number was refused.
    enum class Refusal {
        OutOfRange, ///< a number beyond the field's range ("5000", "1e400")
        Grouped,    ///< digits that may be grouped, read two ways ("1,000", "1,000.5")
        NotWhole,   ///< anything but digits in a whole-number field ("2,5", "1e3" substeps)
        NotANumber, ///< no number at all ("abc", "2x5"): kept as typed, not cut to one
        TooSmall,   ///< a number closer to 0 than a double can be ("1e-400")
        Empty,      ///< nothing typed: the field emptied and left so
    };
    Refusal refusal() const { return m_refusal; }
    /// Whether the last refusal was of a text the field cannot read as a number as written, rather
    /// than of a number beyond its range. Its number is NaN.
    bool refusedUnreadable() const { return m_refusal != Refusal::OutOfRange; }
    /// The box's range and value, and a value as the box shows it (suffix included).
    virtual double low() const = 0;
    virtual double high() const = 0;
    virtual double current() const = 0;
    virtual QString shown(double value) const = 0;
    /// Whether the field holds typing not yet taken (its text is not its value's).
    virtual bool typing() const = 0;

protected:
    mutable std::optional<double> m_refused;
    mutable QString m_refusedText;
    mutable Refusal m_refusal = Refusal::OutOfRange;
};

/// A spin box that keeps a number typed beyond its range as typed, instead of dropping the
/// keystroke that took it there (which turned "1.5" into ".5", a friction of 0.5 where friction
/// must stay below 1, and "5000" into "500"); ending the edit then refuses it, keeps the value
/// and notes the number for the dock to explain. A lone minus may start such a number.
template<typename Base>
class RefusingSpinBox : public FocusedWheel<Base>, public Refusing {
public:
    explicit RefusingSpinBox(QWidget *parent = nullptr)
        : FocusedWheel<Base>(parent)
    {
        // valueChanged only on Enter, focus loss, arrows or the wheel: typing "0.25" is one edit,
        // not three ("0", "0.2", "0.25").
        this->setKeyboardTracking(false);
        this->setAccelerated(true);
        // The wheel changes a field only once it has been clicked or tabbed into (FocusedWheel),
        // and gives it no focus.
        this->setFocusPolicy(Qt::StrongFocus);
    }

    QValidator::State validate(QString &input, int &pos) const override
    {
        // The unit typed after a number typed over the field ("25px", "0.3 px/frame"): the
        // field's own, taken ("25px" was refused as no number in a field that showed "px").
        if (const std::optional<QValidator::State> state = unitTyped(input, pos))
            return *state;
        if (breaksUnit(input))
            return QValidator::Invalid;
        // The text is left as typed; a decimal comma is read as the locale's mark.
        QString text = input;
        switch (marksIn(bareText(input))) {
        case Marks::None:
            break;
        case Marks::OtherDecimal:
            text = withLocaleMark(input);
            break;
        case Marks::Unreadable:
            // Typed on until the edit ends, and refused then with why (fixup()).
            return onlyNumberCharacters(bareText(input)) ? QValidator::Intermediate : QValidator::Invalid;
        }
        const QValidator::State state = Base::validate(text, pos);
        if (state != QValidator::Invalid)
            return state;
        const QString bare = bareText(text);
        bool number = false;
        const double value = this->locale().toDouble(bare, &number);
        if ((number && outside(value)) || beyondDoubles(number, value)
            || (bare == this->locale().negativeSign() && low() >= 0.0))
            return QValidator::Intermediate;
        if constexpr (kDecimal) {
            // A number in powers of ten ("2e1", "1.5E-3"), which QDoubleSpinBox drops the 'e' of
            // (2e1 became 21): taken when it is within the range, and while it is being typed.
            if (number && std::isfinite(value))
                return QValidator::Acceptable;
            if (isExponentStart(bare))
                return QValidator::Intermediate;
        }
        // Anything else stays as typed and is refused when the edit ends, with why: a keystroke
        // dropped here turned "1e3" substeps into 13 and "2x5" into 25, without a word. Not a
        // keystroke into the suffix or prefix, which stays dropped ("0.080 px/f4rame" became
        // "0.08045rame px/frame" once kept).
        const bool framed = input.startsWith(this->prefix()) && input.endsWith(this->suffix());
        return framed && !bareText(input).isEmpty() ? QValidator::Intermediate : state;
    }

    bool typing() const override { return this->cleanText() != this->textFromValue(this->value()); }

    void fixup(QString &input) const override
    {
        // Called when an edit ends on text that is not a value of the box. Grouped digits are
        // refused before the base class's fixup, which drops group separators ("1,000.5" became
        // 1000.5 and "1,000" 1000, guesses either way).
        const auto refuse = [this](Refusal why, double value, const QString &text) {
            m_refusal = why;
            m_refused = value;
            m_refusedText = text;
        };
        constexpr double unread = std::numeric_limits<double>::quiet_NaN();
        if (marksIn(bareText(input)) == Marks::Unreadable) {
            refuse(kDecimal ? Refusal::Grouped : Refusal::NotWhole, unread, bareText(input));
            return;
        }
        input = withLocaleMark(input); // "5,5" would lose its comma to the base class: 55
        Base::fixup(input);
        bool number = false;
        const QString bare = bareText(input);
        const double value = this->locale().toDouble(bare, &number);
        if ((number && outside(value)) || beyondDoubles(number, value))
            refuse(Refusal::OutOfRange, value, bare);
        else if (!number && kDecimal && belowDoubles(bare))
            refuse(Refusal::TooSmall, unread, bare);
        else if ((!number && !bare.isEmpty()) || (number && std::isnan(value)))
            refuse(Refusal::NotANumber, unread, bare); // "nan", which QLocale reads, went back without a word
        else if (bare.isEmpty())
            refuse(Refusal::Empty, unread, bare); // the number put back, with why
        else if (!kDecimal && number)
            refuse(Refusal::NotWhole, unread, bare); // "1e3": a number, not as digits
    }

    double low() const override { return static_cast<double>(this->minimum()); }
    double high() const override { return static_cast<double>(this->maximum()); }
    double current() const override { return static_cast<double>(this->value()); }

protected:
    // A space is never part of a number. Left to the field, Space (the window's Play / Pause,
    // pressed right after Enter while the field still has the focus) replaced the selected value
    // with a blank and the run went on; passed over, it reaches the window's shortcut.
    // Likewise Undo and Redo once the typing is taken: the field's own undo would only put back
    // text whose number the scene already has, and the teacher's "oops" after Enter is meant for
    // the scene's Undo. While typing, they undo the typing, as in any field.
    // Space after typing without Enter first takes the typing, as Enter would: the run that
    // Space starts uses the number the field shows (it ran with the old one, the new one taken
    // only when the field lost the focus).
    bool event(QEvent *event) override
    {
        if (event->type() == QEvent::ShortcutOverride) {
            const auto *key = static_cast<QKeyEvent *>(event);
            if (isPlainSpace(key) && typing()) {
                QKeyEvent enter(QEvent::KeyPress, Qt::Key_Return, Qt::NoModifier);
                Base::keyPressEvent(&enter);
            }
            if (isPlainSpace(key) || isNoNumberKey(key) || (isUndoOrRedo(key) && !typing()))
                return true; // not accepted: the shortcut may take the key
            // Shift and an arrow select text here, as in any field (the window's Shift+Up and
            // Shift+Down, which push the selected marble, took them).
            if (key->modifiers() == Qt::ShiftModifier
                && (key->key() == Qt::Key_Up || key->key() == Qt::Key_Down || key->key() == Qt::Key_Left
                    || key->key() == Qt::Key_Right)) {
                event->accept();
                return true;
            }
        }
        return Base::event(event);
    }
    void keyPressEvent(QKeyEvent *event) override
    {
        if (isPlainSpace(event) || isNoNumberKey(event)) {
            event->ignore(); // to the parent, as a key the field has no use for
            return;
        }
        Base::keyPressEvent(event);
    }

    QString bareText(const QString &text) const
    {
        QString bare = text;
        if (!this->prefix().isEmpty() && bare.startsWith(this->prefix()))
            bare.remove(0, this->prefix().size());
        if (!this->suffix().isEmpty() && bare.endsWith(this->suffix()))
            bare.chop(this->suffix().size());
        return bare.trimmed();
    }

private:
    static constexpr bool kDecimal = std::is_same_v<Base, QDoubleSpinBox>;

    // A number too large for a double: QLocale gives an infinity and says it is no number. Left
    // Invalid, its last keystroke was dropped ("1e400" stayed "1e40", refused as 1e+40).
    static bool beyondDoubles(bool number, double value) { return !number && std::isinf(value); }
    // A number too close to 0 for a double ("1e-400"), which QLocale calls no number.
    bool belowDoubles(const QString &bare) const
    {
        const QByteArray c = QString(bare).replace(this->locale().decimalPoint(), QStringLiteral(".")).toLatin1();
        char *end = nullptr;
        errno = 0;
        const double value = std::strtod(c.constData(), &end);
        return !c.isEmpty() && end == c.constData() + c.size() && errno == ERANGE && value == 0.0;
    }

    static bool isPlainSpace(const QKeyEvent *event)
    {
        return event->key() == Qt::Key_Space && (event->modifiers() & ~Qt::KeypadModifier) == Qt::NoModifier;
    }
    // < and > are in no number: the window's Run Slower / Run Faster take them from a field as
    // from the stage (they did nothing there, without a word).
    static bool isNoNumberKey(const QKeyEvent *event)
    {
        return event->key() == Qt::Key_Less || event->key() == Qt::Key_Greater;
    }
    static bool isUndoOrRedo(const QKeyEvent *event)
    {
        const QKeyCombination pressed = event->keyCombination();
        return event->matches(QKeySequence::Undo) || event->matches(QKeySequence::Redo)
            || pressed == QKeyCombination(Qt::ControlModifier | Qt::ShiftModifier, Qt::Key_Z);
    }
    // "2e", "-1.5E-": a number in powers of ten whose exponent is still to come.
    bool isExponentStart(const QString &bare) const
    {
        const qsizetype e = bare.lastIndexOf(QLatin1Char('e'), -1, Qt::CaseInsensitive);
        if (e <= 0)
            return false;
        const QString exponent = bare.mid(e + 1);
        if (!exponent.isEmpty() && exponent != this->locale().negativeSign() && exponent != this->locale().positiveSign())
            return false;
        bool number = false;
        this->locale().toDouble(bare.left(e), &number);
        return number;
    }

    bool outside(double value) const { return value < low() || value > high(); }

    // A number followed by the field's unit, or by the start of it while it is typed ("25p"),
    // before the field's own unit or in place of it (typed over the whole text): the text becomes
    // the number and the unit as the field writes them ("25 px"), validated as such; the start
    // of a unit is kept.
    std::optional<QValidator::State> unitTyped(QString &input, int &pos) const
    {
        const QString unit = this->suffix().trimmed();
        if (unit.isEmpty())
            return std::nullopt;
        const QString body = input.endsWith(this->suffix()) ? input.chopped(this->suffix().size()) : input;
        for (qsizetype n = std::min(unit.size(), body.size()); n > 0; --n) {
            const QString tail = body.right(n);
            if (!unit.startsWith(tail, Qt::CaseInsensitive))
                continue;
            const QString before = body.left(body.size() - n);
            const QString number = before.trimmed();
            if (number.isEmpty() || !number.back().isDigit())
                return std::nullopt;
            // The start of a unit right after the digits is being typed; after a space it is
            // what is left of the field's own unit, cut ("0.01 px/fram"), which stays refused.
            if (n < unit.size())
                return before.back().isDigit() ? std::optional(QValidator::Intermediate) : std::nullopt;
            input = number + this->suffix();
            pos = static_cast<int>(number.size());
            return validate(input, pos);
        }
        return std::nullopt;
    }

    // A keystroke into the unit or after it ("0.01 px/framez", "0.01 px/fame"): dropped, as a spin
    // box drops it. Qt's own check let it through, and the unit then grew on every Delete ("5.000
    // px/frame px/frame px/frame") or took the typing ("0.08045rame px/frame"). Whole, the unit
    // ends the text once; gone whole (all of the text replaced by typing) is fine; a remnant of
    // it is a unit typed into.
    bool breaksUnit(const QString &input) const
    {
        const QString unit = this->suffix();
        if (unit.isEmpty())
            return false;
        const qsizetype at = input.indexOf(unit);
        if (at >= 0)
            return at + unit.size() != input.size() || input.indexOf(unit, at + 1) >= 0;
        const QString head = unit.trimmed().left(2);
        return !head.isEmpty() && input.contains(head);
    }

protected:
    // A decimal comma typed where the locale writes a point, or a point where it writes a comma
    // (the "other" mark), is read as the locale's decimal mark: "2,5" was read as 25, the comma
    // dropped as a group separator, and a teacher who writes decimals with a comma got ten times
    // the mass scale. Digits that may be grouped ("1,000", "12,500", "1,000.5", "1,000,000") are
    // refused with why, not guessed at: 1000 to one teacher is 1.0 to another. In a whole-number
    // field any mark is refused so ("2,5" substeps became 25). The fields never show group
    // separators themselves.
    enum class Marks { None, OtherDecimal, Unreadable };
    Marks marksIn(const QString &bare) const
    {
        const QString point = this->locale().decimalPoint();
        const QChar other = point == QLatin1String(",") ? QLatin1Char('.') : QLatin1Char(',');
        const qsizetype others = bare.count(other);
        const qsizetype points = point.size() == 1 ? bare.count(point.at(0)) : 0;
        if constexpr (!kDecimal)
            return others + points == 0 ? Marks::None : Marks::Unreadable;
        if (others == 0)
            return Marks::None;
        if (others > 1 || points > 0 || point.size() != 1)
            return Marks::Unreadable;
        // One mark: grouped digits if 1 to 3 digits, not starting with 0, stand before it and
        // exactly three after it ("0,125" is a decimal; "1,000" could be either).
        const qsizetype at = bare.indexOf(other);
        const qsizetype start = bare.startsWith(this->locale().negativeSign()) || bare.startsWith(QLatin1Char('+')) ? 1 : 0;
        const QString before = bare.mid(start, at - start);
        const QString after = bare.mid(at + 1);
        const auto digits = [](const QString &s) {
            return !s.isEmpty() && std::all_of(s.begin(), s.end(), [](QChar c) { return c.isDigit(); });
        };
        const bool grouped = digits(before) && before.size() <= 3 && before.front() != QLatin1Char('0')
            && digits(after) && after.size() == 3;
        return grouped ? Marks::Unreadable : Marks::OtherDecimal;
    }
    QString withLocaleMark(const QString &text) const
    {
        if (marksIn(bareText(text)) != Marks::OtherDecimal)
            return text;
        const QString point = this->locale().decimalPoint();
        QString out = text;
        out.replace(point == QLatin1String(",") ? QLatin1Char('.') : QLatin1Char(','), point.at(0));
        return out;
    }
    // Digits, marks, signs and exponents only: text a number was meant by, refused with why.
    static bool onlyNumberCharacters(const QString &bare)
    {
        return !bare.isEmpty() && std::all_of(bare.begin(), bare.end(), [](QChar c) {
            return c.isDigit() || c == QLatin1Char('.') || c == QLatin1Char(',') || c == QLatin1Char('-')
                || c == QLatin1Char('+') || c == QLatin1Char('e') || c == QLatin1Char('E');
        });
    }
};

/// Shows `value` in `box` as setValue() does, for a value set from the scene (an undo, a file
/// opened), and selects the whole number when the box has the focus and its text changed: the
/// line edit kept the old selection's length, so an undo from "0.5" back to "0.01 px/frame"
/// selected "0.0" alone, and the 0.2 typed next was taken as 0.21.
template<typename Box, typename Value>
void showSceneValue(Box *box, Value value)
{
    const QString before = box->text();
    box->setValue(value);
    if (box->hasFocus() && box->text() != before)
        box->selectAll();
}

/// A decimal spin box with that refusal.
class RefusingDoubleSpinBox : public RefusingSpinBox<QDoubleSpinBox> {
public:
    using RefusingSpinBox<QDoubleSpinBox>::RefusingSpinBox;
    QString shown(double value) const override { return textFromValue(value) + suffix(); }

    // A step lands on the value the box shows: its own step added 0.1 to a double and kept the
    // rounding (restitution 1, Down twice: 0.8999999999999999 in the Undo History and the file),
    // where setValue() rounds to the box's decimals.
    void stepBy(int steps) override
    {
        setValue(value() + steps * singleStep());
        selectAll();
    }

protected:
    // Reads powers of ten too ("2e1" is 20), which validate() lets through.
    double valueFromText(const QString &text) const override
    {
        bool number = false;
        const double value = locale().toDouble(bareText(withLocaleMark(text)), &number);
        return number && std::isfinite(value) ? value : QDoubleSpinBox::valueFromText(text);
    }
};

/// A whole-number spin box with the same refusal of numbers beyond its range.
class CountSpinBox : public RefusingSpinBox<QSpinBox> {
public:
    using RefusingSpinBox<QSpinBox>::RefusingSpinBox;
    QString shown(double value) const override { return textFromValue(static_cast<int>(value)) + suffix(); }
};

/// The red of a refusal's message, in the Parameters dock and the Inspector alike.
inline constexpr const char *kRefusalColour = "#b00020";

/// A refused number as the messages write it: without group separators ("5000"), or as typed
/// where it is beyond the doubles ("1e400").
QString refusedNumber(const Refusing &box, double refused, const QLocale &locale);

/// Why `refused` was not taken by `box`, short enough for two lines of a dock: "5000 is above
/// this field's maximum (1000 per px): it stays 1.25 per px."
QString refusalMessage(const Refusing &box, double refused, const QLocale &locale);

} // namespace marbles
