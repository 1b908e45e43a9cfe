#!/bin/bash
# Issue 12's figures: medians of 3, wall seconds from summary.json.
C=${CLOTHSIM:-build/release/apps/clothsim/clothsim}
wall() { grep -o '"wall_seconds": *[0-9.e-]*' $1/summary.json | grep -o '[0-9.e-]*$'; }
med() { printf "%s\n" "$@" | sort -g | sed -n 2p; }
run3() { # label, args...
  local label=$1; shift; local w=()
  for i in 1 2 3; do rm -rf /tmp/m12; $C run "$@" --render none --quiet --out /tmp/m12 || echo FAIL; w+=($(wall /tmp/m12)); done
  local ev=$(grep -o '"force_evaluations": *[0-9]*' /tmp/m12/summary.json | grep -o '[0-9]*$')
  local cg=$(grep -o '"cg_iterations_per_step": *[0-9.e-]*' /tmp/m12/summary.json | grep -o '[0-9.e-]*$')
  echo "$label | walls ${w[*]} | median $(med ${w[@]}) | evals $ev | cg/step $cg"
}
echo "# $(date -u) $(uptime)"
for n in 64 96; do for pr in float64 float32; do
  run3 "paper N=$n $pr 2 threads 2 s" --paper-args $n,$n,1,4,1,1400,200,80,5,1 --duration 2 --threads 2 --precision $pr
done; done
for pr in float64 float32; do for t in 2 1; do
  run3 "paper N=128 $pr $t threads 1 s" --paper-args 128,128,1,4,1,1400,200,80,5,1 --duration 1 --threads $t --precision $pr
done; done
run3 "paper N=128 auto 2 threads 1 s" --paper-args 128,128,1,4,1,1400,200,80,5,1 --duration 1 --threads 2 --precision auto
run3 "cotton 128 implicit 2 threads 1 s" cotton-drape --duration 1 --threads 2
run3 "cotton 128 implicit 1 thread 1 s" cotton-drape --duration 1 --threads 1
run3 "cotton 64 implicit 2 threads 2 s" cotton-drape --set lattice.rows=64 --set lattice.cols=64 --set anchors=edge-corners --duration 2 --threads 2
echo "# bench"
$C bench --sizes 64,128 --integrators rkf45 --threads 2 --seconds 3 --precision float64 | grep -E "^lattice|^[0-9]+x"
$C bench --sizes 64,128 --integrators rkf45 --threads 2 --seconds 3 --precision float32 | grep -E "^[0-9]+x"
echo "# $(date -u) $(uptime)"
