/*
 * codegen_response.c -- the frequency response of a mechanism's linearisation about a state
 * (codegen_model.h): the receptance of the declared mode's M, B, K at theta, through
 * codegen_receptance (codegen_modal.h).
 * Hand-written (not generated). Plain C99 + libm; no allocation, no static state, no I/O.
 */
#include "codegen_modal.h"
#include "codegen_model.h"

int codegen_frequency_response(const codegen_model *model, const void *params, codegen_real theta,
                               size_t count, const codegen_real *omega, codegen_real *H_re,
                               codegen_real *H_im)
{
    codegen_real work[CODEGEN_RECEPTANCE_WORK(1)], mbk[3];
    unsigned signs;
    size_t i;
    int status;
    if (model == NULL || params == NULL || (count > 0 && (omega == NULL || H_re == NULL
                                                          || H_im == NULL))) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    status = model->check_params(params);
    if (status != CODEGEN_OK) {
        return status;
    }
    if (!isfinite(theta)) {
        return CODEGEN_ERR_NONFINITE;
    }
    for (i = 0; i < count; ++i) {
        if (!isfinite(omega[i])) {
            return CODEGEN_ERR_NONFINITE;
        }
    }
    status = codegen_signs_at(model, params, theta, model->linearisation_failure, &signs);
    if (status != CODEGEN_OK) {
        return status;
    }
    model->linearisation(params, signs, theta, mbk);
    if (!isfinite(mbk[0]) || !isfinite(mbk[1]) || !isfinite(mbk[2])) {
        return model->linearisation_failure;
    }
    for (i = 0; i < count; ++i) {
        /* an undamped resonance: the amplitude is infinite */
        if (codegen_receptance(1, &mbk[0], &mbk[1], &mbk[2], omega[i], &H_re[i], &H_im[i],
                               work) != CODEGEN_MODAL_OK) {
            return CODEGEN_ERR_OVERFLOW;
        }
    }
    return CODEGEN_OK;
}
