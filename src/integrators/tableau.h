// Butcher tableaus of explicit Runge-Kutta methods, held as data (STYLE.md rule 8): one driver
// (explicit_runge_kutta.cpp) serves every method, adaptive or fixed-step. Below them the additive
// (IMEX) pairs of the imex integrator (imex.h).
#pragma once

#include <array>

namespace clothsim {

inline constexpr int kMaxStages = 6;

struct ButcherTableau {
  const char* name;
  int stages;
  int order;                             // order of the propagated solution
  int embedded_order;                    // order of the embedded solution used for the error estimate; 0: none
  std::array<double, kMaxStages> nodes;  // c_i
  std::array<std::array<double, kMaxStages>, kMaxStages> coefficients;  // a_ij, j < i
  std::array<double, kMaxStages> weights;                               // b_i, propagated solution
  std::array<double, kMaxStages> embedded_weights;                      // b^_i, embedded solution
};

// Runge-Kutta-Fehlberg 4(5), the paper's Figure 3 (Fehlberg 1969, via the paper's reference [1]).
// The 5th-order row (16/135, ...) is propagated and the 4th-order row (25/216, ...) is the
// embedded one: "local extrapolation", as in Dormand-Prince and most modern codes. The error
// estimate y5 - y4 then bounds the error of the 4th-order solution, so the step is accepted on a
// conservative estimate while the state carries the more accurate 5th-order result at no extra
// cost. docs/model.md discusses the choice.
inline constexpr ButcherTableau kFehlberg45{
    "rkf45",
    6,
    5,
    4,
    {0.0, 1.0 / 4.0, 3.0 / 8.0, 12.0 / 13.0, 1.0, 1.0 / 2.0},
    {{
        {},
        {1.0 / 4.0},
        {3.0 / 32.0, 9.0 / 32.0},
        {1932.0 / 2197.0, -7200.0 / 2197.0, 7296.0 / 2197.0},
        {439.0 / 216.0, -8.0, 3680.0 / 513.0, -845.0 / 4104.0},
        {-8.0 / 27.0, 2.0, -3544.0 / 2565.0, 1859.0 / 4104.0, -11.0 / 40.0},
    }},
    {16.0 / 135.0, 0.0, 6656.0 / 12825.0, 28561.0 / 56430.0, -9.0 / 50.0, 2.0 / 55.0},
    {25.0 / 216.0, 0.0, 1408.0 / 2565.0, 2197.0 / 4104.0, -1.0 / 5.0, 0.0},
};

// The classical 4th-order Runge-Kutta method (fixed step, no error estimate).
inline constexpr ButcherTableau kClassicRk4{
    "rk4",
    4,
    4,
    0,
    {0.0, 0.5, 0.5, 1.0},
    {{
        {},
        {0.5},
        {0.0, 0.5},
        {0.0, 0.0, 1.0},
    }},
    {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0},
    {},
};

// The same method with the roles of the two weight rows swapped: propagates the embedded
// solution. Used by the convergence tests to measure the order of each row.
constexpr ButcherTableau embedded_as_propagated(const ButcherTableau& t) {
  ButcherTableau swapped = t;
  swapped.weights = t.embedded_weights;
  swapped.embedded_weights = t.weights;
  swapped.order = t.embedded_order;
  swapped.embedded_order = t.order;
  return swapped;
}

// An additive Runge-Kutta pair: an explicit tableau for the non-stiff part of y' = f_E(y) + f_I(y)
// and a diagonally implicit one for the stiff part, with shared nodes and weights (b^E = b^I and
// the same embedded row), so that the solution and its error estimate are sums of whole stage
// rates f_E + f_I. The implicit tableau is ESDIRK: a_11 = 0 (the first stage is the step's start)
// and a_ii = gamma for i >= 2.
struct AdditiveTableau {
  const char* name;
  int stages;
  int order;           // of the solution
  int embedded_order;  // of the embedded solution of the error estimate
  std::array<double, kMaxStages> nodes;                                         // c_i
  std::array<std::array<double, kMaxStages>, kMaxStages> explicit_coefficients;  // a^E_ij, j < i
  std::array<std::array<double, kMaxStages>, kMaxStages> implicit_coefficients;  // a^I_ij, j <= i
  std::array<double, kMaxStages> weights;                                       // b_i
  std::array<double, kMaxStages> embedded_weights;                              // b^_i
  double gamma() const { return implicit_coefficients[1][1]; }
};

// Kennedy and Carpenter's ARK3(2)4L[2]SA (C. A. Kennedy and M. H. Carpenter, "Additive Runge-Kutta
// schemes for convection-diffusion-reaction equations", Applied Numerical Mathematics 44 (2003)
// 139-181, Appendix C, the rational coefficients): third order with a second-order embedded
// solution; its ESDIRK part is L-stable and stiffly accurate (a^I_4j = b_j) with stage order 2.
// (Checked against SUNDIALS ARKODE's ARK324L2SA_ERK_4_2_3 and ARK324L2SA_DIRK_4_2_3 to 16
// digits; tests/integrators/test_tableau.cpp checks the order conditions.)
inline constexpr double kArk324Gamma = 1767732205903.0 / 4055673282236.0;
inline constexpr AdditiveTableau kArk324L2SA{
    "ark3(2)4l[2]sa",
    4,
    3,
    2,
    {0.0, 1767732205903.0 / 2027836641118.0, 3.0 / 5.0, 1.0},
    {{
        {},
        {1767732205903.0 / 2027836641118.0},
        {5535828885825.0 / 10492691773637.0, 788022342437.0 / 10882634858940.0},
        {6485989280629.0 / 16251701735622.0, -4246266847089.0 / 9704473918619.0,
         10755448449292.0 / 10357097424841.0},
    }},
    {{
        {},
        {kArk324Gamma, kArk324Gamma},
        {2746238789719.0 / 10658868560708.0, -640167445237.0 / 6845629431997.0, kArk324Gamma},
        {1471266399579.0 / 7840856788654.0, -4482444167858.0 / 7529755066697.0, 11266239266428.0 / 11593286722821.0,
         kArk324Gamma},
    }},
    {1471266399579.0 / 7840856788654.0, -4482444167858.0 / 7529755066697.0, 11266239266428.0 / 11593286722821.0,
     kArk324Gamma},
    {2756255671327.0 / 12835298489170.0, -10771552573575.0 / 22201958757719.0, 9247589265047.0 / 10645013368117.0,
     2193209047091.0 / 5459859503100.0},
};

// The same pair propagating its embedded solution, for the convergence tests (as
// embedded_as_propagated does for explicit tableaus).
constexpr AdditiveTableau embedded_as_propagated(const AdditiveTableau& t) {
  AdditiveTableau swapped = t;
  swapped.weights = t.embedded_weights;
  swapped.embedded_weights = t.weights;
  swapped.order = t.embedded_order;
  swapped.embedded_order = t.order;
  return swapped;
}

}  // namespace clothsim
