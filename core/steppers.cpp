#include "core/bookmodel.h"
#include "core/world.h"

#include <stdexcept>

namespace marbles {

std::unique_ptr<Stepper> makeStepper(ModelKind kind)
{
    switch (kind) {
    case ModelKind::Book:
        return std::make_unique<BookModel>();
    case ModelKind::Impulse:
    case ModelKind::Exact:
        break;
    }
    throw std::logic_error("model not built in yet");
}

} // namespace marbles
