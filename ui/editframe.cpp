#include "ui/editframe.h"

#include "ui/scenedocument.h"

#include <QCoreApplication>

namespace marbles {

QString atFrame(const QString &text, std::int64_t frame)
{
    return frame > 0 ? QCoreApplication::translate("marbles", "%1 at frame %2").arg(text).arg(frame) : text;
}

FramedCommand::FramedCommand(SceneDocument *document)
    : m_document(document)
    , m_frame(document->world().frame)
{
}

void FramedCommand::setName(const QString &name)
{
    m_name = name;
    setText(atFrame(m_name, m_frame));
}

void FramedCommand::toItsFrame()
{
    m_document->goToFrame(m_frame);
    if (m_document->world().frame != m_frame) {
        m_frame = m_document->world().frame;
        setText(atFrame(m_name, m_frame));
    }
}

void FramedCommand::backToItsFrame()
{
    if (m_document->world().frame > m_frame)
        m_document->goToFrame(m_frame);
}

} // namespace marbles
