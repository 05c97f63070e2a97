#include "core/exactmodel.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

// The "exact" model, derived for teachers.
//
// 1. Motion between events. Each marble obeys dv/dt = -lambda v + g with lambda = -ln(1 - k):
//    then a whole frame without collisions multiplies v by e^{-lambda} = 1 - k, the book's factor.
//    Solving from a state (p0, v0) at time t0, with tau = t - t0:
//        v(tau) = v0 e^{-lambda tau} + g phi1(tau)
//        p(tau) = p0 + v0 phi1(tau) + g phi2(tau)
//    where phi1(tau) = (1 - e^{-lambda tau}) / lambda   (integral of e^{-lambda s}, -> tau as lambda -> 0)
//          phi2(tau) = (tau - phi1(tau)) / lambda        (integral of phi1,        -> tau^2 / 2).
//    phi1 uses expm1 and phi2 a Taylor series for small lambda tau, so that both stay accurate
//    to the last bits for every lambda >= 0 (k = 0 gives exactly tau and tau^2 / 2).
//
// 2. The key simplification. All marbles share lambda. Without gravity, p(tau) = p0 + v0 s with
//    s = phi1(tau): in the variable s every marble moves in a straight line at its "reduced
//    velocity" v0, and after a collision at s_c with velocity v_c the motion is again a straight
//    line in s. Impulses are linear in the velocities, so a whole frame is an ordinary hard-disk
//    event-driven simulation in s, over [0, s(1)] with s(1) = k / lambda (= 1 when k = 0); the
//    velocity at the end is the reduced velocity times e^{-lambda} = 1 - k.
//    With gravity the same holds for the *difference* of two marbles: g cancels in
//    p_i(tau) - p_j(tau) = d0 + (v_i - v_j) phi1(tau). So a marble-marble contact
//    |d0 + dv s|^2 = (r_i + r_j)^2 is always a quadratic in s, solved in closed form (below),
//    and s converts back to time with tau = -ln(1 - lambda s) / lambda.
//
// 3. Walls and pins feel gravity: a wall coordinate f(tau) = f0 + fv phi1 + fg phi2 has
//    f'' = (fg - lambda fv) e^{-lambda tau}, of constant sign, so f is convex or concave: at most
//    two roots, separated by the zero of f' (in closed form). We split there and find the first
//    root with a bracketed, safeguarded Newton iteration. For pins (and for marbles the collapse
//    guard holds still) the squared distance F(tau) = |d(tau)|^2 - R^2 is not so simple, so we
//    advance conservatively with a rigorous bound M >= |F''|: F(tau + u) >= F + F' u - M u^2 / 2,
//    so no contact can happen before the first positive root u of that quadratic. Near a
//    transversal root the step is Newton's step, so this converges fast, and it never skips a
//    contact, grazing ones included.
//
// 4. The calendar. Each marble has exactly one pending event: the earliest of its predicted
//    contacts, its next cell crossing, or the frame end. A tournament tree over the marbles gives
//    the earliest event in O(1) and updates in O(log N). When a marble's velocity changes, its
//    stamp increases; a pair event whose partner's stamp has changed since the prediction is stale
//    and only triggers a new prediction. Ties are broken by (time, kind, lower index, higher
//    index), so results never depend on anything but the World.
//
// 5. Robustness. Contacts are only resolved between approaching bodies. A pair that overlaps (by
//    rounding, or because the scene put it so) and approaches collides at once; one that overlaps
//    and separates is left alone. The quadratic's smaller root is computed in the citardauq form
//    c / (-b + sqrt(b^2 - a c)), free of cancellation.
//
// 6. Endless collision sequences, and the guard against them. Elastic hard disks (e = 1) without
//    gravity collide finitely often in a finite time, however fast they move: a frame at
//    1e6 px/frame is simply many real collisions, and each one keeps the kinetic energy to
//    rounding. So with e = 1 no collision is ever altered or counted against a marble; the only
//    degenerate case is a grazing pair whose approach is pure rounding noise, and the predictor
//    ignores it (grazingApproach, below). Two situations do produce infinitely many events in a
//    finite time, and only these trigger the guard:
//    - Inelastic collapse (e < 1 only). A cluster of marbles with e < 1 can collide infinitely
//      often in a finite time (each bounce smaller and sooner, the gaps shrinking geometrically).
//      After elasticAfterCollisions collisions of a marble in one frame its further collisions in
//      that frame are elastic, which stops the shrinking; after freezeAfterCollisions (or
//      freezeAfterWallBounces wall bounces) it is frozen: held at rest as an immovable body until
//      the frame ends (it leaves the frame with zero velocity). Momentum is not conserved by a
//      frozen marble; only such degenerate clusters ever reach this stage.
//    - Resting contact under gravity (any e). In a world of perfectly hard disks, "sitting" on a
//      floor, a pin or another marble is an infinite sequence of ever smaller bounces. A wall
//      bounce that would rise less than restHeightPx becomes resting contact (the marble slides
//      along the wall, its normal velocity and gravity held at zero) until a collision gives it a
//      normal velocity again. A marble-marble or marble-pin contact approaching slower than
//      sqrt(2 |g| restHeightPx) is a resting contact; after freezeAfterRestingContacts of them in
//      a frame the marble is frozen. Curved relative paths (gravity on a pin, or on a frozen or
//      wall-held partner) are tested by conservative advancement; a marble whose tests failed to
//      conclude freezeAfterRechecks times in a frame is frozen too. Without gravity none of
//      these can happen (restHeightPx gives a resting speed of 0, and all paths are straight).
//    Together they bound the work of every frame: a resting pile costs a few events per marble.

