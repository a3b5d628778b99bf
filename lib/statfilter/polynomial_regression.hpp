// Least-squares polynomial fits of time series, the same design for every series: time is scaled to
// [-1, 1] (never raw frame numbers, whose Vandermonde matrix is hopelessly ill-conditioned) and the
// design is factored once into an orthonormal polynomial basis, so the fits of every degree 0..D of
// any number of series come from one projection.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace statfilter {

// Frame f of F at scaled time -1 + 2 f / (F - 1); 0 for a single frame.
double scaled_time(int64_t frame, int64_t frames);

// Columns 0..degree of Q (frames x (degree + 1), row-major) are orthonormal and column d is a
// polynomial of degree d in scaled time, so columns 0..d span every polynomial of degree <= d.
// Built by "Vandermonde with Arnoldi": each column is t times the previous one, orthogonalised
// twice against all earlier columns and normalised. Q stays orthonormal to rounding for any degree
// up to frames - 1, where a monomial basis, even in scaled time, has lost most of its digits.
struct PolynomialBasis {
    int64_t frames = 0, degree = 0;
    std::vector<double> q;
    int64_t columns() const { return degree + 1; }
    double at(int64_t frame, int64_t d) const { return q[static_cast<size_t>(frame * (degree + 1) + d)]; }
};

// Throws Error(InvalidArgument) unless frames >= 1 and 0 <= degree <= frames - 1 (a degree-D fit
// needs D + 1 frames).
PolynomialBasis polynomial_basis(int64_t frames, int64_t degree);

enum class TimeAxis {
    FrameNumber,  // t = 1, 2, ..., F: what a naive fit uses
    Scaled,       // t in [-1, 1]
};

// The monomial design matrix, frames x (degree + 1) row-major: column d is t^d.
std::vector<double> vandermonde(int64_t frames, int64_t degree, TimeAxis axis);

// 2-norm condition number sigma_max / sigma_min of a rows x cols row-major matrix (LAPACK dgesvd);
// infinity when the smallest singular value is zero.
double condition_number(const std::vector<double>& matrix, int64_t rows, int64_t cols);

// Least squares with any design matrix (rows x cols, row-major) for n right-hand sides at once, by
// Householder QR (LAPACK dgels): rhs is rows x n (row-major); returns the cols x n solution.
std::vector<double> least_squares_qr(std::vector<double> design, int64_t rows, int64_t cols, std::vector<double> rhs,
                                     int64_t n);

// Coefficients ((degree + 1) x n, row-major) of n series (frames x n, row-major: series j in column
// j) in the basis: Q^T series.
std::vector<double> project(const PolynomialBasis& basis, const double* series, int64_t n);

// The degree-d fit (frames x n) of n series from their coefficients.
std::vector<double> fit_of_degree(const PolynomialBasis& basis, const std::vector<double>& coefficients, int64_t n,
                                  int64_t degree);

// The study's degree rule, for groups of `group` consecutive series (e.g. a pixel's channels):
// group g gets the smallest degree d <= basis.degree whose mean absolute residual, over the frames
// and the group's series, is below tolerance[g]; basis.degree + 1 when no degree is. fit (frames x
// n) receives every series' fit at its group's degree (the degree-basis.degree fit for groups no
// degree explains). n must be a multiple of group.
struct DegreeChoice {
    std::vector<int64_t> degrees;  // one per group
    std::vector<double> fit;       // frames x n
};
DegreeChoice choose_degrees(const PolynomialBasis& basis, const double* series, int64_t n, int64_t group,
                            const double* tolerance);

}  // namespace statfilter
