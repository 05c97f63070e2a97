#include "ui/editframe.h"

#include "ui/scenedocument.h"

#include <QCoreApplication>
#include <QUndoCommand>

namespace marbles {

QString atFrame(const QString &text, std::int64_t frame)
{
    return frame > 0 ? QCoreApplication::translate("marbles", "%1 at frame %2").arg(text).arg(frame) : text;
}

void backToItsFrame(SceneDocument *document, std::int64_t frame)
{
    if (document->world().frame > frame)
        document->goToFrame(frame);
}

void toItsFrame(SceneDocument *document, std::int64_t &frame, QUndoCommand &command, const QString &name)
{
    // A delete redone after Step Back went before it applied at the frame stepped back to, its
    // Undo History text still naming the other: its undo then went to a frame where the kept
    // frames had no place for the marble, and the plot and the comparison started again there
    // (a regression tester's finding).
    document->goToFrame(frame);
    if (document->world().frame != frame) {
        frame = document->world().frame;
        command.setText(atFrame(name, frame));
    }
}

} // namespace marbles
