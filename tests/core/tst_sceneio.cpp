// Scene files (INTERFACES.md, "Scene file"): every refusal rule, malformed and hostile input,
// defaults, exact round trips of numbers and unknown keys, atomic saving, and --set.

#include "core/presets.h"
#include "core/sceneio.h"
#include "core/world.h"

#include <QtTest>

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>

using namespace marbles;

namespace {

using Json = nlohmann::json;

constexpr const char *kSource = "demo.marbles.json";

std::string_view view(const QByteArray &bytes)
{
    return {bytes.constData(), static_cast<std::size_t>(bytes.size())};
}

QString q(const std::string &s)
{
    return QString::fromStdString(s);
}

/// A valid scene with every section filled: 4 marbles (so marbles[3] exists), 1 pin, 1 push.
Json baseScene()
{
    return Json::parse(R"({
        "format": "marbles-scene",
        "version": 1,
        "stage": {"width": 800, "height": 600, "walls": true},
        "params": {"model": "book", "massScale": 1.25, "friction": 0.1, "zeroThreshold": 0.01,
                   "pushScale": 10, "frameMs": 20, "restitution": 1.0, "gravity": [0, 0],
                   "substeps": 1, "shortCircuit": false},
        "marbles": [
            {"x": 100, "y": 100, "radius": 20, "vx": 1, "vy": 0, "name": "a", "color": "#ff0000"},
            {"x": 200, "y": 100, "radius": 20, "mass": 3},
            {"x": 300, "y": 100, "radius": 20, "vy": 0.5},
            {"x": 400, "y": 100, "radius": 20}
        ],
        "pins": [{"x": 250, "y": 300}],
        "pushes": [{"frame": 0, "marble": 0, "x": 90, "y": 100}]
    })");
}

QByteArray dumpScene(const Json &j)
{
    return QByteArray::fromStdString(j.dump());
}

/// baseScene() with the value at `pointer` replaced by `value` (JSON text), or removed when empty.
QByteArray patchedScene(const QString &pointer, const QByteArray &value)
{
    Json doc = baseScene();
    const Json::json_pointer where(pointer.toStdString());
    if (value.isEmpty())
        doc[where.parent_pointer()].erase(where.back());
    else
        doc[where] = Json::parse(view(value));
    return dumpScene(doc);
}

/// Ten megabytes of reproducible random bytes.
QByteArray garbage()
{
    QRandomGenerator random(20261123);
    QByteArray bytes(10 * 1024 * 1024, '\0');
    for (char &c : bytes)
        c = static_cast<char>(random.bounded(256));
    return bytes;
}

/// The value of one --set key in the world, as text, to compare with what was set.
QString setting(const World &w, const QString &key)
{
    const auto num = [](double v) { return QString::number(v, 'g', 17); };
    const auto flag = [](bool b) { return QString(b ? "true" : "false"); };
    const Params &p = w.params;
    if (key == "model")
        return q(std::string(modelName(p.model)));
    if (key == "massScale")
        return num(p.massScale);
    if (key == "friction")
        return num(p.friction);
    if (key == "zeroThreshold")
        return num(p.zeroThreshold);
    if (key == "pushScale")
        return num(p.pushScale);
    if (key == "frameMs")
        return num(p.frameMs);
    if (key == "restitution")
        return num(p.restitution);
    if (key == "gravity")
        return num(p.gravity.x) + "," + num(p.gravity.y);
    if (key == "substeps")
        return QString::number(p.substeps);
    if (key == "shortCircuit")
        return flag(p.shortCircuit);
    if (key == "width")
        return num(w.stage.width);
    if (key == "height")
        return num(w.stage.height);
    if (key == "walls")
        return flag(w.stage.walls);
    return "?";
}

/// Every double, integer and string of two worlds agrees bit for bit; names the first difference.
QString difference(const World &a, const World &b)
{
    auto vecs = [](const std::vector<Vec2> &u, const std::vector<Vec2> &v) {
        if (u.size() != v.size())
            return false;
        for (std::size_t i = 0; i < u.size(); ++i) {
            if (!sameBits(u[i].x, v[i].x) || !sameBits(u[i].y, v[i].y))
                return false;
        }
        return true;
    };
    auto scalars = [](const std::vector<double> &u, const std::vector<double> &v) {
        if (u.size() != v.size())
            return false;
        for (std::size_t i = 0; i < u.size(); ++i) {
            if (!sameBits(u[i], v[i]))
                return false;
        }
        return true;
    };
    const Params &p = a.params;
    const Params &r = b.params;
    if (!sameBits(a.stage.width, b.stage.width) || !sameBits(a.stage.height, b.stage.height)
        || a.stage.walls != b.stage.walls)
        return "stage";
    if (p.model != r.model || !sameBits(p.massScale, r.massScale) || !sameBits(p.friction, r.friction)
        || !sameBits(p.zeroThreshold, r.zeroThreshold) || !sameBits(p.pushScale, r.pushScale)
        || !sameBits(p.frameMs, r.frameMs) || !sameBits(p.restitution, r.restitution)
        || !sameBits(p.gravity.x, r.gravity.x) || !sameBits(p.gravity.y, r.gravity.y) || p.substeps != r.substeps
        || p.shortCircuit != r.shortCircuit)
        return "params";
    if (!vecs(a.position, b.position))
        return "position";
    if (!vecs(a.velocity, b.velocity))
        return "velocity";
    if (!scalars(a.radius, b.radius))
        return "radius";
    if (!scalars(a.mass, b.mass))
        return "mass";
    if (a.info != b.info)
        return "info";
    if (!vecs(a.pins, b.pins) || a.pinExtraJson != b.pinExtraJson)
        return "pins";
    if (a.pushes.size() != b.pushes.size())
        return "pushes";
    for (std::size_t i = 0; i < a.pushes.size(); ++i) {
        const Push &u = a.pushes[i];
        const Push &v = b.pushes[i];
        if (u.frame != v.frame || u.marble != v.marble || !sameBits(u.at.x, v.at.x) || !sameBits(u.at.y, v.at.y) || u.extraJson != v.extraJson)
            return "pushes";
    }
    if (a.paramsExtraJson != b.paramsExtraJson || a.stageExtraJson != b.stageExtraJson
        || a.sceneExtraJson != b.sceneExtraJson)
        return "extras";
    return {};
}

QStringList folderEntries(const QString &path)
{
    return QDir(path).entryList(QDir::AllEntries | QDir::Hidden | QDir::System | QDir::NoDotAndDotDot);
}

} // namespace

class TestSceneIo : public QObject {
    Q_OBJECT

private slots:
    void baseSceneIsValid();
    void invalidScene_data();
    void invalidScene();
    void malformed_data();
    void malformed();
    void manyKeysLoad();
    void placeOfSyntaxError_data();
    void placeOfSyntaxError();
    void garbageIsRefusedQuickly();
    void deepButAllowedNesting();
    void memoryBudget();
    void largeSceneRoundTrips();
    void utf8ByteOrderMarkIsAccepted();
    void defaults_data();
    void defaults();
    void interfacesExample();
    void frictionByModel_data();
    void frictionByModel();
    void wholeNumbersAsFloats();
    void roundTripWorld_data();
    void roundTripWorld();
    void roundTripText_data();
    void roundTripText();
    void unknownKeysSurvive_data();
    void unknownKeysSurvive();
    void unknownKeysAreNoted();
    void savedLayout();
    void massWrittenOnlyWhenExplicit();
    void saveIntoMissingFolder();
    void saveReplacesCompletely();
    void saveKeepsPermissions();
    void saveRefusesWhatWouldNotLoad_data();
    void saveRefusesWhatWouldNotLoad();
    void saveOverFolderFails();
    void savedMidRunRunsOnAsTheWorld();
    void loadFileErrors_data();
    void loadFileErrors();
    void loadRefusesHugeFileBeforeReading();
    void loadFileNamesFileAsGiven();
    void derivedMassUnderflowIsRefused();
    void setParamAccepts_data();
    void setParamAccepts();
    void setParamRejects_data();
    void setParamRejects();
    void setMassScaleRefreshesDerivedMasses();
    void validateParams_data();
    void validateParams();
    void printableTextIsOneLine_data();
    void printableTextIsOneLine();
};

