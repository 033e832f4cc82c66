/*
 * codegen_analysis.c -- Table 1 steps 8-10 in one call, by two routes, for any mechanism
 * described by a codegen_model (codegen_model.h). Hand-written (not generated).
 *
 * The polynomial route: every real root of the polynomial in tan(theta/2), each classified by
 * the branch of the square roots on which G vanishes there (the mechanism as declared, another
 * assembly mode, or a negative length), equilibria polished by Newton's method on G and
 * certified by interval enclosures around them, and the vibration at each root.
 * The isolation route: every zero of G itself on each assembly mode, proven by interval
 * enclosures of G and G' (codegen_interval.c), and the vibration at each.
 */
#include "codegen_model.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "codegen_runtime.h"

#define NEWTON_STEPS 8
/* How far Newton may move a root the branches call genuine [rad]: the polynomial's roots are
 * far more accurate than this, and the closest distinct roots (Table 2's pairs) farther. */
#define POLISH_RADIUS CODEGEN_R(1e-3)
/* Roots of different kinds this close are one (a root of two branches at once, kept as the
 * equilibrium) in double; in float MULTIPLE_ROOT_SPREAD is ~3e-3 rad, and only roots of one
 * kind merge. */
#ifdef CODEGEN_FLOAT
#define MERGE_ACROSS_KINDS 0
#else
#define MERGE_ACROSS_KINDS 1
#endif
/* |G| within this many rounding units of the size of its terms is zero to working precision */
#define GENUINE_RESIDUAL (CODEGEN_R(32.0) * CODEGEN_EPSILON)
/* Angles this close to -pi [rad] are pi (see wrap): ~1e-10 rad in double, invisible in any
 * table, and a few ulps of pi in float. */
#define PI_SNAP (CODEGEN_SQRT_EPSILON / 128)
/* A root the branches call genuine whose |G| stays above this relative size after Newton is
 * the jump of G across r = 0, not an equilibrium (a regular root polishes to ~eps). */
#define SINGULAR_RESIDUAL CODEGEN_SQRT_EPSILON
/* Roots closer than this [rad] are one multiple root that rounding split in two: the root
 * finder itself treats a spread of ~sqrt(8 eps) as a multiple root (codegen_roots.c). */
#define MULTIPLE_ROOT_SPREAD (8 * CODEGEN_SQRT_EPSILON)
/* The first half-width [rad, relative to max(|theta|, 1)] tried around a root of another branch,
 * grown fourfold up to BRANCH_RADIUS [rad], and at most the steps that then reach adjacent
 * doubles (bisection would need ~60; the Illinois steps typically take ~10). Squaring out
 * nested roots can cost the polynomial's roots many digits (a slider-crank's other-mode root
 * comes 5e-4 rad off); the branch value itself is accurate. */
#define BRACKET_START (512 * CODEGEN_EPSILON)
#define BRANCH_RADIUS CODEGEN_R(1e-2)
#define BRACKET_STEPS 64
/* Where the circle of a periodic coordinate may be cut for isolation: its far end, or up to
 * SEAM_TRIES steps of SEAM_STEP [rad] before it, the first where G's sign is decided. */
#define SEAM_STEP CODEGEN_R(0.0390625)
#define SEAM_TRIES 16
/* Half-width [rad, relative to max(|cut|, 1)] of the zero-free interval the cut must lie in:
 * far beyond the rounding of 2 pi, so the range may overlap itself by that much. */
#define SEAM_MARGIN (4096 * CODEGEN_EPSILON)

/* Each route keeps its own frame (the isolation's stack does not hold the polynomial route's
 * locals): gcc would otherwise inline both into codegen_analysis_run. */
#if defined(__GNUC__)
#define ROUTE __attribute__((noinline))
#else
#define ROUTE
#endif

typedef codegen_analysis_view result_view;
typedef codegen_analysis_call call;

static void *field(void *base, size_t offset)
{
    return (char *)base + offset;
}

static result_view results_in(const codegen_model *model, void *base)
{
    const codegen_analysis_layout *at = &model->analysis;
    result_view r;
    r.base = base;
    r.sigma = model->sigma != NULL ? (codegen_real *)field(base, at->sigma) : NULL;
    r.n_roots = (int *)field(base, at->n_roots);
    r.roots = (codegen_equilibrium *)field(base, at->roots);
    r.n_singular = (int *)field(base, at->n_singular);
    r.singular_theta = (codegen_real *)field(base, at->singular_theta);
    r.n_unassembled = (int *)field(base, at->n_unassembled);
    r.unassembled_theta = (codegen_real *)field(base, at->unassembled_theta);
    r.n_uncertain = (int *)field(base, at->n_uncertain);
    r.uncertain = (codegen_uncertain *)field(base, at->uncertain);
    return r;
}

static void clear(const codegen_model *model, const result_view *r)
{
    memset(r->base, 0, model->analysis.size);
}

static int all_finite(const codegen_real *values, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        if (!isfinite(values[i])) {
            return 0;
        }
    }
    return 1;
}

static int finite_or(const codegen_real *values, int count, int failure)
{
    return all_finite(values, count) ? CODEGEN_OK : failure;
}

static void state_at(const call *c, codegen_real theta, codegen_real *at)
{
    c->model->equilibrium_state(c->enclosure.params, theta, at);
}

/* G and the size of its terms, as NAME_equilibrium_residual returns them. */
static int residual_of(const codegen_model *model, const codegen_real *at)
{
    return finite_or(at + model->state.residual, 2, model->residual_failure);
}

/* M, B, K, as NAME_linearisation returns them. */
static int linearisation_of(const codegen_model *model, const codegen_real *at)
{
    return finite_or(at + model->state.m, 3, model->linearisation_failure);
}

/* The size against which G(theta_E) counts as zero: the sum of the magnitudes of its
 * contributions (springs, gravity, loads), plus the change of G over the rounding of theta_E
 * itself, |K| max(|theta|, 1). */
static int residual_scale(const codegen_model *model, const codegen_real *at, codegen_real theta,
                          codegen_real k, codegen_real *scale)
{
    const int status = residual_of(model, at);
    if (status == CODEGEN_OK) {
        *scale = at[model->state.scale] + codegen_fabs(k) * codegen_fmax(codegen_fabs(theta), (codegen_real)1);
    }
    return status;
}

/* eigenvalues where (B/2M)^2 - K/M overflows: with s = max(|h|, sqrt(|K|/M)), h = B/2M, the
 * discriminant is s^2 ((h/s)^2 - (K/M)/s^2) and that factor is at most 2, so the roots are
 * finite wherever they are representable (an infinite s or root: the caller reports it). */
static void eigenvalues_scaled(codegen_real m, codegen_real half_b, codegen_real k, codegen_real re[2],
                               codegen_real im[2])
{
    const codegen_real root_k = codegen_sqrt(codegen_fabs(k)) / codegen_sqrt(m);
    const codegen_real s = codegen_fmax(codegen_fabs(half_b), root_k);
    const codegen_real h_s = half_b / s, k_s = codegen_copysign(root_k / s, k) * (root_k / s);
    const codegen_real disc = h_s * h_s - k_s;
    if (disc < 0) {
        re[0] = re[1] = -half_b;
        im[0] = s * codegen_sqrt(-disc);
        im[1] = -im[0];
    } else {
        const codegen_real q = -(half_b + codegen_copysign(s * codegen_sqrt(disc), half_b));
        re[0] = q;
        re[1] = q != 0 ? codegen_copysign(root_k, k) * (root_k / q) : 0; /* (K/M) / q */
        im[0] = im[1] = 0;
    }
}

/* Roots of M s^2 + B s + K = 0, without cancellation; M > 0. Divided by M first: B^2 and
 * M K can overflow where B/M and K/M do not; where the discriminant still does, scaled. */
static void eigenvalues(codegen_real m, codegen_real b, codegen_real k, codegen_real re[2], codegen_real im[2])
{
    const codegen_real half_b = CODEGEN_R(0.5) * (b / m), k_m = k / m;
    const codegen_real disc = half_b * half_b - k_m;
    if (!isfinite(disc)) {
        eigenvalues_scaled(m, half_b, k, re, im);
    } else if (disc < 0) {
        re[0] = re[1] = -half_b;
        im[0] = codegen_sqrt(-disc);
        im[1] = -im[0];
    } else {
        const codegen_real q = -(half_b + codegen_copysign(codegen_sqrt(disc), half_b));
        re[0] = q;
        re[1] = q != 0 ? k_m / q : 0;
        im[0] = im[1] = 0;
    }
}

/* omega_n = sqrt(K/M) and zeta = B / (2 M omega_n) as complex numbers (54)-(55). */
static void frequency(codegen_real m, codegen_real b, codegen_real k, codegen_equilibrium *e)
{
    codegen_real w = codegen_sqrt(codegen_fabs(k) / m);
    if (isinf(w)) { /* |K|/M overflowed, its square root may not */
        w = codegen_sqrt(codegen_fabs(k)) / codegen_sqrt(m);
    }
    e->omega_n[0] = k >= 0 ? w : 0;
    e->omega_n[1] = k >= 0 ? 0 : w;
    e->zeta[0] = e->zeta[1] = 0;
    if (w == 0) {
        e->zeta[0] = b > 0 ? CODEGEN_HUGE : 0;
    } else if (k >= 0) {
        e->zeta[0] = b / (CODEGEN_R(2.0) * m * w);
    } else {
        e->zeta[1] = -b / (CODEGEN_R(2.0) * m * w); /* 1/i = -i */
    }
}

static void classify_motion(codegen_real b, codegen_real k, codegen_equilibrium *e)
{
    if (k < 0) {
        e->stability = CODEGEN_UNSTABLE;
    } else if (k > 0 && b > 0) {
        e->stability = CODEGEN_STABLE;
    } else {
        e->stability = CODEGEN_MARGINAL;
    }
    if (k <= 0) {
        e->damping = CODEGEN_NOT_OSCILLATORY;
    } else if (b == 0) {
        e->damping = CODEGEN_UNDAMPED;
    } else if (codegen_fabs(e->zeta[0] - 1) <= CODEGEN_R(8.0) * CODEGEN_EPSILON) {
        e->damping = CODEGEN_CRITICALLY_DAMPED;
    } else {
        e->damping = e->zeta[0] < 1 ? CODEGEN_UNDERDAMPED : CODEGEN_OVERDAMPED;
    }
}