namespace marbles {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// Two marbles closer than this relative gap are "in contact" for the conservative advancement.
constexpr double contactGapTolerance = 1e-10;
// Conservative-advancement steps per prediction before handing back a "re-check later" event.
constexpr int advancementSteps = 64;
// A pair on straight relative paths approaches only if d.dv < -grazingApproach |d| |dv|, that is
// if the normal approach speed exceeds this fraction of the relative speed. Below it, the
// approach is rounding noise: after an elastic bounce the normal component is reversed, but
// rounding in the velocity components (a few ulp of |dv|) can leave a grazing pair "approaching"
// by ~1e-16 |dv| again, and it would bounce back and forth at the same instant for ever.
// Ignoring such an approach costs nothing measurable: a straight path that enters the contact
// circle at a grazing angle eps penetrates by at most R eps^2 / 2 (1e-24 R here).
constexpr double grazingApproach = 1e-12;

// Coefficients (-1)^n / (n + 2)! of the series of h(x) = (x - 1 + e^{-x}) / x^2.
constexpr int seriesTerms = 17;
constexpr auto phi2Series = [] {
    std::array<double, seriesTerms> c{};
    double factorial = 2.0;
    for (int n = 0; n < seriesTerms; ++n) {
        c[n] = ((n % 2) ? -1.0 : 1.0) / factorial;
        factorial *= n + 3;
    }
    return c;
}();

// phi1, phi2 and the decay e^{-lambda tau} for an elapsed time tau >= 0.
struct Flow {
    double decay = 1.0;
    double phi1 = 0.0;
    double phi2 = 0.0;
};

Flow flow(double lambda, double tau)
{
    Flow f;
    if (tau == 0.0)
        return f;
    if (lambda == 0.0) {
        f.phi1 = tau;
        f.phi2 = 0.5 * tau * tau;
        return f;
    }
    const double x = lambda * tau;
    const double em1 = std::expm1(-x);
    f.decay = 1.0 + em1;
    f.phi1 = -em1 / lambda;
    if (x < 0.5) {
        // phi2 = tau^2 h(x), h(x) = (x - 1 + e^{-x}) / x^2 = sum_n (-x)^n / (n + 2)!  (Horner;
        // 16 terms leave an error below 0.5^17 / 19! ~ 1e-22).
        double h = 0.0;
        for (int n = seriesTerms - 1; n >= 0; --n)
            h = phi2Series[n] + x * h;
        f.phi2 = tau * tau * h;
    } else {
        f.phi2 = (tau - f.phi1) / lambda;
    }
    return f;
}

// Inverse of phi1: the elapsed time at which phi1 reaches s (infinity if never).
double phi1Inverse(double lambda, double s)
{
    if (lambda == 0.0)
        return s;
    const double y = lambda * s;
    if (!(y < 1.0))
        return infinity;
    return -std::log1p(-y) / lambda;
}

// The first tau in [0, tauMax] at which f(tau) = f0 + fv phi1(tau) + fg phi2(tau) reaches <= 0
// while not increasing (a body arriving at a line it must not cross, or a centre arriving at a
// cell boundary). Infinity if none. f is convex or concave (f'' = (fg - lambda fv) e^{-lambda tau}).
double firstDownCrossing(double f0, double fv, double fg, double lambda, double tauMax)
{
    if (fg == 0.0) {
        // Linear in s = phi1(tau).
        if (!(fv < 0.0))
            return infinity;
        if (f0 <= 0.0)
            return 0.0;
        const double tau = phi1Inverse(lambda, f0 / -fv);
        return tau <= tauMax ? tau : infinity;
    }
    auto value = [&](double tau) {
        const Flow fl = flow(lambda, tau);
        return f0 + fv * fl.phi1 + fg * fl.phi2;
    };
    auto slope = [&](double tau) {
        const Flow fl = flow(lambda, tau);
        return fv * fl.decay + fg * fl.phi1;
    };
    // Zero of f' for tau > 0 exists only when fv and fg have opposite signs:
    // f'(tau) = fg/lambda + (fv - fg/lambda) e^{-lambda tau} = 0  =>  tau* = ln(1 - lambda fv / fg) / lambda,
    // or tau* = -fv / fg when lambda = 0.
    double turn = infinity;
    if ((fv < 0.0 && fg > 0.0) || (fv > 0.0 && fg < 0.0))
        turn = lambda == 0.0 ? -fv / fg : std::log1p(-lambda * fv / fg) / lambda;

    // The interval [a, b] of [0, tauMax] on which f decreases.
    double a = 0.0;
    double b = tauMax;
    const bool fallingAtStart = fv < 0.0 || (fv == 0.0 && fg < 0.0);
    if (fallingAtStart) {
        if (fg > 0.0)
            b = std::min(turn, tauMax);
    } else {
        if (!(fg < 0.0))
            return infinity; // rising for ever
        a = turn;
        if (!(a <= tauMax))
            return infinity;
    }
    const double fa = a == 0.0 ? f0 : value(a);
    if (fa <= 0.0)
        return a;
    const double fb = value(b);
    if (fb > 0.0)
        return infinity;
    // Bracketed, safeguarded Newton on [lo, hi] with f(lo) > 0 >= f(hi), f decreasing.
    double lo = a;
    double hi = b;
    double x = hi;
    double fx = fb;
    for (int it = 0; it < 200; ++it) {
        const double d = slope(x);
        double next = d < 0.0 ? x - fx / d : 0.5 * (lo + hi);
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        if (next == x || hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, hi))
            break;
        x = next;
        fx = value(x);
        if (fx > 0.0)
            lo = x;
        else
            hi = x;
        if (fx == 0.0)
            break;
    }
    // hi has f <= 0: the contact is reached (overlap at most a rounding error).
    return hi;
}

