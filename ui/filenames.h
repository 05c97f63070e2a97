#pragma once

#include <QRegularExpression>
#include <QString>

namespace marbles {

/// A file name's stem made from a scene's name, as the save and export dialogs offer it:
/// "Preset: Pachinko board" gives "pachinko-board", "collision.marbles.json" "collision"; ""
/// where nothing is left. Nothing a file system might refuse ("Four marbles (Figure 11.8)"); the
/// letters of every language kept ("Übung Stoß" gives "übung-stoß": ASCII-only, it gave "bung-sto").
inline QString sceneFileStem(QString name)
{
    if (name.startsWith(QStringLiteral("Preset: ")))
        name.remove(0, 8);
    for (const QString &end : {QStringLiteral(".marbles.json"), QStringLiteral(".json")}) {
        if (name.endsWith(end, Qt::CaseInsensitive))
            name.chop(end.size());
    }
    name = name.trimmed().toLower();
    static const QRegularExpression notWord(QStringLiteral("[^\\w.-]+"), QRegularExpression::UseUnicodePropertiesOption);
    name.replace(notWord, QStringLiteral("-"));
    name.remove(QRegularExpression(QStringLiteral("^-+|-+$")));
    return name;
}

} // namespace marbles