void TestSceneIo::baseSceneIsValid()
{
    const SceneLoad load = parseScene(view(dumpScene(baseScene())), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(load.world.marbleCount(), 4);
}

void TestSceneIo::invalidScene_data()
{
    QTest::addColumn<QString>("pointer");
    QTest::addColumn<QByteArray>("value"); // JSON text; empty removes the key
    QTest::addColumn<QString>("place");
    QTest::addColumn<QString>("rule");

    QTest::addRow("format wrong") << "/format" << QByteArray(R"("marbles")") << "format"
                                  << R"(must be "marbles-scene", got string "marbles")";
    QTest::addRow("format missing") << "/format" << QByteArray() << "format" << R"(is required and must be "marbles-scene")";
    QTest::addRow("format number") << "/format" << QByteArray("1") << "format" << R"(must be "marbles-scene", got number 1)";
    QTest::addRow("version missing") << "/version" << QByteArray() << "version" << "is required and must be 1";
    QTest::addRow("version unknown") << "/version" << QByteArray("2") << "version" << "must be 1 (the only version this program reads), got number 2";
    QTest::addRow("version 1.5") << "/version" << QByteArray("1.5") << "version" << "must be 1 (the only version this program reads), got number 1.5";
    QTest::addRow("version string") << "/version" << QByteArray(R"("1")") << "version" << R"(must be 1 (the only version this program reads), got string "1")";

    QTest::addRow("stage not object") << "/stage" << QByteArray("[800, 600]") << "stage" << "must be an object, got array of 2";
    QTest::addRow("stage width zero") << "/stage/width" << QByteArray("0") << "stage.width" << "must be > 0, got 0";
    QTest::addRow("stage width -0") << "/stage/width" << QByteArray("-0.0") << "stage.width" << "must be > 0, got -0";
    QTest::addRow("stage height negative") << "/stage/height" << QByteArray("-600") << "stage.height" << "must be > 0, got -600";
    QTest::addRow("stage width string") << "/stage/width" << QByteArray(R"("800")") << "stage.width" << R"(must be a number, got string "800")";
    QTest::addRow("walls number") << "/stage/walls" << QByteArray("1") << "stage.walls" << "must be true or false, got number 1";

    QTest::addRow("params not object") << "/params" << QByteArray(R"("fast")") << "params" << R"(must be an object, got string "fast")";
    QTest::addRow("model unknown") << "/params/model" << QByteArray(R"("verlet")") << "params.model"
                                   << R"(must be "book", "impulse" or "exact", got string "verlet")";
    QTest::addRow("model number") << "/params/model" << QByteArray("0") << "params.model"
                                  << R"(must be "book", "impulse" or "exact", got number 0)";
    QTest::addRow("model case") << "/params/model" << QByteArray(R"("Book")") << "params.model"
                                << R"(must be "book", "impulse" or "exact", got string "Book")";
    QTest::addRow("massScale zero") << "/params/massScale" << QByteArray("0") << "params.massScale" << "must be > 0, got 0";
    QTest::addRow("massScale negative") << "/params/massScale" << QByteArray("-1.25") << "params.massScale" << "must be > 0, got -1.25";
    // A derived mass that is no number (it was taken: infinite masses, lost momentum).
    QTest::addRow("massScale overflows a mass") << "/params/massScale" << QByteArray("1e308") << "marbles[0]"
                                                << "its mass massScale x radius = 1e+308 x 20 is beyond what a double can hold: give the marble a mass, or change massScale";
    QTest::addRow("friction negative") << "/params/friction" << QByteArray("-1") << "params.friction" << "must be >= 0, got -1";
    QTest::addRow("friction string") << "/params/friction" << QByteArray(R"("0.1")") << "params.friction" << R"(must be a number, got string "0.1")";
    QTest::addRow("zeroThreshold negative") << "/params/zeroThreshold" << QByteArray("-0.01") << "params.zeroThreshold" << "must be >= 0, got -0.01";
    QTest::addRow("pushScale array") << "/params/pushScale" << QByteArray("[10]") << "params.pushScale" << "must be a number, got array of 1";
    QTest::addRow("frameMs zero") << "/params/frameMs" << QByteArray("0") << "params.frameMs" << "must be > 0, got 0";
    QTest::addRow("restitution negative") << "/params/restitution" << QByteArray("-0.1") << "params.restitution" << "must be between 0 and 1, got -0.1";
    QTest::addRow("restitution above 1") << "/params/restitution" << QByteArray("1.5") << "params.restitution" << "must be between 0 and 1, got 1.5";
    QTest::addRow("gravity three numbers") << "/params/gravity" << QByteArray("[0, 1, 2]") << "params.gravity"
                                           << "must be an array of 2 numbers [x, y], got array of 3";
    QTest::addRow("gravity object") << "/params/gravity" << QByteArray(R"({"x": 0, "y": 1})") << "params.gravity"
                                    << "must be an array of 2 numbers [x, y], got object";
    QTest::addRow("gravity string element") << "/params/gravity" << QByteArray(R"([0, "1"])") << "params.gravity[1]"
                                            << R"(must be a number, got string "1")";
    QTest::addRow("substeps zero") << "/params/substeps" << QByteArray("0") << "params.substeps" << "must be >= 1, got 0";
    QTest::addRow("substeps negative") << "/params/substeps" << QByteArray("-3") << "params.substeps" << "must be >= 1, got -3";
    QTest::addRow("substeps fraction") << "/params/substeps" << QByteArray("1.5") << "params.substeps" << "must be an integer, got 1.5";
    QTest::addRow("substeps huge") << "/params/substeps" << QByteArray("1e12") << "params.substeps" << "must be <= 1000000, got 1000000000000";
    QTest::addRow("substeps beyond int64") << "/params/substeps" << QByteArray("18446744073709551615") << "params.substeps"
                                           << "must be <= 1000000, got 18446744073709551615";
    QTest::addRow("substeps boolean") << "/params/substeps" << QByteArray("true") << "params.substeps" << "must be an integer, got boolean true";
    QTest::addRow("shortCircuit string") << "/params/shortCircuit" << QByteArray(R"("yes")") << "params.shortCircuit"
                                         << R"(must be true or false, got string "yes")";
    QTest::addRow("friction 1 exact") << "/params" << QByteArray(R"({"model": "exact", "friction": 1})") << "params.friction"
                                      << "must be < 1 for the exact model, got 1";
    QTest::addRow("friction 1.5 exact") << "/params" << QByteArray(R"({"model": "exact", "friction": 1.5})") << "params.friction"
                                        << "must be < 1 for the exact model, got 1.5";
    QTest::addRow("friction 1 impulse") << "/params" << QByteArray(R"({"model": "impulse", "friction": 1})") << "params.friction"
                                        << "must be < 1 for the impulse model, got 1";

    QTest::addRow("marbles not array") << "/marbles" << QByteArray("{}") << "marbles" << "must be an array, got object";
    QTest::addRow("marble not object") << "/marbles/1" << QByteArray("5") << "marbles[1]" << "must be an object, got number 5";
    QTest::addRow("x string") << "/marbles/0/x" << QByteArray(R"("12")") << "marbles[0].x" << R"(must be a number, got string "12")";
    QTest::addRow("vy null") << "/marbles/2/vy" << QByteArray("null") << "marbles[2].vy" << "must be a number, got null";
    QTest::addRow("radius negative") << "/marbles/3/radius" << QByteArray("-5") << "marbles[3].radius" << "must be > 0, got -5";
    QTest::addRow("radius zero") << "/marbles/3/radius" << QByteArray("0") << "marbles[3].radius" << "must be > 0, got 0";
    QTest::addRow("mass zero") << "/marbles/1/mass" << QByteArray("0") << "marbles[1].mass" << "must be > 0, got 0";
    QTest::addRow("mass negative") << "/marbles/1/mass" << QByteArray("-3.5") << "marbles[1].mass" << "must be > 0, got -3.5";
    QTest::addRow("name number") << "/marbles/0/name" << QByteArray("7") << "marbles[0].name" << "must be a string, got number 7";
    QTest::addRow("color word") << "/marbles/0/color" << QByteArray(R"("red")") << "marbles[0].color"
                                << R"(must be a colour "#rrggbb", got string "red")";
    QTest::addRow("color short form") << "/marbles/0/color" << QByteArray(R"("#f00")") << "marbles[0].color"
                                      << R"(must be a colour "#rrggbb", got string "#f00")";
    QTest::addRow("color bad digit") << "/marbles/0/color" << QByteArray(R"("#12345g")") << "marbles[0].color"
                                     << R"(must be a colour "#rrggbb", got string "#12345g")";
    QTest::addRow("color with alpha") << "/marbles/0/color" << QByteArray(R"("#12345678")") << "marbles[0].color"
                                      << R"(must be a colour "#rrggbb", got string "#12345678")";

    QTest::addRow("pins not array") << "/pins" << QByteArray("true") << "pins" << "must be an array, got boolean true";
    QTest::addRow("pin y boolean") << "/pins/0/y" << QByteArray("true") << "pins[0].y" << "must be a number, got boolean true";

    QTest::addRow("pushes not array") << "/pushes" << QByteArray("{}") << "pushes" << "must be an array, got object";
    QTest::addRow("push marble missing") << "/pushes/0/marble" << QByteArray("4") << "pushes[0].marble"
                                         << "must name an existing marble (0 to 3), got 4";
    QTest::addRow("push marble negative") << "/pushes/0/marble" << QByteArray("-1") << "pushes[0].marble"
                                          << "must name an existing marble (0 to 3), got -1";
    // Beyond int64: no marble either (a helper's finding: "must be <= 9223372036854775807").
    QTest::addRow("push marble beyond int64") << "/pushes/0/marble" << QByteArray("1000000000000000000000000000000")
                                              << "pushes[0].marble" << "must name an existing marble (0 to 3), got 1e+30";
    QTest::addRow("push marble beyond uint64") << "/pushes/0/marble" << QByteArray("18446744073709551615")
                                               << "pushes[0].marble"
                                               << "must name an existing marble (0 to 3), got 18446744073709551615";
    QTest::addRow("push marble below int64") << "/pushes/0/marble" << QByteArray("-1e19") << "pushes[0].marble"
                                             << "must name an existing marble (0 to 3), got -1e+19";
    QTest::addRow("push marble fraction") << "/pushes/0/marble" << QByteArray("0.5") << "pushes[0].marble"
                                          << "must be an integer, got 0.5";
    QTest::addRow("push marble string") << "/pushes/0/marble" << QByteArray(R"("0")") << "pushes[0].marble"
                                        << R"(must be an integer, got string "0")";
    QTest::addRow("push with no marbles") << "/marbles" << QByteArray("[]") << "pushes[0].marble"
                                          << "must name an existing marble, but the scene has none, got 0";
    QTest::addRow("push frame negative") << "/pushes/0/frame" << QByteArray("-1") << "pushes[0].frame" << "must be >= 0, got -1";
    QTest::addRow("push frame fraction") << "/pushes/0/frame" << QByteArray("2.5") << "pushes[0].frame" << "must be an integer, got 2.5";
    QTest::addRow("push frame huge") << "/pushes/0/frame" << QByteArray("1e19") << "pushes[0].frame"
                                     << "must be <= 9223372036854775807, got 1e+19";
    QTest::addRow("push x string") << "/pushes/0/x" << QByteArray(R"("90")") << "pushes[0].x" << R"(must be a number, got string "90")";
}

void TestSceneIo::invalidScene()
{
    QFETCH(QString, pointer);
    QFETCH(QByteArray, value);
    QFETCH(QString, place);
    QFETCH(QString, rule);

    const SceneLoad load = parseScene(view(patchedScene(pointer, value)), kSource);
    QVERIFY(!load.ok);
    QCOMPARE(q(load.error), QString(kSource) + ": " + place + ": " + rule);
    QCOMPARE(load.world.marbleCount(), 0); // refused whole
}

void TestSceneIo::malformed_data()
{
    QTest::addColumn<QByteArray>("text");
    QTest::addColumn<QString>("place"); // the message starts with source + ": " + place
    QTest::addColumn<QString>("rule");  // and contains this

    const QByteArray base = dumpScene(baseScene());
    QTest::addRow("empty") << QByteArray() << "line 1, column 1" << "the text is empty";
    QTest::addRow("only whitespace") << QByteArray(" \n\t\r\n ") << "line 1, column 1" << "the text is empty";
    QTest::addRow("only a byte order mark") << QByteArray("\xEF\xBB\xBF") << "line 1, column 1" << "the text is empty";
    QTest::addRow("not JSON") << QByteArray("hello") << "line 1, column 1" << "not valid JSON";
    QTest::addRow("truncated") << base.left(base.size() / 2) << "line 1, column " << "not valid JSON";
    QTest::addRow("truncated after colon") << QByteArray(R"({"format": "marbles-scene", "version":)") << "line 1, column "
                                           << "not valid JSON";
    QTest::addRow("trailing garbage") << base + " xyz" << "line 1, column " << "expected end of input";
    QTest::addRow("two objects") << base + base << "line 1, column " << "expected end of input";
    QTest::addRow("comment") << "// scene\n" + base << "line 1, column 1" << "not valid JSON";
    QTest::addRow("single quotes") << QByteArray("{'format': 'marbles-scene'}") << "line 1, column 2" << "not valid JSON";
    QTest::addRow("trailing comma") << QByteArray(R"({"format": "marbles-scene", "version": 1,})") << "line 1, column "
                                    << "not valid JSON";
    QTest::addRow("NaN literal") << QByteArray(R"({"format": "marbles-scene", "version": 1, "params": {"friction": NaN}})")
                                 << "line 1, column " << "not valid JSON";
    QTest::addRow("NUL byte") << QByteArray("{\"format\"\0: 1}", 14) << "line 1, column 10" << "a NUL byte";
    // The parser took a NUL for the end of the text: what followed was never read.
    QTest::addRow("NUL after the object") << base + QByteArray("\0garbage{{{", 11) << "line " << "a NUL byte (0x00)";
    QTest::addRow("NUL first") << QByteArray("\0", 1) + base << "line 1, column 1" << "a NUL byte";
    QTest::addRow("broken UTF-8 in a string")
        << QByteArray("{\"format\": \"marbles-scene\", \"version\": 1, \"marbles\": [{\"name\": \"\xC3\x28\"}]}")
        << "line 1, column " << "not valid JSON";
    QTest::addRow("UTF-16 little endian") << QByteArray("\xFF\xFE{\0}\0", 6) << "line 1, column 1" << "UTF-16";
    QTest::addRow("UTF-16 big endian") << QByteArray("\xFE\xFF\0{\0}", 6) << "line 1, column 1" << "UTF-16";
    QTest::addRow("top level array") << QByteArray("[]") << "top level" << "must be a JSON object (a scene), got array of 0";
    QTest::addRow("top level number") << QByteArray("42") << "top level" << "must be a JSON object (a scene), got number 42";
    QTest::addRow("top level string") << QByteArray(R"("scene")") << "top level" << R"(must be a JSON object (a scene), got string "scene")";

    // JSON allows numbers no double can hold; nlohmann refuses them while parsing, and the
    // message still names the place.
    // A key given twice: the parser kept the last value without a word.
    QTest::addRow("friction twice") << QByteArray(R"({"format": "marbles-scene", "version": 1, "params": {"friction": 0.1, "friction": 0.3}})")
                                    << "params.friction" << "is given twice in the same object: keep one of them";
    QTest::addRow("format twice") << QByteArray(R"({"format": "nope", "format": "marbles-scene", "version": 1})") << "format"
                                  << "is given twice";
    QTest::addRow("a marble's x twice")
        << QByteArray(R"({"format": "marbles-scene", "version": 1, "marbles": [{"x": 50, "y": 50}, {"x": 90, "y": 50, "x": 91}]})")
        << "marbles[1].x" << "is given twice";
    // Too small for a double: read as 0, and quoted as written when it breaks a rule.
    QTest::addRow("subnormal mass")
        << QByteArray(R"({"format": "marbles-scene", "version": 1, "marbles": [{"x": 50, "y": 50, "mass": 1e-320}]})")
        << "marbles[0].mass" << "must be at least 5.562684646268003e-309, whose 1 / m a push and a collision divide by, got 1e-320";
    QTest::addRow("1e-400 radius")
        << QByteArray(R"({"format": "marbles-scene", "version": 1, "marbles": [{"x": 50, "y": 50, "radius": 1e-400}]})")
        << "marbles[0].radius" << "must be > 0, got 0 (the file's 1e-400 is too close to 0 for a double, which holds it as 0)";
    QTest::addRow("1e999 radius")
        << QByteArray(R"({"format": "marbles-scene", "version": 1, "marbles": [{"x": 1}, {"x": 1, "radius": 1e999}]})")
        << "marbles[1].radius: must" << "must be a finite number, got 1e999 (line 1, column 84)";
    QTest::addRow("-1e999 friction")
        << QByteArray("{\"format\": \"marbles-scene\", \"version\": 1,\n \"params\": {\"friction\": -1e999}}")
        << "params.friction: must" << "must be a finite number, got -1e999 (line 2, column 25)";
    QTest::addRow("1e999 in gravity") << QByteArray(R"({"format": "marbles-scene", "version": 1, "params": {"gravity": [0, 1E+999]}})")
                                      << "params.gravity[1]: must" << "must be a finite number, got 1E+999 (line 1, column ";
    QTest::addRow("1e999 in an unknown key") << QByteArray(R"({"format": "marbles-scene", "version": 1, "note": [[1], [2, 3e400]]})")
                                             << "note[1][1]: must" << "must be a finite number, got 3e400 (line 1, column ";
    QTest::addRow("1e999 alone") << QByteArray("1e999") << "value: must" << "must be a finite number, got 1e999 (line 1, column 1)";

    const QByteArray deep = QByteArray(R"({"format": "marbles-scene", "version": 1, "note": )") + QByteArray(100000, '[')
        + QByteArray(100000, ']') + "}";
    QTest::addRow("100000 levels of nesting") << deep << "line 1, column 306" << "nested deeper than 256 levels";
    QTest::addRow("100000 unclosed levels") << QByteArray(100000, '{') << "line 1, column 257" << "nested deeper than 256 levels";
    QTest::addRow("10 MB of garbage") << garbage() << "line 1, column " << "not valid JSON";
}

void TestSceneIo::malformed()
{
    QFETCH(QByteArray, text);
    QFETCH(QString, place);
    QFETCH(QString, rule);

    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY(!load.ok);
    const QString error = q(load.error);
    QVERIFY2(error.startsWith(QString(kSource) + ": " + place), qPrintable(error));
    QVERIFY2(error.contains(rule), qPrintable(error));
    QVERIFY2(!error.contains('\n'), qPrintable(error)); // one line
    QVERIFY2(error.size() < 400, qPrintable(error));    // and a readable one
}

void TestSceneIo::manyKeysLoad()
{
    // Keys are unique per object, not per file; an extra object of 300 keys loads (the check for a
    // key given twice looks at an object's first 256), and so does one with a repeat past those.
    QByteArray extra = "{";
    for (int k = 0; k < 300; ++k)
        extra += (k ? ", \"" : "\"") + QByteArray::number(k) + "\": " + QByteArray::number(k);
    const QByteArray text = R"({"format": "marbles-scene", "version": 1, "note": )" + extra
        + R"(, "0": 1}, "marbles": [{"x": 50, "y": 50, "name": "a"}, {"x": 90, "y": 50, "name": "b"}]})";
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(load.world.marbleCount(), 2);
}

void TestSceneIo::placeOfSyntaxError_data()
{
    QTest::addColumn<QByteArray>("text");
    QTest::addColumn<QString>("message");

    QTest::addRow("bad literal on line 3")
        << QByteArray("{\n  \"format\": \"marbles-scene\",\n  \"version\": x\n}")
        << R"(demo.marbles.json: line 3, column 14: not valid JSON: a text without its double quotes (x): write "x")";
    QTest::addRow("missing comma on line 2")
        << QByteArray("{\"format\": \"marbles-scene\"\n \"version\": 1}")
        << R"(demo.marbles.json: line 2, column 2: not valid JSON: a text in double quotes where a ',' or the '}' should come (a comma missing?))";
    QTest::addRow("unterminated string")
        << QByteArray("{\"format\": \"marbles-scene")
        << R"(demo.marbles.json: line 1, column 26: not valid JSON: a text without its closing double quote (last read: '"marbles-scene'))";
    QTest::addRow("after a byte order mark")
        << QByteArray("\xEF\xBB\xBF{]")
        << R"(demo.marbles.json: line 1, column 2: not valid JSON: ']' where a key in double quotes should come)";
    // A teacher's slips by hand, in words (nlohmann's "syntax error while parsing object key -
    // unexpected '}'; expected string literal" said nothing of a comma).
    QTest::addRow("comma too many")
        << QByteArray("{\"format\": \"marbles-scene\", \"version\": 1,}")
        << R"(demo.marbles.json: line 1, column 42: not valid JSON: a '}' right after a ',' (a comma too many?))";
    QTest::addRow("comma too many in a list")
        << QByteArray("{\"format\": \"marbles-scene\", \"version\": 1, \"pins\": [{\"x\": 1},]}")
        << R"(demo.marbles.json: line 1, column 61: not valid JSON: a ']' right after a ',' (a comma too many?))";
    QTest::addRow("comma missing in a list")
        << QByteArray("[1 2]") << R"(demo.marbles.json: line 1, column 4: not valid JSON: a number where a ',' or the ']' should come (a comma missing?))";
    // A leading zero read as the number 0 and then a number where a comma should come, which it
    // said (a helper's finding).
    QTest::addRow("a leading zero")
        << QByteArray("{\"radius\": 01}")
        << R"(demo.marbles.json: line 1, column 12: not valid JSON: a number with a leading zero (01), which JSON does not allow: write it without the zero)";
    QTest::addRow("leading zeros, negative")
        << QByteArray("[1, -007.5e2]")
        << R"(demo.marbles.json: line 1, column 6: not valid JSON: a number with a leading zero (-007.5e2), which JSON does not allow: write it without the zero)";
    // Cut short in a number after a zero, the text ends too soon: no leading zero (a helper's
    // finding: 7 of 55 cuts of a crowd's file were said to have one).
    QTest::addRow("cut short after a zero")
        << QByteArray("{\"marbles\": [{\"x\": 0.0087")
        << R"(demo.marbles.json: line 1, column 26: not valid JSON: the text ends too soon (a '}' or ']' missing?))";
    QTest::addRow("cut short after a zero and its point")
        << QByteArray("{\"marbles\": [{\"x\": 0.")
        << R"(demo.marbles.json: line 1, column 20: not valid JSON: the text ends too soon, in 0. (cut short?))";
    QTest::addRow("cut short in an exponent")
        << QByteArray("{\"marbles\": [{\"x\": 0.5e-")
        << R"(demo.marbles.json: line 1, column 20: not valid JSON: the text ends too soon, in 0.5e- (cut short?))";
    QTest::addRow("a zero then a number")
        << QByteArray("[0 1]") << R"(demo.marbles.json: line 1, column 4: not valid JSON: a number where a ',' or the ']' should come (a comma missing?))";
    // The invisible second mark had been quoted as it was ("last read: '\uFEFF?'").
    QTest::addRow("two byte order marks")
        << QByteArray("\xEF\xBB\xBF\xEF\xBB\xBF{}")
        << R"(demo.marbles.json: line 1, column 1: a second byte order mark (U+FEFF): a scene file may start with one, not two)";
    // Numbers and words as a teacher writes them by hand, or a spreadsheet exports them: they had
    // been "a word JSON does not know", to be put in double quotes (quoted, each was then "a
    // string"), and a decimal comma "a number where a key should come" (a helper's findings).
    QTest::addRow("a decimal comma")
        << QByteArray("{\"params\": {\"massScale\": 1,25,\n \"friction\": 0.1}}")
        << R"(demo.marbles.json: line 1, column 26: not valid JSON: a decimal comma (1,25): JSON writes a number with a point, 1.25)";
    QTest::addRow("a plus sign")
        << QByteArray("{\"radius\": +5}")
        << R"(demo.marbles.json: line 1, column 12: not valid JSON: a number with a '+' sign (+5), which JSON does not allow: write it without the sign)";
    QTest::addRow("no digit before the point")
        << QByteArray("{\"friction\": .5}")
        << R"(demo.marbles.json: line 1, column 14: not valid JSON: a number without a digit before its point (.5): write a 0 before the point)";
    QTest::addRow("NaN") << QByteArray("{\"x\": NaN}")
                         << R"(demo.marbles.json: line 1, column 7: not valid JSON: NaN is not a number a scene can hold: every number must be finite)";
    QTest::addRow("-Infinity")
        << QByteArray("{\"x\": -Infinity}")
        << R"(demo.marbles.json: line 1, column 7: not valid JSON: -Infinity is not a number a scene can hold: every number must be finite)";
    QTest::addRow("hexadecimal")
        << QByteArray("{\"x\": 0x10}")
        << R"(demo.marbles.json: line 1, column 7: not valid JSON: a hexadecimal number (0x10), which JSON does not allow: write it in decimal)";
    QTest::addRow("an exponent without digits")
        << QByteArray("{\"x\": 1.5e, \"y\": 2}")
        << R"(demo.marbles.json: line 1, column 7: not valid JSON: a number that stops short (1.5e): digits must follow its point, its e and its sign)";
    QTest::addRow("a key without quotes")
        << QByteArray("{\"params\": {\n    friction: 0.02}}")
        << R"(demo.marbles.json: line 2, column 5: not valid JSON: a key without its double quotes (friction): write "friction")";
    QTest::addRow("a text without quotes")
        << QByteArray("{\"params\": {\"model\": exact}}")
        << R"(demo.marbles.json: line 1, column 22: not valid JSON: a text without its double quotes (exact): write "exact")";
    QTest::addRow("True") << QByteArray("{\"stage\": {\"walls\": True}}")
                          << R"(demo.marbles.json: line 1, column 21: not valid JSON: True in small letters: JSON knows true, false and null only so)";
    QTest::addRow("single quotes, a value")
        << QByteArray("{\"format\": 'marbles-scene'}")
        << R"(demo.marbles.json: line 1, column 12: not valid JSON: a text in single quotes: JSON puts a text in double quotes ("like this"))";
    QTest::addRow("Latin-1")
        << QByteArray("{\"marbles\": [{\"name\": \"Sto\xDF\"}]}")
        << R"(demo.marbles.json: line 1, column 27: not valid JSON: a byte that is not UTF-8 in a text (was the file saved as Latin-1 or Windows-1252?): save it as UTF-8 (last read: '"Sto?"'))";
    // Not where the hint would make a valid file with the wrong number: German 1.250,5 (1250.5)
    // would be "250.5", 1e5,25 "5.25" (a reviewer's finding).
    QTest::addRow("a decimal comma after a point")
        << QByteArray("{\"params\": {\"massScale\": 1.250,5}}")
        << R"(demo.marbles.json: line 1, column 32: not valid JSON: a number where a key in double quotes should come)";
    QTest::addRow("a text beyond ASCII without quotes")
        << QByteArray("{\"marbles\": [{\"name\": Sto\xC3\x9F}]}")
        << "demo.marbles.json: line 1, column 23: not valid JSON: a text without its double quotes (Sto\xC3\x9F): write \"Sto\xC3\x9F\"";
    // A key after a value without its comma is the comma's slip, not the quotes'.
    QTest::addRow("a comma missing before a key without quotes")
        << QByteArray("{\"params\": {\"model\": \"exact\" massScale: 2}}")
        << R"(demo.marbles.json: line 1, column 30: not valid JSON: a word (massScale) where a ',' or the '}' should come (a comma missing?))";
    QTest::addRow("Latin-1 at the end")
        << QByteArray("{\"marbles\": [{\"name\": \"Sto\xDF")
        << R"(demo.marbles.json: line 1, column 27: not valid JSON: a byte that is not UTF-8 in a text (was the file saved as Latin-1 or Windows-1252?): save it as UTF-8 (last read: '"Sto?'))";
    // Gravity is a pair: 0,5 there is its brackets left out, not 0.5 (a re-tester's finding).
    QTest::addRow("a pair without brackets")
        << QByteArray("{\"params\": {\"gravity\": 0,5}}")
        << R"(demo.marbles.json: line 1, column 24: not valid JSON: two numbers (0,5) where a pair goes in brackets: write [0, 5])";
    // Cut short in a word or a number: the text's end, not a word without quotes.
    QTest::addRow("cut short in a word")
        << QByteArray("{\"stage\": {\"walls\": tr")
        << R"(demo.marbles.json: line 1, column 21: not valid JSON: the text ends too soon, in tr (cut short?))";
    // A value after a value, its comma missing: placed where it starts, named as the file has it
    // (it was placed on its last character, and "false literal" was the parser's word).
    QTest::addRow("a comma missing before false")
        << QByteArray("{\"stage\": {\"walls\": true false}}")
        << R"(demo.marbles.json: line 1, column 26: not valid JSON: false where a ',' or the '}' should come (a comma missing?))";
    QTest::addRow("a comma missing before a number")
        << QByteArray("{\"friction\": 0.1 0.25}")
        << R"(demo.marbles.json: line 1, column 18: not valid JSON: a number where a ',' or the '}' should come (a comma missing?))";
    // Quoted, a Latin-1 word would still be refused: both are said.
    QTest::addRow("Latin-1 without quotes")
        << QByteArray("{\"marbles\": [{\"name\": Caf\xE9}]}")
        << R"(demo.marbles.json: line 1, column 23: not valid JSON: a text without its double quotes, with a byte that is not UTF-8 in it (Caf?): put it in double quotes, and save the file as UTF-8 (was it saved as Latin-1 or Windows-1252?))";
    // As an editor counts: an old Mac's lone CR ends a line, a character is one column whatever
    // its bytes (the file had been all "line 1", and "Stoß" took two columns).
    QTest::addRow("lines ended by CR")
        << QByteArray("{\r\"format\": \"marbles-scene\",\r\"version\": +1}")
        << R"(demo.marbles.json: line 3, column 12: not valid JSON: a number with a '+' sign (+1), which JSON does not allow: write it without the sign)";
    QTest::addRow("letters beyond ASCII")
        << QByteArray("{\"marbles\": [{\"name\": \"Sto\xC3\x9F \xC3\x84rger\", \"x\": +5}]}")
        << R"(demo.marbles.json: line 1, column 42: not valid JSON: a number with a '+' sign (+5), which JSON does not allow: write it without the sign)";
    QTest::addRow("a comment")
        << QByteArray("// lesson 3\n{}")
        << R"(demo.marbles.json: line 1, column 1: not valid JSON: a comment: JSON has none ('//' and '/* */' are not allowed) (last read: '/'))";
    QTest::addRow("no colon") << QByteArray("{\"format\" \"marbles-scene\"}")
                              << R"(demo.marbles.json: line 1, column 25: not valid JSON: a key without its ':' and value)";
    QTest::addRow("cut short") << QByteArray("{\"format\": \"marbles-scene\", \"version\": 1")
                               << R"(demo.marbles.json: line 1, column 41: not valid JSON: the text ends too soon (a '}' or ']' missing?))";
}

void TestSceneIo::placeOfSyntaxError()
{
    QFETCH(QByteArray, text);
    QFETCH(QString, message);
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY(!load.ok);
    QCOMPARE(q(load.error), message);
}

void TestSceneIo::garbageIsRefusedQuickly()
{
    const QByteArray bytes = garbage();
    // Garbage that opens with a valid-looking start still fails fast at the first bad byte.
    const QByteArray tricky = QByteArray(R"({"format": "marbles-scene", "version": 1, "note": ")") + bytes;
    QVERIFY(!parseScene(view(bytes), kSource).ok);
    QVERIFY(!parseScene(view(tricky), kSource).ok);
}

void TestSceneIo::deepButAllowedNesting()
{
    // 256 levels in all is the limit: the scene object is one, so 255 nested arrays are fine.
    // Brackets inside strings do not count, escaped quotes do not end a string.
    const QByteArray ok = QByteArray(R"({"format": "marbles-scene", "version": 1, "s": "[[[\"{{{", "note": )")
        + QByteArray(255, '[') + QByteArray(255, ']') + "}";
    const SceneLoad load = parseScene(view(ok), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    const SceneLoad again = parseScene(sceneToJson(load.world), kSource);
    QVERIFY2(again.ok, again.error.c_str());
    QCOMPARE(again.world.sceneExtraJson, load.world.sceneExtraJson);

    const QByteArray tooDeep = QByteArray(R"({"format": "marbles-scene", "version": 1, "note": )") + QByteArray(256, '[')
        + QByteArray(256, ']') + "}";
    const SceneLoad refused = parseScene(view(tooDeep), kSource);
    QVERIFY(!refused.ok);
    QVERIFY2(q(refused.error).contains("nested deeper than 256 levels"), refused.error.c_str());
}

void TestSceneIo::memoryBudget()
{
    // A scene whose top-level `key` is an array of `count` empty objects.
    const auto emptyObjects = [](const char *key, int count) {
        QByteArray text = QByteArray(R"({"format": "marbles-scene", "version": 1, ")") + key + R"(": [{})";
        text.reserve(text.size() + 3 * count + 2);
        for (int i = 1; i < count; ++i)
            text += ",{}";
        return text + "]}";
    };
    // 13 million empty objects: 39 MB of text that nlohmann would turn into about 1.1 GB.
    // The parse stops when its estimate passes kMaxSceneMemoryBytes.
    const SceneLoad load = parseScene(view(emptyObjects("note", 13'000'000)), kSource);
    QVERIFY(!load.ok);
    QCOMPARE(q(load.error),
             QString("demo.marbles.json: size: reading this scene would take more than 1024 MiB of memory "
                     "(it holds too many values)"));

    // 5 million marbles "{}": 15 MB of text, within the document's budget, but the World built
    // from it would hold 1.1 GB more (10 million took 3.5 GB in all; a conformance tester's
    // finding). The parse stops when the World's estimate passes kMaxSceneWorldBytes.
    const SceneLoad crowded = parseScene(view(emptyObjects("marbles", 5'000'000)), kSource);
    QVERIFY(!crowded.ok);
    QCOMPARE(q(crowded.error), QString("demo.marbles.json: size: this scene's marbles, pins and pushes would take more "
                                       "than 1024 MiB of memory (it holds too many of them)"));
}

void TestSceneIo::largeSceneRoundTrips()
{
    // 100,000 marbles, a realistic big scene, well inside the memory budget.
    World w;
    for (int i = 0; i < 100'000; ++i)
        w.addMarble({i * 0.1, i / 3.0}, 1.0 + (i % 7), {0.5, -0.25});
    const std::string saved = sceneToJson(w);
    const SceneLoad load = parseScene(saved, kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(difference(w, load.world), QString());
}

void TestSceneIo::utf8ByteOrderMarkIsAccepted()
{
    // Windows editors write a UTF-8 byte order mark; JSON (RFC 8259) lets a reader ignore it.
    const SceneLoad load = parseScene(view("\xEF\xBB\xBF" + dumpScene(baseScene())), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(load.world.marbleCount(), 4);
}

void TestSceneIo::defaults_data()
{
    QTest::addColumn<QByteArray>("text");
    QTest::addRow("only format and version") << QByteArray(R"({"format": "marbles-scene", "version": 1})");
    QTest::addRow("empty sections")
        << QByteArray(R"({"format": "marbles-scene", "version": 1, "stage": {}, "params": {}, "marbles": [], "pins": [], "pushes": []})");
    QTest::addRow("version as 1.0") << QByteArray(R"({"version": 1.0, "format": "marbles-scene"})");
}

void TestSceneIo::defaults()
{
    QFETCH(QByteArray, text);
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    const World &w = load.world;
    // PHYSICS.md: stage 800 x 600 with walls, the book's parameters, nothing on stage.
    QCOMPARE(w.stage, Stage());
    QCOMPARE(w.stage.width, 800.0);
    QCOMPARE(w.stage.height, 600.0);
    QVERIFY(w.stage.walls);
    QCOMPARE(w.params, Params());
    QCOMPARE(w.params.model, ModelKind::Book);
    QCOMPARE(w.params.massScale, 1.25);
    QCOMPARE(w.params.friction, 0.1);
    QCOMPARE(w.params.zeroThreshold, 0.01);
    QCOMPARE(w.params.pushScale, 10.0);
    QCOMPARE(w.params.frameMs, 20.0);
    QCOMPARE(w.params.restitution, 1.0);
    QCOMPARE(w.params.gravity, Vec2());
    QCOMPARE(w.params.substeps, 1);
    QVERIFY(!w.params.shortCircuit);
    QCOMPARE(w.marbleCount(), 0);
    QVERIFY(w.pins.empty());
    QVERIFY(w.pushes.empty());
    QCOMPARE(w.frame, std::int64_t(0));
    QVERIFY(w.sceneExtraJson.empty() && w.stageExtraJson.empty() && w.paramsExtraJson.empty());
}

void TestSceneIo::interfacesExample()
{
    // The example of INTERFACES.md, verbatim, plus a marble and a push with only some keys.
    const QByteArray text = R"({
      "format": "marbles-scene",
      "version": 1,
      "stage":  { "width": 800, "height": 600, "walls": true },
      "params": { "model": "book", "massScale": 1.25, "friction": 0.1,
                  "zeroThreshold": 0.01, "pushScale": 10, "frameMs": 20,
                  "restitution": 1.0, "gravity": [0, 0], "substeps": 1,
                  "shortCircuit": false },
      "marbles": [ { "x": 120, "y": 200, "radius": 25, "vx": 0, "vy": 0 }, { "y": 7, "vx": -2 } ],
      "pins":    [ { "x": 300, "y": 220 } ],
      "pushes":  [ { "frame": 0, "marble": 0, "x": 110, "y": 195 }, { "frame": 4 } ]
    })";
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    const World &w = load.world;
    QCOMPARE(w.marbleCount(), 2);
    QCOMPARE(w.position[0], (Vec2{120, 200}));
    QCOMPARE(w.velocity[0], Vec2());
    QCOMPARE(w.radius[0], 25.0);
    QCOMPARE(w.mass[0], 1.25 * 25.0);
    QVERIFY(!w.info[0].hasMass);
    // Missing marble keys: position and velocity 0, radius kDefaultMarbleRadius.
    QCOMPARE(w.position[1], (Vec2{0, 7}));
    QCOMPARE(w.velocity[1], (Vec2{-2, 0}));
    QCOMPARE(w.radius[1], kDefaultMarbleRadius);
    QCOMPARE(w.mass[1], 1.25 * kDefaultMarbleRadius);
    QCOMPARE(w.acceleration.size(), std::size_t(2));
    QCOMPARE(w.lastHit.size(), std::size_t(2));
    QCOMPARE(w.pins.size(), std::size_t(1));
    QCOMPARE(w.pins[0], (Vec2{300, 220}));
    QCOMPARE(w.pinExtraJson.size(), std::size_t(1));
    QCOMPARE(w.pushes.size(), std::size_t(2));
    QCOMPARE(w.pushes[0], (Push{0, 0, {110, 195}, {}}));
    QCOMPARE(w.pushes[1], (Push{4, 0, {0, 0}, {}}));
}

void TestSceneIo::frictionByModel_data()
{
    QTest::addColumn<QString>("model");
    QTest::addColumn<double>("friction");
    QTest::addColumn<bool>("valid");
    // k >= 1 has no exact-model drag rate (lambda = -ln(1 - k)); the book model takes any k >= 0.
    QTest::addRow("book 1.5") << "book" << 1.5 << true;
    QTest::addRow("book 1") << "book" << 1.0 << true;
    QTest::addRow("book 2.5 (blows up, on purpose)") << "book" << 2.5 << true;
    QTest::addRow("exact 0.999") << "exact" << 0.999 << true;
    QTest::addRow("exact 0") << "exact" << 0.0 << true;
    QTest::addRow("exact 1") << "exact" << 1.0 << false;
    QTest::addRow("exact 1.5") << "exact" << 1.5 << false;
    QTest::addRow("impulse 0.5") << "impulse" << 0.5 << true;
    QTest::addRow("impulse 1") << "impulse" << 1.0 << false;
    QTest::addRow("impulse 1.5") << "impulse" << 1.5 << false;
}

void TestSceneIo::frictionByModel()
{
    QFETCH(QString, model);
    QFETCH(double, friction);
    QFETCH(bool, valid);
    Json doc = baseScene();
    doc["params"]["model"] = model.toStdString();
    doc["params"]["friction"] = friction;
    const SceneLoad load = parseScene(view(dumpScene(doc)), kSource);
    QCOMPARE(load.ok, valid);
    if (valid) {
        QCOMPARE(load.world.params.friction, friction);
    } else {
        QVERIFY2(q(load.error).startsWith(QString(kSource) + ": params.friction: must be < 1 for the " + model + " model"),
                 load.error.c_str());
    }
}

void TestSceneIo::wholeNumbersAsFloats()
{
    const QByteArray text = R"({"format": "marbles-scene", "version": 1, "params": {"substeps": 4.0},
        "marbles": [{"x": 1}], "pushes": [{"frame": 3.0, "marble": 0.0}, {"frame": 9007199254740993, "marble": -0}]})";
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(load.world.params.substeps, 4);
    QCOMPARE(load.world.pushes[0].frame, std::int64_t(3));
    QCOMPARE(load.world.pushes[1].frame, std::int64_t(9007199254740993)); // integers are exact, not doubles
    QCOMPARE(load.world.pushes[1].marble, 0); // -0, read as the double -0
}

void TestSceneIo::roundTripWorld_data()
{
    QTest::addColumn<double>("v");
    QTest::addRow("0.1") << 0.1;
    QTest::addRow("1/3") << 1.0 / 3.0;
    QTest::addRow("-2/3") << -2.0 / 3.0;
    QTest::addRow("1e-300") << 1e-300;
    QTest::addRow("5e-324 (smallest subnormal)") << 5e-324;
    QTest::addRow("smallest normal") << std::numeric_limits<double>::min();
    QTest::addRow("-0.0") << -0.0;
    QTest::addRow("0") << 0.0;
    QTest::addRow("1e300") << 1e300;
    QTest::addRow("largest double") << std::numeric_limits<double>::max();
    QTest::addRow("-largest double") << -std::numeric_limits<double>::max();
    QTest::addRow("2^53 + 2") << 9007199254740994.0;
    QTest::addRow("2^53 - 1") << 9007199254740991.0;
    QTest::addRow("0.1 + 0.2") << 0.1 + 0.2;
    QTest::addRow("pi") << std::numbers::pi;
    QTest::addRow("-7") << -7.0;
    QTest::addRow("123456789.123456789") << 123456789.123456789;
    QTest::addRow("nextafter(1, 2)") << std::nextafter(1.0, 2.0);
}

void TestSceneIo::derivedMassUnderflowIsRefused()
{
    // massScale x radius can also come out 0, a mass no collision can divide by.
    const SceneLoad load = parseScene(R"({"format": "marbles-scene", "version": 1, "params": {"massScale": 1e-300},
                                          "marbles": [{"x": 1, "y": 1, "radius": 1e-30}]})",
                                      kSource);
    QVERIFY(!load.ok);
    QCOMPARE(q(load.error), QString(kSource) + ": marbles[0]: its mass massScale x radius = 1e-300 x 1e-30 is below "
                                               "what a double can hold: give the marble a mass, or change massScale");
    // With a mass of its own, the marble is fine.
    QVERIFY(parseScene(R"({"format": "marbles-scene", "version": 1, "params": {"massScale": 1e-300},
                           "marbles": [{"x": 1, "y": 1, "radius": 1e-30, "mass": 2}]})",
                       kSource)
                .ok);
}

void TestSceneIo::roundTripWorld()
{
    QFETCH(double, v);
    const double a = std::abs(v);
    World w;
    // Fields that take any finite number get v; the ones that must be > 0, >= 0 or in [0, 1]
    // get |v| where that obeys the rule.
    w.params.pushScale = v;
    w.params.gravity = {v, -v};
    if (a > 0) {
        w.stage = {a, a, false};
        w.params.frameMs = a;
        w.setMassScale(a);
    }
    w.params.friction = a;
    w.params.zeroThreshold = a;
    if (a <= 1)
        w.params.restitution = a;
    // Marble 0's mass is derived (massScale x radius) where that is a mass; where it would be
    // no number (1e300 x 1e300), 0 (1e-300 x 1e-300) or so small that 1 / m overflows, the loader
    // refuses it, so it is given. Marble 1's is given: |v| where it is a mass.
    const auto isMass = [](double m) { return std::isfinite(m) && m > 0 && std::isfinite(1.0 / m); };
    const double radius = a > 0 ? a : 1.0;
    const double derived = w.params.massScale * radius;
    w.addMarble({v, -v}, radius, {-v, v}, isMass(derived) ? 0.0 : 5.0);
    w.addMarble({v, v}, 2.0, {v, v}, isMass(a) ? a : 3.0);
    w.addPin({v, -v});
    w.pushes.push_back({7, 1, {v, v}, {}});

    const std::string saved = sceneToJson(w);
    const SceneLoad load = parseScene(saved, kSource);
    QVERIFY2(load.ok, (load.error + "\n" + saved).c_str());
    QCOMPARE(difference(w, load.world), QString());
    QCOMPARE(sceneToJson(load.world), saved); // the saved text is a fixed point
}

void TestSceneIo::roundTripText_data()
{
    QTest::addColumn<QByteArray>("literal");
    QTest::addColumn<double>("expected");
    QTest::addRow("0.1") << QByteArray("0.1") << 0.1;
    QTest::addRow("1/3 written long") << QByteArray("0.33333333333333333333333333") << 1.0 / 3.0;
    QTest::addRow("1e-300") << QByteArray("1e-300") << 1e-300;
    QTest::addRow("5e-324") << QByteArray("5e-324") << 5e-324;
    QTest::addRow("below the smallest subnormal") << QByteArray("1e-400") << 0.0;
    QTest::addRow("-0.0") << QByteArray("-0.0") << -0.0;
    // As `marbles-cli run` prints -0 (%.17g): it reads back as -0, not as the integer 0.
    QTest::addRow("-0") << QByteArray("-0") << -0.0;
    QTest::addRow("0") << QByteArray("0") << 0.0;
    QTest::addRow("1.7976931348623157e308") << QByteArray("1.7976931348623157e308") << std::numeric_limits<double>::max();
    QTest::addRow("huge integer") << QByteArray("123456789012345678901234567890") << 123456789012345678901234567890.0;
    QTest::addRow("2^64 - 1") << QByteArray("18446744073709551615") << 18446744073709551615.0;
    QTest::addRow("-2^63") << QByteArray("-9223372036854775808") << -9223372036854775808.0;
    QTest::addRow("2^53 + 1 (rounds to even)") << QByteArray("9007199254740993") << 9007199254740992.0;
    QTest::addRow("exponent form") << QByteArray("12.5E+2") << 1250.0;
}

void TestSceneIo::roundTripText()
{
    QFETCH(QByteArray, literal);
    QFETCH(double, expected);
    const QByteArray text = R"({"format": "marbles-scene", "version": 1, "params": {"pushScale": )" + literal
        + R"(, "gravity": [)" + literal + ", " + literal + R"(]}, "marbles": [{"x": )" + literal + R"(, "vy": )" + literal
        + R"(}], "pins": [{"y": )" + literal + R"(}], "pushes": [{"x": )" + literal + "}]}";
    const SceneLoad load = parseScene(view(text), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    const World &w = load.world;
    for (double got : {w.params.pushScale, w.params.gravity.x, w.params.gravity.y, w.position[0].x, w.velocity[0].y,
                       w.pins[0].y, w.pushes[0].at.x})
        QVERIFY2(sameBits(got, expected), qPrintable(QString::number(got, 'g', 17)));

    const std::string saved = sceneToJson(w);
    const SceneLoad again = parseScene(saved, kSource);
    QVERIFY2(again.ok, again.error.c_str());
    QCOMPARE(difference(w, again.world), QString());
}

void TestSceneIo::unknownKeysSurvive_data()
{
    QTest::addColumn<QString>("pointer");
    QTest::addRow("top level object") << "/author";
    QTest::addRow("top level number") << "/revision";
    QTest::addRow("stage") << "/stage/background";
    QTest::addRow("params") << "/params/note";
    QTest::addRow("params, nested") << "/params/ui";
    QTest::addRow("marble") << "/marbles/0/tag";
    QTest::addRow("second marble") << "/marbles/1/selected";
    QTest::addRow("pin") << "/pins/1/label";
    // A push's were read and dropped (a tester's "why": "start" was gone after a save).
    QTest::addRow("push") << "/pushes/0/why";
    QTest::addRow("push, nested") << "/pushes/0/by";
}

void TestSceneIo::unknownKeysSurvive()
{
    QFETCH(QString, pointer);
    const Json original = Json::parse(R"({
        "format": "marbles-scene", "version": 1,
        "author": {"name": "A. Teacher \u00e9\u4e2d", "year": 2026, "tags": ["demo", null, true, 0.1]},
        "revision": 1e-300,
        "stage": {"width": 640, "height": 480, "walls": false, "background": "#ffffff"},
        "params": {"model": "exact", "friction": 0.05, "note": "line 1\nline 2 \"quoted\"", "ui": {"zoom": [1.5, -0.0]}},
        "marbles": [{"x": 1, "y": 2, "tag": [1, 2.5, {"deep": [[[]]]}]}, {"x": 3, "selected": false}],
        "pins": [{"x": 0, "y": 0}, {"x": 5, "y": 6, "label": "P2"}],
        "pushes": [{"frame": 3, "marble": 1, "x": 2, "y": 2, "why": "start", "by": {"teacher": [1, 2]}}, {"frame": 4}]
    })");
    const Json::json_pointer where(pointer.toStdString());

    const SceneLoad load = parseScene(original.dump(), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    const std::string saved = sceneToJson(load.world);
    const Json savedJson = Json::parse(saved);
    QVERIFY2(savedJson.contains(where), saved.c_str());
    QCOMPARE(q(savedJson.at(where).dump()), q(original.at(where).dump()));

    // And through a second load: the kept text is identical.
    const SceneLoad again = parseScene(saved, kSource);
    QVERIFY2(again.ok, again.error.c_str());
    QCOMPARE(difference(load.world, again.world), QString());
    QVERIFY(!again.world.sceneExtraJson.empty());
    QCOMPARE(again.world.pinExtraJson[0], std::string());
    QCOMPARE(again.world.info[1].extraJson, std::string(R"({"selected":false})"));
    QCOMPARE(again.world.pushes[1].extraJson, std::string());
}

void TestSceneIo::unknownKeysAreNoted()
{
    // A misspelt key ran the scene with its default without a word: "Friction": 0.5 ran at 0.1,
    // "raduis": 5 drew the marble 25 px wide (a helper's finding). The scene still loads, and the
    // keys are kept (INTERFACES.md), but each is noted, near-misses of a known key first, with it.
    const SceneLoad misspelt = parseScene(R"({"format": "marbles-scene", "version": 1,
        "params": {"Friction": 0.5}, "stage": {"wall": false},
        "marbles": [{"x": 1, "y": 2, "raduis": 5, "vz": 1, "r": 3, "note": "cue ball"}]})",
                                          kSource);
    QVERIFY2(misspelt.ok, misspelt.error.c_str());
    QCOMPARE(misspelt.world.params.friction, Params{}.friction);
    QCOMPARE(misspelt.world.stage.walls, true);
    QCOMPARE(misspelt.world.radius[0], kDefaultMarbleRadius);
    QVERIFY(misspelt.misspeltKeys);
    const std::vector<std::string> expected = {
        "demo.marbles.json: stage.wall: not a key of stage, so not used (did you mean walls?)",
        "demo.marbles.json: params.Friction: not a key of params, so not used (did you mean friction?)",
        "demo.marbles.json: marbles[0].raduis: not a key of a marble, so not used (did you mean radius?)",
        "demo.marbles.json: marbles[0].vz: not a key of a marble, so not used (did you mean vx or vy?)",
        // One letter is one edit from every other: "r" is not taken for x or y.
        "demo.marbles.json: marbles[0].note: not a key of a marble, so not used (kept when the scene is saved)",
        "demo.marbles.json: and 1 more key not used",
    };
    QCOMPARE(misspelt.notes, expected);

    // A teacher's own keys, on every marble: noted, not taken for mistakes; five said, then a count.
    Json many = Json::parse(R"({"format": "marbles-scene", "version": 1, "lesson": "collisions"})");
    for (int i = 0; i < 40; ++i)
        many["marbles"].push_back({{"x", 30 * i}, {"y", 100}, {"radius", 10}, {"tag", i}});
    const SceneLoad tagged = parseScene(many.dump(), kSource);
    QVERIFY2(tagged.ok, tagged.error.c_str());
    QVERIFY(!tagged.misspeltKeys);
    QCOMPARE(tagged.notes.size(), std::size_t{6});
    QCOMPARE(tagged.notes.front(),
             std::string("demo.marbles.json: marbles[0].tag: not a key of a marble, so not used (kept when the scene is saved)"));
    QCOMPARE(tagged.notes.back(), std::string("demo.marbles.json: and 36 more keys not used"));
    QCOMPARE(tagged.world.info[39].extraJson, std::string(R"({"tag":39})"));

    // An empty key is shown as such; a key beside the one it is near to is not taken for it ("X"
    // beside "x": x was read).
    const SceneLoad odd = parseScene(R"({"format": "marbles-scene", "version": 1, "": 1, "marbles": [{"x": 100, "X": 5}]})", kSource);
    QVERIFY2(odd.ok, odd.error.c_str());
    QVERIFY(!odd.misspeltKeys);
    const std::vector<std::string> oddNotes = {
        "demo.marbles.json: marbles[0].X: not a key of a marble, so not used (kept when the scene is saved)",
        "demo.marbles.json: \"\": not a key of a scene, so not used (kept when the scene is saved)",
    };
    QCOMPARE(odd.notes, oddNotes);

    // A scene of known keys only: nothing to say.
    const SceneLoad plain = parseScene(R"({"format": "marbles-scene", "version": 1, "marbles": [{"x": 1}]})", kSource);
    QVERIFY(plain.ok);
    QVERIFY(plain.notes.empty());
    QVERIFY(!plain.misspeltKeys);
}

void TestSceneIo::savedLayout()
{
    World w;
    w.sceneExtraJson = R"({"author":"me"})";
    w.addMarble({120, 200}, 25);
    w.info[0].name = "first";
    w.info[0].color = "#0000ff";
    w.addPin({300, 220});
    w.pushes.push_back({0, 0, {110, 195}, {}});
    const QString saved = q(sceneToJson(w));

    // Known keys in a stable, readable order, unknown top-level keys after them.
    qsizetype last = -1;
    for (const char *key : {"\"format\"", "\"version\"", "\"stage\"", "\"params\"", "\"marbles\"", "\"pins\"", "\"pushes\"",
                            "\"author\""}) {
        const qsizetype at = saved.indexOf(key);
        QVERIFY2(at > last, key);
        last = at;
    }
    // One marble, pin or push per line; whole numbers without ".0".
    QVERIFY2(saved.contains(R"({"x": 120, "y": 200, "radius": 25, "vx": 0, "vy": 0, "name": "first", "color": "#0000ff"})"),
             qPrintable(saved));
    QVERIFY2(saved.contains(R"({"x": 300, "y": 220})"), qPrintable(saved));
    QVERIFY2(saved.contains(R"({"frame": 0, "marble": 0, "x": 110, "y": 195})"), qPrintable(saved));
    QVERIFY(saved.startsWith("{\n  \"format\": \"marbles-scene\",\n  \"version\": 1,\n"));
    QVERIFY(saved.endsWith("}\n"));
}

void TestSceneIo::massWrittenOnlyWhenExplicit()
{
    World w;
    w.params.massScale = 2.0;
    w.addMarble({10, 10}, 5);
    w.addMarble({50, 10}, 5, {}, 7.5);
    const Json saved = Json::parse(sceneToJson(w));
    QVERIFY(!saved["marbles"][0].contains("mass"));
    QCOMPARE(saved["marbles"][1]["mass"].get<double>(), 7.5);

    const SceneLoad load = parseScene(saved.dump(), kSource);
    QVERIFY2(load.ok, load.error.c_str());
    QVERIFY(!load.world.info[0].hasMass);
    QCOMPARE(load.world.mass[0], 10.0); // derived again: massScale * radius
    QVERIFY(load.world.info[1].hasMass);
    QCOMPARE(load.world.mass[1], 7.5);
}

void TestSceneIo::saveIntoMissingFolder()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath("missing/scene.marbles.json");
    const std::string error = saveSceneFile(World(), path.toStdString());
    QVERIFY(!error.empty());
    QVERIFY2(q(error).startsWith(path + ": "), error.c_str());
    QVERIFY2(q(error).contains("No such file or directory"), error.c_str());
    QVERIFY(!QFileInfo::exists(dir.filePath("missing")));
    QCOMPARE(folderEntries(dir.path()), QStringList());
}

void TestSceneIo::saveReplacesCompletely()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath("scene.marbles.json");
    {
        QFile old(path);
        QVERIFY(old.open(QIODevice::WriteOnly));
        old.write(QByteArray(200000, 'x')); // far longer than the new scene
    }
    World w;
    w.addMarble({1, 2}, 3);
    QCOMPARE(saveSceneFile(w, path.toStdString()), std::string());

    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly));
    QCOMPARE(file.readAll(), QByteArray::fromStdString(sceneToJson(w)));
    QCOMPARE(folderEntries(dir.path()), QStringList{"scene.marbles.json"}); // no temporary file left

    const SceneLoad load = loadSceneFile(path.toStdString());
    QVERIFY2(load.ok, load.error.c_str());
    QCOMPARE(difference(w, load.world), QString());
}

