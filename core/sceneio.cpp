#include "core/sceneio.h"

#include "core/filewrite.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <new>
#include <numeric>
#include <span>
#include <system_error>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace marbles {

namespace {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

constexpr std::string_view kFormat = "marbles-scene";
constexpr std::int64_t kVersion = 1;

// ---------------------------------------------------------------------------------------------
// Text for messages

/// Shortest decimal text that reads back as the same double ("-5", "0.1", "1e+300").
std::string formatNumber(double v)
{
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
}

/// Length of the valid UTF-8 sequence starting at s[i], or 0 when the bytes there are not one
/// (a stray or missing continuation byte, an overlong form, a surrogate, or beyond U+10FFFF).
std::size_t utf8SequenceLength(std::string_view s, std::size_t i)
{
    const auto lead = static_cast<unsigned char>(s[i]);
    std::size_t length = 0;
    // The second byte's range, which the lead narrows (RFC 3629's table).
    unsigned char low = 0x80;
    unsigned char high = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        low = lead == 0xE0 ? 0xA0 : 0x80;
        high = lead == 0xED ? 0x9F : 0xBF;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        low = lead == 0xF0 ? 0x90 : 0x80;
        high = lead == 0xF4 ? 0x8F : 0xBF;
    } else {
        return 0;
    }
    if (i + length > s.size())
        return 0;
    for (std::size_t k = 1; k < length; ++k) {
        const auto c = static_cast<unsigned char>(s[i + k]);
        if (c < (k == 1 ? low : 0x80) || c > (k == 1 ? high : 0xBF))
            return 0;
    }
    return length;
}

/// The code point of a valid UTF-8 sequence of 2 to 4 bytes.
char32_t codePointOf(std::string_view sequence)
{
    const auto byte = [&sequence](std::size_t k) { return static_cast<char32_t>(static_cast<unsigned char>(sequence[k])); };
    char32_t code = byte(0) & (sequence.size() == 2 ? 0x1Fu : sequence.size() == 3 ? 0x0Fu : 0x07u);
    for (std::size_t k = 1; k < sequence.size(); ++k)
        code = (code << 6) | (byte(k) & 0x3Fu);
    return code;
}

/// Characters that show nothing, or turn the text around them (Unicode's bidirectional
/// controls): in a message they would hide what is wrong, or reorder what a terminal shows.
bool invisibleFormat(char32_t c)
{
    return c == 0xAD || c == 0x61C || c == 0x180E || (c >= 0x200B && c <= 0x200F) || (c >= 0x202A && c <= 0x202E)
        || (c >= 0x2060 && c <= 0x2064) || (c >= 0x2066 && c <= 0x2069) || c == 0xFEFF;
}

} // namespace

std::string printableText(std::string_view text, std::size_t maxBytes)
{
    std::string out;
    std::size_t i = 0;
    while (i < text.size()) {
        if (out.size() >= maxBytes) {
            out += "...";
            break;
        }
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x80) {
            out += (c < 0x20 || c == 0x7F) ? '?' : static_cast<char>(c);
            ++i;
        } else if (const std::size_t n = utf8SequenceLength(text, i); n == 0) {
            out += '?';
            ++i;
        } else {
            const std::string_view character = text.substr(i, n);
            const char32_t code = codePointOf(character);
            if (code == 0x85 || code == 0x2028 || code == 0x2029) { // NEL, LINE and PARAGRAPH SEPARATOR
                out += '?';
            } else if (invisibleFormat(code)) {
                char hex[16];
                std::snprintf(hex, sizeof hex, "<U+%04X>", static_cast<unsigned>(code));
                out += hex;
            } else {
                out.append(character);
            }
            i += n;
        }
    }
    return out;
}

