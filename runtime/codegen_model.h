/*
 * codegen_model.h -- what a generated library tells the runtime about its mechanism, and
 * the analysis (Table 1, steps 8-10) and time response written once against it.
 * Hand-written (not generated). Plain C99 + libm; no allocation, no mutable static state, no I/O.
 *
 * A library provides one constant codegen_model: its sizes, the layout of its result and
 * workspace types, its status codes for failures of each kernel, and its unchecked kernels
 * (NAME_kernels.h) behind pointers that take the parameters as const void *. The library's
 * public entries (NAME_analyze, NAME_isolate, NAME_simulate...) check nothing themselves and
 * call codegen_analysis_run and codegen_simulation_* with it, as
 * acados' solvers call their generated model functions.
 */
#ifndef CODEGEN_MODEL_H
#define CODEGEN_MODEL_H

#include <stddef.h>

#include "codegen_interval.h"
#include "codegen_ode.h"
#include "codegen_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The status codes every library numbers alike (its first thirteen; the rest are its
 * parameters' requirements). */
enum {
    CODEGEN_OK = 0,
    CODEGEN_ERR_NULL_POINTER = 1,
    CODEGEN_ERR_NONFINITE = 2,
    CODEGEN_ERR_ZERO_POLYNOMIAL = 3,
    CODEGEN_ERR_NONFINITE_PARAM = 4,
    CODEGEN_ERR_SINGULAR_STATE = 5,
    CODEGEN_ERR_OVERFLOW = 6,
    CODEGEN_ERR_EVERY_ANGLE = 7,
    CODEGEN_ERR_ARGUMENT = 8,
    CODEGEN_ERR_CAPACITY = 9,
    CODEGEN_ERR_STEP_BUDGET = 10,
    CODEGEN_ERR_STEP_SIZE = 11,
    CODEGEN_ERR_MODE_UNDECIDED = 12
};

/* Stability of an equilibrium from M, B, K (M > 0). */
typedef enum codegen_stability {
    CODEGEN_STABLE = 0,   /* K > 0, B > 0: perturbations decay */
    CODEGEN_MARGINAL = 1, /* K > 0, B = 0 (undamped), or K = 0 */
    CODEGEN_UNSTABLE = 2  /* K < 0: a perturbation grows */
} codegen_stability;

/* Character of the free motion about an equilibrium. */
typedef enum codegen_damping {
    CODEGEN_UNDERDAMPED = 0,       /* 0 < zeta < 1 */
    CODEGEN_CRITICALLY_DAMPED = 1, /* zeta = 1 to rounding */
    CODEGEN_OVERDAMPED = 2,        /* zeta > 1 */
    CODEGEN_UNDAMPED = 3,          /* B = 0, K > 0 */
    CODEGEN_NOT_OSCILLATORY = 4    /* K <= 0: no natural frequency */
} codegen_damping;

/* What a root is: which branch of the square roots zeroes G there. */
typedef enum codegen_root_kind {
    CODEGEN_EQUILIBRIUM = 0,    /* G = 0 as declared: an equilibrium */
    CODEGEN_OTHER_ASSEMBLY = 1, /* G = 0 in another assembly mode: an equilibrium of that mode */
    CODEGEN_EXTRANEOUS = 2,     /* G = 0 only with a negative length: not an equilibrium */
    CODEGEN_MODE_UNDECIDED = 3  /* G = 0 in a state the model's assembly-mode conditions do not
                                   place in a mode (one is within rounding of 0 there, or holds
                                   in both or neither): an equilibrium of no declared mode */
} codegen_root_kind;

/* One root of G (or of the polynomial) and the vibration about it, (46)-(55); M, B, K are
 * those of its own assembly mode (of the declared one for an extraneous root). Where M = 0 (no
 * inertia at that angle) omega_n, zeta and the eigenvalues are NaN: undefined. Complex
 * quantities are [real part, imaginary part]. */
