/* The compiled DOP853 peer: scipy's DOP853 (scipy/integrate/_ivp/rk.py, class DOP853, and
 * dop853_coefficients.py) transcribed to C, driving the Fig. 8 rigid-block scenes of rocklab's
 * bench with the same physics and events (docs/MODEL.md "Rigid block", "Devices"):
 *
 *   bare         Housner's block, p = 2 rad/s, alpha = 10 deg, one-sine pulse A/(g alpha) = 1.5,
 *                wg/p = 4, 10 s; impact at theta = 0 with r = (1 - 1.5 sin^2 alpha)^2,
 *                overturning at |theta| = alpha.
 *   mechanistic  the same block with the twin mechanistic clutch: sigma = 0.5, clutch frequency
 *                25 p, cbar = 1 1/s, eps = 1e6, rho = 0.05 m, no friction, no play; events at
 *                contact (delta = +-up) and the re-engagement resets, as rocklab's model.
 *
 * What is scipy's: the tableau, the error norm (scipy's _estimate_error_norm: the 5th-order
 * estimate damped by the 3rd, RMS over the components with scale atol + rtol max(|y|, |y_new|)),
 * the step-size control (SAFETY 0.9, factors within [0.2, 10], no growth after a rejection),
 * the starting step (select_initial_step), the dense output of order 7 (its three extra stages
 * computed only on a step that needs its interior, as solve_ivp computes `sol` only when an
 * event is bracketed), events found by sign changes at step ends and located on the dense
 * output to 4 eps. What a hand-written driver adds, as rocklab does: the step size is kept
 * across an event restart (solve_ivp would start a new solver), the located time is the bracket
 * end past the crossing (a restart is never ambiguous about its side), the run stops at the
 * pulse's end (its kink) and goes on from there, and the peak |theta| is read from the step ends,
 * the event points and the zeros of theta' (a non-terminal event) on the dense output.
 *
 * Usage: dop853 bare|mechanistic REPEATS RTOL...   one line per rtol: rtol, RHS calls, steps,
 *                                                   rejected, events, peak |theta|/alpha,
 *                                                   fastest and median time of REPEATS runs (us)
 *        dop853 rhs bare|mechanistic CALLS         ns per right-hand-side call alone
 *
 * Build: gcc -O2 -march=x86-64-v2 -o dop853 dop853.c -lm   (scripts/peer/run.sh builds and runs it beside rocklab)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dop853_coefficients.h"

#define G 9.81
#define NMAX 6
#define NEV 8
#define EPS 2.220446049250313e-16
#define SAFETY 0.9
#define MIN_FACTOR 0.2
#define MAX_FACTOR 10.0
#define ERROR_EXPONENT (-1.0 / 8.0) /* -1 / (error_estimator_order + 1), order 7 */

enum { RISING, FALLING, EITHER };
enum { EV_IMPACT, EV_OVERTURN, EV_UPLIFT_POS, EV_UPLIFT_NEG, EV_CONTACT_A, EV_CONTACT_B,
       EV_RESET_A, EV_RESET_B };
static const int EV_DIRECTION[NEV] = {FALLING, RISING, RISING, RISING, EITHER, EITHER, RISING,
                                      FALLING};

typedef struct {
    int n;    /* state size: 2 (theta, theta') or 6 (+ ya, ya', yb, yb') */
    int mech; /* twin mechanistic clutch */
    int n_events;
    /* block */
    double alpha, r_size, m, p2, i0, sin_a, tan_a, restitution, rest_rate;
    /* pulse a_g = amp sin(omega t), 0 <= t <= t_pulse */
    double amp, omega, t_pulse, duration;
    /* clutch (translational form, docs/MODEL.md "Devices") */
    double mr, k, eps_hat, cbar, play;
    /* phase */
    double pivot;
    int rocking;
    double atol[NMAX];
    double rtol;
    /* results */
    long rhs_calls, steps, rejected, events;
    double peak;
} Scene;

static inline double ground(const Scene *s, double t)
{
    double phase = s->omega * t;
    if (!(phase >= 0.0 && phase <= 2.0 * M_PI))
        return 0.0;
    return s->amp * sin(phase);
}

