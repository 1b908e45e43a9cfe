#!/bin/bash
# Issue 12, auto's rule: SCENE for SECONDS (default 1) with float64 and float32 forces at
# rtol = atol = 1e-4 .. 1e-8 on 1 thread, against a float64 run at 1e-10: force evaluations, the
# energy balance error and the largest distance over all frames. Output: issue12-auto-rule.txt.
# Usage (from the repository root): bench/results/issue12-auto-rule.sh paper-fig5 1
C=${CLOTHSIM:-build/release/apps/clothsim/clothsim}
S=$1; D=${2:-1}; W=$(mktemp -d)
distance() {  # largest |a - b| over every frame of two positions.npy, and the largest coordinate
  python3 - "$1/positions.npy" "$2/positions.npy" <<'PY'
import ast, array, sys
def load(path):
    data = open(path, 'rb').read()
    size = int.from_bytes(data[8:10], 'little')
    header = ast.literal_eval(data[10:10 + size].decode())
    values = array.array('d'); values.frombytes(data[10 + size:])
    return values, header['shape']
a, shape = load(sys.argv[1]); b, _ = load(sys.argv[2])
per = shape[1] * 3
d = [max(abs(a[i] - b[i]) for i in range(f * per, (f + 1) * per)) for f in range(shape[0])]
print('max pos diff %.3g (last frame %.3g), largest coordinate %.3g' % (max(d), d[-1], max(abs(x) for x in a[-per:])))
PY
}
$C run $S --duration $D --render none --threads 1 --rtol 1e-10 --atol 1e-10 --out $W/ref --quiet --set collision.self=false
for tol in 1e-4 1e-5 1e-6 1e-7 1e-8; do for pr in float64 float32; do
  $C run $S --duration $D --render none --threads 1 --rtol $tol --atol $tol --precision $pr --out $W/$pr-$tol --quiet --set collision.self=false
  ev=$(grep -o '"force_evaluations": *[0-9]*' $W/$pr-$tol/summary.json | grep -o '[0-9]*$')
  be=$(grep -o '"balance_error": *[0-9.e-]*' $W/$pr-$tol/summary.json | tail -1 | grep -o '[0-9.e-]*$')
  echo "$S tol=$tol $pr evals=$ev balance=$be $(distance $W/ref $W/$pr-$tol)"
done; done
rm -rf "$W"
