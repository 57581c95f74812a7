// SPDX-License-Identifier: MIT
#pragma once
/// @file krylov.hpp  Deterministic vector kernels and preconditioned conjugate gradients (internal),
/// shared by the voxel multigrid solver and the assembled-matrix AMG solver.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"

namespace fabsynth::fem::detail {

/// Deterministic dot product over n entries (block boundaries independent of the thread count).
[[nodiscard]] inline double dot(const std::vector<double>& a, const std::vector<double>& b) {
    return parallel_reduce(
        0, a.size(), 0.0, [&](std::size_t i) { return a[i] * b[i]; }, [](double s, double t) { return s + t; },
        {.grain = 8192});
}

/// Work vectors of chebyshev_smooth (sized on use).
struct chebyshev_work {
    std::vector<double> r, d, Ad;
};

/// Chebyshev polynomial smoothing of A x = b preconditioned by the diagonal: degree `degree`,
/// aimed at the eigenvalues of D^-1 A in [lambda_max / range, lambda_max] (the same polynomial
/// before and after a coarse correction keeps a V-cycle symmetric). x is taken as 0 on entry when
/// zero_start. `apply(v, y)` computes y = A v; unknowns with keep(i) false stay untouched (fixed
/// DOFs of the voxel path).
template <class Apply, class Keep>
void chebyshev_smooth(Apply&& apply, const std::vector<double>& inv_diag, double lambda_max, double range, int degree,
                      const std::vector<double>& b, std::vector<double>& x, bool zero_start, chebyshev_work& w, Keep&& keep) {
    const double hi = lambda_max, lo = hi / range;
    const double theta = 0.5 * (hi + lo), delta = 0.5 * (hi - lo), sigma = theta / delta;
    double rho = 1.0 / sigma;
    const std::size_t n = b.size();
    constexpr parallel_options vec{.grain = 16384};
    w.r.resize(n), w.d.resize(n), w.Ad.resize(n);
    if (zero_start) {
        w.r = b;
    } else {
        apply(x, w.r);
        parallel_for(0, n, [&](std::size_t i) { w.r[i] = keep(i) ? b[i] - w.r[i] : 0.0; }, vec);
    }
    parallel_for(0, n, [&](std::size_t i) { w.d[i] = keep(i) ? inv_diag[i] * w.r[i] / theta : 0.0; }, vec);
    for (int k = 0; k < degree; ++k) {
        parallel_for(0, n, [&](std::size_t i) { x[i] += w.d[i]; }, vec);
        if (k + 1 == degree) break;
        apply(w.d, w.Ad);
        const double rho_new = 1.0 / (2.0 * sigma - rho);
        parallel_for(0, n, [&](std::size_t i) {
            w.r[i] = keep(i) ? w.r[i] - w.Ad[i] : 0.0;
            w.d[i] = keep(i) ? rho_new * rho * w.d[i] + 2.0 * rho_new / delta * inv_diag[i] * w.r[i] : 0.0;
        }, vec);
        rho = rho_new;
    }
}

/// Result of a preconditioned CG run.
struct pcg_report {
    int iterations = 0;
    double relative_residual = 0;
    bool converged = false;
};

/// Preconditioned conjugate gradients on A x = b (x holds the start and the result). Stops when
/// ||r|| <= tol ||b||; `what` prefixes error messages. `apply(x, y)` computes y = A x; `prec(r, z)` computes z = M^-1 r.
/// `on_iteration(it, rel)` is called after each iteration (progress reporting).
template <class Apply, class Prec, class OnIt>
pcg_report pcg(const char* what, Apply&& apply, Prec&& prec, const std::vector<double>& b, std::vector<double>& x, double tol, int max_it, OnIt&& on_iteration) {
    const std::size_t n = b.size();
    std::vector<double> r(n), z(n), p(n), q(n);
    apply(x, q);
    for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - q[i];
    const double bnorm = std::sqrt(dot(b, b));
    pcg_report rep;
    if (!std::isfinite(bnorm)) throw solver_error(std::string(what) + ": the load vector is not finite");
    if (bnorm == 0.0) {
        std::fill(x.begin(), x.end(), 0.0);
        rep.converged = true;
        return rep;
    }
    double rnorm = std::sqrt(dot(r, r));
    prec(r, z);
    p = z;
    double rz = dot(r, z);
    for (int it = 0; it < max_it; ++it) {
        rep.relative_residual = rnorm / bnorm;
        if (rep.relative_residual <= tol) {
            rep.converged = true;
            return rep;
        }
        apply(p, q);
        const double pq = dot(p, q);
        if (!(pq > 0) || !std::isfinite(rz))
            throw solver_error(std::string(what) + ": CG broke down at iteration " + std::to_string(it) +
                               " (the stiffness matrix is singular or indefinite: is every solid part supported?)");
        const double alpha = rz / pq;
        parallel_for(0, n, [&](std::size_t i) { x[i] += alpha * p[i], r[i] -= alpha * q[i]; }, {.grain = 16384});
        rnorm = std::sqrt(dot(r, r));
        prec(r, z);
        const double rz_new = dot(r, z);
        const double beta = rz_new / rz;
        rz = rz_new;
        parallel_for(0, n, [&](std::size_t i) { p[i] = z[i] + beta * p[i]; }, {.grain = 16384});
        rep.iterations = it + 1;
        on_iteration(rep.iterations, rnorm / bnorm);
    }
    rep.relative_residual = rnorm / bnorm;
    rep.converged = rep.relative_residual <= tol;
    return rep;
}

}  // namespace fabsynth::fem::detail