/* f = 1/2 k [1 + tanh(eps z)] z, z = delta - up (clutch a; b is its mirror). */
static inline double clutch_force(const Scene *s, double z)
{
    return 0.5 * s->k * (1.0 + tanh(s->eps_hat * z)) * z;
}

/* Horizontal position and velocity of the centre of mass (0 while flat). */
static inline void x_xdot(const Scene *s, const double *y, double *x, double *xdot)
{
    if (!s->rocking) {
        *x = 0.0;
        *xdot = 0.0;
        return;
    }
    double a = s->pivot * s->alpha - y[0];
    *x = s->r_size * (s->pivot * s->sin_a - sin(a));
    *xdot = s->r_size * cos(a) * y[1];
}

/* (1 + 3/4 sigma C^2) theta'' = -p^2 (S + (a_g/g) C) + Fd R C / I0 with S = sin(s alpha - theta),
 * C = cos(s alpha - theta); the mechanistic clutch couples through springs (no coupled mass);
 * mr y'' = f - cbar mr y' for each flywheel. */
static inline void rhs(const Scene *s, double t, const double *y, double *dy)
{
    double ag = ground(s, t);
    if (!s->mech) {
        double a = s->pivot * s->alpha - y[0];
        dy[0] = y[1];
        dy[1] = -s->p2 * (sin(a) + ag / G * cos(a));
        return;
    }
    double sa = 0.0, ca = 1.0, x = 0.0;
    if (s->rocking) {
        double a = s->pivot * s->alpha - y[0];
        sa = sin(a);
        ca = cos(a);
        x = s->r_size * (s->pivot * s->sin_a - sa);
    }
    double fa = clutch_force(s, x - y[2] - s->play);
    double fb = -clutch_force(s, -(x - y[4]) - s->play);
    dy[2] = y[3];
    dy[3] = fa / s->mr - s->cbar * y[3];
    dy[4] = y[5];
    dy[5] = fb / s->mr - s->cbar * y[5];
    if (s->rocking) {
        double fd = -(fa + fb);
        dy[0] = y[1];
        dy[1] = -s->p2 * (sa + ag / G * ca) + fd * s->r_size * ca / s->i0;
    } else {
        dy[0] = 0.0;
        dy[1] = 0.0;
    }
}

/* Uplift margin while flat: s (Fd - m a_g) - m g tan(alpha). */
static double uplift_margin(const Scene *s, double side, double t, const double *y)
{
    double fd = 0.0;
    if (s->mech) {
        double fa = clutch_force(s, -y[2] - s->play);
        double fb = -clutch_force(s, y[4] - s->play);
        fd = -(fa + fb);
    }
    return side * (fd - s->m * ground(s, t)) - s->m * G * s->tan_a;
}

static void events(const Scene *s, double t, const double *y, double *g)
{
    g[EV_IMPACT] = s->rocking ? s->pivot * y[0] : 1.0;
    g[EV_OVERTURN] = s->rocking ? s->pivot * y[0] - s->alpha : -1.0;
    g[EV_UPLIFT_POS] = s->rocking ? -1.0 : uplift_margin(s, 1.0, t, y);
    g[EV_UPLIFT_NEG] = s->rocking ? -1.0 : uplift_margin(s, -1.0, t, y);
    if (!s->mech)
        return;
    double x, xdot;
    x_xdot(s, y, &x, &xdot);
    double da = x - y[2], db = x - y[4];
    g[EV_CONTACT_A] = da - s->play;
    g[EV_CONTACT_B] = db + s->play;
    /* A reset function is a constant of its non-triggering sign while the clutch is engaged
     * (the paper's rule: resettable while delta_a < up, delta_b > -up). */
    g[EV_RESET_A] = da < s->play ? xdot - y[3] : 1.0;
    g[EV_RESET_B] = db > -s->play ? xdot - y[5] : -1.0;
}

static double event_one(const Scene *s, int i, double t, const double *y)
{
    double g[NEV];
    if (i == EV_IMPACT)
        return s->rocking ? s->pivot * y[0] : 1.0;
    events(s, t, y, g);
    return g[i];
}