typedef struct codegen_equilibrium {
    codegen_real theta;           /* theta_E [rad], in the coordinate's range */
    codegen_real theta_lo;        /* an interval [rad] holding theta_E: when certified, exactly one */
    codegen_real theta_hi;        /*   zero of G lies in it (G changes sign, G' keeps its sign) */
    int certified;                /* 1: the equilibrium is proven, in [theta_lo, theta_hi] */
    int genuine;                  /* 1: an equilibrium of the declared mode (kind EQUILIBRIUM) */
    codegen_root_kind kind;
    unsigned mode;                /* its assembly mode, decided at run time by the model's
                                     conditions: 0 the declared one, bit i set where the i-th
                                     dyad is assembled the other way; n_modes: undecided */
    codegen_real residual;        /* G(theta_E) (42) [N m] */
    codegen_real residual_scale;  /* size of the contributions to G at theta_E [N m]; a genuine
                                     root has |residual| / residual_scale near machine epsilon */
    codegen_real M;               /* M_EQ [kg m^2] (50) */
    codegen_real B;               /* B_EQ [N m s] (51) */
    codegen_real K;               /* K_EQ [N m] (52) */
    codegen_real omega_n[2];      /* natural frequency, real and imaginary parts [rad/s] (54) */
    codegen_real zeta[2];         /* damping ratio, real and imaginary parts (55) */
    codegen_real eigen_re[2];     /* eigenvalues of M s^2 + B s + K = 0, real parts [1/s] */
    codegen_real eigen_im[2];     /* and imaginary parts [rad/s] */
    codegen_stability stability;
    codegen_damping damping;
} codegen_equilibrium;

/* What the certified isolation could not decide in working precision. */
typedef enum codegen_uncertainty {
    CODEGEN_CLUSTER = 0,  /* G and G' within rounding of 0 throughout: a double root (a fold),
                             two equilibria closer than rounding separates, or a near-double
                             complex pair (none); sign_change = 1 means at least one */
    CODEGEN_SINGULAR = 1  /* G undefined or not smooth somewhere inside (a spring through
                             zero length, a limit position): no equilibrium is claimed there */
} codegen_uncertainty;

typedef struct codegen_uncertain {
    codegen_real lo, hi;          /* [rad] */
    codegen_uncertainty kind;
    unsigned mode;                /* the assembly mode at its middle, as codegen_equilibrium's */
    int sign_change;              /* G's sign differs at lo and hi: an odd number of zeros
                                     inside if G is continuous there */
} codegen_uncertain;

/* A result (NAME_analysis) seen through its library's layout. */
typedef struct codegen_analysis_view {
    void *base;
    codegen_real *sigma;
    int *n_roots;
    codegen_equilibrium *roots;
    int *n_singular;
    codegen_real *singular_theta;
    int *n_unassembled;
    codegen_real *unassembled_theta;
    int *n_uncertain;
    codegen_uncertain *uncertain;
} codegen_analysis_view;

/* What the analysis hands a library's enclosure (codegen_model.enclose) as its context: the
 * validated parameters and the slots its interval programs run in. */
typedef struct codegen_enclosure_context {
    const void *params;
    codegen_iv *slots;
} codegen_enclosure_context;

/* One analysis in progress, kept in the workspace (the stack then holds only scalars): the
 * model, the enclosures' context, and the parts of the workspace at work. */
typedef struct codegen_analysis_call {
    const struct codegen_model *model;
    codegen_enclosure_context enclosure;
    codegen_real *at_root;       /* the state at a root being studied */
    codegen_real *at_next;       /* at a Newton step's trial point */
    codegen_real *at_line;       /* at a root being linearised */
    codegen_real *g;             /* G on every branch at one angle */
    codegen_real *merged;        /* ... at a root and either side of it */
    codegen_real *modes;         /* M, B, K of every mode */
    codegen_real *conditions;    /* the assembly-mode conditions of every mode, and scales */
    codegen_analysis_view result, polynomial;
    int units[3];                /* the characteristic length, mass, time: these powers of 2 */
} codegen_analysis_call;

/* Where the fields of a library's NAME_analysis lie (offsetof; sigma: none without the
 * polynomial route), and its size. */
typedef struct codegen_analysis_layout {
    size_t size, sigma, n_roots, roots, n_singular, singular_theta, n_unassembled,
        unassembled_theta, n_uncertain, uncertain;
} codegen_analysis_layout;

/* Where the parts of a library's NAME_workspace lie (offsetof; those of a route the library
 * lacks are unused). scratch holds CODEGEN_ANALYSIS_SCRATCH(state, branches, modes,
 * conditions) reals. */
typedef struct codegen_workspace_layout {
    size_t call, result, polynomial, roots, spans, sigma_bound, theta, branches, sigma_values,
        sigma_errors, enclosure_slots, found, boxes, scratch, scaled_params;
} codegen_workspace_layout;

/* The reals of the analysis' scratch: three states, four sets of branch values, M, B, K of
 * every mode, and the assembly-mode conditions of every mode with their scales. */
