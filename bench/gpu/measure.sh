#!/usr/bin/env bash
# Measures the Vulkan backend on a machine with a GPU, for docs/performance.md ("The Vulkan
# backend on an NVIDIA H200") and docs/gpu.md: the devices, the GPU tests on the device, one pass
# a stage and chained against three (--stage-passes), then `clothsim bench` with RKF45 on the paper's material
# from 25^2 to 2048^2, float32 and float64, three repetitions each, and the CPU backend on all the
# machine's cores for comparison; where a 1024^2 frame's time goes; implicit Euler (cotton) and
# the obstacle and self-collision passes on the device against the CPU.
#
#   bench/gpu/measure.sh BIN OUT [BUDGET_S]
#
# BIN holds a build's clothsim and test_gpu (a Release build; the renderer is not needed), OUT
# receives the CSV files and logs, and OUT/steps.txt each step's exit code and seconds. BUDGET_S
# (default: none) bounds the whole script: the steps run in order of what the issues need most,
# each under its own time limit and under what is left of the budget, and a step with less than
# 10 s left is skipped (its line in steps.txt says so), so that a lent machine's time is never
# overrun. MEASURE_ONLY (an extended regular expression) runs only the steps whose names match
# it, e.g. MEASURE_ONLY='^bench-large|^paper-sphere'. On a machine whose Vulkan loader does not find the NVIDIA driver by itself, set
# VK_DRIVER_FILES to its ICD file first.
set -u
bin=$(cd "${1:?usage: measure.sh BIN OUT [BUDGET_S]}" && pwd)
out=${2:?usage: measure.sh BIN OUT [BUDGET_S]}
budget=${3:-1000000}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
clothsim=$bin/clothsim
threads=$(nproc)
start=$SECONDS

# step NAME LIMIT_S FILE COMMAND...: runs COMMAND with its output in OUT/FILE, under LIMIT_S and
# what is left of the budget (given to COMMAND as STEP_LIMIT), and notes the exit code and the seconds in OUT/steps.txt.
step() {
  local name=$1 limit=$2 file=$3
  shift 3
  [[ -n ${MEASURE_ONLY:-} && ! $name =~ $MEASURE_ONLY ]] && return
  local left=$((budget - (SECONDS - start)))
  if ((left < 10)); then
    echo "$name: skipped, ${left} s of the budget left" | tee -a "$out/steps.txt"
    return
  fi
  ((limit > left)) && limit=$left
  local t0=$SECONDS
  STEP_LIMIT=$limit timeout "$limit" "$@" >"$out/$file" 2>&1
  local rc=$?
  echo "$name: exit $rc, $((SECONDS - t0)) s (limit $limit s)" | tee -a "$out/steps.txt"
}

"$clothsim" devices | tee "$out/devices.txt"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv \
  >"$out/gpu.txt" 2>&1 || true
{ echo "$threads"; lscpu | grep -i "model name"; } >"$out/cpus.txt"

# The GPU tests on the device (lavapipe's figures are in tests/gpu; these are the GPU's), in 8
# shards at once, each in a folder of its own and under its own limit, so that the logs of the
# shards that finished come back even when one does not.
gpu_tests() {
  local shards=8 i
  for ((i = 0; i < shards; ++i)); do
    mkdir -p "/tmp/test_gpu_$i"
    (cd "/tmp/test_gpu_$i" && GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i timeout $((STEP_LIMIT - 5)) "$bin/test_gpu" >log.txt 2>&1
     echo "shard $i exit $?" >>log.txt) &
  done
  wait
  for ((i = 0; i < shards; ++i)); do cat "/tmp/test_gpu_$i/log.txt"; done
}
export -f gpu_tests
export bin
step test_gpu 130 test_gpu.txt bash -c gpu_tests
[ -f "$out/test_gpu.txt" ] && grep -E '^\[  (PASSED|FAILED) |^shard|FAILED  \]' "$out/test_gpu.txt" | sort | uniq -c

# Issue 22: the explicit stages chained in a pass (three a pass in float32), one pass a stage
# (lattice_stage) and three passes a stage, alternating. On lavapipe the one pass is slower
# (docs/gpu.md, "One pass per stage"); which a GPU runs fastest decides its default
# (DeviceSelection::stage_passes; unset, a GPU chains).
# Two repetitions, two sizes: the lent time is short. float64 chains one stage a pass, as fused.
for rep in 1 2; do
  for precision in float32 float64; do
    for passes in chained fused split; do
      [ "$precision" = float64 ] && [ "$passes" = chained ] && continue
      step "stages $passes $precision $rep" 30 "stages-$passes-$precision-$rep.csv.log" "$clothsim" bench \
        --backend vulkan --precision "$precision" --integrators rkf45 --sizes 128,1024 --seconds 1.5 \
        --sim-cap 60 --stage-passes "$passes" --csv "$out/stages-$passes-$precision-$rep.csv"
    done
  done