namespace {

/// A piece of input made safe to print in one line, at most `maxBytes` long (printableText()).
std::string printable(std::string_view s, std::size_t maxBytes = 60)
{
    return printableText(s, maxBytes);
}

/// What a JSON value is, for "got ..." in messages: `string "abc"`, `number 5`, `array`.
std::string describe(const Json &j)
{
    switch (j.type()) {
    case Json::value_t::null:
        return "null";
    case Json::value_t::boolean:
        return j.get<bool>() ? "boolean true" : "boolean false";
    case Json::value_t::string:
        return "string \"" + printable(j.get_ref<const Json::string_t &>()) + "\"";
    case Json::value_t::number_integer:
        return "number " + std::to_string(j.get<std::int64_t>());
    case Json::value_t::number_unsigned:
        return "number " + std::to_string(j.get<std::uint64_t>());
    case Json::value_t::number_float:
        return "number " + formatNumber(j.get<double>());
    case Json::value_t::array:
        return "array of " + std::to_string(j.size());
    case Json::value_t::object:
        return "object";
    case Json::value_t::binary:
    case Json::value_t::discarded:
        break;
    }
    return "an invalid value";
}

/// 1-based line and column, in characters, of the byte at `offset` in `text`.
std::string lineColumn(std::string_view text, std::size_t offset)
{
    // As a text editor counts them: a line ends at LF, CRLF or a lone CR (an old Mac file was
    // all "line 1, column 489"), and a column is a character, not a byte (each of "Stoß Ärger
    // Überlauf"'s letters beyond ASCII moved every later column one on). A byte order mark is no
    // character of the first line.
    offset = std::min(offset, text.size());
    std::size_t line = 1;
    std::size_t column = 1;
    for (std::size_t i = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0; i < offset; ++i) {
        const char c = text[i];
        if (c == '\n' || (c == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) {
            ++line;
            column = 1;
        } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80 && c != '\r') {
            ++column; // a byte that starts a character (continuation bytes are 10xxxxxx)
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// ---------------------------------------------------------------------------------------------
// Rules shared by the loader, validateParams and setParam: each returns "" or the rule broken.

std::string ruleFinite(double v)
{
    return std::isfinite(v) ? std::string() : std::string("must be a finite number");
}

std::string rulePositive(double v)
{
    if (!std::isfinite(v))
        return ruleFinite(v);
    return v > 0.0 ? std::string() : std::string("must be > 0");
}

// A mass: > 0, and not so small that 1 / m, which a push and a collision divide by, overflows
// (a mass of 1e-320 loaded, and its first push or collision left finite numbers).
std::string ruleMass(double m)
{
    if (std::string rule = rulePositive(m); !rule.empty())
        return rule;
    return std::isfinite(1.0 / m) ? std::string()
                                  : "must be at least " + formatNumber(1.0 / std::numeric_limits<double>::max())
            + ", whose 1 / m a push and a collision divide by";
}

std::string ruleNonNegative(double v)
{
    if (!std::isfinite(v))
        return ruleFinite(v);
    return v >= 0.0 ? std::string() : std::string("must be >= 0");
}

std::string ruleUnitInterval(double v)
{
    if (!std::isfinite(v))
        return ruleFinite(v);
    return (v >= 0.0 && v <= 1.0) ? std::string() : std::string("must be between 0 and 1");
}

std::string ruleSubsteps(std::int64_t n)
{
    if (n < 1)
        return "must be >= 1";
    if (n > kMaxSubsteps)
        return "must be <= " + std::to_string(kMaxSubsteps);
    return {};
}

// The exact model's drag rate is lambda = -ln(1 - k) per frame, which needs k < 1; the impulse
// model's per-sub-step factor (1 - k)^h needs 1 - k > 0 as well. The book model multiplies by
// (1 - k) directly, so any k >= 0 is defined there (k > 1 reverses velocities: the book's flaw).
std::string ruleFrictionForModel(double friction, ModelKind model)
{
    if (model != ModelKind::Book && !(friction < 1.0))
        return "must be < 1 for the " + std::string(modelName(model)) + " model";
    return {};
}

bool isDigit(char c)
{
    return c >= '0' && c <= '9';
}

bool isHexDigit(char c)
{
    return isDigit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

/// `c` in small letters, for ASCII's capitals (the scene's keys and JSON's words are ASCII).
char asciiLower(char c)
{
    return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
}

bool isColor(std::string_view s)
{
    return s.size() == 7 && s[0] == '#' && std::all_of(s.begin() + 1, s.end(), isHexDigit);
}

// The keys each object of a scene knows.
constexpr std::string_view kSceneKeys[] = {"format", "version", "stage", "params", "marbles", "pins", "pushes"};
constexpr std::string_view kStageKeys[] = {"width", "height", "walls"};
constexpr std::string_view kParamsKeys[] = {"model",       "massScale", "friction", "zeroThreshold", "pushScale",
                                            "frameMs",     "restitution", "gravity", "substeps",      "shortCircuit"};
constexpr std::string_view kMarbleKeys[] = {"x", "y", "radius", "vx", "vy", "mass", "name", "color"};
constexpr std::string_view kPinKeys[] = {"x", "y"};
constexpr std::string_view kPushKeys[] = {"frame", "marble", "x", "y"};

/// The keys a scene knows at its top level.
bool isSceneKey(std::string_view key)
{
    return std::find(std::begin(kSceneKeys), std::end(kSceneKeys), key) != std::end(kSceneKeys);
}

/// Edits (a letter added, removed, changed, or two side by side swapped) from `a` to `b`, letters
/// compared without case; `limit` + 1 for any number above `limit`.
std::size_t keyDistance(std::string_view a, std::string_view b, std::size_t limit)
{
    const std::size_t over = limit + 1;
    if ((a.size() > b.size() ? a.size() - b.size() : b.size() - a.size()) > limit)
        return over;
    // Rows of the optimal string alignment table: before last, last, current. `b` is a known key
    // (13 letters at most): the rows fit on the stack (a note's keys are measured against every
    // known key, for every unknown key of a 100k-marble file).
    constexpr std::size_t kLongest = 15;
    assert(b.size() <= kLongest);
    std::array<std::size_t, kLongest + 1> before{}, last{}, row{};
    std::iota(last.begin(), last.begin() + static_cast<std::ptrdiff_t>(b.size()) + 1, std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); ++i) {
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t change = asciiLower(a[i - 1]) == asciiLower(b[j - 1]) ? 0 : 1;
            row[j] = std::min({last[j] + 1, row[j - 1] + 1, last[j - 1] + change});
            if (i > 1 && j > 1 && asciiLower(a[i - 1]) == asciiLower(b[j - 2]) && asciiLower(a[i - 2]) == asciiLower(b[j - 1]))
                row[j] = std::min(row[j], before[j - 2] + 1);
        }
        std::swap(before, last);
        std::swap(last, row);
    }
    return std::min(last[b.size()], over);
}


// ---------------------------------------------------------------------------------------------
// Reading the JSON tree. A broken rule throws SceneError, which parseScene turns into the message.

struct SceneError {
    std::string place;
    std::string rule;
};

[[noreturn]] void fail(std::string place, std::string rule)
{
    throw SceneError{std::move(place), std::move(rule)};
}

double readNumber(const Json &j, const std::string &place)
{
    if (!j.is_number())
        fail(place, "must be a number, got " + describe(j));
    const double v = j.get<double>();
    if (!std::isfinite(v))
        fail(place, "must be a finite number, got " + formatNumber(v));
    return v;
}

/// A number that keeps `rule` (rulePositive(), ruleMass()).
double readRuled(const Json &j, const std::string &place, std::string (*rule)(double))
{
    const double v = readNumber(j, place);
    if (std::string broken = rule(v); !broken.empty())
        fail(place, broken + ", got " + formatNumber(v));
    return v;
}

double readPositive(const Json &j, const std::string &place)
{
    return readRuled(j, place, rulePositive);
}

bool readBool(const Json &j, const std::string &place)
{
    if (!j.is_boolean())
        fail(place, "must be true or false, got " + describe(j));
    return j.get<bool>();
}

const std::string &readString(const Json &j, const std::string &place)
{
    if (!j.is_string())
        fail(place, "must be a string, got " + describe(j));
    return j.get_ref<const Json::string_t &>();
}

/// An integer in [lo, hi]; a JSON number with a fractional part (2.5) is refused, 2.0 is 2.
std::int64_t readInteger(const Json &j, const std::string &place, std::int64_t lo, std::int64_t hi)
{
    if (!j.is_number())
        fail(place, "must be an integer, got " + describe(j));
    if (j.is_number_unsigned()) {
        const auto u = j.get<std::uint64_t>();
        if (u > static_cast<std::uint64_t>(hi))
            fail(place, "must be <= " + std::to_string(hi) + ", got " + std::to_string(u));
        const auto v = static_cast<std::int64_t>(u);
        if (v < lo)
            fail(place, "must be >= " + std::to_string(lo) + ", got " + std::to_string(v));
        return v;
    }
    std::int64_t v = 0;
    if (j.is_number_integer()) {
        v = j.get<std::int64_t>();
    } else {
        const double d = j.get<double>();
        if (!std::isfinite(d) || d != std::trunc(d))
            fail(place, "must be an integer, got " + formatNumber(d));
        // [-2^63, 2^63) is exactly the range of int64; both bounds are exact doubles.
        constexpr double kTwo63 = 9223372036854775808.0;
        if (d < -kTwo63)
            fail(place, "must be >= " + std::to_string(lo) + ", got " + formatNumber(d));
        if (d >= kTwo63)
            fail(place, "must be <= " + std::to_string(hi) + ", got " + formatNumber(d));
        v = static_cast<std::int64_t>(d);
    }
    if (v < lo)
        fail(place, "must be >= " + std::to_string(lo) + ", got " + std::to_string(v));
    if (v > hi)
        fail(place, "must be <= " + std::to_string(hi) + ", got " + std::to_string(v));
    return v;
}

Json &requireObject(Json &j, const std::string &place)
{
    if (!j.is_object())
        fail(place, "must be an object, got " + describe(j));
    return j;
}

Json &requireArray(Json &j, const std::string &place)
{
    if (!j.is_array())
        fail(place, "must be an array, got " + describe(j));
    return j;
}

std::string member(const std::string &parent, const std::string &key)
{
    return parent + "." + printable(key);
}

std::string element(const std::string &parent, std::size_t index)
{
    return parent + "[" + std::to_string(index) + "]";
}

/// Keys of a scene's objects that this program does not read. INTERFACES.md keeps them (a newer
/// version's keys, a teacher's notes), but a misspelt key leaves its default in force: a scene
/// with "Friction": 0.5 ran at 0.1, and one with "raduis": 5 drew the marble 25 px wide, without a
/// word (a helper's finding). Each is noted, those a known key's near-misses first, with that key.
class UnknownKeys {
public:
    /// Notes the key `key` of the object `object` at `place`, whose known keys are `known`.
    void note(const Json &object, const std::string &place, std::string_view key, std::span<const std::string_view> known)
    {
        ++m_count;
        std::vector<std::string_view> meant;
        if (key.size() <= 64) {
            std::size_t best = 3;
            for (std::string_view candidate : known) {
                // Not a key the object also gives ("x" beside "X": x was read).
                if (object.contains(candidate))
                    continue;
                // Other case only, or one edit for keys of up to 4 letters ("vz" for vx), two for
                // longer ones ("raduis").
                // A key of one letter is one edit from every other ("r" from x and y): only its case.
                const std::size_t limit = key.size() < 2 ? 0 : candidate.size() <= 4 ? 1 : 2;
                const std::size_t d = keyDistance(key, candidate, limit);
                if (d > limit || d > best)
                    continue;
                if (d < best)
                    meant.clear();
                best = d;
                meant.push_back(candidate);
            }
        }
        std::vector<std::string> &list = meant.empty() ? m_other : m_misspelt;
        if (list.size() >= kShown)
            return;
        const std::string shownKey = key.empty() ? std::string("\"\"") : printable(key);
        std::string text = (place.empty() ? shownKey : place + "." + shownKey) + ": not a key of " + placeName(place) + ", so not used";
        if (!meant.empty()) {
            text += " (did you mean ";
            for (std::size_t k = 0; k < meant.size(); ++k)
                text += (k == 0 ? "" : k + 1 == meant.size() ? " or " : ", ") + std::string(meant[k]);
            text += "?)";
        } else {
            text += " (kept when the scene is saved)";
        }
        list.push_back(std::move(text));
    }

    /// At most five notes, misspellings first, and how many more keys there are.
    std::vector<std::string> lines() const
    {
        std::vector<std::string> out = m_misspelt;
        out.insert(out.end(), m_other.begin(), m_other.begin() + static_cast<std::ptrdiff_t>(std::min(m_other.size(), kShown - out.size())));
        if (m_count > out.size()) {
            const std::size_t more = m_count - out.size();
            out.push_back("and " + std::to_string(more) + " more key" + (more == 1 ? "" : "s") + " not used");
        }
        return out;
    }

    bool anyMisspelt() const { return !m_misspelt.empty(); }

private:
    static constexpr std::size_t kShown = 5;

    /// "a marble" for "marbles[3]", "params" for "params".
    static std::string placeName(const std::string &place)
    {
        if (place.empty())
            return "a scene";
        if (place.rfind("marbles[", 0) == 0)
            return "a marble";
        if (place.rfind("pins[", 0) == 0)
            return "a pin";
        if (place.rfind("pushes[", 0) == 0)
            return "a push";
        return place;
    }

    std::vector<std::string> m_misspelt;
    std::vector<std::string> m_other;
    std::size_t m_count = 0;
};

/// Unknown keys as JSON object text, "" when there are none.
std::string extraText(const Json &extras)
{
    if (extras.empty())
        return {};
    return extras.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void readStage(Json &j, Stage &stage, std::string &extraJson, UnknownKeys &unknown)
{
    requireObject(j, "stage");
    Json extras = Json::object();
    for (auto &&[key, value] : j.items()) {
        const std::string place = member("stage", key);
        if (key == "width") {
            stage.width = readPositive(value, place);
        } else if (key == "height") {
            stage.height = readPositive(value, place);
        } else if (key == "walls") {
            stage.walls = readBool(value, place);
        } else {
            unknown.note(j, "stage", key, kStageKeys);
            extras[key] = std::move(value);
        }
    }
    extraJson = extraText(extras);
}

void readParams(Json &j, Params &p, std::string &extraJson, UnknownKeys &unknown)
{
    requireObject(j, "params");
    Json extras = Json::object();
    for (auto &&[key, value] : j.items()) {
        const std::string place = member("params", key);
        if (key == "model") {
            if (!value.is_string() || !parseModelName(value.get_ref<const Json::string_t &>(), p.model))
                fail(place, "must be \"book\", \"impulse\" or \"exact\", got " + describe(value));
        } else if (key == "massScale") {
            p.massScale = readNumber(value, place);
        } else if (key == "friction") {
            p.friction = readNumber(value, place);
        } else if (key == "zeroThreshold") {
            p.zeroThreshold = readNumber(value, place);
        } else if (key == "pushScale") {
            p.pushScale = readNumber(value, place);
        } else if (key == "frameMs") {
            p.frameMs = readNumber(value, place);
        } else if (key == "restitution") {
            p.restitution = readNumber(value, place);
        } else if (key == "gravity") {
            if (!value.is_array() || value.size() != 2)
                fail(place, "must be an array of 2 numbers [x, y], got " + describe(value));
            p.gravity.x = readNumber(value[0], element(place, 0));
            p.gravity.y = readNumber(value[1], element(place, 1));
        } else if (key == "substeps") {
            p.substeps = static_cast<int>(readInteger(value, place, 1, kMaxSubsteps));
        } else if (key == "shortCircuit") {
            p.shortCircuit = readBool(value, place);
        } else {
            unknown.note(j, "params", key, kParamsKeys);
            extras[key] = std::move(value);
        }
    }
    extraJson = extraText(extras);
}

// A mass derived from the radius (World's massScale * radius, for a marble without a mass of its
// own) must be a mass too: the product can overflow (1e308 x 25 is no number) or underflow to 0.
// Returns "" or the rule it breaks.
std::string derivedMassRule(double massScale, double radius)
{
    const double m = massScale * radius;
    if (ruleMass(m).empty())
        return {};
    const std::string product = "its mass massScale x radius = " + formatNumber(massScale) + " x " + formatNumber(radius);
    if (rulePositive(m).empty()) // a mass too close to 0 (massScale 1e-320), ruleMass()'s other half
        return product + " = " + formatNumber(m) + " is too close to 0: 1 / m, which a push and a collision divide by, "
               + "is beyond what a double can hold: give the marble a mass, or change massScale";
    return product + " is " + (m > 0.0 ? "beyond" : "below") + " what a double can hold: give the marble a mass, or change massScale";
}

void readMarble(Json &j, const std::string &place, World &world, UnknownKeys &unknown)
{
    requireObject(j, place);
    Vec2 p;
    Vec2 v;
    double r = kDefaultMarbleRadius;
    double m = 0.0;
    MarbleInfo info;
    Json extras = Json::object();
    for (auto &&[key, value] : j.items()) {
        const std::string at = member(place, key);
        if (key == "x") {
            p.x = readNumber(value, at);
        } else if (key == "y") {
            p.y = readNumber(value, at);
        } else if (key == "vx") {
            v.x = readNumber(value, at);
        } else if (key == "vy") {
            v.y = readNumber(value, at);
        } else if (key == "radius") {
            r = readPositive(value, at);
        } else if (key == "mass") {
            m = readRuled(value, at, ruleMass);
        } else if (key == "name") {
            info.name = readString(value, at);
        } else if (key == "color") {
            info.color = readString(value, at);
            if (!isColor(info.color))
                fail(at, "must be a colour \"#rrggbb\", got " + describe(value));
        } else {
            unknown.note(j, place, key, kMarbleKeys);
            extras[key] = std::move(value);
        }
    }
    const int i = world.addMarble(p, r, v, m);
    if (std::string broken = world.info[i].hasMass ? std::string() : derivedMassRule(world.params.massScale, r);
        !broken.empty())
        fail(place, broken);
    info.hasMass = world.info[i].hasMass;
    info.extraJson = extraText(extras);
    world.info[i] = std::move(info);
}

void readPin(Json &j, const std::string &place, World &world, UnknownKeys &unknown)
{
    requireObject(j, place);
    Vec2 q;
    Json extras = Json::object();
    for (auto &&[key, value] : j.items()) {
        if (key == "x") {
            q.x = readNumber(value, member(place, key));
        } else if (key == "y") {
            q.y = readNumber(value, member(place, key));
        } else {
            unknown.note(j, place, key, kPinKeys);
            extras[key] = std::move(value);
        }
    }
    const int k = world.addPin(q);
    world.pinExtraJson[k] = extraText(extras);
}

void readPush(Json &j, const std::string &place, World &world, UnknownKeys &unknown)
{
    requireObject(j, place);
    Push push;
    Json extras = Json::object();
    for (auto &&[key, value] : j.items()) {
        const std::string at = member(place, key);
        if (key == "frame") {
            push.frame = readInteger(value, at, 0, std::numeric_limits<std::int64_t>::max());
        } else if (key == "marble") {
            const std::int64_t count = world.marbleCount();
            const auto noSuchMarble = [&](const std::string &got) {
                fail(at, count == 0 ? "must name an existing marble, but the scene has none, got " + got
                                    : "must name an existing marble (0 to " + std::to_string(count - 1) + "), got " + got);
            };
            // A whole number beyond int64 names no marble either (it said "must be <=
            // 9223372036854775807", a rule no scene could mean).
            if (value.is_number_unsigned()
                && value.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
                noSuchMarble(std::to_string(value.get<std::uint64_t>()));
            if (value.is_number_float()) {
                const double d = value.get<double>();
                if (std::isfinite(d) && d == std::trunc(d) && std::abs(d) >= 9223372036854775808.0)
                    noSuchMarble(formatNumber(d));
            }
            const std::int64_t m = readInteger(value, at, std::numeric_limits<std::int64_t>::min(),
                                               std::numeric_limits<std::int64_t>::max());
            if (m < 0 || m >= count)
                noSuchMarble(std::to_string(m));
            push.marble = static_cast<int>(m);
        } else if (key == "x") {
            push.at.x = readNumber(value, at);
        } else if (key == "y") {
            push.at.y = readNumber(value, at);
        } else {
            unknown.note(j, place, key, kPushKeys);
            extras[key] = std::move(value);
        }
    }
    push.extraJson = extraText(extras);
    // A push that leaves out `marble` means marble 0, which must exist as well.
    if (!j.contains("marble") && world.marbleCount() == 0)
        fail(member(place, "marble"), "must name an existing marble, but the scene has none, got 0 (the default)");
    world.pushes.push_back(push);
}

/// Builds the scene from a parsed document, moving unknown keys out of it (and noting them in
/// `unknown`); throws SceneError.
World readScene(Json &doc, UnknownKeys &unknown)
{
    if (!doc.is_object())
        fail("top level", "must be a JSON object (a scene), got " + describe(doc));

    const auto format = doc.find("format");
    if (format == doc.end())
        fail("format", "is required and must be \"marbles-scene\"");
    if (!format->is_string() || format->get_ref<const Json::string_t &>() != kFormat)
        fail("format", "must be \"marbles-scene\", got " + describe(*format));

    const auto version = doc.find("version");
    if (version == doc.end())
        fail("version", "is required and must be 1");
    if (!version->is_number() || version->get<double>() != static_cast<double>(kVersion))
        fail("version", "must be 1 (the only version this program reads), got " + describe(*version));

    World world;
    if (const auto it = doc.find("stage"); it != doc.end())
        readStage(*it, world.stage, world.stageExtraJson, unknown);
    if (const auto it = doc.find("params"); it != doc.end()) {
        readParams(*it, world.params, world.paramsExtraJson, unknown);
        if (std::string error = validateParams(world.params); !error.empty()) {
            const std::size_t split = error.find(": ");
            fail(error.substr(0, split), error.substr(split + 2));
        }
    }
    // Marbles after params: a marble's derived mass is massScale * radius.
    if (const auto it = doc.find("marbles"); it != doc.end()) {
        Json &list = requireArray(*it, "marbles");
        for (std::size_t i = 0; i < list.size(); ++i)
            readMarble(list[i], element("marbles", i), world, unknown);
    }
    if (const auto it = doc.find("pins"); it != doc.end()) {
        Json &list = requireArray(*it, "pins");
        for (std::size_t i = 0; i < list.size(); ++i)
            readPin(list[i], element("pins", i), world, unknown);
    }
    // Pushes after marbles: each must name a marble that exists.
    if (const auto it = doc.find("pushes"); it != doc.end()) {
        Json &list = requireArray(*it, "pushes");
        for (std::size_t i = 0; i < list.size(); ++i)
            readPush(list[i], element("pushes", i), world, unknown);
    }

    Json extras = Json::object();
    for (auto &&[key, value] : doc.items()) {
        if (!isSceneKey(key)) {
            unknown.note(doc, std::string(), key, kSceneKeys);
            extras[key] = std::move(value);
        }
    }
    world.sceneExtraJson = extraText(extras);
    world.frame = 0;
    return world;
}

// ---------------------------------------------------------------------------------------------
// Parsing text

/// SAX handler that builds the document with nlohmann's own DOM builder and also tracks where
/// in the document it is, so that a number nlohmann cannot hold (1e999) is reported by its place
/// ("marbles[0].x") rather than only by line and column.
class TrackingBuilder {
public:
    explicit TrackingBuilder(Json &root)
        : m_dom(root, true)
    {
    }

    bool null() { return admit(0) && m_dom.null(); }
    bool boolean(bool b) { return admit(0) && m_dom.boolean(b); }
    bool number_integer(Json::number_integer_t v)
    {
        // nlohmann reads a literal with a minus sign as a signed integer, and "-0" as the integer
        // 0: it is taken as the double -0 (as strtod and JavaScript read it), so that a -0 printed
        // by `marbles-cli run` (%.17g) reads back as the same bits (a helper's finding).
        if (v == 0)
            return admit(0) && m_dom.number_float(-0.0, "-0");
        return admit(0) && m_dom.number_integer(v);
    }
    bool number_unsigned(Json::number_unsigned_t v) { return admit(0) && m_dom.number_unsigned(v); }
    bool number_float(Json::number_float_t v, const Json::string_t &text)
    {
        if (!admit(0))
            return false;
        // A number too small for a double ("1e-400") is read as 0: noted by its place, so that a
        // rule it then breaks quotes it as written, not as "got 0".
        if (v == 0.0 && m_underflows.size() < 16
            && text.substr(0, text.find_first_of("eE")).find_first_of("123456789") != std::string::npos)
            m_underflows.emplace_back(currentPath(), text);
        return m_dom.number_float(v, text);
    }
    bool string(Json::string_t &s) { return admit(heapString(s.size())) && m_dom.string(s); }
    bool binary(Json::binary_t &b) { return admit(b.size() + kHeapBlock) && m_dom.binary(b); }
    bool start_object(std::size_t n)
    {
        if (!admit(kObjectCost) || !admitInWorld(worldCostOfElement()))
            return false;
        m_path.push_back({false, 0, {}, m_keys.size()});
        return m_dom.start_object(n);
    }
    bool key(Json::string_t &k)
    {
        // A key given twice in one object: the parser keeps the last value, so a file with two
        // "friction" keys (a hand edit) loaded one of them without a word. Checked among an
        // object's first 256 keys (a scene's objects hold a dozen; more are extra keys).
        Level &level = m_path.back();
        level.key = k;
        if (m_keys.size() - level.firstKey < 256) {
            if (std::find(m_keys.begin() + static_cast<std::ptrdiff_t>(level.firstKey), m_keys.end(), k) != m_keys.end()) {
                m_duplicateKey = currentPath();
                return false;
            }
            m_keys.push_back(k);
        }
        return m_dom.key(k);
    }
    bool end_object()
    {
        m_keys.resize(m_path.back().firstKey);
        m_path.pop_back();
        return m_dom.end_object();
    }
    bool start_array(std::size_t n)
    {
        if (!admit(kArrayCost))
            return false;
        m_path.push_back({true, 0, {}, m_keys.size()});
        return m_dom.start_array(n);
    }
    bool end_array()
    {
        m_path.pop_back();
        return m_dom.end_array();
    }

    template<class Exception>
    bool parse_error(std::size_t position, const std::string &lastToken, const Exception &ex)
    {
        m_failed = true;
        m_position = position;
        m_lastToken = lastToken;
        m_errorId = ex.id;
        m_what = ex.what();
        m_failedPath = currentPath();
        return false;
    }

    bool failed() const { return m_failed; }
    bool overBudget() const { return m_overBudget; }
    /// True when the World would outgrow kMaxSceneWorldBytes (too many marbles, pins or pushes).
    bool overWorldBudget() const { return m_overWorldBudget; }
    std::size_t position() const { return m_position; }
    const std::string &lastToken() const { return m_lastToken; }
    int errorId() const { return m_errorId; }
    const std::string &what() const { return m_what; }
    const std::string &failedPath() const { return m_failedPath; }
    /// The place of a key given twice in one object ("params.friction"), or "".
    const std::string &duplicateKey() const { return m_duplicateKey; }
    /// The number as written at `place` if it was too small for a double, else "".
    std::string underflowAt(const std::string &place) const
    {
        for (const auto &[where, text] : m_underflows) {
            if (where == place)
                return text;
        }
        return {};
    }

private:
    struct Level {
        bool isArray = false;
        std::size_t count = 0; ///< elements begun so far (arrays)
        std::string key;       ///< key being read (objects)
        std::size_t firstKey = 0; ///< its keys' start in m_keys (objects)
    };

    // Memory estimate of nlohmann's document, measured with glibc on x86-64 and rounded up:
    // a value is 16 bytes in its array (24 with the vector's spare capacity) or a std::map node
    // of about 96 bytes in its object; an object's map and an array's vector cost a heap block
    // each; a string or key longer than the 15-byte small-string buffer costs its own block.
    static constexpr std::size_t kHeapBlock = 17;
    static constexpr std::size_t kArraySlot = 24;
    static constexpr std::size_t kObjectMember = 96;
    static constexpr std::size_t kObjectCost = 64;
    static constexpr std::size_t kArrayCost = 40;

    static std::size_t heapString(std::size_t length) { return length > 15 ? length + kHeapBlock : 0; }

    // What the World built from the document takes for each marble, pin and push (World::
    // kMarbleBytes, kPinBytes, kPushBytes) comes on top of the document, which lives until the World
    // is built: 10 million marbles "{}", a 30 MB file within the document's budget, took 3.5 GB.

    /// The World's cost of the object about to begin, when it is an element of the scene's
    /// marbles, pins or pushes.
    std::size_t worldCostOfElement() const
    {
        if (m_path.size() != 2 || m_path[0].isArray || !m_path[1].isArray)
            return 0;
        const std::string &list = m_path[0].key;
        return list == "marbles" ? World::kMarbleBytes : list == "pins" ? World::kPinBytes : list == "pushes" ? World::kPushBytes : 0;
    }

    /// Counts a value about to be added (its place in the parent plus `own` bytes); false once
    /// the document would outgrow kMaxSceneMemoryBytes, which stops the parse before it allocates.
    bool admit(std::size_t own)
    {
        std::size_t cost = own;
        if (m_path.empty()) {
            cost += 16;
        } else if (m_path.back().isArray) {
            ++m_path.back().count;
            cost += kArraySlot;
        } else {
            cost += kObjectMember + heapString(m_path.back().key.size());
        }
        m_bytes += cost;
        if (m_bytes > kMaxSceneMemoryBytes) {
            m_overBudget = true;
            return false;
        }
        return true;
    }

    /// Counts `bytes` of the World about to be built; false once it would outgrow
    /// kMaxSceneWorldBytes, which stops the parse.
    bool admitInWorld(std::size_t bytes)
    {
        m_worldBytes += bytes;
        if (m_worldBytes > kMaxSceneWorldBytes) {
            m_overWorldBudget = true;
            return false;
        }
        return true;
    }

    /// Place of the value being read when the error happened. An open array level points at its
    /// last begun element, except the innermost one, whose failing element has not begun yet.
    std::string currentPath() const
    {
        std::string path;
        for (std::size_t k = 0; k < m_path.size(); ++k) {
            const Level &level = m_path[k];
            if (level.isArray) {
                const bool innermost = k + 1 == m_path.size();
                const std::size_t index = innermost ? level.count : (level.count > 0 ? level.count - 1 : 0);
                path += "[" + std::to_string(index) + "]";
            } else {
                path += (path.empty() ? "" : ".") + printable(level.key);
            }
        }
        return path;
    }

    nlohmann::detail::json_sax_dom_parser<Json> m_dom;
    std::vector<Level> m_path;
    bool m_failed = false;
    bool m_overBudget = false;
    bool m_overWorldBudget = false;
    std::size_t m_worldBytes = 0;
    std::size_t m_bytes = 0;
    std::size_t m_position = 0;
    std::string m_lastToken;
    int m_errorId = 0;
    std::string m_what;
    std::string m_failedPath;
    std::vector<std::pair<std::string, std::string>> m_underflows; ///< place, number as written
    std::vector<std::string> m_keys; ///< the keys of the objects open, outermost first
    std::string m_duplicateKey;
};

/// nlohmann's syntax error in words a scene's author (a teacher editing a file by hand) reads:
/// "syntax error while parsing value - invalid literal; last read: 'th'" said nothing of why.
/// The common slips (a word or text without double quotes, a comma missing or one too many, the
/// text cut short) are named as such, with what the parser last read; the rest keep its words,
/// without the "syntax error while parsing ... - " head.
std::string plainSyntaxError(const std::string &detail)
{
    const std::string head = "syntax error while parsing ";
    const std::size_t dash = detail.find(" - ");
    if (detail.rfind(head, 0) != 0 || dash == std::string::npos)
        return detail;
    const std::string context = detail.substr(head.size(), dash - head.size()); // "value", "object key", ...
    const std::string problem = detail.substr(dash + 3);
    const auto startsWith = [&problem](std::string_view prefix) { return problem.rfind(prefix, 0) == 0; };
    const std::size_t lastRead = problem.find("last read: ");
    const std::string read = lastRead == std::string::npos ? std::string() : " (" + problem.substr(lastRead) + ")";
    // What the parser met, in words: "string literal" is a text in double quotes.
    const auto met = [&problem] {
        std::string token = problem.substr(11, problem.find(';') - 11); // after "unexpected "
        return token == "string literal"  ? std::string("a text in double quotes")
               : token == "number literal" ? std::string("a number")
               : token == "true literal"   ? std::string("true")
               : token == "false literal"  ? std::string("false")
               : token == "null literal"   ? std::string("null")
                                           : token;
    };
    // The parser stops at the first '/' it reads outside a text: a comment's start.
    const std::size_t closing = lastRead == std::string::npos ? std::string::npos : problem.find('\'', lastRead + 12);
    if (startsWith("invalid literal") && closing != std::string::npos && closing > lastRead + 12 && problem[closing - 1] == '/')
        return "a comment: JSON has none ('//' and '/* */' are not allowed)" + read;
    if (startsWith("invalid literal"))
        return "a word JSON does not know: a text goes in double quotes (\"like this\"), and the only words "
               "without them are true, false and null" + read;
    if (startsWith("unexpected end of input"))
        return "the text ends too soon (a '}' or ']' missing?)";
    if (startsWith("invalid string: ill-formed UTF-8 byte"))
        return "a byte that is not UTF-8 in a text (was the file saved as Latin-1 or Windows-1252?): "
               "save it as UTF-8" + read;
    if (startsWith("invalid string: missing closing quote"))
        return "a text without its closing double quote" + read;
    if (context == "object" && startsWith("unexpected ") && problem.find("; expected '}'") != std::string::npos)
        return met() + " where a ',' or the '}' should come (a comma missing?)";
    if (context == "array" && startsWith("unexpected ") && problem.find("; expected ']'") != std::string::npos)
        return met() + " where a ',' or the ']' should come (a comma missing?)";
    if (context == "object key" && startsWith("unexpected '}'"))
        return "a '}' right after a ',' (a comma too many?)";
    if (context == "object key" && startsWith("unexpected "))
        return met() + " where a key in double quotes should come";
    if (context == "value" && startsWith("unexpected ']'"))
        return "a ']' right after a ',' (a comma too many?)";
    if (context == "object separator" && problem.find("expected ':'") != std::string::npos)
        return "a key without its ':' and value";
    return problem;
}

/// Where the first byte of `s` that does not start a well-formed UTF-8 character is, or npos.
std::size_t firstNonUtf8(std::string_view s)
{
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t n = static_cast<unsigned char>(s[i]) < 0x80 ? 1 : utf8SequenceLength(s, i);
        if (n == 0)
            return i;
        i += n;
    }
    return std::string_view::npos;
}

/// What the author of a scene most likely meant where the parser stopped, at `offset` of `text`,
/// in a word or number outside any text (`keyExpected`: where a key should have come; `closer`:
/// where a ',' or this '}' or ']' should have come, after a value, else 0; `pair`: the value was
/// to be a pair [x, y], gravity); "" when the parser's own message says it as well. Sets `start`
/// to where that word or number begins.
/// The parser had called "+5", ".5", NaN, Infinity and 0x10 "a word JSON does not know" and asked
/// for double quotes (quoted, each was then "a string"), and "massScale": 1,25 "a number where a
/// key should come" (a helper's findings).
std::string likelyMeant(std::string_view text, std::size_t offset, bool keyExpected, char closer, bool pair,
                        std::size_t &start)
{
    if (text.empty())
        return {};
    offset = std::min(offset, text.size() - 1); // (a number cut short by the text's end: "0.")
    const auto wordChar = [&](char c) {
        return isDigit(c) || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '.' || c == '+' || c == '-'
            || static_cast<unsigned char>(c) >= 0x80; // a letter beyond ASCII ("Stoß")
    };
    if (text[offset] == '\'')
        return start = offset, "a text in single quotes: JSON puts a text in double quotes (\"like this\")";
    // The parser stops on the character after a number cut short ("1.5e,"), on the one it could
    // not take in a word ("+", "N" of NaN).
    if (!wordChar(text[offset])) {
        if (offset == 0 || !wordChar(text[offset - 1]))
            return {};
        --offset;
    }
    std::size_t from = offset;
    while (from > 0 && wordChar(text[from - 1]))
        --from;
    std::size_t to = offset;
    while (to < text.size() && wordChar(text[to]))
        ++to;
    const std::string_view word = text.substr(from, to - from);
    const std::string shown = printable(word);
    std::string lower(word);
    std::transform(lower.begin(), lower.end(), lower.begin(), asciiLower);
    const std::string_view unsigned_ = std::string_view(lower).substr(!lower.empty() && (lower[0] == '+' || lower[0] == '-') ? 1 : 0);
    start = from;
    if (to == text.size())
        return "the text ends too soon, in " + shown + " (cut short?)";
    // "massScale": 1,25 reads as the number 1 and then 25 where a key should come. Only for a
    // whole number before the comma: 1.250,5 (German for 1250.5) or 1e5,25 would be "250.5" and
    // "5.25", a valid file with the wrong number.
    std::size_t number = from >= 2 ? from - 1 : 0;
    while (number > 0 && isDigit(text[number - 1]))
        --number;
    if (number > 0 && text[number - 1] == '-')
        --number;
    const bool wholeBefore = number == 0 || std::string_view(".eE+-").find(text[number - 1]) == std::string_view::npos;
    if (keyExpected && isDigit(word.front()) && from >= 2 && text[from - 1] == ',' && isDigit(text[from - 2]) && wholeBefore) {
        start = number;
        const std::string whole = printable(text.substr(number, from - 1 - number));
        const std::string part = printable(word.substr(0, static_cast<std::size_t>(
                                                              std::find_if_not(word.begin(), word.end(), isDigit) - word.begin())));
        // "gravity": 0,5 is more likely a pair without its brackets than 0.5.
        if (pair)
            return "two numbers (" + whole + "," + part + ") where a pair goes in brackets: write [" + whole + ", " + part + "]";
        return "a decimal comma (" + whole + "," + part + "): JSON writes a number with a point, " + whole + "." + part;
    }
    if (keyExpected && !isDigit(word.front()) && word.front() != '+' && word.front() != '-' && word.front() != '.')
        return "a key without its double quotes (" + shown + "): write \"" + shown + "\"";
    if (unsigned_ == "nan" || unsigned_ == "infinity" || unsigned_ == "inf")
        return shown + " is not a number a scene can hold: every number must be finite";
    if (unsigned_.substr(0, 2) == "0x")
        return "a hexadecimal number (" + shown + "), which JSON does not allow: write it in decimal";
    if (word.front() == '+' && word.size() > 1 && (isDigit(word[1]) || word[1] == '.'))
        return "a number with a '+' sign (" + shown + "), which JSON does not allow: write it without the sign";
    if (!unsigned_.empty() && unsigned_.front() == '.' && unsigned_.size() > 1 && isDigit(unsigned_[1]))
        return "a number without a digit before its point (" + shown + "): write a 0 before the point";
    if (std::any_of(word.begin(), word.end(), isDigit) && std::string_view(".eE+-").find(word.back()) != std::string_view::npos
        && to == offset + 1)
        return "a number that stops short (" + shown + "): digits must follow its point, its e and its sign";
    const bool letter = (word.front() >= 'a' && word.front() <= 'z') || (word.front() >= 'A' && word.front() <= 'Z')
        || static_cast<unsigned char>(word.front()) >= 0x80;
    // A byte that is not UTF-8 in it: quoted, it would still be refused for that.
    if (letter && firstNonUtf8(word) != std::string_view::npos)
        return "a text without its double quotes, with a byte that is not UTF-8 in it (" + shown
            + "): put it in double quotes, and save the file as UTF-8 (was it saved as Latin-1 or Windows-1252?)";
    // After a value: a key that follows it without its comma ("exact" massScale: 2), even quoted.
    if (closer != 0 && letter)
        return "a word (" + shown + ") where a ',' or the '" + closer + "' should come (a comma missing?)";
    if (lower == "true" || lower == "false" || lower == "null")
        return shown + " in small letters: JSON knows true, false and null only so";
    if (letter)
        return "a text without its double quotes (" + shown + "): write \"" + shown + "\"";
    return {};
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: " head.
std::string parserDetail(const std::string &what)
{
    const std::size_t column = what.find("column ");
    if (column != std::string::npos) {
        const std::size_t colon = what.find(": ", column);
        if (colon != std::string::npos)
            return printable(plainSyntaxError(what.substr(colon + 2)), 200);
    }
    const std::size_t bracket = what.find("] ");
    return printable(plainSyntaxError(bracket == std::string::npos ? what : what.substr(bracket + 2)), 200);
}

/// True for the bytes that may stand outside strings in JSON: whitespace, structure, numbers
/// and the letters of true, false and null.
bool mayStandOutsideString(char c)
{
    switch (c) {
    case ' ': case '\t': case '\n': case '\r':
    case '[': case ']': case '{': case '}': case ':': case ',':
    case '-': case '+': case '.': case 'e': case 'E':
    case 't': case 'r': case 'u': case 'f': case 'a': case 'l': case 's': case 'n':
        return true;
    default:
        return isDigit(c);
    }
}

/// Cheap scan before nlohmann sees the text: refuses nesting deeper than kMaxSceneNesting,
/// counting only brackets outside strings (a backslash escapes the next character inside one).
/// It stops at the first byte that cannot be JSON there (a control character inside a string,
/// anything else outside one): nlohmann fails at or before that byte, so nothing after it is
/// ever nested, and garbage gets nlohmann's syntax error rather than a nesting complaint.
/// Returns "" or "place: rule".
std::string checkNesting(std::string_view text)
{
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (static_cast<unsigned char>(c) < 0x20)
                break;
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxSceneNesting)
                return lineColumn(text, i) + ": arrays and objects are nested deeper than "
                    + std::to_string(kMaxSceneNesting) + " levels";
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        } else if (!mayStandOutsideString(c) && !(i < 3 && text.substr(0, 3) == "\xEF\xBB\xBF")) {
            break;
        }
    }
    return {};
}

/// Empties a parsed document leaves first, without allocating. nlohmann's own destructor first
/// moves every element of an array or object onto a heap stack of their number, and a
/// std::bad_alloc there, in a destructor, is std::terminate: `marbles-cli check` of a 9 MB scene
/// of 3,000,000 pushes under a 256 MiB address-space limit aborted (exit 134) as the document
/// was freed, where it should say there is not enough memory. One path from the root to the
/// node being emptied is enough: checkNesting() bounds its length.
class DismantleOnExit {
public:
    explicit DismantleOnExit(Json &root)
        : m_root(root)
    {
    }
    DismantleOnExit(const DismantleOnExit &) = delete;
    DismantleOnExit &operator=(const DismantleOnExit &) = delete;
    ~DismantleOnExit()
    {
        std::array<Json *, kMaxSceneNesting + 2> path{};
        std::size_t depth = 0;
        path[0] = &m_root;
        const auto branches = [](const Json &j) { return j.is_structured() && !j.empty(); };
        for (;;) {
            Json &node = *path[depth];
            if (node.is_array() && !node.empty()) {
                auto &items = node.get_ref<Json::array_t &>();
                if (branches(items.back()) && depth + 1 < path.size()) {
                    path[++depth] = &items.back();
                    continue;
                }
                items.pop_back(); // a leaf, or (never, the nesting being bounded) the destructor's work
            } else if (node.is_object() && !node.empty()) {
                auto &members = node.get_ref<Json::object_t &>();
                const auto last = std::prev(members.end());
                if (branches(last->second) && depth + 1 < path.size()) {
                    path[++depth] = &last->second;
                    continue;
                }
                members.erase(last);
            } else if (depth == 0) {
                return;
            } else {
                --depth;
            }
        }
    }

private:
    Json &m_root;
};

/// Parses and reads the scene into `world`, noting the keys it does not know in `unknown`;
/// returns "" or "place: rule".
std::string parseInto(std::string_view text, World &world, UnknownKeys &unknown)
{
    if (text.size() > kMaxSceneBytes)
        return sceneTooLarge("a scene", std::to_string(text.size()) + " bytes");
    if (text.size() >= 2
        && ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF')))
        return "line 1, column 1: the text is UTF-16 (it starts with a UTF-16 byte order mark); "
               "a scene file must be UTF-8";
    std::string_view body = text;
    if (body.substr(0, 3) == "\xEF\xBB\xBF")
        body.remove_prefix(3);
    if (body.substr(0, 3) == "\xEF\xBB\xBF")
        return lineColumn(text, 3) + ": a second byte order mark (U+FEFF): a scene file may start with one, not two";
    if (body.find_first_not_of(" \t\r\n") == std::string_view::npos)
        return "line 1, column 1: the text is empty; a scene file holds a JSON object";
    if (std::string nesting = checkNesting(text); !nesting.empty())
        return nesting;

    Json doc;
    const DismantleOnExit freeQuietly(doc); // before doc's destructor, on every way out
    TrackingBuilder builder(doc);
    const bool parsed = Json::sax_parse(text.data(), text.data() + text.size(), &builder,
                                        Json::input_format_t::json, true, false);
    if (builder.overBudget())
        return "size: reading this scene would take more than " + std::to_string(kMaxSceneMemoryBytes >> 20)
            + " MiB of memory (it holds too many values)";
    if (builder.overWorldBudget())
        return "size: this scene's marbles, pins and pushes would take more than "
            + std::to_string(kMaxSceneWorldBytes >> 20) + " MiB of memory (it holds too many of them)";
    if (!builder.duplicateKey().empty())
        return builder.duplicateKey() + ": is given twice in the same object: keep one of them";
    // The parser takes a NUL byte for the end of the text: whatever followed it was never read
    // (a scene with "\0garbage{{{" after its object loaded), and one at the start read as empty.
    // Named where the parse stopped at it, or got past the place where it should have.
    const std::size_t nul = text.find('\0');
    const std::size_t stopped = builder.position() > 0 ? builder.position() - 1 : 0;
    if (nul != std::string_view::npos && ((parsed && !builder.failed()) || nul <= stopped))
        return lineColumn(text, nul) + ": a NUL byte (0x00), which JSON text cannot hold";
    if (!parsed || builder.failed()) {
        // 406: a number too large for a double (1e999): JSON allows it, a scene does not.
        if (builder.errorId() == 406) {
            const std::string &token = builder.lastToken();
            const std::size_t start = builder.position() >= token.size() ? builder.position() - token.size() : 0;
            const std::string path = builder.failedPath().empty() ? std::string("value") : builder.failedPath();
            // The place first, as in every other message ("FILE: PLACE: RULE", INTERFACES.md).
            return path + ": must be a finite number, got " + printable(token) + " (" + lineColumn(text, start) + ")";
        }
        // "radius": 01 reads as the number 0 and then a number where a ',' should come, which
        // the message said ("a comma missing?", a helper's finding): a leading zero is named.
        const std::string &token = builder.lastToken();
        const std::size_t start = builder.position() >= token.size() ? builder.position() - token.size() : 0;
            // Only where the parser met a number right after the zero: a text cut short after one
        // ("x": 0.0087, 0. or 0.5e- cut there) ends too soon, or in a number without its digits,
        // as said below (a helper's finding).
        const bool numberAfterNumber = builder.what().find("unexpected number literal") != std::string::npos;
        if (numberAfterNumber && !token.empty() && isDigit(token.front()) && start >= 1 && start <= text.size() && text[start - 1] == '0'
            && (start < 2 || !(isDigit(text[start - 2]) || text[start - 2] == '.' || text[start - 2] == 'e' || text[start - 2] == 'E'))) {
            // The number as written: from its sign or zero to where number characters end.
            const std::size_t from = start >= 2 && text[start - 2] == '-' ? start - 2 : start - 1;
            std::size_t to = start;
            while (to < text.size() && (isDigit(text[to]) || std::string_view(".eE+-").find(text[to]) != std::string_view::npos))
                ++to;
            const std::string written = printable(text.substr(from, to - from));
            return lineColumn(text, start - 1) + ": not valid JSON: a number with a leading zero (" + written
                + "), which JSON does not allow: write it without the zero";
        }
        const std::size_t offset = builder.position() > 0 ? builder.position() - 1 : 0;
        const std::string &what = builder.what();
        // At the byte that is not UTF-8, not the end of the text holding it.
        if (what.find("ill-formed UTF-8") != std::string::npos && offset <= text.size()) {
            const std::size_t opening = text.rfind('"', offset > 0 ? offset - 1 : 0);
            if (opening != std::string_view::npos && opening < offset) {
                const std::size_t bad = firstNonUtf8(text.substr(opening + 1, offset - opening - 1));
                if (bad != std::string_view::npos)
                    return lineColumn(text, opening + 1 + bad) + ": not valid JSON: " + parserDetail(what);
            }
        }
        // After a value: where a ',' or this '}' or ']' should have come, else 0.
        const char closer = what.find("; expected '}'") != std::string::npos   ? '}'
                            : what.find("; expected ']'") != std::string::npos ? ']'
                                                                                 : '\0';
        // Not past the scene's end: "} xyz" is text after it, whatever that text is.
        if ((what.find("invalid literal") != std::string::npos || what.find("invalid number") != std::string::npos
             || what.find("unexpected number literal") != std::string::npos)
            && what.find("expected end of input") == std::string::npos) {
            std::size_t at = offset;
            const bool pair = builder.failedPath() == "params.gravity";
            if (const std::string meant = likelyMeant(text, offset, what.find("parsing object key") != std::string::npos, closer, pair, at);
                !meant.empty())
                return lineColumn(text, at) + ": not valid JSON: " + meant;
        }
        // A value where a ',' should come is placed where it starts (a text's opening quote, a
        // number's first digit), as the words after a value are: it was placed on its end.
        std::size_t at = offset;
        if (closer != '\0') {
            if ((what.find("unexpected string literal") != std::string::npos
                 || what.find("unexpected number literal") != std::string::npos)
                && !token.empty() && builder.position() >= token.size())
                at = builder.position() - token.size();
            else if (what.find("unexpected true literal") != std::string::npos || what.find("unexpected false literal") != std::string::npos
                     || what.find("unexpected null literal") != std::string::npos)
                while (at > 0 && at <= text.size() && text[at - 1] >= 'a' && text[at - 1] <= 'z')
                    --at;
        }
        return lineColumn(text, at) + ": not valid JSON: " + parserDetail(what);
    }

    try {
        world = readScene(doc, unknown);
    } catch (const SceneError &e) {
        if (const std::string written = builder.underflowAt(e.place); !written.empty())
            return e.place + ": " + e.rule + " (the file's " + printable(written)
                + " is too close to 0 for a double, which holds it as 0)";
        return e.place + ": " + e.rule;
    }
    return {};
}

// ---------------------------------------------------------------------------------------------
// Writing

constexpr Json::error_handler_t kReplace = Json::error_handler_t::replace;

/// A double as JSON that reads back bit-identical. Whole numbers below 2^53 are written as
/// integers (120, not 120.0), which is exact because every such integer is a double; -0.0 keeps
/// its sign as a float. Everything else uses nlohmann's shortest round-trip form.
OrderedJson number(double v)
{
    constexpr double kTwo53 = 9007199254740992.0;
    if (std::isfinite(v) && v == std::trunc(v) && std::abs(v) < kTwo53 && !(v == 0.0 && std::signbit(v)))
        return OrderedJson(static_cast<std::int64_t>(v));
    return OrderedJson(v);
}

/// Appends the unknown keys kept in `extraJson` to `object`; known keys already there win.
void appendExtras(OrderedJson &object, const std::string &extraJson)
{
    if (extraJson.empty())
        return;
    const OrderedJson extras = OrderedJson::parse(extraJson, nullptr, false);
    if (!extras.is_object())
        return;
    for (const auto &[key, value] : extras.items()) {
        if (!object.contains(key))
            object[key] = value;
    }
}

std::string dumpValue(const OrderedJson &j)
{
    return j.dump(-1, ' ', false, kReplace);
}

/// `{"x": 120, "y": 200}` on one line.
std::string inlineObject(const OrderedJson &object)
{
    std::string out = "{";
    bool first = true;
    for (const auto &[key, value] : object.items()) {
        out += first ? "" : ", ";
        first = false;
        out += dumpValue(OrderedJson(key)) + ": " + dumpValue(value);
    }
    return out + "}";
}

/// One key per line at `indent` + 2 spaces; values compact.
std::string blockObject(const OrderedJson &object, const std::string &indent)
{
    if (object.empty())
        return "{}";
    std::string out = "{\n";
    bool first = true;
    for (const auto &[key, value] : object.items()) {
        out += first ? "" : ",\n";
        first = false;
        out += indent + "  " + dumpValue(OrderedJson(key)) + ": " + dumpValue(value);
    }
    return out + "\n" + indent + "}";
}

/// One element per line.
std::string blockArray(const std::vector<OrderedJson> &items, const std::string &indent)
{
    if (items.empty())
        return "[]";
    std::string out = "[\n";
    for (std::size_t i = 0; i < items.size(); ++i)
        out += indent + "  " + inlineObject(items[i]) + (i + 1 < items.size() ? ",\n" : "\n");
    return out + indent + "]";
}

/// A pretty-printed value at `indent`: nested lines shifted by the indent. Newlines inside JSON
/// text only ever come from the pretty printer (strings escape theirs), so shifting them is safe.
std::string prettyValue(const OrderedJson &value, const std::string &indent)
{
    const std::string text = value.dump(2, ' ', false, kReplace);
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        out += c;
        if (c == '\n')
            out += indent;
    }
    return out;
}

std::string osError(int error)
{
    return std::generic_category().message(error);
}

} // namespace

// -------------------------------------------------------------------------------------------------
// Public functions

namespace {

/// parseInto(), with what it throws said as a rule broken; sets `outOfMemory` when memory ran out.
std::string parseCaught(std::string_view text, World &world, bool &outOfMemory, UnknownKeys *unknown = nullptr)
{
    UnknownKeys ignored;
    try {
        return parseInto(text, world, unknown ? *unknown : ignored);
    } catch (const std::bad_alloc &) {
        outOfMemory = true;
        return "size: not enough memory to read this scene";
    } catch (const std::exception &e) {
        return "scene: cannot be read: " + printable(e.what(), 160);
    }
}

} // namespace

SceneLoad parseScene(std::string_view text, std::string_view source)
{
    SceneLoad result;
    UnknownKeys unknown;
    const std::string error = parseCaught(text, result.world, result.outOfMemory, &unknown);
    if (error.empty()) {
        result.ok = true;
        for (const std::string &line : unknown.lines())
            result.notes.push_back(std::string(source) + ": " + line);
        result.misspeltKeys = unknown.anyMisspelt();
    } else {
        result.world = World();
        result.error = std::string(source) + ": " + error;
    }
    return result;
}

std::string sceneTooLarge(std::string_view what, std::string_view got)
{
    return "size: " + std::string(what) + " must be at most " + std::to_string(kMaxSceneBytes) + " bytes ("
        + std::to_string(kMaxSceneBytes >> 20) + " MiB), got " + std::string(got);
}

SceneRead readSceneText(int fd, std::string &text, int &error)
{
    // In chunks up to one byte past the limit: pipes and devices have no size to check first.
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            error = errno;
            return SceneRead::Failed;
        }
        if (n == 0)
            return SceneRead::Whole;
        text.append(buffer, static_cast<std::size_t>(n));
        if (text.size() > kMaxSceneBytes)
            return SceneRead::TooLarge;
    }
}

