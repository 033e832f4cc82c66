/*
 * codegen_modal.c -- modes, damped eigenvalues and receptance of M, B, K (codegen_modal.h).
 * Hand-written (not generated). Plain C99 + libm; no allocation, no static state, no I/O.
 */
#include "codegen_modal.h"

#include <stddef.h>

/* Jacobi sweeps before giving up: each converges quadratically, ~6-10 suffice. */
#define JACOBI_SWEEPS 64
/* Francis QR steps allowed in all: this many per row of the matrix, at least ten rows' worth
 * (LAPACK's dlahqr allows as many). */
#define QR_STEPS_PER_ROW 30
/* Steps without a deflation after which an entry kept near sqrt(eps) splits the matrix. */
#define STAGNATION 30

static int all_finite(const codegen_real *a, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        if (!isfinite(a[i])) {
            return 0;
        }
    }
    return 1;
}

static codegen_real symmetric_at(const codegen_real *a, int n, int i, int j)
{
    return CODEGEN_R(0.5) * a[i * n + j] + CODEGEN_R(0.5) * a[j * n + i];
}

/* M = L L^T, L lower triangular into l (row-major, upper part zero). */
static int cholesky(int n, const codegen_real *m, codegen_real *l)
{
    int i, j, k;
    for (i = 0; i < n * n; ++i) {
        l[i] = 0;
    }
    for (j = 0; j < n; ++j) {
        codegen_real d = symmetric_at(m, n, j, j);
        for (k = 0; k < j; ++k) {
            d -= l[j * n + k] * l[j * n + k];
        }
        if (!(d > 0) || !isfinite(d)) {
            return CODEGEN_MODAL_NOT_DEFINITE;
        }
        l[j * n + j] = codegen_sqrt(d);
        for (i = j + 1; i < n; ++i) {
            codegen_real s = symmetric_at(m, n, i, j);
            for (k = 0; k < j; ++k) {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / l[j * n + j];
        }
    }
    return CODEGEN_MODAL_OK;
}

/* Column c of x (stride n) := L^-1 column c of b (b read through get: symmetric or plain). */
static void forward(int n, const codegen_real *l, const codegen_real *b, int symmetric, int c, codegen_real *x)
{
    int i, k;
    for (i = 0; i < n; ++i) {
        codegen_real s = symmetric ? symmetric_at(b, n, i, c) : b[i * n + c];
        for (k = 0; k < i; ++k) {
            s -= l[i * n + k] * x[k * n + c];
        }
        x[i * n + c] = s / l[i * n + i];
    }
}

/* Column c of x := L^-T column c of x, in place. */
static void backward(int n, const codegen_real *l, int c, codegen_real *x)
{
    int i, k;
    for (i = n - 1; i >= 0; --i) {
        codegen_real s = x[i * n + c];
        for (k = i + 1; k < n; ++k) {
            s -= l[k * n + i] * x[k * n + c];
        }
        x[i * n + c] = s / l[i * n + i];
    }
}

/* The rotation in the plane (p, q) that zeroes a[p][q], applied to a on both sides and to
 * the columns of v. */
static void rotate(int n, codegen_real *a, codegen_real *v, int p, int q)
{
    const codegen_real apq = a[p * n + q];
    const codegen_real theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
    codegen_real t, c, s;
    int k;
    if (codegen_fabs(theta) > 1 / CODEGEN_SQRT_EPSILON) {
        t = 1 / (2 * theta); /* theta^2 would overflow or lose 1 */
    } else {
        t = codegen_copysign((codegen_real)1, theta) / (codegen_fabs(theta) + codegen_sqrt(theta * theta + 1));
    }
    c = 1 / codegen_sqrt(t * t + 1);
    s = t * c;
    for (k = 0; k < n; ++k) { /* columns p, q */
        const codegen_real akp = a[k * n + p], akq = a[k * n + q];
        a[k * n + p] = c * akp - s * akq;
        a[k * n + q] = s * akp + c * akq;
    }
    for (k = 0; k < n; ++k) { /* rows p, q */
        const codegen_real apk = a[p * n + k], aqk = a[q * n + k];
        a[p * n + k] = c * apk - s * aqk;
        a[q * n + k] = s * apk + c * aqk;
    }
    a[p * n + q] = a[q * n + p] = 0;
    for (k = 0; k < n; ++k) {
        const codegen_real vkp = v[k * n + p], vkq = v[k * n + q];
        v[k * n + p] = c * vkp - s * vkq;
        v[k * n + q] = s * vkp + c * vkq;
    }
}

/* The eigenvalues of the symmetric a (destroyed) on its diagonal, eigenvectors as the columns
 * of v. An entry is rotated away unless it is below rounding relative to its diagonal pair
 * (which keeps small eigenvalues of a graded matrix to relative accuracy). */
static int jacobi(int n, codegen_real *a, codegen_real *v)
{
    int sweep, p, q;
    for (p = 0; p < n * n; ++p) {
        v[p] = 0;
    }
    for (p = 0; p < n; ++p) {
        v[p * n + p] = 1;
    }
    for (sweep = 0; sweep < JACOBI_SWEEPS; ++sweep) {
        int rotated = 0;
        for (p = 0; p < n; ++p) {
            for (q = p + 1; q < n; ++q) {
                const codegen_real apq = codegen_fabs(a[p * n + q]);
                const codegen_real pair = codegen_sqrt(codegen_fabs(a[p * n + p])) * codegen_sqrt(codegen_fabs(a[q * n + q]));
                if (apq > CODEGEN_EPSILON * pair && apq > CODEGEN_REAL_MIN) {
                    rotate(n, a, v, p, q);
                    rotated = 1;
                } else {
                    a[p * n + q] = a[q * n + p] = 0;
                }
            }
        }
        if (!rotated) {
            return CODEGEN_MODAL_OK;
        }
    }
    return CODEGEN_MODAL_NO_CONVERGENCE;
}

/* Columns of v reordered with the values w ascending (insertion sort: n is small). */
static void sort_modes(int n, codegen_real *w, codegen_real *v)
{
    int i, j, k;
    for (i = 1; i < n; ++i) {
        for (j = i; j > 0 && w[j - 1] > w[j]; --j) {
            const codegen_real t = w[j];
            w[j] = w[j - 1];
            w[j - 1] = t;
            for (k = 0; k < n; ++k) {
                const codegen_real x = v[k * n + j];
                v[k * n + j] = v[k * n + j - 1];
                v[k * n + j - 1] = x;
            }
        }
    }
}

int codegen_modes(int n, const codegen_real *M, const codegen_real *K, codegen_real *omega_squared,
                  codegen_real *shapes, codegen_real *work)
{
    codegen_real *l, *y, *c;
    int i, j, status;
    if (n < 1 || M == NULL || K == NULL || omega_squared == NULL || shapes == NULL || work == NULL
        || !all_finite(M, n * n) || !all_finite(K, n * n)) {
        return CODEGEN_MODAL_BAD_INPUT;
    }
    l = work;
    y = work + n * n;
    c = work + 2 * n * n;
    status = cholesky(n, M, l);
    if (status != CODEGEN_MODAL_OK) {
        return status;
    }
    for (j = 0; j < n; ++j) { /* y = L^-1 K */
        forward(n, l, K, 1, j, y);
    }
    for (i = 0; i < n; ++i) { /* c = L^-1 y^T = L^-1 K L^-T, as y^T = K L^-T */
        for (j = 0; j < n; ++j) {
            c[i * n + j] = y[j * n + i];
        }
    }
    for (j = 0; j < n; ++j) {
        forward(n, l, c, 0, j, c);
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < i; ++j) {
            c[i * n + j] = c[j * n + i] = symmetric_at(c, n, i, j);
        }
    }
    status = jacobi(n, c, shapes);
    if (status != CODEGEN_MODAL_OK) {
        return status;
    }
    for (i = 0; i < n; ++i) {
        omega_squared[i] = c[i * n + i];
    }
    sort_modes(n, omega_squared, shapes);
    for (j = 0; j < n; ++j) { /* phi = L^-T x: phi^T M phi = x^T x = 1 */
        int largest = 0;
        backward(n, l, j, shapes);
        for (i = 1; i < n; ++i) {
            if (codegen_fabs(shapes[i * n + j]) > codegen_fabs(shapes[largest * n + j])) {
                largest = i;
            }
        }
        if (shapes[largest * n + j] < 0) {
            for (i = 0; i < n; ++i) {
                shapes[i * n + j] = -shapes[i * n + j];
            }
        }
    }
    return all_finite(omega_squared, n) && all_finite(shapes, n * n) ? CODEGEN_MODAL_OK
                                                                       : CODEGEN_MODAL_NOT_DEFINITE;
}