void TestSceneIo::saveKeepsPermissions()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const std::string path = dir.filePath("scene.marbles.json").toStdString();
    QCOMPARE(saveSceneFile(World(), path), std::string());
    QCOMPARE(::chmod(path.c_str(), 0640), 0);
    QCOMPARE(saveSceneFile(World(), path), std::string());
    struct stat info {};
    QCOMPARE(::stat(path.c_str(), &info), 0);
    QCOMPARE(info.st_mode & 07777, mode_t(0640));
}

void TestSceneIo::saveRefusesWhatWouldNotLoad_data()
{
    QTest::addColumn<QString>("what");
    QTest::addColumn<QString>("rule");
    QTest::addRow("position NaN") << "nan" << "marbles[0].x: must be a number, got null";
    QTest::addRow("friction 1.5, exact") << "exact" << "params.friction: must be < 1 for the exact model, got 1.5";
    QTest::addRow("radius 0") << "radius" << "marbles[0].radius: must be > 0, got 0";
}

void TestSceneIo::saveRefusesWhatWouldNotLoad()
{
    QFETCH(QString, what);
    QFETCH(QString, rule);
    World w;
    w.addMarble({1, 2}, 3);
    if (what == "nan")
        w.position[0].x = std::numeric_limits<double>::quiet_NaN();
    else if (what == "exact")
        QCOMPARE(setParam(w, "model", "exact") + setParam(w, "friction", "1.5"), std::string());
    else
        w.radius[0] = 0.0;

    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath("scene.marbles.json");
    const std::string error = saveSceneFile(w, path.toStdString());
    QCOMPARE(q(error), path + ": not saved, the scene would not load back: " + rule);
    QCOMPARE(folderEntries(dir.path()), QStringList());
}