struct Contact {
    double tau = infinity; // elapsed time of contact, or of the re-check
    bool recheck = false;  // true: no contact before tau, predict again then
};

// Relative motion d(tau) = d0 + dv phi1 + dg phi2; contact when |d| = R while approaching.
// sMax = phi1(tauMax), computed once by the caller.
Contact firstContact(Vec2 d0, Vec2 dv, Vec2 dg, double R, double lambda, double tauMax, double sMax)
{
    Contact none;
    const double R2 = R * R;
    if (dg.x == 0.0 && dg.y == 0.0) {
        // Straight lines in s: |d0 + dv s|^2 = R^2, i.e. a s^2 + 2 b s + c = 0.
        const double b = dot(d0, dv);
        if (!(b < -grazingApproach * length(d0) * length(dv)))
            return none; // separating, or sliding past (within rounding): no contact ahead
        const double c = dot(d0, d0) - R2;
        if (c <= 0.0)
            return {0.0, false}; // touching or overlapping, and approaching: collide at once
        const double a = dot(dv, dv);
        const double disc = b * b - a * c;
        if (!(disc > 0.0))
            return none; // misses (or grazes without approach)
        const double s = c / (-b + std::sqrt(disc)); // citardauq form of (-b - sqrt(disc)) / a
        if (!(s <= sMax))
            return none;
        const double tau = std::min(phi1Inverse(lambda, s), tauMax);
        return {tau, false};
    }

    // Conservative advancement (see the header comment, point 3).
    const double tolF = 2.0 * R * contactGapTolerance * std::max(1.0, R);
    const double gNorm = length(dg);
    {
        // Quick rejection: the gap cannot close at the largest possible relative speed.
        const double reach = (length(dv) + gNorm * tauMax) * tauMax;
        if (length(d0) - R > reach)
            return none;
    }
    double tau = 0.0;
    for (int it = 0; it < advancementSteps; ++it) {
        const Flow f = flow(lambda, tau);
        const Vec2 d{d0.x + dv.x * f.phi1 + dg.x * f.phi2, d0.y + dv.y * f.phi1 + dg.y * f.phi2};
        const Vec2 w{dv.x * f.decay + dg.x * f.phi1, dv.y * f.decay + dg.y * f.phi1};
        const Vec2 acc{dg.x - lambda * w.x, dg.y - lambda * w.y};
        const double F = dot(d, d) - R2;
        const double F1 = 2.0 * dot(d, w);
        const double F2 = 2.0 * (dot(w, w) + dot(d, acc));
        const double rest = tauMax - tau;
        // Over [tau, tauMax]: |d'| <= V, |d''| <= A (d'' = acc e^{-lambda u}), |d| <= D.
        const double V = length(w) + gNorm * rest;
        const double A = length(acc);
        const double D = length(d) + V * rest;
        const double M = 2.0 * V * V + 2.0 * D * A; // >= |F''|
        double u;
        if (F <= tolF) {
            if (F1 < 0.0 || (F1 <= 0.0 && F2 < 0.0))
                return {tau, false};
            // Touching but separating (F' > 0, or F' = 0 and F'' >= 0). No contact can start
            // while F' stays >= 0. Two certified bounds: F'(tau + u) >= F1 - M u, and with
            // |F'''| <= M3 = 2 (3 V A + lambda D A) (as d''' = -lambda d''),
            // F'(tau + u) >= F1 + F2 u - M3 u^2 / 2. Take the longer safe step.
            const double M3 = 2.0 * (3.0 * V * A + lambda * D * A);
            const double u2 = M > 0.0 ? F1 / M : infinity;
            double u3 = 0.0;
            if (M3 > 0.0) {
                const double disc = F2 * F2 + 2.0 * M3 * F1;
                u3 = (F2 + std::sqrt(std::max(disc, 0.0))) / M3;
            } else if (F2 >= 0.0) {
                u3 = infinity;
            }
            u = std::max(u2, u3);
        } else if (M > 0.0) {
            u = 2.0 * F / (-F1 + std::sqrt(F1 * F1 + 2.0 * M * F));
        } else {
            u = F1 < 0.0 ? F / -F1 : infinity;
        }
        if (!(u <= rest))
            return none;
        tau += u;
    }
    // No verdict yet: ask to be predicted again from tau. Without any progress at all (a pair
    // exactly touching, at relative rest, with no relative acceleration) call it a contact: the
    // collision then finds no approach, and the collapse guard counts it.
    return {tau, tau > 0.0};
}