static int triggers(int direction, double before, double after)
{
    switch (direction) {
    case RISING: return before < 0.0 && after > 0.0;
    case FALLING: return before > 0.0 && after < 0.0;
    default: return before * after < 0.0;
    }
}

/* ---- the solver: scipy's RungeKutta/DOP853 ---- */

typedef struct {
    Scene *s;
    int n;
    double t, h_abs;
    double y[NMAX], f[NMAX];
    double K[N_STAGES_EXTENDED][NMAX];
    double t_old, h;
    double y_old[NMAX];
    double F[INTERPOLATOR_POWER][NMAX];
    int dense_ready;
} Solver;

static inline void call_rhs(Solver *so, double t, const double *y, double *dy)
{
    so->s->rhs_calls++;
    rhs(so->s, t, y, dy);
}

static double rms_norm(int n, const double *v)
{
    double sum = 0.0;
    for (int i = 0; i < n; i++)
        sum += v[i] * v[i];
    return sqrt(sum / n);
}

/* scipy's select_initial_step (error_estimator_order 7). */
static double select_initial_step(Solver *so)
{
    int n = so->n;
    double scale[NMAX], v[NMAX], y1[NMAX], f1[NMAX];
    for (int i = 0; i < n; i++)
        scale[i] = so->s->atol[i] + fabs(so->y[i]) * so->s->rtol;
    for (int i = 0; i < n; i++)
        v[i] = so->y[i] / scale[i];
    double d0 = rms_norm(n, v);
    for (int i = 0; i < n; i++)
        v[i] = so->f[i] / scale[i];
    double d1 = rms_norm(n, v);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    for (int i = 0; i < n; i++)
        y1[i] = so->y[i] + h0 * so->f[i];
    call_rhs(so, so->t + h0, y1, f1);
    for (int i = 0; i < n; i++)
        v[i] = (f1[i] - so->f[i]) / scale[i];
    double d2 = rms_norm(n, v) / h0;
    double h1 = (d1 <= 1e-15 && d2 <= 1e-15) ? fmax(1e-6, h0 * 1e-3)
                                             : pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    return fmin(100.0 * h0, h1);
}

static void restart(Solver *so, double t, const double *y)
{
    so->t = t;
    memcpy(so->y, y, sizeof(double) * so->n);
    call_rhs(so, t, so->y, so->f);
    if (so->h_abs == 0.0)
        so->h_abs = select_initial_step(so);
    so->dense_ready = 0;
}

/* scipy's rk_step: stages K[0..11], y_new, f_new = K[12]. */
static void rk_step(Solver *so, double h, double *y_new)
{
    int n = so->n;
    double (*K)[NMAX] = so->K;
    memcpy(K[0], so->f, sizeof(double) * n);
    for (int s = 1; s < N_STAGES; s++) {
        double ys[NMAX];
        for (int i = 0; i < n; i++) {
            double dy = 0.0;
            for (int j = 0; j < s; j++)
                dy += K[j][i] * A[s][j];
            ys[i] = so->y[i] + dy * h;
        }
        call_rhs(so, so->t + C[s] * h, ys, K[s]);
    }
    for (int i = 0; i < n; i++) {
        double acc = 0.0;
        for (int j = 0; j < N_STAGES; j++)
            acc += K[j][i] * B[j];
        y_new[i] = so->y[i] + h * acc;
    }
    call_rhs(so, so->t + h, y_new, K[N_STAGES]);
}

/* scipy's DOP853._estimate_error_norm. */
static double error_norm(Solver *so, double h, const double *scale)
{
    int n = so->n;
    double e5 = 0.0, e3 = 0.0;
    for (int i = 0; i < n; i++) {
        double a5 = 0.0, a3 = 0.0;
        for (int j = 0; j <= N_STAGES; j++) {
            a5 += so->K[j][i] * E5[j];
            a3 += so->K[j][i] * E3[j];
        }
        a5 /= scale[i];
        a3 /= scale[i];
        e5 += a5 * a5;
        e3 += a3 * a3;
    }
    if (e5 == 0.0 && e3 == 0.0)
        return 0.0;
    double denominator = e5 + 0.01 * e3;
    return fabs(h) * e5 / sqrt(denominator * n);
}

