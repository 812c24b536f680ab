/* A hand-written C nonholonomic leap-frog on cvt_pendulum (docs/model.md §3), for scale against
 * nhlab's generic one (criterion: step/cvt_pendulum/LF). Same preset (oscillating, ε = 0),
 * same h = 0.1, same formulas; no integrals, no observer.
 *   gcc -O3 -march=native -o target/leapfrog bench/leapfrog.c -lm && target/leapfrog */
#include <math.h>
#include <stdio.h>
#include <time.h>

int main(void) {
    const double h = 0.1, eps = 0.0;
    const long n = 30000000;
    double x1 = 1, x2 = 1, z = 0, v1 = 0, v2 = 0, vz = 1.8973666, lam = 0;
    /* continuous multiplier at the start: A A^T λ = A∇V − Ȧ q̇ */
    {
        double s = sin(z), c = cos(z);
        lam = (x1 + s * x2 - c * vz * v2) / (1 + s * s);
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (long k = 0; k < n; k++) {
        double s = sin(z), c = cos(z);
        double g1 = x1, g2 = x2, gz = s - eps * (c * c - s * s);
        double h1 = v1 + 0.5 * h * (lam - g1);
        double h2 = v2 + 0.5 * h * (s * lam - g2);
        double hz = vz - 0.5 * h * gz;
        x1 += h * h1; x2 += h * h2; z += h * hz;
        s = sin(z); c = cos(z);
        double w1 = h1 - 0.5 * h * x1, w2 = h2 - 0.5 * h * x2;
        double wz = hz - 0.5 * h * (s - eps * (c * c - s * s));
        lam = -2.0 / h * (w1 + s * w2) / (1 + s * s);
        v1 = w1 + 0.5 * h * lam; v2 = w2 + 0.5 * h * s * lam; vz = wz;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double ns = ((t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec)) / n;
    printf("C leap-frog on cvt_pendulum: %.1f ns/step (x = %g %g %g)\n", ns, x1, x2, z);
    return 0;
}
