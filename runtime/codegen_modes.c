/*
 * codegen_modes.c -- which assembly mode a state is in, as the model declares its modes
 * (codegen_model.h). Hand-written (not generated). Plain C99 + libm.
 *
 * The closed form of the positions takes a sign for each dyad's square root (a sign choice,
 * numbered as mode_linearisation numbers its modes). The model declares a dyad's mode by
 * conditions (e.g. "the block below the crank pin") instead, and which sign makes them hold
 * can change with the parameters (a slide's inclination, a pivot on either side of a line)
 * and with the angle: it is decided here from the conditions evaluated on every sign choice.
 */
#include "codegen_model.h"

#include <math.h>

/* An assembly-mode condition within this much of the size of its terms is zero (the dyad
 * between its modes, or a condition that does not tell them apart there): the mode is not
 * decided. Far above the conditions' rounding, far below any assembly a user draws. */
#define CONDITION_MARGIN CODEGEN_SQRT_EPSILON

/* The sign of a condition: 1 (holds), -1 (fails) or 0 (within CONDITION_MARGIN of 0, or
 * not finite: that choice cannot be assembled there). */
static int condition_sign(codegen_real value, codegen_real scale)
{
    const codegen_real margin = CONDITION_MARGIN * scale;
    return value > margin ? 1 : value < -margin ? -1 : 0;
}

/* Whether every condition of one dyad (mode bit) holds on a sign choice (1), one fails (-1),
 * the choice has no state there (NO_STATE: every one of them not finite), or neither is
 * certain (0). */
#define NO_STATE 2
static int dyad_holds(const codegen_model *model, const codegen_real *conditions,
                      unsigned choice, unsigned bit)
{
    const int n = model->n_conditions, offset = (int)choice * n;
    const codegen_real *scales = conditions + model->n_modes * n;
    int k, all = 1, none = 1;
    for (k = 0; k < n; ++k) {
        if (model->condition_bit[k] == bit) {
            const codegen_real value = conditions[offset + k];
            const int sign = condition_sign(value, scales[offset + k]);
            if (sign < 0) {
                return -1;
            }
            all = all && sign > 0;
            none = none && !isfinite(value);
        }
    }
    return none ? NO_STATE : all;
}

/* Whether dyad `bit` is as declared on sign choice `choice` (1), the other way (-1), or
 * undecided (0): its conditions must hold there and fail with its sign flipped, or the
 * reverse; where the flipped sign gives no state (a dyad after this one cannot be assembled
 * on it), the state's own conditions decide. Both without a state: NO_STATE. */
static int dyad_as_declared(const codegen_model *model, const codegen_real *conditions,
                            unsigned choice, unsigned bit)
{
    const int here = dyad_holds(model, conditions, choice, bit);
    const int flipped = dyad_holds(model, conditions, choice ^ (1u << bit), bit);
    if (here == NO_STATE && flipped == NO_STATE) {
        return NO_STATE;
    }
    if (here == 1 && (flipped == -1 || flipped == NO_STATE)) {
        return 1;
    }
    if (here == -1 && (flipped == 1 || flipped == NO_STATE)) {
        return -1;
    }
    return 0;
}

unsigned codegen_declared_mode(const codegen_model *model, const codegen_real *conditions,
                               unsigned found)
{
    unsigned bit, mode = 0u;
    for (bit = 0u; (1u << bit) < (unsigned)model->n_modes; ++bit) {
        const int as_declared = dyad_as_declared(model, conditions, found, bit);
        if (as_declared == -1) {
            mode |= 1u << bit;           /* this dyad the other way */
        } else if (as_declared != 1) {
            return (unsigned)model->n_modes;
        }
    }
    return mode;
}

int codegen_signs_at(const codegen_model *model, const void *params, codegen_real theta,
                     int no_state, unsigned *signs)
{
    *signs = model->declared_signs != NULL ? model->declared_signs(params, theta) : 0u;
    if (*signs < (unsigned)model->n_modes) {
        return CODEGEN_OK;
    }
    return *signs == (unsigned)model->n_modes ? CODEGEN_ERR_MODE_UNDECIDED : no_state;
}

unsigned codegen_declared_signs(const codegen_model *model, const void *params,
                                codegen_real theta, codegen_real *conditions)
{
    unsigned bit, choice = 0u;
    if (model->assembly_conditions == NULL) {
        return 0u;
    }
    model->assembly_conditions(params, theta, conditions);
    /* dyad by dyad in solving order: a dyad's conditions depend on the signs before it */
    for (bit = 0u; (1u << bit) < (unsigned)model->n_modes; ++bit) {
        const int as_declared = dyad_as_declared(model, conditions, choice, bit);
        if (as_declared == -1) {
            choice ^= 1u << bit;
        } else if (as_declared == NO_STATE) {
            return (unsigned)model->n_modes + 1u;   /* this dyad has no state here */
        } else if (as_declared != 1) {
            return (unsigned)model->n_modes;
        }
    }
    return choice;
}