/* One accepted step toward t_bound (scipy's _step_impl). Returns 0, or -1 when the step size
 * underflows. */
static int step(Solver *so, double t_bound)
{
    int n = so->n;
    double min_step = 10.0 * fabs(nextafter(so->t, INFINITY) - so->t);
    double h_abs = so->h_abs < min_step ? min_step : so->h_abs;
    int rejected = 0;
    double y_new[NMAX];
    for (;;) {
        if (h_abs < min_step)
            return -1;
        double t_new = so->t + h_abs;
        if (t_new > t_bound)
            t_new = t_bound;
        double h = t_new - so->t;
        h_abs = fabs(h);
        rk_step(so, h, y_new);
        double scale[NMAX];
        for (int i = 0; i < n; i++)
            scale[i] = so->s->atol[i] + fmax(fabs(so->y[i]), fabs(y_new[i])) * so->s->rtol;
        double err = error_norm(so, h, scale);
        if (err < 1.0) {
            double factor = err == 0.0 ? MAX_FACTOR
                                       : fmin(MAX_FACTOR, SAFETY * pow(err, ERROR_EXPONENT));
            if (rejected)
                factor = fmin(1.0, factor);
            so->h_abs = h_abs * factor;
            so->h = h;
            so->t_old = so->t;
            memcpy(so->y_old, so->y, sizeof(double) * n);
            so->t = t_new;
            memcpy(so->y, y_new, sizeof(double) * n);
            memcpy(so->f, so->K[N_STAGES], sizeof(double) * n);
            so->dense_ready = 0;
            so->s->steps++;
            return 0;
        }
        h_abs *= fmax(MIN_FACTOR, SAFETY * pow(err, ERROR_EXPONENT));
        rejected = 1;
        so->s->rejected++;
    }
}

/* scipy's DOP853._dense_output_impl: the three extra stages, then F. */
static void dense_output(Solver *so)
{
    if (so->dense_ready)
        return;
    int n = so->n;
    double h = so->h;
    double (*K)[NMAX] = so->K;
    for (int s = N_STAGES + 1; s < N_STAGES_EXTENDED; s++) {
        double ys[NMAX];
        for (int i = 0; i < n; i++) {
            double dy = 0.0;
            for (int j = 0; j < s; j++)
                dy += K[j][i] * A[s][j];
            ys[i] = so->y_old[i] + dy * h;
        }
        call_rhs(so, so->t_old + C[s] * h, ys, K[s]);
    }
    for (int i = 0; i < n; i++) {
        double delta_y = so->y[i] - so->y_old[i];
        so->F[0][i] = delta_y;
        so->F[1][i] = h * K[0][i] - delta_y;
        so->F[2][i] = 2.0 * delta_y - h * (so->f[i] + K[0][i]);
        for (int r = 0; r < INTERPOLATOR_POWER - 3; r++) {
            double acc = 0.0;
            for (int j = 0; j < N_STAGES_EXTENDED; j++)
                acc += D[r][j] * K[j][i];
            so->F[3 + r][i] = h * acc;
        }
    }
    so->dense_ready = 1;
}

/* Dop853DenseOutput._call_impl. */
static void dense_at(const Solver *so, double t, double *y)
{
    double x = (t - so->t_old) / so->h;
    for (int i = 0; i < so->n; i++) {
        double v = 0.0;
        for (int r = INTERPOLATOR_POWER - 1; r >= 0; r--) {
            v += so->F[r][i];
            v *= ((INTERPOLATOR_POWER - 1 - r) % 2 == 0) ? x : 1.0 - x;
        }
        y[i] = v + so->y_old[i];
    }
}

/* A root of g on [ta, tb] (g(ta), g(tb) of opposite signs) on the dense output, by the
 * Illinois method to 4 eps (solve_ivp's brentq xtol = rtol = 4 eps). Returns the end of the
 * final bracket past the crossing (tb's side). */
typedef double (*GFun)(const Scene *, int, double, const double *);

static double theta_dot_fn(const Scene *s, int i, double t, const double *y)
{
    (void)s; (void)i; (void)t;
    return y[1];
}