/* ---- general real eigenvalues ---- */

/* Rows and columns of a (m x m) scaled by powers of 2 until each row and column have similar
 * norms (Parlett and Reinsch): the eigenvalues are unchanged exactly, their rounding errors
 * shrink where the state matrix mixes very different magnitudes. */
static void balance(int m, codegen_real *a)
{
    int done = 0, i, j, pass;
    for (pass = 0; !done && pass < 64; ++pass) { /* converges in a few passes; 64 bounds it */
        done = 1;
        for (i = 0; i < m; ++i) {
            codegen_real column = 0, row = 0, f = 1, g, total;
            for (j = 0; j < m; ++j) {
                if (j != i) {
                    column += codegen_fabs(a[j * m + i]);
                    row += codegen_fabs(a[i * m + j]);
                }
            }
            if (column == 0 || row == 0 || !(column + row < CODEGEN_HUGE)) {
                continue;  /* nothing to balance, or a sum that overflowed (no power of 2 helps) */
            }
            total = column + row;
            g = row / 2;
            while (column < g) {
                f *= 2;
                column *= 4;
            }
            g = row * 2;
            while (column > g) {
                f /= 2;
                column /= 4;
            }
            if ((column + row) / f < CODEGEN_R(0.95) * total) {
                done = 0;
                for (j = 0; j < m; ++j) {
                    a[i * m + j] /= f;
                    a[j * m + i] *= f;
                }
            }
        }
    }
}

