#include "statfilter/polynomial_regression.hpp"

#include <cblas.h>
#include <lapacke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "statfilter/error.hpp"

namespace statfilter {

double scaled_time(int64_t frame, int64_t frames) {
    if (frames <= 1) return 0.0;
    return -1.0 + 2.0 * static_cast<double>(frame) / static_cast<double>(frames - 1);
}

PolynomialBasis polynomial_basis(int64_t frames, int64_t degree) {
    if (frames < 1) throw Error(Status::InvalidArgument, "a polynomial fit needs at least one frame");
    if (degree < 0) throw Error(Status::InvalidArgument, "polynomial degree " + std::to_string(degree) + " is negative");
    if (degree > frames - 1)
        throw Error(Status::InvalidArgument, "polynomial degree " + std::to_string(degree) + " needs at least " +
                                                 std::to_string(degree + 1) + " frames; the sequence has " +
                                                 std::to_string(frames) + " (use degree <= " +
                                                 std::to_string(frames - 1) + ")");
    PolynomialBasis b;
    b.frames = frames;
    b.degree = degree;
    const int64_t K = degree + 1;
    b.q.assign(static_cast<size_t>(frames * K), 0.0);
    auto q = [&](int64_t f, int64_t d) -> double& { return b.q[static_cast<size_t>(f * K + d)]; };
    const double c0 = 1.0 / std::sqrt(static_cast<double>(frames));
    for (int64_t f = 0; f < frames; ++f) q(f, 0) = c0;
    std::vector<double> v(static_cast<size_t>(frames));
    for (int64_t d = 1; d < K; ++d) {
        for (int64_t f = 0; f < frames; ++f) v[f] = scaled_time(f, frames) * q(f, d - 1);
        // Two passes of modified Gram-Schmidt against every earlier column ("twice is enough").
        for (int pass = 0; pass < 2; ++pass)
            for (int64_t k = 0; k < d; ++k) {
                double dot = 0;
                for (int64_t f = 0; f < frames; ++f) dot += q(f, k) * v[f];
                for (int64_t f = 0; f < frames; ++f) v[f] -= dot * q(f, k);
            }
        double norm = 0;
        for (double x : v) norm += x * x;
        norm = std::sqrt(norm);
        if (!(norm > 0)) throw Error(Status::Numeric, "polynomial basis lost rank at degree " + std::to_string(d));
        for (int64_t f = 0; f < frames; ++f) q(f, d) = v[f] / norm;
    }
    return b;
}

std::vector<double> vandermonde(int64_t frames, int64_t degree, TimeAxis axis) {
    const int64_t K = degree + 1;
    std::vector<double> a(static_cast<size_t>(frames * K));
    for (int64_t f = 0; f < frames; ++f) {
        const double t = axis == TimeAxis::Scaled ? scaled_time(f, frames) : static_cast<double>(f + 1);
        double p = 1.0;
        for (int64_t d = 0; d < K; ++d) {
            a[static_cast<size_t>(f * K + d)] = p;
            p *= t;
        }
    }
    return a;
}

double condition_number(const std::vector<double>& matrix, int64_t rows, int64_t cols) {
    std::vector<double> a = matrix;
    const int64_t k = std::min(rows, cols);
    std::vector<double> s(static_cast<size_t>(k)), superb(static_cast<size_t>(std::max<int64_t>(k, 2)));
    const lapack_int info = LAPACKE_dgesvd(LAPACK_ROW_MAJOR, 'N', 'N', static_cast<lapack_int>(rows),
                                           static_cast<lapack_int>(cols), a.data(), static_cast<lapack_int>(cols),
                                           s.data(), nullptr, 1, nullptr, 1, superb.data());
    if (info != 0) throw Error(Status::Numeric, "singular values failed (LAPACK dgesvd info " + std::to_string(info) + ")");
    if (k == 0) return 1.0;
    if (!(s[static_cast<size_t>(k - 1)] > 0)) return std::numeric_limits<double>::infinity();
    return s[0] / s[static_cast<size_t>(k - 1)];
}

std::vector<double> least_squares_qr(std::vector<double> design, int64_t rows, int64_t cols, std::vector<double> rhs,
                                     int64_t n) {
    if (rows < cols) throw Error(Status::InvalidArgument, "least squares needs at least as many rows as columns");
    const lapack_int info = LAPACKE_dgels(LAPACK_ROW_MAJOR, 'N', static_cast<lapack_int>(rows),
                                          static_cast<lapack_int>(cols), static_cast<lapack_int>(n), design.data(),
                                          static_cast<lapack_int>(cols), rhs.data(), static_cast<lapack_int>(n));
    if (info != 0)
        throw Error(Status::Numeric, "least squares failed (LAPACK dgels info " + std::to_string(info) +
                                         (info > 0 ? ": the design matrix is rank deficient)" : ")"));
    rhs.resize(static_cast<size_t>(cols * n));
    return rhs;
}

std::vector<double> project(const PolynomialBasis& basis, const double* series, int64_t n) {
    const int64_t F = basis.frames, K = basis.columns();
    std::vector<double> c(static_cast<size_t>(K * n), 0.0);
    if (n == 0) return c;
    // c (K x n) = Q^T (K x F) * series (F x n)
    cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, static_cast<int>(K), static_cast<int>(n), static_cast<int>(F), 1.0,
                basis.q.data(), static_cast<int>(K), series, static_cast<int>(n), 0.0, c.data(), static_cast<int>(n));
    return c;
}