Vec2 unit(Vec2 u)
{
    const double len = length(u);
    if (!(len > 0.0) || !std::isfinite(len))
        return {};
    return {u.x / len, u.y / len};
}

} // namespace

ExactModel::ExactModel() = default;
ExactModel::~ExactModel() = default;

void ExactModel::positionAt(int i, double t, Vec2 &p, Vec2 &v) const
{
    const Flow f = flow(m_lambda, t - m_t0[i]);
    const Vec2 b = m_base[i];
    const Vec2 u = m_vel[i];
    const Vec2 g = m_grav[i];
    p = {b.x + u.x * f.phi1 + g.x * f.phi2, b.y + u.y * f.phi1 + g.y * f.phi2};
    v = {u.x * f.decay + g.x * f.phi1, u.y * f.decay + g.y * f.phi1};
}

void ExactModel::rebase(int i, double t)
{
    if (m_t0[i] == t)
        return;
    Vec2 p;
    Vec2 v;
    positionAt(i, t, p, v);
    m_base[i] = p;
    m_vel[i] = v;
    m_t0[i] = t;
}

void ExactModel::linkIntoBucket(int i, int bucket)
{
    m_bucketOf[i] = bucket;
    m_prev[i] = -1;
    m_next[i] = m_head[bucket];
    if (m_head[bucket] >= 0)
        m_prev[m_head[bucket]] = i;
    m_head[bucket] = i;
}

void ExactModel::unlinkFromBucket(int i)
{
    const int b = m_bucketOf[i];
    if (m_prev[i] >= 0)
        m_next[m_prev[i]] = m_next[i];
    else
        m_head[b] = m_next[i];
    if (m_next[i] >= 0)
        m_prev[m_next[i]] = m_prev[i];
    m_next[i] = m_prev[i] = -1;
}