#define CODEGEN_ANALYSIS_SCRATCH(state, branches, modes, conditions) \
    (3 * (state) + 4 * (branches) + 3 * (modes) + 2 * (conditions))

/* Where the fields of a library's NAME_simulation lie. */
typedef struct codegen_simulation_layout {
    size_t params, options, state, work, signs;
} codegen_simulation_layout;

/* Where each quantity lies in the output of the fused kernel equilibrium_state. */
typedef struct codegen_state_layout {
    int size, residual, scale, m, b, k, branch_residuals, radicands, radicand_scales;
} codegen_state_layout;

/* The units the analysis divides out (codegen_analysis.c): each parameter's powers of metre,
 * kilogram and second, and those of G (and K) and of sigma's coefficients, which it
 * multiplies back into its results. n_params 0: the analysis keeps the user's units. */
typedef struct codegen_units {
    int n_params;
    const signed char *parameter;   /* 3 per parameter, in the order of NAME_params */
    signed char force[3], sigma[3];
} codegen_units;

/* A library's mechanism, as the runtime's analysis and time response see it. Kernels are
 * unchecked: the runtime calls them only with parameters check_params accepted. */
struct codegen_model {
    size_t params_size;           /* sizeof(NAME_params) */
    int n_modes;                  /* assembly modes (1: only as declared) */
    int n_roots;                  /* square roots whose radicands the state holds */
    int n_branches;               /* sign branches of those roots (2^n_roots) */
    int max_roots, max_uncertain; /* the result's capacities */
    int degree;                   /* of the polynomial in tan(theta/2); 0: no polynomial route */
    int periodic;                 /* the coordinate is an angle on the circle */
    unsigned length_branch_bits;  /* branches (bit i: root i negative) with a negative length */
    const unsigned *mode_of_branch, *branch_of_mode; /* NULL with a single mode */
    int n_conditions;             /* the model's assembly-mode conditions (0: none) */
    const unsigned *condition_bit; /* the mode bit each decides */
    codegen_state_layout state;
    int mode_m, mode_b, mode_k;   /* where each mode's M, B, K start in mode_linearisation's output */
    /* the status of each kernel's failure (a result not finite) */
    int residual_failure, linearisation_failure, mode_linearisation_failure, radicands_failure,
        branches_failure, sigma_failure, acceleration_failure;
    int (*check_params)(const void *params);
    /* G, its scale, M, B, K, G on every branch and the radicands at theta: out[state.size] */
    void (*equilibrium_state)(const void *params, codegen_real theta, codegen_real *out);
    /* G on every branch (NULL: no square roots declared) */
    void (*equilibrium_branches)(const void *params, codegen_real theta, codegen_real *out);
    /* M, B, K of every mode (NULL: a single mode) */
    void (*mode_linearisation)(const void *params, codegen_real theta, codegen_real *out);
    /* every condition on every mode, then their scales: out[2 * n_modes * n_conditions]
     * (NULL: no conditions) */
    void (*assembly_conditions)(const void *params, codegen_real theta, codegen_real *out);
    /* G and G' enclosed over theta on a mode; context: a codegen_enclosure_context, made
     * ready for its parameters by prepare_enclosure (NULL: nothing to prepare) */
    codegen_enclosure enclose;
    void (*prepare_enclosure)(const void *context);
    /* 1 where enclose, given g NULL (and dg NULL), runs G's divisions and square roots alone
     * and sets only the flags (the generated libraries' do); 0: never asked so */
    int enclose_flags_alone;
    /* the polynomial's coefficients (NULL: no polynomial route) and, unless bound is NULL, a
     * bound on each one's error (CODEGEN_HUGE where there is none); values and errors: its
     * program's memory */
    int (*sigma)(const void *params, codegen_real *sigma, codegen_real *bound, void *values,
                 codegen_real *errors);
    /* the centre of the coordinate's range [rad] */
    codegen_real (*range_centre)(const void *params);
    /* thetaddot at (theta, thetadot) on a sign choice of the assembly roots (< n_modes) */
    codegen_real (*angular_acceleration)(const void *params, unsigned signs, codegen_real theta,
                                         codegen_real theta_d);
    /* M, B, K at theta on a sign choice of the assembly roots: out[3] */
    void (*linearisation)(const void *params, unsigned signs, codegen_real theta,
                          codegen_real *out);
    /* the sign choice on which the model's assembly-mode conditions hold at theta, n_modes
     * where they decide none, n_modes + 1 where there is no state (codegen_declared_signs;
     * NULL: always 0, the model declares no conditions) */
    unsigned (*declared_signs)(const void *params, codegen_real theta);
    codegen_units units;
    codegen_analysis_layout analysis;
    codegen_workspace_layout workspace;
    codegen_simulation_layout simulation;
};
typedef struct codegen_model codegen_model;