SceneLoad loadSceneFile(const std::string &path, std::string_view shownAs)
{
    SceneLoad result;
    const std::string name = shownAs.empty() ? path : std::string(shownAs);
    auto refuse = [&](const std::string &message) {
        result.error = name + ": " + message;
        return result;
    };

    // Opened without blocking: opening a named pipe would otherwise wait for a writer, for ever
    // if none comes. Reads block again (a pipe that is being written is read to its end).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return refuse("cannot open the file: " + osError(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    if (const int flags = ::fcntl(fd, F_GETFL); flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) < 0)
        return refuse("cannot read the file: " + osError(errno));

    struct stat info {};
    if (::fstat(fd, &info) != 0)
        return refuse("cannot read the file: " + osError(errno));
    if (S_ISDIR(info.st_mode))
        return refuse("cannot read the file: it is a folder, not a scene file");
    const auto tooLarge = [&](const std::string &size) {
        return refuse(sceneTooLarge("a scene file", size));
    };
    if (S_ISREG(info.st_mode) && static_cast<std::uint64_t>(info.st_size) > kMaxSceneBytes)
        return tooLarge(std::to_string(info.st_size) + " bytes");

    std::string text;
    try {
        if (S_ISREG(info.st_mode))
            text.reserve(static_cast<std::size_t>(info.st_size));
        int error = 0;
        switch (readSceneText(fd, text, error)) {
        case SceneRead::Whole:
            break;
        case SceneRead::TooLarge:
            return tooLarge("more than that");
        case SceneRead::Failed:
            return refuse("cannot read the file: " + osError(error));
        }
    } catch (const std::bad_alloc &) {
        result.outOfMemory = true;
        return refuse("size: not enough memory to read this file");
    }
    if (text.empty() && S_ISFIFO(info.st_mode))
        return refuse("cannot read the file: it is a named pipe, and nothing was written to it");
    return parseScene(text, name);
}