void ExactModel::beginFrame(World &world)
{
    const int n = world.marbleCount();
    m_world = &world;
    double k = world.params.friction;
    assert(k >= 0.0 && k < 1.0);
    if (!(k >= 0.0))
        k = 0.0;
    if (!(k < 1.0))
        k = std::nextafter(1.0, 0.0);
    m_lambda = -std::log1p(-k);
    m_restitution = std::clamp(world.params.restitution, 0.0, 1.0);
    m_inelastic = m_restitution < 1.0;
    m_gravity = world.params.gravity;
    m_width = world.stage.width;
    m_height = world.stage.height;
    m_walls = world.stage.walls;
    m_restSpeed = std::sqrt(2.0 * length(m_gravity) * restHeightPx);

    m_base.resize(n);
    m_vel.resize(n);
    m_grav.resize(n);
    m_t0.assign(n, 0.0);
    m_radius.resize(n);
    m_invMass.resize(n);
    m_stamp.assign(n, 0);
    m_pairHits.assign(n, 0);
    m_restHits.assign(n, 0);
    m_recheckHits.assign(n, 0);
    m_wallHits.assign(n, 0);
    m_frozen.assign(n, 0);
    m_locked.assign(n, 0);
    m_cellX.resize(n);
    m_cellY.resize(n);
    m_bucketOf.resize(n);
    m_next.assign(n, -1);
    m_prev.assign(n, -1);
    m_event.resize(n);

    double rMax = 0.0;
    for (int i = 0; i < n; ++i) {
        // Pushes act at the frame boundary: an instant velocity change.
        m_base[i] = world.position[i];
        m_vel[i] = {world.velocity[i].x + world.acceleration[i].x,
                    world.velocity[i].y + world.acceleration[i].y};
        world.acceleration[i] = {};
        m_grav[i] = m_gravity;
        m_radius[i] = world.radius[i];
        m_invMass[i] = 1.0 / world.mass[i];
        rMax = std::max(rMax, m_radius[i]);
    }

    // Contacts happen at centre distances up to 2 rMax (marble-marble) or rMax (pins).
    const double w = m_walls ? m_width : std::max(m_width, 1.0);
    const double h = m_walls ? m_height : std::max(m_height, 1.0);
    const int items = n + static_cast<int>(world.pins.size());
    m_geometry = GridGeometry::fit(2.0 * rMax, w, h, items);
    // A few bodies are cheaper to test all against all than to track through a grid: at extreme
    // speeds the cell crossings would outnumber the collisions a hundred to one.
    m_singleCell = items <= singleCellItems;
    m_head.assign(m_singleCell ? 1 : m_geometry.bucketCount(), -1);
    // Link in descending index order, so each bucket list starts in ascending order.
    for (int i = n - 1; i >= 0; --i) {
        m_cellX[i] = m_singleCell ? 0 : m_geometry.coord(m_base[i].x);
        m_cellY[i] = m_singleCell ? 0 : m_geometry.coord(m_base[i].y);
        linkIntoBucket(i, m_singleCell ? 0 : m_geometry.bucket(m_cellX[i], m_cellY[i]));
    }
    m_pinGrid.build(m_geometry, world.pins.data(), static_cast<int>(world.pins.size()));
}

void ExactModel::endFrame(World &world)
{
    const int n = world.marbleCount();
    const double z = world.params.zeroThreshold;
    for (int i = 0; i < n; ++i) {
        Vec2 p;
        Vec2 v;
        positionAt(i, 1.0, p, v);
        if (m_frozen[i])
            v = {};
        // The zero threshold acts at the frame boundary, component by component.
        if (std::abs(v.x) <= z)
            v.x = 0.0;
        if (std::abs(v.y) <= z)
            v.y = 0.0;
        world.position[i] = p;
        world.velocity[i] = v;
    }
    m_world = nullptr;
}

bool ExactModel::earlier(int a, int b) const
{
    if (b < 0)
        return a >= 0;
    if (a < 0)
        return false;
    const Event &ea = m_event[a];
    const Event &eb = m_event[b];
    if (ea.time != eb.time)
        return ea.time < eb.time;
    if (ea.kind != eb.kind)
        return ea.kind < eb.kind;
    // Indices: for a pair the lower and higher marble, otherwise the marble and the object.
    auto lowHigh = [](int slot, const Event &e, int &lo, int &hi) {
        if (e.kind == EventKind::Pair) {
            lo = std::min(slot, e.other);
            hi = std::max(slot, e.other);
        } else {
            lo = slot;
            hi = e.other;
        }
    };
    int la, ha, lb, hb;
    lowHigh(a, ea, la, ha);
    lowHigh(b, eb, lb, hb);
    if (la != lb)
        return la < lb;
    if (ha != hb)
        return ha < hb;
    return a < b;
}

void ExactModel::buildTree()
{
    const int n = static_cast<int>(m_event.size());
    m_leaves = 1;
    while (m_leaves < n)
        m_leaves *= 2;
    m_tree.assign(2 * static_cast<std::size_t>(m_leaves), -1);
    for (int i = 0; i < n; ++i)
        m_tree[m_leaves + i] = i;
    for (int node = m_leaves - 1; node >= 1; --node) {
        const int l = m_tree[2 * node];
        const int r = m_tree[2 * node + 1];
        m_tree[node] = earlier(r, l) ? r : l;
    }
}

void ExactModel::updateTree(int i)
{
    for (int node = (m_leaves + i) / 2; node >= 1; node /= 2) {
        const int l = m_tree[2 * node];
        const int r = m_tree[2 * node + 1];
        const int winner = earlier(r, l) ? r : l;
        if (m_tree[node] == winner && winner != i)
            break; // nothing above can change
        m_tree[node] = winner;
    }
}