/* The Householder vector v (length k, v[0] set) and beta with (I - beta v v^T) x = (-+|x|, 0..);
 * beta = 0 where x is zero. */
static codegen_real householder(int k, const codegen_real *x, codegen_real *v)
{
    codegen_real scale = 0, norm = 0, vv = 0;
    int i;
    for (i = 0; i < k; ++i) {
        scale = codegen_fmax(scale, codegen_fabs(x[i]));
    }
    if (scale == 0) {
        for (i = 0; i < k; ++i) {
            v[i] = 0;
        }
        return 0;
    }
    for (i = 0; i < k; ++i) {
        v[i] = x[i] / scale;
        norm += v[i] * v[i];
    }
    v[0] += codegen_copysign(codegen_sqrt(norm), v[0]);
    for (i = 0; i < k; ++i) {
        vv += v[i] * v[i];
    }
    return 2 / vv;
}

/* Rows r0.. r0+k-1 of a (stride m), columns c0..c1: (I - beta v v^T) applied from the left. */
static void reflect_rows(codegen_real *a, int m, const codegen_real *v, codegen_real beta, int k, int r0, int c0, int c1)
{
    int i, j;
    for (j = c0; j <= c1; ++j) {
        codegen_real s = 0;
        for (i = 0; i < k; ++i) {
            s += v[i] * a[(r0 + i) * m + j];
        }
        s *= beta;
        for (i = 0; i < k; ++i) {
            a[(r0 + i) * m + j] -= s * v[i];
        }
    }
}

/* Columns c0..c0+k-1 of a, rows r0..r1: (I - beta v v^T) applied from the right. */
static void reflect_columns(codegen_real *a, int m, const codegen_real *v, codegen_real beta, int k, int c0, int r0, int r1)
{
    int i, j;
    for (i = r0; i <= r1; ++i) {
        codegen_real s = 0;
        for (j = 0; j < k; ++j) {
            s += a[i * m + c0 + j] * v[j];
        }
        s *= beta;
        for (j = 0; j < k; ++j) {
            a[i * m + c0 + j] -= s * v[j];
        }
    }
}