std::string sceneToJson(const World &world)
{
    OrderedJson stage = OrderedJson::object();
    stage["width"] = number(world.stage.width);
    stage["height"] = number(world.stage.height);
    stage["walls"] = world.stage.walls;
    appendExtras(stage, world.stageExtraJson);

    const Params &p = world.params;
    OrderedJson params = OrderedJson::object();
    params["model"] = std::string(modelName(p.model));
    params["massScale"] = number(p.massScale);
    params["friction"] = number(p.friction);
    params["zeroThreshold"] = number(p.zeroThreshold);
    params["pushScale"] = number(p.pushScale);
    params["frameMs"] = number(p.frameMs);
    params["restitution"] = number(p.restitution);
    params["gravity"] = OrderedJson::array({number(p.gravity.x), number(p.gravity.y)});
    params["substeps"] = p.substeps;
    params["shortCircuit"] = p.shortCircuit;
    appendExtras(params, world.paramsExtraJson);

    std::vector<OrderedJson> marbles;
    marbles.reserve(world.radius.size());
    for (int i = 0; i < world.marbleCount(); ++i) {
        OrderedJson m = OrderedJson::object();
        m["x"] = number(world.position[i].x);
        m["y"] = number(world.position[i].y);
        m["radius"] = number(world.radius[i]);
        m["vx"] = number(world.velocity[i].x);
        m["vy"] = number(world.velocity[i].y);
        const MarbleInfo *info = static_cast<std::size_t>(i) < world.info.size() ? &world.info[i] : nullptr;
        if (info && info->hasMass && static_cast<std::size_t>(i) < world.mass.size())
            m["mass"] = number(world.mass[i]);
        if (info && !info->name.empty())
            m["name"] = info->name;
        if (info && !info->color.empty())
            m["color"] = info->color;
        if (info)
            appendExtras(m, info->extraJson);
        marbles.push_back(std::move(m));
    }

    std::vector<OrderedJson> pins;
    pins.reserve(world.pins.size());
    for (std::size_t j = 0; j < world.pins.size(); ++j) {
        OrderedJson q = OrderedJson::object();
        q["x"] = number(world.pins[j].x);
        q["y"] = number(world.pins[j].y);
        if (j < world.pinExtraJson.size())
            appendExtras(q, world.pinExtraJson[j]);
        pins.push_back(std::move(q));
    }

    std::vector<OrderedJson> pushes;
    pushes.reserve(world.pushes.size());
    for (const Push &push : world.pushes) {
        // The file holds the world as it is now, from its frame 0 (it has no frame number): a
        // push still to come is written as many frames ahead as it is now; one that has acted
        // is left out (read back, it would act again).
        if (push.frame < world.frame)
            continue;
        OrderedJson e = OrderedJson::object();
        e["frame"] = push.frame - world.frame;
        e["marble"] = push.marble;
        e["x"] = number(push.at.x);
        e["y"] = number(push.at.y);
        appendExtras(e, push.extraJson);
        pushes.push_back(std::move(e));
    }

    std::string out = "{\n";
    out += "  \"format\": \"marbles-scene\",\n";
    out += "  \"version\": " + std::to_string(kVersion) + ",\n";
    out += "  \"stage\": " + blockObject(stage, "  ") + ",\n";
    out += "  \"params\": " + blockObject(params, "  ") + ",\n";
    out += "  \"marbles\": " + blockArray(marbles, "  ") + ",\n";
    out += "  \"pins\": " + blockArray(pins, "  ") + ",\n";
    out += "  \"pushes\": " + blockArray(pushes, "  ");
    OrderedJson top = OrderedJson::object();
    appendExtras(top, world.sceneExtraJson);
    for (const auto &[key, value] : top.items()) {
        if (!isSceneKey(key))
            out += ",\n  " + dumpValue(OrderedJson(key)) + ": " + prettyValue(value, "  ");
    }
    out += "\n}\n";
    return out;
}

