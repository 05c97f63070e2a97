#include "core/world.h"

#include <cassert>

namespace marbles {

std::string_view modelName(ModelKind kind)
{
    switch (kind) {
    case ModelKind::Book:
        return "book";
    case ModelKind::Impulse:
        return "impulse";
    case ModelKind::Exact:
        return "exact";
    }
    return "book";
}

bool parseModelName(std::string_view name, ModelKind &kind)
{
    for (ModelKind k : {ModelKind::Book, ModelKind::Impulse, ModelKind::Exact}) {
        if (name == modelName(k)) {
            kind = k;
            return true;
        }
    }
    return false;
}

World::World() = default;
World::~World() = default;
World::World(World &&) noexcept = default;
World &World::operator=(World &&) noexcept = default;

// A copy is a snapshot of the state; the stepper holds only caches, so the copy makes its own.
World::World(const World &other)
    : stage(other.stage)
    , params(other.params)
    , position(other.position)
    , velocity(other.velocity)
    , acceleration(other.acceleration)
    , radius(other.radius)
    , mass(other.mass)
    , info(other.info)
    , lastHit(other.lastHit)
    , pins(other.pins)
    , pinExtraJson(other.pinExtraJson)
    , pushes(other.pushes)
    , paramsExtraJson(other.paramsExtraJson)
    , stageExtraJson(other.stageExtraJson)
    , sceneExtraJson(other.sceneExtraJson)
    , frame(other.frame)
{
}

World &World::operator=(const World &other)
{
    if (this != &other) {
        World copy(other);
        *this = std::move(copy);
    }
    return *this;
}

int World::addMarble(Vec2 p, double r, Vec2 v, double explicitMass)
{
    position.push_back(p);
    velocity.push_back(v);
    acceleration.push_back({});
    radius.push_back(r);
    MarbleInfo mi;
    mi.hasMass = explicitMass > 0.0;
    mass.push_back(mi.hasMass ? explicitMass : params.massScale * r);
    info.push_back(std::move(mi));
    lastHit.push_back({});
    return marbleCount() - 1;
}

void World::removeMarble(int i)
{
    assert(i >= 0 && i < marbleCount());
    if (i < 0 || i >= marbleCount())
        return;
    position.erase(position.begin() + i);
    velocity.erase(velocity.begin() + i);
    acceleration.erase(acceleration.begin() + i);
    radius.erase(radius.begin() + i);
    mass.erase(mass.begin() + i);
    info.erase(info.begin() + i);
    lastHit.erase(lastHit.begin() + i);
    std::vector<Push> kept;
    kept.reserve(pushes.size());
    for (Push p : pushes) {
        if (p.marble == i)
            continue;
        if (p.marble > i)
            --p.marble;
        kept.push_back(p);
    }
    pushes = std::move(kept);
}

int World::addPin(Vec2 q)
{
    pins.push_back(q);
    pinExtraJson.emplace_back();
    return static_cast<int>(pins.size()) - 1;
}

void World::removePin(int j)
{
    assert(j >= 0 && j < static_cast<int>(pins.size()));
    if (j < 0 || j >= static_cast<int>(pins.size()))
        return;
    pins.erase(pins.begin() + j);
    pinExtraJson.erase(pinExtraJson.begin() + j);
}

void World::setRadius(int i, double r)
{
    assert(i >= 0 && i < marbleCount());
    if (i < 0 || i >= marbleCount())
        return;
    radius[i] = r;
    if (!info[i].hasMass)
        mass[i] = params.massScale * r;
}

void World::setExplicitMass(int i, double m)
{
    assert(i >= 0 && i < marbleCount());
    if (i < 0 || i >= marbleCount())
        return;
    info[i].hasMass = m > 0.0;
    mass[i] = info[i].hasMass ? m : params.massScale * radius[i];
}

void World::setMassScale(double s)
{
    params.massScale = s;
    refreshMasses();
}

void World::refreshMasses()
{
    for (int i = 0; i < marbleCount(); ++i) {
        if (!info[i].hasMass)
            mass[i] = params.massScale * radius[i];
    }
}

void World::push(int i, Vec2 at)
{
    assert(i >= 0 && i < marbleCount());
    if (i < 0 || i >= marbleCount())
        return;
    const Vec2 add = pushAcceleration(i, at);
    acceleration[i].x += add.x;
    acceleration[i].y += add.y;
}

Vec2 World::pushAcceleration(int i, Vec2 at) const
{
    // The book's hitMarble: force = (marble centre - click point), a += force * 10 / mass.
    // Evaluated as ((p - c) * pushScale) / m, the book's order of operations.
    const auto k = static_cast<std::size_t>(i);
    const Vec2 p = position[k];
    return {((p.x - at.x) * params.pushScale) / mass[k], ((p.y - at.y) * params.pushScale) / mass[k]};
}

Vec2 World::rescaledPush(Vec2 a, double massWas, double pushScaleWas, double mass, double pushScale)
{
    // A push scale of 0 leaves nothing waiting to work out again.
    if ((massWas == mass && pushScaleWas == pushScale) || pushScaleWas == 0.0)
        return a;
    const auto one = [&](double x) {
        double force = x * massWas; // (p - c) * pushScaleWas
        if (pushScale != pushScaleWas)
            force = force / pushScaleWas * pushScale;
        return force / mass;
    };
    return {one(a.x), one(a.y)};
}

void World::applyScriptedPushes()
{
    for (const Push &p : pushes) {
        if (appliesNow(p))
            push(p.marble, p.at);
    }
}

Vec2 World::scriptedPushDue(int i) const
{
    Vec2 due;
    for (const Push &p : pushes) {
        if (p.marble == i && appliesNow(p)) {
            const Vec2 add = pushAcceleration(i, p.at);
            due.x += add.x;
            due.y += add.y;
        }
    }
    return due;
}

StepResult World::step()
{
    // Scripted pushes for this frame, in file order, all before the update: a push reads only
    // the marble's own position, which no other marble's update changes, so this is the same
    // as applying each just before its marble is processed.
    applyScriptedPushes();
    if (!m_stepper || m_stepperKind != params.model) {
        m_stepper = makeStepper(params.model);
        m_stepperKind = params.model;
    }
    m_stepper->step(*this);
    ++frame;

    StepResult result;
    result.badMarble = m_stepper->leftAllFinite() ? -1 : firstNonFiniteMarble();
    result.finite = result.badMarble < 0;
    result.heldMarbles = m_stepper->lastHeldCount();
    return result;
}

int World::firstNonFiniteMarble() const
{
    for (int i = 0; i < marbleCount(); ++i) {
        if (!isFinite(position[i]) || !isFinite(velocity[i]))
            return i;
    }
    return -1;
}

double World::kineticEnergy() const
{
    double e = 0.0;
    for (int i = 0; i < marbleCount(); ++i)
        e += 0.5 * mass[i] * (velocity[i].x * velocity[i].x + velocity[i].y * velocity[i].y);
    return e;
}

Vec2 World::momentum() const
{
    Vec2 p;
    for (int i = 0; i < marbleCount(); ++i) {
        p.x += mass[i] * velocity[i].x;
        p.y += mass[i] * velocity[i].y;
    }
    return p;
}

} // namespace marbles