done

# RKF45 on the paper's material (issue 22): throughput from the paper's 25^2 to 2048^2; the large
# lattices with a longer budget, so that the first frame's one-time work (the model's upload, the
# shaders' pipelines) is a small part of the case.
for rep in 1 2 3; do
  for precision in float32 float64; do
    step "bench $precision $rep" 60 "vulkan-$precision-$rep.csv.log" "$clothsim" bench --backend vulkan \
      --precision "$precision" --integrators rkf45 --sizes 25,128,256,512 --seconds 1.5 --sim-cap 60 \
      --csv "$out/vulkan-$precision-$rep.csv"
  done
done
for rep in 1 2 3; do
  for precision in float32 float64; do
    step "bench-large $precision $rep" 60 "vulkan-large-$precision-$rep.csv.log" "$clothsim" bench --backend vulkan \
      --precision "$precision" --integrators rkf45 --sizes 1024,2048 --seconds 6 --sim-cap 60 \
      --csv "$out/vulkan-large-$precision-$rep.csv"
  done
done
step "bench cpu" 90 cpu.csv.log "$clothsim" bench --integrators rkf45 --sizes 25,128,256,512,1024 --threads "$threads" \
  --seconds 1.5 --csv "$out/cpu.csv"

# Where a frame's wall time goes at 1024^2 and 60 frames per second: the device's passes, the
# transfers, the host's checks and energies.
step "profile 1024" 60 profile-1024-60fps.txt "$clothsim" run --paper-args 1024,1024,1,4,1,1400,200,80,5,1 \
  --backend vulkan --duration 0.25 --render none --profile --out /tmp/clothsim-profile-run

# Issue 23: implicit Euler on the device (cotton at the frame step), against the CPU backend on
# all the machine's cores; and the device's V-cycle smoothing single particles instead of lines
# (integrator.cg_line_smoother): which of the two is faster on a GPU decides the device's default.
for n in 256 512 1024; do
  for backend in vulkan cpu; do
    step "cotton-drape $n $backend" 60 "cotton-$n-$backend.txt" "$clothsim" run cotton-drape \
      --set lattice.rows=$n --set lattice.cols=$n --anchor edge-corners --backend "$backend" --threads "$threads" \
      --duration 0.25 --render none --profile --out "/tmp/clothsim-cotton-$n-$backend"
  done
  step "cotton-drape $n vulkan points" 60 "cotton-$n-vulkan-points.txt" "$clothsim" run cotton-drape \
    --set lattice.rows=$n --set lattice.cols=$n --anchor edge-corners --backend vulkan \
    --set integrator.cg_line_smoother=false --duration 0.25 --render none --profile \
    --out "/tmp/clothsim-cotton-$n-points"
done
# The obstacle pass on the device after each of implicit Euler's steps (drape-sphere), and the
# self-collision pass on the host between them (drape-sphere with collision.self, pile,
# tear-crumple), against the CPU.
for backend in vulkan cpu; do
  for self in false true; do
    step "drape-sphere 512 $backend self=$self" 40 "drape-sphere-512-$backend-self-$self.txt" "$clothsim" run \
      drape-sphere --set lattice.rows=512 --set lattice.cols=512 --set collision.self=$self --backend "$backend" \
      --threads "$threads" --duration 0.05 --render none --profile --out "/tmp/clothsim-drape-$backend-$self"
  done
done
for n in 256 512; do
  for backend in vulkan cpu; do
    step "tear-crumple $n $backend" 40 "tear-crumple-$n-$backend.txt" "$clothsim" run tear-crumple \
      --set lattice.rows=$n --set lattice.cols=$n --backend "$backend" --threads "$threads" --duration 0.05 \
      --render none --profile --out "/tmp/clothsim-crumple-$n-$backend"
  done
done
# RKF45's obstacle pass on the device: the paper's sheet dropped on a sphere above a floor, at its
# 11^2 and at 512^2 (every particle is tested against both colliders at every step either way).
for n in 11 512; do
  step "paper-sphere $n" 40 "obstacles-$n.txt" "$clothsim" run "$here/paper-sphere.json" --set lattice.rows=$n \
    --set lattice.cols=$n --backend vulkan --duration 1 --render none --profile --out "/tmp/clothsim-obstacles-$n"
done
# The device's V-cycle against its block Jacobi at 256 x 256: CG iterations per step, time per step.
step "cotton-drape 256 jacobi" 60 cotton-256-vulkan-jacobi.txt "$clothsim" run cotton-drape \
  --set lattice.rows=256 --set lattice.cols=256 --anchor edge-corners --backend vulkan --duration 0.1 --render none \
  --profile --set integrator.cg_two_level=false --out /tmp/clothsim-cotton-jacobi
echo "measure.sh: $((SECONDS - start)) s" | tee -a "$out/steps.txt"