/* a (m x m) to upper Hessenberg form by Householder similarity transformations. */
static void hessenberg(int m, codegen_real *a, codegen_real *x, codegen_real *v)
{
    int k, i;
    for (k = 0; k + 2 < m; ++k) {
        const int len = m - k - 1;
        codegen_real beta;
        for (i = 0; i < len; ++i) {
            x[i] = a[(k + 1 + i) * m + k];
        }
        beta = householder(len, x, v);
        if (beta == 0) {
            continue;
        }
        reflect_rows(a, m, v, beta, len, k + 1, k, m - 1);
        reflect_columns(a, m, v, beta, len, k + 1, 0, m - 1);
        for (i = k + 2; i < m; ++i) {
            a[i * m + k] = 0;
        }
    }
}

/* The eigenvalues of the 2 x 2 block [[a, b], [c, d]] into re, im [0..2). */
static void block_eigenvalues(codegen_real a, codegen_real b, codegen_real c, codegen_real d, codegen_real *re,
                              codegen_real *im)
{
    const codegen_real p = CODEGEN_R(0.5) * (a - d);
    const codegen_real q = p * p + b * c;
    if (q >= 0) {
        const codegen_real z = p + codegen_copysign(codegen_sqrt(q), p);
        re[0] = d + z;
        re[1] = z != 0 ? d - b * c / z : d + z;
        im[0] = im[1] = 0;
    } else {
        re[0] = re[1] = d + p;
        im[0] = codegen_sqrt(-q);
        im[1] = -im[0];
    }
}

/* One Francis double-shift step on the active block h[lo..hi][lo..hi] (hi - lo >= 2). An
 * exceptional shift (after 10 and 20 steps without deflation) breaks cycles. */
static void francis_step(int m, codegen_real *h, int lo, int hi, int exceptional)
{
    codegen_real s, t, x, y, z, xyz[3], v[3], beta;
    int k;
    if (exceptional) {
        const codegen_real w = codegen_fabs(h[hi * m + hi - 1]) + codegen_fabs(h[(hi - 1) * m + hi - 2]);
        s = CODEGEN_R(1.5) * w;
        t = w * w;
    } else {
        s = h[(hi - 1) * m + hi - 1] + h[hi * m + hi];
        t = h[(hi - 1) * m + hi - 1] * h[hi * m + hi] - h[(hi - 1) * m + hi] * h[hi * m + hi - 1];
    }
    x = h[lo * m + lo] * h[lo * m + lo] + h[lo * m + lo + 1] * h[(lo + 1) * m + lo] - s * h[lo * m + lo] + t;
    y = h[(lo + 1) * m + lo] * (h[lo * m + lo] + h[(lo + 1) * m + lo + 1] - s);
    z = h[(lo + 1) * m + lo] * h[(lo + 2) * m + lo + 1];
    for (k = lo - 1; k + 3 <= hi; ++k) {
        const int first = k < lo ? lo : k;
        const int last = k + 4 < hi ? k + 4 : hi;
        xyz[0] = x;
        xyz[1] = y;
        xyz[2] = z;
        beta = householder(3, xyz, v);
        if (beta != 0) {
            reflect_rows(h, m, v, beta, 3, k + 1, first, hi);
            reflect_columns(h, m, v, beta, 3, k + 1, lo, last);
        }
        if (k >= lo) {
            h[(k + 2) * m + k] = h[(k + 3) * m + k] = 0;
        }
        x = h[(k + 2) * m + k + 1];
        y = h[(k + 3) * m + k + 1];
        z = k + 4 <= hi ? h[(k + 4) * m + k + 1] : 0;
    }
    xyz[0] = x;
    xyz[1] = y;
    beta = householder(2, xyz, v);
    if (beta != 0) {
        reflect_rows(h, m, v, beta, 2, hi - 1, hi - 2, hi);
        reflect_columns(h, m, v, beta, 2, hi - 1, lo, hi);
    }
    h[hi * m + hi - 2] = 0;
}

/* A subdiagonal entry that the iteration keeps at the level of rounding's square root, where
 * a multiple eigenvalue has fewer eigenvectors than its multiplicity (a critically damped
 * mode): zero, which moves the eigenvalues by about what rounding already does to such an
 * eigenvalue (sqrt(eps) relative), the smallest such entry relative to its diagonal pair. */
