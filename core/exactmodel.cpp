#include "core/exactmodel.h"

#include "core/pairimpulse.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
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
//    The functions 1, phi1(t) and phi2(t) span all solutions (they span 1, e^{-lambda t} and t),
//    so each marble's trajectory is stored once per frame-clock, not per marble clock:
//        p(t) = a + b phi1(t) + g phi2(t),   v(t) = b e^{-lambda t} + g phi1(t),
//    t the time since the start of the frame, (a, b) constant between the marble's events. After
//    an event at t_c with new (p, v): b = (v - g phi1(t_c)) e^{lambda t_c}, a = p - b phi1 - g phi2.
//    phi1(t) and phi2(t) are computed once per event time, so looking up any neighbour's position
//    and velocity "now" costs a few multiplications and no exponential.
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
// 4. The calendar. Each marble keeps two things: its best contact (the earliest of the wall,
//    pin and marble contacts it has looked at since its velocity last changed) and its next grid
//    event (below). Its event is the earlier of the two; a calendar queue holds only the marbles
//    whose event falls inside the frame (in a calm crowd most marbles have none, and cost nothing
//    after the first look): [0, 1] is cut into as many equal time slots as the first look found
//    events, each marble sits in its event's slot, and the next event is the least (time, tie)
//    of the first non-empty slot (a small heap), the order one heap of them all would give.
//    When a marble's velocity changes, its stamp increases; a pair event whose partner's stamp
//    has changed since the prediction is stale and only triggers a new prediction, so the
//    calendar never holds more than N entries. Every contact event (stale or not) triggers a
//    full new prediction of its marble when it comes due, which allows two savings:
//    - a search for the contacts of i stops at the earlier of i's and the partner's best
//      contact (anything later will be found again by whichever of them is predicted first);
//    - a grid event keeps the best contact and only looks for new partners if the marble's
//      neighbourhood changed.
//    At the start of a frame every pair of neighbours is tested once, for both marbles, from the
//    moving side (without gravity, two marbles at rest cannot meet, so a crowd at rest costs
//    almost nothing). Ties are broken by (time, kind, lower rank, higher rank, marble's rank),
//    a marble's rank being its place in the bucket order of all the marbles (its index, below),
//    so results never depend on anything but the World.
//
//    The grid. At the start of a frame the marbles are sorted by bucket and renumbered, so the
//    marbles of a bucket (and of three neighbouring buckets in a row) lie side by side in memory.
//    Each marble is anchored at its position then. Cells are wider than the contact distance
//    D = 2 rMax by twice a margin m: while every marble stays within m of its anchor (in x and in
//    y), two marbles anchored in cells that are not neighbours are more than (D + 2m) - 2m = D
//    apart, so only the 3 x 3 neighbourhood can hold partners. A marble that strays to m from
//    its anchor (its grid event, rare when m exceeds a frame's travel) is anchored afresh where
//    it is, and if that is in another bucket it joins that bucket's overflow list and looks for
//    partners in its new neighbourhood. The lattice is folded as described in broadphase.h.
//    A few marbles far larger than the rest would make every cell hold dozens of marbles: they
//    are left out of the grid (RadiusSplit in broadphase.h), whose rMax is then the largest of
//    the others. They come first in the arrays, in no bucket and without grid events; each
//    marble's neighbourhood includes them, and theirs is every marble anchored in the cells
//    their path can reach before the frame ends (see bucketsInReach()), and every pin.
//
//    Sleepers. In a large world where nearly every marble is at rest, reading, renumbering and
//    writing back every marble each frame would cost far more than the few that move. Marbles at
//    rest (velocity and push exactly +0, no gravity) then stay in a layer of their own, sorted by
//    bucket and kept from frame to frame, and only the others are renumbered: a sleeper's rank
//    (above) still counts it, and the first look meets the sleepers of a bucket in their places
//    among its awake marbles, so every test, tie and pruning happens as if all were renumbered.
//    A sleeper joins the frame's arrays (at the end, as a marble still in its bucket) as soon as a
//    moving marble's path may reach it; one that nothing reaches is left as it is, which is what
//    the frame would do to it. Each frame first checks every sleeper against the World (same
//    position, radius and mass bits, still at rest, nothing pending); one that changed, or that
//    the last frame set moving, leaves the layer.
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
//    - Bodies that cannot fit (any e). Disks that start overlapping, or that cannot all fit where
//      they are, can be sent from one contact straight into the next at the same instant, for
//      ever: a marble wider than the stage between its two walls, one overlapping two pins, or
//      two marbles side by side in a stage narrower than both. A marble too wide for the stage
//      along an axis is held between the walls on that axis (stopped along it where it is, as in
//      resting contact). Otherwise such sequences take no time: once more than
//      freezeAfterInstantCollisions collisions per marble of the world have happened at one
//      instant, every marble that collides again at that instant is frozen as above. Near-misses
//      (a marble just narrower than the gap it bounces in) do take time, ever so little: a marble
//      that collides more than freezeAfterElasticCollisions times, or bounces off walls more than
//      freezeAfterWallBounces times, in one frame is frozen too. Real elastic motion stays far
//      below these counts.
//    Together they bound the work of every frame: a resting pile costs a few events per marble.

namespace marbles {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// v.assign(count, value), with the capacity grown by doubling, as push_back grows it: a size that
// creeps up from frame to frame (the calendar's slots follow the events found) then reallocates a
// few times in all, not in every frame that finds one event more.
template<typename Vector>
void assignGrowingByDoubling(Vector &v, std::size_t count, typename Vector::value_type value)
{
    if (v.capacity() < count)
        v.reserve(2 * count);
    v.assign(count, value);
}

// Two marbles closer than this relative gap are "in contact" for the conservative advancement.
constexpr double contactGapTolerance = 1e-10;
// Conservative-advancement steps per prediction before handing back a "re-check later" event.
constexpr int advancementSteps = 64;
// How far past its wall (side px wide, the marble r in radius) a marble still counts as touching
// it: the solver's rounding at a wall contact (collideWall()), and the end of a frame's check
// (keepWithinWalls()).
inline double wallTouchTolerance(double side, double r)
{
    return 1e-9 * (side + r);
}
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
double firstDownCrossingCurved(double f0, double fv, double fg, double lambda, double tauMax);

inline double firstDownCrossing(double f0, double fv, double fg, double lambda, double tauMax)
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
    return firstDownCrossingCurved(f0, fv, fg, lambda, tauMax);
}