/* Whether omega_n, zeta and the eigenvalues are all representable: zeta alone may be +inf,
 * on purpose, where omega_n = 0 and B > 0 (K = 0); any other infinity or NaN overflowed. */
static int vibration_finite(const codegen_equilibrium *e)
{
    const int zeta_infinite_on_purpose = e->omega_n[0] == 0 && e->omega_n[1] == 0
                                         && e->zeta[0] > 0 && e->zeta[1] == 0;
    return all_finite(e->omega_n, 2) && all_finite(e->eigen_re, 2) && all_finite(e->eigen_im, 2)
           && (all_finite(e->zeta, 2) || zeta_infinite_on_purpose);
}

/* The vibration about an equilibrium from its M, B, K. Where M = 0 (no inertia at this angle:
 * statics need none) omega_n, zeta and the eigenvalues are undefined (NaN); K and B alone
 * still say whether a perturbation grows. */
static int vibrate(codegen_equilibrium *e)
{
    if (!(e->M > 0)) {
        e->omega_n[0] = e->omega_n[1] = e->zeta[0] = e->zeta[1] = CODEGEN_NAN;
        e->eigen_re[0] = e->eigen_re[1] = e->eigen_im[0] = e->eigen_im[1] = CODEGEN_NAN;
        e->stability = e->K < 0 ? CODEGEN_UNSTABLE
                     : e->K > 0 && e->B > 0 ? CODEGEN_STABLE : CODEGEN_MARGINAL;
        e->damping = CODEGEN_NOT_OSCILLATORY;
        return CODEGEN_OK;
    }
    frequency(e->M, e->B, e->K, e);
    eigenvalues(e->M, e->B, e->K, e->eigen_re, e->eigen_im);
    if (!vibration_finite(e)) {
        return CODEGEN_ERR_OVERFLOW;
    }
    classify_motion(e->B, e->K, e);
    return CODEGEN_OK;
}

/* G on one branch at theta; 0 if it cannot be evaluated there. The branches' own kernel: the
 * search along one branch needs nothing else. */
static int branch_value(const call *c, codegen_real theta, unsigned branch, codegen_real *value)
{
    codegen_real *g = c->g;
    c->model->equilibrium_branches(c->enclosure.params, theta, g);
    if (!isfinite(g[branch])) {   /* (another branch may not exist here: not read) */
        return 0;
    }
    *value = g[branch];
    return 1;
}

/* M, B, K of an assembly mode at theta, G on that mode and the size of G's terms, into e;
 * at: the state at theta. */
static int linearise_at(const call *c, unsigned mode, codegen_real theta, const codegen_real *at,
                        codegen_equilibrium *e)
{
    const codegen_model *model = c->model;
    const codegen_state_layout *s = &model->state;
    int status;
    if (mode != 0u) {
        codegen_real *modes = c->modes;
        const codegen_real branch = at[s->branch_residuals + (int)model->branch_of_mode[mode]];
        model->mode_linearisation(c->enclosure.params, theta, modes);
        e->M = modes[model->mode_m + (int)mode];
        e->B = modes[model->mode_b + (int)mode];
        e->K = modes[model->mode_k + (int)mode];
        /* this mode's values only: in a chain of dyads another mode may not exist here */
        status = isfinite(e->M) && isfinite(e->B) && isfinite(e->K)
                 ? CODEGEN_OK : model->mode_linearisation_failure;
        if (status != CODEGEN_OK) {
            return status;
        }
        if (!isfinite(branch)) {
            return CODEGEN_ERR_SINGULAR_STATE;
        }
        e->residual = branch;
    } else {
        status = linearisation_of(model, at);
        if (status == CODEGEN_OK) {
            status = residual_of(model, at);
        }
        e->M = at[s->m];
        e->B = at[s->b];
        e->K = at[s->k];
        e->residual = at[s->residual];
    }
    if (status == CODEGEN_OK) {
        status = residual_scale(model, at, theta, e->K, &e->residual_scale);
        if (status != CODEGEN_OK && mode != 0u) {
            /* the declared mode has no state here (a chain's later dyad cannot be assembled
             * on it): the scale from this mode's own G and K */
            e->residual_scale = codegen_fabs(e->residual)
                                + codegen_fabs(e->K) * codegen_fmax(codegen_fabs(theta), (codegen_real)1);
            status = CODEGEN_OK;
        }
    }
    e->theta = theta;
    e->mode = mode; /* as found; assign_modes names it as the model declares its modes */
    return status;
}

static int check_state(const codegen_model *model, const codegen_real *at, int *assembled);

/* linearise_at at theta. M, B or K not finite where no square root is near zero is no
 * singular state but an overflow (K ~ k L^2 beyond the largest real). */
static int linearise(const call *c, unsigned mode, codegen_real theta, codegen_equilibrium *e)
{
    int status, assembled;
    state_at(c, theta, c->at_line);
    status = linearise_at(c, mode, theta, c->at_line, e);
    if (status == CODEGEN_ERR_SINGULAR_STATE && mode == 0u
        && check_state(c->model, c->at_line, &assembled) == CODEGEN_OK) {
        return CODEGEN_ERR_OVERFLOW;
    }
    return status;
}

/* Sort roots by theta (insertion sort: the lists are short and nearly sorted). */
static void sort_roots(codegen_equilibrium *roots, int count)
{
    int i, j;
    for (i = 1; i < count; ++i) {
        for (j = i; j > 0 && roots[j - 1].theta > roots[j].theta; --j) {
            const codegen_equilibrium swap = roots[j];
            roots[j] = roots[j - 1];
            roots[j - 1] = swap;
        }
    }
}

/* ==== The polynomial route ==== */

/* Newton's method on G(theta) = 0, whose derivative is K_EQ. A step is kept only while it
 * shrinks |G| and stays within radius of the start, so polishing cannot move a root onto a
 * neighbour farther away than that. A root already zero to working precision is left where it
 * is (theta = pi stays pi). at: the state at theta on entry, at the result on return. */
static codegen_real polish(const call *c, codegen_real theta, codegen_real radius, codegen_real *at)
{
    const codegen_model *model = c->model;
    const codegen_state_layout *s = &model->state;
    const codegen_real start = theta;
    codegen_real *next_at = c->at_next;
    int i;
    if (residual_of(model, at) != CODEGEN_OK) {
        return theta;
    }
    for (i = 0; i < NEWTON_STEPS && at[s->residual] != 0; ++i) {
        codegen_real next, scale;
        const codegen_real k = at[s->k];
        if (linearisation_of(model, at) != CODEGEN_OK || k == 0
            || residual_scale(model, at, theta, k, &scale) != CODEGEN_OK
            || codegen_fabs(at[s->residual]) <= GENUINE_RESIDUAL * scale) {
            break;
        }
        next = theta - at[s->residual] / k;
        if (!(codegen_fabs(next - start) <= radius)) {
            break;
        }
        state_at(c, next, next_at);
        if (residual_of(model, next_at) != CODEGEN_OK
            || !(codegen_fabs(next_at[s->residual]) < codegen_fabs(at[s->residual]))) {
            break;
        }
        theta = next;
        memcpy(at, next_at, (size_t)s->size * sizeof *at);
    }
    return theta;
}

/* Wrap into (-pi, pi]. An angle within PI_SNAP of -pi is the root at tau = infinity seen from
 * the negative side (a leading coefficient that is a rounding residue puts it ~1e-13 off):
 * it is reported as pi, where (-pi, pi] puts that root. */
static codegen_real wrap(codegen_real theta)
{
    const codegen_real pi = CODEGEN_R(3.14159265358979323846);
    if (theta > pi) {
        theta -= CODEGEN_R(2.0) * pi;
    } else if (theta <= -pi) {
        theta += CODEGEN_R(2.0) * pi;
    }
    return theta <= -pi + PI_SNAP ? pi : theta;
}

/* How far apart two angles are on the circle (pi - 1e-9 and -pi + 1e-9 are 2e-9 apart). */
static codegen_real angle_between(codegen_real a, codegen_real b)
{
    return codegen_fabs(wrap(a - b));
}

/* Where the square roots stand at theta: CODEGEN_ERR_SINGULAR_STATE if one of them is zero to
 * working precision (relative to the size of its radicand's terms: a limit position, or a
 * length through zero, where G is undefined); *assembled = 0 if an assembly radicand is below
 * zero (the mechanism cannot be put together at theta). */
static int check_state(const codegen_model *model, const codegen_real *at, int *assembled)
{
    const codegen_real *values = at + model->state.radicands, *scales = at + model->state.radicand_scales;
    const codegen_real tolerance = CODEGEN_R(64.0) * CODEGEN_EPSILON * CODEGEN_R(64.0) * CODEGEN_EPSILON;
    int i, status;
    *assembled = 1;
    if (model->n_roots == 0) {
        return CODEGEN_OK;
    }
    status = finite_or(values, 2 * model->n_roots, model->radicands_failure);
    if (status != CODEGEN_OK) {
        return status;
    }
    for (i = 0; i < model->n_roots; ++i) {
        if (codegen_fabs(values[i]) <= tolerance * scales[i]) {
            return CODEGEN_ERR_SINGULAR_STATE;
        }
        if (values[i] < 0) {
            *assembled = 0;
        }
    }
    return CODEGEN_OK;
}

/* The branch whose value in g is nearest zero (the first of equals). */
static unsigned nearest_branch(const codegen_real *g, int n_branches)
{
    unsigned j, best = 0u;
    for (j = 1u; j < (unsigned)n_branches; ++j) {
        best = codegen_fabs(g[j]) < codegen_fabs(g[best]) ? j : best;
    }
    return best;
}

/* Which branch zeroes G at theta: known (< n_branches: the root was found on it), else the one
 * where |G| is smallest (a comparison of values of the same quantity, free of any absolute
 * threshold). */
