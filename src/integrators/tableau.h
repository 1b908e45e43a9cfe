// Butcher tableaus of explicit Runge-Kutta methods, held as data (STYLE.md rule 8): one driver
// (explicit_runge_kutta.cpp) serves every method, adaptive or fixed-step.
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

}  // namespace clothsim
