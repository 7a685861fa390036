// Real roots of a polynomial inside an interval, by isolation and bisection.
//
// Used for the torus (a quartic). The closed-form quartic formulas lose most of their
// digits when roots are close together (grazing rays) or the coefficients differ wildly in
// size; isolating the roots instead is robust: the roots of the derivative split the
// interval into pieces on which the polynomial is monotone, so each piece holds at most one
// root, found by bisection where the sign changes. The derivative's roots come the same
// way, down to a linear polynomial. The kernel does the same cascade in float
// (cl/geometry/torus_mesh.cl, intersectTorus).
#pragma once

namespace ray {

constexpr int kMaxPolynomialDegree = 4;

// The real roots of c[0] + c[1]·x + … + c[degree]·x^degree (c[degree] ≠ 0) in [lo, hi],
// ascending, written to roots (room for `degree` values); returns how many. A double
// root where the polynomial only touches zero is reported when the sampled extremum
// reaches zero exactly or crosses it.
int polynomialRootsInInterval(const double* c, int degree, double lo, double hi, double* roots);

double evaluatePolynomial(const double* c, int degree, double x);

}  // namespace ray