void TestSceneIo::savedMidRunRunsOnAsTheWorld()
{
    // The chapter's four marbles push marble 0 at frame 0 and marble 3 at frame 150. Saved at
    // frame 100, the file has the second push 50 frames ahead and not the first (which has acted:
    // read back, it pushed marble 0 again). Run on, the file's world is the world's, bit for bit.
    for (const ModelKind model : {ModelKind::Book, ModelKind::Impulse, ModelKind::Exact}) {
        World w = defaultScene();
        w.params.model = model;
        QCOMPARE(w.pushes.size(), std::size_t(2));
        QCOMPARE(w.pushes[0].frame, std::int64_t(0));
        QCOMPARE(w.pushes[1].frame, std::int64_t(150));
        for (int f = 0; f < 100; ++f)
            QVERIFY(w.step().finite);
        const SceneLoad load = parseScene(sceneToJson(w), kSource);
        QVERIFY2(load.ok, load.error.c_str());
        World read = load.world;
        QCOMPARE(read.frame, std::int64_t(0));
        QCOMPARE(read.pushes.size(), std::size_t(1));
        QCOMPARE(read.pushes[0].frame, std::int64_t(50));
        QCOMPARE(read.pushes[0].marble, w.pushes[1].marble);
        for (int f = 0; f < 150; ++f) {
            QVERIFY(w.step().finite);
            QVERIFY(read.step().finite);
        }
        QVERIFY(read.position == w.position);
        QVERIFY(read.velocity == w.velocity);
        // Saved at frame 0, the pushes are as they were.
        const SceneLoad start = parseScene(sceneToJson(defaultScene()), kSource);
        QVERIFY(start.ok);
        QVERIFY(start.world.pushes == defaultScene().pushes);
    }
}

