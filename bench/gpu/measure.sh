#!/usr/bin/env bash
# Measures the Vulkan backend on a machine with a GPU, for docs/performance.md ("The Vulkan
# backend"): the devices, the GPU tests on the device, then `clothsim bench` with RKF45 on the
# paper's material from 16^2 (the per-step latency) to 2048^2, float32 and float64, three
# repetitions each, and the CPU backend on all the machine's cores for comparison; the obstacle
# pass's share of a step.
#
#   bench/gpu/measure.sh BIN OUT
#
# BIN holds a build's clothsim and test_gpu (a Release build; the renderer is not needed), OUT
# receives the CSV files and logs. On a machine whose Vulkan loader does not find the NVIDIA
# driver by itself, set VK_DRIVER_FILES to its ICD file first.
set -u
bin=${1:?usage: measure.sh BIN OUT}
out=${2:?usage: measure.sh BIN OUT}
mkdir -p "$out"
sizes=16,128,256,512,1024,2048

"$bin/clothsim" devices | tee "$out/devices.txt"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv \
  >"$out/gpu.txt" 2>&1 || true
nproc >"$out/cpus.txt"

# The GPU tests on the device (lavapipe's figures are in tests/gpu; these are the GPU's).
timeout 240 "$bin/test_gpu" >"$out/test_gpu.txt" 2>&1
echo "test_gpu exit $?" | tee -a "$out/test_gpu.txt"
tail -3 "$out/test_gpu.txt"

# Where a frame's wall time goes at 1024^2 (device steps, transfers, the host's checks and energy).
"$bin/clothsim" run --paper-args 1024,1024,1,4,1,1400,200,80,5,1 --backend vulkan --duration 0.5 --fps 10 \
  --render none --profile --out /tmp/clothsim-profile-run >"$out/profile-1024.txt" 2>&1
cat "$out/profile-1024.txt"

# The obstacle pass's share of the step (docs/gpu.md, "Obstacles on the device"): the paper's
# sheet dropped on a sphere above a floor, at its 11^2 and at 512^2 (a sheet 511 m wide over the
# same sphere: every particle is tested against both colliders at every step either way).
for n in 11 512; do
  "$bin/clothsim" run "$(dirname "$0")/paper-sphere.json" --set lattice.rows=$n --set lattice.cols=$n \
    --backend vulkan --duration 1 --render none --profile --out "/tmp/clothsim-obstacles-$n" \
    >"$out/obstacles-$n.txt" 2>&1
  tail -20 "$out/obstacles-$n.txt"
done

for rep in 1 2 3; do
  for precision in float32 float64; do
    "$bin/clothsim" bench --backend vulkan --precision "$precision" --integrators rkf45 --sizes "$sizes" \
      --seconds 3 --sim-cap 60 --csv "$out/vulkan-$precision-$rep.csv" | tail -n +1
  done
done
"$bin/clothsim" bench --integrators rkf45 --sizes 128,256,512,1024 --seconds 3 --csv "$out/cpu.csv"

# Issue 23: implicit Euler on the device (cotton at the frame step) and self-collision on the host
# between the device's steps (tear-crumple), against the CPU backend on all the machine's cores;
# each run bounded, so that the script keeps to the device time a session has.
for n in 256 512; do
  for backend in vulkan cpu; do
    timeout 150 "$bin/clothsim" run cotton-drape --set lattice.rows=$n --set lattice.cols=$n --anchor edge-corners \
      --backend "$backend" --duration 0.25 --render none --profile --out "/tmp/clothsim-cotton-$n-$backend" \
      >"$out/cotton-$n-$backend.txt" 2>&1
    echo "cotton-drape $n x $n on $backend: exit $?"; grep -E '^(steps|forces|integration|collisions|total)' "$out/cotton-$n-$backend.txt"
  done
done
# The device's V-cycle against its block Jacobi at 256 x 256 (docs/gpu.md, "Implicit Euler's
# multigrid on the device"): CG iterations per step and the time per step.
timeout 150 "$bin/clothsim" run cotton-drape --set lattice.rows=256 --set lattice.cols=256 --anchor edge-corners \
  --backend vulkan --duration 0.1 --render none --profile --set integrator.cg_two_level=false \
  --out /tmp/clothsim-cotton-jacobi >"$out/cotton-256-vulkan-jacobi.txt" 2>&1
echo "cotton-drape 256 x 256 on vulkan, block Jacobi: exit $?"
grep -E '^(steps|integration|total)' "$out/cotton-256-vulkan-jacobi.txt"
for n in 128 256; do
  for backend in vulkan cpu; do
    timeout 150 "$bin/clothsim" run tear-crumple --set lattice.rows=$n --set lattice.cols=$n --backend "$backend" \
      --duration 0.1 --render none --profile --out "/tmp/clothsim-crumple-$n-$backend" \
      >"$out/tear-crumple-$n-$backend.txt" 2>&1
    echo "tear-crumple $n x $n on $backend: exit $?"; grep -E '^(steps|forces|integration|collisions|total)' "$out/tear-crumple-$n-$backend.txt"
  done
done