static double locate(const Solver *so, GFun g, int index, double ta, double ga, double tb,
                     double gb)
{
    double y[NMAX];
    int side = 0;
    for (int it = 0; it < 200; it++) {
        if (tb - ta <= 4.0 * EPS * fmax(fabs(ta), fabs(tb)) + 4.0 * EPS)
            break;
        double tm = (ta * gb - tb * ga) / (gb - ga);
        if (!(tm > ta && tm < tb))
            tm = 0.5 * (ta + tb);
        dense_at(so, tm, y);
        double gm = g(so->s, index, tm, y);
        if (gm == 0.0) {
            /* On the root: step just past it toward tb. */
            ta = tm;
            ga = gm;
            continue;
        }
        if ((gm < 0.0) == (ga < 0.0) && ga != 0.0) {
            ta = tm;
            ga = gm;
            if (side == -1)
                gb *= 0.5;
            side = -1;
        } else {
            tb = tm;
            gb = gm;
            if (side == 1)
                ga *= 0.5;
            side = 1;
        }
    }
    return tb;
}

/* ---- the scene driver ---- */

static void observe(Scene *s, const double *y)
{
    if (s->rocking && fabs(y[0]) > s->peak)
        s->peak = fabs(y[0]);
}

/* First time >= t at which |a_g| exceeds level (closed form for the sine pulse); -1: never. */
static double first_exceedance(const Scene *s, double t, double level)
{
    if (t >= s->t_pulse || level >= s->amp)
        return -1.0;
    double arc = asin(level / s->amp);
    double phase0 = s->omega * t;
    double k = ceil((phase0 - arc) / M_PI - 1e-9);
    if (k < 0.0)
        k = 0.0;
    double te = fmax((arc + k * M_PI) / s->omega, t);
    for (int i = 0; i < 64; i++) {
        if (te > s->t_pulse)
            return -1.0;
        if (fabs(ground(s, te)) > level)
            return te;
        te = nextafter(te, INFINITY);
    }
    return -1.0;
}

enum { GO, STOP };

static int uplift(Scene *s, double side, double *y)
{
    s->rocking = 1;
    s->pivot = side;
    y[0] = 0.0;
    y[1] = 0.0;
    return GO;
}

/* Flat at t: lift at once if the ground asks for it; after the pulse the block is at rest
 * (it cannot move in contact); during the pulse, idle until the next exceedance if the device
 * is at rest, else integrate the flat phase. */
static int land(Scene *s, double *t, double *y)
{
    s->rocking = 0;
    for (double side = 1.0; side >= -1.0; side -= 2.0)
        if (uplift_margin(s, side, *t, y) > 0.0)
            return uplift(s, side, y);
    if (*t >= s->t_pulse)
        return STOP;
    int device_rest = !s->mech || (y[3] == 0.0 && y[5] == 0.0);
    if (!device_rest)
        return GO;
    double te = first_exceedance(s, *t, G * s->tan_a);
    if (te < 0.0)
        return STOP;
    *t = te;
    return uplift(s, -copysign(1.0, ground(s, te)), y);
}

static int apply_event(Scene *s, int index, double *t, double *y)
{
    double x, xdot;
    switch (index) {
    case EV_IMPACT:
        y[1] *= sqrt(s->restitution);
        y[0] = 0.0;
        s->pivot = -s->pivot;
        if (fabs(y[1]) < s->rest_rate) {
            y[1] = 0.0;
            return land(s, t, y);
        }
        return GO;
    case EV_OVERTURN:
        return STOP;
    case EV_UPLIFT_POS:
        return uplift(s, 1.0, y);
    case EV_UPLIFT_NEG:
        return uplift(s, -1.0, y);
    case EV_RESET_A:
        x_xdot(s, y, &x, &xdot);
        y[2] = x;
        return GO;
    case EV_RESET_B:
        x_xdot(s, y, &x, &xdot);
        y[4] = x;
        return GO;
    default: /* contacts: only a restart, so that no step straddles the clutch corner */
        return GO;
    }
}