void TestSceneIo::saveOverFolderFails()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(QDir(dir.path()).mkdir("scene"));
    const QString path = dir.filePath("scene");
    const std::string error = saveSceneFile(World(), path.toStdString());
    QVERIFY2(q(error).startsWith(path + ": cannot save: "), error.c_str());
    QVERIFY(QFileInfo(path).isDir());
    QCOMPARE(folderEntries(dir.path()), QStringList{"scene"}); // the temporary file is gone
}

void TestSceneIo::loadFileErrors_data()
{
    QTest::addColumn<QString>("name");
    QTest::addColumn<QString>("rule");
    QTest::addRow("missing") << "nothing-here.marbles.json" << "cannot open the file: No such file or directory";
    QTest::addRow("folder") << "folder" << "cannot read the file: it is a folder, not a scene file";
    QTest::addRow("empty") << "empty.marbles.json" << "line 1, column 1: the text is empty";
    // A named pipe nothing writes to: read as empty at once (opening it used to wait for ever).
    QTest::addRow("named pipe") << "pipe.marbles.json" << "cannot read the file: it is a named pipe, and nothing was written to it";
    // A device without end: read only up to the limit (the window's reader read on without one).
    QTest::addRow("endless device") << "zero.marbles.json"
                                    << "size: a scene file must be at most 268435456 bytes (256 MiB), got more than that";
}

