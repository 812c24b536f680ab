/* Nonholonomic RATTLE on the Chaplygin sleigh written by hand in C: the yardstick for nhlab's
 * `rattle` on the built-in `chaplygin_sleigh` and on the sleigh given as formulas
 * (`bench/sleigh_ratio.py` runs all three and compares them, speed and trajectory).
 *
 * The same equations as core/src/methods/rattle.rs (McLachlan & Perlmutter 2006, (4.18)), in
 * momenta p = M q̇:
 *   q½ = q0 + h/2 M⁻¹p0,   p1 = p0 − h∇V(q½) + h A(q½)ᵀλ,   q1 = q½ + h/2 M⁻¹p1,
 *   A(q1) M⁻¹p1 = 0,
 * solved by Newton in (p1, λ) with the exact Jacobian, from the same guess (λ from the last
 * step) and with the same stopping rule as core/src/solver/newton.rs: max-norm increment
 * ≤ 1e-14 (1 + max|unknowns|), or Newton's estimate of the error it leaves ≤ 1e-14 (…) once
 * the increment is ≤ 1e-6 (…), or a stagnating increment ≤ 1e-10 (…); at most 20 iterations.
 * q advances by Kahan's compensated sum, as nhlab's states do. M⁻¹ is multiplied in by
 * reciprocals (nhlab divides; with the preset's unit masses the numbers are the same).
 *
 * Sleigh: q = (x, y, θ), M = diag(m, m, I), V = m g y, A = [−sin θ, cos θ, −a]; the
 * `inclined` preset: m = I = a = 1, g = 0.1, q0 = 0, q̇0 = (0, 1, 1), h = 0.1.
 *
 *   gcc -O2 -o target/rattle_sleigh bench/rattle_sleigh.c -lm
 *   target/rattle_sleigh STEPS [RESTART]
 *
 * takes STEPS steps, from the preset's start again every RESTART steps if given (as
 * `step_loop`'s RESTART: the inclined sleigh slides away, and Newton's iterations per step
 * fall from 1.7 over the preset's t = 100 to 1.0 later), and prints the final q and q̇
 * (%.17g) and the constraint's residual. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double m = 1.0, inertia = 1.0, a = 1.0, g = 0.1, h = 0.1;

/* max of two numbers, inlined (fmax is a call into libm at -O2); a NaN it drops leaves every
 * later iterate NaN, and Newton fails after 20 iterations */
static inline double max2(double x, double y) { return x > y ? x : y; }

static double amax3(const double x[3]) {
    return max2(fabs(x[0]), max2(fabs(x[1]), fabs(x[2])));
}

/* One step from (q, v, λ); returns 0, or 1 when Newton fails. */
static int step(double q[3], double qc[3], double v[3], double *lambda) {
    const double minv[3] = {1.0 / m, 1.0 / m, 1.0 / inertia};
    const double grad[3] = {0.0, m * g, 0.0};
    double p0[3] = {m * v[0], m * v[1], inertia * v[2]}, qh[3], p1[3], gv[3];
    for (int i = 0; i < 3; i++) qh[i] = q[i] + 0.5 * h * (p0[i] * minv[i]);
    double sh = sin(qh[2]), ch = cos(qh[2]);
    const double ah[3] = {-sh, ch, -a};
    double lam = *lambda;
    for (int i = 0; i < 3; i++) {
        gv[i] = -h * ah[i]; /* ∂f1/∂λ */
        p1[i] = p0[i] - h * grad[i] + h * (ah[i] * lam);
    }
    double previous = INFINITY;
    for (int it = 1; it <= 20; it++) {
        double v1[3], f1[3], c[3];
        for (int i = 0; i < 3; i++) v1[i] = p1[i] * minv[i];
        double th1 = qh[2] + 0.5 * h * v1[2];
        double s1 = sin(th1), c1 = cos(th1);
        const double a1[3] = {-s1, c1, -a};
        for (int i = 0; i < 3; i++) f1[i] = p1[i] - p0[i] + h * grad[i] + gv[i] * lam;
        double f2 = a1[0] * v1[0] + a1[1] * v1[1] + a1[2] * v1[2];
        /* ∂f2/∂p1 = (A(q1) + h/2 ∂(A(q1) v1)/∂q) M⁻¹; only ∂A/∂θ = [−cos θ, −sin θ, 0] */
        c[0] = a1[0] * minv[0];
        c[1] = a1[1] * minv[1];
        c[2] = (a1[2] + 0.5 * h * (-c1 * v1[0] - s1 * v1[1])) * minv[2];
        /* ∂f1/∂p1 = I: Schur complement c·gv */
        double cg = c[0] * gv[0] + c[1] * gv[1] + c[2] * gv[2];
        double cf = c[0] * f1[0] + c[1] * f1[1] + c[2] * f1[2];
        double dlam = (f2 - cf) / cg, dp[3];
        for (int i = 0; i < 3; i++) {
            dp[i] = -(f1[i] + gv[i] * dlam);
            p1[i] += dp[i];
        }
        lam += dlam;
        double inc = max2(amax3(dp), fabs(dlam));
        if (!isfinite(inc)) return 1;
        double scale = 1.0 + max2(amax3(p1), fabs(lam));
        double left = isfinite(previous) ? inc * (inc / previous) * (inc / previous) : inc * inc;
        if (inc <= 1e-14 * scale || (inc <= 1e-6 * scale && left <= 1e-14 * scale) ||
            (inc <= 1e-10 * scale && inc >= 0.5 * previous)) {
            for (int i = 0; i < 3; i++) {
                double v1i = p1[i] * minv[i];
                double d = 0.5 * h * (v[i] + v1i) + qc[i]; /* Kahan */
                double sum = q[i] + d;
                qc[i] = (q[i] - sum) + d;
                q[i] = sum;
                v[i] = v1i;
            }
            *lambda = lam;
            return 0;
        }
        previous = inc;
    }
    return 1;
}

/* The preset's start, λ the continuous multiplier, (A M⁻¹ Aᵀ) λ = A M⁻¹∇V − (∂(A q̇)/∂q) q̇. */
static void start(double q[3], double qc[3], double v[3], double *lambda) {
    for (int i = 0; i < 3; i++) q[i] = qc[i] = 0.0;
    v[0] = 0.0, v[1] = 1.0, v[2] = 1.0;
    double s = sin(q[2]), c = cos(q[2]);
    *lambda = (c * g + v[2] * (c * v[0] + s * v[1])) / (1.0 / m + a * a / inertia);
}

int main(int argc, char **argv) {
    long n = argc > 1 ? atol(argv[1]) : 3000000, restart = argc > 2 ? atol(argv[2]) : 0;
    double q[3], qc[3], v[3], lambda;
    start(q, qc, v, &lambda);
    for (long k = 0; k < n; k++) {
        if (restart > 0 && k > 0 && k % restart == 0) start(q, qc, v, &lambda);
        if (step(q, qc, v, &lambda)) {
            fprintf(stderr, "Newton failed at step %ld\n", k);
            return 1;
        }
    }
    double residual = -sin(q[2]) * v[0] + cos(q[2]) * v[1] - a * v[2];
    printf("q = [%.17g, %.17g, %.17g]\nv = [%.17g, %.17g, %.17g]\nresidual %.3g\n", q[0], q[1],
           q[2], v[0], v[1], v[2], residual);
    return 0;
}