void ExactModel::predict(int i, double now)
{
    Event best;
    best.time = infinity;
    best.kind = EventKind::None;
    auto offer = [&](double time, EventKind kind, int other, std::uint32_t stamp) {
        Event e{time, kind, other, stamp};
        bool better;
        if (e.time != best.time)
            better = e.time < best.time;
        else if (e.kind != best.kind)
            better = e.kind < best.kind;
        else if (kind == EventKind::Pair)
            better = std::min(i, other) < std::min(i, best.other)
                || (std::min(i, other) == std::min(i, best.other) && std::max(i, other) < std::max(i, best.other));
        else
            better = other < best.other;
        if (better)
            best = e;
    };

    Vec2 p;
    Vec2 v;
    positionAt(i, now, p, v);
    const Vec2 g = m_grav[i];
    const double r = m_radius[i];
    const double tauEnd = 1.0 - now;
    double horizon = tauEnd; // elapsed time up to which contacts are searched

    int buckets[9] = {0};
    const int bucketCount = m_singleCell ? 1 : 9;
    if (!m_singleCell)
        m_geometry.neighbourhood(m_cellX[i], m_cellY[i], buckets);

    if (!m_frozen[i] && !m_singleCell) {
        // Cell crossings: the centre reaching a lattice line of its cell. The lines are only
        // book-keeping, so the lower and upper lines are approached "from inside".
        const std::int64_t kx = m_cellX[i];
        const std::int64_t ky = m_cellY[i];
        const double lx = m_geometry.line(kx), ux = m_geometry.line(kx + 1);
        const double ly = m_geometry.line(ky), uy = m_geometry.line(ky + 1);
        double tc[4] = {infinity, infinity, infinity, infinity};
        if (kx > -GridGeometry::coordLimit)
            tc[0] = firstDownCrossing(p.x - lx, v.x, g.x, m_lambda, tauEnd);
        if (kx < GridGeometry::coordLimit)
            tc[1] = firstDownCrossing(ux - p.x, -v.x, -g.x, m_lambda, tauEnd);
        if (ky > -GridGeometry::coordLimit)
            tc[2] = firstDownCrossing(p.y - ly, v.y, g.y, m_lambda, tauEnd);
        if (ky < GridGeometry::coordLimit)
            tc[3] = firstDownCrossing(uy - p.y, -v.y, -g.y, m_lambda, tauEnd);
        for (int side = 0; side < 4; ++side) {
            if (tc[side] <= tauEnd) {
                offer(now + tc[side], EventKind::Cross, side, 0);
                horizon = std::min(horizon, tc[side]);
            }
        }

    }
    if (!m_frozen[i]) {
        if (m_walls) {
            // Walls 0..3: left, right, top, bottom; contact when the centre is r from the edge.
            const double tw[4] = {
                firstDownCrossing(p.x - r, v.x, g.x, m_lambda, horizon),
                firstDownCrossing(m_width - r - p.x, -v.x, -g.x, m_lambda, horizon),
                firstDownCrossing(p.y - r, v.y, g.y, m_lambda, horizon),
                firstDownCrossing(m_height - r - p.y, -v.y, -g.y, m_lambda, horizon),
            };
            // The marble's own next event ends the search: it is predicted afresh after it.
            double firstWall = horizon;
            for (int wall = 0; wall < 4; ++wall) {
                if (tw[wall] <= horizon) {
                    offer(now + tw[wall], EventKind::Wall, wall, 0);
                    firstWall = std::min(firstWall, tw[wall]);
                }
            }
            horizon = firstWall;
        }

        if (!m_world->pins.empty()) {
            const double sHorizon = flow(m_lambda, horizon).phi1;
            auto testPin = [&](int pin) {
                const Vec2 q = m_world->pins[pin];
                const Contact c = firstContact({p.x - q.x, p.y - q.y}, v, g, r, m_lambda, horizon, sHorizon);
                if (c.tau <= horizon)
                    offer(now + c.tau, c.recheck ? EventKind::RecheckPin : EventKind::Pin, pin, 0);
            };
            if (m_singleCell) {
                for (int pin = 0; pin < static_cast<int>(m_world->pins.size()); ++pin)
                    testPin(pin);
            } else {
                for (int b : buckets) {
                    for (int k = m_pinGrid.begin(b); k < m_pinGrid.end(b); ++k)
                        testPin(m_pinGrid.items()[k]);
                }
            }
        }
    }

    // Other marbles in the 3 x 3 neighbourhood. Computed with the pair in canonical order
    // (lower index first), so both marbles of a pair predict bit-identical times.
    const double limit = m_frozen[i] ? tauEnd : horizon;
    const double sLimit = flow(m_lambda, limit).phi1;
    for (int nb = 0; nb < bucketCount; ++nb) {
        for (int j = m_head[buckets[nb]]; j >= 0; j = m_next[j]) {
            if (j == i || (m_frozen[i] && m_frozen[j]))
                continue;
            Vec2 pj;
            Vec2 vj;
            positionAt(j, now, pj, vj);
            const bool iLow = i < j;
            const Vec2 pa = iLow ? p : pj, pb = iLow ? pj : p;
            const Vec2 va = iLow ? v : vj, vb = iLow ? vj : v;
            const Vec2 ga = iLow ? g : m_grav[j], gb = iLow ? m_grav[j] : g;
            const Contact c = firstContact({pa.x - pb.x, pa.y - pb.y}, {va.x - vb.x, va.y - vb.y},
                                           {ga.x - gb.x, ga.y - gb.y}, r + m_radius[j], m_lambda, limit, sLimit);
            if (c.tau <= limit) {
                if (c.recheck)
                    offer(now + c.tau, EventKind::RecheckPair, j, 0);
                else
                    offer(now + c.tau, EventKind::Pair, j, m_stamp[j]);
            }
        }
    }
    m_event[i] = best;
}