static int branch_kind(const codegen_model *model, const codegen_real *at, unsigned known,
                       codegen_root_kind *kind, unsigned *branch)
{
    const codegen_real *g = at + model->state.branch_residuals;
    unsigned best;
    int status;
    if (model->equilibrium_branches == NULL) {
        *branch = 0u;
        *kind = CODEGEN_EQUILIBRIUM;
        return CODEGEN_OK;
    }
    status = finite_or(g, model->n_branches, model->branches_failure);
    if (status != CODEGEN_OK) {
        return status;
    }
    best = known < (unsigned)model->n_branches ? known : nearest_branch(g, model->n_branches);
    *branch = best;
    *kind = best == 0u ? CODEGEN_EQUILIBRIUM
          : (best & model->length_branch_bits) != 0u ? CODEGEN_EXTRANEOUS : CODEGEN_OTHER_ASSEMBLY;
    return CODEGEN_OK;
}

/* The zero of a branch inside [lo, hi], where it takes the values g_lo and g_hi of opposite
 * signs: the Illinois method (regula falsi that halves a stale end's weight: superlinear, and
 * safe inside the bracket) to adjacent doubles, or BRACKET_STEPS steps. */
static codegen_real solve_on_branch(const call *c, unsigned branch, codegen_real lo,
                                    codegen_real hi, codegen_real g_lo, codegen_real g_hi)
{
    codegen_real g;
    int i, side = 0;
    for (i = 0; i < BRACKET_STEPS; ++i) {
        codegen_real mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        if (!(mid > lo && mid < hi)) {
            mid = lo + CODEGEN_R(0.5) * (hi - lo);
        }
        if (!(mid > lo && mid < hi) || !branch_value(c, mid, branch, &g)) {
            break;
        }
        if (g == 0) {
            return mid;
        }
        if ((g < 0) == (g_lo < 0)) {
            lo = mid;
            g_lo = g;
            g_hi *= side < 0 ? CODEGEN_R(0.5) : 1;
            side = -1;
        } else {
            hi = mid;
            g_hi = g;
            g_lo *= side > 0 ? CODEGEN_R(0.5) : 1;
            side = 1;
        }
    }
    return codegen_fabs(g_lo) < codegen_fabs(g_hi) ? lo : hi;
}

/* The zero of G on its own branch nearest theta (a root of another assembly mode, or of a
 * negative length): the polynomial places it only as well as its conditioning allows, and
 * no derivative of the other branches is emitted. A bracket grows outwards from theta until
 * the branch changes sign (within radius), then solve_on_branch. */
static codegen_real refine_on_branch(const call *c, codegen_real theta, unsigned branch,
                                     codegen_real radius)
{
    codegen_real g0, g, step;
    if (!branch_value(c, theta, branch, &g0) || g0 == 0) {
        return theta;
    }
    for (step = BRACKET_START * codegen_fmax(codegen_fabs(theta), (codegen_real)1); step <= radius; step *= CODEGEN_R(4.0)) {
        if (branch_value(c, theta - step, branch, &g) && (g < 0) != (g0 < 0)) {
            return solve_on_branch(c, branch, theta - step, theta, g, g0);
        }
        if (branch_value(c, theta + step, branch, &g) && (g < 0) != (g0 < 0)) {
            return solve_on_branch(c, branch, theta, theta + step, g0, g);
        }
    }
    return theta;
}

/* One root of the polynomial where the spans cannot be proven (the isolation lists the
 * equilibria; complete_by_isolation keeps the extraneous roots from here): classify by the
 * branch it zeroes (see branch_kind), polish, then linearise. Where branches vanish together,
 * G itself decides, relative to the size of its contributions. *assembled = 0 (and nothing
 * else written) where the mechanism cannot be assembled. */
static int study_root(const call *c, codegen_real theta, codegen_equilibrium *e, int *assembled)
{
    const codegen_model *model = c->model;
    int status, declared;
    unsigned branch;
    codegen_real *at = c->at_root, polished;
    theta = wrap(theta);
    state_at(c, theta, at);
    status = check_state(model, at, assembled);
    if (status != CODEGEN_OK || !*assembled) {
        return status;
    }
    status = branch_kind(model, at, (unsigned)model->n_branches, &e->kind, &branch);
    if (status != CODEGEN_OK) {
        return status;
    }
    declared = e->kind == CODEGEN_EQUILIBRIUM;
    e->genuine = declared;
    polished = polish(c, theta, declared ? POLISH_RADIUS : 0, at);
    status = linearise_at(c, 0u, polished, at, e);
    if (status != CODEGEN_OK) {
        return status;
    }
    if (e->genuine && !(codegen_fabs(e->residual) <= SINGULAR_RESIDUAL * e->residual_scale)) {
        /* The genuine branch r*G vanishes but Newton cannot bring G near zero: G jumps
         * here, which it does only where r = 0 (a root the finder placed ~1e-8 off it). */
        return CODEGEN_ERR_SINGULAR_STATE;
    }
    e->genuine = e->genuine || codegen_fabs(e->residual) <= GENUINE_RESIDUAL * e->residual_scale;
    if (e->genuine) {
        e->kind = CODEGEN_EQUILIBRIUM;
        e->theta = wrap(e->theta);
    } else { /* not G's: the root itself, on its own branch */
        if (model->equilibrium_branches != NULL) {
            theta = wrap(refine_on_branch(c, theta, branch, BRANCH_RADIUS));
        }
        const unsigned mode = model->mode_of_branch != NULL && e->kind == CODEGEN_OTHER_ASSEMBLY
                            ? model->mode_of_branch[branch] : 0u;
        status = linearise(c, mode, theta, e);
        if (status != CODEGEN_OK) {
            return status;
        }
    }
    e->certified = 0;
    e->theta_lo = e->theta_hi = e->theta;
    return vibrate(e);
}

/* Whether [alo, ahi] and [blo, bhi] overlap on the circle: as they are, or one of them 2 pi
 * away (a root near pi may be written near -pi), up to the rounding of 2 pi's addition. */
static int meet(codegen_real alo, codegen_real ahi, codegen_real blo, codegen_real bhi)
{
    const codegen_real two_pi = CODEGEN_R(6.28318530717958647692);
    const codegen_real slack = CODEGEN_R(16.0) * CODEGEN_EPSILON;
    int k;
    for (k = -1; k <= 1; ++k) {
        const codegen_real shift = (codegen_real)k * two_pi, tolerance = k != 0 ? slack : 0;
        if (alo <= bhi + shift + tolerance && blo + shift <= ahi + tolerance) {
            return 1;
        }
    }
    return 0;
}

/* Whether two roots are one: two proven ones whose intervals overlap, or others that rounding
 * split, closer than MULTIPLE_ROOT_SPREAD on the circle (and in float, of one kind). */
static int split_pair(const codegen_equilibrium *a, const codegen_equilibrium *b)
{
    if (a->certified && b->certified) {
        /* Each interval holds one zero, where G is monotone: overlapping, they hold the same
         * one (G stays monotone over both); apart, two. */
        return a->kind == b->kind && meet(a->theta_lo, a->theta_hi, b->theta_lo, b->theta_hi);
    }
    return angle_between(a->theta, b->theta) <= MULTIPLE_ROOT_SPREAD
        && (MERGE_ACROSS_KINDS || a->kind == b->kind);
}

/* Merge split pairs among neighbours (sorted input), the first and the last included: the
 * circle closes at pi. A merged root is genuine if either half is. Returns the new count. */
static int merge_split_roots(codegen_equilibrium *roots, int count)
{
    int i, kept = 0;
    for (i = 0; i < count; ++i) {
        if (kept > 0 && split_pair(&roots[i], &roots[kept - 1])) {
            if (roots[i].genuine && !roots[kept - 1].genuine) {
                roots[kept - 1] = roots[i];
            }
            continue;
        }
        roots[kept++] = roots[i];
    }
    if (kept > 1 && split_pair(&roots[0], &roots[kept - 1])) {
        if (roots[kept - 1].genuine || !roots[0].genuine) { /* the one nearer pi stays */
            memmove(roots, roots + 1, (size_t)(kept - 1) * sizeof *roots);
        }
        --kept;
    }
    return kept;
}

static int isolate_mode(const call *c, unsigned mode, codegen_real lo, codegen_real hi,
                        codegen_real below, int whole, void *workspace, const result_view *work);
static void sort_uncertain(codegen_uncertain *uncertain, int count);
static void drop_repeated(const result_view *r);
static codegen_uncertain *listed_as(const result_view *r, int count, const codegen_uncertain *u);
static void widen(codegen_uncertain *v, const codegen_uncertain *u);

/* What one mode's G has on a span. */
typedef enum span_outcome {
    SPAN_NO_ZERO = 0,  /* proven: no zero of G on this mode */
    SPAN_ONE_ZERO = 1, /* proven: exactly one */
    SPAN_UNDECIDED = 2 /* the enclosures cannot tell: the isolation searches it */
} span_outcome;

/* Whether G of one mode vanishes in [lo, hi], an interval that holds at most one root of the
 * polynomial, a simple one. Every zero of G on any mode is a root of the polynomial (the
 * product of G's numerators over every branch, elimination.py), so G has at most one zero
 * there, simple; where G is continuous on [lo, hi] (its divisions and square roots raise no
 * flag there: no pole, every square root defined) it has one exactly where it changes sign
 * between the ends. expecting: the branch nearest zero at the span's root is this mode's, so
 * G's enclosure over [lo, hi] would hold 0 anyway: only the flags are asked (the divisions
 * and square roots alone, a fraction of G's operations: the model's enclose_flags_alone);
 * otherwise G's enclosure first, which settles most spans that hold no zero of this mode at
 * once. *smooth = 0 where a pole or a square root's edge may lie inside (no interval around
 * it will do). */