void TestSceneIo::loadFileErrors()
{
    QFETCH(QString, name);
    QFETCH(QString, rule);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(QDir(dir.path()).mkdir("folder"));
    {
        QFile empty(dir.filePath("empty.marbles.json"));
        QVERIFY(empty.open(QIODevice::WriteOnly));
    }
    QVERIFY(::mkfifo(QFile::encodeName(dir.filePath("pipe.marbles.json")).constData(), 0600) == 0);
    QVERIFY(QFile::link(QStringLiteral("/dev/zero"), dir.filePath("zero.marbles.json")));
    const QString path = dir.filePath(name);
    const SceneLoad load = loadSceneFile(path.toStdString());
    QVERIFY(!load.ok);
    QVERIFY2(q(load.error).startsWith(path + ": " + rule), load.error.c_str());
    // Named as the caller shows it (the window gives the file's name without its folder).
    const SceneLoad shown = loadSceneFile(path.toStdString(), "shown.json");
    QVERIFY2(q(shown.error).startsWith("shown.json: " + rule), shown.error.c_str());
}

void TestSceneIo::loadRefusesHugeFileBeforeReading()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString path = dir.filePath("huge.marbles.json");
    {
        QFile huge(path);
        QVERIFY(huge.open(QIODevice::WriteOnly));
        QVERIFY(huge.resize(qint64(kMaxSceneBytes) + 1)); // sparse: costs no disk
    }
    const SceneLoad load = loadSceneFile(path.toStdString());
    QVERIFY(!load.ok);
    QCOMPARE(q(load.error), path + ": size: a scene file must be at most 268435456 bytes (256 MiB), got 268435457 bytes");
}