std::string sceneTextLoadingBack(const World &world, std::string &text)
{
    text = sceneToJson(world);
    World check;
    bool outOfMemory = false;
    return parseCaught(text, check, outOfMemory);
}

std::string saveSceneFile(const World &world, const std::string &path)
{
    // Never write a file this program would refuse to open again.
    std::string text;
    if (std::string error = sceneTextLoadingBack(world, text); !error.empty())
        return path + ": not saved, the scene would not load back: " + error;

    if (std::string error = writeFileWhole(path, text, SpecialFiles::Refuse); !error.empty())
        return path + ": cannot save: " + error;
    return {};
}

std::string validateParams(const Params &p)
{
    auto check = [](const char *key, const std::string &rule, double v) {
        return rule.empty() ? std::string() : "params." + std::string(key) + ": " + rule + ", got " + formatNumber(v);
    };
    std::string error;
    ModelKind known;
    if (!parseModelName(modelName(p.model), known) || known != p.model)
        return "params.model: must be \"book\", \"impulse\" or \"exact\", got "
            + std::to_string(static_cast<int>(p.model));
    if (!(error = check("massScale", rulePositive(p.massScale), p.massScale)).empty())
        return error;
    if (!(error = check("friction", ruleNonNegative(p.friction), p.friction)).empty())
        return error;
    if (!(error = check("zeroThreshold", ruleNonNegative(p.zeroThreshold), p.zeroThreshold)).empty())
        return error;
    if (!(error = check("pushScale", ruleFinite(p.pushScale), p.pushScale)).empty())
        return error;
    if (!(error = check("frameMs", rulePositive(p.frameMs), p.frameMs)).empty())
        return error;
    if (!(error = check("restitution", ruleUnitInterval(p.restitution), p.restitution)).empty())
        return error;
    if (!isFinite(p.gravity))
        return "params.gravity: must be 2 finite numbers, got [" + formatNumber(p.gravity.x) + ", "
            + formatNumber(p.gravity.y) + "]";
    if (std::string rule = ruleSubsteps(p.substeps); !rule.empty())
        return "params.substeps: " + rule + ", got " + std::to_string(p.substeps);
    return check("friction", ruleFrictionForModel(p.friction, p.model), p.friction);
}

