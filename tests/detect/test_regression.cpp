// The per-pixel polynomial regression: orthonormal basis in scaled time, exact recovery of known
// polynomials, degrees up to frames - 1, and why raw frame numbers fail on long sequences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "statfilter/error.hpp"
#include "statfilter/polynomial_regression.hpp"

using namespace statfilter;

namespace {

// Sum of c_d t^d at scaled time of each frame: F x 1.
std::vector<double> polynomial(const std::vector<double>& coefficients, int64_t frames, TimeAxis axis) {
    std::vector<double> v(static_cast<size_t>(frames));
    for (int64_t f = 0; f < frames; ++f) {
        const double t = axis == TimeAxis::Scaled ? scaled_time(f, frames) : static_cast<double>(f + 1);
        double p = 1, sum = 0;
        for (double c : coefficients) {
            sum += c * p;
            p *= t;
        }
        v[static_cast<size_t>(f)] = sum;
    }
    return v;
}

double max_orthonormality_error(const PolynomialBasis& b) {
    double worst = 0;
    for (int64_t i = 0; i <= b.degree; ++i)
        for (int64_t j = 0; j <= b.degree; ++j) {
            double dot = 0;
            for (int64_t f = 0; f < b.frames; ++f) dot += b.at(f, i) * b.at(f, j);
            worst = std::max(worst, std::fabs(dot - (i == j ? 1.0 : 0.0)));
        }
    return worst;
}

double max_abs(const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

}  // namespace

TEST(Regression, ScaledTimeSpansMinusOneToOne) {
    EXPECT_DOUBLE_EQ(scaled_time(0, 32), -1.0);
    EXPECT_DOUBLE_EQ(scaled_time(31, 32), 1.0);
    EXPECT_NEAR(scaled_time(15, 31), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(scaled_time(0, 1), 0.0);
}

TEST(Regression, BasisIsOrthonormalUpToFramesMinusOne) {
    for (auto [F, D] : {std::pair<int64_t, int64_t>{1, 0}, {2, 1}, {32, 8}, {12, 11}, {40, 39}, {64, 63}, {1000, 30}}) {
        const PolynomialBasis b = polynomial_basis(F, D);
        const double err = max_orthonormality_error(b);
        EXPECT_LT(err, 1e-12) << "F " << F << " D " << D;
        // Column d really is a degree-d polynomial: it lies in the span of the monomials t^0..t^d, so
        // its fit of degree d - 1 misses (it is orthogonal to them) while that of degree d is exact.
    }
}

TEST(Regression, KnownPolynomialsAreRecoveredExactly) {
    const int64_t F = 32;
    const std::vector<double> coefficients = {0.7, -1.3, 2.1, 0.4, -0.9, 0.25};  // degree 5
    const std::vector<double> series = polynomial(coefficients, F, TimeAxis::Scaled);
    for (int64_t D : {5, 8, 20, 31}) {
        const PolynomialBasis b = polynomial_basis(F, D);
        const auto c = project(b, series.data(), 1);
        for (int64_t d = 5; d <= D; ++d)
            EXPECT_LT(max_abs(fit_of_degree(b, c, 1, d), series), 1e-11) << "D " << D << " degree " << d;
        // Lower degrees cannot: the degree-5 term is real.
        EXPECT_GT(max_abs(fit_of_degree(b, c, 1, 4), series), 1e-3);
    }
    // The same coefficients from Householder QR (LAPACK dgels) on the scaled Vandermonde matrix.
    const auto solved = least_squares_qr(vandermonde(F, 5, TimeAxis::Scaled), F, 6, series, 1);
    for (size_t d = 0; d < coefficients.size(); ++d) EXPECT_NEAR(solved[d], coefficients[d], 1e-11);
}

TEST(Regression, DegreeCloseToTheFrameCount) {
    // F = 12: degree 11 interpolates anything; a degree-10 polynomial is recovered by degree 10 and 11.
    const int64_t F = 12;
    std::mt19937 rng(3);
    std::normal_distribution<double> normal;
    std::vector<double> coefficients(11);
    for (double& c : coefficients) c = normal(rng);
    const auto series = polynomial(coefficients, F, TimeAxis::Scaled);
    const PolynomialBasis b = polynomial_basis(F, 11);
    const auto c = project(b, series.data(), 1);
    EXPECT_LT(max_abs(fit_of_degree(b, c, 1, 10), series), 1e-10);
    EXPECT_LT(max_abs(fit_of_degree(b, c, 1, 11), series), 1e-10);
    std::vector<double> random(F);
    for (double& v : random) v = normal(rng);
    const auto cr = project(b, random.data(), 1);
    EXPECT_LT(max_abs(fit_of_degree(b, cr, 1, 11), random), 1e-11);
    EXPECT_GT(max_abs(fit_of_degree(b, cr, 1, 10), random), 1e-6);
    // Many right-hand sides at once equal one at a time.
    std::vector<double> two(static_cast<size_t>(2 * F));
    for (int64_t f = 0; f < F; ++f) {
        two[static_cast<size_t>(2 * f)] = series[static_cast<size_t>(f)];
        two[static_cast<size_t>(2 * f + 1)] = random[static_cast<size_t>(f)];
    }
    const auto fit2 = fit_of_degree(b, project(b, two.data(), 2), 2, 10);
    const auto fit1 = fit_of_degree(b, cr, 1, 10);
    for (int64_t f = 0; f < F; ++f) EXPECT_NEAR(fit2[static_cast<size_t>(2 * f + 1)], fit1[static_cast<size_t>(f)], 1e-12);
}

TEST(Regression, DegreeAboveFramesMinusOneIsRefused) {
    try {
        polynomial_basis(8, 8);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("needs at least 9 frames"), std::string::npos) << e.what();
    }
    EXPECT_THROW(polynomial_basis(0, 0), Error);
    EXPECT_THROW(polynomial_basis(5, -1), Error);
}

// Max |fit - series| of the least-squares fit with the monomial design in the given time axis, by
// Householder QR (LAPACK dgels); infinity when dgels declares the matrix rank deficient.
double monomial_fit_error(const std::vector<double>& series, int64_t degree, TimeAxis axis) {
    const int64_t F = static_cast<int64_t>(series.size());
    try {
        const auto c = least_squares_qr(vandermonde(F, degree, axis), F, degree + 1, series, 1);
        return max_abs(polynomial(c, F, axis), series);
    } catch (const Error&) {
        return HUGE_VAL;
    }
}

double orthonormal_fit_error(const std::vector<double>& series, int64_t degree) {
    const int64_t F = static_cast<int64_t>(series.size());
    const PolynomialBasis b = polynomial_basis(F, degree);
    return max_abs(fit_of_degree(b, project(b, series.data(), 1), 1, degree), series);
}

TEST(Regression, ThousandFramesRawFrameNumbersFailScaledTimeDoesNot) {
    // A 1,000-frame sequence. The monomial design in raw frame numbers 1..1000 is numerically
    // singular from degree 5 on; in scaled time it stays usable far longer; the orthonormal basis is
    // perfectly conditioned at every degree.
    const int64_t F = 1000;
    std::printf("  condition numbers of the %lld-frame design matrix (2-norm, LAPACK dgesvd):\n", static_cast<long long>(F));
    std::printf("  %6s %14s %14s %14s\n", "degree", "raw frames", "scaled time", "orthonormal");
    for (int64_t D : {2, 3, 5, 8, 12, 20, 30}) {
        const double raw = condition_number(vandermonde(F, D, TimeAxis::FrameNumber), F, D + 1);
        const double scaled = condition_number(vandermonde(F, D, TimeAxis::Scaled), F, D + 1);
        const double ortho = condition_number(polynomial_basis(F, D).q, F, D + 1);
        std::printf("  %6lld %14.3g %14.3g %14.3g\n", static_cast<long long>(D), raw, scaled, ortho);
        ::testing::Test::RecordProperty("cond_raw_degree_" + std::to_string(D), std::to_string(raw));
        ::testing::Test::RecordProperty("cond_scaled_degree_" + std::to_string(D), std::to_string(scaled));
        EXPECT_NEAR(ortho, 1.0, 1e-10);
        if (D >= 5) EXPECT_GT(raw, 1e14);
        if (D <= 12) EXPECT_LT(scaled, 2e4);
    }
    // A smooth trend over the 1,000 frames needing a high degree: its degree-40 fit. The orthonormal
    // basis gets it to rounding; QR with raw frame numbers loses it by nine orders of magnitude.
    std::vector<double> series(static_cast<size_t>(F));
    for (int64_t f = 0; f < F; ++f) {
        const double t = scaled_time(f, F);
        series[static_cast<size_t>(f)] = std::sin(6 * t) + 0.3 * std::cos(17 * t);
    }
    const double ortho = orthonormal_fit_error(series, 40);
    const double scaled = monomial_fit_error(series, 40, TimeAxis::Scaled);
    const double raw = monomial_fit_error(series, 40, TimeAxis::FrameNumber);
    std::printf("  degree-40 fit of sin(6t) + 0.3 cos(17t) over %lld frames, max error: orthonormal %.3g, "
                "scaled-time monomials %.3g, raw-frame monomials %.3g\n",
                static_cast<long long>(F), ortho, scaled, raw);
    EXPECT_LT(ortho, 1e-11);
    EXPECT_GT(raw, 1e-6);
    EXPECT_GT(raw, 1e4 * ortho);
    // A degree-5 polynomial is recovered exactly at every degree from 5 to 40.
    const auto poly = polynomial({0.5, 0.3, -0.8, 0.2, 0.6, -0.4}, F, TimeAxis::Scaled);
    for (int64_t D : {5, 12, 40}) EXPECT_LT(orthonormal_fit_error(poly, D), 1e-12) << D;
}

TEST(Regression, MonomialsFailNearTheFrameCountTheOrthonormalBasisDoesNot) {
    // 32 frames of random data, degree 31: an exact interpolation. The orthonormal basis does it to
    // rounding; monomials cannot, even in scaled time (condition number ~1e14), let alone raw.
    std::mt19937 rng(9);
    std::normal_distribution<double> normal;
    std::vector<double> series(32);
    for (double& v : series) v = normal(rng);
    const double ortho = orthonormal_fit_error(series, 31);
    const double scaled = monomial_fit_error(series, 31, TimeAxis::Scaled);
    const double raw = monomial_fit_error(series, 31, TimeAxis::FrameNumber);
    std::printf("  degree-31 interpolation of 32 random frames, max error: orthonormal %.3g, scaled monomials %.3g, "
                "raw monomials %.3g\n", ortho, scaled, raw);
    EXPECT_LT(ortho, 1e-10);
    EXPECT_GT(scaled, 1e-8);
    EXPECT_GT(raw, 1e-3);
}

TEST(Regression, DegreeRulePicksTheSmallestDegreeWithinTolerance) {
    const int64_t F = 24, D = 6;
    const PolynomialBasis b = polynomial_basis(F, D);
    // Four single-channel series: constant, line, cubic, and a jump no degree <= 6 explains.
    std::vector<double> s(static_cast<size_t>(F * 4));
    for (int64_t f = 0; f < F; ++f) {
        const double t = scaled_time(f, F);
        s[static_cast<size_t>(f * 4 + 0)] = 2.0;
        s[static_cast<size_t>(f * 4 + 1)] = 1.0 + 0.5 * t;
        s[static_cast<size_t>(f * 4 + 2)] = 1.0 + t * t * t;
        s[static_cast<size_t>(f * 4 + 3)] = f < F / 2 ? 0.0 : 1.0;
    }
    const std::vector<double> tol(4, 1e-9);
    const DegreeChoice d = choose_degrees(b, s.data(), 4, 1, tol.data());
    EXPECT_EQ(d.degrees, (std::vector<int64_t>{0, 1, 3, D + 1}));
    for (int64_t f = 0; f < F; ++f)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(d.fit[static_cast<size_t>(f * 4 + j)], s[static_cast<size_t>(f * 4 + j)], 1e-9);
    // A looser tolerance accepts a lower degree for the jump; groups share one degree.
    const std::vector<double> loose = {1e-9, 1e-9, 1e-9, 0.3};
    EXPECT_LT(choose_degrees(b, s.data(), 4, 1, loose.data()).degrees[3], D + 1);
    const std::vector<double> group_tol(2, 1e-9);
    const DegreeChoice g = choose_degrees(b, s.data(), 4, 2, group_tol.data());
    EXPECT_EQ(g.degrees, (std::vector<int64_t>{1, D + 1}));
}