void TestSceneIo::loadFileNamesFileAsGiven()
{
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(QDir::setCurrent(dir.path()));
    {
        QFile bad("bad.marbles.json");
        QVERIFY(bad.open(QIODevice::WriteOnly));
        bad.write(patchedScene("/marbles/3/radius", "-5"));
    }
    const SceneLoad load = loadSceneFile("./bad.marbles.json");
    QCOMPARE(q(load.error), QString("./bad.marbles.json: marbles[3].radius: must be > 0, got -5"));
    QVERIFY(QDir::setCurrent(QDir::tempPath()));
}

void TestSceneIo::setParamAccepts_data()
{
    QTest::addColumn<QString>("key");
    QTest::addColumn<QString>("value");
    QTest::addColumn<QString>("expected"); // the setting read back
    QTest::addRow("model exact") << "model" << "exact" << "exact";
    QTest::addRow("model impulse") << "model" << "impulse" << "impulse";
    QTest::addRow("model book") << "model" << "book" << "book";
    QTest::addRow("massScale") << "massScale" << "2" << "2";
    QTest::addRow("friction") << "friction" << "0.2" << "0.20000000000000001";
    QTest::addRow("friction 1.5 (book)") << "friction" << "1.5" << "1.5";
    QTest::addRow("friction 0") << "friction" << "0" << "0";
    QTest::addRow("friction with plus") << "friction" << "+0.25" << "0.25";
    QTest::addRow("zeroThreshold") << "zeroThreshold" << "0" << "0";
    QTest::addRow("pushScale negative") << "pushScale" << "-3" << "-3";
    QTest::addRow("pushScale exponent") << "pushScale" << "1e3" << "1000";
    // Too close to 0 for a double: its nearest, 0, as a scene file's "friction": 1e-400 reads.
    QTest::addRow("friction 1e-400") << "friction" << "1e-400" << "0";
    QTest::addRow("pushScale -1e-400") << "pushScale" << "-1e-400" << "0";
    QTest::addRow("zeroThreshold subnormal") << "zeroThreshold" << "1e-310" << "9.9999999999999694e-311";
    QTest::addRow("frameMs") << "frameMs" << "16.5" << "16.5";
    QTest::addRow("restitution 0") << "restitution" << "0" << "0";
    QTest::addRow("restitution 1") << "restitution" << "1" << "1";
    QTest::addRow("restitution 0.5") << "restitution" << "0.5" << "0.5";
    QTest::addRow("gravity") << "gravity" << "0,0.5" << "0,0.5";
    QTest::addRow("gravity negative") << "gravity" << "-1.5,2" << "-1.5,2";
    QTest::addRow("substeps") << "substeps" << "8" << "8";
    // Whole numbers written as decimals, as a file may hold them ("substeps": 4.0 loads).
    QTest::addRow("substeps 4.0") << "substeps" << "4.0" << "4";
    QTest::addRow("substeps 1e3") << "substeps" << "1e3" << "1000";
    QTest::addRow("substeps limit") << "substeps" << "1000000" << "1000000";
    QTest::addRow("shortCircuit true") << "shortCircuit" << "true" << "true";
    QTest::addRow("shortCircuit 1") << "shortCircuit" << "1" << "true";
    QTest::addRow("width") << "width" << "1024" << "1024";
    QTest::addRow("height") << "height" << "768.5" << "768.5";
    QTest::addRow("walls false") << "walls" << "false" << "false";
    QTest::addRow("walls 0") << "walls" << "0" << "false";
}

void TestSceneIo::setParamAccepts()
{
    QFETCH(QString, key);
    QFETCH(QString, value);
    QFETCH(QString, expected);
    World w;
    QCOMPARE(q(setParam(w, key.toStdString(), value.toStdString())), QString());
    QCOMPARE(setting(w, key), expected);
    QCOMPARE(q(marbles::validateParams(w.params)), QString());
}