void ExactModel::unlockMoved(int i)
{
    // A marble held against a wall keeps the hold only while nothing gives it a normal velocity.
    if ((m_locked[i] & 1) && m_vel[i].x != 0.0) {
        m_locked[i] &= ~1u;
        m_grav[i].x = m_gravity.x;
    }
    if ((m_locked[i] & 2) && m_vel[i].y != 0.0) {
        m_locked[i] &= ~2u;
        m_grav[i].y = m_gravity.y;
    }
}

bool ExactModel::countContact(int i, double t)
{
    if (++m_recheckHits[i] <= freezeAfterRechecks || m_frozen[i])
        return false;
    rebase(i, t);
    ++m_stamp[i];
    freeze(i);
    return true;
}

bool ExactModel::overLimit(int i) const
{
    // Collision counts only matter for e < 1 (inelastic collapse); resting contacts always.
    return m_restHits[i] > freezeAfterRestingContacts || (m_inelastic && m_pairHits[i] > freezeAfterCollisions);
}

void ExactModel::freeze(int i)
{
    if (m_frozen[i])
        return;
    m_frozen[i] = 1;
    m_vel[i] = {};
    m_grav[i] = {};
    m_invMass[i] = 0.0;
    ++m_frozenCount;
}

void ExactModel::collidePair(World &world, int i, int j, double t)
{
    rebase(i, t);
    rebase(j, t);
    const Vec2 n = unit({m_base[j].x - m_base[i].x, m_base[j].y - m_base[i].y});
    // Approach speed along the normal (from i towards j).
    const double approach = (m_vel[i].x - m_vel[j].x) * n.x + (m_vel[i].y - m_vel[j].y) * n.y;
    const double wi = m_invMass[i];
    const double wj = m_invMass[j];
    ++m_pairHits[i];
    ++m_pairHits[j];
    if (approach <= m_restSpeed) {
        ++m_restHits[i];
        ++m_restHits[j];
    }
    if (approach > 0.0 && wi + wj > 0.0) {
        // Impulse J along n with (v_i' - v_j').n = -e (v_i - v_j).n and m_i v_i + m_j v_j kept:
        // J = (1 + e) approach / (1/m_i + 1/m_j); v_i -= J/m_i n, v_j += J/m_j n.
        const bool elastic = m_inelastic
            && (m_pairHits[i] > elasticAfterCollisions || m_pairHits[j] > elasticAfterCollisions);
        const double e = elastic ? 1.0 : m_restitution;
        const double impulse = (1.0 + e) * approach / (wi + wj);
        const Vec2 inI = m_vel[i];
        const Vec2 inJ = m_vel[j];
        m_vel[i].x -= impulse * wi * n.x;
        m_vel[i].y -= impulse * wi * n.y;
        m_vel[j].x += impulse * wj * n.x;
        m_vel[j].y += impulse * wj * n.y;
        const std::int64_t frame = world.frame + 1;
        world.lastHit[i] = {frame, unit(inI), n, unit(m_vel[i])};
        world.lastHit[j] = {frame, unit(inJ), {-n.x, -n.y}, unit(m_vel[j])};
        ++m_collisionCount;
    }
    ++m_stamp[i];
    ++m_stamp[j];
    unlockMoved(i);
    unlockMoved(j);
    if (overLimit(i))
        freeze(i);
    if (overLimit(j))
        freeze(j);
}

void ExactModel::collidePin(World &world, int i, int pin, double t)
{
    rebase(i, t);
    const Vec2 q = world.pins[pin];
    const Vec2 n = unit({q.x - m_base[i].x, q.y - m_base[i].y});
    const double approach = dot(m_vel[i], n);
    ++m_pairHits[i];
    if (approach <= m_restSpeed)
        ++m_restHits[i];
    if (approach > 0.0) {
        // The pin is immovable (infinite mass): v' = v - (1 + e) (v.n) n.
        const bool elastic = m_inelastic && m_pairHits[i] > elasticAfterCollisions;
        const double e = elastic ? 1.0 : m_restitution;
        const Vec2 in = m_vel[i];
        m_vel[i].x -= (1.0 + e) * approach * n.x;
        m_vel[i].y -= (1.0 + e) * approach * n.y;
        world.lastHit[i] = {world.frame + 1, unit(in), n, unit(m_vel[i])};
        ++m_collisionCount;
    }
    ++m_stamp[i];
    unlockMoved(i);
    if (overLimit(i))
        freeze(i);
}