/* Event values at a restart. A value that is exactly zero (a jump put the state on the
 * function's surface: theta = 0 after an impact or uplift, delta_a = up after a reset) has no
 * sign yet and takes that of the first sample inside the next step without triggering (as
 * rocklab's integrator), except the impact margin, whose sign just after is known, as rocklab's
 * model tells its integrator (`sign_after_zero`): +1 at uplift (theta' = 0), else that of
 * pivot theta'. */
static void events_at_restart(const Solver *so, double *g)
{
    const Scene *s = so->s;
    events(s, so->t, so->y, g);
    if (g[EV_IMPACT] == 0.0)
        g[EV_IMPACT] = so->y[1] == 0.0 ? 1.0 : copysign(1.0, s->pivot * so->y[1]);
}

/* Rates of the event functions at (t, y) moving at f, by a difference along f over d (d < 0 at
 * a step's end, inside the step just taken). */
static void event_rates(const Scene *s, double t, const double *y, const double *f,
                        const double *g, double d, int n, double *rates)
{
    double yd[NMAX], gd[NEV];
    for (int j = 0; j < n; j++)
        yd[j] = y[j] + d * f[j];
    events(s, t + d, yd, gd);
    for (int i = 0; i < s->n_events; i++)
        rates[i] = (gd[i] - g[i]) / d;
}

/* rocklab's event screen (src/solver/events.rs, no_root_inside): true when the cubic Hermite
 * interpolant of a function's end values a, b and end slopes da, db (per unit step), enlarged by
 * a margin, keeps the ends' common sign over the whole step. */
static int no_root_inside(double a, double da, double b, double db)
{
    double sg = a != 0.0 ? copysign(1.0, a) : copysign(1.0, da);
    if (!(sg * b > 0.0 && (a != 0.0 || sg * da > 0.0)))
        return 0;
    double v = fabs(b - a) + fabs(da) + fabs(db);
    double b0 = sg * a, b1 = sg * (a + da / 3.0), b2 = sg * (b - db / 3.0), b3 = sg * b;
    double c1 = (b0 + 3.0 * b1) / 4.0, c2 = (b1 + b2) / 2.0, c3 = (3.0 * b2 + b3) / 4.0;
    return c1 > 0.0 && c2 - v / 12.0 > 0.0 && c3 > 0.0;
}

#define EVENT_SAMPLES 4