static void split_stagnant(int m, codegen_real *h, int lo, int hi)
{
    int k, best = -1;
    codegen_real smallest = CODEGEN_SQRT_EPSILON;
    for (k = lo + 1; k <= hi; ++k) {
        const codegen_real pair = codegen_fabs(h[(k - 1) * m + k - 1]) + codegen_fabs(h[k * m + k]);
        const codegen_real ratio = codegen_fabs(h[k * m + k - 1]) / pair;
        if (pair > 0 && ratio <= smallest) {
            smallest = ratio;
            best = k;
        }
    }
    if (best >= 0) {
        h[best * m + best - 1] = 0;
    }
}

/* The eigenvalues of the upper Hessenberg h (m x m, destroyed) into re, im. */
static int hessenberg_eigenvalues(int m, codegen_real *h, codegen_real *re, codegen_real *im)
{
    int hi = m - 1, steps = 0, budget = QR_STEPS_PER_ROW * (m > 10 ? m : 10), i;
    codegen_real norm = 0;
    for (i = 0; i < m * m; ++i) {
        norm = codegen_fmax(norm, codegen_fabs(h[i]));
    }
    while (hi >= 0) {
        int lo = hi;
        while (lo > 0) { /* the last negligible subdiagonal entry splits the matrix there */
            codegen_real s = codegen_fabs(h[(lo - 1) * m + lo - 1]) + codegen_fabs(h[lo * m + lo]);
            if (codegen_fabs(h[lo * m + lo - 1]) <= CODEGEN_EPSILON * (s != 0 ? s : norm)) {
                h[lo * m + lo - 1] = 0;
                break;
            }
            --lo;
        }
        if (lo == hi) {
            re[hi] = h[hi * m + hi];
            im[hi] = 0;
            --hi;
            steps = 0;
        } else if (lo == hi - 1) {
            block_eigenvalues(h[(hi - 1) * m + hi - 1], h[(hi - 1) * m + hi], h[hi * m + hi - 1], h[hi * m + hi],
                              re + hi - 1, im + hi - 1);
            hi -= 2;
            steps = 0;
        } else {
            if (budget-- == 0) {
                return CODEGEN_MODAL_NO_CONVERGENCE;
            }
            ++steps; /* since the last deflation: every tenth an exceptional shift */
            if (steps % STAGNATION == 0) {
                split_stagnant(m, h, lo, hi);
            }
            francis_step(m, h, lo, hi, steps % 10 == 0);
        }
    }
    return CODEGEN_MODAL_OK;
}

/* Whether eigenvalue i comes after j: ascending modulus, then imaginary part. */
static int after(const codegen_real *re, const codegen_real *im, int i, int j)
{
    const codegen_real mi = re[i] * re[i] + im[i] * im[i], mj = re[j] * re[j] + im[j] * im[j];
    return mi > mj || (mi == mj && im[i] > im[j]);
}