/* The assembly mode, as the model declares its modes (mode_linearisation's numbering read
 * as: bit i set where dyad i is the other way), of a state found on sign choice `found`,
 * from the conditions assembly_conditions gave at its angle: for each dyad, its conditions
 * must hold with its root's sign as found and fail with it flipped (then the dyad is as
 * declared), or the reverse (then it is the other way); where the flipped sign gives no
 * state, the state's own conditions decide. model->n_modes where a dyad's conditions decide
 * neither way. (codegen_modes.c) */
unsigned codegen_declared_mode(const codegen_model *model, const codegen_real *conditions,
                               unsigned found);

/* The sign choice whose state at theta is the mode the model declares (every condition
 * holds), dyad by dyad in solving order: 0 without conditions; model->n_modes where the
 * conditions decide no choice; model->n_modes + 1 where a dyad has no state on either sign
 * (it cannot be assembled at theta). conditions: 2 n_modes n_conditions reals of working
 * memory. (codegen_modes.c) */
unsigned codegen_declared_signs(const codegen_model *model, const void *params,
                                codegen_real theta, codegen_real *conditions);

/* The sign choice a function of one angle evaluates on at theta (model->declared_signs; 0
 * where the model declares no conditions) in *signs: CODEGEN_OK, CODEGEN_ERR_MODE_UNDECIDED
 * where the conditions decide no choice, or no_state where a dyad has no state there.
 * (codegen_modes.c) */
int codegen_signs_at(const codegen_model *model, const void *params, codegen_real theta,
                     int no_state, unsigned *signs);

/* The two routes of the analysis. */
typedef enum codegen_route {
    CODEGEN_ROUTE_DEFAULT = 0,   /* the polynomial route where there is one (completed by the
                                    isolation in float), else the isolation */
    CODEGEN_ROUTE_ISOLATION = 1  /* every zero of G proven by interval enclosures */
} codegen_route;

/* The analysis of one parameter set into *result (a NAME_analysis), in workspace (a
 * NAME_workspace): checks the pointers and the parameters; *result is written only on
 * CODEGEN_OK. Returns a status of the library's. */
int codegen_analysis_run(const codegen_model *model, codegen_route route, const void *params,
                         void *result, void *workspace);

/* The time response (codegen_ode.h) of thetaddot = f(theta, thetadot): simulation is a
 * NAME_simulation; the statuses and contracts are NAME_simulation_start's, _advance's,
 * NAME_simulate's and NAME_rk4_step's (NAME.h). */
int codegen_simulation_start(const codegen_model *model, void *simulation, const void *params,
                             codegen_real t0, codegen_real theta0, codegen_real theta_d0,
                             const codegen_ode_options *options);
int codegen_simulation_advance(const codegen_model *model, void *simulation,
                               const codegen_real *times, size_t n_times, codegen_real *theta,
                               codegen_real *theta_d, size_t *reached);
int codegen_simulate(const codegen_model *model, void *simulation, const void *params,
                     codegen_real theta0, codegen_real theta_d0, const codegen_real *times,
                     size_t n_times, const codegen_ode_options *options, codegen_real *theta,
                     codegen_real *theta_d, size_t *reached);
int codegen_rk4_step(const codegen_model *model, const void *params, codegen_real h,
                     codegen_real theta, codegen_real theta_d, codegen_real *theta_next,
                     codegen_real *theta_d_next);

/* The receptance H(omega) = 1 / (K - omega^2 M + i omega B) of the declared mode's
 * linearisation at theta (on the sign choice the model's conditions hold on there), at count
 * circular frequencies omega[i] [rad/s] (any finite value: H(-omega) is H(omega)'s
 * conjugate) into H_re[i], H_im[i]. The statuses and contracts are
 * NAME_frequency_response's (NAME.h). */
int codegen_frequency_response(const codegen_model *model, const void *params, codegen_real theta,
                               size_t count, const codegen_real *omega, codegen_real *H_re,
                               codegen_real *H_im);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_MODEL_H */
