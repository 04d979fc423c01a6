/* src/rotation.c - quaternion, DCM and Rodrigues kernels (rotation.h). */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "rotation.h"

#include "igea/envfun.h"

void igea__cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

void igea__quat_dcm(const double *q, double *C)
{
    double a = q[0], b = q[1], c = q[2], d = q[3];
    C[0] = a * a + b * b - c * c - d * d;
    C[1] = 2.0 * (b * c - a * d);
    C[2] = 2.0 * (b * d + a * c);
    C[3] = 2.0 * (b * c + a * d);
    C[4] = a * a - b * b + c * c - d * d;
    C[5] = 2.0 * (c * d - a * b);
    C[6] = 2.0 * (b * d - a * c);
    C[7] = 2.0 * (c * d + a * b);
    C[8] = a * a - b * b - c * c + d * d;
}

void igea__quat_dcm_unit(const double *q, double *C)
{
    double u[4], n = 0.0;
    for (int i = 0; i < 4; i++)
        n += q[i] * q[i];
    n = sqrt(n);
    for (int i = 0; i < 4; i++)
        u[i] = q[i] / n;
    igea__quat_dcm(u, C);
}

void igea__quat_rotate(double *q, const double *v)
{
    double a = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double c = cos(0.5 * a), s = a > 0 ? sin(0.5 * a) / a : 0.5;
    double d[4] = {c, s * v[0], s * v[1], s * v[2]}, r[4], n;
    r[0] = q[0] * d[0] - q[1] * d[1] - q[2] * d[2] - q[3] * d[3];
    r[1] = q[0] * d[1] + q[1] * d[0] + q[2] * d[3] - q[3] * d[2];
    r[2] = q[0] * d[2] - q[1] * d[3] + q[2] * d[0] + q[3] * d[1];
    r[3] = q[0] * d[3] + q[1] * d[2] - q[2] * d[1] + q[3] * d[0];
    n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    for (int i = 0; i < 4; i++)
        q[i] = r[i] / n;
}

void igea__m3_mul(const double *a, const double *b, double *c)
{
    double t[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            t[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] +
                           a[3 * i + 2] * b[6 + j];
    memcpy(c, t, sizeof t);
}

void igea__m3_vec(const double *a, const double *x, double *y, int trans)
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = trans ? a[i] * x[0] + a[3 + i] * x[1] + a[6 + i] * x[2]
                     : a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2];
    memcpy(y, t, sizeof t);
}

void igea__m3_exp(const double *v, double *R)
{
    double a = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double s = a > 1e-8 ? sin(a) / a : 1.0 - a * a / 6.0;
    double c = a > 1e-8 ? (1.0 - cos(a)) / (a * a) : 0.5 - a * a / 24.0;
    double K[9] = {0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0}, K2[9];
    igea__m3_mul(K, K, K2);
    for (int i = 0; i < 9; i++)
        R[i] = (i % 4 == 0 ? 1.0 : 0.0) + s * K[i] + c * K2[i];
}

int igea__traj_args(int system, int nsamp, const double *traj, int ldt)
{
    if (system != IGEA_ENVFUN_STRAPDOWN && system != IGEA_ENVFUN_PLATFORM)
        return -1;
    if (nsamp < 2)
        return -2;
    if (!traj)
        return -3;
    if (ldt < nsamp)
        return -4;
    return 0;
}

int igea__traj_times(int nsamp, const double *traj, int ldt, int nepochs,
                     const double *epochs)
{
    for (int k = 1; k < nsamp; k++)
        if (!(IGEA_AT(traj, ldt, k, 0) > IGEA_AT(traj, ldt, k - 1, 0)))
            return 1;
    for (int e = 0; e < nepochs; e++)
        if (epochs[e] < IGEA_AT(traj, ldt, 0, 0) ||
            epochs[e] > IGEA_AT(traj, ldt, nsamp - 1, 0) ||
            (e > 0 && epochs[e] < epochs[e - 1]))
            return 2;
    return 0;
}

double igea__traj_qnorm2(const double *traj, int ldt, int k)
{
    double nq = 0.0;
    for (int i = 0; i < 4; i++)
        nq += IGEA_AT(traj, ldt, k, 7 + i) * IGEA_AT(traj, ldt, k, 7 + i);
    return nq;
}