void ExactModel::collideWall(World &world, int i, int wall, double t)
{
    rebase(i, t);
    const int axis = wall / 2;        // 0: x, 1: y
    const bool upper = (wall % 2) == 1; // right or bottom
    double &x = axis == 0 ? m_base[i].x : m_base[i].y;
    double &v = axis == 0 ? m_vel[i].x : m_vel[i].y;
    double &g = axis == 0 ? m_grav[i].x : m_grav[i].y;
    const double r = m_radius[i];
    const double side = axis == 0 ? m_width : m_height;
    // Outward speed (towards this wall) and the push of gravity towards it.
    const double outward = upper ? v : -v;
    const double gOut = upper ? m_gravity.x * (axis == 0) + m_gravity.y * (axis == 1)
                              : -(m_gravity.x * (axis == 0) + m_gravity.y * (axis == 1));
    // Touching exactly: the solver stops at contact up to rounding.
    x = upper ? side - r : r;
    ++m_wallHits[i];
    const double e = m_restitution;
    // A bounce of speed w against gravity gOut rises w^2 / (2 gOut): below restHeightPx it is
    // resting contact instead.
    const double restSpeed = gOut > 0.0 ? std::sqrt(2.0 * gOut * restHeightPx) : 0.0;
    const Vec2 in = m_vel[i];
    bool hit = false;
    if (outward > 0.0) {
        v = -e * v;
        hit = true;
        ++m_collisionCount;
    }
    if (gOut > 0.0 && outward >= 0.0 && e * outward <= restSpeed && !m_frozen[i]) {
        v = 0.0;
        g = 0.0;
        m_locked[i] |= static_cast<std::uint8_t>(1u << axis);
    }
    if (hit) {
        Vec2 n{};
        (axis == 0 ? n.x : n.y) = upper ? 1.0 : -1.0;
        world.lastHit[i] = {world.frame + 1, unit(in), n, unit(m_vel[i])};
    }
    ++m_stamp[i];
    if (m_inelastic && m_wallHits[i] > freezeAfterWallBounces)
        freeze(i);
}

void ExactModel::crossCell(int i, int side)
{
    switch (side) {
    case 0: --m_cellX[i]; break;
    case 1: ++m_cellX[i]; break;
    case 2: --m_cellY[i]; break;
    default: ++m_cellY[i]; break;
    }
    const int b = m_geometry.bucket(m_cellX[i], m_cellY[i]);
    if (b != m_bucketOf[i]) {
        unlinkFromBucket(i);
        linkIntoBucket(i, b);
    }
}

void ExactModel::step(World &world)
{
    const int n = world.marbleCount();
    m_eventCount = 0;
    m_collisionCount = 0;
    m_frozenCount = 0;
    if (n == 0)
        return;
    beginFrame(world);

    // A world that already left finite numbers is only carried along (World::step reports it).
    bool finite = std::isfinite(m_lambda) && isFinite(m_gravity);
    for (int i = 0; i < n && finite; ++i)
        finite = isFinite(m_base[i]) && isFinite(m_vel[i]) && std::isfinite(m_radius[i]) && std::isfinite(m_invMass[i]);
    if (!finite) {
        endFrame(world);
        return;
    }

    for (int i = 0; i < n; ++i)
        predict(i, 0.0);
    buildTree();

    double now = 0.0;
    while (true) {
        const int i = m_tree[1];
        const Event ev = m_event[i];
        if (!(ev.time <= 1.0))
            break;
        now = std::max(now, ev.time);
        ++m_eventCount;
        switch (ev.kind) {
        case EventKind::Pair:
            if (m_stamp[ev.other] == ev.stamp) {
                collidePair(world, i, ev.other, now);
                predict(ev.other, now);
                updateTree(ev.other);
            }
            break;
        case EventKind::Pin:
            collidePin(world, i, ev.other, now);
            break;
        case EventKind::Wall:
            collideWall(world, i, ev.other, now);
            break;
        case EventKind::Cross:
            crossCell(i, ev.other);
            break;
        case EventKind::RecheckPin:
            countContact(i, now);
            break;
        case EventKind::RecheckPair:
            // Re-checks count against both marbles, so that even a frozen marble's re-checks
            // end: its partner freezes in turn, and frozen pairs are not predicted.
            countContact(i, now);
            if (countContact(ev.other, now)) {
                predict(ev.other, now);
                updateTree(ev.other);
            }
            break;
        case EventKind::None:
            break;
        }
        predict(i, now);
        updateTree(i);
    }
    endFrame(world);
}

} // namespace marbles