double firstDownCrossingCurved(double f0, double fv, double fg, double lambda, double tauMax)
{
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

double straightContactScaled(double dx, double dy, double dvx, double dvy, double R, double sMax);

// Straight relative paths (no relative acceleration): d(s) = d0 + dv s in s = phi1(tau). The s of
// the first contact while approaching, 0 if touching or overlapping and approaching already, or
// infinity if none with s <= sMax. Scalar arguments: this is the innermost loop of the model.
inline double straightContact(double dx, double dy, double dvx, double dvy, double R, double sMax)
{
    constexpr double largest = std::numeric_limits<double>::max();
    // |d0 + dv s|^2 = R^2, i.e. a s^2 + 2 b s + c = 0.
    const double b = dx * dvx + dy * dvy;
    const double d2 = dx * dx + dy * dy;
    // Products beyond a double (speeds or distances of about 1e154 and more): solved scaled.
    if (!((std::abs(b) <= largest) & (d2 <= largest))) [[unlikely]]
        return straightContactScaled(dx, dy, dvx, dvy, R, sMax);
    const double c = d2 - R * R;
    // Most pairs fail here: separating or sliding past (b >= 0), or too far to close the gap in
    // time (the root below is s = c / (-b + sqrt(disc)) >= c / (-2 b) > sMax). One branch for
    // both (no short circuit): which of them fails is unpredictable.
    if (!((b < 0.0) & (c <= -2.0 * b * sMax)))
        return infinity;
    const double a = dvx * dvx + dvy * dvy;
    if (!((b * b <= largest) & (d2 * a <= largest))) [[unlikely]]
        return straightContactScaled(dx, dy, dvx, dvy, R, sMax);
    if (b * b <= grazingApproach * grazingApproach * d2 * a)
        return infinity; // an approach within rounding of zero (b < -grazingApproach |d0| |dv| fails)
    if (c <= 0.0)
        return 0.0; // touching or overlapping, and approaching: collide at once
    const double disc = b * b - a * c;
    if (!(disc > 0.0))
        return infinity; // misses (or grazes without approach)
    const double s = c / (-b + std::sqrt(disc)); // citardauq form of (-b - sqrt(disc)) / a
    return s <= sMax ? s : infinity;
}

// straightContact() where its squares and products overflow (a pair 1e160 px/frame apart in
// speed went through each other, every test failing on infinities): the same equation with d0
// and R scaled by 2^-f and dv by 2^-e, powers of two that bring them below 1 and change no bit of
// a mantissa. |D + U sigma| = R 2^-f with s = sigma 2^(f - e).
double straightContactScaled(double dx, double dy, double dvx, double dvy, double R, double sMax)
{
    // Every number finite, or no contact: std::max passes over a NaN after the first argument,
    // and a NaN y (a marble's place, or a speed, once a world has left finite numbers) came back
    // here from straightContact() for ever, until the stack ran out (a crash).
    if (!(std::isfinite(dx) && std::isfinite(dy) && std::isfinite(dvx) && std::isfinite(dvy) && std::isfinite(R)))
        return infinity;
    const double speed = std::max(std::abs(dvx), std::abs(dvy));
    const double size = std::max({std::abs(dx), std::abs(dy), R});
    if (!(speed > 0.0) || !(size > 0.0))
        return infinity;
    int e = 0;
    int f = 0;
    std::frexp(speed, &e);
    std::frexp(size, &f);
    const double sigma = straightContact(std::ldexp(dx, -f), std::ldexp(dy, -f), std::ldexp(dvx, -e), std::ldexp(dvy, -e),
                                         std::ldexp(R, -f), std::ldexp(sMax, e - f));
    const double s = std::ldexp(sigma, f - e);
    return s <= sMax ? s : infinity;
}

// Relative motion d(tau) = d0 + dv phi1 + dg phi2; contact when |d| = R while approaching, at
// tau <= tauMax. sMax >= phi1(tauMax) is a bound computed once by the caller (for a quick rejection).
Contact firstContact(Vec2 d0, Vec2 dv, Vec2 dg, double R, double lambda, double tauMax, double sMax)
{
    Contact none;
    const double R2 = R * R;
    if (dg.x == 0.0 && dg.y == 0.0) {
        const double s = straightContact(d0.x, d0.y, dv.x, dv.y, R, sMax);
        if (!(s <= sMax))
            return none;
        const double tau = phi1Inverse(lambda, s);
        if (!(tau <= tauMax))
            return none;
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

} // namespace

ExactModel::ExactModel() = default;
ExactModel::~ExactModel() = default;

namespace {

constexpr int sides = 4;
constexpr double noTime = std::numeric_limits<double>::infinity();

// Adds one to a guard count, stopping at the largest value its type holds.
template <typename Count>
Count count(Count &c)
{
    if (c < std::numeric_limits<Count>::max())
        ++c;
    return c;
}

} // namespace

void ExactModel::setNow(double t)
{
    m_now = t;
    const Flow f = flow(m_lambda, t);
    m_decayNow = f.decay;
    m_phi1Now = f.phi1;
    m_phi2Now = f.phi2;
    // phi1 of the time left in the frame: phi1(1) - phi1(t) = e^{-lambda t} phi1(1 - t). Only a
    // bound for quick rejections, so a hair of slack covers the rounding.
    m_sLeft = (m_phi1End - m_phi1Now) / m_decayNow * (1.0 + 1e-12);
}

Vec2 ExactModel::gravityOf(const Body &body) const
{
    return {(body.gravityOff & 1) ? 0.0 : m_gravity.x, (body.gravityOff & 2) ? 0.0 : m_gravity.y};
}

void ExactModel::stateAt(const Body &body, Vec2 &p, Vec2 &v) const
{
    const Vec2 g = gravityOf(body);
    p = {body.a.x + body.b.x * m_phi1Now + g.x * m_phi2Now, body.a.y + body.b.y * m_phi1Now + g.y * m_phi2Now};
    v = {body.b.x * m_decayNow + g.x * m_phi1Now, body.b.y * m_decayNow + g.y * m_phi1Now};
}

void ExactModel::setState(int i, Vec2 p, Vec2 v)
{
    // Invert v = b e^{-lambda t} + g phi1 and p = a + b phi1 + g phi2 at t = now.
    Body &body = m_body[i];
    const Vec2 g = gravityOf(body);
    body.b = {(v.x - g.x * m_phi1Now) / m_decayNow, (v.y - g.y * m_phi1Now) / m_decayNow};
    body.a = {p.x - body.b.x * m_phi1Now - g.x * m_phi2Now, p.y - body.b.y * m_phi1Now - g.y * m_phi2Now};
}

void ExactModel::setContact(int i, const Event &e)
{
    Record &rec = m_rec[i];
    rec.contactKind = e.kind;
    rec.contactOther = e.other;
    rec.contactStamp = e.stamp;
    m_body[i].contactTime = e.time;
}

template<typename Map>
[[gnu::always_inline]] inline int ExactModel::runsAround(int bucket, int out[rangeSlots], Map map) const
{
    // The 3 x 3 buckets around `bucket` as runs [first, last) of consecutive buckets, row by row
    // (the three buckets of a row are consecutive, except where the row wraps around: then two
    // runs), each end given as map(bucket).
    const int nx = m_geometry.bucketsX();
    const int ny = m_geometry.bucketsY();
    const int by = bucket / nx;
    const int bx = bucket - by * nx;
    const int rows[3] = {(by == 0 ? ny - 1 : by - 1) * nx, by * nx, (by == ny - 1 ? 0 : by + 1) * nx};
    int count = 0;
    for (const int row : rows) {
        if (bx == 0) {
            out[2 * count] = map(row);
            out[2 * count + 1] = map(row + 2);
            ++count;
            out[2 * count] = map(row + nx - 1);
            out[2 * count + 1] = map(row + nx);
        } else if (bx == nx - 1) {
            out[2 * count] = map(row + nx - 2);
            out[2 * count + 1] = map(row + nx);
            ++count;
            out[2 * count] = map(row);
            out[2 * count + 1] = map(row + 1);
        } else {
            out[2 * count] = map(row + bx - 1);
            out[2 * count + 1] = map(row + bx + 2);
        }
        ++count;
    }
    return count;
}

int ExactModel::neighbourRanges(int i, int out[rangeSlots]) const
{
    // The 3 x 3 buckets around i's as ranges of internal indices (a run of buckets holds
    // consecutive indices), and the oversize marbles 0 .. m_oversize - 1. An oversize marble's
    // partners are all marbles.
    if (m_singleCell) {
        out[0] = 0;
        out[1] = m_count;
        return 1;
    }
    const int bucket = m_body[i].bucket;
    if (m_oversize > 0) [[unlikely]]
        return oversizeRanges(bucket, out);
    return runsAround(bucket, out, [&](int b) { return m_start[b]; });
}

int ExactModel::oversizeRanges(int bucket, int out[rangeSlots]) const
{
    // neighbourRanges() while some marbles are left out of the grid.
    if (bucket < 0) {
        out[0] = 0;
        out[1] = m_count;
        return 1;
    }
    const int count = runsAround(bucket, out, [&](int b) { return m_start[b]; });
    out[2 * count] = 0;
    out[2 * count + 1] = m_oversize;
    return count + 1;
}

int ExactModel::sleeperRanges(int i, int out[rangeSlots]) const
{
    // The same buckets as ranges of the sleepers' layer.
    return runsAround(m_body[i].bucket, out, [&](int b) { return m_sleepStart[b]; });
}

int ExactModel::neighbourBuckets(int i, int out[9]) const
{
    if (m_singleCell) {
        out[0] = 0;
        return 1;
    }
    if (m_body[i].bucket < 0)
        return 0; // oversize: tested against every pin and marble, in no overflow list
    m_geometry.bucketNeighbourhood(m_body[i].bucket, out);
    return 9;
}

namespace {

// The first marble at or after w whose flag (0 or 1) is 0, or n: eight flags at a time while
// they are all set.
int nextOutsideLayer(const std::uint8_t *inLayer, int w, int n)
{
    constexpr std::uint64_t allSet = 0x0101010101010101;
    while (w + 8 <= n) {
        std::uint64_t eight;
        std::memcpy(&eight, inLayer + w, sizeof eight);
        if (eight != allSet)
            break;
        w += 8;
    }
    while (w < n && inLayer[w])
        ++w;
    return w;
}

} // namespace

double ExactModel::localSpacing(const World &world, double side)
{
    // The spacing of the marbles as a marble meets them: with the stage cut into squares of
    // about `side` px (about four marbles each if spread evenly), a marble shares its square with
    // sum(count^2) / n marbles on average (itself included), so each of them has a square's area
    // over that of room: sqrt of it is the spacing. Even spread gives about 0.9 of the stage's area per
    // marble; a clump, its own. Positions off the stage (or not finite) count in the edge squares.
    const int n = world.marbleCount();
    const double width = std::max(m_width, 1.0);
    const double height = std::max(m_height, 1.0);
    // At most 4096 squares a side (a stage of absurd size gets larger ones).
    const int nx = static_cast<int>(std::clamp(std::ceil(width / side), 1.0, 4096.0));
    const int ny = static_cast<int>(std::clamp(std::ceil(height / side), 1.0, 4096.0));
    m_spacingCount.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
    const double inverseX = nx / width;
    const double inverseY = ny / height;
    auto cell = [](double t, int cells) {
        // t >= 0 fails for NaN too: the first square.
        return !(t >= 0.0) ? 0 : t < cells ? static_cast<int>(t) : cells - 1;
    };
    std::int64_t shared = 0;
    for (int w = 0; w < n; ++w) {
        const Vec2 p = world.position[w];
        const std::size_t k = static_cast<std::size_t>(cell(p.x * inverseX, nx))
            + static_cast<std::size_t>(nx) * static_cast<std::size_t>(cell(p.y * inverseY, ny));
        // Sum of count^2 as it grows: (c + 1)^2 - c^2 = 2 c + 1.
        shared += 2 * static_cast<std::int64_t>(m_spacingCount[k]++) + 1;
    }
    return std::sqrt(width / nx * (height / ny) / (static_cast<double>(shared) / n));
}

void ExactModel::beginFrame(World &world)
{
    const int n = world.marbleCount();
    assert(n < (1 << 30)); // indices fit the packed tie-break of the calendar
    m_world = &world;
    const double k = newtonianFriction(world.params.friction);
    m_lambda = -std::log1p(-k);
    const Flow end = flow(m_lambda, 1.0);
    m_phi1End = end.phi1;
    m_phi2End = end.phi2;
    m_restitution = std::clamp(world.params.restitution, 0.0, 1.0);
    m_inelastic = m_restitution < 1.0;
    m_gravity = world.params.gravity;
    m_noGravity = std::bit_cast<std::uint64_t>(m_gravity.x) == 0 && std::bit_cast<std::uint64_t>(m_gravity.y) == 0;
    m_width = world.stage.width;
    m_height = world.stage.height;
    m_walls = world.stage.walls;
    m_restSpeed = std::sqrt(2.0 * length(m_gravity) * restHeightPx);
    setNow(0.0);

    const int items = n + static_cast<int>(world.pins.size());
    // A few bodies are cheaper to test all against all than to track through a grid: at extreme
    // speeds the grid events would outnumber the collisions a hundred to one.
    m_singleCell = items <= singleCellItems;
    // The grid's marbles have radii up to rMax; a few far larger ones may be left out of it
    // (RadiusSplit): they come first in the arrays, outside every bucket, and are the partners of
    // every marble (see neighbourRanges()).
    const RadiusSplit split = splitRadii(world.radius);
    m_split = split;
    m_oversize = m_singleCell || !m_splitRadii ? 0 : split.oversize;
    const double rMax = m_oversize > 0 ? split.cut : split.largest;
    m_gridRadius = rMax;
    // Contacts happen at centre distances up to 2 rMax (marble-marble) or rMax (pins) between
    // marbles of the grid. A marble stays within the margin of its anchor (or gets a new anchor):
    // two marbles whose anchor cells are not neighbours are then more than cell - 2 margin =
    // 2 rMax apart.
    const double contact = 2.0 * rMax;
    m_margin = anchorMargin * contact;
    // Small marbles far apart can be small next to how far they move in a frame (a gas, or the
    // crowd around giants, whose cells are sized for it), and every margin crossed is a grid
    // event (with a scan of the neighbourhood): in a sparse scene the margin grows to twice the
    // mean of |vx| + |vy| (pushes included) times phi1(1), the distance the marbles cover in a
    // frame along the axes, but not beyond half the room a marble has beside its contact
    // distance, past which each event's scan costs more than the events saved. The room is first
    // the stage's area per marble (a dense crowd, such as issue 5's, keeps a quarter of the
    // contact distance and reads nothing more), then the crowding a marble actually meets
    // (localSpacing(): a clump in a corner of a large stage is dense). stress's "radii 0.5 to
    // 500" row (400 marbles of 0.5 to 3 px at up to 20 px/frame among three giants): 1.5e3
    // frames per second with a quarter of the contact distance, 3.0e4 with twice the mean;
    // 2,000 marbles of 1 to 3 px at up to 60 px/frame on a 3000 x 2250 stage, 6.4 -> 0.46 ms per
    // frame; the 20k crowd with four giants at 20 times its speeds took 4.6 times as long with
    // twice the mean uncapped, and 5,000 marbles at up to 20 px/frame packed in a 1000 px square
    // of a 6000 px stage 1.3 times as long with the stage's room alone.
    const double perMarble = std::sqrt(std::max(m_width, 1.0) * std::max(m_height, 1.0) / n);
    if (!m_singleCell && 0.5 * (perMarble - contact) > m_margin) {
        // In four lanes, so that the sum is not one chain of dependent additions.
        double lane[4] = {0.0, 0.0, 0.0, 0.0};
        for (int w = 0; w < n; ++w) {
            const Vec2 v = world.velocity[w];
            const Vec2 a = world.acceleration[w];
            lane[w & 3] += std::abs(v.x + a.x) + std::abs(v.y + a.y);
        }
        const double travel = 2.0 * ((lane[0] + lane[1]) + (lane[2] + lane[3])) / n * m_phi1End;
        if (travel > m_margin && std::isfinite(travel)) {
            const double room = 0.5 * (localSpacing(world, 2.0 * perMarble) - contact);
            const double wider = std::min(travel, room);
            if (wider > m_margin)
                m_margin = wider;
        }
    }
    const double width = m_walls ? m_width : std::max(m_width, 1.0);
    const double height = m_walls ? m_height : std::max(m_height, 1.0);
    m_geometry = GridGeometry::fit(contact + 2.0 * m_margin, width, height, items);
    m_prefetchEvents = n >= prefetchEventsFrom;
    const int buckets = m_singleCell ? 1 : m_geometry.bucketCount();

    // Renumber the marbles in bucket order (a stable counting sort), so that the marbles of a
    // bucket, and of a row of buckets, lie side by side in memory. Note on the way whether any
    // marble rests (see predictAll()). Sleepers kept in the layer stay out.
    const bool gravity = m_gravity.x != 0.0 || m_gravity.y != 0.0;
    m_sortBucket.resize(n);
    m_layer = useLayer(world, n);
    m_anyResting = m_layer && m_layerLive > 0;
    m_start.assign(static_cast<std::size_t>(buckets) + 1, 0);
    const bool layer = m_layer;
    const std::uint8_t *inLayer = m_inLayer.data();
    bool anyResting = m_anyResting;
    int outsideSleepers = 0;
    // The marbles outside the layer, in World order (at rest, eight flags are passed at a time).
    const auto nextAwake = [layer, inLayer, n](int w) { return layer ? nextOutsideLayer(inLayer, w, n) : w; };
    const bool oversize = m_oversize > 0;
    for (int w = nextAwake(0); w < n; w = nextAwake(w + 1)) {
        const Vec2 p = world.position[w];
        int b = m_singleCell ? 0 : m_geometry.bucketAt(p.x, p.y);
        if (oversize && split.isOversize(world.radius[w]))
            b = -1; // counted in m_start[0]: the buckets' marbles follow the oversize ones
        m_sortBucket[w] = b;
        ++m_start[b + 1];
        if (!gravity && !anyResting) {
            const Vec2 v = world.velocity[w];
            const Vec2 a = world.acceleration[w];
            anyResting = v.x + a.x == 0.0 && v.y + a.y == 0.0;
        }
        if (layer && layerSleeper(world, w))
            ++outsideSleepers;
    }
    m_anyResting = anyResting;
    m_outsideSleepers = outsideSleepers;
    accumulateCounts(m_start);
    m_awake = m_start[buckets];
    m_count = m_awake;
    m_cursor.assign(m_start.begin(), m_start.end() - 1);
    m_body.resize(n);
    m_rec.resize(n);
    m_order.resize(n);
    int nextOversize = 0;
    for (int w = nextAwake(0); w < n; w = nextAwake(w + 1)) {
        const int b = m_sortBucket[w];
        m_order[b < 0 ? nextOversize++ : m_cursor[b]++] = w;
    }
    m_overflowHead.assign(buckets, -1);
    m_overflowCount = 0;
    // A frame ends with an empty calendar (every entry out of its slot) unless it stopped early.
    if (m_ticket.size() != static_cast<std::size_t>(n) || m_scheduled != 0) {
        m_ticket.assign(static_cast<std::size_t>(n), 0);
        m_scheduled = 0;
    }
    m_heap.clear();
    m_nodes.clear();
    m_finite = std::isfinite(m_lambda) && isFinite(m_gravity);
    m_ready = 0;
    if (!world.pins.empty())
        m_pinGrid.build(m_geometry, world.pins.data(), static_cast<int>(world.pins.size()));
}

namespace {

// Marble w's velocity and pending push are exactly +0.
bool stillWithNothingPending(const World &world, int w)
{
    const Vec2 v = world.velocity[w];
    const Vec2 a = world.acceleration[w];
    return (std::bit_cast<std::uint64_t>(v.x) | std::bit_cast<std::uint64_t>(v.y) | std::bit_cast<std::uint64_t>(a.x)
            | std::bit_cast<std::uint64_t>(a.y))
        == 0;
}

} // namespace

bool ExactModel::sleeps(const World &world, int w)
{
    // At rest with nothing pending, in finite numbers, and not at -0 (the frame's end writes
    // a + 0 = +0 there): the frame would leave it exactly as it is unless something hits it.
    const Vec2 p = world.position[w];
    return stillWithNothingPending(world, w) && isFinite(p) && !(p.x == 0.0 && std::signbit(p.x)) && !(p.y == 0.0 && std::signbit(p.y))
        && std::isfinite(world.radius[w]) && std::isfinite(1.0 / world.mass[w]);
}

bool ExactModel::layerSleeper(const World &world, int w) const
{
    // Oversize marbles stay in the frame's arrays, where every marble finds them.
    return sleeps(world, w) && !leftOut(world.radius[w]);
}

bool ExactModel::layerAllowed(int n) const
{
    // Sleepers need a world without gravity, and a grid (below singleCellItems bodies there is
    // none); by default, many marbles.
    return m_sleepingUse != Sleeping::Never && m_gravity.x == 0.0 && m_gravity.y == 0.0 && !m_singleCell
        && (m_sleepingUse == Sleeping::Always || n >= sleepingLayerFrom);
}

bool ExactModel::useLayer(const World &world, int n)
{
    // Whether this frame keeps the sleepers in the layer; brings the layer up to date if so.
    const bool possible = layerAllowed(n);
    const bool auto_ = m_sleepingUse == Sleeping::Auto;
    const bool kept = possible && m_inLayer.size() == static_cast<std::size_t>(n) && m_layerGeometry == m_geometry;
    if (kept)
        checkLayer(world);
    if (!possible || (kept && auto_ && m_layerLive < n - n / 8)) {
        // Not worth it (or not possible): every marble is read as awake, and the layer is dropped.
        m_inLayer.clear();
        m_layerLive = 0;
        return false;
    }
    if (!kept) {
        // Worth building only if nearly all marbles sleep: as many as the last frame left at rest
        // (or, for a new World, a sample of one in 64).
        if (auto_) {
            int awake = 0;
            int counted = 0;
            if (m_endedAtRest >= 0 && m_endedCount == n) {
                awake = n - m_endedAtRest;
                counted = n;
            } else {
                for (int w = 0; w < n; w += 64, ++counted)
                    awake += !layerSleeper(world, w);
            }
            if (16 * awake > counted) {
                m_inLayer.clear();
                return false;
            }
        }
        buildLayer(world, n);
    } else if (m_layerDead > m_layerLive / 16 || m_outsideSleepers > n / 16) {
        buildLayer(world, n); // many woke (dead entries), or many came to rest outside it
    }
    return true;
}

void ExactModel::buildLayer(const World &world, int n)
{
    // Every marble that sleeps now, sorted by bucket (a stable counting sort).
    const int buckets = m_geometry.bucketCount();
    m_inLayer.assign(static_cast<std::size_t>(n), 0);
    m_sleepStart.assign(static_cast<std::size_t>(buckets) + 1, 0);
    for (int w = 0; w < n; ++w) {
        if (!layerSleeper(world, w))
            continue;
        m_inLayer[w] = 1;
        const Vec2 p = world.position[w];
        m_sortBucket[w] = m_geometry.bucketAt(p.x, p.y);
        ++m_sleepStart[m_sortBucket[w] + 1];
    }
    accumulateCounts(m_sleepStart);
    m_sleepBefore = m_sleepStart;
    m_layerLive = m_sleepStart[buckets];
    m_layerDead = 0;
    m_sleepers.resize(static_cast<std::size_t>(m_layerLive));
    m_sleeperMass.resize(static_cast<std::size_t>(m_layerLive));
    m_cursor.assign(m_sleepStart.begin(), m_sleepStart.end() - 1);
    for (int w = 0; w < n; ++w) {
        if (!m_inLayer[w])
            continue;
        const int b = m_sortBucket[w];
        m_sleeperMass[m_cursor[b]] = world.mass[w];
        m_sleepers[m_cursor[b]++] = {world.position[w], world.radius[w], w, -1};
    }
    m_layerGeometry = m_geometry;
}

void ExactModel::checkLayer(const World &world)
{
    // A sleeper still sleeps if the World holds it as the layer does, at rest with nothing
    // pending; one that the last frame hit, or that was edited or pushed since, wakes (its entry
    // dies). Counts the live sleepers of the buckets before each bucket on the way. (A sleeper
    // that an edit of other radii makes oversize wakes too; but the grid's radius, and with it
    // the lattice, changes whenever the split does, so the layer is built afresh before that
    // test can matter: it is a guard, which no test reaches.)
    const int buckets = m_layerGeometry.bucketCount();
    m_sleepBefore.resize(static_cast<std::size_t>(buckets) + 1);
    int live = 0;
    int dead = 0;
    for (int b = 0; b < buckets; ++b) {
        m_sleepBefore[b] = live;
        for (int q = m_sleepStart[b]; q < m_sleepStart[b + 1]; ++q) {
            Sleeper &s = m_sleepers[q];
            if (s.id < 0) {
                ++dead;
                continue;
            }
            const int w = s.id;
            const bool same = std::bit_cast<std::uint64_t>(world.position[w].x) == std::bit_cast<std::uint64_t>(s.p.x)
                && std::bit_cast<std::uint64_t>(world.position[w].y) == std::bit_cast<std::uint64_t>(s.p.y)
                && std::bit_cast<std::uint64_t>(world.radius[w]) == std::bit_cast<std::uint64_t>(s.radius)
                && std::bit_cast<std::uint64_t>(world.mass[w]) == std::bit_cast<std::uint64_t>(m_sleeperMass[q])
                && stillWithNothingPending(world, w) && !leftOut(s.radius);
            if (s.promoted >= 0)
                s.promoted = -1;
            if (!same) {
                m_inLayer[w] = 0;
                s.id = -1;
                ++dead;
                continue;
            }
            ++live;
        }
    }
    m_sleepBefore[buckets] = live;
    m_layerLive = live;
    m_layerDead = dead;
}

int ExactModel::sleepersBelow(int bucket, int id) const
{
    // Live sleepers before a marble of World index `id` in `bucket`, in bucket order.
    int below = m_sleepBefore[bucket];
    for (int q = m_sleepStart[bucket]; q < m_sleepStart[bucket + 1] && m_sleepers[q].id < id; ++q)
        below += m_sleepers[q].id >= 0;
    return below;
}

[[gnu::always_inline]] inline void ExactModel::startRecords(int k, Vec2 p, Vec2 b, double radius, double mass, int bucket,
                                                             int id, int rank)
{
    // Marble k's records as a frame starts: at p with b = its velocity (t = 0), anchored at p in
    // the bucket it was sorted into, no event, no collision yet.
    Body &body = m_body[k];
    body.a = p;
    body.b = b;
    body.radius = radius;
    body.contactTime = noTime;
    body.bucket = bucket;
    body.id = id;
    body.rank = rank;
    body.gravityOff = 0;
    body.frozen = 0;
    body.moved = 0;
    Record &rec = m_rec[k];
    rec.contactKind = EventKind::None;
    rec.contactOther = -1;
    rec.contactStamp = 0;
    rec.crossTime = noTime;
    rec.anchor = p;
    rec.invMass = 1.0 / mass;
    rec.stamp = 0;
    rec.overflowNext = -1;
    rec.guard = Guard{};
    rec.crossSide = 0;
}

int ExactModel::promote(int q)
{
    // Sleeper q joins the frame's arrays (at the end, in the overflow-free state of a marble
    // still in the bucket it was sorted into): a change of representation only, it is at rest
    // as before. Its rank counts the awake marbles of its bucket with a lower World index.
    Sleeper &s = m_sleepers[q];
    const int k = m_count++;
    const int b = m_geometry.bucketAt(s.p.x, s.p.y); // where the layer sorted it (same lattice)
    const int w = s.id;
    int rank = m_start[b] + sleepersBelow(b, w);
    for (int j = m_start[b]; j < m_start[b + 1]; ++j)
        rank += m_order[j] < w;
    startRecords(k, s.p, {}, s.radius, m_sleeperMass[q], b, w, rank);
    m_sortBucket[w] = b;
    s.promoted = k;
    return k;
}

bool ExactModel::nearSleeper(const Vec2 &p, const Vec2 &v, double r, int q) const
{
    // The first test of pairContact() against sleeper q (at rest at its position, no gravity):
    // true when a marble at p moving at v may touch it in the rest of the frame.
    const Sleeper &s = m_sleepers[q];
    return straightContact(p.x - s.p.x, p.y - s.p.y, v.x, v.y, r + s.radius, m_sLeft) <= m_sLeft;
}

// How many marbles ahead makeReady() and endFrame() request the World's entries: they visit
// the World in grid order, which after a few hundred frames is a random order in a large crowd.
constexpr int makeReadyAhead = 16;

void ExactModel::makeReady(int end)
{
    // Reads marbles m_ready .. end - 1 (internal indices) from the World. The first look calls
    // this just ahead of its pass, so that each record is still in cache when it is first read.
    World &world = *m_world;
    bool finite = m_finite;
    const int n = m_awake;
    const bool layer = m_layer;
    end = std::min(end, n); // (past the awake marbles: sleepers that joined the arrays, ready already)
    for (int i = m_ready; i < end; ++i) {
        if (i + makeReadyAhead < n) {
            const int ahead = m_order[i + makeReadyAhead];
            __builtin_prefetch(&world.position[ahead]);
            __builtin_prefetch(&world.velocity[ahead]);
            __builtin_prefetch(&world.acceleration[ahead]);
            __builtin_prefetch(&world.radius[ahead]);
            __builtin_prefetch(&world.mass[ahead]);
        }
        const int w = m_order[i];
        // Pushes act at the frame boundary: an instant velocity change. At t = 0, a = p and b = v.
        const Vec2 p = world.position[w];
        const Vec2 b{world.velocity[w].x + world.acceleration[w].x, world.velocity[w].y + world.acceleration[w].y};
        if (std::bit_cast<std::uint64_t>(world.acceleration[w].x) != 0 || std::bit_cast<std::uint64_t>(world.acceleration[w].y) != 0)
            world.acceleration[w] = {}; // (written only when set: most marbles have no push)
        const int bucket = m_sortBucket[w];
        // Its place among all marbles (sleepers included) in bucket order, for the ties.
        const int rank = layer && bucket >= 0 ? i + sleepersBelow(bucket, w) : i; // (oversize marbles come first)
        startRecords(i, p, b, world.radius[w], world.mass[w], bucket, w, rank);
        const Body &body = m_body[i];
        const Record &rec = m_rec[i];
        finite = finite && isFinite(body.a) && isFinite(body.b) && std::isfinite(body.radius) && std::isfinite(rec.invMass);
    }
    m_finite = finite;
    m_ready = std::max(m_ready, end);
}

void ExactModel::endFrame(World &world)
{
    // The sleepers left in the layer are as they were: a + 0 phi1 = a and velocity +0.
    const int n = m_count;
    // How many end at rest: what decides whether the next frame builds the sleepers' layer.
    const bool countRest = layerAllowed(world.marbleCount());
    int atRest = 0;
    const double z = world.params.zeroThreshold;
    // Under a gravity of about 1e33 px/frame^2 or more a falling marble's bounces come closer
    // together than a double can tell apart, and it ended the frame past the floor, 0.6 to
    // 10,000 px (marbles-cli run, one marble of radius 25 on the default stage). One that began
    // the frame inside the walls ends it inside: on the wall it went through, not moving out.
    const bool keepInside = m_walls && !m_noGravity;
    setNow(1.0);
    // Whether every number written is finite (World::step() skips its own check then).
    bool finite = true;
    for (int i = 0; i < n; ++i) {
        if (i + makeReadyAhead < n) {
            const int ahead = m_body[i + makeReadyAhead].id;
            __builtin_prefetch(&world.position[ahead], 1);
            __builtin_prefetch(&world.velocity[ahead], 1);
        }
        Vec2 p;
        Vec2 v;
        stateAt(m_body[i], p, v);
        if (m_body[i].frozen)
            v = {};
        // The zero threshold acts at the frame boundary, component by component.
        if (std::abs(v.x) <= z)
            v.x = 0.0;
        if (std::abs(v.y) <= z)
            v.y = 0.0;
        if (keepInside)
            keepWithinWalls(world.position[m_body[i].id], m_body[i].radius, p, v);
        if (countRest)
            atRest += (std::bit_cast<std::uint64_t>(v.x) | std::bit_cast<std::uint64_t>(v.y)) == 0;
        world.position[m_body[i].id] = p;
        world.velocity[m_body[i].id] = v;
        finite &= finiteBits(p) & finiteBits(v);
    }
    m_leftAllFinite = finite;
    m_endedAtRest = countRest ? atRest + lastSleepingCount() : -1;
    m_endedCount = world.marbleCount();
    m_world = nullptr;
}

void ExactModel::keepWithinWalls(Vec2 start, double r, Vec2 &p, Vec2 &v) const
{
    const auto axis = [r](double from, double side, double &x, double &speed) {
        if (2.0 * r >= side)
            return; // held between its walls (collideWall())
        const double tolerance = wallTouchTolerance(side, r);
        const double lo = r;
        const double hi = side - r;
        // One that began past a wall (placed so) leaves through it by its own motion, but never
        // through the other: one placed across the ceiling ended 3.7e277 px below the floor
        // under a gravity of 1e308.
        if (x < lo - tolerance && !(from < lo - tolerance)) {
            x = lo;
            speed = std::max(speed, 0.0);
        } else if (x > hi + tolerance && !(from > hi + tolerance)) {
            x = hi;
            speed = std::min(speed, 0.0);
        }
    };
    axis(start.x, m_width, p.x, v.x);
    axis(start.y, m_height, p.y, v.y);
}

std::uint64_t ExactModel::tieOf(int i, const Event &e) const
{
    // (kind, lower rank, higher rank): for a pair the two marbles, otherwise the marble and the
    // object (wall, pin or margin side). Ranks are below 2^30 (asserted in beginFrame).
    std::int64_t lo = rankOf(i);
    std::int64_t hi = e.other;
    if (e.kind == EventKind::Pair || e.kind == EventKind::RecheckPair) {
        const std::int64_t other = rankOf(e.other);
        hi = std::max(lo, other);
        lo = std::min(lo, other);
    }
    return (static_cast<std::uint64_t>(e.kind) << 60) | (static_cast<std::uint64_t>(lo) << 30)
        | static_cast<std::uint64_t>(hi);
}

bool ExactModel::before(int i, const Event &a, const Event &b) const
{
    if (a.time != b.time)
        return a.time < b.time;
    if (a.kind == EventKind::None || b.kind == EventKind::None)
        return false;
    return tieOf(i, a) < tieOf(i, b);
}

ExactModel::Event ExactModel::contactOf(int i) const
{
    const Record &rec = m_rec[i];
    return {m_body[i].contactTime, rec.contactKind, rec.contactOther, rec.contactStamp};
}

ExactModel::Event ExactModel::currentEvent(int i) const
{
    const Event c = contactOf(i);
    if (m_rec[i].crossTime <= 1.0) {
        const Event x{m_rec[i].crossTime, EventKind::Cross, m_rec[i].crossSide, 0};
        if (before(i, x, c))
            return x;
    }
    return c;
}

ExactModel::Key ExactModel::keyOf(int i) const
{
    const Event e = currentEvent(i);
    return {e.time, e.kind == EventKind::None ? ~std::uint64_t(0) : tieOf(i, e), i, rankOf(i), 0};
}

bool ExactModel::keyBefore(const Key &a, const Key &b)
{
    if (a.time != b.time)
        return a.time < b.time;
    if (a.tie != b.tie)
        return a.tie < b.tie;
    return a.rank < b.rank;
}

// The calendar queue. Slots are monotone in time (rounding is), so a later slot only holds
// later events. The current slot's entries are kept in a 4-ary heap (so that many events at
// one time, such as a crowd spawned overlapping, cost log n each and not a scan of the slot);
// the later slots' entries in lists, each loaded into the heap when its turn comes. An event
// due before the current slot's time (a contact due at once) joins the current slot.
int ExactModel::slotOf(double time) const
{
    // Slots are 1 / slots of a frame wide.
    const int slots = static_cast<int>(m_slotHead.size());
    const double x = time * slots;
    if (x >= slots)
        return slots - 1;
    if (x > m_firstSlot)
        return static_cast<int>(x);
    return m_firstSlot;
}

void ExactModel::issueTicket(Key &key)
{
    if (++m_lastTicket == 0)
        m_lastTicket = 1; // 0 stands for no entry
    key.ticket = m_lastTicket;
    m_ticket[static_cast<std::size_t>(key.marble)] = key.ticket;
    ++m_scheduled;
}

void ExactModel::calendarInsert(Key key)
{
    issueTicket(key);
    const int slot = slotOf(key.time);
    if (slot == m_firstSlot) {
        m_heap.push_back(key);
        heapSiftUp(static_cast<int>(m_heap.size()) - 1);
        return;
    }
    std::int32_t &head = m_slotHead[static_cast<std::size_t>(slot)];
    key.next = head;
    head = static_cast<std::int32_t>(m_nodes.size());
    m_nodes.push_back(key);
}

void ExactModel::calendarRemove(int i)
{
    // Its entry stays where it is, stale from now on.
    m_ticket[static_cast<std::size_t>(i)] = 0;
    --m_scheduled;
}

int ExactModel::calendarFirst()
{
    while (true) {
        if (m_scheduled == 0)
            return -1;
        // Stale entries at the top are dropped (the one of the event just handled among them).
        while (!m_heap.empty() && !live(m_heap.front())) {
            m_heap.front() = m_heap.back();
            m_heap.pop_back();
            if (!m_heap.empty())
                heapSiftDown(0);
        }
        if (!m_heap.empty())
            break;
        // The current slot is done: the next non-empty one becomes current.
        ++m_firstSlot;
        std::int32_t &head = m_slotHead[static_cast<std::size_t>(m_firstSlot)];
        // Stale ones too: each is looked at once either way, at the top of the heap.
        for (std::int32_t k = head; k >= 0; k = m_nodes[static_cast<std::size_t>(k)].next)
            m_heap.push_back(m_nodes[static_cast<std::size_t>(k)]);
        head = -1;
        const int size = static_cast<int>(m_heap.size());
        for (int pos = size > 1 ? (size - 2) / 4 : -1; pos >= 0; --pos)
            heapSiftDown(pos);
    }
    // In a world far larger than the caches, also request the records of the current slot's
    // next marbles (the heap's top's children hold the next least key).
    if (m_prefetchEvents) {
        const std::size_t last = std::min<std::size_t>(m_heap.size(), 5);
        for (std::size_t c = 1; c < last; ++c) {
            const int k = m_heap[c].marble;
            __builtin_prefetch(&m_rec[static_cast<std::size_t>(k)]);
            __builtin_prefetch(&m_body[static_cast<std::size_t>(k)]);
        }
    }
    // Start loading the records of the next slots' first marble: in a large world its event is
    // likely to come soon, and its records are far from this one's (a hint, no effect on results).
    // In a world far larger than the caches, look two slots ahead: the records of the second
    // slot's first marble, and the neighbourhood and partner of the first slot's, whose records
    // were requested one event ago.
    const int slots = static_cast<int>(m_slotHead.size());
    int found = 0;
    for (int s = m_firstSlot + 1; s < slots && s <= m_firstSlot + 8; ++s) {
        const std::int32_t node = m_slotHead[static_cast<std::size_t>(s)];
        if (node < 0)
            continue;
        const int k = m_nodes[static_cast<std::size_t>(node)].marble;
        if (found == 0 && m_prefetchEvents) {
            prefetchNear(k);
            const Record &rec = m_rec[static_cast<std::size_t>(k)];
            __builtin_prefetch(&m_world->lastHit[static_cast<std::size_t>(m_body[static_cast<std::size_t>(k)].id)], 1);
            if (rec.contactKind == EventKind::Pair) {
                __builtin_prefetch(&m_body[static_cast<std::size_t>(rec.contactOther)]);
                __builtin_prefetch(&m_rec[static_cast<std::size_t>(rec.contactOther)]);
            }
        } else {
            __builtin_prefetch(&m_body[static_cast<std::size_t>(k)]);
            __builtin_prefetch(&m_rec[static_cast<std::size_t>(k)]);
        }
        if (++found == (m_prefetchEvents ? 2 : 1))
            break;
    }
    return m_heap.front().marble;
}

void ExactModel::heapSiftUp(int pos)
{
    const Key key = m_heap[static_cast<std::size_t>(pos)];
    while (pos > 0) {
        const int parent = (pos - 1) / 4;
        if (!keyBefore(key, m_heap[static_cast<std::size_t>(parent)]))
            break;
        m_heap[static_cast<std::size_t>(pos)] = m_heap[static_cast<std::size_t>(parent)];
        pos = parent;
    }
    m_heap[static_cast<std::size_t>(pos)] = key;
}

void ExactModel::heapSiftDown(int pos)
{
    const Key key = m_heap[static_cast<std::size_t>(pos)];
    const int size = static_cast<int>(m_heap.size());
    while (true) {
        const int first = 4 * pos + 1;
        if (first >= size)
            break;
        int child = first;
        const int last = std::min(first + 4, size);
        for (int c = first + 1; c < last; ++c) {
            if (keyBefore(m_heap[static_cast<std::size_t>(c)], m_heap[static_cast<std::size_t>(child)]))
                child = c;
        }
        if (!keyBefore(m_heap[static_cast<std::size_t>(child)], key))
            break;
        m_heap[static_cast<std::size_t>(pos)] = m_heap[static_cast<std::size_t>(child)];
        pos = child;
    }
    m_heap[static_cast<std::size_t>(pos)] = key;
}

void ExactModel::schedule(int i)
{
    if (m_ticket[static_cast<std::size_t>(i)] != 0)
        calendarRemove(i);
    const Key key = keyOf(i);
    if (key.time <= 1.0)
        calendarInsert(key);
}

void ExactModel::nextEscape(int i, Vec2 p, Vec2 v)
{
    m_rec[i].crossTime = noTime;
    const Body &body = m_body[i];
    if (m_singleCell || body.frozen || body.bucket < 0)
        return; // (an oversize marble's partners do not depend on where it is)
    // The centre reaching a side of the square of half-width margin around the anchor.
    const Vec2 anchor = m_rec[i].anchor;
    const Vec2 g = m_noGravity ? Vec2{} : gravityOf(body);
    if (m_noGravity || (g.x == 0.0 && g.y == 0.0)) {
        // Straight in s: out of reach if every side is further than |v| phi1(time left). (Most
        // marbles return here, so this comes first: either test returns with no grid event.)
        const double reachX = std::abs(v.x) * m_sLeft;
        const double reachY = std::abs(v.y) * m_sLeft;
        if (p.x - (anchor.x - m_margin) > reachX && (anchor.x + m_margin) - p.x > reachX
            && p.y - (anchor.y - m_margin) > reachY && (anchor.y + m_margin) - p.y > reachY)
            return;
    }
    // Where the margin is below the resolution of the coordinates (a marble 1e17 px from the
    // origin, or one far smaller than its distance from it), anchor +- margin rounds to the
    // anchor: the marble would be past a side at once, re-anchored where it is, and past it again,
    // for ever (found by fuzz/fuzz_physics). Such a marble is not followed through the grid: it
    // keeps the neighbours of its anchor's cell until the frame ends, and the next frame sorts
    // it again.
    if (anchor.x - m_margin == anchor.x || anchor.x + m_margin == anchor.x || anchor.y - m_margin == anchor.y
        || anchor.y + m_margin == anchor.y)
        return;
    const double tauEnd = 1.0 - m_now;
    const double tc[sides] = {
        firstDownCrossing(p.x - (anchor.x - m_margin), v.x, g.x, m_lambda, tauEnd),
        firstDownCrossing((anchor.x + m_margin) - p.x, -v.x, -g.x, m_lambda, tauEnd),
        firstDownCrossing(p.y - (anchor.y - m_margin), v.y, g.y, m_lambda, tauEnd),
        firstDownCrossing((anchor.y + m_margin) - p.y, -v.y, -g.y, m_lambda, tauEnd),
    };
    double best = noTime;
    int side = 0;
    for (int s = 0; s < sides; ++s) {
        if (tc[s] < best) {
            best = tc[s];
            side = s;
        }
    }
    if (best <= tauEnd) {
        m_rec[i].crossTime = m_now + best;
        m_rec[i].crossSide = static_cast<std::uint8_t>(side);
    }
}

void ExactModel::moveToBucket(int i, int bucket)
{
    Body &body = m_body[i];
    if (body.moved) {
        // Leaves the overflow list of its bucket (a few marbles at most: a short walk).
        int *link = &m_overflowHead[body.bucket];
        while (*link != i)
            link = &m_rec[*link].overflowNext;
        *link = m_rec[i].overflowNext;
        --m_overflowCount;
    }
    body.bucket = bucket;
    body.moved = bucket != m_sortBucket[body.id]; // the bucket it was sorted into
    if (body.moved) {
        ++m_overflowCount;
        m_rec[i].overflowNext = m_overflowHead[bucket];
        m_overflowHead[bucket] = i;
    }
}

void ExactModel::reanchor(int i)
{
    Vec2 p;
    Vec2 v;
    stateAt(m_body[i], p, v);
    m_rec[i].anchor = p;
    nextEscape(i, p, v);
    const int bucket = m_geometry.bucketAt(p.x, p.y);
    if (bucket == m_body[i].bucket)
        return; // the same neighbours as before: nothing new in reach
    moveToBucket(i, bucket);
    // New neighbours came into reach. The best contact found so far still stands (the velocity
    // has not changed); look at the new neighbourhood for earlier ones.
    int buckets[9];
    const int count = neighbourBuckets(i, buckets);
    Event best = contactOf(i);
    scanPins(i, p, v, buckets, count, best);
    scanMarbles(i, p, v, buckets, count, best);
    setContact(i, best);
}

void ExactModel::predictOwn(int i, Vec2 p, Vec2 v, Event &best)
{
    nextEscape(i, p, v);
    const Body &body = m_body[i];
    if (!m_walls || body.frozen)
        return;
    // Walls 0..3: left, right, top, bottom; contact when the centre is r from the edge.
    const Vec2 g = m_noGravity ? Vec2{} : gravityOf(body);
    const double r = body.radius;
    if (m_noGravity || (g.x == 0.0 && g.y == 0.0)) {
        // Straight in s: no wall is within reach if every gap exceeds |v| phi1(time left).
        const double reachX = std::abs(v.x) * m_sLeft;
        const double reachY = std::abs(v.y) * m_sLeft;
        if (p.x - r > reachX && m_width - r - p.x > reachX && p.y - r > reachY && m_height - r - p.y > reachY)
            return;
    }
    const double horizon = std::min(best.time, 1.0) - m_now;
    const double tw[sides] = {
        firstDownCrossing(p.x - r, v.x, g.x, m_lambda, horizon),
        firstDownCrossing(m_width - r - p.x, -v.x, -g.x, m_lambda, horizon),
        firstDownCrossing(p.y - r, v.y, g.y, m_lambda, horizon),
        firstDownCrossing(m_height - r - p.y, -v.y, -g.y, m_lambda, horizon),
    };
    for (int wall = 0; wall < sides; ++wall) {
        if (tw[wall] <= horizon) {
            const Event e{m_now + tw[wall], EventKind::Wall, wall, 0};
            if (before(i, e, best))
                best = e;
        }
    }
}

[[gnu::always_inline]] inline double ExactModel::straightWithoutGravity(int i, int j, const Vec2 &pi, const Vec2 &vi,
                                                                      double ri) const
{
    // pairContact() where there is no gravity anywhere (offerPair() takes this path then): the
    // relative path is straight, with j's state now a + b phi1 and b e^{-lambda t}. (The general
    // form adds gravity terms that are +0 here, which can only turn a -0 coordinate into +0: no
    // product or test that follows tells them apart.)
    const Body &bj = m_body[j];
    const double pjx = bj.a.x + bj.b.x * m_phi1Now;
    const double pjy = bj.a.y + bj.b.y * m_phi1Now;
    const double vjx = bj.b.x * m_decayNow;
    const double vjy = bj.b.y * m_decayNow;
    const bool iLow = i < j;
    return straightContact(iLow ? pi.x - pjx : pjx - pi.x, iLow ? pi.y - pjy : pjy - pi.y, iLow ? vi.x - vjx : vjx - vi.x,
                           iLow ? vi.y - vjy : vjy - vi.y, ri + bj.radius, m_sLeft);
}

double ExactModel::searchHorizon(double limit) const
{
    // How far from now a partner's contact is looked for: every tau whose event time m_now + tau
    // rounds to `limit` or earlier. A contact at the time of the best found so far ties with it,
    // and tieOf() decides: the test had been tau <= limit - m_now, which dropped a contact 1.26
    // units in the last place of that difference away, though its time rounded to the best's;
    // which of two such contacts won then followed the order the partners were offered in, and
    // the sleepers' layer, which numbers the marbles it promotes after the others, changed it (a
    // fuzzer's finding: a marble wedged in a corner, positions a few units in the last place
    // apart). The caller keeps the contacts with m_now + tau <= limit. Rounding moves m_now + tau
    // by half a unit of the sum's last place at most, and the difference below by a unit of
    // its own: this bound holds every such tau (a few more are looked for and turned down).
    return (limit - m_now) * (1.0 + 0x1p-50) + std::abs(limit) * 0x1p-51;
}

inline bool ExactModel::pairContact(int i, int j, const Vec2 &pi, const Vec2 &vi, double horizon, double &tau,
                              bool &recheck) const
{
    // The innermost loop of the model, in scalars. Computed with the pair in canonical order
    // (lower index first), so that both marbles of a pair predict bit-identical times; j's state
    // now is stateAt() written out. (On a straight relative path the order only flips every
    // sign, which leaves the result the same bits: so the index order serves with the sleepers'
    // layer too, where marbles that join the arrays are numbered out of rank order.)
    const Body &bi = m_body[i];
    const Body &bj = m_body[j];
    const bool iLow = i < j;
    const double R = bi.radius + bj.radius;
    recheck = false;
    const double gix = (bi.gravityOff & 1) ? 0.0 : m_gravity.x;
    const double giy = (bi.gravityOff & 2) ? 0.0 : m_gravity.y;
    const double gjx = (bj.gravityOff & 1) ? 0.0 : m_gravity.x;
    const double gjy = (bj.gravityOff & 2) ? 0.0 : m_gravity.y;
    const double pjx = bj.a.x + bj.b.x * m_phi1Now + gjx * m_phi2Now;
    const double pjy = bj.a.y + bj.b.y * m_phi1Now + gjy * m_phi2Now;
    const double vjx = bj.b.x * m_decayNow + gjx * m_phi1Now;
    const double vjy = bj.b.y * m_decayNow + gjy * m_phi1Now;
    const double dx = iLow ? pi.x - pjx : pjx - pi.x;
    const double dy = iLow ? pi.y - pjy : pjy - pi.y;
    const double dvx = iLow ? vi.x - vjx : vjx - vi.x;
    const double dvy = iLow ? vi.y - vjy : vjy - vi.y;
    const double dgx = iLow ? gix - gjx : gjx - gix;
    const double dgy = iLow ? giy - gjy : gjy - giy;
    if (dgx == 0.0 && dgy == 0.0) {
        const double s = straightContact(dx, dy, dvx, dvy, R, m_sLeft);
        if (!(s <= m_sLeft))
            return false;
        tau = phi1Inverse(m_lambda, s);
        return tau <= horizon;
    }
    const Contact c = firstContact({dx, dy}, {dvx, dvy}, {dgx, dgy}, R, m_lambda, horizon, m_sLeft);
    tau = c.tau;
    recheck = c.recheck;
    return c.tau <= horizon;
}

void ExactModel::scanPins(int i, Vec2 p, Vec2 v, const int *buckets, int count, Event &best) const
{
    const Body &body = m_body[i];
    if (body.frozen || m_world->pins.empty())
        return;
    const Vec2 g = gravityOf(body);
    const double r = body.radius;
    auto testPin = [&](int pin) {
        const double horizon = std::min(best.time, 1.0) - m_now;
        const Vec2 q = m_world->pins[pin];
        const Contact c = firstContact({p.x - q.x, p.y - q.y}, v, g, r, m_lambda, horizon, m_sLeft);
        if (c.tau <= horizon) {
            const Event e{m_now + c.tau, c.recheck ? EventKind::RecheckPin : EventKind::Pin, pin, 0};
            if (before(i, e, best))
                best = e;
        }
    };
    if (m_singleCell || body.bucket < 0) {
        for (int pin = 0; pin < static_cast<int>(m_world->pins.size()); ++pin)
            testPin(pin);
        return;
    }
    for (int nb = 0; nb < count; ++nb) {
        for (int k = m_pinGrid.begin(buckets[nb]); k < m_pinGrid.end(buckets[nb]); ++k)
            testPin(m_pinGrid.items()[k]);
    }
}

inline void ExactModel::offerPair(int i, int j, const Vec2 &p, const Vec2 &v, Event &best) const
{
    if (m_noGravity) {
        const double s = straightWithoutGravity(i, j, p, v, m_body[i].radius);
        if (s <= m_sLeft) [[unlikely]]
            offerStraight(i, j, s, best);
        return;
    }
    const Body &bj = m_body[j];
    if (m_body[i].frozen && bj.frozen)
        return;
    // Contacts after j's own best contact need not be recorded: j is predicted afresh then.
    const double limit = std::min({best.time, bj.contactTime, 1.0});
    double tau;
    bool recheck;
    if (!pairContact(i, j, p, v, searchHorizon(limit), tau, recheck))
        return;
    const double at = m_now + tau;
    if (!(at <= limit))
        return;
    const Event e{at, recheck ? EventKind::RecheckPair : EventKind::Pair, j, recheck ? 0u : m_rec[j].stamp};
    if (before(i, e, best))
        best = e;
}

void ExactModel::offerStraight(int i, int j, double s, Event &best) const
{
    // offerPair() without gravity, once straightWithoutGravity() found contact at s <= phi1(time
    // left): the steps that follow pairContact() there.
    const Body &bj = m_body[j];
    if (m_body[i].frozen && bj.frozen)
        return;
    const double at = m_now + phi1Inverse(m_lambda, s);
    if (!(at <= std::min({best.time, bj.contactTime, 1.0})))
        return;
    const Event e{at, EventKind::Pair, j, m_rec[j].stamp};
    if (before(i, e, best))
        best = e;
}

void ExactModel::scanMarbles(int i, Vec2 p, Vec2 v, const int *buckets, int count, Event &best)
{
    int ranges[rangeSlots];
    const int rangeCount = neighbourRanges(i, ranges);
    if (m_noGravity) {
        // offerPair()'s no-gravity branch written into the loop (the same steps in the same order):
        // most candidates fail the straight path's first test, and only those that pass go on,
        // out of line, to the partner's horizon and the time. Callgrind, 10k crowd: 12.5
        // candidates a scan, 119 instructions each through offerPair() called here, whose register
        // spills the compiler hoisted above its no-gravity test (4 % slower at 10k still, with
        // that test first).
        const double radius = m_body[i].radius;
        for (int r = 0; r < rangeCount; ++r) {
            for (int j = ranges[2 * r]; j < ranges[2 * r + 1]; ++j) {
                if (j == i || m_body[j].moved)
                    continue;
                const double s = straightWithoutGravity(i, j, p, v, radius);
                if (s <= m_sLeft) [[unlikely]]
                    offerStraight(i, j, s, best);
            }
        }
    } else {
        for (int r = 0; r < rangeCount; ++r) {
            for (int j = ranges[2 * r]; j < ranges[2 * r + 1]; ++j) {
                if (j != i && !m_body[j].moved)
                    offerPair(i, j, p, v, best);
            }
        }
    }
    if (m_layer)
        scanSleepers(i, p, v, best);
    if (m_overflowCount == 0)
        return;
    for (int nb = 0; nb < count; ++nb) {
        for (int j = m_overflowHead[buckets[nb]]; j >= 0; j = m_rec[j].overflowNext) {
            if (j != i)
                offerPair(i, j, p, v, best);
        }
    }
}

[[gnu::always_inline]] inline void ExactModel::offerSleeper(int i, int q, const Vec2 &p, const Vec2 &v, double r,
                                                             Event &best)
{
    // Sleeper q as a partner of marble i (at p moving at v, radius r): one that joined the arrays
    // this frame is offered like any marble (unless it left its bucket: then it is in an overflow
    // list), and one within reach joins them first.
    if (m_sleepers[q].id < 0)
        return;
    int j = m_sleepers[q].promoted;
    if (j < 0 && nearSleeper(p, v, r, q))
        j = promote(q);
    if (j >= 0 && j != i && !m_body[j].moved)
        offerPair(i, j, p, v, best);
}

template<typename Run>
bool ExactModel::bucketsInReach(int i, Run run) const
{
    // Oversize marble i moves on p(t) = a + b phi1(t) + g phi2(t) until its next event. From now
    // to the end of the frame phi1 and phi2 only grow, by at most d1 = phi1(1) - phi1(now) and
    // d2 = phi2(1) - phi2(now), so along each axis it moves by b d1' + g d2' with d1' in [0, d1]
    // and d2' in [0, d2]: within the box of its position now widened by those two terms' ranges.
    // A marble of the grid that touches it is within r_i + rMax of that path, and its anchor (in
    // its bucket) within a margin more, until it strays further and, anchored afresh in another
    // bucket, looks for partners itself (its neighbourhood includes every oversize marble). So
    // the buckets of the cells meeting the box widened by that reach hold every partner it can
    // meet in this frame: calls run(first, last) for them, as runs of consecutive buckets.
    // Returns false without calling it when the box covers the whole lattice.
    const Body &body = m_body[i];
    Vec2 p;
    Vec2 v;
    stateAt(body, p, v);
    const Vec2 g = gravityOf(body);
    const double d1 = (m_phi1End - m_phi1Now) * (1.0 + 1e-12);
    const double d2 = (m_phi2End - m_phi2Now) * (1.0 + 1e-12);
    const double reach = body.radius + m_gridRadius + m_margin;
    const auto range = [&](double from, double b, double g1) {
        return std::pair{from + std::min(0.0, b * d1) + std::min(0.0, g1 * d2) - reach,
                         from + std::max(0.0, b * d1) + std::max(0.0, g1 * d2) + reach};
    };
    const auto [x0, x1] = range(p.x, body.b.x, g.x);
    const auto [y0, y1] = range(p.y, body.b.y, g.y);
    return m_geometry.forEachRunInBox(x0, x1, y0, y1, run);
}

void ExactModel::scanEveryMarble(int i, const Vec2 &p, const Vec2 &v, Event &best)
{
    // An oversize marble's partners: the other oversize marbles, and every marble anchored in
    // the buckets within its reach (each once: those still in their sorted bucket from its
    // range, the others from its overflow list), and the sleepers there (as scanSleepers()).
    for (int j = 0; j < m_oversize; ++j) {
        if (j != i)
            offerPair(i, j, p, v, best);
    }
    const double r = m_body[i].radius;
    const bool bounded = bucketsInReach(i, [&](int b0, int b1) {
        for (int j = m_start[b0]; j < m_start[b1]; ++j) {
            if (!m_body[j].moved)
                offerPair(i, j, p, v, best);
        }
        for (int b = b0; m_overflowCount > 0 && b < b1; ++b) {
            for (int j = m_overflowHead[b]; j >= 0; j = m_rec[j].overflowNext)
                offerPair(i, j, p, v, best);
        }
        if (m_layer) {
            for (int q = m_sleepStart[b0]; q < m_sleepStart[b1]; ++q)
                offerSleeper(i, q, p, v, r, best);
        }
    });
    if (bounded)
        return;
    // Every marble: first the sleepers within reach join the arrays, then all are offered.
    for (int q = 0; m_layer && q < static_cast<int>(m_sleepers.size()); ++q) {
        if (m_sleepers[q].id >= 0 && m_sleepers[q].promoted < 0 && nearSleeper(p, v, r, q))
            promote(q);
    }
    for (int j = m_oversize; j < m_count; ++j)
        offerPair(i, j, p, v, best);
}

void ExactModel::firstLookAtOversize(int i, const FirstLook &look, Event &best)
{
    // The first look of i at the oversize marbles (internal 0 .. m_oversize - 1).
    for (int j = 0; j < m_oversize; ++j) {
        if (testedFrom(i, j))
            offerFirstLook(i, j, look, best);
    }
}

void ExactModel::firstLookOversize(int i, const FirstLook &look, Event &best)
{
    // The first look of an oversize marble (they come first: every partner has a higher index,
    // unless it rests): as scanEveryMarble(), before any marble has left its bucket.
    firstLookAtOversize(i, look, best);
    const bool bounded = bucketsInReach(i, [&](int b0, int b1) { firstLookRun(i, look, b0, b1, best); });
    if (!bounded)
        firstLookRun(i, look, 0, m_geometry.bucketCount(), best);
}

void ExactModel::scanSleepers(int i, const Vec2 &p, const Vec2 &v, Event &best)
{
    // The sleepers around i's bucket (see offerSleeper()).
    int ranges[rangeSlots];
    const int rangeCount = sleeperRanges(i, ranges);
    const double r = m_body[i].radius;
    for (int k = 0; k < rangeCount; ++k) {
        for (int q = ranges[2 * k]; q < ranges[2 * k + 1]; ++q)
            offerSleeper(i, q, p, v, r, best);
    }
}

void ExactModel::prefetchNear(int i) const
{
    // Requests the records of every marble in i's static neighbourhood (a hint: no effect on
    // results), so that a scan that follows finds them on their way instead of missing one by one.
    // (Not for an oversize marble: its neighbourhood is the whole world.)
    if (m_body[i].bucket < 0)
        return;
    int ranges[rangeSlots];
    const int rangeCount = neighbourRanges(i, ranges);
    for (int r = 0; r < rangeCount; ++r) {
        for (int j = ranges[2 * r]; j < ranges[2 * r + 1]; ++j)
            __builtin_prefetch(&m_body[j]);
    }
}

void ExactModel::predict(int i)
{
    Vec2 p;
    Vec2 v;
    stateAt(m_body[i], p, v);
    Event best{noTime, EventKind::None, -1, 0};
    predictOwn(i, p, v, best);
    // The nine buckets one by one are only needed for pins and overflow lists.
    int buckets[9];
    int count = 0;
    if (!m_world->pins.empty() || m_overflowCount > 0)
        count = neighbourBuckets(i, buckets);
    scanPins(i, p, v, buckets, count, best);
    if (m_body[i].bucket < 0)
        scanEveryMarble(i, p, v, best); // oversize (a reanchor() never comes for these)
    else
        scanMarbles(i, p, v, buckets, count, best);
    setContact(i, best);
}

[[gnu::always_inline]] inline void ExactModel::offerFirstLook(int i, int j, const FirstLook &look, Event &best)
{
    // The first look's test of i (moving, at look.p with look.v) and j, offered to both. At t = 0
    // every marble feels the same gravity, so every relative path is straight (pairContact() with
    // phi1 = phi2 = 0 and dg = 0, written out, lower index first: on a straight path the order
    // only flips every sign, which leaves every product and so the result the same bits).
    const Body &bj = m_body[j];
    const Vec2 p = look.p;
    const Vec2 v = look.v;
    const bool iLow = i < j;
    const double dx = iLow ? p.x - bj.a.x : bj.a.x - p.x;
    const double dy = iLow ? p.y - bj.a.y : bj.a.y - p.y;
    const double dvx = iLow ? v.x - bj.b.x : bj.b.x - v.x;
    const double dvy = iLow ? v.y - bj.b.y : bj.b.y - v.y;
    const double s = straightContact(dx, dy, dvx, dvy, look.radius + bj.radius, m_sLeft);
    if (!(s <= m_sLeft))
        return;
    const double tau = phi1Inverse(m_lambda, s);
    if (!(tau <= std::min({best.time, bj.contactTime, 1.0})))
        return;
    const Event ei{tau, EventKind::Pair, j, 0};
    const Event ej{tau, EventKind::Pair, i, 0};
    if (before(i, ei, best))
        best = ei;
    if (before(j, ej, contactOf(j))) {
        // A resting marble has no turn of its own: it joins the calendar (see predictAll()).
        if (m_rec[j].contactKind == EventKind::None && resting(j))
            m_restingHit.push_back(j);
        setContact(j, ej);
    }
}

void ExactModel::firstLookWithSleepers(int i, const FirstLook &look, Event &best)
{
    // The same partners in the same order, bucket by bucket: the awake marbles of each
    // bucket and its sleepers, merged by World index (their order among all marbles); then the
    // oversize marbles (at rest, they have no turn of their own).
    int runs[rangeSlots];
    const int runCount = runsAround(m_body[i].bucket, runs, [](int b) { return b; });
    for (int r = 0; r < runCount; ++r)
        firstLookRun(i, look, runs[2 * r], runs[2 * r + 1], best);
    firstLookAtOversize(i, look, best);
}

void ExactModel::firstLookRun(int i, const FirstLook &look, int firstBucket, int lastBucket, Event &best)
{
    // The first look of i at buckets firstBucket .. lastBucket - 1 (consecutive), with their
    // sleepers in their places. Sleepers rest: they are partners from either side. One within
    // reach joins the arrays.
    if (!m_layer || m_sleepStart[firstBucket] == m_sleepStart[lastBucket]) {
        for (int j = m_start[firstBucket]; j < m_start[lastBucket]; ++j) {
            if (testedFrom(i, j))
                offerFirstLook(i, j, look, best);
        }
        return;
    }
    for (int b = firstBucket; b < lastBucket; ++b) {
        int j = m_start[b];
        int q = m_sleepStart[b];
        const int jEnd = m_start[b + 1];
        const int qEnd = m_sleepStart[b + 1];
        while (j < jEnd || q < qEnd) {
            if (q < qEnd && m_sleepers[q].id < 0) {
                ++q;
                continue;
            }
            if (q == qEnd || (j < jEnd && m_order[j] < m_sleepers[q].id)) {
                if (testedFrom(i, j))
                    offerFirstLook(i, j, look, best);
                ++j;
                continue;
            }
            int k = m_sleepers[q].promoted;
            if (k < 0 && nearSleeper(look.p, look.v, look.radius, q))
                k = promote(q);
            if (k >= 0)
                offerFirstLook(i, k, look, best);
            ++q;
        }
    }
}

void ExactModel::predictAll()
{
    const int n = m_awake;
    // A marble at rest without gravity stays put until something hits it: no wall, pin or grid
    // event, and no contact with another resting marble. The first look costs nothing for it.
    const bool anyResting = m_anyResting;
    m_firstKeys.clear();
    m_restingHit.clear();
    // One pass in grid order. For each moving marble: its own events, pins, then every pair of
    // neighbours once, offered to both marbles: from the lower index when both move, from the
    // moving one otherwise (no marble has moved bucket yet, so each bucket's marbles are its
    // static range). A moving marble's record is final once its turn is over.
    for (int i = 0; i < n; ++i) {
        if (i >= m_ready)
            makeReady(i + 1);
        if (resting(i))
            continue;
        // At t = 0 the state is (a, b) itself.
        const Vec2 p = m_body[i].a;
        const Vec2 v = m_body[i].b;
        const FirstLook look{p, v, m_body[i].radius};
        Event best = contactOf(i);
        predictOwn(i, p, v, best);
        if (!m_world->pins.empty()) {
            int buckets[9];
            const int count = neighbourBuckets(i, buckets);
            scanPins(i, p, v, buckets, count, best);
        }
        int ranges[rangeSlots];
        const int rangeCount = neighbourRanges(i, ranges);
        for (int r = 0; r < rangeCount; ++r) {
            if (ranges[2 * r + 1] > m_ready)
                makeReady(ranges[2 * r + 1]);
        }
        if (m_body[i].bucket < 0) {
            firstLookOversize(i, look, best);
        } else if (!m_layer) {
            for (int r = 0; r < rangeCount; ++r) {
                // Partners below i only if some marbles rest (those are not looked at from their side).
                for (int j = anyResting ? ranges[2 * r] : std::max(ranges[2 * r], i + 1); j < ranges[2 * r + 1]; ++j) {
                    if (testedFrom(i, j))
                        offerFirstLook(i, j, look, best);
                }
            }
        } else {
            firstLookWithSleepers(i, look, best);
        }
        setContact(i, best);
        // Its event (keyOf) is the earlier of that contact and its grid event: inside the frame
        // exactly when one of them is.
        if (best.time <= 1.0 || m_rec[i].crossTime <= 1.0)
            m_firstKeys.push_back(keyOf(i));
    }
    makeReady(n);
    for (const int j : m_restingHit)
        m_firstKeys.push_back(keyOf(j));
    // The calendar: about one slot per event found so far.
    const auto slots = std::max<std::size_t>(16, m_firstKeys.size());
    assignGrowingByDoubling(m_slotHead, slots, -1);
    m_firstSlot = 0;
    // The later slots' entries go into m_nodes in slot order (a counting sort; the same lists
    // as inserting them one by one, which would scatter each slot's nodes over the array).
    assignGrowingByDoubling(m_slotCount, slots + 1, 0);
    for (const Key &key : m_firstKeys) {
        const int slot = slotOf(key.time);
        if (slot != m_firstSlot)
            ++m_slotCount[static_cast<std::size_t>(slot) + 1];
        else
            calendarInsert(key);
    }
    accumulateCounts(m_slotCount);
    if (m_nodes.capacity() < 2 * static_cast<std::size_t>(m_slotCount[slots]))
        m_nodes.reserve(4 * static_cast<std::size_t>(m_slotCount[slots])); // the events add more
    m_nodes.resize(static_cast<std::size_t>(m_slotCount[slots]));
    for (const Key &first : m_firstKeys) {
        const int slot = slotOf(first.time);
        if (slot == m_firstSlot)
            continue;
        Key key = first;
        issueTicket(key);
        m_nodes[static_cast<std::size_t>(m_slotCount[static_cast<std::size_t>(slot)]++)] = key;
    }
    // Slot s's nodes are now the run from m_slotCount[s - 1] to m_slotCount[s]: link each run.
    for (std::size_t slot = 1; slot < slots; ++slot) {
        const std::int32_t begin = m_slotCount[slot - 1];
        const std::int32_t end = m_slotCount[slot];
        if (begin == end)
            continue;
        m_slotHead[slot] = begin;
        for (std::int32_t node = begin; node < end; ++node)
            m_nodes[static_cast<std::size_t>(node)].next = node + 1 < end ? node + 1 : -1;
    }
}

void ExactModel::unlockMoved(int i, Vec2 v)
{
    // A marble held against a wall keeps the hold only while nothing gives it a normal velocity.
    Guard &guard = m_rec[i].guard;
    Body &body = m_body[i];
    if ((guard.locked & 1) && v.x != 0.0) {
        guard.locked &= ~1u;
        body.gravityOff &= ~1u;
    }
    if ((guard.locked & 2) && v.y != 0.0) {
        guard.locked &= ~2u;
        body.gravityOff &= ~2u;
    }
}

bool ExactModel::overLimit(int i) const
{
    // Resting contacts always count; collisions against the inelastic-collapse limit for e < 1,
    // and against the far larger limit of a wedged marble whatever e.
    const Guard &guard = m_rec[i].guard;
    return guard.restHits > freezeAfterRestingContacts || guard.pairHits > freezeAfterElasticCollisions
        || (m_inelastic && guard.pairHits > freezeAfterCollisions);
}

bool ExactModel::countContact(int i)
{
    if (count(m_rec[i].guard.recheckHits) <= freezeAfterRechecks || m_body[i].frozen)
        return false;
    ++m_rec[i].stamp;
    freeze(i);
    return true;
}

void ExactModel::freeze(int i)
{
    Body &body = m_body[i];
    if (body.frozen)
        return;
    Vec2 p;
    Vec2 v;
    stateAt(body, p, v);
    body.frozen = 1;
    body.gravityOff = 3;
    m_rec[i].invMass = 0.0;
    m_rec[i].crossTime = noTime;
    setState(i, p, {});
    ++m_frozenCount;
}

void ExactModel::collidePair(World &world, int i, int j)
{
    Vec2 pi;
    Vec2 vi;
    Vec2 pj;
    Vec2 vj;
    stateAt(m_body[i], pi, vi);
    stateAt(m_body[j], pj, vj);
    const Vec2 n = unitOrZero({pj.x - pi.x, pj.y - pi.y});
    // Approach speed along the normal (from i towards j).
    const double approach = (vi.x - vj.x) * n.x + (vi.y - vj.y) * n.y;
    const double wi = m_rec[i].invMass;
    const double wj = m_rec[j].invMass;
    Guard &gi = m_rec[i].guard;
    Guard &gj = m_rec[j].guard;
    count(gi.pairHits);
    count(gj.pairHits);
    if (approach <= m_restSpeed) {
        count(gi.restHits);
        count(gj.restHits);
    }
    if (approach > 0.0 && wi + wj > 0.0) {
        // Impulse J along n with (v_i' - v_j').n = -e (v_i - v_j).n and m_i v_i + m_j v_j kept:
        // J = (1 + e) approach / (1/m_i + 1/m_j); v_i -= J/m_i n, v_j += J/m_j n.
        const bool elastic = m_inelastic && (gi.pairHits > elasticAfterCollisions || gj.pairHits > elasticAfterCollisions);
        const double e = elastic ? 1.0 : m_restitution;
        const double impulse = (1.0 + e) * approach / (wi + wj);
        applyPairImpulse(impulse, n, vi, wi, vj, wj, world.lastHit[m_body[i].id], world.lastHit[m_body[j].id],
                         world.frame + 1);
        ++m_collisionCount;
    }
    ++m_rec[i].stamp;
    ++m_rec[j].stamp;
    if (!m_body[i].frozen) {
        unlockMoved(i, vi);
        setState(i, pi, vi);
    }
    if (!m_body[j].frozen) {
        unlockMoved(j, vj);
        setState(j, pj, vj);
    }
    if (overLimit(i))
        freeze(i);
    if (overLimit(j))
        freeze(j);
}

void ExactModel::collidePin(World &world, int i, int pin)
{
    Vec2 p;
    Vec2 v;
    stateAt(m_body[i], p, v);
    const Vec2 q = world.pins[pin];
    const Vec2 n = unitOrZero({q.x - p.x, q.y - p.y});
    const double approach = dot(v, n);
    Guard &guard = m_rec[i].guard;
    count(guard.pairHits);
    if (approach <= m_restSpeed)
        count(guard.restHits);
    if (approach > 0.0) {
        // The pin is immovable (infinite mass): v' = v - (1 + e) (v.n) n.
        const bool elastic = m_inelastic && guard.pairHits > elasticAfterCollisions;
        const double e = elastic ? 1.0 : m_restitution;
        const Vec2 in = v;
        v.x -= (1.0 + e) * approach * n.x;
        v.y -= (1.0 + e) * approach * n.y;
        world.lastHit[m_body[i].id] = HitRecord::of(world.frame + 1, in, n, v);
        ++m_collisionCount;
    }
    ++m_rec[i].stamp;
    unlockMoved(i, v);
    setState(i, p, v);
    if (overLimit(i))
        freeze(i);
}

void ExactModel::collideWall(World &world, int i, int wall)
{
    Body &body = m_body[i];
    Vec2 p;
    Vec2 vel;
    stateAt(body, p, vel);
    const int axis = wall / 2;          // 0: x, 1: y
    const bool upper = (wall % 2) == 1; // right or bottom
    double &x = axis == 0 ? p.x : p.y;
    double &v = axis == 0 ? vel.x : vel.y;
    const double r = body.radius;
    const double side = axis == 0 ? m_width : m_height;
    const double gAxis = axis == 0 ? m_gravity.x : m_gravity.y;
    // Outward speed (towards this wall) and the push of gravity towards it.
    const double outward = upper ? v : -v;
    const double gOut = upper ? gAxis : -gAxis;
    // A marble too wide for the stage along this axis touches both of its walls at once: bounced
    // off one, it would be past the other at the same instant, for ever. It is held between them
    // instead: stopped along the axis where it is, and held there (as in resting contact) until a
    // collision moves it again, which it passes on to the walls.
    const bool pinched = 2.0 * r >= side;
    // Touching exactly: the solver stops at contact up to rounding, and the marble is put there.
    // One that was further past the wall (placed or spawned overlapping it) is not moved: it
    // bounces where it is and leaves the wall by its own motion, instead of jumping by the depth
    // of its overlap into whatever lies beside it (found by fuzz/fuzz_physics).
    const double contact = upper ? side - r : r;
    const double past = upper ? x - contact : contact - x;
    if (!pinched && past <= wallTouchTolerance(side, r))
        x = contact;
    Guard &guard = m_rec[i].guard;
    count(guard.wallHits);
    const double e = m_restitution;
    // A bounce of speed w against gravity gOut rises w^2 / (2 gOut): below restHeightPx it is
    // resting contact instead.
    const double restSpeed = gOut > 0.0 ? std::sqrt(2.0 * gOut * restHeightPx) : 0.0;
    const Vec2 in = vel;
    bool hit = false;
    if (outward > 0.0) {
        v = -e * v;
        hit = true;
        ++m_collisionCount;
    }
    if ((pinched || (gOut > 0.0 && outward >= 0.0 && e * outward <= restSpeed)) && !body.frozen) {
        // Its motion across the stage is taken (held, in lastHeldCount()); a marble wider than
        // the stage both ways, stopped on both axes, is one marble held (it had counted two).
        if (pinched && v != 0.0 && !guard.pinched) {
            guard.pinched = 1;
            ++m_pinchedCount;
        }
        v = 0.0;
        body.gravityOff |= static_cast<std::uint8_t>(1u << axis);
        guard.locked |= static_cast<std::uint8_t>(1u << axis);
    }
    if (hit) {
        Vec2 n{};
        (axis == 0 ? n.x : n.y) = upper ? 1.0 : -1.0;
        world.lastHit[m_body[i].id] = HitRecord::of(world.frame + 1, in, n, vel);
    }
    ++m_rec[i].stamp;
    setState(i, p, vel);
    if (guard.wallHits > freezeAfterWallBounces)
        freeze(i);
}

void ExactModel::step(World &world)
{
    const int n = world.marbleCount();
    m_eventCount = 0;
    m_collisionCount = 0;
    m_frozenCount = 0;
    m_pinchedCount = 0;
    m_leftAllFinite = n == 0;
    if (n == 0)
        return;
    beginFrame(world);
    predictAll();
    // A world that already left finite numbers is only carried along (World::step reports it):
    // the first look's findings are dropped.
    if (!m_finite) {
        endFrame(world);
        return;
    }
    const Event none{noTime, EventKind::None, -1, 0};
    // The guard of point 6: the events (all but grid events) handled at the current instant.
    const std::int64_t instantLimit = std::int64_t(freezeAfterInstantCollisions) * n;
    double instant = -infinity;
    std::int64_t atInstant = 0;
    for (int i = calendarFirst(); i >= 0; i = calendarFirst()) {
        const Event ev = currentEvent(i);
        setNow(std::max(m_now, ev.time));
        ++m_eventCount;
        if (ev.kind == EventKind::Cross) {
            reanchor(i);
            schedule(i);
            continue;
        }
        if (m_now > instant) {
            instant = m_now;
            atInstant = 0;
        }
        // Past the limit, time has stopped: whoever collides at this instant is frozen.
        const bool stuck = ++atInstant > instantLimit;
        // Every other event ends with a fresh prediction of i. Its old contact is void from here
        // on (so that no partner's search stops at it).
        setContact(i, none);
        switch (ev.kind) {
        case EventKind::Pair:
            if (m_rec[ev.other].stamp == ev.stamp) {
                if (m_prefetchEvents) {
                    __builtin_prefetch(&world.lastHit[static_cast<std::size_t>(m_body[static_cast<std::size_t>(ev.other)].id)], 1);
                    prefetchNear(ev.other);
                    prefetchNear(i);
                }
                collidePair(world, i, ev.other);
                if (stuck) {
                    freeze(i);
                    freeze(ev.other);
                }
                setContact(ev.other, none);
                predict(ev.other);
                schedule(ev.other);
            }
            break;
        case EventKind::Pin:
            collidePin(world, i, ev.other);
            if (stuck)
                freeze(i);
            break;
        case EventKind::Wall:
            collideWall(world, i, ev.other);
            if (stuck)
                freeze(i);
            break;
        case EventKind::RecheckPin:
            countContact(i);
            break;
        case EventKind::RecheckPair:
            // Re-checks count against both marbles, so that even a frozen marble's re-checks
            // end: its partner freezes in turn, and frozen pairs are not predicted.
            countContact(i);
            if (countContact(ev.other)) {
                setContact(ev.other, none);
                predict(ev.other);
                schedule(ev.other);
            }
            break;
        case EventKind::Cross:
        case EventKind::None:
            break;
        }
        predict(i);
        schedule(i);
    }
    endFrame(world);
}

} // namespace marbles