std::vector<double> fit_of_degree(const PolynomialBasis& basis, const std::vector<double>& coefficients, int64_t n,
                                  int64_t degree) {
    const int64_t F = basis.frames, K = basis.columns();
    if (degree < 0 || degree > basis.degree)
        throw Error(Status::InvalidArgument, "degree " + std::to_string(degree) + " outside the basis (0.." +
                                                 std::to_string(basis.degree) + ")");
    std::vector<double> fit(static_cast<size_t>(F * n), 0.0);
    if (n == 0) return fit;
    // fit (F x n) = Q[:, 0..degree] (F x (degree+1)) * c[0..degree, :]
    cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(F), static_cast<int>(n),
                static_cast<int>(degree + 1), 1.0, basis.q.data(), static_cast<int>(K), coefficients.data(),
                static_cast<int>(n), 0.0, fit.data(), static_cast<int>(n));
    return fit;
}

DegreeChoice choose_degrees(const PolynomialBasis& basis, const double* series, int64_t n, int64_t group,
                            const double* tolerance) {
    const int64_t F = basis.frames, D = basis.degree;
    if (group < 1 || n % group != 0)
        throw Error(Status::InvalidArgument, "series count is not a multiple of the group size");
    const int64_t groups = n / group;
    const std::vector<double> c = project(basis, series, n);
    // residual = series - fit of the current degree, lowered one degree at a time.
    std::vector<double> residual(series, series + F * n);
    DegreeChoice out;
    out.degrees.assign(static_cast<size_t>(groups), D + 1);
    out.fit.assign(static_cast<size_t>(F * n), 0.0);
    std::vector<char> done(static_cast<size_t>(groups), 0);
    std::vector<double> mar(static_cast<size_t>(groups));
    int64_t remaining = groups;
    const double scale = 1.0 / static_cast<double>(F * group);
    for (int64_t d = 0; d <= D && remaining > 0; ++d) {
        const double* cd = &c[static_cast<size_t>(d * n)];
        std::fill(mar.begin(), mar.end(), 0.0);
        for (int64_t f = 0; f < F; ++f) {
            const double qf = basis.at(f, d);
            double* r = &residual[static_cast<size_t>(f * n)];
            for (int64_t j = 0; j < n; ++j) {
                r[j] -= qf * cd[j];
                mar[static_cast<size_t>(j / group)] += std::fabs(r[j]);
            }
        }
        for (int64_t g = 0; g < groups; ++g) {
            if (done[g] || !(mar[g] * scale < tolerance[g])) continue;
            done[g] = 1;
            --remaining;
            out.degrees[g] = d;
            for (int64_t f = 0; f < F; ++f)
                for (int64_t j = g * group; j < (g + 1) * group; ++j)
                    out.fit[static_cast<size_t>(f * n + j)] = series[f * n + j] - residual[static_cast<size_t>(f * n + j)];
        }
    }
    // Groups no degree explains keep the highest-degree fit.
    for (int64_t g = 0; g < groups; ++g) {
        if (done[g]) continue;
        for (int64_t f = 0; f < F; ++f)
            for (int64_t j = g * group; j < (g + 1) * group; ++j)
                out.fit[static_cast<size_t>(f * n + j)] = series[f * n + j] - residual[static_cast<size_t>(f * n + j)];
    }
    return out;
}

}  // namespace statfilter