static void run(Scene *s)
{
    Solver so = {.s = s, .n = s->n};
    int n = s->n, m;
    double y[NMAX] = {0}, g_old[NEV], g_new[NEV], r_old[NEV], r_new[NEV], t = 0.0;
    s->pivot = 1.0;
    s->rocking = 0;
    s->peak = 0.0;
    s->rhs_calls = s->steps = s->rejected = s->events = 0;
    if (land(s, &t, y) == STOP)
        return;
    restart(&so, t, y);
    events_at_restart(&so, g_old);
    m = s->n_events;
    for (;;) {
        double t_bound = so.t < s->t_pulse ? s->t_pulse : s->duration;
        double t0 = so.t, f0[NMAX], y0[NMAX];
        memcpy(y0, so.y, sizeof y0);
        memcpy(f0, so.f, sizeof f0);
        if (step(&so, t_bound) < 0) {
            fprintf(stderr, "step size underflow at t = %g\n", so.t);
            exit(1);
        }
        double h = so.t - t0, d = 1e-7 * h;
        events(s, so.t, so.y, g_new);
        /* The screen: end values and slopes; sub-samples on the dense output only where it
         * cannot rule a crossing out (scipy tests the step's ends only, and misses a function
         * that crosses twice inside a step). */
        double g_start[NEV];
        events(s, t0, y0, g_start);
        event_rates(s, t0, y0, f0, g_start, d, n, r_old);
        event_rates(s, so.t, so.y, so.f, g_new, -d, n, r_new);
        int scan = 0;
        for (int i = 0; i < m && !scan; i++)
            scan = !no_root_inside(g_old[i] != 0.0 ? g_old[i] : g_start[i], h * r_old[i],
                                   g_new[i], h * r_new[i]);
        int first = -1;
        double t_first = so.t;
        if (scan) {
            dense_output(&so);
            double ga[NEV], ta = t0, gb[NEV], yb[NMAX];
            memcpy(ga, g_old, sizeof ga);
            for (int k = 1; k <= EVENT_SAMPLES && first < 0; k++) {
                double tb = k == EVENT_SAMPLES ? so.t : t0 + h * k / EVENT_SAMPLES;
                if (k == EVENT_SAMPLES) {
                    memcpy(gb, g_new, sizeof gb);
                } else {
                    dense_at(&so, tb, yb);
                    events(s, tb, yb, gb);
                }
                for (int i = 0; i < m; i++) {
                    if (ga[i] == 0.0) { /* no sign yet: take this one */
                        ga[i] = gb[i];
                        continue;
                    }
                    if (!triggers(EV_DIRECTION[i], ga[i], gb[i]))
                        continue;
                    double te = locate(&so, event_one, i, ta, ga[i], tb, gb[i]);
                    if (first < 0 || te < t_first) {
                        first = i;
                        t_first = te;
                    }
                }
                for (int i = 0; i < m; i++)
                    if (gb[i] != 0.0)
                        ga[i] = gb[i];
                ta = tb;
            }
            if (first < 0)
                memcpy(g_new, ga, sizeof ga);
        }
        /* The extremum of theta inside the step (theta' changes sign). */
        double w_end = so.y[1];
        if (first >= 0) {
            double ye[NMAX];
            dense_at(&so, t_first, ye);
            w_end = ye[1];
        }
        if (s->rocking && so.y_old[1] * w_end < 0.0) {
            dense_output(&so);
            double tz = locate(&so, theta_dot_fn, 1, so.t_old, so.y_old[1], t_first, w_end);
            double yz[NMAX];
            dense_at(&so, tz, yz);
            observe(s, yz);
        }
        if (first < 0) {
            observe(s, so.y);
            if (so.t >= s->duration || (!s->rocking && so.t >= s->t_pulse))
                return;
            for (int i = 0; i < m; i++)
                if (g_new[i] != 0.0 || g_old[i] == 0.0)
                    g_old[i] = g_new[i];
            continue;
        }
        s->events++;
        dense_at(&so, t_first, y);
        observe(s, y);
        t = t_first;
        int action = apply_event(s, first, &t, y);
        /* Catch up with a crossing the jump put the state past (as rocklab's catch_up). */
        if (action == GO && s->rocking && s->pivot * y[0] - s->alpha >= 0.0)
            action = STOP;
        if (action == GO && s->rocking && s->pivot * y[0] < 0.0)
            action = apply_event(s, EV_IMPACT, &t, y);
        if (action == STOP)
            return;
        restart(&so, t, y);
        events_at_restart(&so, g_old);
    }
}