static int sign_test(const call *c, unsigned mode, codegen_real lo, codegen_real hi, int expecting,
                     span_outcome *outcome, int *smooth)
{
    codegen_iv g, g_lo, g_hi;
    unsigned flags, flags_lo, flags_hi;
    int status = c->model->enclose(&c->enclosure, mode, codegen_iv_make(lo, hi),
                                   expecting ? NULL : &g, NULL, &flags);
    *outcome = SPAN_UNDECIDED;
    *smooth = 1;
    if (status != 0 || (flags & CODEGEN_IV_OUTSIDE) != 0u) { /* OUTSIDE: no state on [lo, hi] */
        *outcome = SPAN_NO_ZERO;
        return status;
    }
    if ((flags & (CODEGEN_IV_POLE | CODEGEN_IV_EDGE)) != 0u) {
        *smooth = 0;
        return CODEGEN_OK;
    }
    if (!expecting && !codegen_iv_has_zero(g)) {
        *outcome = SPAN_NO_ZERO;
        return CODEGEN_OK;
    }
    status = c->model->enclose(&c->enclosure, mode, codegen_iv_point(lo), &g_lo, NULL, &flags_lo);
    if (status == 0) {
        status = c->model->enclose(&c->enclosure, mode, codegen_iv_point(hi), &g_hi, NULL, &flags_hi);
    }
    if (status != 0 || (flags_lo | flags_hi) != 0u) {
        return status;
    }
    if ((g_lo.lo > 0 && g_hi.hi < 0) || (g_lo.hi < 0 && g_hi.lo > 0)) {
        *outcome = SPAN_ONE_ZERO;
    } else if ((g_lo.lo > 0 && g_hi.lo > 0) || (g_lo.hi < 0 && g_hi.hi < 0)) {
        *outcome = SPAN_NO_ZERO;
    }
    return CODEGEN_OK;
}

/* Each end of [lo, hi] moved out by SPAN_GROWTH times its width, within the free interval. */
#define SPAN_GROWTH CODEGEN_R(64.0)
static void grow_span(codegen_real *lo, codegen_real *hi, const codegen_root_span *s)
{
    const codegen_real grow = SPAN_GROWTH * (*hi - *lo);
    *lo = codegen_fmax(s->free_lo, *lo - grow);
    *hi = codegen_fmin(s->free_hi, *hi + grow);
}

/* Whether G of one mode vanishes in a simple span: sign_test on the span and, while G's signs
 * at the ends are within rounding of 0, on intervals grown about it within its free interval,
 * which holds no other root of the polynomial (the zero of G, if any, is the span's root all
 * the same: in [lo, hi]). The span grown once is tried first: the span is as narrow as the
 * polynomial's root is accurate, and on about half the spans that hold a zero, G's signs at
 * its own ends are within G's rounding of 0. Only if that cannot decide (it may take in a
 * pole or a square root's edge that the span does not hold) does the sequence run from the
 * span itself. */
static int span_zeros(const call *c, unsigned mode, const codegen_root_span *s, int expecting,
                      span_outcome *outcome)
{
    codegen_real lo = s->lo, hi = s->hi;
    int smooth, status;
    grow_span(&lo, &hi, s);
    status = sign_test(c, mode, lo, hi, expecting, outcome, &smooth);
    if (status != CODEGEN_OK || *outcome != SPAN_UNDECIDED) {
        return status;
    }
    lo = s->lo;
    hi = s->hi;
    for (;;) {
        status = sign_test(c, mode, lo, hi, expecting, outcome, &smooth);
        if (status != CODEGEN_OK || *outcome != SPAN_UNDECIDED || !smooth
            || (lo <= s->free_lo && hi >= s->free_hi)) {
            return status;
        }
        grow_span(&lo, &hi, s);
    }
}

static int add_uncertain(const codegen_model *model, const result_view *work, codegen_real lo,
                         codegen_real hi, codegen_uncertainty kind, unsigned mode, int sign_change);
static int already_proven(const result_view *work, codegen_root_kind kind, codegen_iv at);
static int extraneous_listed(const codegen_model *model, const result_view *work, codegen_real theta);

/* Every zero of G on one mode within a span's reach (which holds the span, and may hold zeros
 * of the spans beside it, listed once: see already_proven and merge_split_roots), by the
 * certified isolation, into work: a reach that holds theta = pi is searched from below -pi,
 * and its zeros are reported in (-pi, pi]. */
static int isolate_span(const call *c, unsigned mode, const codegen_root_span *s, void *workspace,
                        const result_view *work)
{
    const codegen_real pi = CODEGEN_R(3.14159265358979323846), two_pi = CODEGEN_R(2.0) * pi;
    const codegen_real shift = s->reach_hi > pi ? two_pi : 0;
    return isolate_mode(c, mode, s->reach_lo - shift, s->reach_hi - shift, -pi, 0, workspace, work);
}

/* [lo, hi] turned by turns (-1, 0 or 1) times 2 pi, outward-rounded: 2 pi is enclosed, and so
 * is each sum. A proven interval moved by the working precision's 2 pi instead lands up to
 * 1.7e-7 rad off in float, past the zero it was proven to hold. */
static codegen_iv turned(codegen_real lo, codegen_real hi, int turns)
{
    const codegen_iv two_pi = codegen_iv_make(CODEGEN_BOUND(0x1.921fb54442d18p+2, 0x1.921fb4p+2),
                                              CODEGEN_BOUND(0x1.921fb54442d19p+2, 0x1.921fb6p+2));
    const codegen_iv interval = codegen_iv_make(lo, hi);
    return turns > 0 ? codegen_iv_add(interval, two_pi)
         : turns < 0 ? codegen_iv_sub(interval, two_pi) : interval;
}

/* A proven zero of the declared mode moved to theta = 0 or pi where its interval holds that
 * angle and G is zero there to working precision, as polish leaves a root (symmetric
 * mechanisms have their equilibria exactly there, and a table shows pi, not its
 * neighbour), and linearised there. */
static int exact_angle(const call *c, codegen_equilibrium *e)
{
    const codegen_real pi = CODEGEN_R(3.14159265358979323846);
    const codegen_model *model = c->model;
    codegen_real *at = c->at_next, scale, candidate;
    codegen_equilibrium moved;
    if (e->theta <= -pi + PI_SNAP) { /* pi, where (-pi, pi] puts it (see wrap) */
        const codegen_iv proven = turned(e->theta_lo, e->theta_hi, 1);
        e->theta += CODEGEN_R(2.0) * pi;
        e->theta_lo = proven.lo;
        e->theta_hi = proven.hi;
    }
    candidate = e->theta_lo <= 0 && e->theta_hi >= 0 ? 0
              : e->theta_lo <= pi && e->theta_hi >= pi ? pi : e->theta;
    if (candidate == e->theta || e->kind != CODEGEN_EQUILIBRIUM || !e->certified) {
        return CODEGEN_OK;
    }
    moved = *e;
    state_at(c, candidate, at);
    if (linearisation_of(model, at) != CODEGEN_OK
        || residual_scale(model, at, candidate, at[model->state.k], &scale) != CODEGEN_OK
        || !(codegen_fabs(at[model->state.residual]) <= GENUINE_RESIDUAL * scale)
        || linearise_at(c, 0u, candidate, at, &moved) != CODEGEN_OK || vibrate(&moved) != CODEGEN_OK) {
        return CODEGEN_OK; /* stays where it was proven and linearised */
    }
    *e = moved;
    return CODEGEN_OK;
}

/* The proven zero of G on a mode in a simple span, into work: polished (the declared mode by
 * Newton's method, another on its own branch) without leaving the span, and linearised. */