void TestSceneIo::setParamRejects_data()
{
    QTest::addColumn<QString>("key");
    QTest::addColumn<QString>("value");
    QTest::addColumn<QString>("message");
    QTest::addRow("friction negative") << "friction" << "-1" << "friction=-1: must be >= 0";
    QTest::addRow("friction word") << "friction" << "abc" << "friction=abc: must be a number";
    QTest::addRow("friction empty") << "friction" << "" << "friction=: must be a number";
    QTest::addRow("friction trailing text") << "friction" << "0.1x" << "friction=0.1x: must be a number";
    QTest::addRow("friction comma decimal") << "friction" << "0,1" << "friction=0,1: must be a number";
    QTest::addRow("friction nan") << "friction" << "nan" << "friction=nan: must be a finite number";
    QTest::addRow("friction inf") << "friction" << "inf" << "friction=inf: must be a finite number";
    QTest::addRow("friction overflow") << "friction" << "1e999" << "friction=1e999: must be a number within the range of a double";
    QTest::addRow("friction hexadecimal") << "friction" << "0x10" << "friction=0x10: must be a number";
    QTest::addRow("friction leading space") << "friction" << " 0.1" << "friction= 0.1: must be a number";
    QTest::addRow("massScale zero") << "massScale" << "0" << "massScale=0: must be > 0";
    // A mass whose 1 / m overflows: the first push or collision left finite numbers.
    QTest::addRow("massScale underflows a mass's inverse")
        << "massScale" << "1e-320" << "massScale=1e-320: marble 0: its mass massScale x radius = 1e-320 x 4 = ";
    QTest::addRow("massScale overflows a mass") << "massScale" << "1e308"
                                                << "massScale=1e308: marble 0: its mass massScale x radius = 1e+308 x 4 is beyond";
    QTest::addRow("zeroThreshold negative") << "zeroThreshold" << "-0.5" << "zeroThreshold=-0.5: must be >= 0";
    QTest::addRow("pushScale infinite") << "pushScale" << "-inf" << "pushScale=-inf: must be a finite number";
    QTest::addRow("frameMs zero") << "frameMs" << "0" << "frameMs=0: must be > 0";
    QTest::addRow("restitution 1.5") << "restitution" << "1.5" << "restitution=1.5: must be between 0 and 1";
    QTest::addRow("restitution negative") << "restitution" << "-0.1" << "restitution=-0.1: must be between 0 and 1";
    QTest::addRow("model unknown") << "model" << "verlet" << R"(model=verlet: must be "book", "impulse" or "exact")";
    QTest::addRow("gravity one number") << "gravity" << "1" << R"(gravity=1: must be two numbers "x,y")";
    QTest::addRow("gravity three numbers") << "gravity" << "1,2,3" << R"(gravity=1,2,3: must be two numbers "x,y")";
    QTest::addRow("gravity nan") << "gravity" << "nan,0" << "gravity=nan,0: must be two finite numbers";
    // As friction's: too large, not "two numbers" (a helper's finding).
    QTest::addRow("gravity x overflow") << "gravity" << "1e400,0"
                                        << "gravity=1e400,0: x must be a number within the range of a double";
    QTest::addRow("gravity y overflow") << "gravity" << "0,-1e999"
                                        << "gravity=0,-1e999: y must be a number within the range of a double";
    QTest::addRow("gravity y empty") << "gravity" << "0," << R"(gravity=0,: must be two numbers "x,y")";
    QTest::addRow("substeps zero") << "substeps" << "0" << "substeps=0: must be >= 1";
    QTest::addRow("substeps fraction") << "substeps" << "2.5" << "substeps=2.5: must be an integer";
    QTest::addRow("substeps plus minus") << "substeps" << "+-1" << "substeps=+-1: must be an integer";
    QTest::addRow("friction plus minus") << "friction" << "+-0" << "friction=+-0: must be a number";
    // A decimal comma is named with the number meant (a German-locale tester's finding).
    QTest::addRow("friction decimal comma") << "friction" << "0,5"
                                            << "friction=0,5: must be a number with a decimal point: 0.5, not 0,5";
    QTest::addRow("massScale comma and exponent") << "massScale" << "1,5e3"
                                                  << "massScale=1,5e3: must be a number with a decimal point: 1.5e3, not 1,5e3";
    QTest::addRow("pushScale grouped and comma") << "pushScale" << "1.234,5" << "pushScale=1.234,5: must be a number";
    // Not where the comma may group thousands (a re-tester's finding: "1,000" was offered as 1.000).
    QTest::addRow("massScale grouped") << "massScale" << "1,000"
                                       << "massScale=1,000: must be a number written without group separators (1,000 can be "
                                          "read two ways: 1000 or 1.000)";
    QTest::addRow("friction comma, zero first") << "friction" << "0,125"
                                                << "friction=0,125: must be a number with a decimal point: 0.125, not 0,125";
    QTest::addRow("gravity decimal commas") << "gravity" << "0,0,5" << R"(gravity=0,0,5: must be two numbers "x,y")";
    QTest::addRow("substeps huge") << "substeps" << "99999999999" << "substeps=99999999999: must be <= 1000000";
    // Beyond int64 still an integer: too large, not "must be an integer".
    QTest::addRow("substeps beyond int64") << "substeps" << "99999999999999999999"
                                           << "substeps=99999999999999999999: must be <= 1000000";
    QTest::addRow("substeps below int64") << "substeps" << "-99999999999999999999"
                                          << "substeps=-99999999999999999999: must be >= 1";
    QTest::addRow("shortCircuit yes") << "shortCircuit" << "yes" << "shortCircuit=yes: must be true, false, 1 or 0";
    QTest::addRow("walls maybe") << "walls" << "maybe" << "walls=maybe: must be true, false, 1 or 0";
    QTest::addRow("width zero") << "width" << "0" << "width=0: must be > 0";
    QTest::addRow("height negative") << "height" << "-1" << "height=-1: must be > 0";
    QTest::addRow("unknown key") << "frictoin" << "0.2" << "frictoin=0.2: unknown key; the keys are model, massScale";
    QTest::addRow("key across Unicode lines") << QString::fromUtf8("fric\u2028tion") << "0.2"
                                              << "fric?tion=0.2: unknown key";
    QTest::addRow("params prefix is not a key") << "params.friction" << "0.2" << "params.friction=0.2: unknown key";
}

void TestSceneIo::setParamRejects()
{
    QFETCH(QString, key);
    QFETCH(QString, value);
    QFETCH(QString, message);
    World w;
    w.addMarble({1, 1}, 4);
    const World before = w;
    const QString error = q(setParam(w, key.toStdString(), value.toStdString()));
    QVERIFY2(error.startsWith(message), qPrintable(error));
    QCOMPARE(w.params, before.params); // refused settings change nothing
    QCOMPARE(w.stage, before.stage);
    QCOMPARE(w.mass, before.mass);
}

void TestSceneIo::setMassScaleRefreshesDerivedMasses()
{
    World w;
    w.addMarble({0, 0}, 10);
    w.addMarble({50, 0}, 10, {}, 7);
    QCOMPARE(setParam(w, "massScale", "2"), std::string());
    QCOMPARE(w.params.massScale, 2.0);
    QCOMPARE(w.mass[0], 20.0);
    QCOMPARE(w.mass[1], 7.0);
}

void TestSceneIo::printableTextIsOneLine_data()
{
    QTest::addColumn<QByteArray>("text");
    QTest::addColumn<int>("maxBytes"); // -1: no limit
    QTest::addColumn<QByteArray>("shown");
    QTest::addRow("plain") << QByteArray("lesson 3.json") << -1 << QByteArray("lesson 3.json");
    QTest::addRow("controls and DEL") << QByteArray("a\nb\rc\td\x7F\x1B") << -1 << QByteArray("a?b?c?d??");
    QTest::addRow("Unicode line breaks") << QByteArray("a\xC2\x85" "b\xE2\x80\xA8" "c\xE2\x80\xA9" "d") << -1
                                         << QByteArray("a?b?c?d");
    QTest::addRow("other characters kept") << QByteArray("\xC3\xA9\xE4\xB8\xAD\xE2\x80\xA7\xF0\x9F\x8E\xB1") << -1
                                           << QByteArray("\xC3\xA9\xE4\xB8\xAD\xE2\x80\xA7\xF0\x9F\x8E\xB1");
    QTest::addRow("Latin-1 byte") << QByteArray("caf\xE9.json") << -1 << QByteArray("caf?.json");
    QTest::addRow("cut sequence") << QByteArray("a\xE2\x80") << -1 << QByteArray("a??");
    // Not UTF-8 though each byte is in range: an overlong '/', a surrogate, past U+10FFFF.
    QTest::addRow("overlong") << QByteArray("\xE0\x80\xAF") << -1 << QByteArray("???");
    QTest::addRow("surrogate") << QByteArray("\xED\xA0\x80") << -1 << QByteArray("???");
    QTest::addRow("beyond U+10FFFF") << QByteArray("\xF4\x90\x80\x80") << -1 << QByteArray("????");
    // Shown as nothing, or turning the text around them in a terminal: named.
    QTest::addRow("invisible and bidirectional") << QByteArray("a\xEF\xBB\xBF" "b\xE2\x80\xAE" "c\xC2\xAD" "d\xE2\x80\x8B")
                                                 << -1 << QByteArray("a<U+FEFF>b<U+202E>c<U+00AD>d<U+200B>");
    QTest::addRow("cut at a character") << QByteArray("ab\xC3\xA9" "cd") << 3 << QByteArray("ab\xC3\xA9...");
}

void TestSceneIo::printableTextIsOneLine()
{
    QFETCH(QByteArray, text);
    QFETCH(int, maxBytes);
    QFETCH(QByteArray, shown);
    const std::string_view view(text.constData(), static_cast<std::size_t>(text.size()));
    const std::string out = maxBytes < 0 ? printableText(view) : printableText(view, static_cast<std::size_t>(maxBytes));
    QCOMPARE(QByteArray::fromStdString(out), shown);
}

void TestSceneIo::validateParams_data()
{
    QTest::addColumn<QString>("field");
    QTest::addColumn<double>("value");
    QTest::addColumn<QString>("model");
    QTest::addColumn<QString>("message");
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    QTest::addRow("defaults") << "" << 0.0 << "book" << "";
    QTest::addRow("friction -1") << "friction" << -1.0 << "book" << "params.friction: must be >= 0, got -1";
    QTest::addRow("friction nan") << "friction" << nan << "book" << "params.friction: must be a finite number, got nan";
    QTest::addRow("friction 1.5 book") << "friction" << 1.5 << "book" << "";
    QTest::addRow("friction 3 book") << "friction" << 3.0 << "book" << "";
    QTest::addRow("friction 0.999 exact") << "friction" << 0.999 << "exact" << "";
    QTest::addRow("friction 1 exact") << "friction" << 1.0 << "exact" << "params.friction: must be < 1 for the exact model, got 1";
    QTest::addRow("friction 1.5 impulse") << "friction" << 1.5 << "impulse"
                                          << "params.friction: must be < 1 for the impulse model, got 1.5";
    QTest::addRow("massScale 0") << "massScale" << 0.0 << "book" << "params.massScale: must be > 0, got 0";
    QTest::addRow("zeroThreshold -0.01") << "zeroThreshold" << -0.01 << "book" << "params.zeroThreshold: must be >= 0, got -0.01";
    QTest::addRow("pushScale inf") << "pushScale" << inf << "book" << "params.pushScale: must be a finite number, got inf";
    QTest::addRow("pushScale -10") << "pushScale" << -10.0 << "book" << "";
    QTest::addRow("frameMs -20") << "frameMs" << -20.0 << "book" << "params.frameMs: must be > 0, got -20";
    QTest::addRow("restitution 2") << "restitution" << 2.0 << "exact" << "params.restitution: must be between 0 and 1, got 2";
    QTest::addRow("gravity nan") << "gravity" << nan << "book" << "params.gravity: must be 2 finite numbers, got [nan, 0]";
    QTest::addRow("substeps 0") << "substeps" << 0.0 << "impulse" << "params.substeps: must be >= 1, got 0";
    QTest::addRow("substeps 2000000") << "substeps" << 2e6 << "impulse" << "params.substeps: must be <= 1000000, got 2000000";
}

void TestSceneIo::validateParams()
{
    QFETCH(QString, field);
    QFETCH(double, value);
    QFETCH(QString, model);
    QFETCH(QString, message);
    Params p;
    QVERIFY(parseModelName(model.toStdString(), p.model));
    if (field == "friction")
        p.friction = value;
    else if (field == "massScale")
        p.massScale = value;
    else if (field == "zeroThreshold")
        p.zeroThreshold = value;
    else if (field == "pushScale")
        p.pushScale = value;
    else if (field == "frameMs")
        p.frameMs = value;
    else if (field == "restitution")
        p.restitution = value;
    else if (field == "gravity")
        p.gravity.x = value;
    else if (field == "substeps")
        p.substeps = static_cast<int>(value);
    QCOMPARE(q(marbles::validateParams(p)), message);
}

QTEST_APPLESS_MAIN(TestSceneIo)
#include "tst_sceneio.moc"