namespace {

/// Reads a whole decimal number the way JSON and C write it, whatever the locale; "" or the rule broken.
std::string parseDouble(std::string_view text, double &out)
{
    if (text.size() > 1 && text.front() == '+' && text[1] != '-') // "+-1" is no number
        text.remove_prefix(1);
    if (text.empty())
        return "must be a number";
    const auto result = std::from_chars(text.data(), text.data() + text.size(), out);
    if (result.ptr != text.data() + text.size()) {
        // A decimal comma, as a German or French teacher writes one ("0,5"), is named with the
        // number meant (a helper's finding: "must be a number" alone did not say what was wrong).
        // Not where it may group thousands ("1,000": 1000 to one teacher, 1.0 to another), as the
        // window's fields refuse it (RefusingSpinBox::marksIn(), the same rule on QStrings).
        if (std::count(text.begin(), text.end(), ',') == 1) {
            const std::size_t comma = text.find(',');
            const std::string_view whole = text.substr(0, comma);
            const std::string_view part = text.substr(comma + 1);
            const std::string_view magnitude = !whole.empty() && (whole[0] == '-' || whole[0] == '+') ? whole.substr(1) : whole;
            const auto digits = [](std::string_view s) {
                return !s.empty() && std::all_of(s.begin(), s.end(), isDigit);
            };
            if (digits(magnitude) && magnitude.size() <= 3 && magnitude[0] != '0' && digits(part) && part.size() == 3)
                return "must be a number written without group separators (" + std::string(text) + " can be read two ways: "
                    + std::string(whole) + std::string(part) + " or " + std::string(whole) + "." + std::string(part) + ")";
            std::string point(text);
            point[comma] = '.';
            double meant = 0.0;
            const auto again = std::from_chars(point.data(), point.data() + point.size(), meant);
            if (again.ptr == point.data() + point.size() && again.ec == std::errc())
                return "must be a number with a decimal point: " + point + ", not " + std::string(text);
        }
        return "must be a number";
    }
    if (result.ec == std::errc::result_out_of_range) {
        // Too close to 0 for a double ("1e-400") reads as its nearest double, 0, as JSON's in a
        // scene file does ("friction": 1e-400 loaded, --set friction=1e-400 was refused); too
        // large is refused.
        long double wide = 0.0L;
        const auto again = std::from_chars(text.data(), text.data() + text.size(), wide);
        if (again.ec != std::errc() || !(std::abs(wide) < 1.0L))
            return "must be a number within the range of a double";
        out = static_cast<double>(wide);
        return {};
    }
    return result.ec == std::errc() ? std::string() : std::string("must be a number");
}

bool parseBool(std::string_view text, bool &out)
{
    if (text == "true" || text == "1") {
        out = true;
        return true;
    }
    if (text == "false" || text == "0") {
        out = false;
        return true;
    }
    return false;
}

} // namespace