static int add_span_zero(const call *c, unsigned mode, const codegen_root_span *s,
                         const result_view *work)
{
    const codegen_model *model = c->model;
    const codegen_real pi = CODEGEN_R(3.14159265358979323846), two_pi = CODEGEN_R(2.0) * pi;
    const codegen_real width = s->hi - s->lo;
    codegen_equilibrium *e = &work->roots[*work->n_roots];
    const codegen_real shift_span = s->hi > pi ? two_pi : 0;
    codegen_real theta;
    int status;
    if (already_proven(work, mode == 0u ? CODEGEN_EQUILIBRIUM : CODEGEN_OTHER_ASSEMBLY,
                       codegen_iv_make(s->lo - shift_span, s->hi - shift_span))) {
        return CODEGEN_OK; /* proven by the isolation within a neighbour's reach */
    }
    if (*work->n_roots == model->max_roots) {
        return CODEGEN_ERR_CAPACITY;
    }
    if (mode == 0u) {
        state_at(c, s->theta, c->at_root);
        theta = polish(c, s->theta, width, c->at_root);
    } else {
        theta = refine_on_branch(c, s->theta, model->branch_of_mode[mode], width);
    }
    if (!(theta >= s->lo && theta <= s->hi)) {
        theta = s->theta;
    }
    /* reported in (-pi, pi], with the span moved alike */
    const codegen_real shift = theta > pi ? two_pi : 0;
    status = linearise(c, mode, theta - shift, e);
    if (status == CODEGEN_ERR_SINGULAR_STATE) { /* proven, but K or M undefined there */
        if (*work->n_singular == model->max_roots) {
            return CODEGEN_ERR_CAPACITY;
        }
        work->singular_theta[(*work->n_singular)++] = theta - shift;
        return CODEGEN_OK;
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    e->kind = mode == 0u ? CODEGEN_EQUILIBRIUM : CODEGEN_OTHER_ASSEMBLY;
    e->genuine = mode == 0u;
    e->certified = 1;
    {
        const codegen_iv proven = turned(s->lo, s->hi, shift != 0 ? -1 : 0);
        e->theta_lo = proven.lo;
        e->theta_hi = proven.hi;
    }
    status = vibrate(e);
    if (status == CODEGEN_OK) {
        ++*work->n_roots;
    }
    return status;
}

/* The root of the polynomial in a simple span that is no zero of G on any mode (every mode
 * proven free of zeros there): listed where the mechanism cannot be assembled, or as an
 * extraneous root (a negative length), found on its own branch within the span. */
static int add_span_extraneous(const call *c, const codegen_root_span *s, unsigned branch,
                               int assembled, const result_view *work)
{
    const codegen_model *model = c->model;
    codegen_equilibrium *e = &work->roots[*work->n_roots];
    codegen_real theta = s->theta;
    int status;
    if (!assembled) {
        if (*work->n_unassembled < model->max_roots) {
            work->unassembled_theta[(*work->n_unassembled)++] = wrap(theta);
        }
        return CODEGEN_OK;
    }
    if (extraneous_listed(model, work, wrap(theta))) {
        return CODEGEN_OK;
    }
    if (model->equilibrium_branches != NULL) {
        theta = refine_on_branch(c, theta, branch, s->hi - s->lo);
        theta = theta >= s->lo && theta <= s->hi ? theta : s->theta;
    }
    status = linearise(c, 0u, wrap(theta), e);
    if (status == CODEGEN_OK) {
        e->kind = CODEGEN_EXTRANEOUS;
        e->genuine = 0;
        e->certified = 0;
        e->theta_lo = e->theta_hi = e->theta;
        status = vibrate(e);
    }
    if (status == CODEGEN_OK) {
        ++*work->n_roots;
    } else if (status == CODEGEN_ERR_SINGULAR_STATE && *work->n_singular < model->max_roots) {
        work->singular_theta[(*work->n_singular)++] = wrap(theta);
    }
    return CODEGEN_OK; /* (an extraneous root whose vibration overflows is not listed) */
}

/* A simple span: the one root of the polynomial in it is a zero of G on the mode whose
 * branch is nearest zero there, tried first, or on another mode, or on none (span_zeros on
 * each until one has it: at most one can); a mode the enclosures cannot decide is searched by
 * the isolation, unless another mode is proven to have the zero. */
static int study_simple_span(const call *c, const codegen_root_span *s, void *workspace,
                             const result_view *work)
{
    const codegen_model *model = c->model;
    codegen_real *at = c->at_root;
    codegen_root_kind kind;
    unsigned branch, first, k, undecided = 0u;
    int assembled, status;
    state_at(c, s->theta, at);
    status = check_state(model, at, &assembled);
    if (status == CODEGEN_ERR_SINGULAR_STATE) { /* a limit position, a length through 0 */
        status = CODEGEN_OK;
        if (*work->n_singular < model->max_roots) {
            work->singular_theta[(*work->n_singular)++] = wrap(s->theta);
        }
        for (k = 0u; k < (unsigned)model->n_modes && status == CODEGEN_OK; ++k) {
            status = isolate_span(c, k, s, workspace, work);
        }
        return status;
    }
    if (status == CODEGEN_OK) {
        status = branch_kind(model, at, (unsigned)model->n_branches, &kind, &branch);
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    first = kind == CODEGEN_OTHER_ASSEMBLY ? model->mode_of_branch[branch] : 0u;
    for (k = 0u; k < (unsigned)model->n_modes; ++k) {
        const unsigned mode = k == 0u ? first : k <= first ? k - 1u : k;
        span_outcome outcome;
        status = span_zeros(c, mode, s,
                            k == 0u && kind != CODEGEN_EXTRANEOUS && model->enclose_flags_alone,
                            &outcome);
        if (status != CODEGEN_OK) {
            return status;
        }
        if (outcome == SPAN_ONE_ZERO) {
            return add_span_zero(c, mode, s, work);
        }
        undecided |= outcome == SPAN_UNDECIDED ? 1u << mode : 0u;
    }
    if (undecided == 0u) {
        return add_span_extraneous(c, s, branch, assembled, work);
    }
    for (k = 0u; k < (unsigned)model->n_modes && status == CODEGEN_OK; ++k) {
        if ((undecided >> k) & 1u) {
            status = isolate_span(c, k, s, workspace, work);
        }
    }
    return status;
}

/* Whether theta lies in a span that is not simple (on the circle: see meet). */
static int in_cluster(const codegen_root_span *spans, int n, codegen_real theta)
{
    int i;
    for (i = 0; i < n; ++i) {
        if (!spans[i].simple && meet(theta, theta, spans[i].lo, spans[i].hi)) {
            return 1;
        }
    }
    return 0;
}

/* Whether G of some mode may vanish at theta, or is not smooth there, as its enclosure at the
 * point says: a root of a cluster's span is listed as extraneous only where every mode's G is
 * certainly not 0 (where rounding cannot tell, it is no extraneous root but part of the
 * span's uncertain interval). */
static int may_be_equilibrium(const call *c, codegen_real theta)
{
    unsigned mode;
    for (mode = 0u; mode < (unsigned)c->model->n_modes; ++mode) {
        codegen_iv g;
        unsigned flags;
        if (c->model->enclose(&c->enclosure, mode, codegen_iv_point(theta), &g, NULL, &flags) != 0) {
            return 1;
        }
        if (!(flags & CODEGEN_IV_OUTSIDE)
            && ((flags & (CODEGEN_IV_POLE | CODEGEN_IV_EDGE)) != 0u || codegen_iv_has_zero(g))) {
            return 1;
        }
    }
    return 0;
}

/* Whether an extraneous root at theta would be merged with one listed (see split_pair), or
 * the result is full: extraneous roots are listed for what they say of the polynomial, and
 * never at the cost of a failure. */
static int extraneous_listed(const codegen_model *model, const result_view *work, codegen_real theta)
{
    int i;
    for (i = 0; i < *work->n_roots; ++i) {
        if ((MERGE_ACROSS_KINDS || work->roots[i].kind == CODEGEN_EXTRANEOUS)
            && angle_between(work->roots[i].theta, theta) <= MULTIPLE_ROOT_SPREAD) {
            return 1;
        }
    }
    return *work->n_roots == model->max_roots;
}

/* The roots of a negative length in a span that is not simple: each branch with a negative
 * length that changes sign across its free interval has one there (its partner root beside an
 * equilibrium, closer than the root finder resolves, is found so). Values in working
 * precision: an extraneous root is no equilibrium, and proves nothing. */
static int list_cluster_lengths(const call *c, const codegen_root_span *s, const result_view *work)
{
    const codegen_model *model = c->model;
    unsigned j;
    for (j = 1u; j < (unsigned)model->n_branches && model->equilibrium_branches != NULL; ++j) {
        codegen_real g_lo, g_hi, root;
        codegen_equilibrium *e = &work->roots[*work->n_roots];
        int status;
        if ((j & model->length_branch_bits) == 0u || !branch_value(c, s->free_lo, j, &g_lo)
            || !branch_value(c, s->free_hi, j, &g_hi) || (g_lo < 0) == (g_hi < 0)) {
            continue;
        }
        root = wrap(solve_on_branch(c, j, s->free_lo, s->free_hi, g_lo, g_hi));
        if (extraneous_listed(model, work, root) || may_be_equilibrium(c, root)) {
            continue;
        }
        status = linearise(c, 0u, root, e);
        if (status == CODEGEN_OK) {
            e->kind = CODEGEN_EXTRANEOUS;
            e->genuine = e->certified = 0;
            e->theta_lo = e->theta_hi = e->theta;
            status = vibrate(e);
        }
        if (status == CODEGEN_OK) {
            ++*work->n_roots;
        } /* else not listed: an extraneous root's vibration is no result to fail on */
    }
    return CODEGEN_OK;
}

/* The roots of the polynomial in spans that are not simple, as the root finder places them
 * and study_root classifies them, where they are no equilibrium: extraneous, where the
 * mechanism cannot be assembled, or singular (the equilibria there are the isolation's);
 * and the roots of a negative length there that the finder merged with a neighbour. The
 * finder reuses the spans' iteration, left in the workspace's roots (nothing else writes
 * there in between). */
static int list_cluster_roots(const call *c, void *workspace, const result_view *work,
                              const codegen_root_span *spans, int n)
{
    const codegen_model *model = c->model;
    codegen_real *theta = (codegen_real *)field(workspace, model->workspace.theta);
    int i, count, status;
    if ((int)codegen_poly_real_roots_after_spans(work->sigma, model->degree, theta, &count,
                                                 (codegen_real *)field(workspace, model->workspace.roots))
        != CODEGEN_OK) {
        count = 0; /* (every zero of G is accounted for already) */
    }
    for (i = 0, status = CODEGEN_OK; i < n && status == CODEGEN_OK; ++i) {
        if (!spans[i].simple) {
            status = list_cluster_lengths(c, &spans[i], work);
        }
    }
    for (i = 0; i < count && status == CODEGEN_OK; ++i) {
        int assembled;
        codegen_equilibrium *e = &work->roots[*work->n_roots];
        if (!in_cluster(spans, n, theta[i]) || *work->n_roots == model->max_roots) {
            continue;
        }
        status = study_root(c, theta[i], e, &assembled);
        if (status == CODEGEN_ERR_SINGULAR_STATE || (status == CODEGEN_OK && !assembled)) {
            int *listed = status == CODEGEN_OK ? work->n_unassembled : work->n_singular;
            codegen_real *at = status == CODEGEN_OK ? work->unassembled_theta : work->singular_theta;
            if (*listed < model->max_roots) {
                at[(*listed)++] = wrap(theta[i]);
            }
        } else if (status == CODEGEN_OK && e->kind == CODEGEN_EXTRANEOUS
                   && !extraneous_listed(model, work, e->theta) && !may_be_equilibrium(c, e->theta)) {
            ++*work->n_roots;
        }
        status = CODEGEN_OK; /* a root that cannot be studied is not listed: no equilibrium */
    }
    return status;
}

/* The polynomial route into *work: sigma with a bound on each coefficient's error, every
 * real root of every polynomial within those bounds enclosed in spans (codegen_roots.c), and
 * each span decided by enclosures of G (study_simple_span), or searched by the certified
 * isolation of G on every mode (a cluster, a complex pair near the axis). Every zero of G on
 * every mode is a root of the polynomial, so outside the spans there is none: every
 * equilibrium listed is proven and none is missed. *proven = 0 (and nothing meant by *work)
 * where the spans cannot be proven: then complete_by_isolation answers. */
ROUTE static int analyze_by_spans(const call *c, void *workspace, const result_view *work,
                                  int *proven)
{
    const codegen_model *model = c->model;
    const codegen_workspace_layout *ws = &model->workspace;
    codegen_real *bound = (codegen_real *)field(workspace, ws->sigma_bound);
    codegen_root_span *spans = (codegen_root_span *)field(workspace, ws->spans);
    int i, n, clusters, status;
    *proven = 0;
    clear(model, work);
    status = model->sigma(c->enclosure.params, work->sigma, bound, field(workspace, ws->sigma_values),
                          (codegen_real *)field(workspace, ws->sigma_errors));
    if (status == CODEGEN_OK) {
        status = finite_or(work->sigma, model->degree + 1, model->sigma_failure);
    }
    if (status != CODEGEN_OK
        || codegen_poly_root_spans(work->sigma, bound, model->degree, spans, &n,
                                   (codegen_real *)field(workspace, ws->roots)) != CODEGEN_ROOTS_OK) {
        return status;
    }
    *proven = 1;
    for (i = 0, clusters = 0; i < n && status == CODEGEN_OK; ++i) {
        unsigned mode;
        if (spans[i].simple) {
            status = study_simple_span(c, &spans[i], workspace, work);
            continue;
        }
        for (mode = 0u; mode < (unsigned)model->n_modes && status == CODEGEN_OK; ++mode) {
            status = isolate_span(c, mode, &spans[i], workspace, work);
        }
        ++clusters;
    }
    if (status == CODEGEN_OK && clusters > 0) {
        status = list_cluster_roots(c, workspace, work, spans, n);
    }
    for (i = 0; i < *work->n_roots && status == CODEGEN_OK; ++i) {
        status = exact_angle(c, &work->roots[i]);
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    sort_roots(work->roots, *work->n_roots);
    *work->n_roots = merge_split_roots(work->roots, *work->n_roots);
    sort_uncertain(work->uncertain, *work->n_uncertain);
    return CODEGEN_OK;
}

/* Whether G on the declared mode is within rounding of 0, and finite, wherever a few angles
 * spread over the range probe it: what a vanishing polynomial must be confirmed by. */
static int vanishing_everywhere(const call *c)
{
    const codegen_real centre = c->model->range_centre(c->enclosure.params);
    const codegen_real offsets[3] = {CODEGEN_R(0.7), CODEGEN_R(-1.9), CODEGEN_R(2.6)};
    int i;
    for (i = 0; i < 3; ++i) {
        codegen_iv g;
        unsigned flags;
        if (c->model->enclose(&c->enclosure, 0u, codegen_iv_point(centre + offsets[i]), &g, NULL,
                              &flags) != 0
            || (flags & CODEGEN_IV_OUTSIDE) != 0u || !isfinite(g.lo) || !isfinite(g.hi)
            || !codegen_iv_has_zero(g)) {
            return 0;
        }
    }
    return 1;
}

/* The polynomial's roots where the spans cannot be proven, into *work: each classified and
 * linearised (study_root), none proven; complete_by_isolation takes the equilibria from the
 * isolation of G and the rest from here. */
static int analyze_polynomial(const call *c, void *workspace, const result_view *work)
{
    const codegen_model *model = c->model;
    const codegen_workspace_layout *ws = &model->workspace;
    codegen_real *theta = (codegen_real *)field(workspace, ws->theta);
    int i, count = 0, status;
    clear(model, work);
    status = model->sigma(c->enclosure.params, work->sigma, NULL, field(workspace, ws->sigma_values),
                          NULL);
    if (status == CODEGEN_OK) {
        status = finite_or(work->sigma, model->degree + 1, model->sigma_failure);
    }
    if (status == CODEGEN_OK) {
        /* The runtime's codes 0..3 are the library's generic codes; its only other code (a
         * degree below 1) cannot occur. */
        status = (int)codegen_poly_real_roots_work(work->sigma, model->degree, theta, &count,
                                                   (codegen_real *)field(workspace, ws->roots));
        if (status == CODEGEN_ERR_ZERO_POLYNOMIAL) {
            /* the polynomial vanishes because G does (every angle), or its coefficients
             * underflowed (float, a linkage that closes nowhere): then no roots to list, and
             * the isolation of G decides */
            status = vanishing_everywhere(c) ? CODEGEN_ERR_EVERY_ANGLE : CODEGEN_OK;
            count = 0;
        }
    }
    for (i = 0; i < count && status == CODEGEN_OK; ++i) {
        int assembled;
        codegen_equilibrium *e = &work->roots[*work->n_roots];
        status = study_root(c, theta[i], e, &assembled);
        if (status == CODEGEN_ERR_SINGULAR_STATE) {
            work->singular_theta[(*work->n_singular)++] = theta[i];
            status = CODEGEN_OK;
        } else if (status == CODEGEN_OK && !assembled) {
            work->unassembled_theta[(*work->n_unassembled)++] = theta[i];
        } else if (status == CODEGEN_OK) {
            ++*work->n_roots;
        }
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    sort_roots(work->roots, *work->n_roots);
    *work->n_roots = merge_split_roots(work->roots, *work->n_roots);
    return CODEGEN_OK;
}
/* ==== The isolation route ==== */

/* The interval to isolate on: the coordinate's range, (centre - pi, centre + pi]. A periodic
 * coordinate's circle is cut inside an interval where every mode's G keeps away from 0, so
 * that no zero sits on the seam, to be found at both ends or at neither. Zeros found at or
 * below *below are moved up by 2 pi into the range (-HUGE_VAL: the range is not periodic). */
static int isolation_range(const call *c, codegen_real *lo, codegen_real *hi, codegen_real *below)
{
    const codegen_model *model = c->model;
    const codegen_real pi = CODEGEN_R(3.14159265358979323846), centre = model->range_centre(c->enclosure.params);
    if (model->periodic) {
        int k;
        *below = centre - pi;
        for (k = 0; k < SEAM_TRIES; ++k) {
            const codegen_real cut = centre + pi - (codegen_real)k * SEAM_STEP;
            const codegen_real margin = SEAM_MARGIN * codegen_fmax(codegen_fabs(cut), (codegen_real)1);
            int decided = 1;
            unsigned mode;
            for (mode = 0u; mode < (unsigned)model->n_modes && decided; ++mode) {
                codegen_iv g, dg;
                unsigned flags;
                const int status = model->enclose(&c->enclosure, mode,
                                                  codegen_iv_make(cut - margin, cut + margin),
                                                  &g, &dg, &flags);
                if (status != 0) {
                    return status;
                }
                decided = (flags & CODEGEN_IV_OUTSIDE) != 0u
                       || ((flags & (CODEGEN_IV_POLE | CODEGEN_IV_EDGE)) == 0u && !codegen_iv_has_zero(g));
            }
            if (decided) { /* no zero within margin of the cut: the ends may overlap by that much */
                *lo = cut - CODEGEN_R(2.0) * pi - CODEGEN_R(0.5) * margin;
                *hi = cut;
                return CODEGEN_OK;
            }
        }
    } else {
        *below = -CODEGEN_HUGE;
    }
    *lo = centre - pi;
    *hi = centre + pi;
    return CODEGEN_OK;
}

/* The result holds max_uncertain intervals: u is joined to the listed one nearest to it (of its
 * mode where there is one), which then covers both and what lies between. Coarser, but every
 * zero that either interval may hold is still inside one; a result never fails for want of
 * room. The join is singular where either was, and claims no sign change. */
static void absorb_in_nearest(const result_view *work, const codegen_uncertain *u)
{
    codegen_uncertain *nearest = NULL;
    codegen_real best = 0;
    int i, same_mode = 0;
    for (i = 0; i < *work->n_uncertain; ++i) {
        codegen_uncertain *v = &work->uncertain[i];
        const codegen_real gap = v->lo > u->hi ? v->lo - u->hi : u->lo > v->hi ? u->lo - v->hi : 0;
        const int mine = v->mode == u->mode;
        if (nearest == NULL || (mine && !same_mode) || (mine == same_mode && gap < best)) {
            nearest = v;
            best = gap;
            same_mode = mine;
        }
    }
    widen(nearest, u);
    nearest->kind = nearest->kind == u->kind ? u->kind : CODEGEN_SINGULAR;
    nearest->sign_change = 0;
}

/* An interval the isolation could not decide, into work, or joined to one listed there
 * (listed_as): the isolation leaves a limit position of a chain as a run of slivers. */
static int add_uncertain(const codegen_model *model, const result_view *work, codegen_real lo,
                         codegen_real hi, codegen_uncertainty kind, unsigned mode, int sign_change)
{
    codegen_uncertain u, *same;
    memset(&u, 0, sizeof u);
    u.lo = lo;
    u.hi = hi;
    u.kind = kind;
    u.mode = mode;
    u.sign_change = sign_change;
    same = listed_as(work, *work->n_uncertain, &u);   /* a sliver of one listed */
    if (same != NULL) {
        widen(same, &u);
        return CODEGEN_OK;
    }
    if (*work->n_uncertain == model->max_uncertain) {
        if (model->max_uncertain == 0) {
            return CODEGEN_ERR_CAPACITY;
        }
        absorb_in_nearest(work, &u);
        return CODEGEN_OK;
    }
    /* bytes, not a struct assignment: the slot's padding stays the zeroed result's, so a
     * workspace reused dirty gives the same bytes as a fresh one */
    memcpy(&work->uncertain[(*work->n_uncertain)++], &u, sizeof u);
    return CODEGEN_OK;
}

/* Whether a proven root of this kind whose interval meets [at.lo, at.hi] is listed in work:
 * both intervals hold one zero where G is monotone, so they hold the same one. */
static int already_proven(const result_view *work, codegen_root_kind kind, codegen_iv at)
{
    int i;
    for (i = 0; i < *work->n_roots; ++i) {
        const codegen_equilibrium *e = &work->roots[i];
        if (e->certified && e->kind == kind && meet(e->theta_lo, e->theta_hi, at.lo, at.hi)) {
            return 1;
        }
    }
    return 0;
}

/* Every zero of G on one mode over [lo, hi], into work: certified roots linearised, the
 * rest as uncertain intervals. Angles are moved by 2 pi into the range where needed. whole:
 * [lo, hi] is the whole range (G within rounding of 0 over all of it: every angle). */
static int isolate_mode(const call *c, unsigned mode, codegen_real lo, codegen_real hi,
                        codegen_real below, int whole, void *workspace, const result_view *work)
{
    const codegen_model *model = c->model;
    codegen_isolated *found = (codegen_isolated *)field(workspace, model->workspace.found);
    const codegen_real two_pi = CODEGEN_R(6.28318530717958647692);
    int i, count;
    const int isolated = codegen_isolate_work(model->enclose, &c->enclosure, mode, lo, hi, found,
                                              model->max_roots + model->max_uncertain, &count,
                                              (codegen_isolation_box *)field(workspace, model->workspace.boxes));
    if (!whole && (isolated == CODEGEN_ISOLATE_FULL || isolated == CODEGEN_ISOLATE_BUDGET)) {
        /* a window the isolation cannot settle (G' unbounded near a pole): undecided */
        const codegen_iv window = turned(lo, hi, lo <= below);
        return add_uncertain(model, work, window.lo, window.hi, CODEGEN_SINGULAR, mode, 0);
    }
    if (isolated == CODEGEN_ISOLATE_FULL || isolated == CODEGEN_ISOLATE_BUDGET) {
        return CODEGEN_ERR_CAPACITY;
    }
    if (isolated != 0) {
        return isolated;
    }
    if (whole && count == 1 && found[0].kind == CODEGEN_ISOLATED_CLUSTER && found[0].lo == lo
        && found[0].hi == hi) {
        /* G within rounding of 0 everywhere, or beyond the range of the reals (an anchor
         * 1e200 m away): only a finite G that holds 0 says every angle */
        codegen_iv g;
        unsigned flags;
        const int status = model->enclose(&c->enclosure, mode, codegen_iv_point(found[0].theta),
                                          &g, NULL, &flags);
        return status != 0 ? status
             : isfinite(g.lo) && isfinite(g.hi) ? CODEGEN_ERR_EVERY_ANGLE : CODEGEN_ERR_OVERFLOW;
    }
    for (i = 0; i < count; ++i) {
        const codegen_real shift = found[i].theta <= below ? two_pi : 0;
        const codegen_iv moved = turned(found[i].lo, found[i].hi, shift != 0);
        if (found[i].kind == CODEGEN_ISOLATED_ROOT) {
            codegen_equilibrium *e = &work->roots[*work->n_roots];
            const codegen_root_kind kind = mode == 0u ? CODEGEN_EQUILIBRIUM : CODEGEN_OTHER_ASSEMBLY;
            int status;
            if (!whole && already_proven(work, kind, moved)) { /* a window's: proven already */
                continue;
            }
            if (*work->n_roots == model->max_roots) {
                return CODEGEN_ERR_CAPACITY;
            }
            status = linearise(c, mode, found[i].theta + shift, e);
            if (status == CODEGEN_ERR_SINGULAR_STATE) { /* proven, but K or M undefined */
                if (*work->n_singular == model->max_roots) {
                    return CODEGEN_ERR_CAPACITY;
                }
                work->singular_theta[(*work->n_singular)++] = found[i].theta + shift;
                continue;
            }
            if (status == CODEGEN_OK) {
                e->kind = kind;
                e->genuine = mode == 0u;
                e->certified = 1;
                e->theta_lo = moved.lo;
                e->theta_hi = moved.hi;
                status = vibrate(e);
            }
            if (status != CODEGEN_OK) {
                return status;
            }
            ++*work->n_roots;
        } else {
            const int status = add_uncertain(model, work, moved.lo, moved.hi,
                                             found[i].kind == CODEGEN_ISOLATED_CLUSTER ? CODEGEN_CLUSTER
                                             : CODEGEN_SINGULAR, mode, found[i].sign_change);
            if (status != CODEGEN_OK) {
                return status;
            }
        }
    }
    return CODEGEN_OK;
}

/* The isolation route into *work (parameters checked). */
ROUTE static int isolate_into(const call *c, void *workspace, const result_view *work)
{
    const codegen_model *model = c->model;
    codegen_real lo, hi, below;
    unsigned mode;
    int status;
    clear(model, work);
    status = isolation_range(c, &lo, &hi, &below);
    for (mode = 0u; mode < (unsigned)model->n_modes && status == CODEGEN_OK; ++mode) {
        status = isolate_mode(c, mode, lo, hi, below, 1, workspace, work);
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    sort_roots(work->roots, *work->n_roots);
    sort_uncertain(work->uncertain, *work->n_uncertain);
    return CODEGEN_OK;
}

/* Sort uncertain intervals by lo (insertion sort). */
static void sort_uncertain(codegen_uncertain *uncertain, int count)
{
    int i, j;
    for (i = 1; i < count; ++i) {
        for (j = i; j > 0 && uncertain[j - 1].lo > uncertain[j].lo; --j) {
            const codegen_uncertain swap = uncertain[j];
            uncertain[j] = uncertain[j - 1];
            uncertain[j - 1] = swap;
        }
    }
}

/* Where the spans cannot be proven (the iteration does not converge; both the leading and the
 * trailing coefficient of the polynomial may vanish; sigma has no error bound): the
 * equilibria come from the certified isolation of G itself, which drops none and lists what
 * working precision cannot decide in uncertain[]; the polynomial's roots add sigma, its
 * extraneous roots, and the angles where the mechanism is singular or cannot be assembled:
 * both, then the polynomial's extras into the isolation's result. */
ROUTE static int complete_by_isolation(const call *c, void *workspace,
                                       const result_view *polynomial, const result_view *result)
{
    const codegen_model *model = c->model;
    int i;
    int status = analyze_polynomial(c, workspace, polynomial);
    if (status == CODEGEN_OK) {
        status = isolate_into(c, workspace, result);
    }
    if (status != CODEGEN_OK) {
        return status;
    }
    for (i = 0; i < *polynomial->n_roots && *result->n_roots < model->max_roots; ++i) {
        if (polynomial->roots[i].kind == CODEGEN_EXTRANEOUS) {
            result->roots[(*result->n_roots)++] = polynomial->roots[i];
        }
    }
    sort_roots(result->roots, *result->n_roots);
    memcpy(result->sigma, polynomial->sigma, (size_t)(model->degree + 1) * sizeof *result->sigma);
    *result->n_unassembled = *polynomial->n_unassembled;
    memcpy(result->unassembled_theta, polynomial->unassembled_theta,
           (size_t)model->max_roots * sizeof *result->unassembled_theta);
    for (i = 0; i < *polynomial->n_singular && *result->n_singular < model->max_roots; ++i) {
        result->singular_theta[(*result->n_singular)++] = polynomial->singular_theta[i];
    }
    return CODEGEN_OK;
}

/* The assembly mode, as the model declares its modes, of the state at theta on the sign
 * choice `found` (the mode its closed form was evaluated on): codegen_declared_mode. */
static unsigned declared_mode(const call *c, unsigned found, codegen_real theta)
{
    const codegen_model *model = c->model;
    if (model->assembly_conditions == NULL) {
        return found;
    }
    model->assembly_conditions(c->enclosure.params, theta, c->conditions);
    return codegen_declared_mode(model, c->conditions, found);
}

/* Every root and uncertain interval of a result, named by the mode its state is in as the
 * model declares the modes (see declared_mode); roots of no declared mode are of kind
 * CODEGEN_MODE_UNDECIDED. */
static void assign_modes(const call *c, const result_view *r)
{
    const codegen_model *model = c->model;
    int i;
    for (i = 0; i < *r->n_roots; ++i) {
        codegen_equilibrium *e = &r->roots[i];
        if (e->kind == CODEGEN_EXTRANEOUS) {
            e->mode = 0u;
            continue;
        }
        e->mode = declared_mode(c, e->mode, e->theta);
        e->kind = e->mode == 0u ? CODEGEN_EQUILIBRIUM
                : e->mode < (unsigned)model->n_modes ? CODEGEN_OTHER_ASSEMBLY
                : CODEGEN_MODE_UNDECIDED;
        e->genuine = e->kind == CODEGEN_EQUILIBRIUM;
    }
    for (i = 0; i < *r->n_uncertain; ++i) {
        codegen_uncertain *u = &r->uncertain[i];
        u->mode = declared_mode(c, u->mode, u->lo + CODEGEN_R(0.5) * (u->hi - u->lo));
    }
    drop_repeated(r);
}

/* Whether intervals a and b touch or overlap, or leave between them a gap narrower than
 * SLIVER_GAP that holds no root listed in r (so their union claims nothing that was proven:
 * it only says less). */
#define SLIVER_GAP (CODEGEN_R(64.0) * CODEGEN_EPSILON > CODEGEN_R(1e-9) \
                    ? CODEGEN_R(64.0) * CODEGEN_EPSILON : CODEGEN_R(1e-9))
static int close_without_root(const result_view *r, const codegen_uncertain *a,
                              const codegen_uncertain *b)
{
    const codegen_real end = a->lo < b->lo ? a->hi : b->hi;     /* of the one starting first */
    const codegen_real start = a->lo < b->lo ? b->lo : a->lo;   /* of the other */
    int i;
    if (start - end > SLIVER_GAP) {
        return 0;
    }
    for (i = 0; i < *r->n_roots; ++i) {
        if (r->roots[i].theta_hi >= end && r->roots[i].theta_lo <= start) {
            return 0;
        }
    }
    return 1;
}

/* The interval among r's first count that u is one with, or NULL. Intervals of one kind
 * and one mode are one where they are the same, or where they meet or nearly do
 * (close_without_root) and G changes sign across neither: two sign changes side by side
 * need not make one across the union, and each says where an equilibrium is. */
static codegen_uncertain *listed_as(const result_view *r, int count, const codegen_uncertain *u)
{
    int j;
    for (j = 0; j < count; ++j) {
        codegen_uncertain *v = &r->uncertain[j];
        if (v->kind != u->kind || v->mode != u->mode) {
            continue;
        }
        if ((v->lo == u->lo && v->hi == u->hi && v->sign_change == u->sign_change)
            || (!v->sign_change && !u->sign_change && close_without_root(r, v, u))) {
            return v;
        }
    }
    return NULL;
}

/* v becomes the union of v and u. */
static void widen(codegen_uncertain *v, const codegen_uncertain *u)
{
    v->lo = u->lo < v->lo ? u->lo : v->lo;
    v->hi = u->hi > v->hi ? u->hi : v->hi;
}

/* Uncertain intervals listed once (listed_as): two branches' intervals can become the same
 * one once named by the declared modes (a chain's limit position, shared by both modes of
 * the dyad after it, is of no declared mode on either); add_uncertain already joins the
 * slivers the isolation leaves at a chain's limit position, mode by mode. */
static void drop_repeated(const result_view *r)
{
    int i, kept = 0;
    for (i = 0; i < *r->n_uncertain; ++i) {
        const codegen_uncertain *u = &r->uncertain[i];
        codegen_uncertain *same = listed_as(r, kept, u);
        if (same == NULL) {
            if (kept != i) {
                memcpy(&r->uncertain[kept], u, sizeof *u);
            }
            ++kept;
        } else {
            widen(same, u);
        }
    }
    *r->n_uncertain = kept;
}

/* One route into the workspace's result (parameters checked). */
static int run(const call *c, codegen_route route, void *workspace)
{
    int status, proven;
    if (route == CODEGEN_ROUTE_ISOLATION || c->model->sigma == NULL) {
        status = isolate_into(c, workspace, &c->result);
    } else {
        status = analyze_by_spans(c, workspace, &c->result, &proven);
        if (status == CODEGEN_OK && !proven) {
            status = complete_by_isolation(c, workspace, &c->polynomial, &c->result);
        }
    }
    if (status == CODEGEN_OK) {
        assign_modes(c, &c->result);
    }
    return status;
}

/* ==== Units ==== */

/* What parameter i says of axis (0 length, 1 mass, 2 time) as a binary exponent, given those
 * of the axes before it in x: a length's or a mass's own exponent (from frexp: the same on
 * every libm), or, for time, the exponent its unit leaves to the time's powers where that is
 * s^-2 (a force, a stiffness, a torque, an acceleration: what G is made of; a damper or a
 * mass does not enter the equilibrium). 0 where it says nothing (zero, another unit). */
static int estimate(const codegen_units *u, const codegen_real *p, int i, int axis,
                    const int x[3], codegen_real *value)
{
    const signed char *d = u->parameter + 3 * i;
    int e;
    if (p[i] == 0 || (axis < 2 && !(d[axis] == 1 && d[1 - axis] == 0 && d[2] == 0))
        || (axis == 2 && d[2] != -2)) {
        return 0;
    }
    (void)codegen_frexp(codegen_fabs(p[i]), &e);
    *value = axis < 2 ? (codegen_real)e
           : (codegen_real)(e - d[0] * x[0] - d[1] * x[1]) / (codegen_real)d[2];
    return 1;
}

/* The lower median of what the parameters say of axis, rounded (0 where none says); said:
 * room for one estimate per parameter. */
static int median_exponent(const codegen_units *u, const codegen_real *p, int axis, const int x[3],
                           codegen_real *said)
{
    int i, j, n = 0;
    for (i = 0; i < u->n_params; ++i) {
        n += estimate(u, p, i, axis, x, &said[n]);
    }
    for (i = 0; i < n; ++i) {
        int below = 0, same = 0;
        for (j = 0; j < n; ++j) {
            below += said[j] < said[i];
            same += said[j] == said[i];
        }
        if (below <= (n - 1) / 2 && (n - 1) / 2 < below + same) {
            return said[i] >= 0 ? (int)(said[i] + CODEGEN_R(0.5)) : -(int)(CODEGEN_R(0.5) - said[i]);
        }
    }
    return 0;
}

/* The powers of two of a length, a mass and a time (x[0..2]) the analysis works in: the
 * median exponent of the lengths, then of the masses, then of what each of G's parameters
 * (estimate) leaves to the time. A median moves with a change of units as the units
 * do, and an outlier (k = 1e300 beside forces of 100 N) cannot drag the others out of range,
 * as a mean or least squares would. said: room for one value per parameter. */
static void characteristic_units(const codegen_units *u, const codegen_real *p, int x[3],
                                 codegen_real *said)
{
    int axis;
    x[0] = x[1] = x[2] = 0;
    for (axis = 0; axis < 3; ++axis) {
        x[axis] = median_exponent(u, p, axis, x, said);
    }
}

static int power_of(const signed char d[3], const int x[3])
{
    return d[0] * x[0] + d[1] * x[1] + d[2] * x[2];
}

/* The parameters divided by their units' characteristic powers into scaled (x as chosen), or
 * params itself with x = 0 where the model keeps its units or a scaled value would leave the
 * normal range. */
static const void *in_units(const codegen_model *model, const void *params, void *scaled,
                            int x[3])
{
    const codegen_units *u = &model->units;
    const codegen_real *p = (const codegen_real *)params;
    codegen_real *q = (codegen_real *)scaled;
    int i;
    x[0] = x[1] = x[2] = 0;
    if (u->n_params == 0) {
        return params;
    }
    characteristic_units(u, p, x, q); /* q holds the estimates until it holds the values */
    for (i = 0; i < u->n_params; ++i) {
        q[i] = codegen_ldexp(p[i], -power_of(u->parameter + 3 * i, x));
        if (!isfinite(q[i]) || (p[i] != 0 && !(codegen_fabs(q[i]) >= CODEGEN_REAL_MIN))) {
            x[0] = x[1] = x[2] = 0;
            return params;
        }
    }
    return scaled;
}

/* v times 2^(d . x), the unit d's share of the scale; 0 where v is finite and the product
 * is not (an overflow; a NaN, as omega_n where M = 0, stays what it was). */
static int times_units(codegen_real *v, int count, const signed char d[3], const int x[3])
{
    const int n = power_of(d, x);
    int i, finite = 1;
    for (i = 0; i < count && n != 0; ++i) {
        const int was = isfinite(v[i]);
        v[i] = codegen_ldexp(v[i], n);
        finite = finite && (isfinite(v[i]) || !was);
    }
    return finite;
}

/* The result back in the user's units: G, K and the residuals in the force's, M and B with
 * s^2 and s more, sigma in its own; the vibration (omega_n, zeta, the eigenvalues) computed
 * afresh from M, B and K there, as it would have been in those units. An extraneous root
 * whose vibration overflows is dropped, as the analysis drops it in its own units. */
static int out_of_units(const codegen_model *model, const result_view *r, const int x[3])
{
    const codegen_units *u = &model->units;
    const signed char mass[3] = {u->force[0], u->force[1], (signed char)(u->force[2] + 2)};
    const signed char damping[3] = {u->force[0], u->force[1], (signed char)(u->force[2] + 1)};
    int i, kept = 0, finite = 1;
    if (x[0] == 0 && x[1] == 0 && x[2] == 0) {
        return CODEGEN_OK;
    }
    if (model->sigma != NULL) {
        finite = times_units(r->sigma, model->degree + 1, u->sigma, x);
    }
    for (i = 0; i < *r->n_roots && finite; ++i) {
        codegen_equilibrium *e = &r->roots[i];
        finite = times_units(&e->residual, 1, u->force, x)
              && times_units(&e->residual_scale, 1, u->force, x)
              && times_units(&e->K, 1, u->force, x) && times_units(&e->M, 1, mass, x)
              && times_units(&e->B, 1, damping, x) && vibrate(e) == CODEGEN_OK;
        if (!finite && e->kind == CODEGEN_EXTRANEOUS) {
            finite = 1;
            continue;
        }
        if (kept != i) {
            memcpy(&r->roots[kept], e, sizeof *e);
        }
        ++kept;
    }
    *r->n_roots = kept;
    return finite ? CODEGEN_OK : CODEGEN_ERR_OVERFLOW;
}

/* The analysis of params (in the units c->units names) into c->result, in the user's units:
 * run, its results multiplied back (out_of_units), and where sigma overflows the isolation's
 * result instead, whose sigma is 0 and which overflows in its turn only where G does. */
static int run_in(call *c, codegen_route route, void *workspace, const void *params)
{
    const codegen_model *model = c->model;
    int status;
    c->enclosure.params = params;
    if (model->prepare_enclosure != NULL) {
        model->prepare_enclosure(&c->enclosure);
    }
    status = run(c, route, workspace);
    if (status == CODEGEN_OK) {
        status = out_of_units(model, &c->result, c->units);
    }
    if (status == CODEGEN_ERR_OVERFLOW && route != CODEGEN_ROUTE_ISOLATION && model->sigma != NULL) {
        status = run(c, CODEGEN_ROUTE_ISOLATION, workspace);
        if (status == CODEGEN_OK) {
            status = out_of_units(model, &c->result, c->units);
        }
    }
    return status;
}

int codegen_analysis_run(const codegen_model *model, codegen_route route, const void *params,
                         void *result, void *workspace)
{
    int status;
    call *c;
    codegen_real *scratch;
    if (params == NULL || result == NULL || workspace == NULL) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    status = model->check_params(params);
    if (status != CODEGEN_OK) {
        return status;
    }
    c = (call *)field(workspace, model->workspace.call);
    scratch = (codegen_real *)field(workspace, model->workspace.scratch);
    c->model = model;
    c->enclosure.slots = (codegen_iv *)field(workspace, model->workspace.enclosure_slots);
    c->at_root = scratch;
    c->at_next = c->at_root + model->state.size;
    c->at_line = c->at_next + model->state.size;
    c->g = c->at_line + model->state.size;
    c->merged = c->g + model->n_branches;
    c->modes = c->merged + 3 * model->n_branches;
    c->conditions = c->modes + 3 * model->n_modes;
    c->result = results_in(model, field(workspace, model->workspace.result));
    if (model->sigma != NULL) {
        c->polynomial = results_in(model, field(workspace, model->workspace.polynomial));
    }
    status = run_in(c, route, workspace,
                    in_units(model, params, field(workspace, model->workspace.scaled_params),
                             c->units));
    if (status == CODEGEN_ERR_OVERFLOW && (c->units[0] != 0 || c->units[1] != 0 || c->units[2] != 0)) {
        /* scaled, an intermediate overflowed that does not in the user's units (b near the
         * largest double times lengths scaled up): the analysis in those units */
        c->units[0] = c->units[1] = c->units[2] = 0;
        status = run_in(c, route, workspace, params);
    }
    if (status == CODEGEN_OK) {
        memcpy(result, field(workspace, model->workspace.result), model->analysis.size);
    }
    return status;
}