int codegen_damped_eigenvalues(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                               codegen_real *re, codegen_real *im, codegen_real *work)
{
    const int m = 2 * n;
    codegen_real *a, *l, *x, *v;
    int i, j, status;
    if (n < 1 || M == NULL || B == NULL || K == NULL || re == NULL || im == NULL || work == NULL
        || !all_finite(M, n * n) || !all_finite(B, n * n) || !all_finite(K, n * n)) {
        return CODEGEN_MODAL_BAD_INPUT;
    }
    a = work;
    l = work + m * m;
    x = l + n * n; /* 2n each: a column, then Householder vectors of up to 2n - 1 */
    v = x + m;
    status = cholesky(n, M, l);
    if (status != CODEGEN_MODAL_OK) {
        return status;
    }
    for (i = 0; i < m * m; ++i) {
        a[i] = 0;
    }
    for (i = 0; i < n; ++i) {
        a[i * m + n + i] = 1;
    }
    /* rows n..2n: -M^-1 K and -M^-1 B, each column solved through L and L^T (stride m) */
    for (j = 0; j < n; ++j) {
        int k;
        for (k = 0; k < 2; ++k) {
            const codegen_real *from = k == 0 ? K : B;
            for (i = 0; i < n; ++i) {
                x[i] = symmetric_at(from, n, i, j);
            }
            for (i = 0; i < n; ++i) { /* L y = column */
                int r;
                for (r = 0; r < i; ++r) {
                    x[i] -= l[i * n + r] * x[r];
                }
                x[i] /= l[i * n + i];
            }
            for (i = n - 1; i >= 0; --i) { /* L^T z = y */
                int r;
                for (r = i + 1; r < n; ++r) {
                    x[i] -= l[r * n + i] * x[r];
                }
                x[i] /= l[i * n + i];
            }
            for (i = 0; i < n; ++i) {
                a[(n + i) * m + k * n + j] = -x[i];
            }
        }
    }
    if (!all_finite(a, m * m)) {
        return CODEGEN_MODAL_NOT_DEFINITE;
    }
    balance(m, a);
    hessenberg(m, a, x, v);
    status = hessenberg_eigenvalues(m, a, re, im);
    if (status != CODEGEN_MODAL_OK) {
        return status;
    }
    for (i = 1; i < m; ++i) { /* insertion sort */
        for (j = i; j > 0 && after(re, im, j - 1, j); --j) {
            const codegen_real r = re[j], s = im[j];
            re[j] = re[j - 1];
            im[j] = im[j - 1];
            re[j - 1] = r;
            im[j - 1] = s;
        }
    }
    return CODEGEN_MODAL_OK;
}

/* ---- receptance ---- */

int codegen_receptance(int n, const codegen_real *M, const codegen_real *B, const codegen_real *K,
                       codegen_real omega, codegen_real *H_re, codegen_real *H_im, codegen_real *work)
{
    /* [[D_re, -D_im], [D_im, D_re]] [X_re; X_im] = [I; 0], D = K - omega^2 M + i omega B, as
     * one real system of 2n rows and 3n columns, by Gauss-Jordan elimination with partial
     * pivoting */
    const int rows = 2 * n, cols = 3 * n;
    codegen_real *a = work;
    int i, j, k;
    if (n < 1 || M == NULL || B == NULL || K == NULL || H_re == NULL || H_im == NULL || work == NULL
        || !isfinite(omega) || !all_finite(M, n * n) || !all_finite(B, n * n) || !all_finite(K, n * n)) {
        return CODEGEN_MODAL_BAD_INPUT;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            const codegen_real d_re = symmetric_at(K, n, i, j) - omega * omega * symmetric_at(M, n, i, j);
            const codegen_real d_im = omega * symmetric_at(B, n, i, j);
            a[i * cols + j] = d_re;
            a[i * cols + n + j] = -d_im;
            a[(n + i) * cols + j] = d_im;
            a[(n + i) * cols + n + j] = d_re;
            a[i * cols + 2 * n + j] = i == j ? 1 : 0;
            a[(n + i) * cols + 2 * n + j] = 0;
        }
    }
    for (k = 0; k < rows; ++k) {
        int pivot = k;
        codegen_real p;
        for (i = k + 1; i < rows; ++i) {
            if (codegen_fabs(a[i * cols + k]) > codegen_fabs(a[pivot * cols + k])) {
                pivot = i;
            }
        }
        if (pivot != k) {
            for (j = k; j < cols; ++j) {
                const codegen_real t = a[k * cols + j];
                a[k * cols + j] = a[pivot * cols + j];
                a[pivot * cols + j] = t;
            }
        }
        p = a[k * cols + k];
        if (p == 0) {
            return CODEGEN_MODAL_SINGULAR;
        }
        for (j = k; j < cols; ++j) {
            a[k * cols + j] /= p;
        }
        for (i = 0; i < rows; ++i) {
            const codegen_real f = a[i * cols + k];
            if (i == k || f == 0) {
                continue;
            }
            for (j = k; j < cols; ++j) {
                a[i * cols + j] -= f * a[k * cols + j];
            }
        }
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            H_re[i * n + j] = a[i * cols + 2 * n + j];
            H_im[i * n + j] = a[(n + i) * cols + 2 * n + j];
        }
    }
    return all_finite(H_re, n * n) && all_finite(H_im, n * n) ? CODEGEN_MODAL_OK : CODEGEN_MODAL_SINGULAR;
}