std::string setParam(World &world, std::string_view key, std::string_view value)
{
    const std::string head = printable(key) + "=" + printable(value) + ": ";
    Params &p = world.params;

    // A number with its one-field rule; `rule` returns "" or the rule broken.
    auto setNumber = [&](double &target, std::string (*rule)(double)) -> std::string {
        double v = 0.0;
        if (std::string broken = parseDouble(value, v); !broken.empty())
            return head + broken;
        if (std::string broken = rule(v); !broken.empty())
            return head + broken;
        target = v;
        return {};
    };
    auto boolean = [&](bool &target) -> std::string {
        if (!parseBool(value, target))
            return head + "must be true, false, 1 or 0";
        return {};
    };

    if (key == "model") {
        if (!parseModelName(value, p.model))
            return head + "must be \"book\", \"impulse\" or \"exact\"";
        return {};
    }
    if (key == "massScale") {
        double scale = p.massScale;
        if (std::string error = setNumber(scale, rulePositive); !error.empty())
            return error;
        // Checked before it is set, marble by marble (a copy of the world to try it on was a
        // 100k crowd's whole state, on top of the caller's own trial copy).
        for (int i = 0; i < world.marbleCount(); ++i) {
            const std::string broken = world.info[static_cast<std::size_t>(i)].hasMass
                ? std::string()
                : derivedMassRule(scale, world.radius[static_cast<std::size_t>(i)]);
            if (!broken.empty())
                return head + "marble " + std::to_string(i) + ": " + broken;
        }
        world.setMassScale(scale);
        return {};
    }
    if (key == "friction")
        return setNumber(p.friction, ruleNonNegative);
    if (key == "zeroThreshold")
        return setNumber(p.zeroThreshold, ruleNonNegative);
    if (key == "pushScale")
        return setNumber(p.pushScale, ruleFinite);
    if (key == "frameMs")
        return setNumber(p.frameMs, rulePositive);
    if (key == "restitution")
        return setNumber(p.restitution, ruleUnitInterval);
    if (key == "gravity") {
        const std::size_t comma = value.find(',');
        if (comma == std::string_view::npos)
            return head + "must be two numbers \"x,y\"";
        // Each side's own rule: "1e400,0" is a number too large, as friction=1e400 says.
        Vec2 g;
        for (const auto &[side, text] : {std::pair{&g.x, value.substr(0, comma)}, std::pair{&g.y, value.substr(comma + 1)}}) {
            if (std::string rule = parseDouble(text, *side); !rule.empty())
                // (A comma too many is read as three numbers, not as a decimal comma.)
                return head + (rule.starts_with("must be a number") && !rule.ends_with("double")
                                   ? std::string("must be two numbers \"x,y\"")
                                                         : (side == &g.x ? "x " : "y ") + rule);
        }
        if (!isFinite(g))
            return head + "must be two finite numbers";
        p.gravity = g;
        return {};
    }
    if (key == "substeps") {
        // A whole number as the loader takes one in a file ("8", "4.0", "1e3"); one beyond int64
        // (99999999999999999999) is past the rule's bound all the same, not "no integer".
        double whole = 0.0;
        if (!parseDouble(value, whole).empty() || whole != std::trunc(whole))
            return head + "must be an integer";
        const std::int64_t n = whole >= 9.2e18 ? std::numeric_limits<std::int64_t>::max()
            : whole <= -9.2e18                 ? std::numeric_limits<std::int64_t>::min()
                                               : static_cast<std::int64_t>(whole);
        if (std::string broken = ruleSubsteps(n); !broken.empty())
            return head + broken;
        p.substeps = static_cast<int>(n);
        return {};
    }
    if (key == "shortCircuit")
        return boolean(p.shortCircuit);
    if (key == "width")
        return setNumber(world.stage.width, rulePositive);
    if (key == "height")
        return setNumber(world.stage.height, rulePositive);
    if (key == "walls")
        return boolean(world.stage.walls);
    return head + "unknown key; the keys are model, massScale, friction, zeroThreshold, pushScale, frameMs, "
                  "restitution, gravity, substeps, shortCircuit, width, height and walls";
}

} // namespace marbles
