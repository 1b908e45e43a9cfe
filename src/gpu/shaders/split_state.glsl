// The float32 state as two floats (docs/gpu.md, "float32 that keeps its accuracy"): each
// coordinate x = high + low, high the float nearest x and low the rest, rounded to a multiple of
// 2^-48 of high's binade. So x has 48 bits (a double holds it exactly, and the host's split of
// that double, split_real in gpu/real_arrays.h, gives back the same two floats: a state read back
// and uploaded again, as a resumed run does, is the same bits), and a step's change is added
// without the rounding to float that made RKF45 take up to 1.9 times float64's steps on large
// sheets.
//
// float64 keeps one array per state: these functions are float32's.
#ifndef CLOTHSIM_SPLIT_STATE_GLSL
#define CLOTHSIM_SPLIT_STATE_GLSL

// Below this |high| the low part is dropped (its grid would leave float's normal range).
const float kSplitFloor = 8.673617e-19;  // 2^-60

struct SplitReal {
  float high;
  float low;
};

// high + low as the canonical split: low on high's 2^-48 grid, high the float nearest the sum.
SplitReal canonical_split(float high, float low) {
  SplitReal split;
  if (abs(high) < kSplitFloor) {
    split.high = high + low;
    split.low = 0.0;
    return split;
  }
  int binade;
  frexp(high, binade);  // high = m 2^binade, 0.5 <= |m| < 1
  precise float grid_low = ldexp(roundEven(ldexp(low, 48 - binade)), binade - 48);
  precise float nearest = high + grid_low;  // round to nearest even, of the exact sum
  if (nearest != high) {
    // A tie that rounds the other way: high moves by an ulp, low by the same, exactly.
    grid_low = grid_low - (nearest - high);
    high = nearest;
  }
  split.high = high;
  split.low = grid_low;
  return split;
}

// high + change as a split value (Knuth's error-free sum, then canonical_split). `change` is the
// step's change plus the old low part, a small number.
SplitReal split_sum(float high, float change) {
  precise float sum = high + change;
  precise float change_part = sum - high;
  precise float error = (high - (sum - change_part)) + (change - change_part);
  return canonical_split(sum, error);
}

#endif
