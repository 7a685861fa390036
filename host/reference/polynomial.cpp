#include "reference/polynomial.h"

#include <algorithm>

namespace ray {

namespace {

// Bisection for the one root of a monotone piece [lo, hi] whose ends differ in sign,
// until the interval cannot shrink any further in double precision.
double bisect(const double* c, int degree, double lo, double hi, double fLo) {
    for (int iteration = 0; iteration < 200; ++iteration) {
        double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        double fMid = evaluatePolynomial(c, degree, mid);
        if (fMid == 0) return mid;
        if ((fMid < 0) == (fLo < 0)) {
            lo = mid;
            fLo = fMid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

}  // namespace

double evaluatePolynomial(const double* c, int degree, double x) {
    double value = c[degree];
    for (int i = degree - 1; i >= 0; --i) value = value * x + c[i];
    return value;
}

int polynomialRootsInInterval(const double* c, int degree, double lo, double hi, double* roots) {
    if (degree <= 0 || lo > hi) return 0;
    if (degree == 1) {
        double x = -c[0] / c[1];
        if (x >= lo && x <= hi) {
            roots[0] = x;
            return 1;
        }
        return 0;
    }
    // Breakpoints: the interval's ends and the derivative's roots between them.
    double derivative[kMaxPolynomialDegree];
    for (int i = 0; i < degree; ++i) derivative[i] = double(i + 1) * c[i + 1];
    double breakpoints[kMaxPolynomialDegree + 1];
    breakpoints[0] = lo;
    int count = 1 + polynomialRootsInInterval(derivative, degree - 1, lo, hi, breakpoints + 1);
    breakpoints[count++] = hi;

    int found = 0;
    double fLo = evaluatePolynomial(c, degree, breakpoints[0]);
    if (fLo == 0) roots[found++] = breakpoints[0];
    for (int i = 0; i + 1 < count; ++i) {
        double a = breakpoints[i], b = breakpoints[i + 1];
        double fB = evaluatePolynomial(c, degree, b);
        if (fB == 0) {
            if (found == 0 || roots[found - 1] < b) roots[found++] = b;
        } else if (fLo != 0 && (fLo < 0) != (fB < 0)) {
            roots[found++] = bisect(c, degree, a, b, fLo);
        }
        fLo = fB;
        if (found == degree) break;
    }
    return found;
}

}  // namespace ray