static void setup(Scene *s, int mech, double rtol)
{
    memset(s, 0, sizeof *s);
    double p = 2.0;
    s->alpha = 10.0 * M_PI / 180.0;
    s->m = 1.0;
    s->p2 = p * p;
    s->r_size = 3.0 * G / (4.0 * s->p2);
    s->i0 = 4.0 / 3.0 * s->m * s->r_size * s->r_size;
    s->sin_a = sin(s->alpha);
    s->tan_a = tan(s->alpha);
    s->restitution = pow(1.0 - 1.5 * s->sin_a * s->sin_a, 2.0);
    s->rest_rate = sqrt(2e-10) * p * s->alpha;
    s->amp = 1.5 * G * s->alpha;
    s->omega = 4.0 * p;
    s->t_pulse = 2.0 * M_PI / s->omega;
    s->duration = 10.0;
    s->mech = mech;
    s->n = mech ? 6 : 2;
    s->n_events = mech ? 8 : 4;
    s->rtol = rtol;
    double deflection = s->r_size * s->alpha;
    if (mech) {
        s->mr = 0.5 * s->m;
        s->k = s->mr * pow(25.0 * p, 2.0);
        s->eps_hat = 1e6 / 0.05;
        s->cbar = 1.0;
        s->play = 0.0;
        deflection = fmin(s->m * G * s->tan_a / s->k, deflection);
    }
    /* The error scales of rocklab's model: rotations ~alpha, rates ~p alpha, flywheel positions
     * ~ the clutch deflection that carries the uplift force, their rates p times it. */
    double scales[NMAX] = {s->alpha, p * s->alpha, deflection, p * deflection, deflection,
                           p * deflection};
    for (int i = 0; i < s->n; i++)
        s->atol[i] = rtol * scales[i];
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ns per right-hand-side call alone, over states spread along a rocking cycle: the fastest of
 * many short bursts (a burst fits in a scheduler slice, so on a loaded machine the fastest is
 * close to the idle machine's time, as for the scenes' fastest runs). Timed twice: calls
 * independent of each other (the processor overlaps them: the throughput), and calls chained
 * as a Runge-Kutta stage chain chains them (the latency): each call's angle and rate take
 * 1e-300 times the last call's derivative (the same states, but a data dependence). As in the
 * stage chain of this second-order system, the rate then waits on the last call's angular
 * acceleration and the angle, which the sine reads, on the last call's rate. */
static double rhs_burst_ns(Scene *s, long calls, int chained, double *sink)
{
    enum { BURST = 1000 };
    double y[NMAX] = {0}, dy[NMAX] = {0}, best = INFINITY, sum = 0.0;
    for (long done = 0; done < calls; done += BURST) {
        double t0 = now();
        for (long c = 0; c < BURST; c++) {
            double tau = 1e-7 * (double)(c & 1023);
            y[0] = -0.05 * tau * 1e4;
            y[1] = 0.1 - tau;
            if (chained) { /* (0 * dy would chain the calls too: it is not folded) */
                y[0] += 1e-300 * dy[0];
                y[1] += 1e-300 * dy[1];
            }
            y[2] = 1e-4 * tau;
            y[3] = tau;
            y[4] = -1e-4 * tau;
            y[5] = -tau;
            rhs(s, tau, y, dy);
            sum += dy[1] + dy[3] + dy[5];
        }
        double dt = now() - t0;
        if (dt < best)
            best = dt;
    }
    *sink += sum; /* once: a store through the pointer in the loop could alias the scene */
    return best / BURST * 1e9;
}

static void time_rhs(int mech, long calls)
{
    Scene s;
    setup(&s, mech, 1e-8);
    s.rocking = 1;
    s.pivot = -1.0;
    double sink = 0.0;
    double independent = rhs_burst_ns(&s, calls, 0, &sink);
    double chained = rhs_burst_ns(&s, calls, 1, &sink);
    printf("%s rhs: %.2f ns per call (fastest burst of 1000 calls, %ld calls; checksum %.6g); "
           "%.2f ns per call chained as a stage chain chains them\n",
           mech ? "mechanistic" : "bare", independent, calls, sink, chained);
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "rhs") == 0) {
        time_rhs(strcmp(argv[2], "mechanistic") == 0, argc > 3 ? atol(argv[3]) : 2000000L);
        return 0;
    }
    if (argc < 4) {
        fprintf(stderr, "usage: %s bare|mechanistic REPEATS RTOL... | rhs bare|mechanistic [CALLS]\n",
                argv[0]);
        return 2;
    }
    int mech = strcmp(argv[1], "mechanistic") == 0;
    if (!mech && strcmp(argv[1], "bare") != 0) {
        fprintf(stderr, "unknown scene %s\n", argv[1]);
        return 2;
    }
    int repeats = atoi(argv[2]);
    if (repeats < 1)
        repeats = 1;
    printf("# rtol rhs_calls steps rejected events peak_rotation_ratio fastest_us median_us\n");
    for (int a = 3; a < argc; a++) {
        double rtol = atof(argv[a]);
        double *times = malloc(sizeof(double) * repeats);
        Scene s;
        for (int r = 0; r < repeats; r++) {
            setup(&s, mech, rtol);
            double t0 = now();
            run(&s);
            times[r] = now() - t0;
        }
        qsort(times, repeats, sizeof(double), cmp);
        printf("%g %ld %ld %ld %ld %.17g %.3f %.3f\n", rtol, s.rhs_calls, s.steps, s.rejected,
               s.events, s.peak / s.alpha, times[0] * 1e6, times[repeats / 2] * 1e6);
        free(times);
    }
    return 0;
}
