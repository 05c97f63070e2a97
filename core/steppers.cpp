#include "core/bookmodel.h"
#include "core/exactmodel.h"
#include "core/impulsemodel.h"
#include "core/world.h"

namespace marbles {

std::unique_ptr<Stepper> makeStepper(ModelKind kind)
{
    switch (kind) {
    case ModelKind::Book:
        return std::make_unique<BookModel>();
    case ModelKind::Impulse:
        return std::make_unique<ImpulseModel>();
    case ModelKind::Exact:
        return std::make_unique<ExactModel>();
    }
    return std::make_unique<BookModel>();
}

} // namespace marbles
